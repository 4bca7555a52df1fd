//! coil-io owns the file boundary: confined reads, atomic writes, locked output sets, the UFF
//! writer, progress and cancellation. It may import no other coil crate (std, thiserror, libc,
//! sha2); every coil crate may import it.
//!
//! coil's file boundary, one implementation for every binary and library of the workspace
//! (the rules are documented for users in `docs/files.md`).
//!
//! - [`confine`]: paths named inside user files (record paths of a case, files of a
//!   procedure) are relative, stay inside their folder after symlinks are resolved, and
//!   are read with a size limit; error excerpts of user text are short and sanitised
//!   ([`excerpt`]).
//! - [`write`](mod@write): a single output file is written to a fresh temporary in its folder and
//!   renamed, and only over nothing or a regular file: never over (or through) a symlink,
//!   a device, a FIFO or a socket.
//! - [`set`]: a command's output folder is locked for one run (`.coil-lock`: pid, host,
//!   command; a stale lock is taken over), its files are staged in a hidden folder inside
//!   it and moved in as a set with a manifest last; a killed run is rolled forward or
//!   cleaned up by the next one.
//! - [`cancel`]: a process-wide request to stop long loops (Ctrl-C from Python).
//! - [`digest`]: SHA-256, the digest a part file of a sharded study carries.
//! - [`progress`]: progress lines for long runs, also when stderr is not a terminal.
//! - [`uff`]: time histories as Universal File Format dataset 58 (ASCII and 58b), the
//!   writer below both the solver's histories and the diagnosis' fits.
//! - [`stdout`]: printing that treats a closed stdout (`| head -1`) as the end of the
//!   reader's interest, not as an error.
//!
//! Unix only (symlink and file-type checks use `std::os::unix`).

#![warn(missing_docs)]

pub mod cancel;
pub mod confine;
pub mod digest;
pub mod progress;
pub mod set;
pub mod stdout;
pub mod uff;
pub mod write;

pub use confine::{clean_message, excerpt, read_bounded, resolve_inside, ConfineError};
pub use progress::Progress;
pub use set::{OutputSet, SetError};
pub use write::{check_replaceable, open_journal, produce_file, write_file, WriteError};

/// The size limit of an input deck, bytes (`docs/files.md`).
pub const MAX_DECK_BYTES: u64 = 64 << 20;
/// The size limit of a record (a CSV of a measured or computed signal), bytes.
pub const MAX_RECORD_BYTES: u64 = 64 << 20;
/// The size limit of a JSON input (case, variants, calibration), bytes.
pub const MAX_JSON_BYTES: u64 = 8 << 20;
/// The size limit of a procedure file, bytes.
pub const MAX_PROCEDURE_BYTES: u64 = 1 << 20;

/// Where a non-finite number (`NaN`, `inf`) sits in generated text (VTU, CSV or the
/// `Debug` form of the results), skipping quoted strings (titles); `None` if all finite.
pub fn non_finite_token(text: &str) -> Option<usize> {
    let mut scan = NonFiniteScan::default();
    scan.push(text.as_bytes());
    scan.finish()
}

/// [`non_finite_token`] over text written piece by piece, `write!(scan, "{value:?}")`,
/// without keeping it (the `Debug` form of a large result is as large as its JSON).
#[derive(Debug, Default)]
pub struct NonFiniteScan {
    /// Bytes seen.
    offset: usize,
    quoted: bool,
    previous: u8,
    /// The current token's first bytes (5 at most) and its start and length.
    token: [u8; 5],
    start: usize,
    length: usize,
    found: Option<usize>,
}

impl NonFiniteScan {
    fn push(&mut self, bytes: &[u8]) {
        for &b in bytes {
            if self.found.is_some() {
                return;
            }
            self.byte(b);
        }
    }

    fn byte(&mut self, b: u8) {
        let i = self.offset;
        self.offset += 1;
        let separator = matches!(
            b,
            b' ' | b'\n'
                | b'\t'
                | b','
                | b'['
                | b']'
                | b'('
                | b')'
                | b'{'
                | b'}'
                | b'<'
                | b'>'
                | b'='
                | b':'
                | b'"'
        );
        if separator {
            let token = &self.token[..self.length.min(5)];
            if !self.quoted && self.length <= 4 && matches!(token, b"NaN" | b"inf" | b"-inf") {
                self.found = Some(self.start);
            }
            if b == b'"' && (i == 0 || self.previous != b'\\') {
                self.quoted = !self.quoted;
            }
            self.start = i + 1;
            self.length = 0;
        } else {
            if self.length < 5 {
                self.token[self.length] = b;
            }
            self.length += 1;
        }
        self.previous = b;
    }

    /// The first non-finite token's offset, the text ended.
    pub fn finish(mut self) -> Option<usize> {
        if self.found.is_none() {
            self.byte(b' ');
        }
        self.found
    }
}

impl std::fmt::Write for NonFiniteScan {
    fn write_str(&mut self, s: &str) -> std::fmt::Result {
        self.push(s.as_bytes());
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    #[test]
    fn non_finite_tokens_are_found_outside_quotes() {
        use super::non_finite_token as t;
        assert_eq!(t("a: 1.0, b: [2.0, NaN]"), Some(17));
        assert_eq!(t("x,inf\n"), Some(2));
        assert_eq!(t("<v>-inf</v>"), Some(3));
        assert_eq!(t("title: \"inf NaN\", k: 3.5"), None);
        assert_eq!(t("information NaNa 1e308"), None);
        // Written piece by piece, tokens cut across pieces are found where they start.
        use std::fmt::Write as _;
        for text in [
            "a: 1.0, b: [2.0, NaN]",
            "title: \"inf NaN\", k: -inf",
            "x: 1e-3",
        ] {
            for cut in 0..text.len() {
                let mut scan = super::NonFiniteScan::default();
                let (head, tail) = text.split_at(cut);
                write!(scan, "{head}").unwrap();
                write!(scan, "{tail}").unwrap();
                assert_eq!(scan.finish(), t(text), "{text} cut at {cut}");
            }
        }
    }
}
