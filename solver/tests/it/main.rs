//! coil-solver's integration tests, one test binary: the real `coil-solve` binary in
//! temporary folders, every deck of tests/decks, the Marc dialect. A new test file is a module here.

mod boundary;
mod catenary;
mod cli;
mod decks;
mod marc;
mod superelement;
