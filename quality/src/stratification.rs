//! Stratification: whether every coordinate has one point in each [k/n, (k+1)/n).

use crate::PointSet;

/// The cell of coordinate value `x` among n: ⌊x·n⌋ in f64 arithmetic (what
/// `numpy.floor(x * n)` gives), clamped to n − 1.
pub fn cell_of(x: f64, n: usize) -> usize {
    ((x * n as f64).floor().max(0.0) as usize).min(n.saturating_sub(1))
}

/// Whether every coordinate of `points` lies in [0, 1) and each column has exactly one
/// point in each cell [c/n, (c+1)/n) (as [`cell_of`] computes the cell).
pub fn is_stratified(points: &PointSet) -> bool {
    let (n, s) = (points.n(), points.s());
    let x = points.as_slice();
    (0..s).all(|k| {
        let mut seen = vec![false; n];
        (0..n).all(|i| {
            let v = x[i * s + k];
            if !(0.0..1.0).contains(&v) {
                return false;
            }
            let c = cell_of(v, n);
            !std::mem::replace(&mut seen[c], true)
        })
    })
}

/// The value (c + u)/n, moved by the last bits if rounding put it in a neighbouring cell,
/// so that [`cell_of`] gives exactly c.
pub fn in_cell(c: usize, u: f64, n: usize) -> f64 {
    let mut x = (c as f64 + u.clamp(0.0, 1.0)) / n as f64;
    for _ in 0..64 {
        match cell_of(x, n).cmp(&c) {
            std::cmp::Ordering::Greater => x = f64::from_bits(x.to_bits() - 1),
            std::cmp::Ordering::Less => x = f64::from_bits(x.to_bits() + 1),
            std::cmp::Ordering::Equal => break,
        }
    }
    x
}
