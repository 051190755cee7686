//! Fixed points: points that take part in an energy but never move. A set that grows
//! keeps its old points where they are while the new ones settle among them; wrapping the
//! energy is enough for every integrator, which then sees (and moves) only the new points.

use crate::{Energy, PointSet};
use std::sync::Arc;

/// `inner` evaluated on the fixed points followed by the moving ones; the gradient is
/// that of the moving points only.
pub struct WithFixed {
    inner: Arc<dyn Energy>,
    fixed: PointSet,
}

impl WithFixed {
    /// The energy `inner` of `fixed` ∪ (the points it is given).
    pub fn new(inner: Arc<dyn Energy>, fixed: PointSet) -> WithFixed {
        WithFixed { inner, fixed }
    }

    /// The fixed points followed by `moving`.
    pub fn union(&self, moving: &PointSet) -> PointSet {
        let mut data = self.fixed.as_slice().to_vec();
        data.extend_from_slice(moving.as_slice());
        PointSet::new(self.fixed.n() + moving.n(), moving.s(), data)
            .expect("fixed and moving points share the dimension")
    }
}

impl Energy for WithFixed {
    fn name(&self) -> String {
        format!("{} with {} fixed points", self.inner.name(), self.fixed.n())
    }

    fn value(&self, points: &PointSet) -> f64 {
        self.inner.value(&self.union(points))
    }

    fn value_and_gradient(&self, points: &PointSet, grad: &mut [f64]) -> f64 {
        let union = self.union(points);
        let mut full = vec![0.0; union.as_slice().len()];
        let v = self.inner.value_and_gradient(&union, &mut full);
        grad.copy_from_slice(&full[self.fixed.as_slice().len()..]);
        v
    }

    fn is_smooth(&self) -> bool {
        self.inner.is_smooth()
    }

    fn domain(&self) -> Option<Arc<dyn crate::Domain>> {
        self.inner.domain()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::discrepancy::{DiscrepancyEnergy, DiscrepancyKind};

    #[test]
    fn gradient_is_the_moving_rows_of_the_union_gradient() {
        let fixed = PointSet::from_rows(&[[0.1, 0.2], [0.7, 0.9]]).unwrap();
        let moving = PointSet::from_rows(&[[0.4, 0.5], [0.8, 0.3], [0.25, 0.65]]).unwrap();
        let inner: Arc<dyn Energy> = Arc::new(DiscrepancyEnergy::new(DiscrepancyKind::ModifiedL2));
        let e = WithFixed::new(inner.clone(), fixed);
        let union = e.union(&moving);
        let mut g_union = vec![0.0; union.as_slice().len()];
        let v_union = inner.value_and_gradient(&union, &mut g_union);
        let mut g = vec![0.0; moving.as_slice().len()];
        assert_eq!(e.value_and_gradient(&moving, &mut g), v_union);
        assert_eq!(&g[..], &g_union[4..]);
        // And a finite difference of the wrapped energy agrees.
        let h = 1e-6;
        let mut bumped = moving.clone();
        bumped.as_mut_slice()[3] += h;
        let fd = (e.value(&bumped) - e.value(&moving)) / h;
        assert!(
            (fd - g[3]).abs() < 1e-4 * g[3].abs().max(1e-3),
            "{fd} vs {}",
            g[3]
        );
    }
}
