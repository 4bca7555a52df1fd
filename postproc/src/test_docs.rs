//! docs/postproc.md as the tests that hold its measured figures read it: a table found by its
//! header, a sentence found in the prose, and a figure compared with what a test computes to
//! half a unit of its printed last digit (the page's own precision). A page that drifts from
//! the code fails these tests.

use crate::signal::printed_resolution;

/// The text of docs/postproc.md.
pub fn page() -> String {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../docs/postproc.md");
    std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{path}: {e}"))
}

/// The body rows of the page's table whose header line starts with `header`: cells trimmed,
/// bold marks (`**`) removed; the separator row is skipped.
pub fn table(header: &str) -> Vec<Vec<String>> {
    let page = page();
    let mut lines = page
        .lines()
        .skip_while(|line| !line.trim_start().starts_with(header));
    assert!(
        lines.next().is_some(),
        "docs/postproc.md has no table headed `{header}`"
    );
    lines
        .skip(1)
        .map(str::trim)
        .take_while(|line| line.starts_with('|'))
        .map(|line| {
            line.trim_matches('|')
                .split('|')
                .map(|cell| cell.replace("**", "").trim().to_string())
                .collect()
        })
        .collect()
}

/// Asserts that the page's prose holds `sentence` (spaces and line breaks collapsed), so a
/// figure a test asserts in code is the one the page prints.
pub fn assert_prose(sentence: &str) {
    let collapse = |text: &str| text.split_whitespace().collect::<Vec<_>>().join(" ");
    assert!(
        collapse(&page()).contains(&collapse(sentence)),
        "docs/postproc.md no longer says `{sentence}`"
    );
}

/// Asserts that `got` prints as `printed` does: within half a unit of its last digit.
pub fn assert_printed(got: f64, printed: &str, what: &str) {
    let value: f64 = printed
        .trim()
        .parse()
        .unwrap_or_else(|_| panic!("{what}: `{printed}` is not a number"));
    let half_unit = 0.5 * printed_resolution(printed.trim());
    assert!(
        (got - value).abs() <= half_unit * (1.0 + 1e-9),
        "{what}: computed {got:.3e}, docs/postproc.md prints {printed} (+-{half_unit:e})"
    );
}
