//! A small JSON reader that keeps the line and column of every value, so that a case
//! file's errors can name `file:line:column`, the field's path (`spring.pitch_mm`) and
//! what was expected, for a wrong value as well as for a syntax error.
//!
//! serde_json reports positions only for syntax errors; a value that parses but is out
//! of range (a negative wire diameter) would lose its location. Case files are small
//! (a few hundred bytes), so a located tree costs nothing.
//!
//! The grammar is RFC 8259: objects, arrays, strings with escapes (including surrogate
//! pairs), numbers, `true`, `false`, `null`. Duplicate keys are an error (JSON leaves
//! them undefined; a case with two `mass_kg` is a mistake). Numbers are parsed as f64;
//! a number that overflows to infinity is an error, naming the member it is the value of
//! (`envelope.inner_diameter_mm`). Columns count characters, 1-based.

use std::fmt;

/// A JSON value with the position of its first character.
#[derive(Debug, Clone, PartialEq)]
pub struct Node {
    /// The value.
    pub value: Value,
    /// Its line (1-based).
    pub line: usize,
    /// Its column (1-based).
    pub column: usize,
}

/// The JSON value kinds; object members keep their order and their key's position.
#[derive(Debug, Clone, PartialEq)]
pub enum Value {
    /// `null`.
    Null,
    /// `true` or `false`.
    Bool(bool),
    /// A number.
    Number(f64),
    /// A string.
    String(String),
    /// An array.
    Array(Vec<Node>),
    /// An object, its keys in order.
    Object(Vec<Member>),
}

/// One `"key": value` member of an object.
#[derive(Debug, Clone, PartialEq)]
pub struct Member {
    /// The key.
    pub key: String,
    /// Line of the key.
    pub key_line: usize,
    /// Column of the key.
    pub key_column: usize,
    /// The value.
    pub value: Node,
}

impl Value {
    /// What the value is, for messages ("a string", "an object", ...).
    pub fn kind(&self) -> &'static str {
        match self {
            Value::Null => "null",
            Value::Bool(_) => "a boolean",
            Value::Number(_) => "a number",
            Value::String(_) => "a string",
            Value::Array(_) => "an array",
            Value::Object(_) => "an object",
        }
    }
}

/// A syntax error at a position.
#[derive(Debug, Clone, PartialEq)]
pub struct SyntaxError {
    /// Its line (1-based).
    pub line: usize,
    /// Its column (1-based).
    pub column: usize,
    /// What is wrong and what was expected.
    pub message: String,
}

impl fmt::Display for SyntaxError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}:{}: {}", self.line, self.column, self.message)
    }
}

/// Parses a whole document: one value, surrounded only by whitespace.
pub fn parse(text: &str) -> Result<Node, SyntaxError> {
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let mut p = Parser {
        chars: text.chars().collect(),
        pos: 0,
        line: 1,
        column: 1,
        depth: 0,
        path: Vec::new(),
    };
    p.skip_ws();
    let node = p.value()?;
    p.skip_ws();
    if p.pos < p.chars.len() {
        return Err(p.error("unexpected text after the JSON value; expected the end of the file"));
    }
    Ok(node)
}

/// Nesting deeper than this is refused instead of risking the stack.
const MAX_DEPTH: usize = 128;

struct Parser {
    chars: Vec<char>,
    pos: usize,
    line: usize,
    column: usize,
    depth: usize,
    /// The member names and array indices down to the value being read.
    path: Vec<String>,
}

impl Parser {
    fn error(&self, message: impl Into<String>) -> SyntaxError {
        SyntaxError {
            line: self.line,
            column: self.column,
            message: message.into(),
        }
    }

    /// `` `a.b[2]` = `` for the value being read inside an object or array, else empty.
    fn member(&self) -> String {
        if self.path.is_empty() {
            return String::new();
        }
        let mut name = String::new();
        for part in &self.path {
            if !name.is_empty() && !part.starts_with('[') {
                name.push('.');
            }
            name.push_str(part);
        }
        format!("`{name}` = ")
    }

    fn peek(&self) -> Option<char> {
        self.chars.get(self.pos).copied()
    }

    fn bump(&mut self) -> Option<char> {
        let c = self.peek()?;
        self.pos += 1;
        if c == '\n' {
            self.line += 1;
            self.column = 1;
        } else {
            self.column += 1;
        }
        Some(c)
    }

    fn skip_ws(&mut self) {
        while matches!(self.peek(), Some(' ' | '\t' | '\n' | '\r')) {
            self.bump();
        }
    }

    fn expect_char(&mut self, want: char, what: &str) -> Result<(), SyntaxError> {
        match self.peek() {
            Some(c) if c == want => {
                self.bump();
                Ok(())
            }
            Some(c) => Err(self.error(format!("found `{c}`; expected {what}"))),
            None => Err(self.error(format!("the file ends here; expected {what}"))),
        }
    }

    fn value(&mut self) -> Result<Node, SyntaxError> {
        let (line, column) = (self.line, self.column);
        let value = match self.peek() {
            None => return Err(self.error("the file ends here; expected a JSON value")),
            Some('{') => self.object()?,
            Some('[') => self.array()?,
            Some('"') => Value::String(self.string()?),
            Some('t') => self.literal("true", Value::Bool(true))?,
            Some('f') => self.literal("false", Value::Bool(false))?,
            Some('n') => self.literal("null", Value::Null)?,
            Some(c) if c == '-' || c.is_ascii_digit() => self.number()?,
            Some(c) => {
                return Err(self.error(format!(
                    "found `{c}`; expected a JSON value (number, string, object, array, true, false, null)"
                )))
            }
        };
        Ok(Node {
            value,
            line,
            column,
        })
    }

    fn nest(&mut self) -> Result<(), SyntaxError> {
        self.depth += 1;
        if self.depth > MAX_DEPTH {
            return Err(self.error(format!("nesting deeper than {MAX_DEPTH} levels")));
        }
        Ok(())
    }

    fn object(&mut self) -> Result<Value, SyntaxError> {
        self.nest()?;
        self.bump();
        let mut members: Vec<Member> = Vec::new();
        self.skip_ws();
        if self.peek() == Some('}') {
            self.bump();
            self.depth -= 1;
            return Ok(Value::Object(members));
        }
        loop {
            self.skip_ws();
            let (key_line, key_column) = (self.line, self.column);
            if self.peek() != Some('"') {
                return Err(match self.peek() {
                    Some(c) => self.error(format!("found `{c}`; expected a quoted member name")),
                    None => self.error("the file ends inside an object; expected a member name"),
                });
            }
            let key = self.string()?;
            if members.iter().any(|m| m.key == key) {
                return Err(SyntaxError {
                    line: key_line,
                    column: key_column,
                    message: format!(
                        "member `{key}` appears twice in this object; expected unique names"
                    ),
                });
            }
            self.skip_ws();
            self.expect_char(':', "`:` after the member name")?;
            self.skip_ws();
            self.path.push(key.clone());
            let value = self.value()?;
            self.path.pop();
            members.push(Member {
                key,
                key_line,
                key_column,
                value,
            });
            self.skip_ws();
            match self.peek() {
                Some(',') => {
                    self.bump();
                }
                Some('}') => {
                    self.bump();
                    self.depth -= 1;
                    return Ok(Value::Object(members));
                }
                Some(c) => return Err(self.error(format!("found `{c}`; expected `,` or `}}`"))),
                None => return Err(self.error("the file ends inside an object; expected `}`")),
            }
        }
    }

    fn array(&mut self) -> Result<Value, SyntaxError> {
        self.nest()?;
        self.bump();
        let mut items = Vec::new();
        self.skip_ws();
        if self.peek() == Some(']') {
            self.bump();
            self.depth -= 1;
            return Ok(Value::Array(items));
        }
        loop {
            self.skip_ws();
            self.path.push(format!("[{}]", items.len()));
            items.push(self.value()?);
            self.path.pop();
            self.skip_ws();
            match self.peek() {
                Some(',') => {
                    self.bump();
                }
                Some(']') => {
                    self.bump();
                    self.depth -= 1;
                    return Ok(Value::Array(items));
                }
                Some(c) => return Err(self.error(format!("found `{c}`; expected `,` or `]`"))),
                None => return Err(self.error("the file ends inside an array; expected `]`")),
            }
        }
    }

    fn literal(&mut self, word: &str, value: Value) -> Result<Value, SyntaxError> {
        for want in word.chars() {
            if self.peek() != Some(want) {
                return Err(self.error(format!("expected `{word}`")));
            }
            self.bump();
        }
        Ok(value)
    }

    fn number(&mut self) -> Result<Value, SyntaxError> {
        let (line, column) = (self.line, self.column);
        let start = self.pos;
        let digits = |p: &mut Parser| -> usize {
            let mut n = 0;
            while matches!(p.peek(), Some(c) if c.is_ascii_digit()) {
                p.bump();
                n += 1;
            }
            n
        };
        if self.peek() == Some('-') {
            self.bump();
        }
        let leading_zero = self.peek() == Some('0');
        let int_digits = digits(self);
        if int_digits == 0 {
            return Err(self.error("expected a digit"));
        }
        if leading_zero && int_digits > 1 {
            return Err(SyntaxError {
                line,
                column,
                message: "a number must not start with 0 followed by digits".into(),
            });
        }
        if self.peek() == Some('.') {
            self.bump();
            if digits(self) == 0 {
                return Err(self.error("expected a digit after the decimal point"));
            }
        }
        if matches!(self.peek(), Some('e' | 'E')) {
            self.bump();
            if matches!(self.peek(), Some('+' | '-')) {
                self.bump();
            }
            if digits(self) == 0 {
                return Err(self.error("expected a digit in the exponent"));
            }
        }
        let text: String = self.chars[start..self.pos].iter().collect();
        match text.parse::<f64>() {
            Ok(x) if x.is_finite() => Ok(Value::Number(x)),
            _ => Err(SyntaxError {
                line,
                column,
                message: format!(
                    "{}{text} is out of the range of a double; expected a finite number",
                    self.member()
                ),
            }),
        }
    }

    fn string(&mut self) -> Result<String, SyntaxError> {
        self.bump();
        let mut out = String::new();
        loop {
            let Some(c) = self.peek() else {
                return Err(self.error("the file ends inside a string; expected a closing `\"`"));
            };
            match c {
                '"' => {
                    self.bump();
                    return Ok(out);
                }
                '\\' => {
                    self.bump();
                    let Some(e) = self.bump() else {
                        return Err(self.error("the file ends inside an escape"));
                    };
                    match e {
                        '"' => out.push('"'),
                        '\\' => out.push('\\'),
                        '/' => out.push('/'),
                        'b' => out.push('\u{8}'),
                        'f' => out.push('\u{c}'),
                        'n' => out.push('\n'),
                        'r' => out.push('\r'),
                        't' => out.push('\t'),
                        'u' => {
                            let high = self.hex4()?;
                            let code = if (0xD800..0xDC00).contains(&high) {
                                if self.bump() != Some('\\') || self.bump() != Some('u') {
                                    return Err(self.error("expected the low half of a surrogate pair (`\\uDC00`..`\\uDFFF`)"));
                                }
                                let low = self.hex4()?;
                                if !(0xDC00..0xE000).contains(&low) {
                                    return Err(self.error("expected the low half of a surrogate pair (`\\uDC00`..`\\uDFFF`)"));
                                }
                                0x10000 + ((high - 0xD800) << 10) + (low - 0xDC00)
                            } else {
                                high
                            };
                            match char::from_u32(code) {
                                Some(ch) => out.push(ch),
                                None => return Err(self.error(format!("\\u{code:04X} is not a character"))),
                            }
                        }
                        other => {
                            return Err(self.error(format!(
                                "`\\{other}` is not a JSON escape; expected one of \\\" \\\\ \\/ \\b \\f \\n \\r \\t \\uXXXX"
                            )))
                        }
                    }
                }
                c if (c as u32) < 0x20 => {
                    return Err(
                        self.error("a control character inside a string; write it as an escape")
                    )
                }
                c => {
                    self.bump();
                    out.push(c);
                }
            }
        }
    }

    fn hex4(&mut self) -> Result<u32, SyntaxError> {
        let mut code = 0;
        for _ in 0..4 {
            let digit = self.peek().and_then(|c| c.to_digit(16));
            match digit {
                Some(d) => {
                    self.bump();
                    code = code * 16 + d;
                }
                None => return Err(self.error("expected four hexadecimal digits after \\u")),
            }
        }
        Ok(code)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn positions_are_those_an_editor_shows() {
        let doc = parse("{\n  \"a\": 1.5,\n  \"b\": [true, null, \"x\\u00e9\"]\n}").unwrap();
        let Value::Object(members) = &doc.value else {
            panic!("object expected")
        };
        assert_eq!((members[0].key_line, members[0].key_column), (2, 3));
        assert_eq!(members[0].value.value, Value::Number(1.5));
        assert_eq!((members[0].value.line, members[0].value.column), (2, 8));
        let Value::Array(items) = &members[1].value.value else {
            panic!("array expected")
        };
        assert_eq!(items[2].value, Value::String("x\u{e9}".into()));
        assert_eq!((items[1].line, items[1].column), (3, 15));
    }

    #[test]
    fn syntax_errors_are_located() {
        for (text, line, column, needle) in [
            ("{\"a\": 1,}", 1, 9, "member name"),
            ("{\"a\" 1}", 1, 6, "`:`"),
            ("{\"a\": 1, \"a\": 2}", 1, 10, "twice"),
            ("[1, 2", 1, 6, "ends inside an array"),
            ("{\"a\": 1e999}", 1, 7, "`a` = 1e999 is out of the range"),
            ("{\"e\": {\"d\": [1, -1e400]}}", 1, 17, "`e.d[1]` = -1e400"),
            ("{\"a\": NaN}", 1, 7, "JSON value"),
            ("{\"a\": 01}", 1, 7, "start with 0"),
            ("{}\n x", 2, 2, "after the JSON value"),
            ("\"\\q\"", 1, 4, "escape"),
            ("", 1, 1, "expected a JSON value"),
        ] {
            let e = parse(text).unwrap_err();
            assert_eq!((e.line, e.column), (line, column), "{text}: {e}");
            assert!(e.message.contains(needle), "{text}: {e}");
        }
    }

    #[test]
    fn numbers_and_surrogates() {
        let doc = parse("[-0.5e-3, 12, 0, \"\\ud83d\\ude00\"]").unwrap();
        let Value::Array(items) = doc.value else {
            panic!("array expected")
        };
        assert_eq!(items[0].value, Value::Number(-0.5e-3));
        assert_eq!(items[1].value, Value::Number(12.0));
        assert_eq!(items[2].value, Value::Number(0.0));
        assert_eq!(items[3].value, Value::String("\u{1F600}".into()));
    }

    #[test]
    fn deep_nesting_is_refused_not_a_stack_overflow() {
        let text = "[".repeat(100_000);
        assert!(parse(&text).unwrap_err().message.contains("nesting"));
    }
}
