//! `coil-tune diagnose` on the shared real recordings (a spring with a disk in air,
//! position at 100 Hz, 0.1 mm resolution; `shared/real/README.md`), whole, cut to their
//! first half, and the two runs of the rig jointly (`coil_tests::real_recordings`, the
//! same code the ignored test `shared_data::real_recordings_match_the_docs` holds to
//! docs/diagnose.md).
//!
//! `cargo run --release -p coil-tests --example real_recordings [-- <folder>]`
//!
//! The folder defaults to `$COIL_REAL_DIR`, else `../shared/real` beside the repository;
//! every subfolder with a `case.json` is a case. The recordings are read where they are
//! and never copied into the repository. When the folder is absent the example says so
//! and exits 0.
//!
//! Printed per case: the terminal summary, every candidate's
//! tests (held / failed with their numbers: dBIC, N_eff, the rolling forecasts, the
//! relative standard errors, the signatures), the causes with their
//! parameters, standard errors and shares, `unexplained` when no cause is named, the
//! half-length verdict; then the wall times (library call, release build).

use coil_tests::real_recordings::{self, describe, length_tests};
use std::path::PathBuf;

fn main() {
    let root = std::env::args_os()
        .nth(1)
        .map(PathBuf::from)
        .unwrap_or_else(real_recordings::folder);
    let runs = match real_recordings::run_all(&root) {
        Ok(runs) => runs,
        Err(e) => {
            println!("{e}; nothing to diagnose");
            return;
        }
    };
    for run in &runs {
        print!("{}", describe(run));
    }
    print!("{}", length_tests(&runs));
}
