//! Properties of the L-BFGS integrator: gradients it reaches, known optima, regions,
//! kinks, the trajectory it reports, determinism and refusals.

mod common;
use common::Budget;
use std::sync::Arc;
use stillpoint_energies::boundary::UEpG;
use stillpoint_energies::einf::UEInf;
use stillpoint_energies::shapes::Ball;
use stillpoint_energies::{Distance, Domain, Energy, Error, PeriodicCube, PointSet, Uqp};
use stillpoint_integrators::lbfgs::Lbfgs;
use stillpoint_integrators::{
    Control, Dem, Integrator, NoObserver, Observer, Record, RunOutput, StopReason,
};

/// Calls a closure on every observed state and returns what it says.
struct Check<F: FnMut(&Record, &PointSet) -> Control>(F);

impl<F: FnMut(&Record, &PointSet) -> Control> Observer for Check<F> {
    fn observe(&mut self, record: &mut Record, points: &PointSet) -> Control {
        (self.0)(record, points)
    }
}

fn grad_max_norm(e: &dyn Energy, x: &PointSet) -> f64 {
    let mut g = vec![0.0; x.coordinate_count()];
    e.value_and_gradient(x, &mut g);
    g.iter().fold(0.0, |m, v| m.max(v.abs()))
}

fn close(a: f64, b: f64, rel: f64) -> bool {
    (a - b).abs() <= rel * b.abs().max(a.abs())
}

fn info(out: &RunOutput, key: &str) -> f64 {
    out.info(key)
        .unwrap_or_else(|| panic!("info {key} missing: {:?}", out.info))
}

/// Energies never rise along the trajectory, steps count up from 0, the last record is
/// the returned state.
fn check_trajectory(e: &dyn Energy, out: &RunOutput) {
    let t = &out.trajectory;
    assert_eq!(t[0].step, 0);
    for w in t.windows(2) {
        assert_eq!(w[1].step, w[0].step + 1);
        assert!(
            w[1].energy <= w[0].energy,
            "{} -> {}",
            w[0].energy,
            w[1].energy
        );
        assert!(w[1].max_move > 0.0);
    }
    let last = t.last().unwrap();
    assert!(close(last.energy, e.value(&out.points), 1e-12));
    assert_eq!(last.step as f64, info(out, "iterations"));
}

#[test]
fn smooth_uqp_on_the_torus_reaches_a_small_gradient() {
    let cube = PeriodicCube::new(2).unwrap();
    let start = cube.sample(12, 5).unwrap();
    for q in [1.0, 0.5] {
        let e = Uqp::new(Distance::Q(q), 1.0).unwrap();
        let g0 = grad_max_norm(&e, &start);
        let out = Budget(1000, Lbfgs::default())
            .run(&e, &cube, start.clone(), &mut NoObserver)
            .unwrap();
        let g1 = grad_max_norm(&e, &out.points);
        let (u0, u1) = (e.value(&start), e.value(&out.points));
        eprintln!(
            "U_(q={q},p=1) n=12 s=2: U {u0:.12} -> {u1:.12}, |g|inf {g0:.3e} -> {g1:.3e} \
             ({:.1e} relative), {} iterations, {} evaluations, {} restarts, stop {:?}",
            g1 / g0,
            info(&out, "iterations"),
            info(&out, "evaluations"),
            info(&out, "restarts"),
            out.stop
        );
        assert!(g1 < 1e-6 * g0, "q = {q}: gradient {g0} -> {g1}");
        assert!(u1 < u0);
        assert!(out.points.rows().all(|r| cube.contains(r)));
        assert!(close(info(&out, "final_grad_norm"), g1, 1e-6) || g1 < 1e-9 * g0);
        check_trajectory(&e, &out);
    }
}

/// The pair distance on the circle as a function of Δ ∈ (0, 1).
type PairDistance = fn(f64) -> f64;

/// U_{q,p} (p = 1) of n evenly spaced points on the circle, from the closed form: each
/// point sees the others at Δ = k/n, k = 1..n−1, so S = (n/2) Σ_k d(k/n)^{−1}.
fn even_circle_energy(n: usize, d: impl Fn(f64) -> f64) -> f64 {
    let sum: f64 = (1..n).map(|k| 1.0 / d(k as f64 / n as f64)).sum();
    0.5 * n as f64 * sum
}

fn sorted_gaps(x: &PointSet) -> Vec<f64> {
    let mut v: Vec<f64> = x.as_slice().to_vec();
    v.sort_by(f64::total_cmp);
    let mut gaps: Vec<f64> = v.windows(2).map(|w| w[1] - w[0]).collect();
    gaps.push(1.0 + v[0] - v[v.len() - 1]);
    gaps
}

#[test]
fn nine_points_on_the_circle_reach_the_even_spacing() {
    let n = 9;
    let circle = PeriodicCube::new(1).unwrap();
    let start = circle.sample(n, 17).unwrap();
    let cases: [(Distance, PairDistance); 2] = [
        (Distance::Torus, |t| t.min(1.0 - t)),
        (Distance::Q(1.0), |t| t * (1.0 - t)),
    ];
    for (dist, d) in cases {
        let e = Uqp::new(dist, 1.0).unwrap();
        let exact = even_circle_energy(n, d);
        let even = PointSet::new(n, 1, (0..n).map(|i| i as f64 / n as f64).collect()).unwrap();
        assert!(close(e.value(&even), exact, 1e-13));

        let out = Budget(1000, Lbfgs::default())
            .run(&e, &circle, start.clone(), &mut NoObserver)
            .unwrap();
        let gaps = sorted_gaps(&out.points);
        let worst = gaps
            .iter()
            .map(|g| (g - 1.0 / n as f64).abs())
            .fold(0.0, f64::max);
        let u = e.value(&out.points);

        let dem = Budget(10_000, Dem { ..Dem::default() })
            .run(&e, &circle, start.clone(), &mut NoObserver)
            .unwrap();
        let u_dem = e.value(&dem.points);
        eprintln!(
            "circle n=9, q={}: worst gap error {worst:.2e}, U_lbfgs {u:.15}, U_dem {u_dem:.15}, \
             closed form {exact:.15} (rel {:.1e} / {:.1e}); {} iterations, {} evaluations; \
             DEM {} steps",
            dist.label(),
            (u - exact).abs() / exact,
            (u_dem - exact).abs() / exact,
            info(&out, "iterations"),
            info(&out, "evaluations"),
            dem.trajectory.len() - 1
        );
        assert!(worst < 1e-6, "q = {}: gaps {gaps:?}", dist.label());
        assert!(close(u, exact, 1e-9), "{u} vs closed form {exact}");
        assert!(close(u, u_dem, 1e-9), "{u} vs DEM {u_dem}");
        check_trajectory(&e, &out);
    }
}

/// Runs in the ball, checking every observed state; returns the output, how many
/// observed points were outside and how many records were seen.
fn run_in_ball(e: &dyn Energy, ball: &Ball, start: &PointSet) -> (RunOutput, usize, usize) {
    let mut outside = 0usize;
    let mut records = 0usize;
    let out = Budget(300, Lbfgs { ..Lbfgs::default() })
        .run(
            e,
            ball,
            start.clone(),
            &mut Check(|_: &Record, x: &PointSet| {
                records += 1;
                outside += x.rows().filter(|r| !ball.contains(r)).count();
                Control::Continue
            }),
        )
        .unwrap();
    (out, outside, records)
}

#[test]
fn in_a_ball_every_state_stays_inside_and_the_energy_falls() {
    let ball = Ball::new(vec![0.2, -0.1], 0.8).unwrap();
    let domain: Arc<dyn Domain> = Arc::new(ball.clone());
    let start = ball.sample(30, 9).unwrap();
    // U_{E,4,g} keeps the points off the wall; U_{q,p} with the Euclidean distance presses
    // them onto it, so L-BFGS runs over f∘P with points outside and projects.
    let barrier = UEpG::new(domain, 4.0).unwrap();
    let pressing = Uqp::new(Distance::Euclidean, 1.0).unwrap();
    for (name, e) in [
        ("U_(E,4,g)", &barrier as &dyn Energy),
        ("U_(E,1)", &pressing as &dyn Energy),
    ] {
        let (out, outside, records) = run_in_ball(e, &ball, &start);
        let (u0, u1) = (e.value(&start), e.value(&out.points));
        let on_wall = out
            .points
            .rows()
            .filter(|r| {
                let mut foot = [0.0; 2];
                ball.closest_boundary_point(r, &mut foot).unwrap() < 1e-6
            })
            .count();
        eprintln!(
            "ball, {name} n=30: U {u0:.6} -> {u1:.6}, |g|inf {:.3e} -> {:.3e}, {} iterations, \
             {} evaluations, restarts {} (projection {}, stall {}), {on_wall} points on the \
             wall, stop {:?}",
            info(&out, "start_grad_norm"),
            info(&out, "final_grad_norm"),
            info(&out, "iterations"),
            info(&out, "evaluations"),
            info(&out, "restarts"),
            info(&out, "projection_restarts"),
            info(&out, "stall_restarts"),
            out.stop
        );
        assert_eq!(records, out.trajectory.len());
        assert_eq!(outside, 0, "{name}");
        assert!(out.points.rows().all(|r| ball.contains(r)), "{name}");
        assert!(u1 < 0.9 * u0, "{name}: {u0} -> {u1}");
        check_trajectory(e, &out);
        if name == "U_(E,1)" {
            assert!(info(&out, "projection_restarts") >= 1.0);
            assert!(on_wall > 0);
        } else {
            assert_eq!(on_wall, 0);
        }
    }
}

fn torus_min_distance(x: &PointSet) -> f64 {
    let mut m = f64::INFINITY;
    for i in 0..x.n() {
        for j in i + 1..x.n() {
            m = m.min(Distance::Torus.squared(x.point(i), x.point(j)).sqrt());
        }
    }
    m
}

#[test]
fn a_max_type_energy_ends_without_error_after_restarts() {
    let cube = PeriodicCube::new(2).unwrap();
    let start = cube.sample(20, 4).unwrap();
    let e = UEInf::new(Distance::Torus).unwrap();
    let out = Budget(1000, Lbfgs::default())
        .run(&e, &cube, start.clone(), &mut NoObserver)
        .unwrap();
    let (d0, d1) = (torus_min_distance(&start), torus_min_distance(&out.points));
    eprintln!(
        "U_(E,inf) torus n=20 s=2: d_min {d0:.5} -> {d1:.5}, {} iterations, {} evaluations, \
         {} restarts, {} line-search failures, stop {:?}",
        info(&out, "iterations"),
        info(&out, "evaluations"),
        info(&out, "restarts"),
        info(&out, "line_search_failures"),
        out.stop
    );
    assert!(info(&out, "restarts") >= 1.0);
    let flagged = out.trajectory.iter().filter(|r| r.restarted).count();
    assert!(flagged >= 1 && flagged as f64 <= info(&out, "restarts"));
    assert!(d1 > 1.5 * d0, "{d0} -> {d1}");
    assert!(out.points.rows().all(|r| cube.contains(r)));
    check_trajectory(&e, &out);
}

#[test]
fn the_observer_sees_every_record_and_can_stop_the_run() {
    let cube = PeriodicCube::new(2).unwrap();
    let start = cube.sample(16, 2).unwrap();
    let e = Uqp::new(Distance::Q(0.5), 1.0).unwrap();
    let u0 = e.value(&start);
    let mut seen: Vec<(usize, f64)> = Vec::new();
    let out = Budget(1000, Lbfgs::default())
        .run(
            &e,
            &cube,
            start.clone(),
            &mut Check(|r: &Record, x: &PointSet| {
                assert!(x.rows().all(|p| cube.contains(p)));
                seen.push((r.step, r.energy));
                if seen.len() == 5 {
                    Control::Stop
                } else {
                    Control::Continue
                }
            }),
        )
        .unwrap();
    assert_eq!(out.stop, StopReason::Observer);
    assert_eq!(out.trajectory.len(), 5);
    assert_eq!(seen.len(), 5);
    assert!(close(seen[0].1, u0, 1e-12));
    for (k, (step, u)) in seen.iter().enumerate() {
        assert_eq!(*step, k);
        assert_eq!(out.trajectory[k].energy, *u);
    }
    assert!(seen[4].1 < seen[0].1);
    check_trajectory(&e, &out);

    // Without a stop the run goes on past five records; a zero budget records the start.
    let full = Budget(1000, Lbfgs::default())
        .run(&e, &cube, start.clone(), &mut NoObserver)
        .unwrap();
    assert!(full.trajectory.len() > 5);
    for (a, b) in full.trajectory.iter().zip(&out.trajectory) {
        assert_eq!((a.step, a.energy.to_bits()), (b.step, b.energy.to_bits()));
    }
    let none = Budget(0, Lbfgs { ..Lbfgs::default() })
        .run(&e, &cube, start.clone(), &mut NoObserver)
        .unwrap();
    assert_eq!(none.trajectory.len(), 1);
    assert_eq!(none.stop, StopReason::StepBudget);
    assert_eq!(none.points, start);
}

#[test]
fn same_bits_for_one_and_two_threads() {
    let cube = PeriodicCube::new(3).unwrap();
    let start = cube.sample(40, 21).unwrap();
    let e = Uqp::new(Distance::Q(0.3), 0.8).unwrap();
    let run = |threads: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| {
                Budget(200, Lbfgs { ..Lbfgs::default() })
                    .run(&e, &cube, start.clone(), &mut NoObserver)
                    .unwrap()
            })
    };
    let (a, b) = (run(1), run(2));
    let bits = |x: &PointSet| x.as_slice().iter().map(|v| v.to_bits()).collect::<Vec<_>>();
    assert_eq!(bits(&a.points), bits(&b.points));
    assert_eq!(a.trajectory.len(), b.trajectory.len());
    for (r, s) in a.trajectory.iter().zip(&b.trajectory) {
        assert_eq!(r.energy.to_bits(), s.energy.to_bits());
        assert_eq!(r.max_move.to_bits(), s.max_move.to_bits());
        assert_eq!(r.restarted, s.restarted);
    }
    assert_eq!(a.info, b.info);
}

#[test]
fn bad_settings_are_refused() {
    let cube = PeriodicCube::new(2).unwrap();
    let start = cube.sample(8, 1).unwrap();
    let e = Uqp::new(Distance::Q(1.0), 1.0).unwrap();
    let refuse = |l: Lbfgs, x: PointSet, name: &str| match Budget(1000, l).run(
        &e,
        &cube,
        x,
        &mut NoObserver,
    ) {
        Err(Error::InvalidArgument { name: got, .. }) => {
            assert!(got.contains(name), "{got} does not name {name}")
        }
        other => panic!("expected a refusal naming {name}, got {other:?}"),
    };
    refuse(
        Lbfgs {
            memory: 0,
            ..Lbfgs::default()
        },
        start.clone(),
        "memory",
    );
    refuse(
        Lbfgs {
            tol_grad: -1.0,
            ..Lbfgs::default()
        },
        start.clone(),
        "tol_grad",
    );
    refuse(
        Lbfgs {
            tol_cost: f64::NAN,
            ..Lbfgs::default()
        },
        start.clone(),
        "tol_cost",
    );
    let mut outside = start.clone();
    outside.point_mut(3)[1] = 1.0;
    refuse(Lbfgs::default(), outside, "start point 4");
    let wrong_dim = PeriodicCube::new(3).unwrap().sample(8, 1).unwrap();
    refuse(Lbfgs::default(), wrong_dim, "dimension");

    let mut twins = start.clone();
    let p0 = twins.point(0).to_vec();
    twins.point_mut(1).copy_from_slice(&p0);
    match Budget(1000, Lbfgs::default()).run(&e, &cube, twins, &mut NoObserver) {
        Err(Error::Numerical(msg)) => assert!(msg.contains("not finite"), "{msg}"),
        other => panic!("expected a numerical error, got {other:?}"),
    }
}

#[test]
fn name_shows_the_memory() {
    assert_eq!(Lbfgs::default().name(), "L-BFGS(m=10)");
    let l = Lbfgs::default();
    assert_eq!((l.memory, l.max_restarts), (10, 20));
}
