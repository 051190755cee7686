//! What value an option takes and how it is read: the [`Kind`] of each declaration, and
//! the one parse from a value as a front end received it ([`Arg`]) to a typed [`Value`].
//! A refusal names the option as the front end spells it and echoes the value as typed.

use super::{Declared, Opt};
use crate::pipeline::request::Arg;
use crate::plan::space::number_list;
use crate::{Error, PointSet};

/// The most points a single run accepts (beyond it a set of f64 cannot be addressed).
pub const MAX_COUNT: u64 = u32::MAX as u64 * 16;

/// The value an option takes.
#[derive(Debug, Clone, Copy)]
pub enum Kind {
    /// A whole number in [min, max] (text is parsed, a whole float is its number).
    Count {
        /// The least accepted.
        min: u64,
        /// The most accepted ([`MAX_COUNT`] for a number of points).
        max: u64,
    },
    /// A seed: a whole number in [0, 2^64).
    Seed,
    /// A finite number above `min` (or at least `min` when `closed`), below `below` when
    /// given.
    Real {
        /// The lower bound.
        min: f64,
        /// Whether `min` itself is accepted.
        closed: bool,
        /// The (excluded) upper bound, if any.
        below: Option<f64>,
    },
    /// Yes or no: `true`/`false` (a boolean, or text with ASCII case ignored).
    Flag,
    /// One of the words `words` lists (ASCII case and spaces ignored, `_` read as `-`);
    /// where the words include `true`, a boolean `true` is that word and `false` is as
    /// if the option were not given.
    Word(fn() -> Vec<&'static str>),
    /// A finite number in the range of `Real`, or one of the words.
    RealOrWord {
        /// The words accepted besides a number.
        words: fn() -> Vec<&'static str>,
        /// The lower bound of the number.
        min: f64,
        /// Whether `min` itself is accepted.
        closed: bool,
    },
    /// Numbers LO1,HI1,... (text or a list).
    Numbers,
    /// Numbers LO1,HI1,... as [`Kind::Numbers`] reads them, or lower and upper ends
    /// apart (SciPy's `l_bounds`, `u_bounds`).
    Bounds,
    /// Increasing whole sizes N1 < N2 < ..., N1 ≥ 1 (text or a list).
    Sizes,
    /// A point set.
    Points,
    /// One of the words, or a point set.
    WordOrPoints(fn() -> Vec<&'static str>),
    /// One text (an expression, a shape).
    Text,
    /// One or more texts (text, or a list of them; with `empty`, an empty list is none).
    Texts {
        /// Whether an empty list is accepted (as no text).
        empty: bool,
    },
    /// Rows of numbers: text `1,0.5;0.5,1`, a matrix, or its numbers.
    Rows,
    /// An object only the front end holds (Python's earlier result to continue from):
    /// the library does not read it.
    FrontEnd,
}

/// An option's value once read by its [`Kind`].
#[derive(Debug, Clone, PartialEq)]
pub enum Value {
    /// Of [`Kind::Count`].
    Count(u64),
    /// Of [`Kind::Seed`].
    Seed(u64),
    /// Of [`Kind::Real`], or the number of [`Kind::RealOrWord`].
    Real(f64),
    /// Of [`Kind::Flag`].
    Flag(bool),
    /// Of [`Kind::Word`] and the words of [`Kind::RealOrWord`] and
    /// [`Kind::WordOrPoints`]: the word as the table lists it (lower case, `-`).
    Word(String),
    /// Of [`Kind::Numbers`] given as one list.
    Numbers(Vec<f64>),
    /// Of [`Kind::Numbers`] given as lower and upper ends apart (one number stands for
    /// every coordinate).
    Pair(Vec<f64>, Vec<f64>),
    /// Of [`Kind::Sizes`].
    Sizes(Vec<usize>),
    /// Of [`Kind::Points`] and [`Kind::WordOrPoints`].
    Points(PointSet),
    /// Of [`Kind::Text`].
    Text(String),
    /// Of [`Kind::Texts`].
    Texts(Vec<String>),
    /// Of [`Kind::Rows`]: rows as text.
    RowsText(String),
    /// Of [`Kind::Rows`]: the numbers of a matrix, row by row.
    RowsNumbers(Vec<f64>),
}

/// A word as the tables list it: ASCII case and surrounding spaces ignored, `_` as `-`.
pub fn normal_word(text: &str) -> String {
    text.trim().to_ascii_lowercase().replace('_', "-")
}

/// The number an [`Arg`] gives (text is parsed), if finite.
fn finite(arg: &Arg) -> Option<f64> {
    let v = match arg {
        Arg::Int(i) => Some(*i as f64),
        Arg::Float(f) => Some(*f),
        Arg::Text(t) => t.trim().parse::<f64>().ok(),
        _ => None,
    };
    v.filter(|v| v.is_finite())
}

/// Yes or no: a boolean, or `true`/`false` as text (ASCII case ignored).
fn flag(arg: &Arg) -> Option<bool> {
    match arg {
        Arg::Bool(b) => Some(*b),
        Arg::Text(t) => match t.trim().to_ascii_lowercase().as_str() {
            "true" => Some(true),
            "false" => Some(false),
            _ => None,
        },
        _ => None,
    }
}

/// The word `arg` gives, if it is one of `words` (as [`normal_word`] reads it).
fn word(words: &[&str], arg: &Arg) -> Option<Value> {
    match arg {
        Arg::Text(t) if words.contains(&normal_word(t).as_str()) => {
            Some(Value::Word(normal_word(t)))
        }
        _ => None,
    }
}

/// The numbers of a list (whole or not).
fn numbers(arg: &Arg) -> Option<Vec<f64>> {
    match arg {
        Arg::Numbers(v) => Some(v.clone()),
        Arg::Counts(v) => Some(v.iter().map(|&k| k as f64).collect()),
        _ => None,
    }
}

/// Whether `v` is within a lower bound `min` (included when `closed`).
fn above(v: f64, min: f64, closed: bool) -> bool {
    if closed {
        v >= min
    } else {
        v > min
    }
}

impl Declared {
    /// Reads `arg` as this option's [`Kind`]: the typed value, `None` where the value
    /// means "not given" (a boolean `false` for a word option that takes `true`), or
    /// the refusal `Error::invalid(spell(name), arg, expected)` with the declaration's
    /// accepted values ([`Declared::expected`]). `spell` writes the option's name as the
    /// caller's front end does (`--log-every`, `log_every`).
    pub fn parse(&self, arg: &Arg, spell: &dyn Fn(&str) -> String) -> Result<Option<Value>, Error> {
        let bad = || Error::invalid(spell(self.name), arg, (self.expected)());
        let value = match self.kind {
            Kind::Count { min, max } => Some(Value::Count(self.count(arg, min, max, spell)?)),
            Kind::Seed => seed(arg).map(Value::Seed),
            Kind::Real { min, closed, below } => finite(arg)
                .filter(|&v| above(v, min, closed) && !below.is_some_and(|b| v >= b))
                .map(Value::Real),
            Kind::Flag => flag(arg).map(Value::Flag),
            Kind::Word(words) => {
                let words = words();
                match arg {
                    // Python's True and False where the words include `true`.
                    Arg::Bool(b) if words.contains(&"true") => match b {
                        true => Some(Value::Word("true".into())),
                        false => return Ok(None),
                    },
                    _ => word(&words, arg),
                }
            }
            Kind::RealOrWord { words, min, closed } => word(&words(), arg).or_else(|| {
                finite(arg)
                    .filter(|&v| above(v, min, closed))
                    .map(Value::Real)
            }),
            Kind::Numbers | Kind::Bounds => match arg {
                Arg::Pair(lo, hi) if matches!(self.kind, Kind::Bounds) => {
                    Some(Value::Pair(lo.clone(), hi.clone()))
                }
                Arg::Text(t) => Some(Value::Numbers(number_list(&spell(self.name), t, t)?)),
                _ => numbers(arg).map(Value::Numbers),
            },
            Kind::Sizes => self.sizes(arg).map(Value::Sizes),
            Kind::Points | Kind::WordOrPoints(_) => match (arg, self.kind) {
                (Arg::Points(p), _) => Some(Value::Points(p.clone())),
                (_, Kind::WordOrPoints(words)) => word(&words(), arg),
                _ => None,
            },
            Kind::Text | Kind::Texts { .. } | Kind::Rows | Kind::FrontEnd => self.texts(arg),
        };
        value.map(Some).ok_or_else(bad)
    }

    /// The value of the kinds that hold text or rows, `None` for another value.
    fn texts(&self, arg: &Arg) -> Option<Value> {
        Some(match (self.kind, arg) {
            (Kind::Text, Arg::Text(t)) => Value::Text(t.clone()),
            (Kind::Texts { .. }, Arg::Text(t)) => Value::Texts(vec![t.clone()]),
            (Kind::Texts { .. }, Arg::Texts(v)) => Value::Texts(v.clone()),
            // An empty list reaches here typed as numbers: no text.
            (Kind::Texts { empty: true }, Arg::Counts(v)) if v.is_empty() => {
                Value::Texts(Vec::new())
            }
            (Kind::Texts { empty: true }, Arg::Numbers(v)) if v.is_empty() => {
                Value::Texts(Vec::new())
            }
            (Kind::Rows, Arg::Text(t)) => Value::RowsText(t.clone()),
            (Kind::Rows, Arg::Points(p)) => Value::RowsNumbers(p.as_slice().to_vec()),
            (Kind::Rows, Arg::Numbers(v)) => Value::RowsNumbers(v.clone()),
            _ => return None,
        })
    }

    /// A whole number in [min, max]; above [`MAX_COUNT`] points, the refusal says why.
    fn count(
        &self,
        arg: &Arg,
        min: u64,
        max: u64,
        spell: &dyn Fn(&str) -> String,
    ) -> Result<u64, Error> {
        let v = match arg {
            Arg::Int(i) => Some(*i),
            Arg::Text(t) => t.trim().parse::<i128>().ok(),
            Arg::Float(f) if f.fract() == 0.0 && f.abs() < 1e30 => Some(*f as i128),
            _ => None,
        };
        let expected = (self.expected)();
        match v {
            Some(v) if v >= min as i128 && v <= max as i128 => Ok(v as u64),
            Some(v) if v > max as i128 => Err(Error::invalid(
                spell(self.name),
                arg,
                if max == MAX_COUNT {
                    format!(
                        "{expected}, at most {MAX_COUNT} (a set that large does not fit in \
                         memory)"
                    )
                } else {
                    format!("{expected}, at most {max}")
                },
            )),
            _ => Err(Error::invalid(spell(self.name), arg, expected)),
        }
    }

    /// Increasing sizes N1 < N2 < ..., N1 ≥ 1; a size beyond any set's reach is kept as
    /// one just beyond [`MAX_COUNT`], for the check of the run's size (which knows s) to
    /// refuse with the accepted range.
    fn sizes(&self, arg: &Arg) -> Option<Vec<usize>> {
        let raw: Vec<i128> = match arg {
            Arg::Counts(v) => v.clone(),
            Arg::Text(t) => t
                .split(',')
                .map(|x| x.trim().parse::<i128>())
                .collect::<Result<_, _>>()
                .ok()?,
            _ => return None,
        };
        if raw.is_empty() || raw[0] < 1 || raw.windows(2).any(|w| w[1] <= w[0]) {
            return None;
        }
        Some(
            raw.into_iter()
                .map(|k| k.min(MAX_COUNT as i128 + 1) as usize)
                .collect(),
        )
    }
}

/// A seed: a whole number in [0, 2^64) (a whole float below 2^64 is exact).
fn seed(arg: &Arg) -> Option<u64> {
    match arg {
        Arg::Int(v) if (0..=u64::MAX as i128).contains(v) => Some(*v as u64),
        Arg::Float(f) if f.fract() == 0.0 && (0.0..18446744073709551616.0).contains(f) => {
            Some(*f as u64)
        }
        Arg::Text(t) => t.trim().parse::<u64>().ok(),
        _ => None,
    }
}

/// An option's value read by its declaration: the value, none (not given), or the
/// refusal of the value as typed.
#[derive(Debug, Clone)]
pub struct Field<T>(Result<Option<T>, Error>);

impl<T: FromValue> Field<T> {
    /// `arg`, the value of `opt` as received (if given), read by its declaration.
    pub fn read(opt: Opt, arg: Option<&Arg>, spell: &dyn Fn(&str) -> String) -> Field<T> {
        let Some(arg) = arg else {
            return Field(Ok(None));
        };
        let d = opt.declared();
        Field(d.parse(arg, spell).and_then(|v| {
            match v {
                None => Ok(None),
                Some(v) => T::from_value(v)
                    .map(Some)
                    .ok_or_else(|| Error::invalid(spell(d.name), arg, (d.expected)())),
            }
        }))
    }
}

impl<T> Field<T> {
    /// The value, `None` when not given, or the refusal of the value as typed.
    pub fn get(&self) -> Result<Option<&T>, Error> {
        self.0.as_ref().map(Option::as_ref).map_err(Clone::clone)
    }
}

impl<T: Clone> Field<T> {
    /// The value (a copy), `None` when not given, or the refusal of the value as typed.
    pub fn value(&self) -> Result<Option<T>, Error> {
        self.0.clone()
    }
}

/// A typed field's type, made from the [`Value`] its kind reads (`None` for a value of
/// another kind, which the table's tests rule out).
pub trait FromValue: Sized {
    /// The value as this type.
    fn from_value(v: Value) -> Option<Self>;
}

impl FromValue for Value {
    fn from_value(v: Value) -> Option<Self> {
        Some(v)
    }
}

/// `FromValue` for each type a kind reads: the value's variants that give it.
macro_rules! from_value {
    ($($ty:ty: $($variant:ident)|+ => $make:expr;)*) => {$(
        impl FromValue for $ty {
            fn from_value(v: Value) -> Option<Self> {
                match v {
                    $(Value::$variant(x))|+ => $make(x),
                    _ => None,
                }
            }
        }
    )*};
}

from_value! {
    usize: Count => |c: u64| usize::try_from(c).ok();
    u64: Count | Seed => Some;
    f64: Real => Some;
    bool: Flag => Some;
    String: Word | Text => Some;
    Vec<String>: Texts => Some;
    Vec<f64>: Numbers => Some;
    Vec<usize>: Sizes => Some;
    PointSet: Points => Some;
}
