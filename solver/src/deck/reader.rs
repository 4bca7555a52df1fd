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

use super::card::{CardCtx, Cursor, DeckSection, Keyword};
use super::cards::{self, KEYWORDS};
use super::error::DeckError;
use super::lexer::{self, Line};
use super::raw::RawDeck;

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
        let Some((kw, kw_fields)) = cards::match_keyword(line) else {
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
            table: KEYWORDS,
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
        let near = cards::nearest(&words, 3);
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::deck::card::Origin;
    use crate::deck::cards::testing::*;
    use crate::deck::lexer::lex;
    use crate::deck::read_str;

    /// Every example in the table reads as a card in its section.
    #[test]
    fn every_example_parses_in_its_section() {
        for kw in KEYWORDS {
            let lines = lex(kw.example).unwrap();
            let r = read_cards(&lines, "example", kw.sections[0], false);
            if kw.origin == Origin::Unsupported {
                let e = r.unwrap_err().to_string();
                assert!(e.contains(":1:1:") && e.contains("is not supported"), "{e}");
            } else {
                assert!(r.is_ok(), "{}: {}", kw.name, r.unwrap_err());
            }
        }
    }

    #[test]
    fn sections_are_enforced() {
        let e = read_str("CONNECTIVITY\n0\n", "t.dat")
            .unwrap_err()
            .to_string();
        assert!(e.contains("t.dat:1:1: `CONNECTIVITY` is a model-definition card, but the parameter section has not ended"), "{e}");
        let e = read_str(&format!("{PARAMS}{MESH}AUTO LOAD\n1\n"), "t.dat")
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("history card, but the model definition has not ended"),
            "{e}"
        );
        let e = read_str(&format!("{PARAMS}{MESH}END OPTION\nCOORDINATES\n"), "t.dat")
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("`COORDINATES` belongs to the model definition, which has already ended"),
            "{e}"
        );
        let e = read_str(&format!("{PARAMS}ELEMENTS, 52\n"), "t.dat")
            .unwrap_err()
            .to_string();
        assert!(e.contains("already ended (END at line 3)"), "{e}");
    }
}
