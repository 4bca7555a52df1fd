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

/// A line of the deck with its number, its raw text and its fields.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Line {
    pub no: usize,
    pub raw: String,
    pub kind: LineKind,
    pub fields: Vec<Field>,
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

/// A problem found while splitting text into lines: where and what.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct LexError {
    pub loc: Loc,
    pub message: String,
}

/// Splits a deck into lines and fields. Rejects control characters (other than tab
/// and the carriage return of a CRLF line end), which only binary garbage contains.
pub(crate) fn lex(text: &str) -> Result<Vec<Line>, LexError> {
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let mut lines = Vec::new();
    for (i, raw) in text.split('\n').enumerate() {
        let no = i + 1;
        let raw = raw.strip_suffix('\r').unwrap_or(raw);
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
        lines.push(split_line(no, raw));
    }
    // `split` yields one empty piece after a final newline; it is not a line.
    if text.ends_with('\n') {
        lines.pop();
    }
    Ok(lines)
}

fn split_line(no: usize, raw: &str) -> Line {
    let trimmed = raw.trim_start();
    let kind = if trimmed.is_empty() {
        LineKind::Blank
    } else if trimmed.starts_with('$') {
        LineKind::Comment
    } else {
        LineKind::Text
    };
    let fields = if kind == LineKind::Text {
        split_fields(raw)
    } else {
        Vec::new()
    };
    Line {
        no,
        raw: raw.to_string(),
        kind,
        fields,
    }
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
            let lines = lex(text).unwrap();
            let (loc, _, _) = parse_list_fields(&lines[0]).unwrap_err();
            assert_eq!(loc.col, col, "{text}");
        }
    }

    #[test]
    fn names() {
        assert!(is_name("clamp_1"));
        assert!(is_name("_x.y-z"));
        assert!(!is_name("1abc"));
        assert!(!is_name("a#b"));
    }
}
