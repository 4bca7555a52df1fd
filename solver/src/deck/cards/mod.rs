//! THE keyword table (the registry). Every card of the deck language is one [`Keyword`]
//! entry, defined beside its parse function and its tests in the module of its family
//! (`parameters`, `mesh`, `properties`, `masses`, `catenary`, `superelement`,
//! `point_laws`, `loads`,
//! `history`, `mentat`, `control`); [`KEYWORDS`] lists them in the order of the deck
//! reference. The reader
//! finds cards here, the writer and docs/deck.md follow it ([`reference_markdown`];
//! a test keeps docs/deck.md equal to it), and a test here keeps any two keywords from
//! colliding.
//!
//! The parse functions check each field where it is read (a number, a count, a DOF,
//! a value's sign); references between cards (node ids, set names, tables) are
//! resolved afterwards by [`super::build`] and checked by [`crate::model::check`].

pub(crate) mod catenary;
pub(crate) mod control;
pub(crate) mod history;
pub(crate) mod loads;
pub(crate) mod masses;
pub(crate) mod mentat;
pub(crate) mod mesh;
pub(crate) mod parameters;
pub(crate) mod point_laws;
pub(crate) mod properties;
pub(crate) mod superelement;
#[cfg(test)]
pub(crate) mod testing;

use super::card::{match_in, Keyword, Origin};
use super::lexer::Line;

/// Every card, in the order of the deck reference.
pub static KEYWORDS: &[Keyword] = &[
    parameters::TITLE,
    parameters::SIZING,
    parameters::ELEMENTS,
    parameters::LUMP,
    parameters::DYNAMIC,
    parameters::UNIT,
    parameters::END,
    mesh::CONNECTIVITY,
    mesh::COORDINATES,
    mesh::DEFINE,
    properties::ISOTROPIC,
    properties::GEOMETRY,
    masses::DAMPING,
    catenary::BEAM_TENSION,
    catenary::TENSION_LINK,
    catenary::MOVING_CONTACT,
    superelement::DMIG,
    masses::POINT_MASS,
    point_laws::FRICTION,
    point_laws::QUADRATIC_DAMPER,
    point_laws::CUBIC_SPRING,
    point_laws::DASHPOT,
    point_laws::LOSS_FACTOR,
    point_laws::MODAL_DAMPING,
    masses::RBE2,
    loads::FIXED_DISP,
    loads::POINT_LOAD,
    loads::TABLE,
    loads::INITIAL_VEL,
    loads::HISTORY_OUTPUT,
    history::END_OPTION,
    history::AUTO_LOAD,
    history::TIME_STEP,
    history::MODAL_SHAPE,
    history::DYNAMIC_CHANGE,
    history::CONTINUE,
    mentat::EXTENDED,
    mentat::ALLOC,
    mentat::VERSION,
    mentat::PROCESSOR,
    mentat::ALL_POINTS,
    mentat::NO_ECHO,
    mentat::SETNAME,
    mentat::SOLVER,
    mentat::OPTIMIZE,
    mentat::NO_PRINT,
    mentat::POST,
    mentat::PARAMETERS,
    mentat::CONTROL,
    mentat::MAT_COLOR,
    mentat::LOADCASE,
    mentat::BEAM_SECT,
    mentat::DIST_LOADS,
    mentat::LARGE_STRAIN,
    mentat::LARGE_DISP,
    mentat::UPDATE,
    mentat::FINITE,
    mentat::FOLLOW_FOR,
    mentat::PLASTICITY,
    mentat::WORK_HARD,
    mentat::FORCDT,
    mentat::UMOTION,
    mentat::USDATA,
    control::ASSUMED,
    control::CONSTANT_DIL,
    control::CENTROID,
    control::COMMENT,
    control::ELSTO,
    control::MPC_CHECK,
    control::PRINT,
    control::SHELL_SECT,
    control::STATE_VARS,
    control::AUTOMSET,
    control::PRINT_CHOICE,
    control::PRINT_ELEM,
    control::PRINT_NODE,
    control::PRINT_VMASS,
    control::SUMMARY,
    control::ELEMENT_SORT,
    control::NODE_SORT,
    control::RESTART_LAST,
    control::POST_INCREMENT,
];

/// The keyword a line starts with, and how many fields its words take. The longest
/// keyword wins (`END OPTION` over `END`).
pub(crate) fn match_keyword(line: &Line) -> Option<(&'static Keyword, usize)> {
    match_in(KEYWORDS, line)
}

/// Up to `k` keywords nearest (by edit distance) to the line's first words: the best
/// match and any other within two edits of it.
pub(crate) fn nearest(words: &[&str], k: usize) -> Vec<&'static str> {
    let mut scored: Vec<(usize, &'static str)> = KEYWORDS
        .iter()
        .map(|kw| {
            // Compare a keyword of w words with the line's first w words.
            let w = kw.name.split(' ').count().min(words.len()).max(1);
            let candidate = words[..w.min(words.len())].join(" ").to_ascii_uppercase();
            (edit_distance(&candidate, kw.name), kw.name)
        })
        .collect();
    scored.sort();
    // Keep the close ones: within two edits of the best match.
    let best = scored.first().map_or(0, |s| s.0);
    scored
        .into_iter()
        .take_while(|(d, _)| *d <= best + 2)
        .take(k)
        .map(|(_, n)| n)
        .collect()
}

/// Optimal string alignment distance: Levenshtein's insertions, deletions and
/// substitutions plus the swap of two adjacent characters as one edit, the commonest typo
/// (`LAOD` is one edit from `LOAD`, as `POINT` is from `PRINT`).
fn edit_distance(a: &str, b: &str) -> usize {
    let a: Vec<char> = a.chars().collect();
    let b: Vec<char> = b.chars().collect();
    // Three rows: i - 2 (for the swap), i - 1 and i.
    let mut before: Vec<usize> = vec![0; b.len() + 1];
    let mut prev: Vec<usize> = (0..=b.len()).collect();
    let mut cur = vec![0; b.len() + 1];
    for i in 1..=a.len() {
        cur[0] = i;
        for j in 1..=b.len() {
            let subst = prev[j - 1] + usize::from(a[i - 1] != b[j - 1]);
            cur[j] = subst.min(prev[j] + 1).min(cur[j - 1] + 1);
            if i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1] {
                cur[j] = cur[j].min(before[j - 2] + 1);
            }
        }
        std::mem::swap(&mut before, &mut prev);
        std::mem::swap(&mut prev, &mut cur);
    }
    prev[b.len()]
}

/// The card reference of docs/deck.md, generated from [`KEYWORDS`].
pub fn reference_markdown() -> String {
    let mut s = String::new();
    s.push_str("| Card | Sections | Layout | Keyword line | Data lines |\n");
    s.push_str("|---|---|---|---|---|\n");
    for kw in KEYWORDS {
        let lines: Vec<String> = kw
            .layout
            .iter()
            .skip(1)
            .map(|(f, _)| format!("`{f}`"))
            .collect();
        s.push_str(&format!(
            "| [`{}`](#{}) | {} | {} | `{}` | {} |\n",
            kw.name,
            anchor(kw.name),
            sections_text(kw),
            origin_text(kw.origin),
            kw.layout.first().map_or(kw.name, |l| l.0),
            if lines.is_empty() {
                "none".to_string()
            } else {
                lines.join(" / ")
            },
        ));
    }
    for kw in KEYWORDS {
        s.push_str(&format!("\n### {}\n\n", kw.name));
        s.push_str(&format!(
            "*{}* · {}\n\n{}\n\n",
            match kw.origin {
                Origin::Marc => "Layout of public Marc decks",
                Origin::Coil => "coil's own definition",
                Origin::Unsupported => "Marc's card, not supported: reading it is an error",
            },
            sections_text(kw),
            kw.meaning
        ));
        s.push_str("| Line | Fields | Meaning |\n|---|---|---|\n");
        for (i, (fields, meaning)) in kw.layout.iter().enumerate() {
            s.push_str(&format!("| {} | `{}` | {} |\n", i + 1, fields, meaning));
        }
        if !kw.notes.is_empty() {
            s.push_str(&format!("\n{}\n", kw.notes));
        }
        s.push_str(&format!("\n```text\n{}\n```\n", kw.example));
    }
    s
}

fn sections_text(kw: &Keyword) -> String {
    kw.sections
        .iter()
        .map(|s| s.describe())
        .collect::<Vec<_>>()
        .join(", ")
}

fn origin_text(o: Origin) -> &'static str {
    match o {
        Origin::Marc => "Marc",
        Origin::Coil => "**coil's own**",
        Origin::Unsupported => "Marc, **error**",
    }
}

fn anchor(name: &str) -> String {
    name.to_ascii_lowercase().replace(' ', "-")
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::deck::card::reserved_in;
    use crate::deck::cards::testing::first_line;
    use crate::deck::lexer::LIST_WORDS;

    #[test]
    fn no_two_keywords_collide() {
        for (i, a) in KEYWORDS.iter().enumerate() {
            assert_eq!(
                a.name,
                a.name.to_ascii_uppercase(),
                "{} is not upper case",
                a.name
            );
            assert!(
                !a.name.contains("  ") && a.name.trim() == a.name,
                "{}",
                a.name
            );
            assert!(!a.sections.is_empty(), "{}", a.name);
            for b in &KEYWORDS[i + 1..] {
                assert_ne!(a.name, b.name, "keyword {} is defined twice", a.name);
                // Marc reads 10 characters of a keyword: cut, no two may be equal.
                let cut = |n: &str| n.chars().take(10).collect::<String>();
                assert_ne!(
                    cut(a.name),
                    cut(b.name),
                    "{} and {} collide when cut to 10 characters",
                    a.name,
                    b.name
                );
            }
            // Every keyword, in any case, reads as itself and nothing else.
            let line = first_line(&format!("{}, 1", a.name.to_ascii_lowercase()));
            let (kw, n) = match_keyword(&line).unwrap();
            assert_eq!(kw.name, a.name);
            assert_eq!(n, a.name.split(' ').count());
            assert!(!LIST_WORDS.contains(&a.name), "{} is a list word", a.name);
        }
    }

    #[test]
    fn the_longest_keyword_wins() {
        assert_eq!(
            match_keyword(&first_line("END OPTION")).unwrap().0.name,
            "END OPTION"
        );
        assert_eq!(match_keyword(&first_line("end")).unwrap().0.name, "END");
        assert_eq!(
            match_keyword(&first_line("Point Load, table, t"))
                .unwrap()
                .0
                .name,
            "POINT LOAD"
        );
        assert!(match_keyword(&first_line("POINT, 1")).is_none());
        assert!(match_keyword(&first_line("1, 2")).is_none());
    }

    #[test]
    fn nearest_keywords_by_edit_distance() {
        assert_eq!(nearest(&["FIXED", "DSP"], 1), ["FIXED DISP"]);
        assert_eq!(nearest(&["CONECTIVITY"], 1), ["CONNECTIVITY"]);
        assert_eq!(nearest(&["isotropik"], 1), ["ISOTROPIC"]);
        assert_eq!(nearest(&["ENDOPTION"], 1), ["END OPTION"]);
        assert_eq!(nearest(&["POINT", "LAOD", "1"], 1), ["POINT LOAD"]);
        assert_eq!(edit_distance("LAOD", "LOAD"), 1);
        assert_eq!(edit_distance("POINT", "PRINT"), 1);
        assert_eq!(edit_distance("KITTEN", "SITTING"), 3);
        assert_eq!(edit_distance("CA", "ABC"), 3);
        assert!(!nearest(&["x"], 3).is_empty());
        assert!(nearest(&["x"], 3).len() <= 3);
    }

    #[test]
    fn reserved_names() {
        assert!(reserved_in(KEYWORDS, "end"));
        assert!(reserved_in(KEYWORDS, "Point"));
        assert!(reserved_in(KEYWORDS, "to"));
        assert!(!reserved_in(KEYWORDS, "clamp"));
    }
}
