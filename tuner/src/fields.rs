//! Typed, located access to the members of a JSON object (see [`crate::json`]): every
//! error names the file, the line and column, the field's dotted path and what was
//! expected. The case reader and the variants reader are written with it.
//!
//! Unknown members are accepted and ignored by default: the measured-case format says
//! "add optional fields freely", so a newer writer's case must still be read. Inputs that
//! a person writes by hand for one command (a spring, a design target) call
//! [`Object::strict`]: every unknown key is refused with the list of known ones, and an
//! explicit `null` is refused as case.json refuses one (leave the key out instead).

use crate::json::{Member, Node, Value};
use std::path::{Path, PathBuf};

/// A field that is missing, of the wrong kind or out of range.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{}:{line}:{column}: `{field}`: {problem}; expected {expected}", file.display())]
pub struct FieldError {
    /// The file.
    pub file: PathBuf,
    /// Its line (1-based).
    pub line: usize,
    /// Its column (1-based).
    pub column: usize,
    /// Dotted path from the document root, e.g. `spring.pitch_mm` or `variants[2].name`.
    pub field: String,
    /// What is wrong with what was found.
    pub problem: String,
    /// What the field must hold.
    pub expected: String,
}

/// The admissible range of a number.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Range {
    /// Any finite number.
    Finite,
    /// Strictly positive.
    Positive,
    /// Zero or positive.
    NonNegative,
    /// Open interval (lo, hi).
    Open(f64, f64),
    /// A whole number >= 1.
    Count,
}

impl Range {
    fn admits(self, x: f64) -> bool {
        x.is_finite()
            && match self {
                Range::Finite => true,
                Range::Positive => x > 0.0,
                Range::NonNegative => x >= 0.0,
                Range::Open(lo, hi) => x > lo && x < hi,
                Range::Count => x >= 1.0 && x.fract() == 0.0 && x <= f64::from(u32::MAX),
            }
    }

    fn describe(self) -> String {
        match self {
            Range::Finite => "a finite number".into(),
            Range::Positive => "a number > 0".into(),
            Range::NonNegative => "a number >= 0".into(),
            Range::Open(lo, hi) => format!("a number strictly between {lo} and {hi}"),
            Range::Count => "a whole number >= 1".into(),
        }
    }
}

/// An object node with its path, for typed member access.
#[derive(Debug, Clone)]
pub struct Object<'a> {
    file: &'a Path,
    path: String,
    node: &'a Node,
    members: &'a [Member],
}

/// A located scalar or sub-object handed out by [`Object`].
#[derive(Debug, Clone)]
pub struct Field<'a> {
    /// The file.
    pub file: &'a Path,
    /// The field's path in the JSON (e.g. `targets.stiffness_n_mm`).
    pub path: String,
    /// The node.
    pub node: &'a Node,
}

impl<'a> Field<'a> {
    /// An error at this field.
    pub fn error(&self, problem: impl Into<String>, expected: impl Into<String>) -> FieldError {
        FieldError {
            file: self.file.to_path_buf(),
            line: self.node.line,
            column: self.node.column,
            field: self.path.clone(),
            problem: problem.into(),
            expected: expected.into(),
        }
    }

    fn found(&self) -> String {
        match &self.node.value {
            // 1e300 as 1e300, not as 301 digits.
            Value::Number(x) if *x != 0.0 && !(1e-4..1e7).contains(&x.abs()) => {
                format!("found {x:e}")
            }
            Value::Number(x) => format!("found {x}"),
            Value::String(s) => format!("found the string \"{s}\""),
            other => format!("found {}", other.kind()),
        }
    }

    /// The value as a number in `range`; `meaning` says what the number is.
    pub fn number(&self, range: Range, meaning: &str) -> Result<f64, FieldError> {
        match self.node.value {
            Value::Number(x) if range.admits(x) => Ok(x),
            Value::Number(_) => Err(self.error(
                format!(
                    "{} is out of range",
                    self.found().trim_start_matches("found ")
                ),
                format!("{meaning}: {}", range.describe()),
            )),
            _ => Err(self.error(self.found(), format!("{meaning}: {}", range.describe()))),
        }
    }

    /// The value as a non-empty string.
    pub fn string(&self, meaning: &str) -> Result<&'a str, FieldError> {
        match &self.node.value {
            Value::String(s) if !s.trim().is_empty() => Ok(s),
            Value::String(_) => Err(self.error("found an empty string", meaning.to_string())),
            _ => Err(self.error(self.found(), meaning.to_string())),
        }
    }

    /// The value as an object.
    pub fn object(&self, meaning: &str) -> Result<Object<'a>, FieldError> {
        match &self.node.value {
            Value::Object(members) => Ok(Object {
                file: self.file,
                path: self.path.clone(),
                node: self.node,
                members,
            }),
            _ => Err(self.error(self.found(), format!("{meaning} (a JSON object)"))),
        }
    }

    /// The value as an array of located items (`path[i]`).
    pub fn array(&self, meaning: &str) -> Result<Vec<Field<'a>>, FieldError> {
        match &self.node.value {
            Value::Array(items) => Ok(items
                .iter()
                .enumerate()
                .map(|(i, node)| Field {
                    file: self.file,
                    path: format!("{}[{i}]", self.path),
                    node,
                })
                .collect()),
            _ => Err(self.error(self.found(), format!("{meaning} (a JSON array)"))),
        }
    }
}

/// The root of a document as a field named by its file.
pub fn root<'a>(file: &'a Path, node: &'a Node) -> Field<'a> {
    Field {
        file,
        path: String::new(),
        node,
    }
}

impl<'a> Object<'a> {
    fn child_path(&self, key: &str) -> String {
        if self.path.is_empty() {
            key.to_string()
        } else {
            format!("{}.{key}", self.path)
        }
    }

    /// The member `key`, if present.
    pub fn get(&self, key: &str) -> Option<Field<'a>> {
        self.members.iter().find(|m| m.key == key).map(|m| Field {
            file: self.file,
            path: self.child_path(key),
            node: &m.value,
        })
    }

    /// The member `key`, or an error at the object saying it is missing.
    pub fn require(&self, key: &str, meaning: &str) -> Result<Field<'a>, FieldError> {
        self.get(key).ok_or_else(|| FieldError {
            file: self.file.to_path_buf(),
            line: self.node.line,
            column: self.node.column,
            field: self.child_path(key),
            problem: "missing in this object".into(),
            expected: meaning.to_string(),
        })
    }

    /// A required number in `range`.
    pub fn number(&self, key: &str, range: Range, meaning: &str) -> Result<f64, FieldError> {
        self.require(key, &format!("{meaning}: {}", range.describe()))?
            .number(range, meaning)
    }

    /// An optional number in `range` (`null` counts as absent).
    pub fn opt_number(
        &self,
        key: &str,
        range: Range,
        meaning: &str,
    ) -> Result<Option<f64>, FieldError> {
        match self.get(key) {
            None => Ok(None),
            Some(f) if f.node.value == Value::Null => Ok(None),
            Some(f) => f.number(range, meaning).map(Some),
        }
    }

    /// A required non-empty string.
    pub fn string(&self, key: &str, meaning: &str) -> Result<String, FieldError> {
        self.require(key, meaning)?
            .string(meaning)
            .map(str::to_string)
    }

    /// An optional string (`null` counts as absent).
    pub fn opt_string(&self, key: &str, meaning: &str) -> Result<Option<String>, FieldError> {
        match self.get(key) {
            None => Ok(None),
            Some(f) if f.node.value == Value::Null => Ok(None),
            Some(f) => f.string(meaning).map(|s| Some(s.to_string())),
        }
    }

    /// Refuses unknown keys (naming every one, with the `known` list) and explicit
    /// `null`s (naming the key: leave it out for its default).
    pub fn strict(&self, known: &[&str]) -> Result<(), FieldError> {
        let unknown: Vec<&Member> = self
            .members
            .iter()
            .filter(|m| !known.contains(&m.key.as_str()))
            .collect();
        if let Some(first) = unknown.first() {
            let names = unknown
                .iter()
                .map(|m| format!("`{}`", m.key))
                .collect::<Vec<_>>()
                .join(", ");
            let field = Field {
                file: self.file,
                path: self.child_path(&first.key),
                node: &first.value,
            };
            return Err(field.error(
                format!(
                    "unknown key{} {names}",
                    if unknown.len() > 1 { "s" } else { "" }
                ),
                format!("one of the known keys: {}", known.join(", ")),
            ));
        }
        if let Some(m) = self.members.iter().find(|m| m.value.value == Value::Null) {
            let field = Field {
                file: self.file,
                path: self.child_path(&m.key),
                node: &m.value,
            };
            return Err(field.error(
                "found null",
                "a value; leave the key out for its default (or when it does not apply)",
            ));
        }
        Ok(())
    }

    /// Position of the object itself (for errors that concern several members).
    pub fn error(&self, problem: impl Into<String>, expected: impl Into<String>) -> FieldError {
        FieldError {
            file: self.file.to_path_buf(),
            line: self.node.line,
            column: self.node.column,
            field: if self.path.is_empty() {
                "(document)".into()
            } else {
                self.path.clone()
            },
            problem: problem.into(),
            expected: expected.into(),
        }
    }
}
