//! Potential energies for the stillpoint many-body model.
//!
//! An [`Energy`] is a potential over a whole [`PointSet`] with its gradient; the
//! integrators drive a set to a minimum of one. The geometry (point sets, the periodic
//! cube, implicit regions, shapes, the error type) lives in `stillpoint-domains` and is
//! re-exported here under its old paths ([`PointSet`], [`Domain`], [`PeriodicCube`],
//! [`Error`], [`Result`], [`region`], [`shapes`]).
//!
//! Equation numbers refer to Wu, Zhao, Zhao and Zhong (2021), *Relationship between
//! low-discrepancy sequence and static solution to multi-bodies problem*.

#![deny(missing_docs)]

pub mod boundary;
pub mod discrepancy;
pub mod einf;
pub mod energy_distance;
pub mod fixed;
pub mod pairs;
pub mod report_pairs;
pub mod stop;
pub mod tent_kernel;
mod uqp;

pub use stillpoint_domains::{region, shapes};
pub use stillpoint_domains::{Domain, Error, PeriodicCube, PointSet, Result};
pub use uqp::{paper_qp, Distance, PaperQp, Precision, Uqp};

/// A potential energy over a whole point set.
///
/// Implementations must be deterministic: the same points give the same bits whatever
/// the number of rayon threads (fixed-order reductions).
pub trait Energy: Send + Sync {
    /// Short name with parameters, e.g. `U_{q,p}(q=0.3, p=0.8)`.
    fn name(&self) -> String;

    /// Energy of the set.
    fn value(&self, points: &PointSet) -> f64;

    /// Energy of the set, with its gradient (or a subgradient where the energy is not
    /// differentiable) written into `grad`, laid out like the points (row per point).
    ///
    /// `grad.len()` must equal `points.coordinate_count()` (n·s).
    fn value_and_gradient(&self, points: &PointSet, grad: &mut [f64]) -> f64;

    /// Whether the energy is differentiable away from coincident points. Integrators use
    /// it to judge a trial run: a max-type energy (U_{E,∞}) need not fall at every step
    /// even when the scheme is stable.
    fn is_smooth(&self) -> bool {
        true
    }

    /// The domain this energy is defined on, for an energy that holds its own (the
    /// boundary-aware energies measure distances to that domain's boundary). A
    /// `Problem` built from such an energy must use this domain.
    fn domain(&self) -> Option<std::sync::Arc<dyn Domain>> {
        None
    }
}

impl<E: Energy + ?Sized> Energy for &E {
    fn name(&self) -> String {
        (**self).name()
    }
    fn value(&self, points: &PointSet) -> f64 {
        (**self).value(points)
    }
    fn value_and_gradient(&self, points: &PointSet, grad: &mut [f64]) -> f64 {
        (**self).value_and_gradient(points, grad)
    }
    fn is_smooth(&self) -> bool {
        (**self).is_smooth()
    }
    fn domain(&self) -> Option<std::sync::Arc<dyn Domain>> {
        (**self).domain()
    }
}

impl<E: Energy + ?Sized> Energy for Box<E> {
    fn name(&self) -> String {
        (**self).name()
    }
    fn value(&self, points: &PointSet) -> f64 {
        (**self).value(points)
    }
    fn value_and_gradient(&self, points: &PointSet, grad: &mut [f64]) -> f64 {
        (**self).value_and_gradient(points, grad)
    }
    fn is_smooth(&self) -> bool {
        (**self).is_smooth()
    }
    fn domain(&self) -> Option<std::sync::Arc<dyn Domain>> {
        (**self).domain()
    }
}
