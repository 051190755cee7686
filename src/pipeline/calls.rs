//! A front end's calls by keyword argument (Python's): each value, in the forms a dynamic
//! language gives it ([`Loose`]), read into the request's [`Arg`]; the request made and
//! resolved with refusals spelt by keyword; and the replies that are not point sets (the
//! option table, a design, a measure, a design's figures) as JSON for the front end to
//! load. The extension only converts its objects to and from these.

use std::collections::HashMap;

use serde::Serialize;

use super::evaluation::Measure;
use super::integration::Spelling;
use super::options::{self as declared, Command, Kind, Opt, ALL, OPTIONS};
use super::request::{Arg, Request, Resolved};
use super::worker::StageLines;
use crate::cubature::Rounds;
use crate::design::{Column, Design, DesignSpace};
use crate::{Error, PointSet};

/// A value as a dynamic language holds it, before the library reads it into an [`Arg`].
#[derive(Debug, Clone, PartialEq)]
pub enum Loose {
    /// Not given (Python's `None`).
    None,
    /// A truth value.
    Bool(bool),
    /// A whole number.
    Int(i128),
    /// A whole number too large for any count or seed, as its digits (refused with the
    /// argument's own range).
    Digits(String),
    /// A number with a fraction (or any object that reads as one).
    Float(f64),
    /// Text.
    Text(String),
    /// A 2-D array of floats, row-major.
    Array {
        /// Rows.
        n: usize,
        /// Columns.
        s: usize,
        /// The rows one after another.
        data: Vec<f64>,
    },
    /// A tuple of values (`(lo, hi)` of bounds, a box's pairs).
    Tuple(Vec<Loose>),
    /// Any other sequence of values (lists, 1-D arrays as lists).
    List(Vec<Loose>),
    /// Anything else (refused as a value).
    Other,
}

/// One keyword argument of a call: its keyword, its value, and the value as the user
/// typed it (Python's `repr`), which refusals echo.
#[derive(Debug, Clone)]
pub struct Keyword {
    /// The keyword.
    pub key: String,
    /// The value.
    pub value: Loose,
    /// The value as typed.
    pub shown: String,
}

impl Loose {
    /// As one number (a truth value is 0 or 1).
    fn number(&self) -> Option<f64> {
        match self {
            Loose::Float(f) => Some(*f),
            Loose::Int(i) => Some(*i as f64),
            Loose::Bool(b) => Some(f64::from(u8::from(*b))),
            Loose::Digits(t) => t.parse().ok().filter(|f: &f64| f.is_finite()),
            _ => None,
        }
    }

    /// As one whole number (a truth value is 0 or 1).
    fn whole(&self) -> Option<i128> {
        match self {
            Loose::Int(i) => Some(*i),
            Loose::Bool(b) => Some(i128::from(*b)),
            _ => None,
        }
    }

    /// As numbers: a sequence of them.
    fn numbers(&self) -> Option<Vec<f64>> {
        match self {
            Loose::List(v) | Loose::Tuple(v) => v.iter().map(Loose::number).collect(),
            _ => None,
        }
    }

    /// The request's value of the keyword `key` (`None`: not given); `pair` reads a
    /// tuple of two sides as bounds' lower and upper ends (each a number or one per
    /// coordinate). Only the form is read here; what a value means is the resolution's
    /// to decide.
    pub fn arg(self, key: &str, shown: &str, pair: bool) -> Result<Option<Arg>, Error> {
        let arg = match self {
            Loose::None => return Ok(None),
            Loose::Bool(b) => Some(Arg::Bool(b)),
            Loose::Int(i) => Some(Arg::Int(i)),
            Loose::Digits(t) | Loose::Text(t) => Some(Arg::Text(t)),
            Loose::Float(f) => Some(Arg::Float(f)),
            Loose::Array { n, s, data } => {
                let p = PointSet::new(n, s, data)
                    .map_err(|e| Error::Numerical(format!("{key}: {e}")))?;
                Some(Arg::Points(p))
            }
            Loose::Tuple(v) if pair && v.len() == 2 => {
                let side = |x: &Loose| x.number().map(|f| vec![f]).or_else(|| x.numbers());
                match (side(&v[0]), side(&v[1])) {
                    (Some(lo), Some(hi)) => Some(Arg::Pair(lo, hi)),
                    _ => sequence(&v),
                }
            }
            Loose::Tuple(v) | Loose::List(v) => sequence(&v),
            Loose::Other => None,
        };
        arg.map(Some).ok_or_else(|| {
            Error::invalid(
                key,
                shown,
                "a number, a string, a list of numbers or an (n, d) array",
            )
        })
    }
}

/// A sequence of values as the request reads it: whole numbers, numbers, texts, pairs
/// `[(lo1, hi1), ...]` (as a box is often written) or rows of one length (a matrix).
fn sequence(items: &[Loose]) -> Option<Arg> {
    if let Some(counts) = items.iter().map(Loose::whole).collect() {
        return Some(Arg::Counts(counts));
    }
    if let Some(numbers) = items.iter().map(Loose::number).collect() {
        return Some(Arg::Numbers(numbers));
    }
    let text = |x: &Loose| match x {
        Loose::Text(t) => Some(t.clone()),
        _ => None,
    };
    if let Some(texts) = items.iter().map(text).collect() {
        return Some(Arg::Texts(texts));
    }
    let pair = |x: &Loose| match x {
        Loose::Tuple(v) if v.len() == 2 => Some([v[0].number()?, v[1].number()?]),
        _ => None,
    };
    if let Some(pairs) = items.iter().map(pair).collect::<Option<Vec<_>>>() {
        return Some(Arg::Numbers(pairs.concat()));
    }
    let rows: Vec<Vec<f64>> = items.iter().map(Loose::numbers).collect::<Option<_>>()?;
    let width = rows.first().map_or(0, Vec::len);
    if rows.iter().any(|r| r.len() != width) {
        return None;
    }
    PointSet::new(rows.len(), width, rows.concat())
        .ok()
        .map(Arg::Points)
}

/// Whether Python's keyword `key` is the option `opt`'s.
fn is(key: &str, opt: Opt) -> bool {
    opt.declared().python == Some(key)
}

/// The request of `generate`'s or `eval`'s keyword arguments, each set by its Python
/// keyword ([`OPTIONS`]), refusals named by keyword.
pub fn request(keywords: Vec<Keyword>) -> Result<Request, Error> {
    let mut r = Request::default();
    for Keyword { key, value, shown } in keywords {
        let Some(d) = declared::by_python(&key) else {
            let accepted: Vec<&str> = OPTIONS.iter().filter_map(|d| d.python).collect();
            let expected = format!("one of {}", accepted.join(", "));
            return Err(Error::invalid("keyword argument", key, expected));
        };
        if let Some(value) = value.arg(&key, &shown, is(&key, Opt::bounds))? {
            r.set(d.name, value)
                .map_err(|e| spelt(e, &HashMap::new()))?;
        }
    }
    Ok(r)
}

/// Python's spelling of a parameter (its keyword argument in the option table), or the
/// caller's own name where a wrapper renames one (`m`, `sizes`).
pub fn spell(name: &str, renamed: &HashMap<String, String>) -> String {
    match renamed.get(name) {
        Some(r) => r.clone(),
        None => declared::python_name(name),
    }
}

/// A refusal with the parameter spelt as [`spell`] spells it.
fn spelt(e: Error, renamed: &HashMap<String, String>) -> Error {
    match e {
        Error::InvalidArgument {
            name,
            value,
            expected,
        } => Error::invalid(spell(&name, renamed), value, expected),
        other => other,
    }
}

/// The resolution of `generate`'s keyword arguments, with Python's names (or the
/// caller's, `renamed`) in refusals.
pub fn resolve(
    keywords: Vec<Keyword>,
    renamed: &HashMap<String, String>,
) -> Result<Resolved, Error> {
    request(keywords)?
        .resolve_as(&|name| spell(name, renamed))
        .map_err(|e| spelt(e, renamed))
}

/// How `eval`'s keyword arguments measure points, with Python's names in refusals.
pub fn measure(keywords: Vec<Keyword>) -> Result<Measure, Error> {
    let none = HashMap::new();
    request(keywords)?
        .resolve_eval_as(&|n| spell(n, &none))
        .map_err(|e| spelt(e, &none))
}

/// The figures of the points `x` as `measure` measures them (what `stillpoint eval
/// --json` prints).
pub fn measured(measure: &Measure, x: PointSet) -> Result<serde_json::Value, Error> {
    let none = HashMap::new();
    let spell = |n: &str| spell(n, &none);
    let p = measure
        .unit_points(x, "x", &spell)
        .map_err(|e| spelt(e, &none))?;
    if let Measure::Cube { .. } = measure {
        p.check_unit_cube()
            .map_err(|e| Error::Numerical(format!("x: {e}")))?;
    }
    measure.json(&p, &spell).map_err(|e| spelt(e, &none))
}

/// The result of `resolve` over the request of an integration command's keyword
/// arguments (`quad`, `sobol_indices`), each echoed in refusals as typed. The keywords
/// are the declared ones ([`ALL`]), but for the box: its corners `a` and `b` apart, the
/// library's `bounds` as lower and upper ends (spelt in refusals as the corners given).
pub fn with_request<T>(
    keywords: Vec<Keyword>,
    resolve: impl FnOnce(&Request, &Spelling) -> Result<T, Error>,
) -> Result<T, Error> {
    let mut r = Request::default();
    let mut typed: HashMap<&str, String> = HashMap::new();
    let mut ends: [Option<(Vec<f64>, String)>; 2] = [None, None];
    for Keyword { key, value, shown } in keywords {
        let Some(value) = value.arg(&key, &shown, false)? else {
            continue;
        };
        if let Some(i) = ["a", "b"].iter().position(|c| *c == key) {
            let end = match value {
                Arg::Float(x) => vec![x],
                Arg::Int(i) => vec![i as f64],
                Arg::Numbers(v) => v,
                Arg::Counts(v) => v.into_iter().map(|i| i as f64).collect(),
                _ => return Err(Error::invalid(key, shown, "a number, or one per dimension")),
            };
            ends[i] = Some((end, shown));
            continue;
        }
        let d = ALL
            .iter()
            .find(|d| d.python == Some(key.as_str()))
            .ok_or_else(|| Error::Numerical(format!("invalid keyword argument = {key}")))?;
        r.set(d.name, value)?;
        typed.insert(d.name, shown);
    }
    let corners = match &ends {
        [Some(_), Some(_)] => "a, b",
        [Some(_), None] => "a",
        _ => "b",
    };
    if ends.iter().any(Option::is_some) {
        let show =
            |e: &Option<(Vec<f64>, String)>| e.as_ref().map_or("None".into(), |e| e.1.clone());
        let both = format!("({}, {})", show(&ends[0]), show(&ends[1]));
        typed.insert(Opt::bounds.name(), both);
        let [lo, hi] = ends;
        let end = |e: Option<(Vec<f64>, String)>, fill: f64| e.map_or(vec![fill], |e| e.0);
        r.bounds = Some(Arg::Pair(end(lo, 0.0), end(hi, 1.0)));
    }
    let name = |n: &str| {
        if n == Opt::bounds.name() {
            corners.to_string()
        } else {
            declared::python_name(n)
        }
    };
    let shown = |n: &str, v: &Arg| typed.get(n).cloned().unwrap_or_else(|| v.to_string());
    let spelling = Spelling {
        name: &name,
        shown: &shown,
    };
    resolve(&r, &spelling)
}

/// The bounds of an option's numbers, as the option table lists them.
#[derive(Serialize)]
#[serde(untagged)]
enum Limits {
    Count {
        min: u64,
        max: u64,
    },
    Real {
        min: f64,
        closed: bool,
        below: Option<f64>,
    },
    RealOrWord {
        min: f64,
        closed: bool,
    },
}

/// One row of the option table (see [`options_json`]), its fields in this order.
#[derive(Serialize)]
struct Row {
    name: &'static str,
    cli: &'static str,
    python: Option<&'static str>,
    doc: &'static str,
    groups: Vec<&'static str>,
    commands: Vec<&'static str>,
    #[serde(flatten)]
    limits: Option<Limits>,
    kind: &'static str,
    words: Vec<&'static str>,
    expected: String,
    default: Defaults,
}

/// An option's default per command, in the order of its commands.
struct Defaults(Vec<(&'static str, Option<String>)>);

impl Serialize for Defaults {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.collect_map(self.0.iter().map(|(k, v)| (k, v)))
    }
}

/// Every option as declared once, a JSON list of objects: `name` (the library's), `cli`
/// (the command line's flag, empty where it has none), `python` (the keyword argument,
/// `null` where Python has none), `doc` (one line), `groups`, `commands`, `kind` (with
/// `min`, `max`, `closed`, `below` for numbers), `words` (every word it accepts),
/// `expected` (what a refusal says is accepted) and `default` (per command, as help
/// shows it). Those of `generate` and `eval` by default; `command` gives that command's.
pub fn options_json(command: Option<&str>) -> Result<String, Error> {
    let among: Vec<&declared::Declared> = match command {
        None => OPTIONS.iter().collect(),
        Some(name) => {
            let c = Command::ALL.into_iter().find(|c| c.name() == name);
            let c = c.ok_or_else(|| {
                let names: Vec<&str> = Command::ALL.iter().map(|c| c.name()).collect();
                Error::invalid("command", name, names.join(", "))
            })?;
            ALL.iter().filter(|d| d.takes(c)).collect()
        }
    };
    let rows: Vec<Row> = among.into_iter().map(row).collect();
    serde_json::to_string(&rows).map_err(|e| Error::Numerical(e.to_string()))
}

/// An option's row of the table.
fn row(d: &declared::Declared) -> Row {
    let (limits, kind) = match d.kind {
        Kind::Count { min, max } => (Some(Limits::Count { min, max }), "count"),
        Kind::Real { min, closed, below } => (Some(Limits::Real { min, closed, below }), "real"),
        Kind::RealOrWord { min, closed, .. } => {
            (Some(Limits::RealOrWord { min, closed }), "real_or_word")
        }
        Kind::Seed => (None, "seed"),
        Kind::Flag => (None, "flag"),
        Kind::Word(_) => (None, "word"),
        Kind::Numbers | Kind::Bounds => (None, "numbers"),
        Kind::Sizes => (None, "sizes"),
        Kind::Points => (None, "points"),
        Kind::WordOrPoints(_) => (None, "word_or_points"),
        Kind::Text => (None, "text"),
        Kind::Texts { .. } => (None, "texts"),
        Kind::Rows => (None, "rows"),
        Kind::FrontEnd => (None, "front_end"),
    };
    Row {
        name: d.name,
        cli: d.cli,
        python: d.python,
        doc: d.doc,
        groups: d.groups.iter().map(|g| g.name()).collect(),
        commands: d.commands.iter().map(|c| c.name()).collect(),
        limits,
        kind,
        words: d.words(),
        expected: (d.expected)(),
        default: Defaults(
            d.commands
                .iter()
                .map(|c| (c.name(), (d.default)(*c)))
                .collect(),
        ),
    }
}

/// A design as a front end's reply, beside its unit-scale set: the space, its
/// correlation, the names, each column as written, the figures of the design as written
/// and read back (which a report describes).
#[derive(Serialize)]
struct DesignReply {
    space: Vec<String>,
    correlation: Option<String>,
    names: Vec<String>,
    columns: Vec<serde_json::Value>,
    figures: crate::design::figures::DesignFigures,
    rule: Option<&'static str>,
    unbiased: bool,
}

/// The design the resolved request (which holds a space) makes, as JSON (see
/// the fields of `DesignReply`, with `rule` and `unbiased` of the cube set's rule), and
/// its unit-scale set.
pub fn design(resolved: &Resolved) -> Result<(serde_json::Value, PointSet), Error> {
    let outcome = resolved.run(None, |_| {})?;
    let design = outcome
        .design
        .ok_or_else(|| Error::Numerical("a design needs space=".to_string()))?;
    let written = design.as_written()?;
    let columns = design.columns().into_iter().map(|c| match c {
        Column::Real(v) => serde_json::json!(v),
        Column::Int(v) => serde_json::json!(v),
        Column::Label(v) => serde_json::json!(v),
    });
    let reply = DesignReply {
        space: design.space.texts(),
        correlation: design.space.correlation_text(),
        names: design.space.vars.iter().map(|v| v.name.clone()).collect(),
        columns: columns.collect(),
        figures: crate::design::figures::DesignFigures::of_with(&written, resolved.sums),
        rule: resolved.rule.map(|r| r.phrase()),
        unbiased: resolved.rule.is_some_and(|r| r.unbiased()),
    };
    let v = serde_json::to_value(reply).map_err(|e| Error::Numerical(e.to_string()))?;
    Ok((v, design.unit))
}

/// The unit-scale set of the design the resolved request (which holds a space) makes,
/// and the phrase of its rule ([`super::measure::CubeRule::phrase`]): [`design`]'s set
/// without the figures, for a front end that draws sets and maps them itself (the
/// engine under a space).
pub fn space_set(resolved: &Resolved) -> Result<(PointSet, &'static str), Error> {
    let outcome = resolved.run(None, |_| {})?;
    let design = outcome
        .design
        .ok_or_else(|| Error::Numerical("a design needs space=".to_string()))?;
    let phrase = resolved.rule.map_or("", |r| r.phrase());
    Ok((design.unit, phrase))
}

/// The rule of a randomised sequence under `space` as front ends name it, and the order
/// its columns are dealt to the space's coordinates
/// ([`super::measure::sequence_rule`]).
pub fn space_sequence(space: &DesignSpace) -> (&'static str, Vec<usize>) {
    let (rule, order) = super::measure::sequence_rule(space);
    (rule.as_str(), order)
}

/// A design space from its `NAME=TYPE` texts and, if given, the continuous variables'
/// correlation (row-major).
pub fn space(texts: &[String], correlation: Option<Vec<f64>>) -> Result<DesignSpace, Error> {
    let mut space = DesignSpace::parse(Opt::space.name(), texts)?;
    if let Some(m) = correlation {
        let shown = format!("{m:?}");
        space.correlate(Opt::correlation.name(), &shown, m)?;
    }
    Ok(space)
}

/// The figures of a design given as named columns of cells (each a label, a whole
/// number or a number that reads back to the same float) in `space`, as JSON.
pub fn design_figures(
    space: &DesignSpace,
    columns: &[(String, Vec<String>)],
) -> Result<serde_json::Value, Error> {
    let design = Design::from_columns(space, columns, "table")?;
    serde_json::to_value(crate::design::figures::DesignFigures::of(&design))
        .map_err(|e| Error::Numerical(e.to_string()))
}

/// Points `unit` of the unit cube mapped to the values of `space` (see
/// [`super::measure::mapped`]), one row per point.
pub fn space_values(space: &DesignSpace, unit: &PointSet) -> Result<PointSet, Error> {
    if unit.s() != space.dim() {
        return Err(Error::Numerical(format!(
            "x: {} coordinates per point; expected one per variable of space ({})",
            unit.s(),
            space.dim()
        )));
    }
    crate::cubature::space_numbers(space, unit)
}

/// The points of `generate`'s run, its stages shown on standard error when `progress`
/// ([`StageLines`]).
pub fn generate(resolved: &Resolved, progress: bool) -> Result<PointSet, Error> {
    let (mut lines, mut err) = (StageLines::default(), std::io::stderr());
    let outcome = resolved.run(None, |e| {
        if progress {
            lines.event(e, &mut err)
        }
    });
    lines.finish(&mut err);
    outcome.map(|o| o.points)
}

/// The parts of a resolved space a front end needs to map each batch itself: the
/// space's names and its correlation, row-major.
pub fn space_parts(space: Option<DesignSpace>) -> (Option<Vec<String>>, Option<Vec<f64>>) {
    match space {
        Some(s) => (
            Some(s.vars.iter().map(|v| v.name.clone()).collect()),
            s.copula.map(|c| c.matrix),
        ),
        None => (None, None),
    }
}

/// Feeds f's `values` at the batch handed out (`batch`, which is then cleared). A state
/// restored from a pickle has no batch kept (it is not pickled), so the pending one is
/// made again first.
pub fn feed(
    rounds: &mut impl Rounds,
    batch: &mut Option<PointSet>,
    values: &[f64],
) -> Result<(), Error> {
    if batch.is_none() && rounds.pending() > 0 {
        *batch = rounds.next_points();
    }
    let Some(points) = batch.as_ref() else {
        let refusal = "feed: no batch is pending; call next_points() first";
        return Err(Error::Numerical(refusal.to_string()));
    };
    rounds.feed(points, values)?;
    *batch = None;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn kw(key: &str, value: Loose) -> Keyword {
        let shown = format!("{value:?}");
        Keyword {
            key: key.into(),
            value,
            shown,
        }
    }

    /// `exact=True` reaches the figures of a design, whichever rule makes its cube set,
    /// as it reaches a run's report; without it the report's rule applies.
    #[test]
    fn exact_reaches_a_design_s_figures_as_it_reaches_a_run_s() {
        use crate::quality::metrics::Sums;
        let space = || {
            kw(
                "space",
                Loose::List(vec![Loose::Text("x=normal(0,1)".into())]),
            )
        };
        let cube = |extra: Vec<Keyword>| {
            let mut k = vec![kw("n", Loose::Int(64)), kw("d", Loose::Int(1))];
            k.extend(extra);
            resolve(k, &HashMap::new()).unwrap().sums
        };
        let exact = || kw("exact", Loose::Bool(true));
        let draw = || kw("randomize", Loose::Bool(true));
        assert_eq!(cube(vec![]), Sums::AUTO);
        assert_eq!(cube(vec![exact()]), Sums::EXACT);
        assert_eq!(cube(vec![space()]), Sums::AUTO);
        assert_eq!(cube(vec![space(), exact()]), Sums::EXACT);
        assert_eq!(cube(vec![space(), draw(), exact()]), Sums::EXACT);
        assert_eq!(cube(vec![space(), draw()]), Sums::AUTO);
    }

    fn arg(v: Loose, pair: bool) -> Result<Option<Arg>, Error> {
        v.arg("k", "typed", pair)
    }

    #[test]
    fn each_form_reads_as_the_request_takes_it() {
        use Loose::*;
        assert_eq!(arg(None, false).unwrap(), Option::None);
        assert_eq!(arg(Int(3), false).unwrap(), Some(Arg::Int(3)));
        assert_eq!(
            arg(Digits("9".repeat(40)), false).unwrap(),
            Some(Arg::Text("9".repeat(40)))
        );
        assert_eq!(
            arg(List(vec![Int(1), Bool(true)]), false).unwrap(),
            Some(Arg::Counts(vec![1, 1]))
        );
        assert_eq!(
            arg(List(vec![Int(1), Float(0.5)]), false).unwrap(),
            Some(Arg::Numbers(vec![1.0, 0.5]))
        );
        let texts = List(vec![Text("x=normal(0,1)".into())]);
        assert_eq!(
            arg(texts, false).unwrap(),
            Some(Arg::Texts(vec!["x=normal(0,1)".into()]))
        );
        let pairs = List(vec![
            Tuple(vec![Int(0), Float(0.5)]),
            Tuple(vec![Int(2), Int(3)]),
        ]);
        assert_eq!(
            arg(pairs, false).unwrap(),
            Some(Arg::Numbers(vec![0.0, 0.5, 2.0, 3.0]))
        );
        let rows = List(vec![
            List(vec![Float(0.25), Int(1)]),
            Tuple(vec![Int(0), Float(0.5)]),
        ]);
        let p = PointSet::new(2, 2, vec![0.25, 1.0, 0.0, 0.5]).unwrap();
        assert_eq!(arg(rows, false).unwrap(), Some(Arg::Points(p)));
        let array = Array {
            n: 1,
            s: 2,
            data: vec![0.5, 0.25],
        };
        assert!(matches!(arg(array, false).unwrap(), Some(Arg::Points(p)) if p.s() == 2));
    }

    #[test]
    fn a_pair_of_sides_is_bounds_only_where_asked() {
        use Loose::*;
        let sides = || Tuple(vec![Int(0), List(vec![Float(2.0), Int(3)])]);
        let pair = Arg::Pair(vec![0.0], vec![2.0, 3.0]);
        assert_eq!(arg(sides(), true).unwrap(), Some(pair));
        // Elsewhere a tuple is a sequence like any other: here not one of numbers.
        assert!(arg(sides(), false).is_err());
        assert_eq!(
            arg(Tuple(vec![Int(0), Int(1)]), false).unwrap(),
            Some(Arg::Counts(vec![0, 1]))
        );
    }

    #[test]
    fn a_value_of_no_accepted_form_is_refused_as_typed() {
        let ragged = Loose::List(vec![Loose::List(vec![Loose::Int(1)]), Loose::List(vec![])]);
        for v in [
            Loose::Other,
            ragged,
            Loose::List(vec![Loose::Text("a".into()), Loose::Int(1)]),
        ] {
            let e = arg(v, false).unwrap_err().to_string();
            assert_eq!(
                e,
                "invalid k = typed: expected a number, a string, a list of numbers or an (n, d) array"
            );
        }
    }

    #[test]
    fn keywords_are_python_s_and_refusals_say_them() {
        let e = request(vec![kw("nope", Loose::Int(1))])
            .unwrap_err()
            .to_string();
        assert!(
            e.starts_with("invalid keyword argument = nope: expected one of "),
            "{e}"
        );
        assert!(e.contains("max_n") || e.contains("seed"), "{e}");
        let r = request(vec![kw("n", Loose::Int(8)), kw("d", Loose::Int(2))]).unwrap();
        assert_eq!(r.n, Some(Arg::Int(8)));
        let renamed = HashMap::from([("n".to_string(), "sizes".to_string())]);
        let e = resolve(
            vec![kw("n", Loose::Int(0)), kw("d", Loose::Int(2))],
            &renamed,
        )
        .unwrap_err()
        .to_string();
        assert!(e.starts_with("invalid sizes = 0"), "{e}");
    }

    #[test]
    fn corners_are_the_bounds_and_are_spelt_as_given() {
        let corners = |given: Vec<Keyword>| {
            with_request(given, |r, sp| {
                let b = r.bounds.clone().unwrap();
                Ok((
                    (sp.name)(Opt::bounds.name()),
                    (sp.shown)(Opt::bounds.name(), &b),
                    b,
                ))
            })
            .unwrap()
        };
        let (name, shown, b) = corners(vec![kw("b", Loose::Float(2.5))]);
        assert_eq!((name.as_str(), shown.as_str()), ("b", "(None, Float(2.5))"));
        assert_eq!(b, Arg::Pair(vec![0.0], vec![2.5]));
        let given = vec![
            kw("a", Loose::List(vec![Loose::Int(1), Loose::Int(2)])),
            kw("b", Loose::Int(3)),
        ];
        let (name, _, b) = corners(given);
        assert_eq!(name, "a, b");
        assert_eq!(b, Arg::Pair(vec![1.0, 2.0], vec![3.0]));
        let e = with_request(vec![kw("a", Loose::Text("x".into()))], |_, _| Ok(()));
        assert_eq!(
            e.unwrap_err().to_string(),
            "invalid a = Text(\"x\"): expected a number, or one per dimension"
        );
    }

    #[test]
    fn the_option_table_lists_every_option_in_order_with_its_defaults() {
        let rows: Vec<serde_json::Value> =
            serde_json::from_str(&options_json(None).unwrap()).unwrap();
        assert_eq!(rows.len(), OPTIONS.len());
        for (row, d) in rows.iter().zip(OPTIONS) {
            assert_eq!(row["name"], d.name);
            assert_eq!(row["words"].as_array().unwrap().len(), d.words().len());
            assert_eq!(row["default"].as_object().unwrap().len(), d.commands.len());
        }
        let text = options_json(None).unwrap();
        let count = text.find("\"kind\":\"count\"").unwrap();
        assert!(text[..count].rfind("\"min\"") > text[..count].rfind("\"commands\""));
        let quad = options_json(Some(Command::ALL[1].name())).unwrap();
        assert!(serde_json::from_str::<Vec<serde_json::Value>>(&quad).is_ok());
        let e = options_json(Some("nope")).unwrap_err().to_string();
        assert!(e.starts_with("invalid command = nope: expected "), "{e}");
    }

    #[test]
    fn a_space_maps_the_unit_cube_and_refuses_a_wrong_width() {
        let s = space(&["x=uniform(2,4)".to_string()], None).unwrap();
        let unit = PointSet::new(2, 1, vec![0.25, 0.5]).unwrap();
        assert_eq!(space_values(&s, &unit).unwrap().into_vec(), vec![2.5, 3.0]);
        let wide = PointSet::new(1, 2, vec![0.25, 0.5]).unwrap();
        let e = space_values(&s, &wide).unwrap_err().to_string();
        assert!(e.starts_with("x: 2 coordinates per point"), "{e}");
        let figures = design_figures(&s, &[("x".into(), vec!["2.5".into(), "3.5".into()])]);
        assert!(figures.unwrap().is_object());
    }

    #[test]
    fn a_batch_is_fed_once_and_made_again_after_a_restore() {
        use crate::cubature::{Cubature, QuadOptions};
        let mut state = Cubature::new(1, QuadOptions::default()).unwrap();
        let mut batch = None;
        let e = feed(&mut state, &mut batch, &[]).unwrap_err().to_string();
        assert_eq!(e, "feed: no batch is pending; call next_points() first");
        // Handed out, then lost as by a pickle (the batch is not kept): made again.
        let rows = state.next_points().unwrap().n();
        feed(&mut state, &mut batch, &vec![0.5; rows]).unwrap();
        assert!(batch.is_none());
        assert_eq!((state.n(), state.estimate()), (rows as u64, vec![0.5]));
        assert!(
            feed(&mut state, &mut batch, &vec![0.5; rows]).is_err(),
            "fed once"
        );
    }
}
