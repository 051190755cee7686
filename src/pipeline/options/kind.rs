//! What value an option takes and how it is read: the [`Kind`] of each declaration, and
//! the one parse from a value as a front end received it ([`Arg`]) to a typed [`Value`].
//! A refusal names the option as the front end spells it and echoes the value as typed.

use super::Declared;
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
    /// Numbers LO1,HI1,... (text, a list, or lower and upper ends apart).
    Numbers,
    /// Increasing whole sizes N1 < N2 < ..., N1 ≥ 1 (text or a list).
    Sizes,
    /// A point set.
    Points,
    /// One of the words, or a point set.
    WordOrPoints(fn() -> Vec<&'static str>),
    /// One text (an expression, a shape).
    Text,
    /// One or more texts (text, or a list of them; an empty list is none).
    Texts,
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
            Kind::Count { min, max } => Value::Count(self.count(arg, min, max, spell)?),
            Kind::Seed => Value::Seed(seed(arg).ok_or_else(bad)?),
            Kind::Real { min, closed, below } => {
                let v = finite(arg).ok_or_else(bad)?;
                if !above(v, min, closed) || below.is_some_and(|b| v >= b) {
                    return Err(bad());
                }
                Value::Real(v)
            }
            Kind::Flag => Value::Flag(match arg {
                Arg::Bool(b) => *b,
                Arg::Text(t) => match t.trim().to_ascii_lowercase().as_str() {
                    "true" => true,
                    "false" => false,
                    _ => return Err(bad()),
                },
                _ => return Err(bad()),
            }),
            Kind::Word(words) => {
                let words = words();
                match arg {
                    Arg::Bool(true) if words.contains(&"true") => Value::Word("true".into()),
                    Arg::Bool(false) if words.contains(&"true") => return Ok(None),
                    Arg::Text(t) if words.contains(&normal_word(t).as_str()) => {
                        Value::Word(normal_word(t))
                    }
                    _ => return Err(bad()),
                }
            }
            Kind::RealOrWord { words, min, closed } => match arg {
                Arg::Text(t) if words().contains(&normal_word(t).as_str()) => {
                    Value::Word(normal_word(t))
                }
                _ => {
                    let v = finite(arg).ok_or_else(bad)?;
                    if !above(v, min, closed) {
                        return Err(bad());
                    }
                    Value::Real(v)
                }
            },
            Kind::Numbers => match arg {
                Arg::Numbers(v) => Value::Numbers(v.clone()),
                Arg::Counts(v) => Value::Numbers(v.iter().map(|&k| k as f64).collect()),
                Arg::Pair(lo, hi) => Value::Pair(lo.clone(), hi.clone()),
                Arg::Text(t) => Value::Numbers(number_list(&spell(self.name), t, t)?),
                _ => return Err(bad()),
            },
            Kind::Sizes => Value::Sizes(self.sizes(arg).ok_or_else(bad)?),
            Kind::Points => match arg {
                Arg::Points(p) => Value::Points(p.clone()),
                _ => return Err(bad()),
            },
            Kind::WordOrPoints(words) => match arg {
                Arg::Points(p) => Value::Points(p.clone()),
                Arg::Text(t) if words().contains(&normal_word(t).as_str()) => {
                    Value::Word(normal_word(t))
                }
                _ => return Err(bad()),
            },
            Kind::Text => match arg {
                Arg::Text(t) => Value::Text(t.clone()),
                _ => return Err(bad()),
            },
            Kind::Texts => match arg {
                Arg::Text(t) => Value::Texts(vec![t.clone()]),
                Arg::Texts(v) => Value::Texts(v.clone()),
                // An empty list reaches here typed as numbers: no text.
                Arg::Counts(v) if v.is_empty() => Value::Texts(Vec::new()),
                Arg::Numbers(v) if v.is_empty() => Value::Texts(Vec::new()),
                _ => return Err(bad()),
            },
            Kind::Rows => match arg {
                Arg::Text(t) => Value::RowsText(t.clone()),
                Arg::Points(p) => Value::RowsNumbers(p.as_slice().to_vec()),
                Arg::Numbers(v) => Value::RowsNumbers(v.clone()),
                _ => return Err(bad()),
            },
            Kind::FrontEnd => return Err(bad()),
        };
        Ok(Some(value))
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
