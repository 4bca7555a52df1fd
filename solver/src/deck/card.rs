//! What every card shares, below the registry and the reader: the [`Keyword`] entry
//! type, the deck's sections, and [`CardCtx`], the cursor and raw deck a card's parse
//! function reads its data lines into, with the field readers that check each value
//! where it is read. Nothing here knows a particular card.

use super::error::{DeckError, Loc};
use super::lexer::{self, Field, Line, LineKind, LIST_WORDS};
use super::raw::{RawDeck, RawList, RawLoadCase};

/// The three sections of a deck, in order.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub enum DeckSection {
    /// Before `END`.
    Parameters,
    /// Between `END` and `END OPTION`.
    Model,
    /// After `END OPTION`: load cases closed by `CONTINUE`.
    History,
}

impl DeckSection {
    /// The section in words, as error messages name it.
    pub fn describe(self) -> &'static str {
        match self {
            DeckSection::Parameters => "parameter section",
            DeckSection::Model => "model definition",
            DeckSection::History => "history",
        }
    }
}

/// Whose layout a card follows.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Origin {
    /// The layout of public Marc decks (possibly restricted; see the card's notes).
    Marc,
    /// coil's own definition (Marc has no public layout for it, or coil's differs).
    Coil,
    /// A Marc card whose physics coil does not model: reading it is an error that
    /// names it and what coil supports.
    Unsupported,
}

pub(crate) type ParseFn = fn(&mut CardCtx<'_, '_>) -> Result<(), DeckError>;

/// One card of the deck language.
pub struct Keyword {
    /// Upper case; words separated by one blank (`FIXED DISP`).
    pub name: &'static str,
    /// Where the card may appear.
    pub sections: &'static [DeckSection],
    /// Whose layout the card follows.
    pub origin: Origin,
    /// What the card means, in one or two sentences.
    pub meaning: &'static str,
    /// The card's lines, keyword line first: (fields, meaning).
    pub layout: &'static [(&'static str, &'static str)],
    /// Leniency, restrictions and differences to Marc.
    pub notes: &'static str,
    /// A complete example of the card.
    pub example: &'static str,
    pub(crate) parse: ParseFn,
}

/// The keyword of `table` a line starts with, and how many fields its words take. The
/// longest keyword wins (`END OPTION` over `END`).
pub(crate) fn match_in(
    table: &'static [Keyword],
    line: &Line,
) -> Option<(&'static Keyword, usize)> {
    let first = line.fields.first()?;
    if !first.text.starts_with(|c: char| c.is_ascii_alphabetic()) {
        return None;
    }
    // A fixed-format keyword field: its words, as Marc reads them (the first 10
    // characters count: `large stra` is LARGE STRAIN).
    let lead = (line.fixed.is_some() && line.lead_words > 0).then(|| {
        line.fields[..line.lead_words]
            .iter()
            .map(|f| f.text.to_ascii_uppercase())
            .collect::<Vec<_>>()
            .join(" ")
    });
    let mut best: Option<(&'static Keyword, usize, usize)> = None;
    for kw in table {
        let words: Vec<&str> = kw.name.split(' ').collect();
        let full = words.len() <= line.fields.len()
            && words
                .iter()
                .zip(&line.fields)
                .all(|(w, f)| f.text.eq_ignore_ascii_case(w));
        let cut = lead
            .as_deref()
            .is_some_and(|s| s.len() == 10 && kw.name.len() > 10 && kw.name.starts_with(s));
        let taken = if full {
            words.len()
        } else if cut {
            line.lead_words
        } else {
            continue;
        };
        if best.is_none_or(|(_, _, n)| words.len() > n) {
            best = Some((kw, taken, words.len()));
        }
    }
    best.map(|(kw, taken, _)| (kw, taken))
}

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
    /// The registry the card was found in (to tell a keyword line inside its data).
    pub table: &'static [Keyword],
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
                if let Some((kw, _)) = match_in(self.table, l) {
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

    /// The card's data lines one at a time, for cards of one line per entry: while
    /// the next line is data ([`Self::more_data`]), it is read against `layout`,
    /// checked for `fields.0..=fields.1` fields and handed to `entry`. A card without
    /// a data line is an error naming `layout`.
    pub fn each_line(
        &mut self,
        layout: &str,
        fields: (usize, usize),
        mut entry: impl FnMut(&mut Self, &'a Line) -> Result<(), DeckError>,
    ) -> Result<(), DeckError> {
        let mut done = 0;
        while self.more_data() {
            let l = self.data_line(layout)?;
            self.field_count(l, fields.0, fields.1, layout)?;
            entry(self, l)?;
            done += 1;
        }
        if done == 0 {
            return Err(no_groups(self, layout));
        }
        Ok(())
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
    /// A blank line is an empty list. Items are de-duplicated as they are read (an item
    /// repeated 400,000 times is kept once), so the work and memory of a list are linear
    /// in its text and sets are expanded once.
    pub fn list(&mut self, what: &str) -> Result<RawList, DeckError> {
        let first = self.any_data_line(what)?;
        let mut list = RawList {
            items: Vec::new(),
            loc: first.start_loc(),
        };
        let mut seen = std::collections::HashSet::new();
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
            for (item, loc) in items {
                if seen.insert(item.clone()) {
                    list.items.push((item, loc));
                }
            }
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

pub(crate) fn once(
    c: &CardCtx<'_, '_>,
    previous: Option<super::error::Loc>,
) -> Result<(), DeckError> {
    match previous {
        Some(first) => Err(c.err(
            c.loc(),
            format!(
                "a second {} (the first is at line {})",
                c.kw.name, first.line
            ),
            format!("one {}", c.kw.name),
        )),
        None => Ok(()),
    }
}

/// True while another group is due: `n` groups if `n > 0`, else while data follows.
pub(crate) fn another(c: &mut CardCtx<'_, '_>, n: u64, done: u64) -> bool {
    if n > 0 {
        done < n
    } else {
        c.more_data()
    }
}

/// Reads a Marc header line whose first field is a count (blank = 0) and whose
/// further fields are integers coil does not use, starting at field `count_at`.
pub(crate) fn header_count(
    c: &mut CardCtx<'_, '_>,
    line: &Line,
    count_at: usize,
    what: &str,
) -> Result<u64, DeckError> {
    let n = c.uint_or(line, count_at, 0, what)?;
    for i in count_at + 1..line.fields.len() {
        c.uint_or(line, i, 0, "Marc's header flags: integers")?;
    }
    Ok(n)
}

/// Fails unless the keyword line has nothing after the keyword but, optionally, the
/// qualifier word Mentat writes (`isotropic           structural`).
pub(crate) fn qualifier(c: &CardCtx<'_, '_>, word: &str) -> Result<(), DeckError> {
    match c.args() {
        [q] if q.text.eq_ignore_ascii_case(word) => Ok(()),
        _ => c.no_args(),
    }
}

pub(crate) fn no_groups(c: &CardCtx<'_, '_>, layout: &str) -> DeckError {
    c.err(c.loc(), "the card has no data lines", layout)
}

/// True if a set or table name (in a deck read with the keywords of `table`) would be read as something else: a keyword's first
/// word or a list word.
///
/// The first words of the multi-word keywords of coil's first deck language stay
/// reserved (`FIXED`, `POINT`, ...); those of Marc's further cards (`BEAM SECT`, `ALL
/// POINTS`, ...) are not, so that existing decks keep their set names: a list line
/// that spells a whole keyword is still refused where it is read.
pub(crate) fn reserved_in(table: &[Keyword], name: &str) -> bool {
    const FIRST_WORDS: [&str; 11] = [
        "END",
        "FIXED",
        "POINT",
        "INITIAL",
        "HISTORY",
        "AUTO",
        "TIME",
        "MODAL",
        "DYNAMIC",
        "QUADRATIC",
        "CUBIC",
    ];
    let upper = name.to_ascii_uppercase();
    LIST_WORDS.contains(&upper.as_str())
        || FIRST_WORDS.contains(&upper.as_str())
        || table.iter().any(|kw| kw.name == upper)
}
