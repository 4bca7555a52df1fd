//! docs/architecture.md's crate diagram against the repository: each box's
//! `(folder/, N.Nk)`, the lines of Rust under the folder's `src/`, within 10 % of the count
//! (the diagram is redrawn by hand; a crate that grew or shrank by a tenth fails here
//! until it is). Every workspace crate with a `src/` appears in the diagram.

use std::path::Path;

fn rust_lines(dir: &Path) -> usize {
    let mut n = 0;
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.is_dir() {
            n += rust_lines(&path);
        } else if path.extension().is_some_and(|e| e == "rs") {
            n += std::fs::read_to_string(&path).unwrap().lines().count();
        }
    }
    n
}

#[test]
fn architecture_crate_sizes_match_the_diagram() {
    let repo = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let text = std::fs::read_to_string(repo.join("docs/architecture.md")).unwrap();
    // A box's "(folder/," and its "N.Nk)" may sit on different lines, but within a row
    // of boxes both run left to right: the two lists in reading order pair up.
    let folders: Vec<&str> = text
        .split('(')
        .skip(1)
        .filter_map(|p| p.split_once("/,").map(|(f, _)| f))
        .filter(|f| !f.is_empty() && f.chars().all(|c| c.is_ascii_lowercase()))
        .collect();
    let figures: Vec<f64> = text
        .split("k)")
        .filter_map(|p| {
            let tail = p
                .rsplit(|c: char| !(c.is_ascii_digit() || c == '.'))
                .next()?;
            tail.parse().ok()
        })
        .collect();
    assert_eq!(
        folders.len(),
        figures.len(),
        "{folders:?} against {figures:?}"
    );
    let mut seen = Vec::new();
    for (folder, stated) in folders.iter().zip(&figures) {
        let counted = rust_lines(&repo.join(folder).join("src")) as f64 / 1000.0;
        println!("{folder}: diagram {stated}k, counted {counted:.2}k");
        assert!(
            (counted / stated - 1.0).abs() <= 0.10,
            "{folder}: docs/architecture.md says {stated}k lines, src/ has {counted:.2}k"
        );
        seen.push(folder.to_string());
    }
    for entry in std::fs::read_dir(&repo).unwrap() {
        let path = entry.unwrap().path();
        if path.join("Cargo.toml").is_file() && path.join("src").is_dir() {
            let name = path.file_name().unwrap().to_string_lossy().to_string();
            assert!(seen.contains(&name), "{name}/ is not in the diagram");
        }
    }
}
