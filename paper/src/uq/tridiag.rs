//! The few lowest eigenvalues of a real symmetric tridiagonal matrix, for the shear frame's
//! millions of small eigenproblems: Newton's method on det(T − λI) from caller-supplied
//! guesses, checked by Sturm counts, with Sturm bisection as the fallback that always
//! works.

/// A Newton step is accepted as the last one when it is this small relative to λ: with
/// quadratic convergence the next error would be far below one ulp.
const NEWTON_DONE: f64 = 1e-10;

/// Sturm count (eigenvalues of T below x) and the Newton step p_n(x)/p_n'(x) for the
/// characteristic polynomial p_n(x) = det(T − xI).
///
/// Uses the three-term recurrence p_i = (d_i − x) p_{i−1} − e²_{i−1} p_{i−2}, which has no
/// division (the LDLᵀ pivot form divides at every row and is several times slower); the
/// pair (p, p') is rescaled when it drifts toward overflow or underflow, which changes
/// neither the signs nor the ratio. An exact zero p_i would lose the sign information of
/// the rows below it (with a zero off-diagonal every later p_i is 0), so it is replaced by
/// −tiny·p_{i−1}: the pivot p_i/p_{i−1} becomes −tiny, as LAPACK's dstebz does.
#[inline]
pub(crate) fn sturm(d: &[f64], e2: &[f64], x: f64, tiny: f64) -> (usize, f64) {
    const BIG: f64 = 1e150;
    const SMALL: f64 = 1e-150;
    let mut pp = 1.0;
    let mut dpp = 0.0;
    let mut p = d[0] - x;
    if p == 0.0 {
        p = -tiny;
    }
    let mut dp = -1.0;
    let mut count = (p < 0.0) as usize;
    for i in 1..d.len() {
        let a = d[i] - x;
        let pn = a * p - e2[i - 1] * pp;
        let dpn = a * dp - p - e2[i - 1] * dpp;
        pp = p;
        dpp = dp;
        p = pn;
        dp = dpn;
        let size = p.abs().max(pp.abs());
        if !(SMALL..=BIG).contains(&size) || p == 0.0 {
            // pp is never 0 here: a zero p is replaced below before it becomes pp.
            let f = 1.0 / pp.abs().max(p.abs());
            p *= f;
            pp *= f;
            dp *= f;
            dpp *= f;
            if p == 0.0 {
                p = -tiny * pp;
            }
        }
        count += ((p < 0.0) != (pp < 0.0)) as usize;
    }
    (count, p / dp)
}

/// Brackets of the wanted eigenvalues: λ_{r+1} lies in (lo[r], hi[r]], with clo[r] and
/// chi[r] eigenvalues below the two ends. Scratch slices, one entry per wanted eigenvalue.
pub(crate) struct Brackets<'a> {
    pub(crate) lo: &'a mut [f64],
    pub(crate) clo: &'a mut [usize],
    pub(crate) hi: &'a mut [f64],
    pub(crate) chi: &'a mut [usize],
}

impl Brackets<'_> {
    /// Every count tightens every bracket it bounds, so work on one eigenvalue helps the
    /// others.
    #[inline]
    fn record(&mut self, x: f64, c: usize) {
        for r in 0..self.lo.len() {
            if c <= r {
                if x > self.lo[r] {
                    self.lo[r] = x;
                    self.clo[r] = c;
                }
            } else if x < self.hi[r] {
                self.hi[r] = x;
                self.chi[r] = c;
            }
        }
    }
}

/// Newton from x for eigenvalue r, kept inside its bracket (bisection when a step leaves
/// it). Returns the root and whether the iteration converged.
fn newton(
    d: &[f64],
    e2: &[f64],
    r: usize,
    mut x: f64,
    b: &mut Brackets<'_>,
    tiny: f64,
) -> (f64, bool) {
    for _ in 0..100 {
        let (c, step) = sturm(d, e2, x, tiny);
        b.record(x, c);
        let (lo, hi) = (b.lo[r], b.hi[r]);
        if hi - lo <= 4.0 * f64::EPSILON * lo.abs().max(hi.abs()) + tiny {
            return (0.5 * (lo + hi), true);
        }
        let mut next = x - step;
        let newton_ok = next > lo && next < hi;
        if !newton_ok {
            next = 0.5 * (lo + hi);
        }
        if newton_ok && step.abs() <= NEWTON_DONE * x.abs() + tiny {
            return (next, true);
        }
        x = next;
    }
    (x, false)
}

/// The `out.len()` smallest eigenvalues, ascending, of the symmetric tridiagonal matrix
/// with diagonal d and squared off-diagonal e2 (length d.len() − 1), inputs finite.
///
/// `guesses` (one per wanted eigenvalue) start Newton's method; the result is accepted only
/// if Sturm counts at points separating the roots show exactly one eigenvalue per gap
/// (so root r really is λ_{r+1}). Otherwise each eigenvalue is first isolated by Sturm
/// bisection and then polished by Newton, which cannot pick a wrong root.
pub(crate) fn lowest_eigenvalues(
    d: &[f64],
    e2: &[f64],
    guesses: &[f64],
    out: &mut [f64],
    mut b: Brackets<'_>,
) {
    let n = d.len();
    let m = out.len();
    if m == 0 || n == 0 {
        return;
    }
    let mut gl = f64::INFINITY;
    let mut gu = f64::NEG_INFINITY;
    for i in 0..n {
        let left = if i > 0 { e2[i - 1].sqrt() } else { 0.0 };
        let right = if i + 1 < n { e2[i].sqrt() } else { 0.0 };
        gl = gl.min(d[i] - left - right);
        gu = gu.max(d[i] + left + right);
    }
    let span = (gu - gl).max(gl.abs()).max(gu.abs()).max(f64::MIN_POSITIVE);
    let tiny = (1e-300 * span).max(f64::MIN_POSITIVE);
    gl -= 4.0 * f64::EPSILON * span + tiny;
    gu += 4.0 * f64::EPSILON * span + tiny;
    b.lo.fill(gl);
    b.clo.fill(0);
    b.hi.fill(gu);
    b.chi.fill(n);

    let mut ok = true;
    for (r, o) in out.iter_mut().enumerate() {
        let g = guesses.get(r).copied().unwrap_or(0.5 * (gl + gu));
        let (x, conv) = newton(d, e2, r, g.clamp(gl, gu), &mut b, tiny);
        *o = x;
        ok &= conv;
    }
    if ok {
        // Separators: below the first root, between neighbours, above the last.
        let margin = |x: f64| 1e-9 * x.abs() + 16.0 * tiny;
        for j in 0..=m {
            let s = if j == 0 {
                out[0] - margin(out[0])
            } else if j == m {
                out[m - 1] + margin(out[m - 1])
            } else {
                0.5 * (out[j - 1] + out[j])
            };
            let sorted = j == 0 || j == m || out[j - 1] < out[j];
            if !sorted || sturm(d, e2, s, tiny).0 != j {
                ok = false;
                break;
            }
        }
    }
    if ok {
        return;
    }
    for (r, o) in out.iter_mut().enumerate() {
        while b.chi[r] - b.clo[r] > 1
            && b.hi[r] - b.lo[r] > 4.0 * f64::EPSILON * b.lo[r].abs().max(b.hi[r].abs()) + tiny
        {
            let x = 0.5 * (b.lo[r] + b.hi[r]);
            let (c, _) = sturm(d, e2, x, tiny);
            b.record(x, c);
        }
        let x0 = 0.5 * (b.lo[r] + b.hi[r]);
        *o = newton(d, e2, r, x0, &mut b, tiny).0;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn lowest(d: &[f64], e2: &[f64], guesses: &[f64]) -> Vec<f64> {
        let m = guesses.len();
        let (mut lo, mut hi) = (vec![0.0; m], vec![0.0; m]);
        let (mut clo, mut chi) = (vec![0; m], vec![0; m]);
        let mut out = vec![0.0; m];
        let b = Brackets {
            lo: &mut lo,
            clo: &mut clo,
            hi: &mut hi,
            chi: &mut chi,
        };
        lowest_eigenvalues(d, e2, guesses, &mut out, b);
        out
    }

    #[test]
    fn second_difference_matrix() {
        // tridiag(−1, 2, −1) of size n: λ_j = 2 − 2 cos(jπ/(n+1)).
        let n = 30;
        let d = vec![2.0; n];
        let e2 = vec![1.0; n - 1];
        let exact: Vec<f64> = (1..=6)
            .map(|j| 2.0 - 2.0 * (j as f64 * std::f64::consts::PI / (n as f64 + 1.0)).cos())
            .collect();
        // Good guesses, useless guesses, and misleading guesses all give the same answer.
        for guesses in [
            exact.iter().map(|v| v * 1.01).collect::<Vec<_>>(),
            vec![0.0; 6],
            vec![exact[5]; 6],
        ] {
            let got = lowest(&d, &e2, &guesses);
            for (g, e) in got.iter().zip(&exact) {
                assert!((g - e).abs() < 1e-14, "{got:?} vs {exact:?}");
            }
        }
    }

    #[test]
    fn diagonal_and_tiny_cases() {
        let got = lowest(&[3.0], &[], &[0.0]);
        assert_eq!(got, vec![3.0]);
        // Decoupled blocks: the eigenvalues are the diagonal, with a repeated value.
        let got = lowest(&[5.0, 1.0, 1.0, 2.0], &[0.0, 0.0, 0.0], &[0.0, 0.0, 0.0]);
        for (g, e) in got.iter().zip([1.0, 1.0, 2.0]) {
            assert!((g - e).abs() < 1e-14, "{got:?}");
        }
    }

    #[test]
    fn large_matrix_without_overflow() {
        // Entries of 1e3 and n = 400: p_n(x) would overflow without rescaling.
        let n = 400;
        let d = vec![2e3; n];
        let e2 = vec![1e6; n - 1];
        let got = lowest(&d, &e2, &[0.0, 0.0]);
        for (j, g) in got.iter().enumerate() {
            let e = 1e3
                * (2.0 - 2.0 * ((j + 1) as f64 * std::f64::consts::PI / (n as f64 + 1.0)).cos());
            assert!((g - e).abs() < 1e-9 * 4e3, "{g} vs {e}");
        }
    }
}
