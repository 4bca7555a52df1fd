//! SHA-256 (FIPS 180-4), streaming: the digest a part file of a sharded study carries of
//! its study and of its rows, so that `merge` can refuse an edited or truncated part.
//!
//! A digest proves that a file is the one written; it is not a signature (whoever edits
//! a part and recomputes its digest is not stopped). The hash is RustCrypto's `sha2`
//! (pure Rust, no default features); this module gives it the two calls the study
//! files need and checks it against the NIST examples (FIPS 180-4 appendix / CSRC
//! "SHA_All" examples) in the tests below.

use sha2::Digest;

/// A SHA-256 computation fed piece by piece.
#[derive(Debug, Clone, Default)]
pub struct Sha256(sha2::Sha256);

impl Sha256 {
    /// A fresh computation.
    pub fn new() -> Self {
        Self::default()
    }

    /// Feeds `bytes`.
    pub fn update(&mut self, bytes: &[u8]) {
        self.0.update(bytes);
    }

    /// The digest as 64 lowercase hexadecimal digits.
    pub fn hex(self) -> String {
        self.0
            .finalize()
            .iter()
            .map(|b| format!("{b:02x}"))
            .collect()
    }
}

/// The SHA-256 of `bytes`, hexadecimal.
pub fn sha256_hex(bytes: &[u8]) -> String {
    let mut s = Sha256::new();
    s.update(bytes);
    s.hex()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nist_examples() {
        assert_eq!(
            sha256_hex(b"abc"),
            "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad"
        );
        assert_eq!(
            sha256_hex(b""),
            "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855"
        );
        assert_eq!(
            sha256_hex(b"abcdbcdecdefdefgefghfghighijhijkijkljklmklmnlmnomnopnopq"),
            "248d6a61d20638b8e5c026930c3e6039a33ce45964ff2167f6ecedd419db06c1"
        );
        // One million `a`, fed in uneven pieces (the streaming path).
        let mut s = Sha256::new();
        let piece = [b'a'; 997];
        let mut left = 1_000_000;
        while left > 0 {
            let n = left.min(piece.len());
            s.update(&piece[..n]);
            left -= n;
        }
        assert_eq!(
            s.hex(),
            "cdc76e5c9914fb9281a1c7e284d73e67f1809a48a497200e046d39ccc7112cd0"
        );
    }
}
