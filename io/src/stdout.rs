//! Printing to stdout when the reader may go away: `coil-tune run x.proc | head -1` closes
//! the pipe after one line. A closed stdout (`BrokenPipe`) ends the printing quietly, not
//! the run: the command still finishes and writes its files, and exits 0. Any other write
//! error (a full disk under `> file`) is returned.

use std::io::Write;
use std::sync::atomic::{AtomicBool, Ordering};

static CLOSED: AtomicBool = AtomicBool::new(false);

/// Writes `text` to stdout as it is (no newline added).
pub fn text(text: &str) -> std::io::Result<()> {
    if CLOSED.load(Ordering::Relaxed) {
        return Ok(());
    }
    let mut out = std::io::stdout().lock();
    match out.write_all(text.as_bytes()).and_then(|()| out.flush()) {
        Err(e) if e.kind() == std::io::ErrorKind::BrokenPipe => {
            CLOSED.store(true, Ordering::Relaxed);
            Ok(())
        }
        other => other,
    }
}

/// Writes `line` and a newline to stdout.
pub fn line(line: &str) -> std::io::Result<()> {
    text(&format!("{line}\n"))
}

/// Whether the reader closed stdout.
pub fn closed() -> bool {
    CLOSED.load(Ordering::Relaxed)
}

/// `say!("...", args)`: [`line()`] with `format!` arguments.
#[macro_export]
macro_rules! say {
    ($($arg:tt)*) => {
        $crate::stdout::line(&format!($($arg)*))
    };
}
