//! A request to stop, shared by the whole process: set by the Python boundary when the
//! interpreter has a pending Ctrl-C (SIGINT), read by long loops on their progress path
//! (time steps every 64 steps, tasks, grid points), which then return an error. The
//! output set refuses to commit while a stop is requested, so an interrupted run leaves
//! its output folder as it was.
//!
//! The binaries do not set it: there SIGINT ends the process at once, which the output
//! sets already survive.

use std::sync::atomic::{AtomicBool, Ordering};

static REQUESTED: AtomicBool = AtomicBool::new(false);

/// Asks every long loop of the process to stop.
pub fn request() {
    REQUESTED.store(true, Ordering::SeqCst);
}

/// Withdraws the request (once the interrupted call has returned).
pub fn clear() {
    REQUESTED.store(false, Ordering::SeqCst);
}

/// Whether a stop is requested.
pub fn requested() -> bool {
    REQUESTED.load(Ordering::Relaxed)
}

/// The error text of an interrupted run.
pub const INTERRUPTED: &str = "interrupted (Ctrl-C); nothing was written";
