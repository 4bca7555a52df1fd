//! The `coil-tune` binary's integration tests, one binary (each test binary links the whole
//! dependency tree): every module runs the real binary in a temporary folder.

mod boundary;
mod catenary_cli;
mod cli;
mod damping_cli;
mod diagnose_cli;
mod forced_cli;
mod fuzz;
mod fuzz_spring;
mod fuzz_surfaces;
mod mesh_cli;
