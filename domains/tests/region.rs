//! Checks of the implicit-region projection (against an independent dense reference on the
//! regions of eq. 58) and of the exact built-in shapes.

use rand::{RngExt, SeedableRng};
use rand_xoshiro::Xoshiro256PlusPlus;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Arc;
use stillpoint_domains::region::{paper_region, ImplicitRegion, RegionFn};
use stillpoint_domains::shapes::{Ball, BoxRegion, Ellipsoid, Polytope, Simplex};
use stillpoint_domains::{Domain, Error};

fn paper_g(i: usize) -> fn(&[f64]) -> f64 {
    match i {
        1 => |p| 17.0 * p[0] * p[0] - 16.0 * p[0].abs() * p[1] + 17.0 * p[1] * p[1] - 225.0,
        2 => |p| p[0] * p[0] * p[0].abs() + 10.0 * p[1] * p[1] - 100.0,
        3 => |p| p[1] * p[1] + 2.0 * p[0].abs() - 20.0,
        _ => |p| p[0].abs() + 2.0 * p[1].abs() - 5.0,
    }
}

/// The boundary point of a paper region on the ray from the origin at angle θ (each g
/// increases along such rays): bisection to machine precision.
fn ray_boundary(g: fn(&[f64]) -> f64, th: f64) -> [f64; 2] {
    let (c, s) = (th.cos(), th.sin());
    let (mut a, mut b) = (0.0, 1.0);
    while g(&[b * c, b * s]) <= 0.0 {
        b *= 2.0;
    }
    for _ in 0..64 {
        let m = 0.5 * (a + b);
        if m <= a || m >= b {
            break;
        }
        if g(&[m * c, m * s]) <= 0.0 {
            a = m;
        } else {
            b = m;
        }
    }
    [a * c, a * s]
}

/// An independent reference for the distance to the boundary g = 0 of a paper region:
/// 20 000 boundary points on equally spaced rays from the origin, found once.
struct Reference {
    g: fn(&[f64]) -> f64,
    pts: Vec<[f64; 2]>,
}

impl Reference {
    const M: usize = 20_000;

    fn new(g: fn(&[f64]) -> f64) -> Self {
        let step = std::f64::consts::TAU / Self::M as f64;
        let pts = (0..Self::M)
            .map(|j| ray_boundary(g, j as f64 * step))
            .collect();
        Reference { g, pts }
    }

    /// The nearest sampled point, then golden section in the angle around each of the
    /// four best local minima of the sampled distance.
    fn distance(&self, x: &[f64]) -> f64 {
        let m = Self::M;
        let step = std::f64::consts::TAU / m as f64;
        let sampled: Vec<f64> = self.pts.iter().map(|p| dist(p, x)).collect();
        let mut minima: Vec<usize> = (0..m)
            .filter(|&j| {
                sampled[j] <= sampled[(j + 1) % m] && sampled[j] <= sampled[(j + m - 1) % m]
            })
            .collect();
        minima.sort_by(|&a, &b| sampled[a].total_cmp(&sampled[b]));
        let d = |th: f64| dist(&ray_boundary(self.g, th), x);
        let phi = (5f64.sqrt() - 1.0) / 2.0;
        let mut best = f64::INFINITY;
        for &j in minima.iter().take(4) {
            let th = j as f64 * step;
            let (mut a, mut b) = (th - step, th + step);
            for _ in 0..60 {
                let c = b - phi * (b - a);
                let e = a + phi * (b - a);
                if d(c) < d(e) {
                    b = e;
                } else {
                    a = c;
                }
            }
            best = best.min(sampled[j]).min(d(0.5 * (a + b)));
        }
        best
    }
}

fn counted(i: usize) -> (ImplicitRegion, Arc<AtomicUsize>) {
    let n = Arc::new(AtomicUsize::new(0));
    let n2 = n.clone();
    let g = paper_g(i);
    let f: RegionFn = Arc::new(move |x: &[f64]| {
        n2.fetch_add(1, Ordering::Relaxed);
        g(x)
    });
    let (lo, hi) = paper_region(i).unwrap().bounding_box();
    (ImplicitRegion::new(f, lo, hi).unwrap(), n)
}

#[test]
fn paper_regions_closest_point_matches_dense_reference() {
    for i in 1..=4 {
        let reg = paper_region(i).unwrap();
        let (creg, count) = counted(i);
        let g = paper_g(i);
        let reference = Reference::new(g);
        let (lo, hi) = reg.bounding_box();
        let diam = reg.diameter();
        let mut interior: Vec<Vec<f64>> = reg
            .sample(45, 100 + i as u64)
            .unwrap()
            .rows()
            .map(|r| r.to_vec())
            .collect();
        // The kinks of eq. 58 lie on the axes: points on them, and under the heart's notch.
        interior.extend([
            vec![0.0, 0.0],
            vec![0.0, 1.0],
            vec![0.0, -0.5],
            vec![0.5, 0.0],
            vec![0.0, 0.3],
        ]);
        if i == 1 {
            interior.extend([vec![0.0, 3.0], vec![0.0, 3.5], vec![0.2, 3.4]]);
        }
        let mut rng = Xoshiro256PlusPlus::seed_from_u64(7 + i as u64);
        let mut exterior: Vec<Vec<f64>> = Vec::new();
        // Exterior points on the axes, then random ones.
        exterior.extend([
            vec![0.0, hi[1] * 1.05],
            vec![hi[0] * 1.1, 0.0],
            vec![0.0, lo[1] * 1.1],
        ]);
        if i == 1 {
            // In the notch of the heart, between its lobes.
            exterior.extend([vec![0.0, 3.9], vec![0.1, 4.0]]);
        }
        while exterior.len() < 20 {
            // Exterior points in a box 20 % larger than the bounding box.
            let p: Vec<f64> = (0..2)
                .map(|k| {
                    let w = hi[k] - lo[k];
                    lo[k] - 0.1 * w + 1.2 * w * rng.random::<f64>()
                })
                .collect();
            if g(&p) > 0.0 {
                exterior.push(p);
            }
        }
        for x in &exterior {
            assert!(g(x) > 0.0, "g{i}: {x:?} is not exterior");
        }
        // The one-off search for an anchor point (used from outside the box) is not
        // part of the cost of a call.
        creg.closest_boundary_point(&[1e3, 1e3], &mut [0.0; 2])
            .unwrap();
        reg.closest_boundary_point(&[1e3, 1e3], &mut [0.0; 2])
            .unwrap();
        let mut worst: f64 = 0.0;
        let mut time = 0.0;
        let mut evals = Vec::new();
        assert!(interior.iter().all(|x| reg.contains(x)));
        let n_in = interior.len();
        for x in interior.into_iter().chain(exterior) {
            let mut foot = [0.0; 2];
            count.store(0, Ordering::Relaxed);
            let d = creg.closest_boundary_point(&x, &mut foot).unwrap();
            evals.push(count.load(Ordering::Relaxed));
            // The same search with the analytic gradient of paper_region.
            let mut foot2 = [0.0; 2];
            let t = std::time::Instant::now();
            let d2 = reg.closest_boundary_point(&x, &mut foot2).unwrap();
            time += t.elapsed().as_secs_f64();
            let dref = reference.distance(&x);
            worst = worst
                .max((d - dref).abs() / diam)
                .max((d2 - dref).abs() / diam);
            assert!(
                (d - dref).abs() <= 1e-9 * diam && (d2 - dref).abs() <= 1e-9 * diam,
                "g{i} x = {x:?}: found {d} (foot {foot:?}), with the analytic gradient {d2} \
                 (foot {foot2:?}), reference {dref}"
            );
            assert!(g(&foot) <= 0.0 && g(&foot2) <= 0.0, "g{i}: foot outside");
            assert!(
                dist(&foot, &foot2) <= 1e-6 * diam,
                "g{i}: {foot:?} vs {foot2:?}"
            );
        }
        let stats = |e: &[usize]| {
            (
                e.iter().sum::<usize>() as f64 / e.len() as f64,
                *e.iter().max().unwrap(),
            )
        };
        let (mi, xi) = stats(&evals[..n_in]);
        let (mo, xo) = stats(&evals[n_in..]);
        println!(
            "g{i}: worst |d − ref|/diam = {worst:.1e}; evaluations of g per call (central \
             differences): interior mean {mi:.0} max {xi}, exterior mean {mo:.0} max {xo}; \
             {:.0} µs per call with the analytic gradient",
            1e6 * time / evals.len() as f64
        );
        assert!(mi < 3000.0 && mo < 3000.0, "g{i}: too costly");
    }
}

fn dist(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).powi(2))
        .sum::<f64>()
        .sqrt()
}

fn unit(rng: &mut Xoshiro256PlusPlus, s: usize) -> Vec<f64> {
    loop {
        let v: Vec<f64> = (0..s).map(|_| 2.0 * rng.random::<f64>() - 1.0).collect();
        let n = v.iter().map(|x| x * x).sum::<f64>().sqrt();
        if n > 0.1 && n <= 1.0 {
            return v.iter().map(|x| x / n).collect();
        }
    }
}

/// The boundary point of a convex domain on the ray from an interior point c along u, by
/// bisection on `contains`.
fn ray_hit(d: &dyn Domain, c: &[f64], u: &[f64]) -> Vec<f64> {
    let (lo, hi) = d.bounding_box();
    let (mut a, mut b) = (0.0, 2.0 * dist(&lo, &hi));
    let at = |t: f64| -> Vec<f64> { c.iter().zip(u).map(|(c, u)| c + t * u).collect() };
    for _ in 0..200 {
        let m = 0.5 * (a + b);
        if m <= a || m >= b {
            break;
        }
        if d.contains(&at(m)) {
            a = m;
        } else {
            b = m;
        }
    }
    at(a)
}

/// A shape, the generic region on its level function, and an interior point.
type TestShape = (&'static str, Box<dyn Domain>, ImplicitRegion, Vec<f64>);

/// The shapes of the tests in dimension s, each with an interior point (every shape here
/// is convex, so star-shaped about it).
fn shapes(s: usize) -> Vec<TestShape> {
    let mut out: Vec<TestShape> = Vec::new();
    let c: Vec<f64> = (0..s).map(|k| 0.3 * k as f64 - 0.2).collect();
    let ball = Ball::new(c.clone(), 1.3).unwrap();
    out.push((
        "ball",
        Box::new(ball.clone()),
        ball.to_implicit().unwrap(),
        c.clone(),
    ));
    let axes: Vec<f64> = (0..s).map(|k| 2.0 / (1.0 + 0.6 * k as f64)).collect();
    let ell = Ellipsoid::new(c.clone(), axes).unwrap();
    out.push((
        "ellipsoid",
        Box::new(ell.clone()),
        ell.to_implicit().unwrap(),
        c.clone(),
    ));
    let lo: Vec<f64> = (0..s).map(|k| -1.0 - 0.1 * k as f64).collect();
    let hi: Vec<f64> = (0..s).map(|k| 0.5 + 0.3 * k as f64).collect();
    let bx = BoxRegion::new(lo.clone(), hi.clone()).unwrap();
    let bc: Vec<f64> = lo.iter().zip(&hi).map(|(l, h)| 0.5 * (l + h)).collect();
    out.push(("box", Box::new(bx.clone()), bx.to_implicit().unwrap(), bc));
    let sx = Simplex::new(s).unwrap();
    out.push((
        "simplex",
        Box::new(sx.clone()),
        sx.to_implicit().unwrap(),
        vec![1.0 / (s as f64 + 1.0); s],
    ));
    // A polytope: 3s random half-spaces at distance 1 from the origin, cut by a box that
    // some of them leave part of the boundary to.
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(99 + s as u64);
    let a: Vec<Vec<f64>> = (0..3 * s).map(|_| unit(&mut rng, s)).collect();
    let b: Vec<f64> = (0..3 * s).map(|i| 0.8 + 0.1 * (i % 4) as f64).collect();
    let poly = Polytope::new(a, b, vec![-1.5; s], vec![1.5; s]).unwrap();
    let pc = poly.interior_point().to_vec();
    out.push((
        "polytope",
        Box::new(poly.clone()),
        poly.to_implicit().unwrap(),
        pc,
    ));
    out
}

/// Test points: interior ones from the shape's own sampler, exterior ones uniform in its
/// bounding box widened by 30 %, rejected when inside.
fn test_points(d: &dyn Domain, n_in: usize, n_out: usize, seed: u64) -> Vec<Vec<f64>> {
    let mut pts: Vec<Vec<f64>> = Vec::new();
    if n_in > 0 {
        pts.extend(d.sample(n_in, seed).unwrap().rows().map(|r| r.to_vec()));
    }
    let (lo, hi) = d.bounding_box();
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(seed ^ 0xABCD);
    let mut k = 0;
    while k < n_out {
        let p: Vec<f64> = lo
            .iter()
            .zip(&hi)
            .map(|(l, h)| l - 0.3 * (h - l) + 1.6 * (h - l) * rng.random::<f64>())
            .collect();
        if !d.contains(&p) {
            pts.push(p);
            k += 1;
        }
    }
    pts
}

#[test]
fn shapes_exact_closest_point_agrees_with_brute_force_and_generic_search() {
    for s in [2usize, 5] {
        for (name, shape, generic, c) in shapes(s) {
            let (lo, hi) = shape.bounding_box();
            let diam = dist(&lo, &hi);
            // Dense boundary samples: equal angles in 2-D, random directions in 5-D.
            let m = if s == 2 { 20_000 } else { 50_000 };
            let mut rng = Xoshiro256PlusPlus::seed_from_u64(5);
            let boundary: Vec<Vec<f64>> = (0..m)
                .map(|j| {
                    let u = if s == 2 {
                        let a = std::f64::consts::TAU * j as f64 / m as f64;
                        vec![a.cos(), a.sin()]
                    } else {
                        unit(&mut rng, s)
                    };
                    ray_hit(shape.as_ref(), &c, &u)
                })
                .collect();
            // In 2-D the samples are dense: no gap between neighbours exceeds `gap`.
            let gap = (0..m)
                .map(|j| dist(&boundary[j], &boundary[(j + 1) % m]))
                .fold(0.0, f64::max);
            // The same generic region with a counter on g, for the cost report.
            let count = Arc::new(AtomicUsize::new(0));
            let counted = {
                let (c, inner) = (count.clone(), generic.clone());
                let (glo, ghi) = generic.bounding_box();
                ImplicitRegion::new(
                    Arc::new(move |x: &[f64]| {
                        c.fetch_add(1, Ordering::Relaxed);
                        inner.g(x)
                    }),
                    glo,
                    ghi,
                )
                .unwrap()
            };
            counted.closest_boundary_point(&vec![1e3; s], &mut vec![0.0; s]);
            count.store(0, Ordering::Relaxed);
            let mut worst_rel: f64 = 0.0;
            let pts = test_points(shape.as_ref(), 20, 10, 31 + s as u64);
            for x in &pts {
                counted
                    .closest_boundary_point(x, &mut vec![0.0; s])
                    .unwrap();
            }
            let per_call = count.load(Ordering::Relaxed) as f64 / pts.len() as f64;
            for x in pts {
                let mut foot = vec![0.0; s];
                let d = shape.closest_boundary_point(&x, &mut foot).unwrap();
                assert!((d - dist(&x, &foot)).abs() <= 1e-12 * diam, "{name} s={s}");
                // The foot is on the boundary: its level is zero to rounding.
                let lv = shape.level(&foot).unwrap();
                let scale = if name == "ball" || name == "ellipsoid" {
                    1.0
                } else {
                    diam
                };
                assert!(
                    lv.abs() <= 1e-12 * scale,
                    "{name} s={s}: level(foot) = {lv}"
                );
                // No boundary sample is closer.
                let dmin = boundary
                    .iter()
                    .map(|b| dist(&x, b))
                    .fold(f64::INFINITY, f64::min);
                assert!(
                    d <= dmin + 1e-12 * diam,
                    "{name} s={s} x={x:?}: exact {d} > sample {dmin}"
                );
                if s == 2 {
                    assert!(
                        d >= dmin - gap,
                        "{name} s={s} x={x:?}: exact {d} ≪ samples {dmin}"
                    );
                }
                // The generic search on the same level function finds the same distance.
                let mut gfoot = vec![0.0; s];
                let dg = generic.closest_boundary_point(&x, &mut gfoot).unwrap();
                let rel = (dg - d).abs() / d.max(1e-3 * diam);
                worst_rel = worst_rel.max(rel);
                assert!(
                    rel <= 1e-6,
                    "{name} s={s} x={x:?}: exact {d} (foot {foot:?}), generic {dg} (foot {gfoot:?})"
                );
            }
            println!(
                "{name} s={s}: generic vs exact worst relative difference {worst_rel:.1e}, \
                 {per_call:.0} evaluations of g per call"
            );
        }
    }
}

/// The foot of a paper region's closest point sits on a sign change of g: on the region
/// side, with the other side within 1e-7 of the diameter.
#[test]
fn paper_region_feet_sit_on_a_sign_change() {
    for i in 1..=4 {
        let reg = paper_region(i).unwrap();
        let g = paper_g(i);
        let diam = reg.diameter();
        let mut pts: Vec<Vec<f64>> = reg
            .sample(30, 5)
            .unwrap()
            .rows()
            .map(|r| r.to_vec())
            .collect();
        pts.extend([vec![30.0, -40.0], vec![0.0, 0.0], vec![-12.0, 0.3]]);
        for x in pts {
            let mut foot = [0.0; 2];
            let d = reg.closest_boundary_point(&x, &mut foot).unwrap();
            assert!(
                reg.contains(&foot) && g(&foot) <= 0.0,
                "g{i} x={x:?} foot={foot:?}"
            );
            assert!((d - dist(&x, &foot)).abs() <= 1e-12 * diam);
            // Beyond the foot (away from x from inside, towards x from outside) g > 0.
            let sign = if reg.contains(&x) { 1.0 } else { -1.0 };
            let step: Vec<f64> = (0..2)
                .map(|k| foot[k] + sign * 1e-7 * diam * (foot[k] - x[k]) / d.max(1e-300))
                .collect();
            assert!(
                g(&step) > 0.0,
                "g{i} x={x:?}: no sign change next to foot {foot:?}"
            );
        }
    }
}

/// Far points, points on the boundary, the box, one and three dimensions, wrong lengths.
#[test]
fn closest_point_corner_cases() {
    let reg = paper_region(4).unwrap();
    let g = paper_g(4);
    // Far outside the box: the nearest point of the rhombus |x| + 2|y| ≤ 5 to
    // (100, 100) is the vertex (5, 0) (the foot on the line x + 2y = 5 is off the edge).
    let mut foot = [0.0; 2];
    let d = reg
        .closest_boundary_point(&[100.0, 100.0], &mut foot)
        .unwrap();
    // (The angle is found to ~1e-9, so the accuracy scales with the distance.)
    assert!((d - 95f64.hypot(100.0)).abs() < 1e-10 * d, "{d} {foot:?}");
    // From (2, 1.5) + 50·(1, 2) it is (2, 1.5) on that edge, at distance 50√5.
    let d = reg
        .closest_boundary_point(&[52.0, 101.5], &mut foot)
        .unwrap();
    assert!((d - 50.0 * 5f64.sqrt()).abs() < 1e-10 * d, "{d} {foot:?}");
    assert!(
        (foot[0] - 2.0).abs() < 1e-7 && (foot[1] - 1.5).abs() < 1e-7,
        "{foot:?}"
    );
    // A vertex: from (8, 0) the nearest point is (5, 0).
    let d = reg.closest_boundary_point(&[8.0, 0.0], &mut foot).unwrap();
    assert!((d - 3.0).abs() < 1e-9 && (foot[0] - 5.0).abs() < 1e-8 && foot[1].abs() < 1e-8);
    // On the boundary: distance 0.
    let d = reg.closest_boundary_point(&[1.0, 2.0], &mut foot).unwrap();
    assert!(d < 1e-9 && g(&foot).abs() < 1e-9);
    // Same input, same bits.
    let mut f2 = [0.0; 2];
    let x = [0.3, -0.7];
    assert_eq!(
        reg.closest_boundary_point(&x, &mut foot),
        reg.closest_boundary_point(&x, &mut f2)
    );
    assert_eq!(foot, f2);
    // Wrong lengths or non-finite points get None, not a panic.
    assert!(reg.closest_boundary_point(&[0.0], &mut foot).is_none());
    assert!(reg
        .closest_boundary_point(&[f64::NAN, 0.0], &mut foot)
        .is_none());
    assert!(reg
        .closest_boundary_point(&[0.0, 0.0], &mut [0.0; 3])
        .is_none());
    assert!(reg
        .closest_boundary_point(&[1e12, 0.0], &mut foot)
        .is_none());
    assert_eq!(reg.g(&[1.0]), f64::INFINITY);
    // Such points are still brought inside.
    for x in [[1e12, 0.0], [f64::NAN, 1.0], [f64::INFINITY, 0.0]] {
        let (mut y, mut prev) = (x.to_vec(), vec![0.0; 2]);
        reg.bring_back(&mut y, &mut prev);
        assert!(reg.contains(&y) && y == prev, "{x:?} → {y:?}");
    }

    // A region cut by its box: the half-disc x² + y² ≤ 1 in [-2, 2] × [0, 2]; from
    // (0.5, 0.1) the bottom face is nearest.
    let half = ImplicitRegion::new(
        Arc::new(|p: &[f64]| p[0] * p[0] + p[1] * p[1] - 1.0),
        vec![-2.0, 0.0],
        vec![2.0, 2.0],
    )
    .unwrap();
    let d = half.closest_boundary_point(&[0.5, 0.1], &mut foot).unwrap();
    assert!((d - 0.1).abs() < 1e-10 && foot[1] == 0.0, "{d} {foot:?}");
    // From below the box the nearest region point is on the face.
    let d = half
        .closest_boundary_point(&[0.2, -0.5], &mut foot)
        .unwrap();
    assert!(
        (d - 0.5).abs() < 1e-10 && half.contains(&foot),
        "{d} {foot:?}"
    );

    // One dimension: the interval [-1, 2] as (x + 1)(x − 2) ≤ 0.
    let line = ImplicitRegion::new(
        Arc::new(|p: &[f64]| (p[0] + 1.0) * (p[0] - 2.0)),
        vec![-3.0],
        vec![3.0],
    )
    .unwrap();
    let mut f1 = [0.0];
    assert!((line.closest_boundary_point(&[0.0], &mut f1).unwrap() - 1.0).abs() < 1e-10);
    assert!((f1[0] + 1.0).abs() < 1e-10);
    assert!((line.closest_boundary_point(&[2.5], &mut f1).unwrap() - 0.5).abs() < 1e-10);

    // Three dimensions: a ball of radius 2 about (1, 0, 0).
    let ball = Ball::new(vec![1.0, 0.0, 0.0], 2.0)
        .unwrap()
        .to_implicit()
        .unwrap();
    let mut f3 = [0.0; 3];
    let d = ball
        .closest_boundary_point(&[1.5, 0.5, -0.5], &mut f3)
        .unwrap();
    assert!((d - (2.0 - 0.75f64.sqrt())).abs() < 1e-9, "{d}");
    let d = ball
        .closest_boundary_point(&[5.0, 3.0, 0.0], &mut f3)
        .unwrap();
    assert!((d - 3.0).abs() < 1e-9, "{d}");
}

#[test]
fn paper_regions_bring_points_back_to_the_wall() {
    for i in 1..=4 {
        let reg = paper_region(i).unwrap();
        let g = paper_g(i);
        let reference = Reference::new(g);
        let (lo, hi) = reg.bounding_box();
        let diam = reg.diameter();
        let mut rng = Xoshiro256PlusPlus::seed_from_u64(40 + i as u64);
        let mut n = 0;
        while n < 20 {
            let x: Vec<f64> = (0..2)
                .map(|k| {
                    lo[k] - 0.2 * (hi[k] - lo[k]) + 1.4 * (hi[k] - lo[k]) * rng.random::<f64>()
                })
                .collect();
            if g(&x) <= 0.0 && reg.contains(&x) {
                // Inside: untouched.
                let (mut y, mut prev) = (x.clone(), vec![0.0, 0.0]);
                reg.bring_back(&mut y, &mut prev);
                assert_eq!((y, prev), (x, vec![0.0, 0.0]));
                continue;
            }
            n += 1;
            let (mut y, mut prev) = (x.clone(), vec![7.0, 7.0]);
            reg.bring_back(&mut y, &mut prev);
            assert!(reg.contains(&y), "g{i}: {x:?} brought to {y:?}, outside");
            assert_eq!(y, prev, "the point stops at the wall");
            let dref = reference.distance(&x);
            assert!(
                (dist(&x, &y) - dref).abs() <= 1e-8 * diam,
                "g{i}: {x:?} moved {} but the boundary is {dref} away",
                dist(&x, &y)
            );
        }
    }
}

#[test]
fn shapes_bring_exterior_points_to_the_nearest_point_inside() {
    let s = 5;
    for (name, shape, _, _) in shapes(s) {
        let (lo, hi) = shape.bounding_box();
        let diam = dist(&lo, &hi);
        let inner = shape.sample(4000, 77).unwrap();
        for x in test_points(shape.as_ref(), 0, 30, 8) {
            let mut foot = vec![0.0; s];
            let d = shape.closest_boundary_point(&x, &mut foot).unwrap();
            let (mut y, mut prev) = (x.clone(), vec![0.0; s]);
            shape.bring_back(&mut y, &mut prev);
            assert!(shape.contains(&y), "{name}: {x:?} → {y:?} is outside");
            assert_eq!(y, prev, "{name}: the point stops at the wall");
            let dy = dist(&x, &y);
            assert!(
                (dy - d).abs() <= 1e-8 * diam,
                "{name}: moved {dy}, projection {d}"
            );
            // No point of the shape is closer (4000 uniform interior points).
            for z in inner.rows() {
                assert!(
                    dist(&x, z) >= dy - 1e-8 * diam,
                    "{name}: {z:?} closer than {y:?}"
                );
            }
        }
        // A non-finite point lands inside too.
        let (mut y, mut prev) = (vec![f64::NAN; s], vec![0.0; s]);
        shape.bring_back(&mut y, &mut prev);
        assert!(shape.contains(&y) && y == prev, "{name}: {y:?}");
        // Inside points are untouched.
        let x = inner.point(0).to_vec();
        let (mut y, mut prev) = (x.clone(), vec![9.0; s]);
        shape.bring_back(&mut y, &mut prev);
        assert_eq!((y, prev), (x, vec![9.0; s]));
    }
}

#[test]
fn samples_are_inside_seeded_and_uniform() {
    for s in [2usize, 5] {
        for (name, shape, generic, _) in shapes(s) {
            let a = shape.sample(300, 11).unwrap();
            assert_eq!(
                a,
                shape.sample(300, 11).unwrap(),
                "{name}: same seed, same points"
            );
            assert_ne!(a, shape.sample(300, 12).unwrap(), "{name}");
            assert!(a.rows().all(|r| shape.contains(r)), "{name} s={s}");
            let b = generic.sample(100, 3).unwrap();
            assert!(
                b.rows().all(|r| shape.contains(r) && generic.contains(r)),
                "{name}"
            );
        }
    }
    for i in 1..=4 {
        let reg = paper_region(i).unwrap();
        let a = reg.sample(100, 1).unwrap();
        assert_eq!(a, reg.sample(100, 1).unwrap());
        assert!(a.rows().all(|r| paper_g(i)(r) <= 0.0));
    }
    // Means against the centroid, within 4 standard errors per coordinate, and the mean
    // squared radius of the ball, E|x − c|² = s r²/(s + 2).
    let n = 200_000;
    let s = 5;
    let c = vec![0.5, -1.0, 2.0, 0.0, 3.0];
    let ball = Ball::new(c.clone(), 2.0).unwrap();
    let pts = ball.sample(n, 2024).unwrap();
    let m = pts.mean();
    let se = (4.0 / (s as f64 + 2.0) / n as f64).sqrt();
    for k in 0..s {
        assert!((m[k] - c[k]).abs() < 4.0 * se, "ball mean {m:?}");
    }
    let r2: Vec<f64> = pts.rows().map(|p| dist(p, &c).powi(2)).collect();
    let mean_r2 = r2.iter().sum::<f64>() / n as f64;
    let var_r2 = r2.iter().map(|v| (v - mean_r2).powi(2)).sum::<f64>() / n as f64;
    let expect = s as f64 * 4.0 / (s as f64 + 2.0);
    assert!(
        (mean_r2 - expect).abs() < 4.0 * (var_r2 / n as f64).sqrt(),
        "{mean_r2} vs {expect}"
    );
    let simplex = Simplex::new(s).unwrap();
    let m = simplex.sample(n, 7).unwrap().mean();
    // Each coordinate is Beta(1, s): mean 1/(s+1), variance s/((s+1)²(s+2)).
    let sf = s as f64;
    let se = (sf / ((sf + 1.0).powi(2) * (sf + 2.0)) / n as f64).sqrt();
    for v in &m {
        assert!(
            (v - 1.0 / (sf + 1.0)).abs() < 4.0 * se,
            "simplex mean {m:?}"
        );
    }
    let ell = Ellipsoid::new(c.clone(), vec![3.0, 1.0, 0.5, 2.0, 1.0]).unwrap();
    let m = ell.sample(n, 9).unwrap().mean();
    for k in 0..s {
        let a = [3.0, 1.0, 0.5, 2.0, 1.0][k];
        assert!((m[k] - c[k]).abs() < 4.0 * a * se.max((1.0 / (sf + 2.0) / n as f64).sqrt()));
    }
}

fn name_of(e: Error) -> String {
    match e {
        Error::InvalidArgument { name, .. } => name,
        Error::Numerical(m) => format!("numerical: {m}"),
    }
}

#[test]
fn bad_input_is_refused_with_a_clear_message() {
    let one: RegionFn = Arc::new(|_: &[f64]| 1.0);
    // Boxes.
    let e = ImplicitRegion::new(one.clone(), vec![0.0, 0.0], vec![1.0]).unwrap_err();
    assert_eq!(name_of(e), "box");
    let e = ImplicitRegion::new(one.clone(), vec![0.0, 1.0], vec![1.0, 1.0]).unwrap_err();
    assert_eq!(name_of(e), "box coordinate 2");
    let e = ImplicitRegion::new(one.clone(), vec![f64::NAN], vec![1.0]).unwrap_err();
    assert_eq!(name_of(e), "box coordinate 1");
    assert_eq!(
        name_of(ImplicitRegion::new(one.clone(), vec![], vec![]).unwrap_err()),
        "box"
    );
    // An empty region: g = 1 everywhere.
    let empty = ImplicitRegion::new(one, vec![-1.0, 0.0], vec![1.0, 2.0]).unwrap();
    let msg = empty.check(1000, 1).unwrap_err().to_string();
    assert!(
        msg.contains("[-1, 1] × [0, 2]") && msg.contains("empty"),
        "{msg}"
    );
    let msg = empty.sample(10, 1).unwrap_err().to_string();
    assert!(
        msg.contains("[-1, 1] × [0, 2]") && msg.contains("acceptance"),
        "{msg}"
    );
    assert!(empty
        .closest_boundary_point(&[0.0, 1.0], &mut [0.0; 2])
        .is_none());
    // g returning NaN.
    let nan = ImplicitRegion::new(
        Arc::new(|p: &[f64]| if p[0] > 0.5 { f64::NAN } else { p[0] }),
        vec![0.0, 0.0],
        vec![1.0, 1.0],
    )
    .unwrap();
    let msg = nan.check(100, 1).unwrap_err().to_string();
    assert!(msg.contains("NaN"), "{msg}");
    let msg = nan.sample(50, 1).unwrap_err().to_string();
    assert!(msg.contains("NaN"), "{msg}");
    assert!(
        nan.level(&[0.9, 0.5]).unwrap() > 0.0,
        "NaN counts as outside"
    );
    // A region the box holds too little of.
    let tiny = ImplicitRegion::new(
        Arc::new(|p: &[f64]| p[0] * p[0] + p[1] * p[1] - 1e-8),
        vec![-1.0, -1.0],
        vec![1.0, 1.0],
    )
    .unwrap();
    let msg = tiny.sample(5, 1).unwrap_err().to_string();
    assert!(
        msg.contains("acceptance") && msg.contains("[-1, 1] × [-1, 1]"),
        "{msg}"
    );
    assert!(name_of(paper_region(0).unwrap_err()) == "region");
    assert!(name_of(paper_region(5).unwrap_err()) == "region");
    assert_eq!(
        name_of(paper_region(1).unwrap().sample(0, 1).unwrap_err()),
        "n"
    );
    assert_eq!(
        name_of(paper_region(1).unwrap().check(0, 1).unwrap_err()),
        "samples"
    );

    // Shapes.
    assert_eq!(name_of(Ball::new(vec![0.0], 0.0).unwrap_err()), "radius");
    assert_eq!(name_of(Ball::new(vec![0.0], -1.0).unwrap_err()), "radius");
    assert_eq!(
        name_of(Ball::new(vec![0.0], f64::NAN).unwrap_err()),
        "radius"
    );
    assert_eq!(name_of(Ball::new(vec![], 1.0).unwrap_err()), "center");
    assert_eq!(
        name_of(Ball::new(vec![0.0, f64::INFINITY], 1.0).unwrap_err()),
        "center coordinate 2"
    );
    let e = Ellipsoid::new(vec![0.0, 0.0], vec![1.0, -2.0]).unwrap_err();
    assert_eq!(name_of(e), "semi-axis 2");
    assert_eq!(
        name_of(Ellipsoid::new(vec![0.0, 0.0], vec![1.0]).unwrap_err()),
        "semi_axes"
    );
    assert_eq!(
        name_of(BoxRegion::new(vec![0.0, 2.0], vec![1.0, 1.0]).unwrap_err()),
        "box coordinate 2"
    );
    assert_eq!(
        name_of(BoxRegion::new(vec![0.0], vec![1.0, 1.0]).unwrap_err()),
        "box"
    );
    assert_eq!(name_of(Simplex::new(0).unwrap_err()), "s");
    let bx = (vec![-1.0, -1.0], vec![1.0, 1.0]);
    let e = Polytope::new(
        vec![vec![1.0, 0.0], vec![1.0]],
        vec![0.5, 0.5],
        bx.0.clone(),
        bx.1.clone(),
    )
    .unwrap_err();
    assert_eq!(name_of(e), "row 2 of a");
    let e = Polytope::new(
        vec![vec![1.0, 0.0]],
        vec![0.5, 0.5],
        bx.0.clone(),
        bx.1.clone(),
    )
    .unwrap_err();
    assert_eq!(name_of(e), "b");
    let e = Polytope::new(vec![vec![0.0, 0.0]], vec![0.5], bx.0.clone(), bx.1.clone()).unwrap_err();
    assert_eq!(name_of(e), "row 1 of a");
    // x ≤ −0.5 and −x ≤ −0.5 (x ≥ 0.5): empty.
    let e = Polytope::new(
        vec![vec![1.0, 0.0], vec![-1.0, 0.0]],
        vec![-0.5, -0.5],
        bx.0.clone(),
        bx.1.clone(),
    )
    .unwrap_err();
    let msg = e.to_string();
    assert!(
        msg.contains("polytope") && msg.contains("inscribed") && msg.contains("[-1, 1] × [-1, 1]"),
        "{msg}"
    );
    // x ≤ 0 and x ≥ 0: flat.
    let e = Polytope::new(
        vec![vec![1.0, 0.0], vec![-1.0, 0.0]],
        vec![0.0, 0.0],
        bx.0.clone(),
        bx.1.clone(),
    )
    .unwrap_err();
    assert_eq!(name_of(e), "polytope");
    // A valid one reports its inscribed ball: the square [-1, 1]² cut by x + y ≤ 0.
    let p = Polytope::new(vec![vec![1.0, 1.0]], vec![0.0], bx.0, bx.1).unwrap();
    let r_in = 2.0 / (2.0 + 2f64.sqrt());
    assert!(
        (p.inradius() - r_in).abs() < 1e-5 * r_in,
        "{}",
        p.inradius()
    );
    assert!(p.contains(p.interior_point()));
}

/// A non-convex region in three dimensions: the union of two slabs crossing like a plus
/// sign, extruded. From inside its centre the nearest boundary is a reflex edge; from the
/// notch between the arms, two faces tie.
#[test]
fn reflex_edges_in_three_dimensions() {
    let slab =
        |p: &[f64], a: f64, b: f64| (p[0].abs() - a).max(p[1].abs() - b).max(p[2].abs() - 1.0);
    let cross = ImplicitRegion::new(
        Arc::new(move |p: &[f64]| slab(p, 1.0, 0.3).min(slab(p, 0.3, 1.0))),
        vec![-1.1; 3],
        vec![1.1; 3],
    )
    .unwrap();
    let mut foot = [0.0; 3];
    // Inside, near the reflex edge x = y = 0.3.
    let d = cross
        .closest_boundary_point(&[0.2, 0.2, 0.1], &mut foot)
        .unwrap();
    assert!((d - 0.02f64.sqrt()).abs() < 1e-9, "{d} {foot:?}");
    assert!(
        (foot[0] - 0.3).abs() < 1e-7 && (foot[1] - 0.3).abs() < 1e-7,
        "{foot:?}"
    );
    // Outside, in the notch: the faces y = 0.3 and x = 0.3 are both 0.2 away.
    let d = cross
        .closest_boundary_point(&[0.5, 0.5, 0.2], &mut foot)
        .unwrap();
    assert!((d - 0.2).abs() < 1e-9, "{d} {foot:?}");
    // Outside beyond the end of an arm, off its corner: the corner edge (1, 0.3, z).
    let d = cross
        .closest_boundary_point(&[1.05, 0.4, 0.0], &mut foot)
        .unwrap();
    assert!((d - 0.05f64.hypot(0.1)).abs() < 1e-9, "{d} {foot:?}");
    let (mut y, mut prev) = (vec![0.5, 0.5, 0.2], vec![0.0; 3]);
    cross.bring_back(&mut y, &mut prev);
    assert!(
        cross.contains(&y) && (dist(&y, &[0.5, 0.5, 0.2]) - 0.2).abs() < 1e-7,
        "{y:?}"
    );
}

/// Eberly's special cases: points on the coordinate planes of the ellipsoid, including
/// its centre, where the closest point leaves the plane of the smallest axis.
#[test]
fn ellipsoid_points_on_its_axis_planes() {
    let ell = Ellipsoid::new(vec![1.0, -1.0, 0.5], vec![3.0, 2.0, 1.0]).unwrap();
    let generic = ell.to_implicit().unwrap();
    let mut foot = [0.0; 3];
    let d = ell
        .closest_boundary_point(&[1.0, -1.0, 0.5], &mut foot)
        .unwrap();
    assert!(
        (d - 1.0).abs() < 1e-15 && (foot[2] - 0.5).abs() == 1.0,
        "{d} {foot:?}"
    );
    let pts = [
        [1.5, -1.0, 0.5],
        [1.0, -0.2, 0.5],
        [3.8, -1.0, 0.5],
        [1.0, -1.0, 1.2],
        [1.0, -1.0, 2.5],
        [6.0, -1.0, 0.5],
        [2.0, 0.3, 0.5],
        [-1.5, -2.5, 0.5],
    ];
    for x in pts {
        let d = ell.closest_boundary_point(&x, &mut foot).unwrap();
        let lv = ell.level(&foot).unwrap();
        assert!(lv.abs() < 1e-13, "{x:?}: level(foot) = {lv}");
        let mut gf = [0.0; 3];
        let dg = generic.closest_boundary_point(&x, &mut gf).unwrap();
        assert!(
            (d - dg).abs() < 1e-9,
            "{x:?}: exact {d} {foot:?}, generic {dg} {gf:?}"
        );
    }
    // From (1.5, −1, 0.5), 0.5 along the longest axis: the closest point has
    // x = 3²·0.5/(3² − 1²) = 0.5625 off the centre and leaves the plane z = 0.5.
    let d = ell
        .closest_boundary_point(&[1.5, -1.0, 0.5], &mut foot)
        .unwrap();
    let z = (1.0 - (0.5625f64 / 3.0).powi(2)).sqrt();
    assert!((foot[0] - 1.5625).abs() < 1e-12 && ((foot[2] - 0.5).abs() - z).abs() < 1e-12);
    assert!((d - (0.0625f64.powi(2) + z * z).sqrt()).abs() < 1e-12);
}
