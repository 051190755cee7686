//! Linear constraints as users write them: `x1 + 2*x2 <= 1`, `0.2 <= x + y <= 0.8`,
//! `x1 + x2 = 1`, read into rows a·x ≤ b (or a·x = b). The regions they cut are in
//! `stillpoint_run::plan::constraints`.

use super::lexer::{Kind, Lexer, Numbers};

/// One row a·x ≤ b (or a·x = b, which only a mixture's sum may be).
#[derive(Debug, Clone, PartialEq)]
pub struct Row {
    /// Coefficients, one per coordinate.
    pub a: Vec<f64>,
    /// Right-hand side.
    pub b: f64,
    /// `=` rather than `≤`.
    pub equality: bool,
}

/// Why a constraint's text was refused, and where (a character index).
#[derive(Debug, Clone, PartialEq)]
pub struct ParseError {
    /// What is wrong.
    pub message: String,
    /// The character where it was found.
    pub at: usize,
}

impl std::fmt::Display for ParseError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}, at character {}", self.message, self.at + 1)
    }
}

#[derive(Debug, Clone, Copy, PartialEq)]
enum Cmp {
    Le,
    Ge,
    Eq,
}

#[derive(Debug, Clone, Copy, PartialEq)]
enum Tok {
    Num(f64),
    Var(usize),
    Plus,
    Minus,
    Star,
    Slash,
    Caret,
    Open,
    Close,
    Cmp(Cmp),
}

fn fail<T>(at: usize, message: impl Into<String>) -> Result<T, ParseError> {
    Err(ParseError {
        message: message.into(),
        at,
    })
}

/// The tokens of `text` with their character positions, as this grammar reads them:
/// [`Lexer`]'s with runs of digits and points as numbers, `pi` and the variables (checked
/// against s) as names, the comparisons as symbols of one or two characters.
fn lex(text: &str, s: usize) -> Result<Vec<(Tok, usize)>, ParseError> {
    let mut lexer = Lexer::new(text, Numbers::Run);
    let mut out = Vec::new();
    while let Some(token) = lexer.next() {
        let start = token.start;
        let tok = match token.kind {
            // A run's exponent is taken only when digits follow, so it never stays open.
            Kind::Number | Kind::OpenExponent => {
                let t = lexer.slice(start, token.end);
                match t.parse::<f64>() {
                    Ok(v) if v.is_finite() => Tok::Num(v),
                    _ => return fail(start, format!("{t:?} is not a finite number")),
                }
            }
            Kind::Name => {
                let word = lexer.slice(start, token.end);
                if word == "pi" {
                    Tok::Num(std::f64::consts::PI)
                } else {
                    Tok::Var(variable(&word, s, start)?)
                }
            }
            Kind::Symbol(c @ ('<' | '≤' | '>' | '≥' | '=')) => {
                let two = |n: char| lexer.char_at(start + 1) == Some(n);
                let (cmp, len) = match c {
                    '≤' => (Cmp::Le, 1),
                    '≥' => (Cmp::Ge, 1),
                    '<' if two('=') => (Cmp::Le, 2),
                    '>' if two('=') => (Cmp::Ge, 2),
                    '=' if two('=') => (Cmp::Eq, 2),
                    '=' => (Cmp::Eq, 1),
                    _ => {
                        return fail(
                            start,
                            format!("{c:?}: the comparisons are <=, >=, ≤ and ≥ (not strict)"),
                        )
                    }
                };
                lexer.widen(len - 1);
                Tok::Cmp(cmp)
            }
            Kind::Symbol('+') => Tok::Plus,
            Kind::Symbol('-' | '−') => Tok::Minus,
            Kind::Symbol('*' | '·' | '×') => Tok::Star,
            Kind::Symbol('/') => Tok::Slash,
            Kind::Symbol('^') => Tok::Caret,
            Kind::Symbol('(') => Tok::Open,
            Kind::Symbol(')') => Tok::Close,
            Kind::Symbol(other) => return fail(start, format!("unexpected {other:?}")),
        };
        out.push((tok, start));
    }
    Ok(out)
}

/// The index (from 0) of a variable: `x<k>` for 1 ≤ k ≤ s, or `x`, `y`, `z`.
fn variable(word: &str, s: usize, at: usize) -> Result<usize, ParseError> {
    let lower = word.to_ascii_lowercase();
    let k = match lower.as_str() {
        "x" => Some(1),
        "y" => Some(2),
        "z" => Some(3),
        w => w
            .strip_prefix('x')
            .filter(|d| !d.is_empty() && d.chars().all(|c| c.is_ascii_digit()))
            .and_then(|d| d.parse::<usize>().ok()),
    };
    match k {
        Some(k) if (1..=s).contains(&k) => Ok(k - 1),
        Some(_) => fail(
            at,
            format!("{word} is not a variable of this space: x1..x{s} (s = {s})"),
        ),
        None if crate::expr::RegionExpr::parse(&format!("{word}(1)"), 1).is_ok() => fail(
            at,
            format!("{word}(...) is not linear: a function of a variable"),
        ),
        None => fail(at, format!("unknown variable {word:?}: x1..x{s}")),
    }
}

/// c·x + k, and whether any variable was written (even with a zero coefficient).
#[derive(Debug, Clone)]
struct Affine {
    c: Vec<f64>,
    k: f64,
    has_var: bool,
}

impl Affine {
    fn constant(s: usize, k: f64) -> Affine {
        Affine {
            c: vec![0.0; s],
            k,
            has_var: false,
        }
    }

    fn scale(mut self, f: f64) -> Affine {
        self.c.iter_mut().for_each(|v| *v *= f);
        self.k *= f;
        self
    }

    fn add(mut self, o: &Affine, sign: f64) -> Affine {
        self.c
            .iter_mut()
            .zip(&o.c)
            .for_each(|(a, b)| *a += sign * b);
        self.k += sign * o.k;
        self.has_var |= o.has_var;
        self
    }
}

/// A recursive-descent reader of affine expressions over the tokens.
struct Parser<'t> {
    toks: &'t [(Tok, usize)],
    pos: usize,
    s: usize,
    end: usize,
}

impl Parser<'_> {
    fn peek(&self) -> Option<Tok> {
        self.toks.get(self.pos).map(|t| t.0)
    }

    fn at(&self) -> usize {
        self.toks.get(self.pos).map_or(self.end, |t| t.1)
    }

    fn expr(&mut self) -> Result<Affine, ParseError> {
        let mut v = self.term()?;
        while let Some(op @ (Tok::Plus | Tok::Minus)) = self.peek() {
            self.pos += 1;
            let t = self.term()?;
            v = v.add(&t, if op == Tok::Plus { 1.0 } else { -1.0 });
        }
        Ok(v)
    }

    fn term(&mut self) -> Result<Affine, ParseError> {
        let mut v = self.unary()?;
        loop {
            let at = self.at();
            match self.peek() {
                Some(Tok::Star) => {
                    self.pos += 1;
                    let w = self.unary()?;
                    v = product(v, w, at)?;
                }
                // `2 x1`, `2x1`, `3(x1 + x2)`: a product without its star.
                Some(Tok::Num(_) | Tok::Var(_) | Tok::Open) => {
                    let w = self.power()?;
                    v = product(v, w, at)?;
                }
                Some(Tok::Slash) => {
                    self.pos += 1;
                    let w = self.unary()?;
                    if w.has_var {
                        return fail(at, "dividing by a variable is not linear");
                    }
                    if w.k == 0.0 {
                        return fail(at, "a division by zero");
                    }
                    v = v.scale(1.0 / w.k);
                }
                _ => return Ok(v),
            }
        }
    }

    fn unary(&mut self) -> Result<Affine, ParseError> {
        match self.peek() {
            Some(Tok::Minus) => {
                self.pos += 1;
                Ok(self.unary()?.scale(-1.0))
            }
            Some(Tok::Plus) => {
                self.pos += 1;
                self.unary()
            }
            _ => self.power(),
        }
    }

    fn power(&mut self) -> Result<Affine, ParseError> {
        let base = self.atom()?;
        if self.peek() != Some(Tok::Caret) {
            return Ok(base);
        }
        let at = self.at();
        self.pos += 1;
        let e = self.unary()?;
        if base.has_var || e.has_var {
            return fail(at, "a power of a variable is not linear");
        }
        Ok(Affine::constant(self.s, base.k.powf(e.k)))
    }

    fn atom(&mut self) -> Result<Affine, ParseError> {
        let at = self.at();
        let tok = self.peek();
        self.pos += 1;
        match tok {
            Some(Tok::Num(v)) => Ok(Affine::constant(self.s, v)),
            Some(Tok::Var(k)) => {
                let mut a = Affine::constant(self.s, 0.0);
                a.c[k] = 1.0;
                a.has_var = true;
                Ok(a)
            }
            Some(Tok::Open) => {
                let v = self.expr()?;
                if self.peek() != Some(Tok::Close) {
                    return fail(self.at(), "a closing parenthesis");
                }
                self.pos += 1;
                Ok(v)
            }
            Some(Tok::Cmp(_)) | None => fail(at, "a number or a variable is missing"),
            Some(_) => fail(at, "a number, a variable or ( was expected"),
        }
    }
}

fn product(a: Affine, b: Affine, at: usize) -> Result<Affine, ParseError> {
    match (a.has_var, b.has_var) {
        (true, true) => fail(at, "a product of two variables is not linear"),
        (_, false) => Ok(a.scale(b.k)),
        (false, true) => Ok(b.scale(a.k)),
    }
}

/// The rows of one constraint's text in s variables: linear expressions compared by
/// `<=`, `>=`, `≤`, `≥` or `=` (a chain `0.2 <= x1 + x2 <= 0.8` gives a row per
/// comparison), each as a·x ≤ b (`≥` flipped) or a·x = b.
pub fn parse_constraint(text: &str, s: usize) -> Result<Vec<Row>, ParseError> {
    let toks = lex(text, s)?;
    let end = text.chars().count();
    let mut p = Parser {
        toks: &toks,
        pos: 0,
        s,
        end,
    };
    let mut sides = vec![p.expr()?];
    let mut cmps = Vec::new();
    while let Some(Tok::Cmp(c)) = p.peek() {
        cmps.push((c, p.at()));
        p.pos += 1;
        sides.push(p.expr()?);
    }
    if p.pos < toks.len() {
        return fail(
            p.at(),
            "an operator (+, -, *, /) or a comparison was expected",
        );
    }
    if cmps.is_empty() {
        return fail(end, "a comparison <= or >= between two sides is missing");
    }
    let mut rows = Vec::new();
    for (i, &(cmp, at)) in cmps.iter().enumerate() {
        // left − right ≤ 0, i.e. c·x ≤ −k; `≥` is the same with the sides swapped.
        let d = sides[i].clone().add(&sides[i + 1], -1.0);
        let d = if cmp == Cmp::Ge { d.scale(-1.0) } else { d };
        if !d.has_var {
            return fail(at, "a comparison with no variable on either side");
        }
        if d.c.iter().all(|&v| v == 0.0) {
            return fail(at, "the variables cancel: every coefficient is zero");
        }
        if d.c.iter().any(|v| !v.is_finite()) || !d.k.is_finite() {
            return fail(at, "a coefficient overflows");
        }
        rows.push(Row {
            a: d.c,
            b: -d.k,
            equality: cmp == Cmp::Eq,
        });
    }
    Ok(rows)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rows(text: &str, s: usize) -> Vec<(Vec<f64>, f64)> {
        parse_constraint(text, s)
            .unwrap_or_else(|e| panic!("{text}: {e}"))
            .into_iter()
            .map(|r| (r.a, r.b))
            .collect()
    }

    fn refusal(text: &str, s: usize) -> String {
        parse_constraint(text, s)
            .map(|r| panic!("{text} was accepted as {r:?}"))
            .unwrap_err()
            .to_string()
    }

    #[test]
    fn coefficients_are_read_in_every_spelling() {
        assert_eq!(rows("x1 + 2*x2 <= 1", 2), vec![(vec![1.0, 2.0], 1.0)]);
        assert_eq!(rows("x1+2x2<=1", 2), vec![(vec![1.0, 2.0], 1.0)]);
        assert_eq!(
            rows("2 x1 - x3 <= 0.5", 3),
            vec![(vec![2.0, 0.0, -1.0], 0.5)]
        );
        assert_eq!(
            rows("0.5*x2 + 1e-3*x1 ≤ 4", 2),
            vec![(vec![1e-3, 0.5], 4.0)]
        );
        assert_eq!(rows("-x1 + -2*x2 <= 1", 2), vec![(vec![-1.0, -2.0], 1.0)]);
        assert_eq!(
            rows("x1/4 + 3(x2 - 1) <= 0", 2),
            vec![(vec![0.25, 3.0], 3.0)]
        );
        assert_eq!(rows("x + 2*y <= 1", 2), vec![(vec![1.0, 2.0], 1.0)]);
        assert_eq!(rows("2^2 * x1 <= 1", 1), vec![(vec![4.0], 1.0)]);
    }

    #[test]
    fn both_sides_move_and_greater_is_flipped() {
        assert_eq!(rows("x1 + 1 <= x2 - 2", 2), vec![(vec![1.0, -1.0], -3.0)]);
        assert_eq!(rows("x1 + x2 >= 0.5", 2), vec![(vec![-1.0, -1.0], -0.5)]);
        assert_eq!(rows("1 ≥ x2", 2), vec![(vec![0.0, 1.0], 1.0)]);
        assert_eq!(
            rows("0.2 <= x1 + x2 <= 0.8", 2),
            vec![(vec![-1.0, -1.0], -0.2), (vec![1.0, 1.0], 0.8)]
        );
        let eq = parse_constraint("x1 + x2 = 1", 2).unwrap();
        assert!(eq[0].equality);
    }

    #[test]
    fn what_is_not_linear_or_not_a_variable_is_refused() {
        for (text, s, says) in [
            ("x1*x2 <= 1", 2, "product of two variables"),
            ("x1^2 <= 1", 1, "power of a variable"),
            ("1/x1 <= 1", 1, "dividing by a variable"),
            ("sin(x1) <= 1", 1, "not linear"),
            ("x3 <= 1", 2, "x1..x2"),
            ("x0 <= 1", 2, "x1..x2"),
            ("w1 <= 1", 2, "unknown variable"),
            ("1 <= 2", 2, "no variable"),
            ("x1 - x1 <= 2", 2, "cancel"),
            ("x1 + x2", 2, "comparison"),
            ("x1 < 1", 1, "not strict"),
            ("x1 + <= 1", 1, "missing"),
            ("x1 1 2 ) <= 1", 1, "expected"),
            ("(x1 + 1 <= 2", 1, "closing"),
            ("1e400*x1 <= 1", 1, "finite"),
            ("x1 / 0 <= 1", 1, "division by zero"),
        ] {
            let e = refusal(text, s);
            assert!(e.contains(says), "{text}: {e}");
        }
    }
}
