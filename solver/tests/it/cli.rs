//! The real `coil-solve` binary on the deck corpus: every broken deck exits non-zero with
//! a message that names its line (or, for solve-stage decks, the failure), never panics,
//! and leaves no result file behind; every good deck solves and writes results.json.

use std::path::{Path, PathBuf};
use std::process::Command;

fn corpus(kind: &str) -> Vec<PathBuf> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../tests/decks")
        .join(kind);
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "dat"))
        .collect();
    files.sort();
    files
}

/// The `$ expect-<key>: value` header line of a corpus deck (read as bytes: some decks
/// are deliberately not UTF-8).
fn header(path: &Path, key: &str) -> Option<String> {
    let bytes = std::fs::read(path).unwrap();
    let text = String::from_utf8_lossy(&bytes);
    let prefix = format!("$ expect-{key}:");
    text.lines()
        .find_map(|l| l.strip_prefix(&prefix).map(|v| v.trim().to_string()))
}

fn coil_solve(deck: &Path, out: &Path) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_coil-solve"))
        .arg(deck)
        .arg("--out")
        .arg(out)
        .output()
        .expect("coil-solve runs")
}

#[test]
fn every_bad_deck_fails_cleanly_through_the_binary() {
    let decks = corpus("bad");
    assert!(decks.len() >= 30, "the corpus must hold at least 30 decks");
    for deck in decks {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("out");
        let run = coil_solve(&deck, &out);
        let stderr = String::from_utf8_lossy(&run.stderr);
        let name = deck.display();
        assert!(!run.status.success(), "{name}: exit 0");
        // A panic exits with 101; a clean error uses another code.
        assert_ne!(run.status.code(), Some(101), "{name}: panicked: {stderr}");
        assert!(!stderr.contains("panicked"), "{name}: {stderr}");
        let message = header(&deck, "message").expect("expect-message");
        assert!(
            stderr.contains(&message),
            "{name}: no '{message}' in: {stderr}"
        );
        if let Some(line) = header(&deck, "line") {
            assert!(
                stderr.contains(&format!(":{line}:")),
                "{name}: line {line} not named: {stderr}"
            );
        }
        assert!(
            !out.join("results.json").exists(),
            "{name}: results written"
        );
    }
}

#[test]
fn every_good_deck_solves() {
    for deck in corpus("good") {
        let dir = tempfile::tempdir().unwrap();
        let run = coil_solve(&deck, dir.path());
        assert!(
            run.status.success(),
            "{}: {}",
            deck.display(),
            String::from_utf8_lossy(&run.stderr)
        );
        let results = std::fs::read_to_string(dir.path().join("results.json")).unwrap();
        let json: serde_json::Value = serde_json::from_str(&results).unwrap();
        assert!(json["load_cases"].is_array());
        assert!(dir.path().join("model.vtu").exists());
    }
}
