//! The extension module `stillpoint._core`: the library's point generation, metrics,
//! baselines and test integrals on NumPy arrays.
//!
//! Every function copies its input into a [`PointSet`], releases the GIL for the
//! computation (other Python threads run meanwhile), and turns every refusal of the
//! library into a `ValueError` carrying the library's message (a panic, which would be a
//! bug, becomes a `RuntimeError`, never a crash). Reports (metrics, test integrals,
//! designs) come back as Python dicts and lists built here from the library's JSON
//! values, never as text for Python to parse again. The Python package `stillpoint` wraps
//! these functions: it casts any array-like to C-ordered float64, scales to bounds, and
//! adds the SciPy engine.

#![deny(missing_docs)]

mod drivers;

use std::panic::{catch_unwind, AssertUnwindSafe};
use std::time::Instant;

use numpy::ndarray::Array2;
use numpy::{IntoPyArray, PyArray2, PyReadonlyArray2};
use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyFloat, PyInt, PyList, PyString};

use std::collections::HashMap;
use stillpoint::pipeline::options::{self as declared, OPTIONS};
use stillpoint::pipeline::request::{Arg, Resolved};
use stillpoint::sequences::Baseline;
use stillpoint::solve::Event;
use stillpoint::PointSet;
use stillpoint::Request;

/// A refusal as Python sees it.
fn value_error(message: impl std::fmt::Display) -> PyErr {
    PyValueError::new_err(message.to_string())
}

/// How long a call waits for its worker after Ctrl-C before it raises
/// `KeyboardInterrupt` anyway: the runs and the pair sums stop within a step or a tile,
/// but a computation without such checks must not keep the user waiting.
const STOP_GRACE: std::time::Duration = std::time::Duration::from_millis(300);

/// The workers of calls that raised `KeyboardInterrupt` before their worker stopped.
fn abandoned() -> std::sync::MutexGuard<'static, Vec<std::thread::JoinHandle<()>>> {
    static ABANDONED: std::sync::Mutex<Vec<std::thread::JoinHandle<()>>> =
        std::sync::Mutex::new(Vec::new());
    ABANDONED.lock().unwrap_or_else(|e| e.into_inner())
}

/// Returns once every abandoned worker has stopped (the stop request stays set until
/// then), looking at the signals every 50 ms meanwhile: Ctrl-C raises here too.
fn wait_for_abandoned(py: Python<'_>) -> PyResult<()> {
    loop {
        let running = {
            let mut workers = abandoned();
            workers.retain(|w| !w.is_finished());
            !workers.is_empty()
        };
        if !running {
            return Ok(());
        }
        py.detach(|| std::thread::sleep(std::time::Duration::from_millis(50)));
        py.check_signals()?;
    }
}

/// Runs `f` on a worker thread without the GIL, while this thread watches for signals:
/// Ctrl-C asks the library's runs and pair sums to stop ([`stillpoint::solve::cancel`])
/// and raises `KeyboardInterrupt` as soon as the worker has stopped, or after
/// [`STOP_GRACE`] at the latest (the worker's result, when it comes, is dropped). A
/// library refusal becomes a `ValueError`, a panic a `RuntimeError`.
fn detached<T: Send + 'static>(
    py: Python<'_>,
    f: impl FnOnce() -> Result<T, String> + Send + 'static,
) -> PyResult<T> {
    // A worker given up on after Ctrl-C still holds the thread pool: clearing the stop
    // request under it would let it run on beside this call (which would then wait for
    // its share of the pool). It is asked to stop until it has.
    wait_for_abandoned(py)?;
    stillpoint::solve::clear_cancel();
    let mut signal: Option<(PyErr, Instant)> = None;
    let (done, mut finished) = std::sync::mpsc::channel();
    let worker = std::thread::spawn(move || {
        let _ = done.send(catch_unwind(AssertUnwindSafe(f)));
    });
    let mut worker = Some(worker);
    let outcome = loop {
        // Back as soon as the worker is done; otherwise look at the signals every
        // 50 ms (with the GIL, which the check needs).
        let wait = std::time::Duration::from_millis(50);
        let (got, back) = py.detach(move || (finished.recv_timeout(wait), finished));
        finished = back;
        match got {
            Ok(result) => break result,
            Err(std::sync::mpsc::RecvTimeoutError::Disconnected) => {
                break Err(Box::new("the worker thread ended without a result")
                    as Box<dyn std::any::Any + Send>)
            }
            Err(std::sync::mpsc::RecvTimeoutError::Timeout) => {}
        }
        match &signal {
            None => {
                if let Err(e) = py.check_signals() {
                    stillpoint::solve::cancel();
                    signal = Some((e, Instant::now()));
                }
            }
            Some((_, since)) if since.elapsed() >= STOP_GRACE => {
                if let Some(w) = worker.take() {
                    abandoned().push(w);
                }
                break Err(Box::new("interrupted") as Box<dyn std::any::Any + Send>);
            }
            Some(_) => {}
        }
    };
    if let Some((e, _)) = signal {
        // The stop request stays set until the next call clears it, so that a worker
        // still running winds down meanwhile.
        return Err(e);
    }
    match outcome {
        Ok(Ok(v)) => Ok(v),
        Ok(Err(message)) => Err(value_error(message)),
        Err(panic) => {
            let what = panic
                .downcast_ref::<String>()
                .cloned()
                .or_else(|| panic.downcast_ref::<&str>().map(|s| s.to_string()))
                .unwrap_or_default();
            Err(PyRuntimeError::new_err(format!(
                "internal error in stillpoint (please report it): {what}"
            )))
        }
    }
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

/// A JSON value as the Python object `json.loads` makes of its text: dicts (keys in the
/// value's order), lists, `str`, `int` (a whole number), `float` (a number written with a
/// fraction or exponent), `bool` and `None`. The library's reports are JSON values; they
/// reach Python as objects, never as text to parse again.
fn py_value<'py>(py: Python<'py>, v: &serde_json::Value) -> PyResult<Bound<'py, PyAny>> {
    use serde_json::Value;
    Ok(match v {
        Value::Null => py.None().into_bound(py),
        Value::Bool(b) => PyBool::new(py, *b).to_owned().into_any(),
        Value::Number(x) => match (x.as_i64(), x.as_u64(), x.as_f64()) {
            (Some(i), _, _) => i.into_pyobject(py)?.into_any(),
            (None, Some(u), _) => u.into_pyobject(py)?.into_any(),
            (None, None, Some(f)) => PyFloat::new(py, f).into_any(),
            (None, None, None) => {
                return Err(PyRuntimeError::new_err(format!("unreadable number {x}")))
            }
        },
        Value::String(text) => PyString::new(py, text).into_any(),
        Value::Array(items) => {
            let items = items
                .iter()
                .map(|x| py_value(py, x))
                .collect::<PyResult<Vec<_>>>()?;
            PyList::new(py, items)?.into_any()
        }
        Value::Object(map) => {
            let dict = PyDict::new(py);
            for (key, x) in map {
                dict.set_item(key, py_value(py, x)?)?;
            }
            dict.into_any()
        }
    })
}

/// A keyword argument as the library's request takes it; `None` means "not given".
/// Only the form is converted here (numbers, text, arrays, lists); what a value means is
/// the library's to decide.
fn arg(key: &str, v: &Bound<'_, PyAny>) -> PyResult<Option<Arg>> {
    let shown = || v.repr().map(|r| r.to_string()).unwrap_or_default();
    if v.is_none() {
        return Ok(None);
    }
    // NumPy's booleans (`numpy.bool_`) are truth values too, never the numbers 0 and 1.
    let numpy_bool = v
        .get_type()
        .name()
        .is_ok_and(|t| t == "bool" || t == "bool_");
    if v.is_instance_of::<PyBool>() || numpy_bool {
        return Ok(Some(Arg::Bool(v.is_truthy()?)));
    }
    if v.is_instance_of::<PyString>() {
        return Ok(Some(Arg::Text(v.extract()?)));
    }
    // A NumPy integer scalar has a shape (`()`) like an array; it is still one integer,
    // and goes through `__index__` exactly (a float would lose bits above 2^53). A 0-d
    // array of floats has `__index__` too, which refuses: it goes on as a number.
    let scalar = !v.hasattr("shape")? || v.getattr("ndim")?.extract::<usize>().ok() == Some(0);
    if v.is_instance_of::<PyInt>() || v.hasattr("__index__")? && scalar {
        match v
            .call_method0("__index__")
            .and_then(|i| i.extract::<i128>())
        {
            Ok(i) => return Ok(Some(Arg::Int(i))),
            // Too large for any count or seed: its digits, which the library refuses
            // with the argument's own range.
            Err(_) if v.is_instance_of::<PyInt>() => {
                return Ok(Some(Arg::Text(v.str()?.to_string())))
            }
            Err(_) => {}
        }
    }
    if v.is_instance_of::<PyFloat>() {
        return Ok(Some(Arg::Float(v.extract()?)));
    }
    if let Ok(a) = v.extract::<PyReadonlyArray2<'_, f64>>() {
        return point_set(key, &a).map(|p| Some(Arg::Points(p)));
    }
    if let Ok(f) = v.extract::<f64>() {
        return Ok(Some(Arg::Float(f)));
    }
    // A pair of sides (bounds' lo and hi, each a number or one per coordinate).
    if let Ok((lo, hi)) = v.extract::<(Bound<'_, PyAny>, Bound<'_, PyAny>)>() {
        let side = |x: &Bound<'_, PyAny>| -> Option<Vec<f64>> {
            x.extract::<f64>()
                .map(|f| vec![f])
                .ok()
                .or_else(|| x.extract::<Vec<f64>>().ok())
        };
        if key == "bounds" {
            if let (Some(lo), Some(hi)) = (side(&lo), side(&hi)) {
                return Ok(Some(Arg::Pair(lo, hi)));
            }
        }
    }
    if let Ok(counts) = v.extract::<Vec<i128>>() {
        return Ok(Some(Arg::Counts(counts)));
    }
    if let Ok(numbers) = v.extract::<Vec<f64>>() {
        return Ok(Some(Arg::Numbers(numbers)));
    }
    if let Ok(texts) = v.extract::<Vec<String>>() {
        return Ok(Some(Arg::Texts(texts)));
    }
    // Pairs [(lo1, hi1), (lo2, hi2), ...], as a box is often written.
    if let Ok(pairs) = v.extract::<Vec<(f64, f64)>>() {
        return Ok(Some(Arg::Numbers(
            pairs.into_iter().flat_map(|(a, b)| [a, b]).collect(),
        )));
    }
    // Rows of numbers of one length (a matrix written as nested lists).
    if let Ok(rows) = v.extract::<Vec<Vec<f64>>>() {
        let width = rows.first().map_or(0, Vec::len);
        if rows.iter().all(|r| r.len() == width) {
            if let Ok(p) = PointSet::new(rows.len(), width, rows.concat()) {
                return Ok(Some(Arg::Points(p)));
            }
        }
    }
    Err(value_error(format!(
        "invalid {key} = {}: expected a number, a string, a list of numbers or an (n, d) \
         array",
        shown()
    )))
}

/// The request of a call: every keyword argument through [`Request::set`], each named by
/// its Python keyword ([`stillpoint::pipeline::options::OPTIONS`]); `names` and
/// `progress` are this front end's own.
fn request(kwargs: Option<&Bound<'_, PyDict>>) -> PyResult<Request> {
    let mut r = Request::default();
    if let Some(dict) = kwargs {
        for (k, v) in dict.iter() {
            let key: String = k.extract()?;
            if key == "names" || key == "progress" {
                continue;
            }
            let declared = declared::by_python(&key).ok_or_else(|| {
                let accepted: Vec<&str> = OPTIONS.iter().filter_map(|d| d.python).collect();
                value_error(format!(
                    "invalid keyword argument = {key}: expected one of {}",
                    accepted.join(", ")
                ))
            })?;
            if let Some(value) = arg(&key, &v)? {
                r.set(declared.name, value)
                    .map_err(|e| value_error(spell_error(e, &HashMap::new())))?;
            }
        }
    }
    Ok(r)
}

/// Python's spelling of a parameter (its keyword argument in the option table), or the
/// caller's own name where a wrapper renames one (`m`, `sizes`).
fn spell(name: &str, renamed: &HashMap<String, String>) -> String {
    match renamed.get(name) {
        Some(r) => r.clone(),
        None => declared::python_name(name),
    }
}

fn spell_error(e: stillpoint::Error, renamed: &HashMap<String, String>) -> String {
    match e {
        stillpoint::Error::InvalidArgument {
            name,
            value,
            expected,
        } => stillpoint::Error::invalid(spell(&name, renamed), value, expected).to_string(),
        other => other.to_string(),
    }
}

/// The resolution of a call's keyword arguments, with Python's names in refusals.
fn resolve(kwargs: Option<&Bound<'_, PyDict>>) -> PyResult<Resolved> {
    let renamed: HashMap<String, String> = match kwargs.map(|d| d.get_item("names")).transpose()? {
        Some(Some(v)) if !v.is_none() => v.extract()?,
        _ => HashMap::new(),
    };
    let r = request(kwargs)?;
    r.resolve_as(&|name| spell(name, &renamed))
        .map_err(|e| value_error(spell_error(e, &renamed)))
}

/// Progress lines on standard error, at most five a second.
struct Progress {
    stage: &'static str,
    steps: Option<u64>,
    last: Option<Instant>,
}

impl Progress {
    fn event(&mut self, e: Event) {
        match e {
            Event::Stage { name, steps } => {
                if self.last.is_some() {
                    eprintln!();
                }
                self.stage = name;
                self.steps = steps;
                self.last = Some(Instant::now());
                eprint!("\rstillpoint: {name}");
            }
            Event::Progress(step) => {
                let due = self.last.is_none_or(|t| t.elapsed().as_secs_f64() >= 0.2);
                if due {
                    self.last = Some(Instant::now());
                    match self.steps {
                        Some(total) => eprint!("\rstillpoint: {} {step}/{total}", self.stage),
                        None => eprint!("\rstillpoint: {} {step}", self.stage),
                    }
                }
            }
            Event::Record(_) => {}
        }
    }

    fn finish(&self) {
        if self.last.is_some() {
            eprintln!();
        }
    }
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
    let progress = match kwargs.map(|d| d.get_item("progress")).transpose()? {
        Some(Some(v)) => v.is_truthy()?,
        _ => false,
    };
    let resolved = resolve(kwargs)?;
    let points = detached(py, move || {
        let mut bar = Progress {
            stage: "",
            steps: None,
            last: None,
        };
        let outcome = resolved.run(None, |e| {
            if progress {
                bar.event(e)
            }
        });
        bar.finish();
        outcome.map(|o| o.points).map_err(|e| e.to_string())
    })?;
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
    let (v, unit) = detached(py, move || {
        let outcome = resolved.run(None, |_| {}).map_err(|e| e.to_string())?;
        let design = outcome
            .design
            .ok_or_else(|| "a design needs space=".to_string())?;
        let written = design.as_written().map_err(|e| e.to_string())?;
        let mut v = design_value(&design, &written);
        v["rule"] = serde_json::json!(resolved.rule.map(|r| r.phrase()));
        v["unbiased"] = serde_json::json!(resolved.rule.is_some_and(|r| r.unbiased()));
        Ok((v, design.unit))
    })?;
    let out = py_value(py, &v)?;
    out.set_item("unit", to_array(py, unit)?)?;
    Ok(out)
}

/// A design space from its `NAME=TYPE` texts and, if given, the continuous variables'
/// correlation (row-major).
fn parsed_space(
    space: &[String],
    correlation: Option<Vec<f64>>,
) -> PyResult<stillpoint::design::DesignSpace> {
    let mut space = stillpoint::design::DesignSpace::parse("space", space).map_err(value_error)?;
    if let Some(m) = correlation {
        let shown = format!("{m:?}");
        space
            .correlate("correlation", &shown, m)
            .map_err(value_error)?;
    }
    Ok(space)
}

/// The figures of a design given as named columns of cells (each value as text: a
/// label, a whole number or a number that reads back to the same float), read back onto
/// the unit scale of `space`, as a dict (a design's `figures`). The cells cross as values,
/// never as one CSV text, so a label holding a comma or a line break is a label, not a
/// new cell or row.
#[pyfunction]
#[pyo3(signature = (space, columns, correlation=None))]
fn design_figures<'py>(
    py: Python<'py>,
    space: Vec<String>,
    columns: Vec<(String, Vec<String>)>,
    correlation: Option<Vec<f64>>,
) -> PyResult<Bound<'py, PyAny>> {
    let space = parsed_space(&space, correlation)?;
    let v = detached(py, move || {
        let design = stillpoint::design::Design::from_columns(&space, &columns, "table")
            .map_err(|e| e.to_string())?;
        serde_json::to_value(stillpoint::design::figures::DesignFigures::of(&design))
            .map_err(|e| e.to_string())
    })?;
    py_value(py, &v)
}

/// The column names of `space` in order, one per coordinate (a path `W=brownian(1,64)`
/// gives `W_1` … `W_64`): its dimension and where each variable's values are.
#[pyfunction]
fn space_names(space: Vec<String>) -> PyResult<Vec<String>> {
    let space = parsed_space(&space, None)?;
    Ok(space.vars.into_iter().map(|v| v.name).collect())
}

/// Points of the unit cube mapped to the values of `space`, one row per point: each
/// continuous variable through the copula (if any) and its marginal's quantile function,
/// each discrete one to its level floor(u·L) (levels equally likely; a label as its index
/// in the list). Integrating over the unit cube after this map is the expectation under
/// the space's distributions.
#[pyfunction]
#[pyo3(signature = (space, x, correlation=None))]
fn space_values<'py>(
    py: Python<'py>,
    space: Vec<String>,
    x: PyReadonlyArray2<'py, f64>,
    correlation: Option<Vec<f64>>,
) -> PyResult<Bound<'py, PyArray2<f64>>> {
    let space = parsed_space(&space, correlation)?;
    let unit = unit_points("x", &x)?;
    if unit.s() != space.dim() {
        return Err(value_error(format!(
            "x: {} coordinates per point; expected one per variable of space ({})",
            unit.s(),
            space.dim()
        )));
    }
    let design = stillpoint::pipeline::measure::mapped(&space, &unit).map_err(value_error)?;
    to_array(py, design.numbers().map_err(value_error)?)
}

/// A design as a JSON value (all but its unit-scale set), its figures those of `written`
/// (the design as its values are written and read back, which a report describes).
fn design_value(
    design: &stillpoint::design::Design,
    written: &stillpoint::design::Design,
) -> serde_json::Value {
    use stillpoint::design::Column;
    let columns: Vec<serde_json::Value> = design
        .columns()
        .into_iter()
        .map(|c| match c {
            Column::Real(v) => serde_json::json!(v),
            Column::Int(v) => serde_json::json!(v),
            Column::Label(v) => serde_json::json!(v),
        })
        .collect();
    serde_json::json!({
        "space": design.space.texts(),
        "correlation": design.space.correlation_text(),
        "names": design.space.vars.iter().map(|v| v.name.clone()).collect::<Vec<_>>(),
        "columns": columns,
        "figures": stillpoint::design::figures::DesignFigures::of(written),
    })
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
        stillpoint::goals::integration::tent::tent_set(n, d)
            .map(|t| t.points)
            .map_err(|e| e.to_string())
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
    let unbounded = parsed_space(&space, None)?.unbounded();
    let points = detached(py, move || {
        stillpoint::sequences::law_lattice(n, &unbounded, seed).map_err(|e| e.to_string())
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
    resolve(kwargs).map(|r| r.unusual_as(&declared::python_name))
}

/// The library's note before a run it estimates above its long-run threshold (the same
/// rule and words as the command line's), `None` below it.
#[pyfunction]
#[pyo3(signature = (**kwargs))]
fn long_run_note(kwargs: Option<&Bound<'_, PyDict>>) -> PyResult<Option<String>> {
    resolve(kwargs).map(|r| r.long_run_note_as(&declared::python_name))
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
    let p = unit_points("x", &x)?;
    let kind = stillpoint::post::randomize::Randomize::parse(kind)
        .map_err(|e| value_error(e.to_string()))?;
    let points = detached(py, move || {
        Ok(stillpoint::post::randomize::randomize(&p, kind, seed))
    })?;
    to_array(py, points)
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
    let none = HashMap::new();
    let measure = request(kwargs)?
        .resolve_eval_as(&|n| spell(n, &none))
        .map_err(|e| value_error(spell_error(e, &none)))?;
    let p = point_set("x", &x)?;
    detached(py, move || {
        let spell = |n: &str| spell(n, &HashMap::new());
        let p = measure
            .unit_points(p, "x", &spell)
            .map_err(|e| spell_error(e, &HashMap::new()))?;
        if let stillpoint::pipeline::evaluation::Measure::Cube { .. } = measure {
            p.check_unit_cube().map_err(|e| format!("x: {e}"))?;
        }
        measure
            .json(&p, &spell)
            .map_err(|e| spell_error(e, &HashMap::new()))
    })
    .and_then(|v| py_value(py, &v))
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
    let v = detached(py, move || {
        stillpoint::quality::integrands::report_json(&p).map_err(|e| e.to_string())
    })?;
    py_value(py, &v)
}

/// Every option as declared once in the library, a list of dicts: `name` (the
/// library's), `cli` (the command line's flag, empty where it has none), `python` (the
/// keyword argument, `None` where Python has none), `doc` (one line), `groups`,
/// `commands`, `kind` (with `min`, `max`, `closed`, `below` for numbers), `words` (every
/// word it accepts), `expected` (what a refusal says is accepted) and `default` (per
/// command, as help shows it). Those of `generate` and `eval` by default; `command`
/// (`quad`, `sensitivity`, ...) gives that command's.
#[pyfunction]
#[pyo3(signature = (command=None))]
fn options<'py>(py: Python<'py>, command: Option<&str>) -> PyResult<Vec<Bound<'py, PyDict>>> {
    use declared::{Command, Kind, ALL};
    let among: Vec<&declared::Declared> = match command {
        None => OPTIONS.iter().collect(),
        Some(name) => {
            let c = Command::ALL
                .into_iter()
                .find(|c| c.name() == name)
                .ok_or_else(|| {
                    let names: Vec<&str> = Command::ALL.iter().map(|c| c.name()).collect();
                    value_error(format!(
                        "invalid command = {name}: expected {}",
                        names.join(", ")
                    ))
                })?;
            ALL.iter().filter(|d| d.takes(c)).collect()
        }
    };
    among
        .into_iter()
        .map(|d| {
            let row = PyDict::new(py);
            row.set_item("name", d.name)?;
            row.set_item("cli", d.cli)?;
            row.set_item("python", d.python)?;
            row.set_item("doc", d.doc)?;
            let groups: Vec<&str> = d.groups.iter().map(|g| g.name()).collect();
            row.set_item("groups", groups)?;
            let commands: Vec<&str> = d.commands.iter().map(|c| c.name()).collect();
            row.set_item("commands", commands)?;
            let kind = match d.kind {
                Kind::Count { min, max } => {
                    row.set_item("min", min)?;
                    row.set_item("max", max)?;
                    "count"
                }
                Kind::Real { min, closed, below } => {
                    row.set_item("min", min)?;
                    row.set_item("closed", closed)?;
                    row.set_item("below", below)?;
                    "real"
                }
                Kind::RealOrWord { min, closed, .. } => {
                    row.set_item("min", min)?;
                    row.set_item("closed", closed)?;
                    "real_or_word"
                }
                Kind::Seed => "seed",
                Kind::Flag => "flag",
                Kind::Word(_) => "word",
                Kind::Numbers | Kind::Bounds => "numbers",
                Kind::Sizes => "sizes",
                Kind::Points => "points",
                Kind::WordOrPoints(_) => "word_or_points",
                Kind::Text => "text",
                Kind::Texts { .. } => "texts",
                Kind::Rows => "rows",
                Kind::FrontEnd => "front_end",
            };
            row.set_item("kind", kind)?;
            row.set_item("words", d.words())?;
            row.set_item("expected", (d.expected)())?;
            let defaults = PyDict::new(py);
            for c in d.commands {
                defaults.set_item(c.name(), (d.default)(*c))?;
            }
            row.set_item("default", defaults)?;
            Ok(row)
        })
        .collect()
}

/// The extension module.
#[pymodule]
fn _core(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add("SEQUENCE_MAX_D", stillpoint::sequences::EXTENSIBLE_MAX_D)?;
    m.add_function(wrap_pyfunction!(generate, m)?)?;
    m.add_function(wrap_pyfunction!(check_generate, m)?)?;
    m.add_function(wrap_pyfunction!(design, m)?)?;
    m.add_function(wrap_pyfunction!(design_figures, m)?)?;
    m.add_function(wrap_pyfunction!(space_values, m)?)?;
    m.add_function(wrap_pyfunction!(space_names, m)?)?;
    m.add_function(wrap_pyfunction!(estimate, m)?)?;
    m.add_function(wrap_pyfunction!(notes, m)?)?;
    m.add_function(wrap_pyfunction!(long_run_note, m)?)?;
    m.add_function(wrap_pyfunction!(discrepancy, m)?)?;
    m.add_function(wrap_pyfunction!(baselines, m)?)?;
    m.add_function(wrap_pyfunction!(integrate, m)?)?;
    m.add_function(wrap_pyfunction!(randomize, m)?)?;
    m.add_function(wrap_pyfunction!(tent_set, m)?)?;
    m.add_function(wrap_pyfunction!(law_set, m)?)?;
    m.add_function(wrap_pyfunction!(options, m)?)?;
    m.add_function(wrap_pyfunction!(metrics, m)?)?;
    drivers::register(m)?;
    Ok(())
}
