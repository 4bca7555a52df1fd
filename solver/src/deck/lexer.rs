//! Stage one of reading: deck text -> located lines and fields.
//!
//! Marc's free format: a line is split at commas into fields, and each comma-separated
//! chunk is split again at blanks, so `1, 2, 3`, `1 2 3` and `1 TO 20` all give
//! separate fields. Two commas with nothing between them give a blank field; one
//! trailing comma is allowed and ignored (Mentat writes `TITLE job1,`). A line whose
//! first non-blank character is `$` is a comment. A blank line is a *data* line with
//! no fields wherever a card expects a line (as in Marc), and is skipped between cards
//! and between the groups of a card.
//!
//! Numbers follow Fortran as Marc does: `1.5e-9`, `1.5E-9`, `1.5D-9`, `1.5-9` (an
//! exponent sign right after the mantissa) and `1e21` are all numbers; `inf`, `NaN`
//! and anything else that is not a finite number are rejected with the exact token.
//!
//! Lists (of nodes or elements) are ids, `a TO b` ranges with an optional `BY k`, and
//! set names; a trailing `C` field continues the list on the next line.

use super::error::Loc;

/// One field of a data or keyword line: its text (empty for a blank field) and the
/// 1-based column where it starts.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Field {
    pub text: String,
    pub col: usize,
}

/// What a line is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum LineKind {
    /// Only blanks.
    Blank,
    /// First non-blank character is `$`.
    Comment,
    /// Anything else.
    Text,
}

/// Column widths of Marc's fixed format: integers, reals and words (keywords, names).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Widths {
    pub int: usize,
    pub real: usize,
    pub word: usize,
}

/// Marc's normal fixed format: integers in 5 columns, reals and words in 10.
pub(crate) const NORMAL: Widths = Widths {
    int: 5,
    real: 10,
    word: 10,
};

/// Marc's extended fixed format (parameter `EXTENDED`): integers in 10 columns, reals
/// and words in 20.
pub(crate) const EXTENDED: Widths = Widths {
    int: 10,
    real: 20,
    word: 20,
};

/// A line of the deck with its number, its raw text and its fields.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Line {
    pub no: usize,
    pub raw: String,
    pub kind: LineKind,
    pub fields: Vec<Field>,
    /// The fixed-format widths the line was cut with; `None` for a free-format line
    /// (one with a comma, or any line of a free-format deck).
    pub fixed: Option<Widths>,
    /// How many leading fields are the words of the line's first (keyword or name)
    /// field of a fixed-format line.
    pub lead_words: usize,
    /// Why the line cannot be cut into fixed-format fields (a number out of its
    /// columns), if it cannot; reported when a card reads the line as data.
    pub cut_error: Option<(Loc, String)>,
}

impl Line {
    /// Location of field `i`, or of the end of the line if it has no field `i`.
    pub fn loc_of(&self, i: usize) -> Loc {
        match self.fields.get(i) {
            Some(f) => Loc::new(self.no, f.col),
            None => self.end_loc(),
        }
    }

    /// Location just past the last character.
    pub fn end_loc(&self) -> Loc {
        Loc::new(self.no, self.raw.chars().count() + 1)
    }

    /// Location of the first field (or column 1).
    pub fn start_loc(&self) -> Loc {
        match self.fields.first() {
            Some(f) => Loc::new(self.no, f.col),
            None => Loc::new(self.no, 1),
        }
    }
}

/// The longest deck line, bytes: far above any card's (a list is continued on the next
/// line), low enough that a hostile line costs milliseconds.
pub(crate) const MAX_LINE_BYTES: usize = 100_000;

/// A problem found while splitting text into lines: where and what.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct LexError {
    pub loc: Loc,
    pub message: String,
}

/// Splits a deck into lines and fields. Rejects control characters (other than tab
/// and the carriage return of a CRLF line end), which only binary garbage contains.
///
/// The format of each line follows Marc: a line with a comma is free format. A line
/// without one is fixed format when the deck is: extended fixed format after the
/// parameter `EXTENDED`, normal fixed format (5/10/10 columns) in a deck with no
/// comma on any line that is not a comment (what Mentat writes without `EXTENDED`).
/// In coil's own free-format decks (which have commas) a line without a comma is
/// split at blanks, as before; Marc would cut it by columns, which gives the same
/// fields whenever each sits within its columns.
pub(crate) fn lex(text: &str) -> Result<Vec<Line>, LexError> {
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let raws: Vec<&str> = text
        .split('\n')
        .map(|r| r.strip_suffix('\r').unwrap_or(r))
        .collect();
    let is_comment = |r: &str| r.trim_start().starts_with('$');
    let extended_at = raws
        .iter()
        .position(|r| !is_comment(r) && r.trim().eq_ignore_ascii_case("EXTENDED"));
    let no_commas = raws.iter().all(|r| is_comment(r) || !r.contains(','));
    let mut lines = Vec::new();
    for (i, raw) in raws.iter().copied().enumerate() {
        let no = i + 1;
        if raw.len() > MAX_LINE_BYTES {
            return Err(LexError {
                loc: Loc::new(no, MAX_LINE_BYTES + 1),
                message: format!(
                    "a line of {} bytes; deck lines hold at most {MAX_LINE_BYTES} (Marc's fixed format uses 80 columns, extended 160; continue a long list on the next line with `c`)",
                    raw.len()
                ),
            });
        }
        for (c, ch) in raw.chars().enumerate() {
            if ch.is_control() && ch != '\t' {
                return Err(LexError {
                    loc: Loc::new(no, c + 1),
                    message: format!(
                        "unexpected control character U+{:04X} (is this a binary file?)",
                        ch as u32
                    ),
                });
            }
        }
        let widths = match extended_at {
            Some(at) if i > at => Some(EXTENDED),
            Some(_) => None,
            None if no_commas => Some(NORMAL),
            None => None,
        };
        let widths = widths.filter(|_| !raw.contains(','));
        lines.push(split_line(no, raw, widths));
    }
    // `split` yields one empty piece after a final newline; it is not a line.
    if text.ends_with('\n') {
        lines.pop();
    }
    Ok(lines)
}

fn split_line(no: usize, raw: &str, widths: Option<Widths>) -> Line {
    let trimmed = raw.trim_start();
    let kind = if trimmed.is_empty() {
        LineKind::Blank
    } else if trimmed.starts_with('$') {
        LineKind::Comment
    } else {
        LineKind::Text
    };
    let mut line = Line {
        no,
        raw: raw.to_string(),
        kind,
        fields: Vec::new(),
        fixed: None,
        lead_words: 0,
        cut_error: None,
    };
    if kind == LineKind::Text {
        match widths {
            Some(w) => {
                let cut = cut_fixed(no, raw, w);
                line.fields = cut.fields;
                line.lead_words = cut.lead_words;
                line.cut_error = cut.error;
                line.fixed = Some(w);
            }
            None => line.fields = split_fields(raw),
        }
    }
    line
}

/// A fixed-format line cut into fields.
struct Cut {
    fields: Vec<Field>,
    lead_words: usize,
    error: Option<(Loc, String)>,
}

/// Cuts a fixed-format line by columns, never at blanks (Marc's reading, so that
/// `0-2.0+0` is the integer 0 and the real -2.0, and `0Support` the integer 0 and the
/// name `Support`):
/// - a line that starts with a letter in column 1 begins with a word field (a keyword
///   or a name) of `word` columns, longer if a word runs over its end; its words are
///   separate fields (`fixed disp`);
/// - then, field by field: a real (a number with a point or an exponent) right-aligned
///   in `real` columns, else an integer right-aligned in `int` columns, else `int`
///   blank columns (a blank field), else a word of `word` columns (the rest of the
///   line if nothing follows it).
///
/// A number that does not end at its field's last column (a shifted column) is an
/// error, kept with the line and reported when a card reads it as data.
fn cut_fixed(no: usize, raw: &str, w: Widths) -> Cut {
    let chars: Vec<char> = raw.chars().collect();
    let n = chars.len();
    let blank = |c: char| c == ' ' || c == '\t';
    let text_of = |a: usize, b: usize| -> String { chars[a..b.min(n)].iter().collect() };
    let mut fields = Vec::new();
    let mut p = 0;
    let mut lead_words = 0;
    if chars.first().is_some_and(|c| c.is_ascii_alphabetic()) {
        let mut end = w.word.min(n);
        while end < n && !blank(chars[end]) && !blank(chars[end - 1]) {
            end += 1;
        }
        let mut k = 0;
        while k < end {
            if blank(chars[k]) {
                k += 1;
                continue;
            }
            let start = k;
            while k < end && !blank(chars[k]) {
                k += 1;
            }
            fields.push(Field {
                text: text_of(start, k),
                col: start + 1,
            });
            lead_words += 1;
        }
        p = end;
    }
    let mut error = None;
    // One past the last non-blank character: the tests below are O(1), so cutting a
    // line is linear in its length (a blank run is not rescanned field by field).
    let text_end = chars.iter().rposition(|&c| !blank(c)).map_or(0, |i| i + 1);
    while p < n {
        if p >= text_end {
            break;
        }
        // A field's text is one token within its columns; a token may touch the
        // next field's sign or name (Mentat's `0-2.0+0`, `0Support`) but a digit or a
        // point across the boundary means the number runs over its field.
        let token_in = |width: usize| -> Option<(String, usize, bool)> {
            let end = (p + width).min(n);
            let t = text_of(p, end);
            let lead = t.chars().take_while(|&c| blank(c)).count();
            let tok = t.trim();
            if tok.is_empty() {
                return None;
            }
            let single = !tok.contains([' ', '\t']);
            let over = end < n
                && !blank(chars[end - 1])
                && (chars[end].is_ascii_digit() || chars[end] == '.');
            Some((tok.to_string(), p + lead + 1, single && !over))
        };
        if let Some((r, col, true)) = token_in(w.real) {
            if r.contains(['.', 'e', 'E', 'd', 'D']) && looks_numeric(&r) && parse_real(&r).is_ok()
            {
                fields.push(Field { text: r, col });
                p = (p + w.real).min(n);
                continue;
            }
        }
        let is_int = |s: &str| {
            let d = s.strip_prefix(['+', '-']).unwrap_or(s);
            !d.is_empty() && d.chars().all(|c| c.is_ascii_digit())
        };
        let Some((i, col, clean)) = token_in(w.int) else {
            fields.push(Field {
                text: String::new(),
                col: p + 1,
            });
            p = (p + w.int).min(n);
            continue;
        };
        if clean && is_int(&i) {
            fields.push(Field { text: i, col });
            p = (p + w.int).min(n);
            continue;
        }
        if i.starts_with(|c: char| c.is_ascii_alphabetic() || c == '_') {
            let end = if (p + w.word).min(n) >= text_end {
                n
            } else {
                (p + w.word).min(n)
            };
            fields.push(Field {
                text: text_of(p, end).trim().to_string(),
                col,
            });
            p = end;
            continue;
        }
        // A number that runs over the end of its field, or two in one field.
        let token: String = chars[col - 1..]
            .iter()
            .take_while(|&&c| !blank(c))
            .collect();
        error = Some((
            Loc::new(no, col),
            format!(
                "`{token}` does not fit the fixed-format field of columns {}-{} (a shifted column?): integers take {} columns, reals {} (a line with a comma is read in free format)",
                p + 1,
                (p + w.int).min(n),
                w.int,
                w.real,
            ),
        ));
        fields.push(Field { text: token, col });
        break;
    }
    Cut {
        fields,
        lead_words,
        error,
    }
}

/// The fields of a line split at commas and blanks (free format), whatever the line's
/// format: lists are read this way in every format, as Marc does.
pub(crate) fn free_fields(raw: &str) -> Vec<Field> {
    split_fields(raw)
}

fn split_fields(raw: &str) -> Vec<Field> {
    // Chunks between commas, each with the column of its first character.
    let mut chunks: Vec<(usize, Vec<(usize, char)>)> = vec![(1, Vec::new())];
    for (i, ch) in raw.chars().enumerate() {
        let col = i + 1;
        if ch == ',' {
            chunks.push((col + 1, Vec::new()));
        } else if let Some(last) = chunks.last_mut() {
            last.1.push((col, ch));
        }
    }
    let n = chunks.len();
    let mut fields = Vec::new();
    for (k, (start_col, chars)) in chunks.into_iter().enumerate() {
        let mut words: Vec<Field> = Vec::new();
        let mut current: Option<Field> = None;
        for (col, ch) in chars {
            if ch.is_whitespace() {
                if let Some(w) = current.take() {
                    words.push(w);
                }
            } else {
                match current.as_mut() {
                    Some(w) => w.text.push(ch),
                    None => {
                        current = Some(Field {
                            text: ch.to_string(),
                            col,
                        })
                    }
                }
            }
        }
        if let Some(w) = current.take() {
            words.push(w);
        }
        if words.is_empty() {
            // One trailing comma is Marc's habit, not an extra blank field.
            let trailing = k == n - 1 && k > 0;
            if !trailing {
                fields.push(Field {
                    text: String::new(),
                    col: start_col,
                });
            }
        } else {
            fields.extend(words);
        }
    }
    fields
}

/// Parses a real number the way Marc reads one: decimal, with an exponent written
/// `e`, `E`, `d`, `D`, or as a bare sign after the mantissa (`1.5-3` = 1.5e-3).
/// Rejects NaN, infinities, overflow and every other token, naming it.
pub(crate) fn parse_real(token: &str) -> Result<f64, String> {
    if token.is_empty() {
        return Err("the field is blank".to_string());
    }
    let allowed =
        |c: char| c.is_ascii_digit() || matches!(c, '+' | '-' | '.' | 'e' | 'E' | 'd' | 'D');
    if !token.chars().all(allowed) || !token.chars().any(|c| c.is_ascii_digit()) {
        return Err(format!("`{token}` is not a number"));
    }
    let mut s: String = token
        .chars()
        .map(|c| if c == 'd' || c == 'D' { 'e' } else { c })
        .collect();
    if !s.contains(['e', 'E']) {
        // Fortran's exponent without a letter: a sign that follows a digit or a point.
        let bytes = s.as_bytes();
        if let Some(p) = (1..bytes.len()).find(|&i| {
            matches!(bytes[i], b'+' | b'-')
                && (bytes[i - 1].is_ascii_digit() || bytes[i - 1] == b'.')
        }) {
            s.insert(p, 'e');
        }
    }
    match s.parse::<f64>() {
        Ok(v) if v.is_finite() => Ok(v),
        Ok(_) => Err(format!("`{token}` overflows a double")),
        Err(_) => Err(format!("`{token}` is not a number")),
    }
}

/// Parses a non-negative integer (digits with an optional leading `+`).
pub(crate) fn parse_uint(token: &str) -> Result<u64, String> {
    if token.is_empty() {
        return Err("the field is blank".to_string());
    }
    let digits = token.strip_prefix('+').unwrap_or(token);
    if digits.is_empty() || !digits.chars().all(|c| c.is_ascii_digit()) {
        return Err(format!("`{token}` is not a non-negative integer"));
    }
    digits
        .parse::<u64>()
        .map_err(|_| format!("`{token}` is too large"))
}

/// True if the token can start a number (so it is data, not a name or keyword).
pub(crate) fn looks_numeric(token: &str) -> bool {
    token
        .chars()
        .next()
        .is_some_and(|c| c.is_ascii_digit() || matches!(c, '+' | '-' | '.'))
}

/// True if the token is a valid name: a letter or `_` first, then letters, digits,
/// `_`, `-` or `.`.
pub(crate) fn is_name(token: &str) -> bool {
    let mut chars = token.chars();
    chars
        .next()
        .is_some_and(|c| c.is_ascii_alphabetic() || c == '_')
        && chars.all(|c| c.is_ascii_alphanumeric() || matches!(c, '_' | '-' | '.'))
}

/// Words with a meaning inside lists; they cannot be set names.
pub(crate) const LIST_WORDS: [&str; 3] = ["TO", "BY", "C"];

/// One item of a node or element list.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub(crate) enum ListItem {
    Id(u32),
    /// `from TO to [BY by]`, inclusive.
    Range {
        from: u32,
        to: u32,
        by: u32,
    },
    Set(String),
    /// Every node or element (Mentat's blank element list of a material).
    All,
}

/// The items of one list line with their locations, and whether it ends with `C`.
pub(crate) type ListLine = (Vec<(ListItem, Loc)>, bool);

/// Where, what is wrong, what was expected.
pub(crate) type Problem = (Loc, String, String);

/// Parses the fields of one list line. Returns the items (with their locations) and
/// whether the line ends with the continuation mark `C`.
pub(crate) fn parse_list_fields(line: &Line) -> Result<ListLine, Problem> {
    let f = &line.fields;
    let mut items = Vec::new();
    let mut i = 0;
    let mut continued = false;
    let id = |k: usize| -> Result<u32, Problem> {
        let tok = &f[k].text;
        match parse_uint(tok) {
            Ok(v) if v >= 1 && v <= u64::from(u32::MAX) => Ok(v as u32),
            Ok(_) => Err((
                line.loc_of(k),
                format!("id `{tok}` is out of range"),
                "an id from 1 to 4294967295".to_string(),
            )),
            Err(m) => Err((line.loc_of(k), m, "an id".to_string())),
        }
    };
    while i < f.len() {
        let tok = f[i].text.as_str();
        let upper = tok.to_ascii_uppercase();
        if tok.is_empty() {
            return Err((
                line.loc_of(i),
                "blank field in a list".to_string(),
                "ids, `a TO b` ranges or set names".to_string(),
            ));
        }
        if upper == "C" && i == f.len() - 1 {
            continued = true;
            i += 1;
            continue;
        }
        if looks_numeric(tok) {
            let from = id(i)?;
            let loc = line.loc_of(i);
            if f.get(i + 1)
                .is_some_and(|x| x.text.eq_ignore_ascii_case("TO"))
            {
                if i + 2 >= f.len() {
                    return Err((
                        line.end_loc(),
                        format!("range `{from} TO` has no end"),
                        "an id after TO".to_string(),
                    ));
                }
                let to = id(i + 2)?;
                if to < from {
                    return Err((
                        loc,
                        format!("range `{from} TO {to}` runs backwards"),
                        "a range `a TO b` with a <= b".to_string(),
                    ));
                }
                let mut by = 1;
                i += 3;
                if f.get(i).is_some_and(|x| x.text.eq_ignore_ascii_case("BY")) {
                    if i + 1 >= f.len() {
                        return Err((
                            line.end_loc(),
                            "`BY` has no step".to_string(),
                            "a step after BY".to_string(),
                        ));
                    }
                    by = id(i + 1)?;
                    i += 2;
                }
                items.push((ListItem::Range { from, to, by }, loc));
            } else {
                items.push((ListItem::Id(from), loc));
                i += 1;
            }
        } else if LIST_WORDS.contains(&upper.as_str()) {
            return Err((
                line.loc_of(i),
                format!("`{tok}` is misplaced"),
                "`a TO b [BY k]`, with C only as the last field".to_string(),
            ));
        } else if is_name(tok) {
            items.push((ListItem::Set(tok.to_string()), line.loc_of(i)));
            i += 1;
        } else {
            return Err((
                line.loc_of(i),
                format!("`{tok}` is neither an id nor a set name"),
                "ids, `a TO b` ranges or set names".to_string(),
            ));
        }
    }
    Ok((items, continued))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn texts(line: &Line) -> Vec<&str> {
        line.fields.iter().map(|f| f.text.as_str()).collect()
    }

    #[test]
    fn fields_split_at_commas_and_blanks() {
        let lines = lex("1, 2.5  3\n 1 TO 20 c\nTITLE job1,\n1,,2\n  \n$ note\n").unwrap();
        assert_eq!(lines.len(), 6);
        assert_eq!(texts(&lines[0]), ["1", "2.5", "3"]);
        assert_eq!(lines[0].fields[1].col, 4);
        assert_eq!(lines[0].fields[2].col, 9);
        assert_eq!(texts(&lines[1]), ["1", "TO", "20", "c"]);
        assert_eq!(texts(&lines[2]), ["TITLE", "job1"]);
        assert_eq!(texts(&lines[3]), ["1", "", "2"]);
        assert_eq!(lines[3].fields[1].col, 3);
        assert_eq!(lines[4].kind, LineKind::Blank);
        assert_eq!(lines[5].kind, LineKind::Comment);
    }

    #[test]
    fn crlf_bom_and_missing_final_newline() {
        let lines = lex("\u{feff}END\r\nEND OPTION").unwrap();
        assert_eq!(lines.len(), 2);
        assert_eq!(lines[0].raw, "END");
        assert_eq!(texts(&lines[1]), ["END", "OPTION"]);
    }

    #[test]
    fn control_characters_are_rejected_with_location() {
        let e = lex("END\nab\u{0}c\n").unwrap_err();
        assert_eq!(e.loc, Loc::new(2, 3));
        assert!(e.message.contains("U+0000"));
    }

    #[test]
    fn reals_in_every_marc_spelling() {
        for (t, v) in [
            ("1", 1.0),
            ("-2.5", -2.5),
            ("+.5", 0.5),
            ("7.85e-9", 7.85e-9),
            ("7.85E-9", 7.85e-9),
            ("7.85D-9", 7.85e-9),
            ("7.85-9", 7.85e-9),
            ("2.1+5", 2.1e5),
            ("1e21", 1e21),
            ("5.", 5.0),
        ] {
            assert_eq!(parse_real(t), Ok(v), "{t}");
        }
    }

    #[test]
    fn non_finite_and_garbage_reals_are_rejected_naming_the_token() {
        for t in [
            "NaN", "nan", "inf", "-inf", "infinity", "1.2.3", "1e", "abc", "1e999", "--1", "0x10",
            ".",
        ] {
            let e = parse_real(t).unwrap_err();
            assert!(e.contains(&format!("`{t}`")), "{t}: {e}");
        }
        assert!(parse_real("").is_err());
    }

    #[test]
    fn shortest_round_trip_floats_read_back_exactly() {
        for v in [
            7.85e-9,
            190708.0,
            -0.1,
            1.0 / 3.0,
            1e-300,
            6.02e23,
            f64::MIN_POSITIVE,
        ] {
            assert_eq!(parse_real(&format!("{v:?}")), Ok(v));
        }
    }

    #[test]
    fn unsigned_integers() {
        assert_eq!(parse_uint("42"), Ok(42));
        assert_eq!(parse_uint("+7"), Ok(7));
        assert!(parse_uint("-1").is_err());
        assert!(parse_uint("1.0").is_err());
        assert!(parse_uint("99999999999999999999999").is_err());
    }

    #[test]
    fn lists_with_ranges_sets_and_continuation() {
        let lines = lex("1 TO 9 BY 2, 12, clamp, 20 to 21 C\n").unwrap();
        let (items, cont) = parse_list_fields(&lines[0]).unwrap();
        assert!(cont);
        let items: Vec<ListItem> = items.into_iter().map(|(i, _)| i).collect();
        assert_eq!(
            items,
            [
                ListItem::Range {
                    from: 1,
                    to: 9,
                    by: 2
                },
                ListItem::Id(12),
                ListItem::Set("clamp".into()),
                ListItem::Range {
                    from: 20,
                    to: 21,
                    by: 1
                },
            ]
        );
    }

    #[test]
    fn bad_lists_name_the_field() {
        for (text, col) in [
            ("5 TO 3", 1),
            ("1 TO", 5),
            ("1, 0", 4),
            ("1 C 2", 3),
            ("1 #x", 3),
        ] {
            let line = split_line(1, text, None);
            let (loc, _, _) = parse_list_fields(&line).unwrap_err();
            assert_eq!(loc.col, col, "{text}");
        }
    }

    fn ext(raw: &str) -> Line {
        split_line(7, raw, Some(EXTENDED))
    }

    #[test]
    fn extended_fields_are_cut_by_column() {
        // A negative real touching the integer before it, a bare exponent.
        let l = ext(&format!(
            "{:>10}{:>20}{:>20}",
            0, "-2.5+0", "4.000000000000000+1"
        ));
        assert_eq!(texts(&l), ["0", "-2.5+0", "4.000000000000000+1"]);
        assert_eq!(l.fields[1].col, 25);
        assert_eq!(parse_real(&l.fields[2].text), Ok(40.0));
        // A name touching the last integer; a blank integer field.
        let l = ext(&format!("{:>10}{:>10}{:>10}Support", 1, "", 5));
        assert_eq!(texts(&l), ["1", "", "5", "Support"]);
        assert_eq!(l.fields[3].col, 31);
        // A keyword with its words, a qualifier word, integer parameters.
        let l = ext("isotropic           structural");
        assert_eq!(texts(&l), ["isotropic", "structural"]);
        assert_eq!(l.lead_words, 1);
        let l = ext(&format!("{:<20}{:>10}{:>10}", "large stra", 4, 213));
        assert_eq!(texts(&l), ["large", "stra", "4", "213"]);
        assert_eq!(l.lead_words, 2);
        // A line longer than 80 columns.
        let long: String = (0..9)
            .map(|i| format!("{:>20}", format!("{i}.5")))
            .collect();
        assert_eq!(ext(&long).fields.len(), 9);
        assert!(ext(&long).cut_error.is_none());
    }

    #[test]
    fn normal_fixed_fields_are_5_and_10_columns() {
        let l = split_line(1, "elements     27", Some(NORMAL));
        assert_eq!(texts(&l), ["elements", "27"]);
        let l = split_line(1, "    1   27    1   48", Some(NORMAL));
        assert_eq!(texts(&l), ["1", "27", "1", "48"]);
        let l = split_line(
            1,
            &format!("{:>5}{:>10}{:>10}", 12, "1.5-3", "-2.0"),
            Some(NORMAL),
        );
        assert_eq!(texts(&l), ["12", "1.5-3", "-2.0"]);
    }

    #[test]
    fn a_shifted_column_is_an_error_naming_its_column() {
        let l = ext(&format!("{:>10}{:<10}", 1, "2"));
        let (loc, msg) = l.cut_error.unwrap();
        assert_eq!(loc, Loc::new(7, 10));
        assert!(msg.contains("columns 1-10"), "{msg}");
        // Every field one column to the right.
        let l = ext(&format!(" {:>10}{:>20}", 1, "0.000000000000000+0"));
        let (loc, msg) = l.cut_error.unwrap();
        assert_eq!(loc, Loc::new(7, 11), "{msg}");
        // Left-aligned in its field is what Fortran reads too.
        let l = ext(&format!("{:<10}{:>10}", 3, 4));
        assert_eq!(texts(&l), ["3", "4"]);
    }

    #[test]
    fn decks_choose_their_format_line_by_line() {
        let lines =
            lex("title   t\nextended\nsizing                                 0        10\n1, 2\n")
                .unwrap();
        assert_eq!(lines[0].fixed, None);
        assert_eq!(lines[2].fixed, Some(EXTENDED));
        assert_eq!(texts(&lines[2]), ["sizing", "", "0", "10"]);
        assert_eq!(lines[3].fixed, None);
        let lines = lex("elements     27\n").unwrap();
        assert_eq!(lines[0].fixed, Some(NORMAL));
        let lines = lex("ELEMENTS, 98\n1 2\n").unwrap();
        assert_eq!(lines[1].fixed, None);
    }

    #[test]
    fn long_lines_are_cut_in_linear_time_and_bounded() {
        // 90,000 blanks and one character: 18,000 blank fields, cut at once.
        let line = format!("{}7\n", " ".repeat(90_000));
        let start = std::time::Instant::now();
        let lines = lex(&format!("title x\n{line}")).unwrap();
        assert!(start.elapsed().as_secs_f64() < 2.0, "{:?}", start.elapsed());
        assert_eq!(lines[1].fields.last().unwrap().text, "7");
        // Four million blanks: refused at once, naming the line.
        let huge = format!("title x\n{}x\n", " ".repeat(4_000_000));
        let e = lex(&huge).unwrap_err();
        assert_eq!(e.loc.line, 2);
        assert!(e.message.contains("at most 100000"), "{}", e.message);
    }

    #[test]
    fn names() {
        assert!(is_name("clamp_1"));
        assert!(is_name("_x.y-z"));
        assert!(!is_name("1abc"));
        assert!(!is_name("a#b"));
    }
}
