//! coil-catenary's integration tests (one binary): the mean contact force against its
//! closed form on a short catenary, the reference case against its ranges and at 320 km/h
//! (the command itself: `cli/tests/it/catenary_cli.rs`; the spring study's and the
//! discretisation tables' claims: coil-tests' `catenary_docs.rs`).

mod closed_form;
mod reference_case;
