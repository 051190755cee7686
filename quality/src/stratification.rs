//! Stratification: whether every coordinate has one point in each [k/n, (k+1)/n).

use crate::PointSet;

/// The cell of coordinate value `x` among n: ⌊x·n⌋ in f64 arithmetic (what
/// `numpy.floor(x * n)` gives), clamped to n − 1.
pub fn cell_of(x: f64, n: usize) -> usize {
    ((x * n as f64).floor().max(0.0) as usize).min(n.saturating_sub(1))
}

/// Whether every coordinate of `points` lies in [0, 1) and each column has exactly one
/// point in each cell [c/n, (c+1)/n) (as [`cell_of`] computes the cell).
///
/// One pass over the points in the order they are stored, a bit per cell and column:
/// column by column the reads are n·s strides of a row apart (at 2·10⁵ × 50 the check
/// cost a quarter as much as the report's estimated figures).
pub fn is_stratified(points: &PointSet) -> bool {
    let (n, s) = (points.n(), points.s());
    let mut seen = vec![0u64; (n * s).div_ceil(64)];
    points.rows().all(|row| {
        row.iter().enumerate().all(|(k, &v)| {
            if !(0.0..1.0).contains(&v) {
                return false;
            }
            let bit = k * n + cell_of(v, n);
            let (word, mask) = (bit / 64, 1u64 << (bit % 64));
            let fresh = (seen[word] & mask) == 0;
            seen[word] |= mask;
            fresh
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_column_with_two_points_in_a_cell_or_one_outside_is_not_stratified() {
        // Columns: a permutation of the cells, then the same with one cell taken twice.
        let n = 7;
        let good: Vec<f64> = (0..n).map(|i| in_cell((3 * i) % n, 0.5, n)).collect();
        let p = |cols: &[&[f64]]| {
            let data = (0..n)
                .flat_map(|i| cols.iter().map(move |c| c[i]))
                .collect();
            PointSet::new(n, cols.len(), data).unwrap()
        };
        assert!(is_stratified(&p(&[&good, &good])));
        let mut twice = good.clone();
        twice[4] = in_cell(cell_of(good[2], n), 0.1, n);
        assert!(!is_stratified(&p(&[&good, &twice])));
        assert!(!is_stratified(&p(&[&twice, &good])));
        let mut outside = good.clone();
        outside[0] = 1.0;
        assert!(!is_stratified(&p(&[&good, &outside])));
    }
}
