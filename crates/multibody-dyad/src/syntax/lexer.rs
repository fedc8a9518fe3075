//! The lexer: source text to tokens. Words are all `Ident` tokens; the
//! parser decides which are keywords where, because Dyad uses some of them
//! as names too (`phi(initial = 0)`).

use crate::reports::diagnostics::Diagnostic;
use crate::syntax::source::{FileId, Span};

#[derive(Clone, Debug, PartialEq)]
pub enum TokenKind {
    Ident(String),
    Number(f64),
    /// A `"..."` string, escapes decoded.
    Str(String),
    /// A `"""..."""` string, as written.
    TripleStr(String),
    LParen,
    RParen,
    LBracket,
    RBracket,
    LBrace,
    RBrace,
    Comma,
    Semicolon,
    Colon,
    ColonColon,
    Dot,
    Eq,
    EqEq,
    NotEq,
    Lt,
    Le,
    Gt,
    Ge,
    FatArrow,
    Bar,
    Bang,
    Question,
    AndAnd,
    OrOr,
    Plus,
    Minus,
    Star,
    Slash,
    Caret,
    Percent,
    DotPlus,
    DotMinus,
    DotStar,
    DotSlash,
    DotCaret,
    Eof,
}

impl TokenKind {
    /// How the token reads in a message: `` `=` ``, "a number", "the end of the file".
    pub fn describe(&self) -> String {
        match self {
            TokenKind::Ident(name) => format!("`{name}`"),
            TokenKind::Number(_) => "a number".into(),
            TokenKind::Str(_) | TokenKind::TripleStr(_) => "a string".into(),
            TokenKind::Eof => "the end of the file".into(),
            other => format!("`{}`", other.symbol()),
        }
    }

    fn symbol(&self) -> &'static str {
        use TokenKind::*;
        match self {
            LParen => "(",
            RParen => ")",
            LBracket => "[",
            RBracket => "]",
            LBrace => "{",
            RBrace => "}",
            Comma => ",",
            Semicolon => ";",
            Colon => ":",
            ColonColon => "::",
            Dot => ".",
            Eq => "=",
            EqEq => "==",
            NotEq => "!=",
            Lt => "<",
            Le => "<=",
            Gt => ">",
            Ge => ">=",
            FatArrow => "=>",
            Bar => "|",
            Bang => "!",
            Question => "?",
            AndAnd => "&&",
            OrOr => "||",
            Plus => "+",
            Minus => "-",
            Star => "*",
            Slash => "/",
            Caret => "^",
            Percent => "%",
            DotPlus => ".+",
            DotMinus => ".-",
            DotStar => ".*",
            DotSlash => "./",
            DotCaret => ".^",
            Ident(_) | Number(_) | Str(_) | TripleStr(_) | Eof => "",
        }
    }
}

#[derive(Clone, Debug, PartialEq)]
pub struct Token {
    pub kind: TokenKind,
    pub span: Span,
}

/// Splits a file into tokens, ending with `Eof`. Stops at the first
/// character that starts no token.
pub fn tokenize(file: FileId, text: &str) -> Result<Vec<Token>, Diagnostic> {
    // Editors on Windows may start a file with a byte-order mark.
    let start = if text.starts_with('\u{feff}') { '\u{feff}'.len_utf8() } else { 0 };
    Lexer { file, text, pos: start, tokens: Vec::new() }.run()
}

struct Lexer<'a> {
    file: FileId,
    text: &'a str,
    pos: usize,
    tokens: Vec<Token>,
}

fn is_ident_start(c: char) -> bool {
    c.is_alphabetic() || c == '_'
}

fn is_ident_continue(c: char) -> bool {
    // `is_numeric` also takes subscripts such as the `₁` of `C₁`.
    c.is_alphanumeric() || c == '_'
}

impl Lexer<'_> {
    fn span(&self, start: usize) -> Span {
        Span::new(self.file, start, self.pos)
    }

    fn peek(&self) -> Option<char> {
        self.text[self.pos..].chars().next()
    }

    fn peek_at(&self, offset: usize) -> Option<char> {
        self.text[self.pos..].chars().nth(offset)
    }

    fn bump(&mut self) -> Option<char> {
        let c = self.peek()?;
        self.pos += c.len_utf8();
        Some(c)
    }

    fn push(&mut self, kind: TokenKind, start: usize) {
        let span = self.span(start);
        self.tokens.push(Token { kind, span });
    }

    fn run(mut self) -> Result<Vec<Token>, Diagnostic> {
        while let Some(c) = self.peek() {
            let start = self.pos;
            if c.is_whitespace() {
                self.bump();
            } else if c == '#' {
                while let Some(c) = self.bump() {
                    if c == '\n' {
                        break;
                    }
                }
            } else if c == '"' {
                self.string()?;
            } else if c.is_ascii_digit() {
                self.number()?;
            } else if is_ident_start(c) {
                while self.peek().is_some_and(is_ident_continue) {
                    self.bump();
                }
                let word = self.text[start..self.pos].to_string();
                self.push(TokenKind::Ident(word), start);
            } else {
                self.punctuation(c)?;
            }
        }
        let end = self.text.len();
        self.tokens.push(Token { kind: TokenKind::Eof, span: Span::new(self.file, end, end) });
        Ok(self.tokens)
    }

    fn punctuation(&mut self, c: char) -> Result<(), Diagnostic> {
        use TokenKind::*;
        let start = self.pos;
        let next = self.peek_at(1);
        let (kind, len) = match (c, next) {
            ('(', _) => (LParen, 1),
            (')', _) => (RParen, 1),
            ('[', _) => (LBracket, 1),
            (']', _) => (RBracket, 1),
            ('{', _) => (LBrace, 1),
            ('}', _) => (RBrace, 1),
            (',', _) => (Comma, 1),
            (';', _) => (Semicolon, 1),
            (':', Some(':')) => (ColonColon, 2),
            (':', _) => (Colon, 1),
            ('.', Some('+')) => (DotPlus, 2),
            ('.', Some('-')) => (DotMinus, 2),
            ('.', Some('*')) => (DotStar, 2),
            ('.', Some('/')) => (DotSlash, 2),
            ('.', Some('^')) => (DotCaret, 2),
            ('.', _) => (Dot, 1),
            ('=', Some('=')) => (EqEq, 2),
            ('=', Some('>')) => (FatArrow, 2),
            ('=', _) => (Eq, 1),
            ('!', Some('=')) => (NotEq, 2),
            ('!', _) => (Bang, 1),
            ('<', Some('=')) => (Le, 2),
            ('<', Some('>')) => (NotEq, 2),
            ('<', _) => (Lt, 1),
            ('>', Some('=')) => (Ge, 2),
            ('>', _) => (Gt, 1),
            ('|', Some('|')) => (OrOr, 2),
            ('|', _) => (Bar, 1),
            ('&', Some('&')) => (AndAnd, 2),
            ('?', _) => (Question, 1),
            ('+', _) => (Plus, 1),
            ('-', _) => (Minus, 1),
            ('*', _) => (Star, 1),
            ('/', _) => (Slash, 1),
            ('^', _) => (Caret, 1),
            ('%', _) => (Percent, 1),
            _ => {
                self.bump();
                return Err(Diagnostic::error(format!("unexpected character `{}`", c.escape_debug()))
                    .primary(self.span(start), "no token starts with this character")
                    .help("remove it, or put it inside a string or a `#` comment"));
            }
        };
        for _ in 0..len {
            self.bump();
        }
        self.push(kind, start);
        Ok(())
    }

    /// `123`, `1.5`, `1e-6`, `3.986004418e14`.
    fn number(&mut self) -> Result<(), Diagnostic> {
        let start = self.pos;
        let digits = |l: &mut Self| {
            while l.peek().is_some_and(|c| c.is_ascii_digit()) {
                l.bump();
            }
        };
        digits(self);
        if self.peek() == Some('.') && self.peek_at(1).is_some_and(|c| c.is_ascii_digit()) {
            self.bump();
            digits(self);
        }
        if matches!(self.peek(), Some('e' | 'E')) {
            let sign = usize::from(matches!(self.peek_at(1), Some('+' | '-')));
            if self.peek_at(1 + sign).is_some_and(|c| c.is_ascii_digit()) {
                for _ in 0..=sign {
                    self.bump();
                }
                digits(self);
            }
        }
        let literal = &self.text[start..self.pos];
        if let Some(c) = self.peek().filter(|&c| is_ident_start(c)) {
            let suffix_start = self.pos;
            while self.peek().is_some_and(is_ident_continue) {
                self.bump();
            }
            let suffix = &self.text[suffix_start..self.pos];
            let mut d = Diagnostic::error(format!("a number cannot be followed directly by `{suffix}`"))
                .primary(Span::new(self.file, suffix_start, self.pos), "unexpected letters after the number");
            d = if "QRYZEPTGMkhdcmμunpfazyrq".contains(c) && suffix.chars().count() <= 2 {
                d.help(format!(
                    "SI-prefix suffixes such as `{literal}{suffix}` are not supported yet; write the power of ten, e.g. `{literal}e-3` for milli"
                ))
            } else {
                d.help(format!("put an operator or a space between them, e.g. `{literal} * {suffix}`"))
            };
            return Err(d);
        }
        let value: f64 = literal.parse().unwrap_or(f64::INFINITY);
        if !value.is_finite() {
            return Err(Diagnostic::error(format!("the number `{literal}` is too large"))
                .primary(self.span(start), "out of range")
                .help("numbers must be below about 1.8e308"));
        }
        self.push(TokenKind::Number(value), start);
        Ok(())
    }

    fn string(&mut self) -> Result<(), Diagnostic> {
        let start = self.pos;
        if self.text[self.pos..].starts_with("\"\"\"") {
            self.pos += 3;
            let Some(len) = self.text[self.pos..].find("\"\"\"") else {
                self.pos = start + 3;
                return Err(Diagnostic::error("this `\"\"\"` string is never closed")
                    .primary(self.span(start), "the string starts here")
                    .help("end it with `\"\"\"`"));
            };
            let body = self.text[self.pos..self.pos + len].to_string();
            self.pos += len + 3;
            self.push(TokenKind::TripleStr(body), start);
            return Ok(());
        }
        self.bump();
        let mut value = String::new();
        loop {
            let Some(c) = self.bump() else {
                self.pos = start + 1;
                return Err(Diagnostic::error("this string is never closed")
                    .primary(self.span(start), "the string starts here")
                    .help("end it with `\"`"));
            };
            match c {
                '"' => break,
                '\\' => value.push(self.escape()?),
                c => value.push(c),
            }
        }
        self.push(TokenKind::Str(value), start);
        Ok(())
    }

    /// The character after a backslash (JSON escapes, and `\v`).
    fn escape(&mut self) -> Result<char, Diagnostic> {
        let start = self.pos - 1;
        let bad = |l: &Self| {
            Diagnostic::error("unknown escape in a string")
                .primary(l.span(start), "not an escape")
                .help("the escapes are \\\" \\\\ \\/ \\b \\f \\n \\r \\t \\v and \\uXXXX; write \\\\ for a backslash")
        };
        Ok(match self.bump() {
            Some('"') => '"',
            Some('\\') => '\\',
            Some('/') => '/',
            Some('b') => '\u{8}',
            Some('f') => '\u{c}',
            Some('n') => '\n',
            Some('r') => '\r',
            Some('t') => '\t',
            Some('v') => '\u{b}',
            Some('u') => {
                let hex: String = (0..4)
                    .filter_map(|_| self.peek().filter(char::is_ascii_hexdigit).and_then(|_| self.bump()))
                    .collect();
                let code = u32::from_str_radix(&hex, 16).ok().filter(|_| hex.len() == 4);
                code.and_then(char::from_u32).ok_or_else(|| bad(self))?
            }
            _ => return Err(bad(self)),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn kinds(text: &str) -> Vec<TokenKind> {
        tokenize(0, text).unwrap().into_iter().map(|t| t.kind).collect()
    }

    #[test]
    fn numbers_names_and_operators() {
        use TokenKind::*;
        assert_eq!(
            kinds("r_cm = [0.5, 1e-6] # comment\n.* C₁"),
            vec![
                Ident("r_cm".into()),
                Eq,
                LBracket,
                Number(0.5),
                Comma,
                Number(1e-6),
                RBracket,
                DotStar,
                Ident("C₁".into()),
                Eof
            ]
        );
    }

    #[test]
    fn strings_keep_markdown_hashes_and_quotes() {
        let k = kinds("\"\"\"\n# Title \"quoted\"\n\"\"\" \"a\\n\\u0041\"");
        assert_eq!(k[0], TokenKind::TripleStr("\n# Title \"quoted\"\n".into()));
        assert_eq!(k[1], TokenKind::Str("a\nA".into()));
    }

    #[test]
    fn a_byte_order_mark_and_windows_line_ends_are_accepted() {
        use TokenKind::*;
        assert_eq!(kinds("\u{feff}end\r\n# c\r\nend"), vec![Ident("end".into()), Ident("end".into()), Eof]);
    }

    #[test]
    fn si_suffixes_are_explained() {
        let e = tokenize(0, "abstol = 10m").unwrap_err();
        assert!(e.help[0].contains("SI-prefix"), "{e:?}");
    }
}
