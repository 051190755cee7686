//! Integration to a tolerance for Python: the library's `Cubature` state machine as a
//! class (the Python side evaluates f on each batch, in one process or on an executor),
//! and the extensible randomised lattice sequence's points by index.

use numpy::ndarray::Array2;
use numpy::{IntoPyArray, PyArray2, PyReadonlyArray2};
use pyo3::prelude::*;
use pyo3::types::PyBytes;

use stillpoint::cubature::{Cubature, QuadOptions};
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
    #[pyo3(signature = (d, abs_tol=0.0, rel_tol=1e-3, level=0.95, replicates=8,
                        max_n=1u64 << 20, start_n=64, seed=0, a=None, b=None))]
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
    ) -> PyResult<Self> {
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
        };
        let inner = Cubature::new(d, options).map_err(value_error)?;
        Ok(PyCubature { inner, batch: None })
    }

    /// The next batch of points as an (R·m, d) array, replicate after replicate (asking
    /// again before `feed` gives the same batch); None when the budget is spent.
    fn next_points<'py>(&mut self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyArray2<f64>>>> {
        let Some(points) = self.inner.next_points() else {
            return Ok(None);
        };
        self.batch = Some(points.clone());
        to_array(py, points).map(Some)
    }

    /// f's values at the batch of `next_points()`, an (n, k) array; refuses NaN or ±∞
    /// naming the point, and values without a batch handed out.
    fn feed(&mut self, values: PyReadonlyArray2<'_, f64>) -> PyResult<()> {
        if self.batch.is_none() && self.inner.pending() > 0 {
            self.batch = self.inner.next_points();
        }
        let Some(points) = self.batch.as_ref() else {
            return Err(value_error(
                "feed: no batch is pending; call next_points() first",
            ));
        };
        let v: Vec<f64> = values.as_array().iter().copied().collect();
        self.inner.feed(points, &v).map_err(value_error)?;
        self.batch = None;
        Ok(())
    }

    /// New tolerances; the evaluations made are kept.
    fn set_tolerance(&mut self, abs_tol: f64, rel_tol: f64) -> PyResult<()> {
        self.inner
            .set_tolerance(abs_tol, rel_tol)
            .map_err(value_error)
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
        let bytes = serde_json::to_vec(&self.inner).map_err(value_error)?;
        Ok(PyBytes::new(py, &bytes))
    }

    fn __setstate__(&mut self, state: &[u8]) -> PyResult<()> {
        self.inner = serde_json::from_slice(state).map_err(value_error)?;
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
