//! The one lexer of typed text: it cuts a text into numbers, names and single symbols,
//! each with its place in characters (what a caret line or a message points at), and
//! skips whitespace. What a symbol means, and which are refused with what message, is
//! the grammar's business ([`super::expr`], [`super::constraint`]); so is a symbol of two
//! characters (`**`, `<=`), which the grammar takes with [`Lexer::widen`].

/// How a number is cut from the text.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Numbers {
    /// Digits with at most one point (`3`, `2.5`, `.5`, `1.`; a point alone is a
    /// symbol), then an exponent; an exponent begun and not finished (`2e`, `2e-`) is a
    /// token of its own, [`Kind::OpenExponent`].
    Strict,
    /// A run of digits and points (`1.2.3` is one token, for its grammar to refuse),
    /// then an exponent when digits follow it; otherwise the number ends before the `e`.
    Run,
}

/// What a token is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Kind {
    /// A number's text (not yet read as a value).
    Number,
    /// A number whose exponent has no digits (only with [`Numbers::Strict`]).
    OpenExponent,
    /// A letter or `_`, then letters, digits and `_`.
    Name,
    /// Any other character, alone.
    Symbol(char),
}

/// A token: its kind and its characters `start..end` of the text.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Token {
    /// What it is.
    pub kind: Kind,
    /// Its first character, from 0.
    pub start: usize,
    /// One past its last character.
    pub end: usize,
}

/// The tokens of one text, in order, as an iterator (a grammar that refuses a token stops
/// there, so a refusal is always the first one in the text).
pub(crate) struct Lexer {
    chars: Vec<char>,
    next: usize,
    numbers: Numbers,
}

impl Lexer {
    /// A lexer over `text` that cuts numbers as `numbers` says.
    pub fn new(text: &str, numbers: Numbers) -> Lexer {
        Lexer {
            chars: text.chars().collect(),
            next: 0,
            numbers,
        }
    }

    /// The text's length in characters.
    pub fn len(&self) -> usize {
        self.chars.len()
    }

    /// The character at `at`, if the text is that long.
    pub fn char_at(&self, at: usize) -> Option<char> {
        self.chars.get(at).copied()
    }

    /// The characters `start..end` of the text.
    pub fn slice(&self, start: usize, end: usize) -> String {
        self.chars[start..end].iter().collect()
    }

    /// Takes `n` more characters into the token just returned (a symbol of two
    /// characters).
    pub fn widen(&mut self, n: usize) {
        self.next = (self.next + n).min(self.chars.len());
    }

    fn digit_at(&self, k: usize) -> bool {
        self.chars.get(k).is_some_and(|c| c.is_ascii_digit())
    }

    fn name_char_at(&self, k: usize) -> bool {
        self.chars
            .get(k)
            .is_some_and(|c| c.is_alphanumeric() || *c == '_')
    }

    /// The end of the digits from `i`.
    fn digits_from(&self, mut i: usize) -> usize {
        while self.digit_at(i) {
            i += 1;
        }
        i
    }

    /// A number from `start`, as [`Numbers`] says: its kind and end.
    fn number(&self, start: usize) -> (Kind, usize) {
        let mut i = match self.numbers {
            Numbers::Strict => {
                let i = self.digits_from(start);
                if self.char_at(i) == Some('.') {
                    self.digits_from(i + 1)
                } else {
                    i
                }
            }
            Numbers::Run => {
                let mut i = start;
                while self.digit_at(i) || self.char_at(i) == Some('.') {
                    i += 1;
                }
                i
            }
        };
        if matches!(self.char_at(i), Some('e' | 'E')) {
            let sign = usize::from(matches!(self.char_at(i + 1), Some('+' | '-')));
            if self.digit_at(i + 1 + sign) {
                i = self.digits_from(i + 1 + sign);
            } else if self.numbers == Numbers::Strict && !self.name_char_at(i + 1) {
                // `2e`, `2e-`, `2e+x`: an exponent was begun and not finished. `2ex` is
                // left to the grammar, which reports the missing operator.
                return (Kind::OpenExponent, i + 1 + sign);
            }
        }
        (Kind::Number, i)
    }
}

impl Iterator for Lexer {
    type Item = Token;

    fn next(&mut self) -> Option<Token> {
        while self.char_at(self.next).is_some_and(char::is_whitespace) {
            self.next += 1;
        }
        let start = self.next;
        let c = self.char_at(start)?;
        let number_starts = match self.numbers {
            Numbers::Strict => c.is_ascii_digit() || (c == '.' && self.digit_at(start + 1)),
            Numbers::Run => c.is_ascii_digit() || c == '.',
        };
        let (kind, end) = if number_starts {
            self.number(start)
        } else if c.is_alphabetic() || c == '_' {
            let mut end = start + 1;
            while self.name_char_at(end) {
                end += 1;
            }
            (Kind::Name, end)
        } else {
            (Kind::Symbol(c), start + 1)
        };
        self.next = end;
        Some(Token { kind, start, end })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Each token's kind and text.
    fn cut(text: &str, numbers: Numbers) -> Vec<(Kind, String)> {
        let mut lexer = Lexer::new(text, numbers);
        let mut out = Vec::new();
        while let Some(t) = lexer.next() {
            out.push((t.kind, lexer.slice(t.start, t.end)));
        }
        out
    }

    #[test]
    fn numbers_names_and_symbols_keep_their_text() {
        let text = " 2.5e-3*x_1 + .5 ≤ pi ";
        let kinds: Vec<Kind> = cut(text, Numbers::Strict).iter().map(|t| t.0).collect();
        assert_eq!(
            kinds,
            [
                Kind::Number,
                Kind::Symbol('*'),
                Kind::Name,
                Kind::Symbol('+'),
                Kind::Number,
                Kind::Symbol('≤'),
                Kind::Name,
            ]
        );
        // Gluing the tokens back gives the text without its whitespace.
        let glued: String = cut(text, Numbers::Run).into_iter().map(|t| t.1).collect();
        let squeezed: String = text.chars().filter(|c| !c.is_whitespace()).collect();
        assert_eq!(glued, squeezed);
    }

    #[test]
    fn the_two_number_rules_differ_only_where_documented() {
        let strict = cut("1.2.3", Numbers::Strict);
        assert_eq!(
            strict.iter().map(|t| t.1.as_str()).collect::<Vec<_>>(),
            ["1.2", ".3"]
        );
        assert_eq!(cut("1.2.3", Numbers::Run), [(Kind::Number, "1.2.3".into())]);
        assert_eq!(cut(".", Numbers::Strict), [(Kind::Symbol('.'), ".".into())]);
        assert_eq!(cut(".", Numbers::Run), [(Kind::Number, ".".into())]);
        assert_eq!(
            cut("2e-", Numbers::Strict),
            [(Kind::OpenExponent, "2e-".into())]
        );
        let run: Vec<Kind> = cut("2e-", Numbers::Run).iter().map(|t| t.0).collect();
        assert_eq!(run, [Kind::Number, Kind::Name, Kind::Symbol('-')]);
        for numbers in [Numbers::Strict, Numbers::Run] {
            assert_eq!(cut("2ex", numbers)[1], (Kind::Name, "ex".into()));
            assert_eq!(cut("1E+20", numbers), [(Kind::Number, "1E+20".into())]);
        }
    }
}
