//! Integration to a tolerance for Python: the library's `Cubature` state machine as a
//! class (the Python side evaluates f on each batch, in one process or on an executor),
//! and the extensible randomised lattice sequence's points by index.

use numpy::ndarray::Array2;
use numpy::{IntoPyArray, PyArray2, PyReadonlyArray2};
use pyo3::prelude::*;
use pyo3::types::PyBytes;

use stillpoint::cubature::{Cubature, QuadOptions, Rounds, Rule, StopReason};
use stillpoint::design::DesignSpace;
use stillpoint::sequences::ExtensibleLattice;
use stillpoint::PointSet;

use super::{to_array, value_error};

/// The state of an integration to a tolerance: `next_points()` gives the next batch
/// (all replicates, the next doubling; None when max_n would be passed), `feed(values)`
/// takes f's values there as an (n, k) array; `estimate`, `half_width`, `met` say where
/// it stands. Picklable; `set_tolerance` continues with a tighter tolerance without
/// evaluating again.
#[pyclass(name = "Cubature", module = "stillpoint._core")]
pub(crate) struct PyCubature {
    inner: Cubature,
    /// The batch handed out and not yet fed (not pickled: it is made again).
    batch: Option<PointSet>,
}

#[pymethods]
impl PyCubature {
    #[new]
    #[pyo3(signature = (d, abs_tol=0.0, rel_tol=1e-3, level=0.95, replicates=4,
                        max_n=1u64 << 20, start_n=64, seed=0, a=None, b=None,
                        rule="lattice", rule_reason=String::new()))]
    #[allow(clippy::too_many_arguments)]
    fn new(
        d: usize,
        abs_tol: f64,
        rel_tol: f64,
        level: f64,
        replicates: usize,
        max_n: u64,
        start_n: u64,
        seed: u64,
        a: Option<Vec<f64>>,
        b: Option<Vec<f64>>,
        rule: &str,
        rule_reason: String,
    ) -> PyResult<Self> {
        let rule = Rule::parse("rule", rule).map_err(value_error)?;
        let options = QuadOptions {
            a,
            b,
            abs_tol,
            rel_tol,
            level,
            replicates,
            max_n,
            start_n,
            seed,
            rule,
            rule_reason,
        };
        let inner = Cubature::new(d, options).map_err(value_error)?;
        Ok(PyCubature { inner, batch: None })
    }

    /// The next batch of points as an (R·m, d) array, replicate after replicate (asking
    /// again before `feed` gives the same batch); None when the budget is spent.
    fn next_points<'py>(&mut self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyArray2<f64>>>> {
        hand_out(py, &mut self.batch, self.inner.next_points())
    }

    /// f's values at the batch of `next_points()`, an (n, k) array; refuses NaN or ±∞
    /// naming the point, and values without a batch handed out.
    fn feed(&mut self, values: PyReadonlyArray2<'_, f64>) -> PyResult<()> {
        take_values(&mut self.inner, &mut self.batch, values)
    }

    /// New tolerances; the evaluations made are kept.
    fn set_tolerance(&mut self, abs_tol: f64, rel_tol: f64) -> PyResult<()> {
        self.inner
            .set_tolerance(abs_tol, rel_tol)
            .map_err(value_error)
    }

    /// Refuses an estimate or half-width beyond the largest float (where the run stops).
    fn check_representable(&self) -> PyResult<()> {
        self.inner.check_representable().map_err(value_error)
    }

    /// A new budget (a larger one continues a run stopped by max_n).
    fn set_max_n(&mut self, max_n: u64) -> PyResult<()> {
        self.inner.set_max_n(max_n).map_err(value_error)
    }

    /// A new confidence level (the half-width is recomputed).
    fn set_level(&mut self, level: f64) -> PyResult<()> {
        self.inner.set_level(level).map_err(value_error)
    }

    /// Why the run stops here: "met", "max_n" or "sequence" (the sequence's 2^20
    /// points per replicate); None while another doubling may be made.
    #[getter]
    fn reason(&self) -> Option<&'static str> {
        self.inner.reason().map(StopReason::as_str)
    }

    /// (abs_tol, rel_tol, level, replicates, max_n, seed).
    #[getter]
    fn settings(&self) -> (f64, f64, f64, usize, u64, u64) {
        let o = self.inner.options();
        (o.abs_tol, o.rel_tol, o.level, o.replicates, o.max_n, o.seed)
    }

    /// The rule evaluated, "lattice" or "sobol", and why it was chosen.
    #[getter]
    fn rule(&self) -> (&'static str, String) {
        let o = self.inner.options();
        (o.rule.as_str(), o.rule_reason.clone())
    }

    /// Per output, the change of the estimate since half the points (the round guard
    /// under the half-width), None before it exists.
    #[getter]
    fn round_change(&self) -> Vec<Option<f64>> {
        self.inner.round_change()
    }

    /// The estimate of each output's integral.
    #[getter]
    fn estimate(&self) -> Vec<f64> {
        self.inner.estimate()
    }

    /// The half-width of each output's interval.
    #[getter]
    fn half_width(&self) -> Vec<f64> {
        self.inner.half_width()
    }

    /// Evaluations of f so far.
    #[getter]
    fn n(&self) -> u64 {
        self.inner.n()
    }

    /// Independent shifts R.
    #[getter]
    fn replicates(&self) -> usize {
        self.inner.options().replicates
    }

    /// The dimension d.
    #[getter]
    fn d(&self) -> usize {
        self.inner.d()
    }

    /// Outputs of f (0 before the first values).
    #[getter]
    fn outputs(&self) -> usize {
        self.inner.outputs()
    }

    /// Whether every output met the tolerance.
    #[getter]
    fn met(&self) -> bool {
        self.inner.met()
    }

    /// Whether the next doubling would pass max_n.
    #[getter]
    fn exhausted(&self) -> bool {
        self.inner.exhausted()
    }

    /// Warnings about the settings (too few replicates for the level).
    #[getter]
    fn warnings(&self) -> Vec<String> {
        self.inner.warnings()
    }

    /// Per output, the R replicate means.
    #[getter]
    fn replicate_means(&self) -> Vec<Vec<f64>> {
        self.inner.replicate_means()
    }

    fn __getnewargs__(&self) -> (usize,) {
        (self.inner.d(),)
    }

    fn __getstate__<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyBytes>> {
        pickled(py, &self.inner)
    }

    fn __setstate__(&mut self, state: &[u8]) -> PyResult<()> {
        self.inner = unpickled(state)?;
        self.batch = None;
        Ok(())
    }
}

/// Points [start, start + count) of replicate `replicate` of the extensible randomised
/// lattice sequence in d dimensions seeded by `seed`, as a (count, d) array.
#[pyfunction]
#[pyo3(signature = (d, seed=0, replicate=0, start=0, count=1))]
pub(crate) fn sequence_points<'py>(
    py: Python<'py>,
    d: usize,
    seed: u64,
    replicate: u64,
    start: u64,
    count: usize,
) -> PyResult<Bound<'py, PyArray2<f64>>> {
    let seq = ExtensibleLattice::new(d, seed, replicate).map_err(value_error)?;
    let mut data = vec![0.0; count * d];
    seq.fill(start, count, &mut data).map_err(value_error)?;
    let a = Array2::from_shape_vec((count, d), data).map_err(value_error)?;
    Ok(a.into_pyarray(py))
}

/// Refuses a box as every front end does (`plan::space::intervals`): `values` are
/// LO1,HI1,...; `name` and `shown` are the arguments and their values as typed.
#[pyfunction]
pub(crate) fn check_box(name: &str, shown: &str, values: Vec<f64>) -> PyResult<()> {
    stillpoint::plan::space::intervals(name, shown, &values).map_err(value_error)?;
    Ok(())
}

/// Checks a quad space as design checks its space (its variables, the vanishing-scale
/// check of `stillpoint::cubature::check_space`, the correlation as text `1,0.5;0.5,1` or
/// as a row-major matrix) and returns the correlation matrix, row-major, if any, and the
/// rule for its laws with why (`Rule::for_space`).
#[pyfunction]
#[pyo3(signature = (space, text=None, matrix=None))]
pub(crate) fn quad_space(
    space: Vec<String>,
    text: Option<String>,
    matrix: Option<Vec<f64>>,
) -> PyResult<(Option<Vec<f64>>, &'static str, String)> {
    let mut parsed = DesignSpace::parse("space", &space).map_err(value_error)?;
    stillpoint::cubature::check_space(&parsed, "space").map_err(value_error)?;
    match (text, matrix) {
        (Some(text), _) => parsed.correlate_rows("correlation", &text),
        (None, Some(m)) => parsed.correlate("correlation", &format!("{m:?}"), m),
        (None, None) => Ok(()),
    }
    .map_err(value_error)?;
    let (rule, why) = Rule::for_space(Some(&parsed));
    Ok((parsed.copula.map(|c| c.matrix), rule.as_str(), why))
}

/// The rule quad takes without a space (the cube or a box), and why.
#[pyfunction]
pub(crate) fn quad_box_rule() -> (&'static str, String) {
    let (rule, why) = Rule::for_space(None);
    (rule.as_str(), why)
}

/// Hands out a driver's next batch (`next`), keeping it as the one `feed` expects.
pub(crate) fn hand_out<'py>(
    py: Python<'py>,
    batch: &mut Option<PointSet>,
    next: Option<PointSet>,
) -> PyResult<Option<Bound<'py, PyArray2<f64>>>> {
    let Some(points) = next else {
        return Ok(None);
    };
    *batch = Some(points.clone());
    to_array(py, points).map(Some)
}

/// Feeds f's values at the batch handed out. A driver restored from a pickle has no batch
/// kept (it is not pickled), so the pending one is made again first.
pub(crate) fn take_values(
    driver: &mut impl Rounds,
    batch: &mut Option<PointSet>,
    values: PyReadonlyArray2<'_, f64>,
) -> PyResult<()> {
    if batch.is_none() && driver.pending() > 0 {
        *batch = driver.next_points();
    }
    let Some(points) = batch.as_ref() else {
        return Err(value_error(
            "feed: no batch is pending; call next_points() first",
        ));
    };
    let v: Vec<f64> = values.as_array().iter().copied().collect();
    driver.feed(points, &v).map_err(value_error)?;
    *batch = None;
    Ok(())
}

/// A driver's state as a pickle's bytes (JSON: readable by later versions).
pub(crate) fn pickled<'py>(
    py: Python<'py>,
    state: &impl serde::Serialize,
) -> PyResult<Bound<'py, PyBytes>> {
    let bytes = serde_json::to_vec(state).map_err(value_error)?;
    Ok(PyBytes::new(py, &bytes))
}

/// A driver's state from the bytes of [`pickled`].
pub(crate) fn unpickled<T: serde::de::DeserializeOwned>(state: &[u8]) -> PyResult<T> {
    serde_json::from_slice(state).map_err(value_error)
}
