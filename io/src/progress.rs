//! Progress of long runs on stderr. Nothing is shown for a run that ends within
//! [`QUIET_FOR`]; past it, a terminal gets one line rewritten in place a few times a
//! second, and a pipe or a log file gets a plain line every [`PLAIN_EVERY`] (so `2> log`
//! and CI logs show a run is alive). Each line: what, done of total, percent, elapsed and
//! an estimate of the time left. Thread-safe (grid points finish on rayon's workers).

use std::io::{IsTerminal, Write};
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::Mutex;
use std::time::{Duration, Instant};

/// Silence before the first progress line.
pub const QUIET_FOR: Duration = Duration::from_secs(2);
/// Interval of plain lines when stderr is not a terminal.
pub const PLAIN_EVERY: Duration = Duration::from_secs(5);
const TERMINAL_EVERY: Duration = Duration::from_millis(200);

/// A progress reporter for `total` units of work (see the module doc).
#[derive(Debug)]
pub struct Progress {
    label: String,
    unit: &'static str,
    total: u64,
    done: AtomicU64,
    start: Instant,
    last: Mutex<Option<Instant>>,
    terminal: bool,
    enabled: bool,
    shown: AtomicBool,
}

impl Progress {
    /// A reporter for `total` `unit`s (e.g. "steps", "points") of `label`.
    pub fn new(label: impl Into<String>, total: u64, unit: &'static str) -> Self {
        Progress {
            label: label.into(),
            unit,
            total,
            done: AtomicU64::new(0),
            start: Instant::now(),
            last: Mutex::new(None),
            terminal: std::io::stderr().is_terminal(),
            enabled: true,
            shown: AtomicBool::new(false),
        }
    }

    /// No output at all (`--quiet`).
    pub fn hidden(mut self, hidden: bool) -> Self {
        self.enabled = !hidden;
        self
    }

    /// Prints `text` as a line now (announcements such as a step count).
    pub fn announce(&self, text: &str) {
        if self.enabled {
            let _ = writeln!(std::io::stderr(), "{text}");
        }
    }

    /// Adds `n` finished units.
    pub fn inc(&self, n: u64) {
        let done = self.done.fetch_add(n, Ordering::Relaxed) + n;
        self.set(done);
    }

    /// Sets the number of finished units.
    pub fn set(&self, done: u64) {
        if !self.enabled {
            return;
        }
        self.done.store(done, Ordering::Relaxed);
        let now = Instant::now();
        let elapsed = now - self.start;
        if elapsed < QUIET_FOR {
            return;
        }
        let every = if self.terminal {
            TERMINAL_EVERY
        } else {
            PLAIN_EVERY
        };
        let Ok(mut last) = self.last.try_lock() else {
            return;
        };
        if last.is_some_and(|t| now - t < every) {
            return;
        }
        *last = Some(now);
        self.shown.store(true, Ordering::Relaxed);
        let line = self.line(done, elapsed);
        let mut err = std::io::stderr().lock();
        let _ = if self.terminal {
            write!(err, "\r{line}\x1b[K")
        } else {
            writeln!(err, "{line}")
        };
    }

    /// The progress line for `done` units after `elapsed`.
    pub fn line(&self, done: u64, elapsed: Duration) -> String {
        let secs = elapsed.as_secs_f64();
        let mut line = format!("{}: {done}/{} {}", self.label, self.total, self.unit);
        if self.total > 0 {
            let fraction = done as f64 / self.total as f64;
            line.push_str(&format!(" ({:.0}%), {secs:.0} s", 100.0 * fraction));
            if done > 0 && done < self.total {
                let left = secs * (1.0 / fraction - 1.0);
                line.push_str(&format!(", about {left:.0} s left"));
            }
        } else {
            line.push_str(&format!(", {secs:.0} s"));
        }
        line
    }

    /// Ends the reporter: a final line if any progress line was shown.
    pub fn finish(&self) {
        if !self.enabled || !self.shown.load(Ordering::Relaxed) {
            return;
        }
        let line = self.line(self.done.load(Ordering::Relaxed), self.start.elapsed());
        let mut err = std::io::stderr().lock();
        let _ = if self.terminal {
            writeln!(err, "\r{line}\x1b[K")
        } else {
            writeln!(err, "{line}")
        };
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lines_say_how_far_and_how_long() {
        let p = Progress::new("transient", 20000, "steps");
        let l = p.line(5000, Duration::from_secs(10));
        assert_eq!(
            l,
            "transient: 5000/20000 steps (25%), 10 s, about 30 s left"
        );
        assert_eq!(
            p.line(20000, Duration::from_secs(40)),
            "transient: 20000/20000 steps (100%), 40 s"
        );
        p.inc(3);
        assert_eq!(p.done.load(Ordering::Relaxed), 3);
    }
}
