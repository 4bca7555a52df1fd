//! The docs' markdown tables as the claims read them: the first table after a heading,
//! its body rows split into trimmed cells, and a printed number's half unit of its last
//! digit (the tolerance a printed figure claims).

/// The body rows of the first table after the line `heading` in `text` (the header and
/// the `|---|` line skipped), each row's cells trimmed.
pub fn table_after(text: &str, heading: &str) -> Vec<Vec<String>> {
    let start = text
        .find(heading)
        .unwrap_or_else(|| panic!("heading `{heading}` not found"));
    let rows: Vec<Vec<String>> = text[start..]
        .lines()
        .skip_while(|l| !l.starts_with('|'))
        .take_while(|l| l.starts_with('|'))
        .map(|l| {
            l.trim()
                .trim_matches('|')
                .split('|')
                .map(|c| c.trim().to_string())
                .collect()
        })
        .collect();
    assert!(rows.len() > 2, "no table after `{heading}`");
    rows[2..].to_vec()
}

/// A printed number and half a unit of its last printed digit.
pub fn printed(cell: &str) -> (f64, f64) {
    let cell = cell.trim().trim_end_matches('%').trim();
    let value: f64 = cell
        .parse()
        .unwrap_or_else(|_| panic!("`{cell}` is not a number"));
    let decimals = cell.split_once('.').map_or(0, |(_, d)| d.len());
    (value, 0.5 * 10f64.powi(-(decimals as i32)) + 1e-9)
}

/// Asserts that `got` prints as `cell` (within half its last digit).
pub fn assert_printed(what: &str, got: f64, cell: &str) {
    if let Some(miss) = misprinted(what, got, cell) {
        panic!("{miss}");
    }
}

/// Why `got` does not print as `cell`, if it does not.
pub fn misprinted(what: &str, got: f64, cell: &str) -> Option<String> {
    let (value, tol) = printed(cell);
    ((got - value).abs() > tol).then(|| format!("{what}: computed {got}, docs {cell}"))
}
