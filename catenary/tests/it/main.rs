//! coil-catenary's integration tests (one binary): the mean contact force against its
//! closed form on a short catenary, the reference case against its ranges and beyond, and
//! docs/catenary.md's spring study and the head stage from a spring against the hand-built one (second stage: long)
//! (the command itself: `cli/tests/it/catenary_cli.rs`).

mod closed_form;
mod docs_tables;
mod reference_case;
mod spring_study;
