//! Region expressions g(x1, …, xs) typed on the command line; the region is where g ≤ 0.
//!
//! A small recursive-descent parser of its own compiles the text into a postfix program
//! that [`RegionExpr::eval`] runs on a stack array, with no allocation per call. The exmex
//! crate is not used here: its grammar differs from the one users expect in three places
//! (it reads `-x^2` as (−x)², and rejects `1e-3` and `|x|`), rewriting text for it would
//! still need a parser to find where a unary minus ends, and its error positions would
//! refer to the rewritten text instead of what the user typed.
//!
//! # Grammar
//!
//! ```text
//! expr   := term (("+" | "-") term)*
//! term   := unary (("*" | "/") unary)*
//! unary  := ("-" | "+") unary | power
//! power  := atom ("^" unary)?                  ("**" is accepted for "^")
//! atom   := number | variable | "pi" | function "(" expr ("," expr)* ")"
//!         | "(" expr ")" | "|" expr "|"
//! ```
//!
//! - **Numbers**: `3`, `2.5`, `.5`, `1.`, and scientific notation `1e-3`, `2.5E+2`.
//! - **Variables**: `x1` … `xs`; also `x`, `y`, `z` for x1, x2, x3 when s is large enough.
//!   Both spellings can be mixed in one expression. Any other name is refused, and the
//!   message lists the accepted ones. `pi` (or `π`) is the constant π.
//! - **Precedence**, loosest first: `+ -`, then `* /` (both left-associative), then unary
//!   `-`/`+`, then `^` (right-associative). So `-x^2` is −(x²), `2^3^2` is 2⁹ = 512, and
//!   `2^-1` is 0.5 (the exponent may carry its own sign, as in Python's `2**-1`);
//!   `x*-y` and `x - -y` are accepted. There is no implicit multiplication: write `2*x`.
//! - **Absolute value**: `abs(e)` or `|e|`. A `|` where an operand is expected opens a
//!   bar, and where an operator is expected closes the innermost open bar, so
//!   `|x|*|y|` and `||x| - 1|` read as intended.
//! - **Functions** of one argument: `abs sqrt cbrt exp ln log` (both natural) `log10 log2
//!   sin cos tan asin acos atan sinh cosh tanh floor ceil sign`; and `min(a, b, …)`,
//!   `max(a, b, …)` of two or more arguments. `min`/`max` propagate NaN rather than drop
//!   it, so that an undefined g is noticed at sampled points.
//! - Spaces (any whitespace) may appear anywhere between tokens. Names are case-sensitive.
//!   The Unicode minus sign `−` is read as `-`.
//!
//! Results follow IEEE arithmetic: `sqrt(-1)` and `(-8)^(1/3)` are NaN, `1/0` is ∞; the
//! region code checks for NaN at its sample points. Integer constant exponents such as
//! `x^2` are computed by multiplication, which is faster and exact for squares.

use std::cell::RefCell;
use std::fmt;
use std::sync::Arc;

use super::lexer::{Kind, Lexer, Numbers};
use stillpoint_domains::region::RegionFn;

/// Why a region expression was refused. Messages name the problem and, for anything
/// tied to a place in the text, echo the text with a caret line under that place.
#[derive(Debug, thiserror::Error)]
pub enum ExprError {
    /// The text holds nothing but whitespace.
    #[error(
        "empty region expression: give g so that the region is where g ≤ 0, \
         e.g. \"x^2 + y^2 - 1\" for the unit disc"
    )]
    Empty,
    /// Asked for a region in zero dimensions.
    #[error("a region expression needs at least 1 variable (s = 0 was given)")]
    NoDimension,
    /// A name that is neither a variable for this dimension nor a known constant.
    #[error("unknown variable {name:?}: {accepted}\n{at}")]
    UnknownVariable {
        /// The name as written.
        name: String,
        /// The variable names accepted for this dimension, as a sentence.
        accepted: String,
        /// Where the name is.
        at: Location,
    },
    /// A name followed by `(` that is not a known function.
    #[error(
        "unknown function {name:?}: the functions are {}\n{at}",
        function_list()
    )]
    UnknownFunction {
        /// The name as written.
        name: String,
        /// Where the name is.
        at: Location,
    },
    /// Anything else that does not follow the grammar: a misplaced or missing operator,
    /// an unclosed `(` or `|`, a malformed number, a wrong number of arguments.
    #[error("syntax error: {message}\n{at}")]
    Syntax {
        /// What is wrong, quoting the offending token.
        message: String,
        /// Where it is.
        at: Location,
    },
}

/// A place in the text of an expression, shown as the text with a caret line under it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Location {
    /// The whole expression as given.
    pub text: String,
    /// 1-based position of the first offending character, counted in characters; one past
    /// the end when the text stops too early.
    pub column: usize,
    /// How many characters are marked (at least 1).
    pub width: usize,
}

impl fmt::Display for Location {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        // A tab or newline in the echoed text would move the caret off its character.
        let shown: String = self
            .text
            .chars()
            .map(|c| if c.is_control() { ' ' } else { c })
            .collect();
        write!(
            f,
            "  {shown}\n  {}{}",
            " ".repeat(self.column.saturating_sub(1)),
            "^".repeat(self.width.max(1))
        )
    }
}

/// A compiled region expression g: cheap to evaluate, to clone and to share across threads.
#[derive(Clone, Debug)]
pub struct RegionExpr {
    text: String,
    s: usize,
    program: Vec<Op>,
    depth: usize,
}

/// Stack slots kept on the call stack; deeper programs use a per-thread buffer.
const INLINE_STACK: usize = 16;

/// Nesting (parentheses, bars, unary signs, exponents) beyond which the parser refuses
/// the text rather than risk exhausting the call stack on hostile input.
const MAX_NESTING: usize = 200;

thread_local! {
    static DEEP_STACK: RefCell<Vec<f64>> = const { RefCell::new(Vec::new()) };
}

impl RegionExpr {
    /// Compiles `text` as a function of s variables (see the module documentation for the
    /// grammar). Refuses s = 0, empty text, unknown names and syntax errors.
    pub fn parse(text: &str, s: usize) -> Result<RegionExpr, ExprError> {
        RegionExpr::parse_named(text, s, &[])
    }

    /// [`RegionExpr::parse`] where variable k may also be written by `names[k]` (a
    /// design space's column names), which come before the `xk` and `x, y, z` spellings:
    /// a variable named `x` in the second column is that column, not the first.
    pub fn parse_named(text: &str, s: usize, names: &[String]) -> Result<RegionExpr, ExprError> {
        if s == 0 {
            return Err(ExprError::NoDimension);
        }
        if text.trim().is_empty() {
            return Err(ExprError::Empty);
        }
        let tokens = lex(text)?;
        let mut parser = Parser {
            text,
            tokens,
            next: 0,
            s,
            names: &names[..names.len().min(s)],
            program: Vec::new(),
            nesting: 0,
        };
        parser.expr()?;
        let end = parser.peek();
        if end.kind != Tok::End {
            return Err(parser.after_operand_error(end, "the end of the expression"));
        }
        let program = parser.program;
        let depth = stack_depth(&program);
        Ok(RegionExpr {
            text: text.to_string(),
            s,
            program,
            depth,
        })
    }

    /// g(x). Uses `x[0..s]`; extra coordinates are ignored, and a point with fewer than s
    /// coordinates gives NaN rather than a panic.
    #[inline]
    pub fn eval(&self, x: &[f64]) -> f64 {
        if x.len() < self.s {
            return f64::NAN;
        }
        if self.depth <= INLINE_STACK {
            let mut stack = [0.0; INLINE_STACK];
            run(&self.program, x, &mut stack)
        } else {
            DEEP_STACK.with(|cell| match cell.try_borrow_mut() {
                Ok(mut stack) => {
                    if stack.len() < self.depth {
                        stack.resize(self.depth, 0.0);
                    }
                    run(&self.program, x, &mut stack)
                }
                // Only reachable if evaluation were re-entered on this thread.
                Err(_) => run(&self.program, x, &mut vec![0.0; self.depth]),
            })
        }
    }

    /// The expression as a shareable closure x ↦ g(x), the form region domains take
    /// ([`RegionFn`] is `Arc<dyn Fn(&[f64]) -> f64 + Send + Sync>`).
    pub fn into_fn(self) -> RegionFn {
        Arc::new(move |x: &[f64]| self.eval(x))
    }

    /// The text the expression was compiled from, as given.
    pub fn text(&self) -> &str {
        &self.text
    }

    /// The dimension s the expression was compiled for.
    pub fn s(&self) -> usize {
        self.s
    }
}

// ---------------------------------------------------------------------------------------
// Evaluation
// ---------------------------------------------------------------------------------------

#[derive(Clone, Copy, Debug, PartialEq)]
enum Op {
    Const(f64),
    Var(usize),
    Neg,
    Add,
    Sub,
    Mul,
    Div,
    Pow,
    Square,
    PowI(i32),
    AddC(f64),
    MulC(f64),
    DivC(f64),
    RSubC(f64),
    RDivC(f64),
    Min,
    Max,
    Func(Func),
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Func {
    Abs,
    Sqrt,
    Cbrt,
    Exp,
    Ln,
    Log10,
    Log2,
    Sin,
    Cos,
    Tan,
    Asin,
    Acos,
    Atan,
    Sinh,
    Cosh,
    Tanh,
    Floor,
    Ceil,
    Sign,
}

impl Func {
    #[inline]
    fn apply(self, v: f64) -> f64 {
        match self {
            Func::Abs => v.abs(),
            Func::Sqrt => v.sqrt(),
            Func::Cbrt => v.cbrt(),
            Func::Exp => v.exp(),
            Func::Ln => v.ln(),
            Func::Log10 => v.log10(),
            Func::Log2 => v.log2(),
            Func::Sin => v.sin(),
            Func::Cos => v.cos(),
            Func::Tan => v.tan(),
            Func::Asin => v.asin(),
            Func::Acos => v.acos(),
            Func::Atan => v.atan(),
            Func::Sinh => v.sinh(),
            Func::Cosh => v.cosh(),
            Func::Tanh => v.tanh(),
            Func::Floor => v.floor(),
            Func::Ceil => v.ceil(),
            // f64::signum gives 1 at 0; the sign function of mathematics gives 0.
            Func::Sign => {
                if v > 0.0 {
                    1.0
                } else if v < 0.0 {
                    -1.0
                } else {
                    v
                }
            }
        }
    }
}

/// One-argument functions by name; `min`/`max` are handled apart as they take several.
const FUNCTIONS: &[(&str, Func)] = &[
    ("abs", Func::Abs),
    ("sqrt", Func::Sqrt),
    ("cbrt", Func::Cbrt),
    ("exp", Func::Exp),
    ("ln", Func::Ln),
    ("log", Func::Ln),
    ("log10", Func::Log10),
    ("log2", Func::Log2),
    ("sin", Func::Sin),
    ("cos", Func::Cos),
    ("tan", Func::Tan),
    ("asin", Func::Asin),
    ("acos", Func::Acos),
    ("atan", Func::Atan),
    ("sinh", Func::Sinh),
    ("cosh", Func::Cosh),
    ("tanh", Func::Tanh),
    ("floor", Func::Floor),
    ("ceil", Func::Ceil),
    ("sign", Func::Sign),
];

fn function_list() -> String {
    let mut names: Vec<&str> = FUNCTIONS.iter().map(|(n, _)| *n).collect();
    names.extend(["min", "max"]);
    names.join(", ")
}

/// f64::min/max return the other operand for a NaN; here NaN wins so that an undefined
/// g cannot hide behind a defined one.
#[inline]
fn nan_min(a: f64, b: f64) -> f64 {
    if a <= b {
        a
    } else if b < a {
        b
    } else {
        f64::NAN
    }
}

#[inline]
fn nan_max(a: f64, b: f64) -> f64 {
    if a >= b {
        a
    } else if b > a {
        b
    } else {
        f64::NAN
    }
}

/// Runs a postfix program. The parser guarantees that every operator finds its operands
/// and that `x` and `stack` are long enough (checked by the callers).
#[inline]
fn run(program: &[Op], x: &[f64], stack: &mut [f64]) -> f64 {
    let mut sp = 0usize;
    for op in program {
        match *op {
            Op::Const(c) => {
                stack[sp] = c;
                sp += 1;
            }
            Op::Var(k) => {
                stack[sp] = x[k];
                sp += 1;
            }
            Op::Neg => stack[sp - 1] = -stack[sp - 1],
            Op::Square => stack[sp - 1] *= stack[sp - 1],
            Op::PowI(k) => stack[sp - 1] = stack[sp - 1].powi(k),
            Op::Func(f) => stack[sp - 1] = f.apply(stack[sp - 1]),
            Op::AddC(c) => stack[sp - 1] += c,
            Op::MulC(c) => stack[sp - 1] *= c,
            Op::DivC(c) => stack[sp - 1] /= c,
            Op::RSubC(c) => stack[sp - 1] = c - stack[sp - 1],
            Op::RDivC(c) => stack[sp - 1] = c / stack[sp - 1],
            binary => {
                sp -= 1;
                let (a, b) = (stack[sp - 1], stack[sp]);
                stack[sp - 1] = match binary {
                    Op::Add => a + b,
                    Op::Sub => a - b,
                    Op::Mul => a * b,
                    Op::Div => a / b,
                    Op::Pow => a.powf(b),
                    Op::Min => nan_min(a, b),
                    Op::Max => nan_max(a, b),
                    _ => f64::NAN,
                };
            }
        }
    }
    stack[0]
}

fn stack_depth(program: &[Op]) -> usize {
    let (mut sp, mut max) = (0usize, 0usize);
    for op in program {
        match op {
            Op::Const(_) | Op::Var(_) => {
                sp += 1;
                max = max.max(sp);
            }
            Op::Min | Op::Max | Op::Add | Op::Sub | Op::Mul | Op::Div | Op::Pow => sp -= 1,
            _ => {}
        }
    }
    max
}

// ---------------------------------------------------------------------------------------
// Lexing
// ---------------------------------------------------------------------------------------

#[derive(Clone, Debug, PartialEq)]
enum Tok {
    Num(f64),
    Name(String),
    Plus,
    Minus,
    Star,
    Slash,
    Caret,
    LParen,
    RParen,
    Comma,
    Bar,
    End,
}

/// A token with its place in the text, in characters (for the caret line).
#[derive(Clone, Debug)]
struct Token {
    kind: Tok,
    column: usize,
    width: usize,
    lexeme: String,
}

fn location(text: &str, column: usize, width: usize) -> Location {
    Location {
        text: text.to_string(),
        column,
        width,
    }
}

fn syntax(text: &str, column: usize, width: usize, message: impl Into<String>) -> ExprError {
    ExprError::Syntax {
        message: message.into(),
        at: location(text, column, width),
    }
}

/// The tokens of `text` as this grammar reads them: [`Lexer`]'s with strict numbers,
/// `**` for `^`, and every symbol outside the grammar refused where it stands.
fn lex(text: &str) -> Result<Vec<Token>, ExprError> {
    let mut lexer = Lexer::new(text, Numbers::Strict);
    let mut tokens = Vec::new();
    while let Some(token) = lexer.next() {
        let (start, mut end) = (token.start, token.end);
        let lexeme = lexer.slice(start, end);
        let kind = match token.kind {
            Kind::OpenExponent => {
                return Err(syntax(
                    text,
                    start + 1,
                    end - start,
                    format!("malformed number {lexeme:?}: the exponent needs digits, e.g. 2e-3"),
                ))
            }
            Kind::Number => match lexeme.parse::<f64>() {
                Ok(v) if v.is_finite() => Tok::Num(v),
                _ => {
                    return Err(syntax(
                        text,
                        start + 1,
                        end - start,
                        format!("number {lexeme} is out of the range of f64"),
                    ))
                }
            },
            Kind::Name => Tok::Name(lexeme),
            Kind::Symbol(c) => match c {
                '+' => Tok::Plus,
                '-' | '−' => Tok::Minus,
                '*' if lexer.char_at(end) == Some('*') => {
                    lexer.widen(1);
                    end += 1;
                    Tok::Caret
                }
                '*' => Tok::Star,
                '/' => Tok::Slash,
                '^' => Tok::Caret,
                '(' => Tok::LParen,
                ')' => Tok::RParen,
                ',' => Tok::Comma,
                '|' => Tok::Bar,
                '<' | '>' | '=' | '≤' | '≥' => {
                    return Err(syntax(
                        text,
                        start + 1,
                        1,
                        format!(
                            "unexpected {c:?}: give g alone, the region is where g ≤ 0 \
                             (e.g. \"x^2 + y^2 - 1\" for x^2 + y^2 ≤ 1)"
                        ),
                    ))
                }
                _ => {
                    return Err(syntax(
                        text,
                        start + 1,
                        1,
                        format!("unexpected character {c:?}"),
                    ))
                }
            },
        };
        tokens.push(Token {
            kind,
            column: start + 1,
            width: end - start,
            lexeme: lexer.slice(start, end),
        });
    }
    tokens.push(Token {
        kind: Tok::End,
        column: lexer.len() + 1,
        width: 1,
        lexeme: String::new(),
    });
    Ok(tokens)
}

// ---------------------------------------------------------------------------------------
// Parsing
// ---------------------------------------------------------------------------------------

struct Parser<'a> {
    text: &'a str,
    tokens: Vec<Token>,
    next: usize,
    s: usize,
    /// The variables' own names, if any (before the `xk` spellings).
    names: &'a [String],
    program: Vec<Op>,
    nesting: usize,
}

fn describe(token: &Token) -> String {
    match token.kind {
        Tok::End => "the end of the expression".to_string(),
        _ => format!("{:?}", token.lexeme),
    }
}

impl Parser<'_> {
    fn peek(&self) -> Token {
        // The lexer always ends the list with `End`, and `bump` never moves past it.
        self.tokens[self.next.min(self.tokens.len() - 1)].clone()
    }

    fn bump(&mut self) -> Token {
        let token = self.peek();
        if token.kind != Tok::End {
            self.next += 1;
        }
        token
    }

    fn error_at(&self, token: &Token, message: impl Into<String>) -> ExprError {
        syntax(self.text, token.column, token.width, message)
    }

    /// The error for a token found right after a complete operand where `wanted` (an
    /// operator, `)`, `|`, the end) was expected.
    fn after_operand_error(&self, token: Token, wanted: &str) -> ExprError {
        match token.kind {
            Tok::Num(_) | Tok::Name(_) | Tok::LParen => self.error_at(
                &token,
                format!(
                    "missing operator before {} (there is no implicit multiplication: write *)",
                    describe(&token)
                ),
            ),
            Tok::RParen => self.error_at(&token, "')' closes no '('"),
            Tok::Bar => self.error_at(&token, "'|' closes no '|'"),
            Tok::Comma => self.error_at(&token, "',' outside the arguments of min or max"),
            _ => self.error_at(
                &token,
                format!("expected {wanted} but found {}", describe(&token)),
            ),
        }
    }

    /// Emits a one-operand operator, folding it into a constant operand.
    fn emit_unary(&mut self, op: Op) {
        if let Some(&Op::Const(a)) = self.program.last() {
            self.program.pop();
            self.program
                .push(Op::Const(run(&[Op::Const(a), op], &[], &mut [0.0])));
        } else {
            self.program.push(op);
        }
    }

    /// Emits a two-operand operator whose operands' code starts at `left` and `right`.
    ///
    /// A constant operand is folded into the instruction (`AddC`, `MulC`, …), which halves
    /// the instruction count of typical expressions such as `17*x^2 - 225`; every rewrite
    /// gives the same bits as the plain instruction. Two constants fold into one, and a
    /// constant integer exponent becomes multiplication.
    fn emit_binary(&mut self, op: Op, left: usize, right: usize) {
        let n = self.program.len();
        let constant = |k: usize, len: usize| match self.program[k] {
            Op::Const(c) if len == 1 => Some(c),
            _ => None,
        };
        let (a, b) = (constant(left, right - left), constant(right, n - right));
        if let (Some(a), Some(b)) = (a, b) {
            let v = run(&[Op::Const(a), Op::Const(b), op], &[], &mut [0.0; 2]);
            self.program.truncate(left);
            self.program.push(Op::Const(v));
            return;
        }
        if let Some(b) = b {
            let fused = match op {
                Op::Add => Some(Op::AddC(b)),
                // a − b and a + (−b) round identically.
                Op::Sub => Some(Op::AddC(-b)),
                Op::Mul => Some(Op::MulC(b)),
                Op::Div => Some(Op::DivC(b)),
                Op::Pow if b == 2.0 => Some(Op::Square),
                Op::Pow if b.fract() == 0.0 && b.abs() <= 64.0 => Some(Op::PowI(b as i32)),
                _ => None,
            };
            if let Some(fused) = fused {
                self.program.pop();
                self.program.push(fused);
                return;
            }
        }
        if let Some(a) = a {
            let fused = match op {
                // IEEE addition and multiplication are commutative, bit for bit.
                Op::Add => Some(Op::AddC(a)),
                Op::Mul => Some(Op::MulC(a)),
                Op::Sub => Some(Op::RSubC(a)),
                Op::Div => Some(Op::RDivC(a)),
                _ => None,
            };
            if let Some(fused) = fused {
                self.program.remove(left);
                self.program.push(fused);
                return;
            }
        }
        self.program.push(op);
    }

    fn expr(&mut self) -> Result<(), ExprError> {
        let left = self.program.len();
        self.term()?;
        loop {
            let op = match self.peek().kind {
                Tok::Plus => Op::Add,
                Tok::Minus => Op::Sub,
                _ => return Ok(()),
            };
            self.bump();
            let right = self.program.len();
            self.term()?;
            self.emit_binary(op, left, right);
        }
    }

    fn term(&mut self) -> Result<(), ExprError> {
        let left = self.program.len();
        self.unary()?;
        loop {
            let op = match self.peek().kind {
                Tok::Star => Op::Mul,
                Tok::Slash => Op::Div,
                _ => return Ok(()),
            };
            self.bump();
            let right = self.program.len();
            self.unary()?;
            self.emit_binary(op, left, right);
        }
    }

    fn unary(&mut self) -> Result<(), ExprError> {
        // Every cycle of the recursion passes through here, so counting here bounds the
        // depth of the parser's own call stack.
        self.nesting += 1;
        if self.nesting > MAX_NESTING {
            let token = self.peek();
            return Err(self.error_at(
                &token,
                format!("expression nested more than {MAX_NESTING} levels deep"),
            ));
        }
        let result = match self.peek().kind {
            Tok::Minus => {
                self.bump();
                self.unary().map(|()| self.emit_unary(Op::Neg))
            }
            Tok::Plus => {
                self.bump();
                self.unary()
            }
            _ => self.power(),
        };
        self.nesting -= 1;
        result
    }

    fn power(&mut self) -> Result<(), ExprError> {
        let left = self.program.len();
        self.atom()?;
        if self.peek().kind == Tok::Caret {
            self.bump();
            let right = self.program.len();
            self.unary()?;
            self.emit_binary(Op::Pow, left, right);
        }
        Ok(())
    }

    fn atom(&mut self) -> Result<(), ExprError> {
        let index = self.next;
        let token = self.bump();
        match &token.kind {
            Tok::Num(v) => {
                self.program.push(Op::Const(*v));
                Ok(())
            }
            Tok::Name(name) => {
                if self.peek().kind == Tok::LParen {
                    self.call(&token, name)
                } else {
                    self.name(&token, name)
                }
            }
            Tok::LParen => {
                self.expr()?;
                self.close(Tok::RParen, &token)
            }
            Tok::Bar => {
                self.expr()?;
                self.close(Tok::Bar, &token)?;
                self.emit_unary(Op::Func(Func::Abs));
                Ok(())
            }
            _ => {
                let previous = index
                    .checked_sub(1)
                    .and_then(|k| self.tokens.get(k))
                    .map(|t| format!(" after {:?}", t.lexeme))
                    .unwrap_or_default();
                let message = if token.kind == Tok::End {
                    format!(
                        "the expression ends too early: expected a number, a variable, \
                         a function or '('{previous}"
                    )
                } else {
                    format!(
                        "expected a number, a variable, a function or '('{previous} \
                         but found {}",
                        describe(&token)
                    )
                };
                Err(self.error_at(&token, message))
            }
        }
    }

    /// Expects the `)` or `|` that closes `open`.
    fn close(&mut self, kind: Tok, open: &Token) -> Result<(), ExprError> {
        let token = self.peek();
        if token.kind == kind {
            self.bump();
            return Ok(());
        }
        let symbol = if kind == Tok::Bar { '|' } else { ')' };
        let opener = if kind == Tok::Bar { '|' } else { '(' };
        // Another closer here means this one was forgotten, not that the other is extra.
        if matches!(token.kind, Tok::End | Tok::RParen | Tok::Bar) {
            return Err(syntax(
                self.text,
                open.column,
                open.width,
                format!(
                    "missing '{symbol}' to close the '{opener}' at column {}",
                    open.column
                ),
            ));
        }
        Err(self.after_operand_error(token, &format!("an operator or '{symbol}'")))
    }

    /// The coordinate `name` stands for: a variable's own name, then `xk` or x, y, z.
    fn variable(&self, name: &str) -> Option<usize> {
        (self.names.iter().position(|n| n == name)).or_else(|| variable_index(name, self.s))
    }

    fn name(&mut self, token: &Token, name: &str) -> Result<(), ExprError> {
        if let Some(k) = self.variable(name) {
            self.program.push(Op::Var(k));
            return Ok(());
        }
        if name == "pi" || name == "π" {
            self.program.push(Op::Const(std::f64::consts::PI));
            return Ok(());
        }
        if name == "min" || name == "max" || FUNCTIONS.iter().any(|(n, _)| *n == name) {
            return Err(self.error_at(token, format!("{name} is a function: write {name}(...)")));
        }
        Err(ExprError::UnknownVariable {
            name: name.to_string(),
            accepted: accepted_variables(self.s, self.names),
            at: location(self.text, token.column, token.width),
        })
    }

    fn call(&mut self, token: &Token, name: &str) -> Result<(), ExprError> {
        let (op, variadic) = match name {
            "min" => (Op::Min, true),
            "max" => (Op::Max, true),
            _ => match FUNCTIONS.iter().find(|(n, _)| *n == name) {
                Some(&(_, f)) => (Op::Func(f), false),
                None if self.variable(name).is_some() || name == "pi" => {
                    return Err(self.error_at(
                        token,
                        format!(
                            "{name} is not a function (there is no implicit multiplication: \
                             write {name}*(...))"
                        ),
                    ))
                }
                None => {
                    return Err(ExprError::UnknownFunction {
                        name: name.to_string(),
                        at: location(self.text, token.column, token.width),
                    })
                }
            },
        };
        let open = self.bump();
        if self.peek().kind == Tok::RParen {
            let close = self.peek();
            return Err(self.error_at(&close, format!("{name}() needs an argument")));
        }
        let mut count = 0usize;
        let first = self.program.len();
        loop {
            let right = self.program.len();
            self.expr()?;
            count += 1;
            if variadic && count >= 2 {
                self.emit_binary(op, first, right);
            }
            if self.peek().kind == Tok::Comma {
                self.bump();
            } else {
                break;
            }
        }
        self.close(Tok::RParen, &open)?;
        match (variadic, count) {
            (false, 1) => {
                self.emit_unary(op);
                Ok(())
            }
            (true, 2..) => Ok(()),
            (false, _) => Err(self.error_at(
                token,
                format!("{name} takes 1 argument, {count} were given"),
            )),
            (true, _) => Err(self.error_at(
                token,
                format!("{name} takes 2 or more arguments, 1 was given"),
            )),
        }
    }
}

/// The coordinate a variable name stands for: `xk` for 1 ≤ k ≤ s (no leading zeros), and
/// `x`, `y`, `z` for the first three when the dimension has them.
fn variable_index(name: &str, s: usize) -> Option<usize> {
    let k = match name {
        "x" => 1,
        "y" => 2,
        "z" => 3,
        _ => {
            let digits = name.strip_prefix('x')?;
            if digits.starts_with('0') || !digits.bytes().all(|b| b.is_ascii_digit()) {
                return None;
            }
            digits.parse::<usize>().ok()?
        }
    };
    (1..=s).contains(&k).then(|| k - 1)
}

fn accepted_variables(s: usize, names: &[String]) -> String {
    let indexed = match s {
        1..=4 => (1..=s)
            .map(|k| format!("x{k}"))
            .collect::<Vec<_>>()
            .join(", "),
        _ => format!("x1, x2, …, x{s}"),
    };
    if !names.is_empty() {
        let shown = if names.len() <= 6 {
            names.join(", ")
        } else {
            format!("{}, …, {}", names[..3].join(", "), names[names.len() - 1])
        };
        return format!("the variables are {shown} (or {indexed} in that order)");
    }
    let aliases = match s {
        1 => " (or x)",
        2 => " (or x, y)",
        3 => " (or x, y, z)",
        _ => " (x, y, z stand for x1, x2, x3)",
    };
    format!("with s = {s} the variables are {indexed}{aliases}")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_variable_s_own_name_comes_before_the_x_spellings() {
        let names: Vec<String> = ["y", "x", "W_1"].iter().map(|n| n.to_string()).collect();
        let e = RegionExpr::parse_named("x + 10*y + 100*W_1 + 1000*x3", 3, &names).unwrap();
        // x is the second column (named x), y the first, W_1 and x3 the third.
        assert_eq!(e.eval(&[1.0, 2.0, 3.0]), 2.0 + 10.0 + 300.0 + 3000.0);
        // Without names, x and y are x1 and x2.
        let plain = RegionExpr::parse("x + 10*y", 3).unwrap();
        assert_eq!(plain.eval(&[1.0, 2.0, 3.0]), 21.0);
        let e = RegionExpr::parse_named("q", 3, &names)
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("the variables are y, x, W_1 (or x1, x2, x3 in that order)"),
            "{e}"
        );
        let e = RegionExpr::parse_named("x(2)", 3, &names)
            .unwrap_err()
            .to_string();
        assert!(e.contains("x is not a function"), "{e}");
    }

    #[test]
    fn constants_fold_and_squares_multiply() {
        let e = RegionExpr::parse("-2^2 + x^2", 1).unwrap();
        assert_eq!(e.program, vec![Op::Var(0), Op::Square, Op::AddC(-4.0)]);
        assert_eq!(stack_depth(&e.program), 1);
        let e = RegionExpr::parse("17*x^2 - 16*abs(x)*y + 17*y^2 - 225", 2).unwrap();
        assert_eq!(e.program.len(), 14);
        assert_eq!(stack_depth(&e.program), 3);
        let e = RegionExpr::parse("1 - 2/x - x/4 - min(1, x, 2)", 1).unwrap();
        assert_eq!(e.program.len(), 12);
    }
}
