//! Checks of the max-form energies U_{E,∞} (eq. 19), U_{E,∞,g} (eqs. 56–57) and the smooth
//! boundary-aware U_{E,p,g}: values against brute force, (sub)gradients against finite
//! differences and the subgradient inequality, tie sharing, determinism and refusals.
//!
//! The regions are defined here (a disc and the unit square with exact closest boundary
//! points) so that these tests do not depend on the library's implicit regions.

use rand::{RngExt, SeedableRng};
use rand_xoshiro::Xoshiro256PlusPlus;
use std::sync::Arc;
use stillpoint_energies::boundary::{UEInfG, UEpG};
use stillpoint_energies::einf::UEInf;
use stillpoint_energies::{Distance, Domain, Energy, PeriodicCube, PointSet, Result};

mod common;
use common::{fd_gradient, rel_err};

/// The disc |x − c| ≤ R; the closest boundary point is c + R (x − c)/|x − c|.
#[derive(Debug)]
struct Disc {
    c: [f64; 2],
    r: f64,
}

impl Domain for Disc {
    fn dim(&self) -> usize {
        2
    }
    fn contains(&self, x: &[f64]) -> bool {
        (x[0] - self.c[0]).hypot(x[1] - self.c[1]) <= self.r
    }
    fn sample(&self, n: usize, seed: u64) -> Result<PointSet> {
        let mut rng = Xoshiro256PlusPlus::seed_from_u64(seed);
        let mut rows = Vec::new();
        while rows.len() < n {
            let p = [
                self.c[0] + self.r * (2.0 * rng.random::<f64>() - 1.0),
                self.c[1] + self.r * (2.0 * rng.random::<f64>() - 1.0),
            ];
            if self.contains(&p) {
                rows.push(p);
            }
        }
        PointSet::from_rows(&rows)
    }
    fn bring_back(&self, x: &mut [f64], _prev: &mut [f64]) {
        if !self.contains(x) {
            let mut foot = [0.0; 2];
            self.closest_boundary_point(x, &mut foot);
            x.copy_from_slice(&foot);
        }
    }
    fn closest_boundary_point(&self, x: &[f64], foot: &mut [f64]) -> Option<f64> {
        let (dx, dy) = (x[0] - self.c[0], x[1] - self.c[1]);
        let rho = dx.hypot(dy);
        // At the centre every boundary point is closest; take one.
        let (ux, uy) = if rho > 0.0 {
            (dx / rho, dy / rho)
        } else {
            (1.0, 0.0)
        };
        foot[0] = self.c[0] + self.r * ux;
        foot[1] = self.c[1] + self.r * uy;
        Some((self.r - rho).abs())
    }
    fn bounding_box(&self) -> (Vec<f64>, Vec<f64>) {
        (
            vec![self.c[0] - self.r, self.c[1] - self.r],
            vec![self.c[0] + self.r, self.c[1] + self.r],
        )
    }
}

/// The square [0, 1]²; inside, the closest boundary point lies on the nearest face.
#[derive(Debug)]
struct Square;

impl Domain for Square {
    fn dim(&self) -> usize {
        2
    }
    fn contains(&self, x: &[f64]) -> bool {
        x.iter().all(|v| (0.0..=1.0).contains(v))
    }
    fn sample(&self, n: usize, seed: u64) -> Result<PointSet> {
        let mut rng = Xoshiro256PlusPlus::seed_from_u64(seed);
        PointSet::new(n, 2, (0..2 * n).map(|_| rng.random::<f64>()).collect())
    }
    fn bring_back(&self, x: &mut [f64], _prev: &mut [f64]) {
        x.iter_mut().for_each(|v| *v = v.clamp(0.0, 1.0));
    }
    fn closest_boundary_point(&self, x: &[f64], foot: &mut [f64]) -> Option<f64> {
        foot.copy_from_slice(x);
        if !self.contains(x) {
            foot.iter_mut().for_each(|v| *v = v.clamp(0.0, 1.0));
            return Some(((x[0] - foot[0]).powi(2) + (x[1] - foot[1]).powi(2)).sqrt());
        }
        let faces = [
            (0, 0.0, x[0]),
            (0, 1.0, 1.0 - x[0]),
            (1, 0.0, x[1]),
            (1, 1.0, 1.0 - x[1]),
        ];
        let &(k, v, d) = faces.iter().min_by(|a, b| a.2.total_cmp(&b.2)).unwrap();
        foot[k] = v;
        Some(d)
    }
    fn bounding_box(&self) -> (Vec<f64>, Vec<f64>) {
        (vec![0.0; 2], vec![1.0; 2])
    }
}

fn disc() -> Arc<dyn Domain> {
    Arc::new(Disc {
        c: [0.3, -0.2],
        r: 1.5,
    })
}

fn unit_disc() -> Arc<dyn Domain> {
    Arc::new(Disc {
        c: [0.0, 0.0],
        r: 1.0,
    })
}

fn random_cube(n: usize, s: usize, seed: u64) -> PointSet {
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(seed);
    PointSet::new(n, s, (0..n * s).map(|_| rng.random::<f64>()).collect()).unwrap()
}

/// Whether a point of `disc()` is away from the disc's medial axis (its centre), so
/// that the closest boundary point is unique and the boundary distance smooth nearby.
fn disc_ok(p: &[f64]) -> bool {
    let rho = (p[0] - 0.3).hypot(p[1] + 0.2);
    rho > 0.2 * 1.5 && rho < 1.5 - 0.01
}

/// The same for the unit square, whose medial axis is its diagonals: the nearest face
/// must be nearer than the second by 0.05.
fn square_ok(p: &[f64]) -> bool {
    let mut f = [p[0], 1.0 - p[0], p[1], 1.0 - p[1]];
    f.sort_by(|a, b| a.total_cmp(b));
    f[1] - f[0] > 0.05 && f[0] > 0.01
}

/// A test of whether a point is away from a region's medial axis.
type AwayFromAxis = fn(&[f64]) -> bool;

/// The two test regions with their "away from the medial axis" tests.
fn regions() -> Vec<(&'static str, Arc<dyn Domain>, AwayFromAxis)> {
    vec![
        ("disc", disc(), disc_ok as AwayFromAxis),
        ("square", Arc::new(Square), square_ok),
    ]
}

/// n points of `domain` drawn uniformly, keeping those that pass `ok`.
fn interior_points(domain: &dyn Domain, ok: AwayFromAxis, n: usize, seed: u64) -> PointSet {
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(seed);
    let (lo, hi) = domain.bounding_box();
    let mut rows = Vec::new();
    while rows.len() < n {
        let p: Vec<f64> = (0..2)
            .map(|k| lo[k] + (hi[k] - lo[k]) * rng.random::<f64>())
            .collect();
        if domain.contains(&p) && ok(&p) {
            rows.push(p);
        }
    }
    PointSet::from_rows(&rows).unwrap()
}

fn grad_of(e: &dyn Energy, x: &PointSet) -> (f64, Vec<f64>) {
    let mut g = vec![0.0; x.coordinate_count()];
    let u = e.value_and_gradient(x, &mut g);
    (u, g)
}

/// Signed coordinate difference under the given distance (minimum image on the torus).
fn diff(torus: bool, a: f64, b: f64) -> f64 {
    let d = a - b;
    if torus {
        d - d.round()
    } else {
        d
    }
}

fn dist(torus: bool, a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| diff(torus, *x, *y).powi(2))
        .sum::<f64>()
        .sqrt()
}

fn brute_min_pair(torus: bool, x: &PointSet) -> (f64, usize, usize) {
    let mut best = (f64::INFINITY, 0, 0);
    for i in 0..x.n() {
        for j in i + 1..x.n() {
            let d = dist(torus, x.point(i), x.point(j));
            if d < best.0 {
                best = (d, i, j);
            }
        }
    }
    best
}

/// Gradient of 1/d_ij over the whole set.
fn pair_gradient(torus: bool, x: &PointSet, i: usize, j: usize) -> Vec<f64> {
    let s = x.s();
    let d = dist(torus, x.point(i), x.point(j));
    let mut g = vec![0.0; x.coordinate_count()];
    for k in 0..s {
        let a = diff(torus, x.point(i)[k], x.point(j)[k]);
        g[i * s + k] = -a / d.powi(3);
        g[j * s + k] = a / d.powi(3);
    }
    g
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

#[test]
fn einf_value_is_inverse_brute_force_min_distance() {
    for (torus, distance) in [(false, Distance::Euclidean), (true, Distance::Torus)] {
        let e = UEInf::new(distance).unwrap();
        for (seed, s) in [(1u64, 1usize), (2, 2), (3, 3), (4, 7)] {
            let x = random_cube(40, s, seed);
            let (d, i, j) = brute_min_pair(torus, &x);
            let u = e.value(&x);
            assert!((u - 1.0 / d).abs() <= 1e-13 * u, "torus={torus} s={s}");
            assert!((e.min_distance(&x) - d).abs() <= 1e-13 * d);
            assert_eq!(e.active_pairs(&x), vec![(i, j)]);
            let (v, _) = grad_of(&e, &x);
            assert_eq!(v, u, "both paths give the same value");
        }
    }
    // Torus distance uses the nearest image: 0.05 and 0.95 are 0.1 apart.
    let x = PointSet::from_rows(&[[0.05, 0.5], [0.95, 0.5], [0.5, 0.5]]).unwrap();
    let t = UEInf::new(Distance::Torus).unwrap().value(&x);
    assert!((t - 10.0).abs() < 1e-12, "{t}");
    let eu = UEInf::new(Distance::Euclidean).unwrap().value(&x);
    assert!((eu - 1.0 / 0.45).abs() < 1e-12, "{eu}");
    assert_eq!(UEInf::new(Distance::Euclidean).unwrap().name(), "U_{E,∞}");
    // A single point has no pair: zero energy, zero gradient.
    let one = PointSet::from_rows(&[[0.3, 0.4]]).unwrap();
    let (u, g) = grad_of(&UEInf::new(Distance::Euclidean).unwrap(), &one);
    assert_eq!((u, g), (0.0, vec![0.0, 0.0]));
}

#[test]
fn einf_subgradient_is_the_gradient_for_a_unique_closest_pair() {
    for (torus, distance) in [(false, Distance::Euclidean), (true, Distance::Torus)] {
        let e = UEInf::new(distance).unwrap();
        for (seed, s) in [(11u64, 1usize), (12, 2), (13, 3), (14, 5)] {
            let x = random_cube(10, s, seed);
            // The finite-difference step must not change which pair is closest.
            let mut ds: Vec<f64> = (0..10)
                .flat_map(|i| (i + 1..10).map(move |j| (i, j)))
                .map(|(i, j)| dist(torus, x.point(i), x.point(j)))
                .collect();
            ds.sort_by(|a, b| a.total_cmp(b));
            assert!(ds[1] - ds[0] > 1e-4, "seed {seed}: near tie, pick another");
            let (_, g) = grad_of(&e, &x);
            let fd = fd_gradient(&e, &x, 1e-7);
            let err = rel_err(&g, &fd);
            assert!(err < 1e-6, "torus={torus} s={s}: relative error {err:e}");
            let (_, i, j) = brute_min_pair(torus, &x);
            assert!(rel_err(&g, &pair_gradient(torus, &x, i, j)) < 1e-13);
            for p in (0..10).filter(|&p| p != i && p != j) {
                assert!(g[p * s..(p + 1) * s].iter().all(|v| *v == 0.0), "point {p}");
            }
        }
    }
}

/// Checks the tie rule on `x`: the subgradient is the mean of the `active` pair gradients,
/// other points get no force, and for random directions v the one-sided directional
/// derivative (the max over the active pairs) is at least ⟨g, v⟩, also by finite
/// differences: U(x + hv) − U(x) ≥ h⟨g, v⟩ − O(h²).
fn check_tie(torus: bool, x: &PointSet, active: &[(usize, usize)]) {
    let distance = if torus {
        Distance::Torus
    } else {
        Distance::Euclidean
    };
    let e = UEInf::new(distance).unwrap();
    assert_eq!(e.active_pairs(x), active);
    let (u, g) = grad_of(&e, x);
    let pieces: Vec<Vec<f64>> = active
        .iter()
        .map(|&(i, j)| pair_gradient(torus, x, i, j))
        .collect();
    let mean: Vec<f64> = (0..x.coordinate_count())
        .map(|k| pieces.iter().map(|p| p[k]).sum::<f64>() / pieces.len() as f64)
        .collect();
    assert!(rel_err(&g, &mean) < 1e-12 || g == mean, "{g:?} vs {mean:?}");
    let s = x.s();
    for p in 0..x.n() {
        if !active.iter().any(|&(i, j)| i == p || j == p) {
            assert!(g[p * s..(p + 1) * s].iter().all(|v| *v == 0.0), "point {p}");
        }
    }
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(99);
    let h = 1e-7;
    for _ in 0..200 {
        let v: Vec<f64> = (0..x.coordinate_count())
            .map(|_| 2.0 * rng.random::<f64>() - 1.0)
            .collect();
        let gv = dot(&g, &v);
        let dir = pieces
            .iter()
            .map(|p| dot(p, &v))
            .fold(f64::NEG_INFINITY, f64::max);
        assert!(dir >= gv - 1e-12 * gv.abs().max(1.0), "{dir} < {gv}");
        let y = PointSet::new(
            x.n(),
            s,
            x.as_slice()
                .iter()
                .zip(&v)
                .map(|(a, b)| a + h * b)
                .collect(),
        )
        .unwrap();
        let one_sided = (e.value(&y) - u) / h;
        assert!(
            one_sided >= gv - 1e-4 * u,
            "subgradient inequality: {one_sided} < {gv}"
        );
        assert!(
            (one_sided - dir).abs() < 1e-4 * u,
            "{one_sided} vs max {dir}"
        );
    }
}

#[test]
fn einf_ties_share_the_subgradient_equally() {
    // Three collinear, equally spaced points (dyadic, so exactly tied) and a far one.
    let x = PointSet::from_rows(&[[0.25, 0.5], [0.5, 0.5], [0.75, 0.5], [0.5, 0.0625]]).unwrap();
    check_tie(false, &x, &[(0, 1), (1, 2)]);
    // A square: four sides tie, the diagonals do not.
    let x = PointSet::from_rows(&[[0.25, 0.25], [0.75, 0.25], [0.25, 0.75], [0.75, 0.75]]).unwrap();
    check_tie(false, &x, &[(0, 1), (0, 2), (1, 3), (2, 3)]);
    // Near-ties within the tolerance count: spacings 0.2 and 0.2 ± rounding.
    let x = PointSet::from_rows(&[[0.1, 0.3], [0.3, 0.3], [0.5, 0.3], [0.3, 0.9]]).unwrap();
    let e = UEInf::new(Distance::Euclidean).unwrap();
    assert_eq!(e.active_pairs(&x), vec![(0, 1), (1, 2)]);
    // Four equally spaced points on the circle of length 1: every neighbour pair, the wrap
    // pair included, is active and the forces cancel (a stationary point).
    let x = PointSet::from_rows(&[[0.125], [0.375], [0.625], [0.875]]).unwrap();
    check_tie(true, &x, &[(0, 1), (0, 3), (1, 2), (2, 3)]);
    let (_, g) = grad_of(&UEInf::new(Distance::Torus).unwrap(), &x);
    assert!(g.iter().all(|v| v.abs() < 1e-12), "{g:?}");
}

#[test]
fn einf_tie_tolerance_is_configurable() {
    // Spacings 0.2 and 0.2001: a tie at τ = 1e-3, not at the default.
    let x = PointSet::from_rows(&[[0.1, 0.3], [0.3, 0.3], [0.5001, 0.3]]).unwrap();
    let e = UEInf::new(Distance::Euclidean).unwrap();
    assert_eq!(e.tie_tolerance(), 1e-9);
    assert_eq!(e.active_pairs(&x), vec![(0, 1)]);
    let loose = e.clone().with_tie_tolerance(1e-3).unwrap();
    assert_eq!(loose.active_pairs(&x), vec![(0, 1), (1, 2)]);
    let (_, g) = grad_of(&loose, &x);
    let want: Vec<f64> = pair_gradient(false, &x, 0, 1)
        .iter()
        .zip(pair_gradient(false, &x, 1, 2))
        .map(|(a, b)| 0.5 * (a + b))
        .collect();
    assert!(rel_err(&g, &want) < 1e-14);
    let exact = e.clone().with_tie_tolerance(0.0).unwrap();
    assert_eq!(exact.active_pairs(&x), vec![(0, 1)]);
    for bad in [-1e-3, f64::NAN, f64::INFINITY] {
        let err = e.clone().with_tie_tolerance(bad).unwrap_err().to_string();
        assert!(err.contains("tie tolerance"), "{err}");
    }
}

#[test]
fn ueinfg_value_matches_brute_force_on_the_disc() {
    let d = disc();
    let e = UEInfG::new(d.clone()).unwrap();
    assert_eq!(e.name(), "U_{E,∞,g}");
    for seed in 0..6u64 {
        let x = d.sample(25, seed).unwrap();
        let pair = brute_min_pair(false, &x).0;
        let bnd = x
            .rows()
            .map(|p| 2.0 * (1.5 - (p[0] - 0.3).hypot(p[1] + 0.2)))
            .fold(f64::INFINITY, f64::min);
        let want = 1.0 / pair.min(bnd);
        let u = e.value(&x);
        assert!(
            (u - want).abs() <= 1e-13 * want,
            "seed {seed}: {u} vs {want}"
        );
        assert_eq!(grad_of(&e, &x).0, u);
    }
}

#[test]
fn ueinfg_subgradient_matches_fd_and_pushes_off_the_boundary() {
    let d = unit_disc();
    let e = UEInfG::new(d.clone()).unwrap();

    // A unique closest pair, far from the boundary.
    let x = PointSet::from_rows(&[[0.1, 0.0], [0.15, 0.02], [-0.4, 0.3], [0.2, -0.5]]).unwrap();
    let act = e.active_set(&x);
    assert_eq!((act.pairs, act.boundary), (vec![(0, 1)], vec![]));
    let (_, g) = grad_of(&e, &x);
    let fd = fd_gradient(&e, &x, 1e-7);
    assert!(rel_err(&g, &fd) < 1e-6, "{g:?} vs {fd:?}");
    assert_eq!(&g[4..], &[0.0; 4]);

    // A unique active boundary point.
    let x = PointSet::from_rows(&[[0.9, 0.1], [-0.3, 0.2], [0.1, -0.4], [-0.2, -0.3]]).unwrap();
    let act = e.active_set(&x);
    assert_eq!((act.pairs, act.boundary), (vec![], vec![0]));
    let (u, g) = grad_of(&e, &x);
    let fd = fd_gradient(&e, &x, 1e-7);
    assert!(rel_err(&g, &fd) < 1e-6, "{g:?} vs {fd:?}");
    assert_eq!(&g[2..], &[0.0; 6]);
    // Eq. 57: −4 (x − foot)/d_min³ with d_min = 2 d_g.
    let r = 0.9f64.hypot(0.1);
    let dmin = 2.0 * (1.0 - r);
    assert!((u - 1.0 / dmin).abs() < 1e-12);
    let foot = [0.9 / r, 0.1 / r];
    for k in 0..2 {
        let want = -4.0 * ([0.9, 0.1][k] - foot[k]) / dmin.powi(3);
        assert!(
            (g[k] - want).abs() < 1e-10 * want.abs(),
            "{} vs {want}",
            g[k]
        );
    }
    // −∇U, the descent direction, points towards the centre (away from the boundary).
    assert!(-(g[0] * 0.9 + g[1] * 0.1) < 0.0);

    // A tie between a pair and a boundary point shares the subgradient equally.
    // Points at radius 0.75 (2 d_g = 0.5) and a pair 0.5 apart: all tie exactly.
    let x = PointSet::from_rows(&[[0.75, 0.0], [0.25, 0.0]]).unwrap();
    let act = e.active_set(&x);
    assert_eq!(
        (act.pairs.clone(), act.boundary.clone()),
        (vec![(0, 1)], vec![0])
    );
    let (u, g) = grad_of(&e, &x);
    assert!((u - 2.0).abs() < 1e-12);
    // Pair: ∓0.5/0.125 = ∓4 on x_0/x_1; boundary of x_0: −4·(−0.25)/0.125 = 8.
    let want = [(-4.0 + 8.0) / 2.0, 0.0, 4.0 / 2.0, 0.0];
    assert!(rel_err(&g, &want) < 1e-12, "{g:?}");
}

#[test]
fn uepg_value_matches_brute_force() {
    for (name, dom, ok) in regions() {
        for &p in &[0.5, 1.0, 2.0, 4.0, 7.3] {
            let x = interior_points(dom.as_ref(), ok, 9, 5);
            let e = UEpG::new(dom.clone(), p).unwrap();
            let mut sum = 0.0;
            for i in 0..x.n() {
                for j in i + 1..x.n() {
                    sum += dist(false, x.point(i), x.point(j)).powf(-p);
                }
                let mut foot = [0.0; 2];
                let dg = dom.closest_boundary_point(x.point(i), &mut foot).unwrap();
                sum += (2.0 * dg).powf(-p);
            }
            let want = sum.powf(1.0 / p);
            let u = e.value(&x);
            assert!(
                (u - want).abs() <= 1e-12 * want,
                "{name} p={p}: {u} vs {want}"
            );
            let (v, _) = grad_of(&e, &x);
            assert!(
                (v - u).abs() <= 1e-13 * u,
                "{name} p={p}: value paths differ"
            );
        }
    }
    let e = UEpG::new(disc(), 2.5).unwrap();
    assert_eq!(e.name(), "U_{E,p,g}(p=2.5)");
    assert_eq!(e.p(), 2.5);
}

#[test]
fn uepg_gradient_matches_finite_differences() {
    let mut worst: f64 = 0.0;
    for (di, (name, dom, ok)) in regions().into_iter().enumerate() {
        for &p in &[0.5, 1.0, 2.0, 4.0] {
            for n in 6..=12 {
                let x = interior_points(dom.as_ref(), ok, n, 100 * di as u64 + n as u64);
                let e = UEpG::new(dom.clone(), p).unwrap();
                let (_, g) = grad_of(&e, &x);
                let fd = fd_gradient(&e, &x, 1e-6);
                let err = rel_err(&g, &fd);
                worst = worst.max(err);
                assert!(err < 1e-6, "{name} p={p} n={n}: relative error {err:e}");
            }
        }
    }
    eprintln!("worst relative gradient error {worst:e}");
}

#[test]
fn uepg_approaches_ueinfg_as_p_grows() {
    for (name, dom, ok) in regions() {
        let x = interior_points(dom.as_ref(), ok, 8, 3);
        let inf = UEInfG::new(dom.clone()).unwrap().value(&x);
        let mut prev = f64::INFINITY;
        for p in [1.0, 4.0, 16.0, 64.0] {
            let u = UEpG::new(dom.clone(), p).unwrap().value(&x);
            // ‖·‖_p decreases in p towards ‖·‖_∞.
            assert!(u >= inf * (1.0 - 1e-12) && u <= prev, "p={p}: {u}");
            prev = u;
        }
        let ratio = prev / inf;
        assert!(
            (1.0..1.05).contains(&ratio),
            "{name}: ratio at p = 64: {ratio}"
        );
        // Terms are scaled by the smallest distance, so even p = 1e4 stays finite.
        let (u, g) = grad_of(&UEpG::new(dom.clone(), 1e4).unwrap(), &x);
        assert!((u / inf - 1.0).abs() < 1e-3, "{u} vs {inf}");
        assert!(g.iter().all(|v| v.is_finite()));
    }
}

#[test]
fn same_bits_for_one_and_two_threads() {
    let d = disc();
    let x = d.sample(300, 17).unwrap();
    let cube = random_cube(300, 3, 18);
    let energies: Vec<(Box<dyn Energy>, &PointSet)> = vec![
        (Box::new(UEInf::new(Distance::Euclidean).unwrap()), &x),
        (Box::new(UEInf::new(Distance::Torus).unwrap()), &cube),
        (Box::new(UEInfG::new(d.clone()).unwrap()), &x),
        (Box::new(UEpG::new(d.clone(), 1.5).unwrap()), &x),
        (Box::new(UEpG::new(d.clone(), 1.0).unwrap()), &x),
    ];
    for (e, pts) in &energies {
        let run = |t: usize| {
            rayon::ThreadPoolBuilder::new()
                .num_threads(t)
                .build()
                .unwrap()
                .install(|| {
                    let mut g = vec![0.0; pts.coordinate_count()];
                    let u = e.value_and_gradient(pts, &mut g);
                    (
                        u.to_bits(),
                        e.value(pts).to_bits(),
                        g.iter().map(|v| v.to_bits()).collect::<Vec<_>>(),
                    )
                })
        };
        let one = run(1);
        assert_eq!(one, run(2), "{}", e.name());
        assert_eq!(one, run(3), "{}", e.name());
    }
}

#[test]
fn degenerate_sets_give_infinity_and_no_nan() {
    let d = unit_disc();
    // Two coincident points and a third one.
    let x = PointSet::from_rows(&[[0.1, 0.2], [0.1, 0.2], [-0.3, 0.1]]).unwrap();
    let energies: Vec<Box<dyn Energy>> = vec![
        Box::new(UEInf::new(Distance::Euclidean).unwrap()),
        Box::new(UEInf::new(Distance::Torus).unwrap()),
        Box::new(UEInfG::new(d.clone()).unwrap()),
        Box::new(UEpG::new(d.clone(), 0.5).unwrap()),
        Box::new(UEpG::new(d.clone(), 3.0).unwrap()),
    ];
    for e in &energies {
        let (u, g) = grad_of(e.as_ref(), &x);
        assert_eq!(u, f64::INFINITY, "{}", e.name());
        assert_eq!(e.value(&x), f64::INFINITY, "{}", e.name());
        assert!(g.iter().all(|v| v.is_finite()), "{}: {g:?}", e.name());
    }
    // The max-form energies see only the coincident pair: zero subgradient.
    let (_, g) = grad_of(&UEInf::new(Distance::Euclidean).unwrap(), &x);
    assert!(g.iter().all(|v| *v == 0.0));
    // U_{E,p,g} leaves the singular pair out; the third point still feels the others.
    let (_, g) = grad_of(&UEpG::new(d.clone(), 2.0).unwrap(), &x);
    assert!(g[4] != 0.0 && g[5] != 0.0, "{g:?}");
    // A point on the boundary.
    let y = PointSet::from_rows(&[[1.0, 0.0], [0.0, 0.2]]).unwrap();
    for e in &energies[2..] {
        let (u, g) = grad_of(e.as_ref(), &y);
        assert_eq!(u, f64::INFINITY, "{}", e.name());
        assert!(g.iter().all(|v| v.is_finite()), "{}: {g:?}", e.name());
    }
}

#[test]
fn bad_arguments_are_refused() {
    let err = UEInf::new(Distance::Q(0.5)).unwrap_err().to_string();
    assert!(err.contains("distance") && err.contains("q = 0.5"), "{err}");
    let cube: Arc<dyn Domain> = Arc::new(PeriodicCube::new(2).unwrap());
    let err = UEInfG::new(cube.clone()).unwrap_err().to_string();
    assert!(
        err.contains("domain") && err.contains("periodic cube"),
        "{err}"
    );
    assert!(UEpG::new(cube, 1.0).is_err());
    for bad in [0.0, -1.0, f64::NAN, f64::INFINITY] {
        let err = UEpG::new(disc(), bad).unwrap_err().to_string();
        assert!(err.contains("p =") && err.contains("> 0"), "{bad}: {err}");
    }
    let err = UEInfG::new(disc())
        .unwrap()
        .with_tie_tolerance(-1.0)
        .unwrap_err()
        .to_string();
    assert!(err.contains("tie tolerance"), "{err}");
}
