//! Paths as design variables: a standard Brownian motion W observed at the m equal steps
//! t_i = iT/m of [0, T], made from m uniform coordinates u by z = Φ⁻¹(u) (the clipping of
//! [`super::dist`]: z stays within ±8.21) and one linear map W = A z with
//! A Aᵀ = Cov(W(t_i), W(t_j)) = min(t_i, t_j). The three constructions differ in which
//! direction each coordinate drives, and so in how much a low-discrepancy set's best
//! (first) coordinates are worth to the integrand:
//!
//! * `standard`: W_i = √Δt (z_1 + … + z_i), coordinate i the i-th increment;
//! * `bridge`: the Brownian bridge (Caflisch, Morokoff and Owen 1997): z_1 fixes W(T),
//!   then each further coordinate a midpoint given its two ends, interval after interval
//!   breadth first (see [`Brownian::bridge_plan`]);
//! * `pca`: A = V √Λ from the eigen-decomposition of the covariance, eigenvalues
//!   decreasing, in closed form (Åkesson and Lehoczky 2000): λ_k = Δt / (4 sin²((2k − 1)π
//!   / (2(2m + 1)))), v_k(i) ∝ sin((2k − 1) i π / (2m + 1)). The first k coordinates
//!   carry the largest share of the path's variance any k directions can (about 81 % for
//!   the first at large m).
//!
//! `pca` is the default, as in QMCPy's `BrownianMotion`: it front-loads the variance
//! best, which is what the ordering of a lattice's or Sobol' set's coordinates rewards.

use super::Marginal;
use crate::Error;

/// The most steps a path may have: the principal-component map is a dense m × m matrix
/// (128 MiB at this size) applied to every point.
pub const MAX_STEPS: usize = 4096;

/// The constructions as a user writes them, the default first.
pub const CONSTRUCTIONS: &str = "pca (the default), bridge or standard";

/// How the uniform coordinates become the path.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Construction {
    /// Cumulative sums of the increments, in time order.
    Standard,
    /// The Brownian bridge: the end point first, then midpoints breadth first.
    Bridge,
    /// Principal components, largest variance first.
    Pca,
}

impl Construction {
    /// The construction's name as written.
    pub fn name(self) -> &'static str {
        match self {
            Construction::Standard => "standard",
            Construction::Bridge => "bridge",
            Construction::Pca => "pca",
        }
    }

    /// The construction named `word` (case-insensitive), if any.
    pub fn parse(word: &str) -> Option<Construction> {
        match word.trim().to_ascii_lowercase().as_str() {
            "standard" => Some(Construction::Standard),
            "bridge" => Some(Construction::Bridge),
            "pca" => Some(Construction::Pca),
            _ => None,
        }
    }
}

/// A standard Brownian motion on [0, T] observed at m equal steps.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Brownian {
    /// The horizon T (> 0).
    pub t: f64,
    /// The number of steps m (1 to [`MAX_STEPS`]): the variable's coordinates.
    pub m: usize,
    /// The map from the normal scores to the path.
    pub construction: Construction,
}

/// One step of the bridge: W(mid) = wl·W(left) + wr·W(right) + sd·z (indices on the grid
/// 0..=m, W(0) = 0).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BridgeStep {
    /// The left end's grid index.
    pub left: usize,
    /// The point filled.
    pub mid: usize,
    /// The right end's grid index.
    pub right: usize,
    /// The left end's weight (right − mid)/(right − left).
    pub wl: f64,
    /// The right end's weight (mid − left)/(right − left).
    pub wr: f64,
    /// The conditional standard deviation √((mid − left)(right − mid)Δt/(right − left)).
    pub sd: f64,
}

/// The standard normal, through which every coordinate of a path is read.
const STANDARD_NORMAL: Marginal = Marginal::Normal {
    mu: 0.0,
    sigma: 1.0,
};

impl Brownian {
    /// Parses the arguments of `brownian(T,m[,construction])` (the text inside the
    /// parentheses); `refuse` makes the refusal from what is accepted.
    pub fn parse(args: &str, refuse: impl Fn(String) -> Error) -> Result<Brownian, Error> {
        let parts: Vec<&str> = args.split(',').map(str::trim).collect();
        let form = format!(
            "brownian(T,m) or brownian(T,m,construction) with a horizon T > 0, \
             1 ≤ m ≤ {MAX_STEPS} steps and a construction {CONSTRUCTIONS}"
        );
        if !(2..=3).contains(&parts.len()) {
            return Err(refuse(form));
        }
        let t = parts[0]
            .parse::<f64>()
            .ok()
            .filter(|t| t.is_finite() && *t > 0.0);
        let m = parts[1]
            .parse::<usize>()
            .ok()
            .filter(|m| (1..=MAX_STEPS).contains(m));
        let construction = match parts.get(2) {
            None => Some(Construction::Pca),
            Some(w) => Construction::parse(w),
        };
        match (t, m, construction) {
            (Some(t), Some(m), Some(construction)) => {
                let b = Brownian { t, m, construction };
                // Every step must be a positive, finite variance (T = 1e-320 over 4096
                // steps would not be).
                if !(b.dt() > 0.0 && b.dt().is_finite() && (b.dt() * 4.0 * m as f64).is_finite()) {
                    return Err(refuse(format!(
                        "{form} (T/m = {:e} is not a usable step)",
                        t / m as f64
                    )));
                }
                Ok(b)
            }
            (None, ..) => Err(refuse(format!(
                "{form}: T = {} is not a number > 0",
                parts[0]
            ))),
            (_, None, _) => Err(refuse(format!(
                "{form}: m = {} is not a whole number from 1 to {MAX_STEPS}",
                parts[1]
            ))),
            (.., None) => Err(refuse(format!(
                "{form}: the construction {} is not one of them",
                parts[2]
            ))),
        }
    }

    /// The variable's type as written, `brownian(1,64,pca)`.
    pub fn text(&self) -> String {
        format!(
            "brownian({},{},{})",
            super::dist::num(self.t),
            self.m,
            self.construction.name()
        )
    }

    /// The step Δt = T/m.
    pub fn dt(&self) -> f64 {
        self.t / self.m as f64
    }

    /// The observation times t_i = iT/m, i = 1..m.
    pub fn times(&self) -> Vec<f64> {
        (1..=self.m).map(|i| i as f64 * self.dt()).collect()
    }

    /// The bridge's order: z_1 fixes W(m) = √T z_1; then, from the queue of intervals
    /// that starts as [0, m], each interval [l, r] with r − l ≥ 2 is taken in turn, its
    /// point mid = ⌊(l + r)/2⌋ filled by the next coordinate given W(l) and W(r), and
    /// [l, mid], [mid, r] queued behind the others (breadth first). For m a power of two
    /// this is the classic bridge (T, T/2, T/4 and 3T/4, …); for other m the left half
    /// is the shorter one. Returns the m − 1 steps after the first.
    pub fn bridge_plan(&self) -> Vec<BridgeStep> {
        let dt = self.dt();
        let mut queue = std::collections::VecDeque::from([(0usize, self.m)]);
        let mut plan = Vec::with_capacity(self.m.saturating_sub(1));
        while let Some((l, r)) = queue.pop_front() {
            if r - l < 2 {
                continue;
            }
            let mid = (l + r) / 2;
            let (a, b, w) = ((mid - l) as f64, (r - mid) as f64, (r - l) as f64);
            plan.push(BridgeStep {
                left: l,
                mid,
                right: r,
                wl: b / w,
                wr: a / w,
                sd: (a * b * dt / w).sqrt(),
            });
            queue.push_back((l, mid));
            queue.push_back((mid, r));
        }
        plan
    }

    /// The k-th eigenvalue (k = 1..m, decreasing) of Cov(W(t_i), W(t_j)) = min(t_i, t_j).
    pub fn eigenvalue(&self, k: usize) -> f64 {
        let s = ((2 * k - 1) as f64 * std::f64::consts::PI / (2 * (2 * self.m + 1)) as f64).sin();
        self.dt() / (4.0 * s * s)
    }

    /// The map A, m × m row-major (W = A z): column k is the path one unit of the k-th
    /// normal coordinate makes.
    pub fn matrix(&self) -> Vec<f64> {
        let m = self.m;
        match self.construction {
            Construction::Pca => {
                // Unit eigenvectors: Σ_i sin²((2k − 1)iπ/(2m + 1)) = (2m + 1)/4.
                let norm = 2.0 / ((2 * m + 1) as f64).sqrt();
                let mut a = vec![0.0; m * m];
                for k in 1..=m {
                    let scale = norm * self.eigenvalue(k).sqrt();
                    let w = (2 * k - 1) as f64 * std::f64::consts::PI / (2 * m + 1) as f64;
                    for i in 1..=m {
                        a[(i - 1) * m + (k - 1)] = scale * (w * i as f64).sin();
                    }
                }
                a
            }
            _ => {
                let mut a = vec![0.0; m * m];
                let mut w = vec![0.0; m];
                for k in 0..m {
                    let unit: Vec<f64> = (0..m).map(|i| f64::from(u8::from(i == k))).collect();
                    self.apply(None, &unit, &mut w);
                    for (i, &wi) in w.iter().enumerate() {
                        a[i * m + k] = wi;
                    }
                }
                a
            }
        }
    }

    /// W = A z into `w` (both of length m); `a` is [`Brownian::matrix`] for `pca` (made
    /// once by the caller for many points), unused otherwise.
    fn apply(&self, a: Option<&[f64]>, z: &[f64], w: &mut [f64]) {
        let m = self.m;
        match self.construction {
            Construction::Standard => {
                let s = self.dt().sqrt();
                let mut sum = 0.0;
                for (wi, zi) in w.iter_mut().zip(z) {
                    sum += s * zi;
                    *wi = sum;
                }
            }
            Construction::Bridge => {
                // On the grid 0..=m with W[0] = 0; w holds W[1..=m].
                let mut grid = vec![0.0; m + 1];
                grid[m] = self.t.sqrt() * z[0];
                for (step, zk) in self.bridge_plan().iter().zip(&z[1..]) {
                    grid[step.mid] =
                        step.wl * grid[step.left] + step.wr * grid[step.right] + step.sd * zk;
                }
                w.copy_from_slice(&grid[1..]);
            }
            Construction::Pca => {
                let owned;
                let a = match a {
                    Some(a) => a,
                    None => {
                        owned = self.matrix();
                        &owned
                    }
                };
                for (wi, row) in w.iter_mut().zip(a.chunks_exact(m)) {
                    *wi = row.iter().zip(z).map(|(x, y)| x * y).sum();
                }
            }
        }
    }

    /// The paths of n points: `u` holds n rows of m uniform coordinates (row-major), the
    /// result n rows of W(t_1) … W(t_m).
    pub fn paths(&self, u: &[f64]) -> Vec<f64> {
        let m = self.m;
        let a = (self.construction == Construction::Pca).then(|| self.matrix());
        let mut out = vec![0.0; u.len()];
        let mut z = vec![0.0; m];
        for (row, w) in u.chunks_exact(m).zip(out.chunks_exact_mut(m)) {
            for (zi, &ui) in z.iter_mut().zip(row) {
                *zi = STANDARD_NORMAL.ppf(ui);
            }
            self.apply(a.as_deref(), &z, w);
        }
        out
    }

    /// The uniform coordinates a path came from: z = A⁻¹ W, u = Φ(z) (the inverse of
    /// [`Brownian::paths`], up to rounding), for n rows of m values.
    pub fn unit(&self, w: &[f64]) -> Vec<f64> {
        let m = self.m;
        let a = (self.construction == Construction::Pca).then(|| self.matrix());
        let mut out = vec![0.0; w.len()];
        let mut z = vec![0.0; m];
        for (row, u) in w.chunks_exact(m).zip(out.chunks_exact_mut(m)) {
            match self.construction {
                Construction::Standard => {
                    let s = self.dt().sqrt();
                    let mut last = 0.0;
                    for (zi, &wi) in z.iter_mut().zip(row) {
                        *zi = (wi - last) / s;
                        last = wi;
                    }
                }
                Construction::Bridge => {
                    let at = |i: usize| if i == 0 { 0.0 } else { row[i - 1] };
                    z[0] = row[m - 1] / self.t.sqrt();
                    for (zk, step) in z[1..].iter_mut().zip(self.bridge_plan()) {
                        *zk = (at(step.mid) - step.wl * at(step.left) - step.wr * at(step.right))
                            / step.sd;
                    }
                }
                Construction::Pca => {
                    // A = V √Λ with V orthogonal: A⁻¹ = Λ^(−1/2) Vᵀ, so z_k = Σ_i A_ik W_i / λ_k.
                    let a = a.as_deref().unwrap_or_default();
                    for (k, zk) in z.iter_mut().enumerate() {
                        let dot: f64 = (0..m).map(|i| a[i * m + k] * row[i]).sum();
                        *zk = dot / self.eigenvalue(k + 1);
                    }
                }
            }
            for (ui, &zi) in u.iter_mut().zip(&z) {
                *ui = STANDARD_NORMAL.cdf(zi);
            }
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn path(m: usize, c: Construction) -> Brownian {
        Brownian {
            t: 1.7,
            m,
            construction: c,
        }
    }

    const ALL: [Construction; 3] = [
        Construction::Standard,
        Construction::Bridge,
        Construction::Pca,
    ];

    #[test]
    fn every_map_has_the_brownian_covariance() {
        // A Aᵀ = min(t_i, t_j) exactly (to rounding), for powers of two and others.
        for m in [1usize, 2, 3, 5, 8, 13, 64, 100] {
            for c in ALL {
                let b = path(m, c);
                let a = b.matrix();
                let t = b.times();
                for i in 0..m {
                    for j in 0..m {
                        let cov: f64 = (0..m).map(|k| a[i * m + k] * a[j * m + k]).sum();
                        let want = t[i].min(t[j]);
                        assert!(
                            (cov - want).abs() < 1e-12 * (1.0 + want),
                            "{c:?} m={m} ({i},{j}): {cov} vs {want}"
                        );
                    }
                }
            }
        }
    }

    /// Eigenvalues of a symmetric matrix by cyclic Jacobi rotations, decreasing: a check
    /// independent of the closed form.
    fn jacobi_eigenvalues(mut a: Vec<f64>, m: usize) -> Vec<f64> {
        for _sweep in 0..100 {
            let off: f64 = (0..m)
                .flat_map(|i| (0..m).filter(move |&j| j != i).map(move |j| (i, j)))
                .map(|(i, j)| a[i * m + j] * a[i * m + j])
                .sum();
            if off < 1e-30 {
                break;
            }
            for p in 0..m {
                for q in p + 1..m {
                    let apq = a[p * m + q];
                    if apq.abs() < 1e-300 {
                        continue;
                    }
                    let theta = (a[q * m + q] - a[p * m + p]) / (2.0 * apq);
                    let t = theta.signum() / (theta.abs() + (theta * theta + 1.0).sqrt());
                    let t = if theta == 0.0 { 1.0 } else { t };
                    let c = 1.0 / (t * t + 1.0).sqrt();
                    let s = t * c;
                    for k in 0..m {
                        let (akp, akq) = (a[k * m + p], a[k * m + q]);
                        a[k * m + p] = c * akp - s * akq;
                        a[k * m + q] = s * akp + c * akq;
                    }
                    for k in 0..m {
                        let (apk, aqk) = (a[p * m + k], a[q * m + k]);
                        a[p * m + k] = c * apk - s * aqk;
                        a[q * m + k] = s * apk + c * aqk;
                    }
                }
            }
        }
        let mut d: Vec<f64> = (0..m).map(|i| a[i * m + i]).collect();
        d.sort_by(|x, y| y.total_cmp(x));
        d
    }

    #[test]
    fn the_closed_form_eigenvalues_are_the_covariances() {
        for m in [1usize, 2, 7, 16, 31] {
            let b = path(m, Construction::Pca);
            let t = b.times();
            let cov: Vec<f64> = (0..m * m).map(|x| t[x / m].min(t[x % m])).collect();
            let numeric = jacobi_eigenvalues(cov.clone(), m);
            for (k, &l) in numeric.iter().enumerate() {
                let closed = b.eigenvalue(k + 1);
                assert!(
                    (closed - l).abs() < 1e-12 * l.max(1.0),
                    "m={m} k={k}: {closed} vs {l}"
                );
            }
            // Columns of A are orthogonal with squared norms λ_k (A = V √Λ, V orthogonal),
            // and each is an eigenvector: Cov·a_k = λ_k a_k.
            let a = b.matrix();
            for k in 0..m {
                for l in 0..m {
                    let dot: f64 = (0..m).map(|i| a[i * m + k] * a[i * m + l]).sum();
                    let want = if k == l { b.eigenvalue(k + 1) } else { 0.0 };
                    assert!((dot - want).abs() < 1e-12, "m={m} ({k},{l}): {dot}");
                }
                for i in 0..m {
                    let cv: f64 = (0..m).map(|j| cov[i * m + j] * a[j * m + k]).sum();
                    assert!((cv - b.eigenvalue(k + 1) * a[i * m + k]).abs() < 1e-12);
                }
            }
        }
    }

    #[test]
    fn the_bridge_follows_its_definition_at_m_4_and_6() {
        // m = 4, T = 1: W(1) = z1, W(1/2) = W(1)/2 + √(1/4) z2, W(1/4) = W(1/2)/2 +
        // √(1/8) z3, W(3/4) = (W(1/2) + W(1))/2 + √(1/8) z4 (the conditional variance of
        // a midpoint is (half the interval)²/(the interval)).
        let b = Brownian {
            t: 1.0,
            m: 4,
            construction: Construction::Bridge,
        };
        let z = [0.3, -1.1, 0.7, 2.0];
        let mut w = [0.0; 4];
        b.apply(None, &z, &mut w);
        let w4 = z[0];
        let w2 = w4 / 2.0 + 0.5 * z[1];
        let w1 = w2 / 2.0 + (1.0f64 / 8.0).sqrt() * z[2];
        let w3 = (w2 + w4) / 2.0 + (1.0f64 / 8.0).sqrt() * z[3];
        for (got, want) in w.iter().zip([w1, w2, w3, w4]) {
            assert!((got - want).abs() < 1e-15, "{w:?}");
        }
        // m = 6: the order is 6, 3, then 1 (of [0,3]), 4 (of [3,6]), then 2, 5.
        let b = Brownian { m: 6, ..b };
        let order: Vec<usize> = b.bridge_plan().iter().map(|s| s.mid).collect();
        assert_eq!(order, [3, 1, 4, 2, 5]);
    }

    #[test]
    fn pca_and_standard_follow_their_definitions_at_m_3() {
        let z = [0.4, -0.2, 1.3];
        let b = path(3, Construction::Standard);
        let mut w = [0.0; 3];
        b.apply(None, &z, &mut w);
        let s = b.dt().sqrt();
        let want = [s * z[0], s * (z[0] + z[1]), s * (z[0] + z[1] + z[2])];
        for (g, v) in w.iter().zip(want) {
            assert!((g - v).abs() < 1e-15);
        }
        // m = 3: 2m + 1 = 7, eigenvector k ∝ sin((2k − 1)iπ/7), normalised by 2/√7.
        let b = path(3, Construction::Pca);
        b.apply(None, &z, &mut w);
        let pi = std::f64::consts::PI;
        for (i, &wi) in w.iter().enumerate() {
            let want: f64 = (1..=3)
                .map(|k| {
                    let lam = b.dt() / (4.0 * (((2 * k - 1) as f64) * pi / 14.0).sin().powi(2));
                    let v = 2.0 / 7f64.sqrt() * (((2 * k - 1) * (i + 1)) as f64 * pi / 7.0).sin();
                    v * lam.sqrt() * z[k - 1]
                })
                .sum();
            assert!((wi - want).abs() < 1e-14, "{i}: {wi} vs {want}");
        }
        // The first component is the largest and moves every W_i the same way.
        assert!(b.eigenvalue(1) > b.eigenvalue(2) && b.eigenvalue(2) > b.eigenvalue(3));
        let a = b.matrix();
        assert!((0..3).all(|i| a[i * 3] > 0.0));
    }

    #[test]
    fn unit_inverts_paths() {
        for m in [1usize, 5, 16] {
            for c in ALL {
                let b = path(m, c);
                let u: Vec<f64> = (0..3 * m)
                    .map(|i| ((i * 37 + 11) % 97) as f64 / 97.0 + 0.004)
                    .collect();
                let back = b.unit(&b.paths(&u));
                for (x, y) in u.iter().zip(&back) {
                    assert!((x - y).abs() < 1e-10, "{c:?} m={m}: {x} vs {y}");
                }
            }
        }
    }

    #[test]
    fn refuses_bad_parameters_naming_what_is_accepted() {
        let refuse = |e: String| Error::invalid("--var", "W=brownian(...)", e);
        for (args, says) in [
            ("0,4", "T = 0"),
            ("-1,4", "T = -1"),
            ("1,0", "m = 0"),
            ("1,4097", "m = 4097"),
            ("1,2.5", "m = 2.5"),
            ("1,4,cholesky", "cholesky"),
            ("1", "brownian(T,m)"),
            ("1,2,pca,4", "brownian(T,m)"),
        ] {
            let e = Brownian::parse(args, refuse).unwrap_err().to_string();
            assert!(
                e.contains(says) && e.contains("pca (the default)"),
                "{args}: {e}"
            );
        }
        let b = Brownian::parse("2, 8", refuse).unwrap();
        assert_eq!(b.construction, Construction::Pca);
        assert_eq!(b.text(), "brownian(2,8,pca)");
        assert_eq!(
            Brownian::parse("2,8,Bridge", refuse).unwrap().construction,
            Construction::Bridge
        );
    }
}
