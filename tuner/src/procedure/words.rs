//! The words of a procedure line and the small values every command parses from them:
//! numbers, targets, tolerances, names inside the output folder, word counts.

use crate::error::ProcedureError;
use std::path::Path;

/// What [`ProcedureError`]s are returned as while parsing a line.
pub type Parsed<T> = std::result::Result<T, ProcedureError>;

/// A number or the case's target.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum TargetValue {
    /// This value.
    Number(f64),
    /// The case's `targets` value.
    Target,
}

/// Splits a line into words (double quotes group blanks; `#` outside quotes ends it).
pub(crate) fn words(text: &str) -> Parsed<Vec<String>> {
    let mut out = Vec::new();
    let mut chars = text.chars().peekable();
    loop {
        while chars.peek().is_some_and(|c| c.is_whitespace()) {
            chars.next();
        }
        match chars.peek() {
            None | Some('#') => return Ok(out),
            Some('"') => {
                chars.next();
                let mut word = String::new();
                loop {
                    match chars.next() {
                        Some('"') => break,
                        Some(c) => word.push(c),
                        None => return Err(ProcedureError::UnclosedQuote),
                    }
                }
                out.push(word);
            }
            Some(_) => {
                let mut word = String::new();
                while let Some(&c) = chars.peek() {
                    if c.is_whitespace() {
                        break;
                    }
                    word.push(c);
                    chars.next();
                }
                out.push(word);
            }
        }
    }
}

/// A finite number; `what` says what was expected.
pub(crate) fn number(word: &str, what: &str) -> Parsed<f64> {
    word.parse::<f64>()
        .ok()
        .filter(|x| x.is_finite())
        .ok_or_else(|| ProcedureError::NotANumber {
            word: word.to_string(),
            expected: what.to_string(),
        })
}

/// A positive number or `target`.
pub(crate) fn target_value(word: &str, what: &str) -> Parsed<TargetValue> {
    if word == "target" {
        Ok(TargetValue::Target)
    } else {
        let x = number(word, &format!("{what} or `target`"))?;
        if x > 0.0 {
            Ok(TargetValue::Number(x))
        } else {
            Err(ProcedureError::NotPositive {
                value: x,
                what: what.to_string(),
            })
        }
    }
}

/// Checks that the line `w` (the command first) has `min` to `max` words.
pub(crate) fn arity(w: &[String], min: usize, max: usize, usage: &str) -> Parsed<()> {
    if w.len() < min || w.len() > max {
        Err(ProcedureError::WordCount {
            text: w.join(" "),
            takes: if min + 1 == max && max - 1 == min {
                format!("{} or {} words", min - 1, max - 1)
            } else if min == max {
                format!("{} word(s) after the command", min - 1)
            } else {
                format!("{} to {} words after the command", min - 1, max - 1)
            },
            usage: usage.to_string(),
        })
    } else {
        Ok(())
    }
}

/// The line's words do not have the command's form.
pub(crate) fn usage_error(w: &[String], usage: &str) -> ProcedureError {
    ProcedureError::Usage {
        text: w.join(" "),
        usage: usage.to_string(),
    }
}

/// Nothing, or `tolerance TOL` with `TOL` in (0, 1).
pub(crate) fn optional_tolerance(rest: &[String], usage: &str) -> Parsed<Option<f64>> {
    match rest {
        [] => Ok(None),
        [t, value] if t == "tolerance" => {
            let x = number(value, "a relative tolerance")?;
            if x > 0.0 && x < 1.0 {
                Ok(Some(x))
            } else {
                Err(ProcedureError::Tolerance { value: x })
            }
        }
        _ => Err(ProcedureError::Unexpected {
            text: rest.join(" "),
            usage: usage.to_string(),
        }),
    }
}

/// A file or folder name written in a procedure: relative, no `..` (the boundary rules of
/// `docs/files.md`: a procedure writes only inside its output folder).
pub(crate) fn inside_name(word: &str, expected: &str) -> Parsed<String> {
    coil_io::confine::check_entry(word, Path::new("the folder")).map_err(|e| {
        ProcedureError::Outside {
            reason: e.to_string(),
            expected: expected.to_string(),
        }
    })?;
    if word.chars().any(char::is_control) {
        return Err(ProcedureError::BadName {
            text: coil_io::excerpt(word),
            expected: expected.to_string(),
        });
    }
    Ok(word.to_string())
}

/// A grid name: it names the grid's files, so letters, digits, `_`, `-` and `.` only.
pub(crate) fn grid_name(word: &str) -> Parsed<String> {
    let ok = !word.is_empty()
        && word.len() <= 64
        && !word.starts_with('.')
        && word
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || matches!(c, '_' | '-' | '.'));
    if ok {
        Ok(word.to_string())
    } else {
        Err(ProcedureError::GridName {
            text: coil_io::excerpt(word),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quotes_group_blanks_and_hash_ends_the_line() {
        assert_eq!(
            words(r#"case "my cases/spring 3" # comment"#).unwrap(),
            ["case", "my cases/spring 3"]
        );
        assert_eq!(words("echo \"open"), Err(ProcedureError::UnclosedQuote));
    }
}
