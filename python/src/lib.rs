//! The extension module `stillpoint._core`: the library's point generation, metrics,
//! baselines and test integrals on NumPy arrays.
//!
//! Every function copies its input into a [`PointSet`], releases the GIL for the
//! computation (other Python threads run meanwhile, Ctrl-C stops it: the library's
//! [`worker::watched`]), and turns every refusal of the library into a `ValueError`
//! carrying the library's message (a panic, which would be a bug, becomes a
//! `RuntimeError`, never a crash). Keyword arguments are read and resolved by the
//! library ([`calls`]); reports (metrics, test integrals, designs, the option table) come
//! back as the objects `json.loads` makes of the library's JSON. The Python package
//! `stillpoint` wraps these functions: it casts any array-like to C-ordered float64,
//! scales to bounds, and adds the SciPy engine.

#![deny(missing_docs)]

mod drivers;

use std::collections::HashMap;

use numpy::ndarray::Array2;
use numpy::{IntoPyArray, PyArray2, PyReadonlyArray2};
use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyFloat, PyInt, PySequence, PyString, PyTuple};

use stillpoint::pipeline::calls::{self, Keyword, Loose};
use stillpoint::pipeline::options::python_name;
use stillpoint::pipeline::request::Resolved;
use stillpoint::pipeline::worker::{self, Stopped};
use stillpoint::sequences::Baseline;
use stillpoint::PointSet;

/// A refusal as Python sees it.
fn value_error(message: impl std::fmt::Display) -> PyErr {
    PyValueError::new_err(message.to_string())
}

/// Runs `f` without the GIL on the library's watched worker, Python's signals looked at
/// meanwhile: Ctrl-C raises `KeyboardInterrupt`, a refusal a `ValueError`, a panic a
/// `RuntimeError`.
fn detached<T: Send + 'static>(
    py: Python<'_>,
    f: impl FnOnce() -> Result<T, stillpoint::Error> + Send + 'static,
) -> PyResult<T> {
    let signals = || Python::attach(|py| py.check_signals());
    py.detach(|| worker::watched(move || f().map_err(|e| e.to_string()), signals))
        .map_err(|stopped| match stopped {
            Stopped::Signal(e) => e,
            Stopped::Refused(message) => value_error(message),
            Stopped::Panicked(message) => PyRuntimeError::new_err(message),
        })
}

/// Copies a 2-D float64 array (any memory layout) into a point set named `name` in
/// messages.
fn point_set(name: &str, x: &PyReadonlyArray2<'_, f64>) -> PyResult<PointSet> {
    let view = x.as_array();
    let (n, s) = view.dim();
    let data: Vec<f64> = view.iter().copied().collect();
    PointSet::new(n, s, data).map_err(|e| value_error(format!("{name}: {e}")))
}

/// A point set of the unit cube (what the discrepancies and test integrals assume).
fn unit_points(name: &str, x: &PyReadonlyArray2<'_, f64>) -> PyResult<PointSet> {
    let p = point_set(name, x)?;
    p.check_unit_cube()
        .map_err(|e| value_error(format!("{name}: {e}")))?;
    Ok(p)
}

/// A point set as an (n, s) array, without copying the buffer.
fn to_array<'py>(py: Python<'py>, p: PointSet) -> PyResult<Bound<'py, PyArray2<f64>>> {
    let (n, s) = (p.n(), p.s());
    let a = Array2::from_shape_vec((n, s), p.into_vec())
        .map_err(|e| PyRuntimeError::new_err(e.to_string()))?;
    Ok(a.into_pyarray(py))
}

/// The object `json.loads` makes of a JSON value or text of the library's.
fn loads<'py>(py: Python<'py>, text: impl ToString) -> PyResult<Bound<'py, PyAny>> {
    py.import("json")?
        .call_method1("loads", (text.to_string(),))
}

/// A Python value in the forms the library reads ([`Loose`]): only the form is taken
/// here, never what it means.
fn loose(v: &Bound<'_, PyAny>) -> PyResult<Loose> {
    if v.is_none() {
        return Ok(Loose::None);
    }
    // NumPy's booleans (`numpy.bool_`) are truth values too, never the numbers 0 and 1.
    let numpy_bool = v
        .get_type()
        .name()
        .is_ok_and(|t| t == "bool" || t == "bool_");
    if v.is_instance_of::<PyBool>() || numpy_bool {
        return Ok(Loose::Bool(v.is_truthy()?));
    } else if v.is_instance_of::<PyString>() {
        return Ok(Loose::Text(v.extract()?));
    }
    // A NumPy integer scalar has dimensions (none) like an array; it is still one integer,
    // and goes through `__index__` exactly (a float would lose bits above 2^53). A 0-d
    // array of floats has `__index__` too, which refuses: it goes on as a number.
    let ndim = v
        .getattr("ndim")
        .ok()
        .and_then(|d| d.extract::<usize>().ok());
    let scalar = ndim.is_none_or(|d| d == 0);
    if v.is_instance_of::<PyInt>() || v.hasattr("__index__")? && scalar {
        match v
            .call_method0("__index__")
            .and_then(|i| i.extract::<i128>())
        {
            Ok(i) => return Ok(Loose::Int(i)),
            Err(_) if v.is_instance_of::<PyInt>() => {
                return Ok(Loose::Digits(v.str()?.to_string()))
            }
            Err(_) => {}
        }
    }
    if v.is_instance_of::<PyFloat>() {
        return Ok(Loose::Float(v.extract()?));
    } else if let Ok(a) = v.extract::<PyReadonlyArray2<'_, f64>>() {
        let (n, s) = a.as_array().dim();
        let data = a.as_array().iter().copied().collect();
        return Ok(Loose::Array { n, s, data });
    } else if let Ok(f) = v.extract::<f64>() {
        return Ok(Loose::Float(f));
    }
    let items = |s: &Bound<'_, PyAny>| -> PyResult<Vec<Loose>> {
        s.try_iter()?.map(|x| loose(&x?)).collect()
    };
    if v.is_instance_of::<PyTuple>() {
        Ok(Loose::Tuple(items(v)?))
    } else if !scalar && v.hasattr("tolist")? {
        // An array (or a pandas Series) as the lists of its rows' Python numbers.
        loose(&v.call_method0("tolist")?)
    } else if v.cast::<PySequence>().is_ok() {
        Ok(Loose::List(items(v)?))
    } else {
        Ok(Loose::Other)
    }
}

/// Every keyword argument of a call (but `names` and `progress`, which are this front
/// end's own) with its value and its repr; the renames `names` asks for; `progress`.
fn keywords(
    kwargs: Option<&Bound<'_, PyDict>>,
) -> PyResult<(Vec<Keyword>, HashMap<String, String>, bool)> {
    let (mut out, mut renamed, mut progress) = (Vec::new(), HashMap::new(), false);
    for (k, v) in kwargs.into_iter().flat_map(|d| d.iter()) {
        let key: String = k.extract()?;
        match key.as_str() {
            "names" if !v.is_none() => renamed = v.extract()?,
            "progress" => progress = v.is_truthy()?,
            "names" => {}
            _ => {
                let (value, shown) = (loose(&v)?, v.repr()?.to_string());
                out.push(Keyword { key, value, shown });
            }
        }
    }
    Ok((out, renamed, progress))
}

/// The resolution of a call's keyword arguments, with Python's names in refusals.
fn resolve(kwargs: Option<&Bound<'_, PyDict>>) -> PyResult<Resolved> {
    let (given, renamed, _) = keywords(kwargs)?;
    calls::resolve(given, &renamed).map_err(value_error)
}

/// Generates points: the library's run for the request the keyword arguments make
/// (by default exactly `stillpoint generate -n N -s D`), or a baseline. `names` renames
/// parameters in refusals (a wrapper's own argument names); `progress` prints stages.
#[pyfunction]
#[pyo3(signature = (**kwargs))]
fn generate<'py>(
    py: Python<'py>,
    kwargs: Option<&Bound<'py, PyDict>>,
) -> PyResult<Bound<'py, PyArray2<f64>>> {
    let (given, renamed, progress) = keywords(kwargs)?;
    let resolved = calls::resolve(given, &renamed).map_err(value_error)?;
    let points = detached(py, move || calls::generate(&resolved, progress))?;
    to_array(py, points)
}

/// A design: the run of the request (which holds `space`), dealt into the space, as a
/// dict: the variables, each column as written, the unit-scale set (an (n, d) array)
/// and the design's figures.
#[pyfunction]
#[pyo3(signature = (**kwargs))]
fn design<'py>(
    py: Python<'py>,
    kwargs: Option<&Bound<'py, PyDict>>,
) -> PyResult<Bound<'py, PyAny>> {
    let resolved = resolve(kwargs)?;
    let (v, unit) = detached(py, move || calls::design(&resolved))?;
    let out = loads(py, v)?;
    out.set_item("unit", to_array(py, unit)?)?;
    Ok(out)
}

/// The unit-scale set `design` would deal into its space, and the phrase of its rule,
/// without the design's figures: what `Engine(d, space=..., draws='independent')` draws.
#[pyfunction]
#[pyo3(signature = (**kwargs))]
fn space_set<'py>(
    py: Python<'py>,
    kwargs: Option<&Bound<'py, PyDict>>,
) -> PyResult<(Bound<'py, PyArray2<f64>>, &'static str)> {
    let resolved = resolve(kwargs)?;
    let (unit, phrase) = detached(py, move || calls::space_set(&resolved))?;
    Ok((to_array(py, unit)?, phrase))
}

/// The rule of a randomised sequence under `space` (`'first-order lattice'` or
/// `'sobol'`) and the space's coordinate each of its columns goes to.
#[pyfunction]
fn space_sequence(space: Vec<String>) -> PyResult<(&'static str, Vec<usize>)> {
    Ok(calls::space_sequence(&self::space(&space, None)?))
}

/// A design space from its `NAME=TYPE` texts and its correlation, if given.
fn space(
    texts: &[String],
    correlation: Option<Vec<f64>>,
) -> PyResult<stillpoint::design::DesignSpace> {
    calls::space(texts, correlation).map_err(value_error)
}

/// The figures of a design given as named columns of cells in `space`, as a dict. The
/// cells cross as values, never as one CSV text, so a label holding a comma or a line
/// break is a label, not a new cell or row.
#[pyfunction]
#[pyo3(signature = (space, columns, correlation=None))]
fn design_figures<'py>(
    py: Python<'py>,
    space: Vec<String>,
    columns: Vec<(String, Vec<String>)>,
    correlation: Option<Vec<f64>>,
) -> PyResult<Bound<'py, PyAny>> {
    let space = self::space(&space, correlation)?;
    let v = detached(py, move || calls::design_figures(&space, &columns))?;
    loads(py, v)
}

/// The column names of `space` in order, one per coordinate (a path `W=brownian(1,64)`
/// gives `W_1` … `W_64`): its dimension and where each variable's values are.
#[pyfunction]
fn space_names(space: Vec<String>) -> PyResult<Vec<String>> {
    Ok(self::space(&space, None)?
        .vars
        .into_iter()
        .map(|v| v.name)
        .collect())
}

/// Points of the unit cube mapped to the values of `space`, one row per point, as the
/// library maps a design (copula, quantile functions, levels equally likely): integrating
/// over the cube after this map is the expectation under the space's distributions.
#[pyfunction]
#[pyo3(signature = (space, x, correlation=None))]
fn space_values<'py>(
    py: Python<'py>,
    space: Vec<String>,
    x: PyReadonlyArray2<'py, f64>,
    correlation: Option<Vec<f64>>,
) -> PyResult<Bound<'py, PyArray2<f64>>> {
    let space = self::space(&space, correlation)?;
    let unit = unit_points("x", &x)?;
    to_array(py, calls::space_values(&space, &unit).map_err(value_error)?)
}

/// Checks the keyword arguments of `generate` without running it.
#[pyfunction]
#[pyo3(signature = (**kwargs))]
fn check_generate(kwargs: Option<&Bound<'_, PyDict>>) -> PyResult<()> {
    resolve(kwargs).map(|_| ())
}

/// The set `generate(n, d, randomize='tent')` randomises, unrandomised.
#[pyfunction]
fn tent_set<'py>(py: Python<'py>, n: usize, d: usize) -> PyResult<Bound<'py, PyArray2<f64>>> {
    let points = detached(py, move || {
        stillpoint::goals::integration::tent::tent_set(n, d).map(|t| t.points)
    })?;
    to_array(py, points)
}

/// The unit-scale set `design(n, space, randomize=True, seed=seed)` maps into a space
/// with an unbounded law: the lattice made for the laws, randomised from `seed`.
#[pyfunction]
fn law_set<'py>(
    py: Python<'py>,
    space: Vec<String>,
    n: usize,
    seed: u64,
) -> PyResult<Bound<'py, PyArray2<f64>>> {
    let unbounded = self::space(&space, None)?.unbounded();
    let points = detached(py, move || {
        stillpoint::sequences::law_lattice(n, &unbounded, seed)
    })?;
    to_array(py, points)
}

/// The estimated seconds of `generate` with these keyword arguments on this machine's
/// thread pool, from the library's cost model; refuses what `generate` would refuse.
#[pyfunction]
#[pyo3(signature = (**kwargs))]
fn estimate(kwargs: Option<&Bound<'_, PyDict>>) -> PyResult<f64> {
    resolve(kwargs).map(|r| r.estimate_seconds())
}

/// What the library says before the run of the request besides its time (e.g. that the
/// default lattice will reuse generators); refuses what `generate` would refuse.
#[pyfunction]
#[pyo3(signature = (**kwargs))]
fn notes(kwargs: Option<&Bound<'_, PyDict>>) -> PyResult<Vec<String>> {
    resolve(kwargs).map(|r| r.unusual_as(&python_name))
}

/// The library's note before a run it estimates above its long-run threshold (the same
/// rule and words as the command line's), `None` below it.
#[pyfunction]
#[pyo3(signature = (**kwargs))]
fn long_run_note(kwargs: Option<&Bound<'_, PyDict>>) -> PyResult<Option<String>> {
    resolve(kwargs).map(|r| r.long_run_note_as(&python_name))
}

/// `x` randomised from `seed` as `generate(..., randomize=kind)` randomises its result:
/// `'tent'` (uniform shift, then the tent transform), `'cells'` (cells rotated, offsets
/// shifted within them) or `'shift'`.
#[pyfunction]
fn randomize<'py>(
    py: Python<'py>,
    x: PyReadonlyArray2<'_, f64>,
    kind: &str,
    seed: u64,
) -> PyResult<Bound<'py, PyArray2<f64>>> {
    use stillpoint::post::randomize::{randomize, Randomize};
    let p = unit_points("x", &x)?;
    let kind = Randomize::parse(kind).map_err(value_error)?;
    to_array(py, detached(py, move || Ok(randomize(&p, kind, seed)))?)
}

/// The figures of points `x` as `stillpoint eval --json` prints them, as a dict: the
/// keyword arguments make `eval`'s request (`exact`, `bounds`, `region`, `box`, `shape`,
/// `constraints`, `mixture`), which the library resolves and refuses by keyword.
#[pyfunction]
#[pyo3(signature = (x, **kwargs))]
fn metrics<'py>(
    py: Python<'py>,
    x: PyReadonlyArray2<'_, f64>,
    kwargs: Option<&Bound<'_, PyDict>>,
) -> PyResult<Bound<'py, PyAny>> {
    let measure = calls::measure(keywords(kwargs)?.0).map_err(value_error)?;
    let p = point_set("x", &x)?;
    loads(py, detached(py, move || calls::measured(&measure, p))?)
}

/// One discrepancy (the root): `l2star`, `md` (modified), `cd` (centred), `wd`
/// (wrap-around) or `mixture`.
#[pyfunction]
fn discrepancy(py: Python<'_>, x: PyReadonlyArray2<'_, f64>, kind: &str) -> PyResult<f64> {
    let f = stillpoint::metrics::discrepancy_by_name("kind", kind).map_err(value_error)?;
    let p = unit_points("x", &x)?;
    detached(py, move || Ok(f(&p)))
}

/// The baselines as (name, paper label, description) triples.
#[pyfunction]
fn baselines() -> Vec<(&'static str, &'static str, &'static str)> {
    Baseline::all()
        .iter()
        .map(|b| (b.name(), b.label(), b.describe()))
        .collect()
}

/// The F1–F8 test integrals of points in [0, 1]^d as a dict (`stillpoint integrate
/// --json` without the file name).
#[pyfunction]
fn integrate<'py>(py: Python<'py>, x: PyReadonlyArray2<'_, f64>) -> PyResult<Bound<'py, PyAny>> {
    let p = unit_points("x", &x)?;
    let v = detached(py, move || stillpoint::quality::integrands::report_json(&p))?;
    loads(py, v)
}

/// Every option as declared once in the library, a list of dicts (the library's
/// [`calls::options_json`]: name, flag, keyword, doc line, groups, commands, kind and
/// limits, words, what is accepted, defaults per command). Those of `generate` and
/// `eval` by default; `command` (`quad`, `sensitivity`, ...) gives that command's.
#[pyfunction]
#[pyo3(signature = (command=None))]
fn options<'py>(py: Python<'py>, command: Option<&str>) -> PyResult<Bound<'py, PyAny>> {
    loads(py, calls::options_json(command).map_err(value_error)?)
}

/// Adds each function to the module.
macro_rules! add {
    ($m:ident: $($f:ident),*) => {
        $($m.add_function(wrap_pyfunction!($f, $m)?)?;)*
    };
}

/// The extension module.
#[pymodule]
fn _core(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add("SEQUENCE_MAX_D", stillpoint::sequences::EXTENSIBLE_MAX_D)?;
    m.add("SOBOL_MAX_D", stillpoint::sequences::SOBOL_MAX_S)?;
    m.add(
        "ENGINE_SEQUENCE_MAX_D",
        stillpoint::sequences::ENGINE_SEQUENCE_MAX_D,
    )?;
    add!(m: generate, check_generate, design, design_figures, space_values, space_names,
        space_set, space_sequence, estimate, notes, long_run_note, discrepancy, baselines, integrate, randomize,
        tent_set, law_set, options, metrics);
    drivers::register(m)
}
