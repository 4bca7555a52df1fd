//! The card reader: walks the located lines section by section, finds each card's
//! keyword in the table of [`super::keywords`] and lets that card read its data lines
//! into a [`RawDeck`]. Field-level checks (numbers, counts, ranges of single values)
//! happen here and in the card parsers; checks across cards happen in
//! [`super::build`].
//!
//! Where a card expects a line, the next non-comment line is taken, a blank line
//! being a line with no fields (as in Marc). A keyword line or the end of the file
//! there means the card is incomplete. Between cards and between the repeated groups
//! of a card, blank and comment lines are skipped; a group continues while the next
//! line starts with a number.

use super::error::{DeckError, Loc};
use super::keywords::{self, DeckSection, Keyword};
use super::lexer::{self, Field, Line, LineKind};
use super::raw::{RawDeck, RawList, RawLoadCase};

/// A position in the lines of a deck.
pub(crate) struct Cursor<'a> {
    pub lines: &'a [Line],
    pub pos: usize,
    pub file: &'a str,
}

impl<'a> Cursor<'a> {
    pub fn new(lines: &'a [Line], file: &'a str) -> Self {
        Cursor {
            lines,
            pos: 0,
            file,
        }
    }

    /// The next line that is not a comment (may be blank), without consuming it.
    fn peek_data(&mut self) -> Option<&'a Line> {
        while let Some(l) = self.lines.get(self.pos) {
            if l.kind == LineKind::Comment {
                self.pos += 1;
            } else {
                return Some(l);
            }
        }
        None
    }

    /// The next line that is neither blank nor a comment, without consuming it.
    pub fn peek_significant(&mut self) -> Option<&'a Line> {
        while let Some(l) = self.lines.get(self.pos) {
            if l.kind == LineKind::Text {
                return Some(l);
            }
            self.pos += 1;
        }
        None
    }

    pub fn advance(&mut self) {
        self.pos += 1;
    }

    /// Where the file ends: just past the last character of the last line.
    pub fn eof_loc(&self) -> Loc {
        match self.lines.last() {
            Some(l) => l.end_loc(),
            None => Loc::new(1, 1),
        }
    }
}

/// What a card parser works with: the card's keyword line, its arguments (the
/// fields after the keyword words), the cursor for its data lines and the deck.
pub(crate) struct CardCtx<'c, 'a> {
    pub cur: &'c mut Cursor<'a>,
    pub deck: &'c mut RawDeck,
    pub section: &'c mut DeckSection,
    pub kw: &'static Keyword,
    pub line: &'a Line,
    /// Number of fields of `line` taken by the keyword's words.
    pub kw_fields: usize,
}

impl<'c, 'a> CardCtx<'c, 'a> {
    /// An error inside this card.
    pub fn err(&self, loc: Loc, msg: impl Into<String>, expected: impl Into<String>) -> DeckError {
        DeckError::new(self.cur.file, loc, Some(self.kw.name), msg, expected)
    }

    /// Location of the keyword line.
    pub fn loc(&self) -> Loc {
        self.line.start_loc()
    }

    /// The fields after the keyword.
    pub fn args(&self) -> &'a [Field] {
        self.line.fields.get(self.kw_fields..).unwrap_or(&[])
    }

    /// Location of argument `i` (or the end of the keyword line).
    pub fn arg_loc(&self, i: usize) -> Loc {
        self.line.loc_of(self.kw_fields + i)
    }

    /// The raw text after the keyword (for `TITLE`): leading blanks and one comma
    /// removed, trailing blanks removed.
    pub fn rest_of_line(&self) -> String {
        let end_col = match self
            .kw_fields
            .checked_sub(1)
            .and_then(|i| self.line.fields.get(i))
        {
            Some(f) => f.col - 1 + f.text.chars().count(),
            None => 0,
        };
        let rest: String = self.line.raw.chars().skip(end_col).collect();
        let rest = rest.trim_start();
        let rest = rest.strip_prefix(',').unwrap_or(rest);
        rest.trim().to_string()
    }

    /// Fails unless the keyword line has nothing after the keyword.
    pub fn no_args(&self) -> Result<(), DeckError> {
        match self.args().iter().position(|f| !f.text.is_empty()) {
            None => Ok(()),
            Some(i) => Err(self.err(
                self.arg_loc(i),
                format!("unexpected `{}` after the keyword", self.args()[i].text),
                format!("`{}` alone on its line", self.kw.name),
            )),
        }
    }

    /// The next data line of this card (comments skipped; a blank line is a line
    /// without fields). The end of the file or a keyword line is an error: the card
    /// is incomplete.
    pub fn data_line(&mut self, what: &str) -> Result<&'a Line, DeckError> {
        let line = self.any_data_line(what)?;
        if let Some((loc, msg)) = &line.cut_error {
            return Err(self.err(*loc, msg.clone(), what));
        }
        Ok(line)
    }

    /// [`Self::data_line`] for a line read in free format whatever its format (a
    /// list), so a fixed-format cutting problem does not matter.
    fn any_data_line(&mut self, what: &str) -> Result<&'a Line, DeckError> {
        match self.cur.peek_data() {
            None => Err(self.err(
                self.cur.eof_loc(),
                format!(
                    "the file ends inside the card begun at line {}",
                    self.line.no
                ),
                what,
            )),
            Some(l) => {
                if let Some((kw, _)) = keywords::match_keyword(l) {
                    return Err(self.err(
                        l.start_loc(),
                        format!(
                            "the card `{}` begins before this card (line {}) is complete",
                            kw.name, self.line.no
                        ),
                        what,
                    ));
                }
                self.cur.advance();
                Ok(l)
            }
        }
    }

    /// True if another group (or line) of this card follows: the next significant
    /// line starts with a number. A keyword, a word that is not a keyword, or the
    /// end of the file ends the card (the section reader reports the latter two).
    pub fn more_data(&mut self) -> bool {
        match self.cur.peek_significant() {
            Some(l) if l.fixed.is_some() => l
                .raw
                .split_whitespace()
                .next()
                .is_some_and(lexer::looks_numeric),
            Some(l) => l
                .fields
                .first()
                .is_some_and(|f| lexer::looks_numeric(&f.text)),
            None => false,
        }
    }

    /// Reads a list (one line, continued on the next while a line ends with `C`).
    /// A blank line is an empty list.
    pub fn list(&mut self, what: &str) -> Result<RawList, DeckError> {
        let first = self.any_data_line(what)?;
        let mut list = RawList {
            items: Vec::new(),
            loc: first.start_loc(),
        };
        let mut line = first;
        loop {
            // Marc reads lists in free format in every format.
            let free;
            let read = if line.fixed.is_some() {
                free = Line {
                    fields: lexer::free_fields(&line.raw),
                    fixed: None,
                    lead_words: 0,
                    cut_error: None,
                    ..line.clone()
                };
                &free
            } else {
                line
            };
            if list.items.is_empty() {
                list.loc = read.start_loc();
            }
            let (items, continued) = lexer::parse_list_fields(read)
                .map_err(|(loc, msg, exp)| self.err(loc, msg, exp))?;
            list.items.extend(items);
            if !continued {
                return Ok(list);
            }
            line = self.any_data_line(&format!(
                "the continuation of the list ended with C on line {}",
                line.no
            ))?;
        }
    }

    /// Fails unless `line` has between `min` and `max` fields.
    pub fn field_count(
        &self,
        line: &Line,
        min: usize,
        max: usize,
        layout: &str,
    ) -> Result<(), DeckError> {
        let n = line.fields.len();
        if n < min || n > max {
            let (loc, msg) = if n < min {
                (
                    line.end_loc(),
                    format!("the line has {n} field{}", plural(n)),
                )
            } else {
                (
                    line.loc_of(max),
                    format!(
                        "the line has {n} fields, `{}` is one too many",
                        line.fields[max].text
                    ),
                )
            };
            return Err(self.err(loc, msg, layout));
        }
        Ok(())
    }

    fn field<'l>(&self, line: &'l Line, i: usize, what: &str) -> Result<&'l Field, DeckError> {
        match line.fields.get(i) {
            Some(f) if !f.text.is_empty() => Ok(f),
            Some(_) => Err(self.err(line.loc_of(i), format!("field {} is blank", i + 1), what)),
            None => Err(self.err(
                line.end_loc(),
                format!("the line ends before field {}", i + 1),
                what,
            )),
        }
    }

    /// Field `i` as a finite real.
    pub fn real(&self, line: &Line, i: usize, what: &str) -> Result<f64, DeckError> {
        let f = self.field(line, i, what)?;
        lexer::parse_real(&f.text).map_err(|m| self.err(line.loc_of(i), m, what))
    }

    /// Field `i` as a non-negative integer; a blank or missing field is `blank`.
    pub fn uint_or(&self, line: &Line, i: usize, blank: u64, what: &str) -> Result<u64, DeckError> {
        match line.fields.get(i) {
            None => Ok(blank),
            Some(f) if f.text.is_empty() => Ok(blank),
            Some(f) => lexer::parse_uint(&f.text).map_err(|m| self.err(line.loc_of(i), m, what)),
        }
    }

    /// Field `i` as a non-negative integer.
    pub fn uint(&self, line: &Line, i: usize, what: &str) -> Result<u64, DeckError> {
        let f = self.field(line, i, what)?;
        lexer::parse_uint(&f.text).map_err(|m| self.err(line.loc_of(i), m, what))
    }

    /// Field `i` as a count that fits a `u32` and is at least `min`.
    pub fn count(&self, line: &Line, i: usize, min: u32, what: &str) -> Result<u32, DeckError> {
        let v = self.uint(line, i, what)?;
        if v < u64::from(min) || v > u64::from(u32::MAX) {
            return Err(self.err(
                line.loc_of(i),
                format!("{v} is out of range"),
                format!("{what} (at least {min})"),
            ));
        }
        Ok(v as u32)
    }

    /// Field `i` as a node or element id (1 ..= 4294967295).
    pub fn id(&self, line: &Line, i: usize, what: &str) -> Result<u32, DeckError> {
        let v = self.uint(line, i, what)?;
        if v == 0 || v > u64::from(u32::MAX) {
            return Err(self.err(
                line.loc_of(i),
                format!("id {v} is out of range"),
                format!("{what} from 1 to 4294967295"),
            ));
        }
        Ok(v as u32)
    }

    /// Field `i` as a DOF number 1..=6.
    pub fn dof(&self, line: &Line, i: usize) -> Result<u8, DeckError> {
        const WHAT: &str = "a DOF number 1..6 (1-3 translations x, y, z; 4-6 rotations)";
        let f = self.field(line, i, WHAT)?;
        match lexer::parse_uint(&f.text) {
            Ok(d @ 1..=6) => Ok(d as u8),
            Ok(d) => Err(self.err(line.loc_of(i), format!("DOF {d} does not exist"), WHAT)),
            Err(_) => Err(self.err(
                line.loc_of(i),
                format!("`{}` is not a DOF number", f.text),
                WHAT,
            )),
        }
    }

    /// DOF numbers from field `from` to the end of the line: at least one, no repeats.
    pub fn dofs(&self, line: &Line, from: usize) -> Result<Vec<u8>, DeckError> {
        if line.fields.len() <= from {
            return Err(self.err(line.end_loc(), "no DOF numbers", "DOF numbers 1..6"));
        }
        let mut dofs = Vec::new();
        for i in from..line.fields.len() {
            let d = self.dof(line, i)?;
            if dofs.contains(&d) {
                return Err(self.err(
                    line.loc_of(i),
                    format!("DOF {d} is listed twice"),
                    "each DOF once",
                ));
            }
            dofs.push(d);
        }
        Ok(dofs)
    }

    /// Field `i` as a name (letter or `_` first; letters, digits, `_ - .`).
    pub fn name(&self, line: &Line, i: usize, what: &str) -> Result<String, DeckError> {
        let f = self.field(line, i, what)?;
        if !lexer::is_name(&f.text) {
            return Err(self.err(
                line.loc_of(i),
                format!("`{}` is not a valid name", f.text),
                format!("{what}: a letter or `_` first, then letters, digits, `_`, `-` or `.`"),
            ));
        }
        Ok(f.text.clone())
    }

    /// Marc's further fields that coil does not use must be blank or zero.
    pub fn zeros_from(&self, line: &Line, from: usize, what: &str) -> Result<(), DeckError> {
        for i in from..line.fields.len() {
            let t = &line.fields[i].text;
            if t.is_empty() {
                continue;
            }
            if lexer::parse_real(t).is_ok_and(|v| v == 0.0) {
                continue;
            }
            return Err(self.err(
                line.loc_of(i),
                format!("field {} is `{t}`, but coil does not use {what}", i + 1),
                "the field blank or 0",
            ));
        }
        Ok(())
    }

    /// Fails unless `v > 0`.
    pub fn positive(&self, v: f64, loc: Loc, what: &str) -> Result<f64, DeckError> {
        if v > 0.0 {
            Ok(v)
        } else {
            Err(self.err(loc, format!("{what} is {v:?}"), format!("{what} > 0")))
        }
    }

    /// Fails unless `v >= 0`.
    pub fn non_negative(&self, v: f64, loc: Loc, what: &str) -> Result<f64, DeckError> {
        if v >= 0.0 {
            Ok(v)
        } else {
            Err(self.err(loc, format!("{what} is {v:?}"), format!("{what} >= 0")))
        }
    }

    /// The load case being read, opened at this card if none is open.
    pub fn case(&mut self) -> &mut RawLoadCase {
        let loc = self.line.start_loc();
        self.deck.open_case.get_or_insert_with(|| RawLoadCase {
            loc: Some(loc),
            ..RawLoadCase::default()
        })
    }
}

pub(crate) fn plural(n: usize) -> &'static str {
    if n == 1 {
        ""
    } else {
        "s"
    }
}

/// Reads all cards of a deck into a [`RawDeck`], starting in section `start`. With
/// `complete`, the deck must end in the history section with no open load case.
pub(crate) fn read_cards(
    lines: &[Line],
    file: &str,
    start: DeckSection,
    complete: bool,
) -> Result<RawDeck, DeckError> {
    let mut cur = Cursor::new(lines, file);
    let mut deck = RawDeck::default();
    let mut section = start;
    let mut previous: Option<(&'static str, usize)> = None;
    while let Some(line) = cur.peek_significant() {
        let Some((kw, kw_fields)) = keywords::match_keyword(line) else {
            return Err(not_a_keyword(file, line, previous));
        };
        if !kw.sections.contains(&section) {
            return Err(misplaced(file, line, kw, section, &deck));
        }
        cur.advance();
        let mut ctx = CardCtx {
            cur: &mut cur,
            deck: &mut deck,
            section: &mut section,
            kw,
            line,
            kw_fields,
        };
        (kw.parse)(&mut ctx)?;
        previous = Some((kw.name, line.no));
    }
    if complete {
        let loc = cur.eof_loc();
        let err = |msg: &str, exp: &str| DeckError::new(file, loc, None, msg, exp);
        match section {
            DeckSection::Parameters if previous.is_none() => {
                return Err(err(
                    "the deck is empty (no cards)",
                    "a parameter section ending with END, a model definition ending with END OPTION, then load cases",
                ))
            }
            DeckSection::Parameters => {
                return Err(err(
                    "the file ends in the parameter section",
                    "END, then the model definition",
                ))
            }
            DeckSection::Model => {
                return Err(err(
                    "the file ends in the model definition",
                    "END OPTION, then the load cases",
                ))
            }
            DeckSection::History => {
                if let Some(case) = &deck.open_case {
                    let begun = case.loc.map_or(0, |l| l.line);
                    return Err(err(
                        &format!("the file ends inside the load case begun at line {begun}"),
                        "CONTINUE to close the load case",
                    ));
                }
            }
        }
    }
    Ok(deck)
}

fn not_a_keyword(file: &str, line: &Line, previous: Option<(&str, usize)>) -> DeckError {
    let first = line.fields.first().map_or("", |f| f.text.as_str());
    if first
        .chars()
        .next()
        .is_some_and(|c| c.is_ascii_alphabetic())
    {
        let words: Vec<&str> = line
            .fields
            .iter()
            .take(3)
            .map(|f| f.text.as_str())
            .collect();
        let near = keywords::nearest(&words, 3);
        let shown = if words.len() > 1 && !lexer::looks_numeric(words[1]) && !words[1].is_empty() {
            format!("{} {}", words[0], words[1])
        } else {
            words[0].to_string()
        };
        DeckError::new(
            file,
            line.start_loc(),
            None,
            format!("unknown keyword `{shown}`"),
            format!("a known keyword; the nearest are {}", near.join(", ")),
        )
    } else {
        let after = match previous {
            Some((card, no)) => format!(
                "; the card {card} (line {no}) is already complete (did its previous line need a C continuation, or is a count on its header line too small?)"
            ),
            None => String::new(),
        };
        DeckError::new(
            file,
            line.start_loc(),
            None,
            format!(
                "data line `{}` where a card keyword belongs{after}",
                line.raw.trim()
            ),
            "a keyword",
        )
    }
}

fn misplaced(
    file: &str,
    line: &Line,
    kw: &Keyword,
    section: DeckSection,
    deck: &RawDeck,
) -> DeckError {
    use DeckSection::*;
    let (msg, expected) = match kw.sections.iter().copied().find(|s| *s > section) {
        // The card's section has not begun: the current one lacks its end card.
        Some(target) => {
            let kind = match target {
                Model => "model-definition",
                _ => "history",
            };
            let expected = match (section, target) {
                (Parameters, Model) => "END before the model definition",
                (Parameters, _) => "END, the model definition and END OPTION before the load cases",
                _ => "END OPTION before the first load case",
            };
            (
                format!(
                    "`{}` is a {kind} card, but the {} has not ended",
                    kw.name,
                    section.describe()
                ),
                expected.to_string(),
            )
        }
        None => {
            let home = kw
                .sections
                .iter()
                .map(|s| s.describe())
                .collect::<Vec<_>>()
                .join(" or the ");
            let ended = match section {
                Model => deck.end.map(|l| format!(" (END at line {})", l.line)),
                History => deck
                    .end_option
                    .map(|l| format!(" (END OPTION at line {})", l.line)),
                Parameters => None,
            }
            .unwrap_or_default();
            (
                format!(
                    "`{}` belongs to the {home}, which has already ended{ended}",
                    kw.name
                ),
                format!("a card of the {}", section.describe()),
            )
        }
    };
    DeckError::new(file, line.start_loc(), None, msg, expected)
}
