//! Properties of the damped central-difference DEM.

mod common;
use common::Budget;
use stillpoint_energies::{Distance, Domain, Energy, PeriodicCube, PointSet, Uqp};
use stillpoint_integrators::{
    Control, Dem, DemState, Kappa, NoObserver, Observer, Record, Restart, StopReason,
};

/// Calls a closure on every observed state.
struct Check<F: FnMut(&Record, &PointSet)>(F);

impl<F: FnMut(&Record, &PointSet)> Observer for Check<F> {
    fn observe(&mut self, record: &mut Record, points: &PointSet) -> Control {
        (self.0)(record, points);
        Control::Continue
    }
}

fn mean_gap(x: &PointSet) -> f64 {
    x.mean().iter().map(|m| (m - 0.5).abs()).fold(0.0, f64::max)
}

#[test]
fn energy_falls_from_a_random_start() {
    let cube = PeriodicCube::new(2).unwrap();
    let start = cube.sample(64, 3).unwrap();
    let e = Uqp::new(Distance::Q(0.3), 1.0).unwrap();
    let dem = Budget(300, Dem { ..Dem::default() });
    let out = dem.run(&e, &cube, start.clone(), &mut NoObserver).unwrap();
    let u0 = e.value(&start);
    let u1 = e.value(&out.points);
    // The gradient path sums pairs in another order than `value`: equal to rounding.
    let close = |a: f64, b: f64| (a - b).abs() <= 1e-12 * b.abs();
    assert!(close(out.trajectory.first().unwrap().energy, u0));
    assert!(close(out.trajectory.last().unwrap().energy, u1));
    // U_{q,p} is dominated by far pairs, so its relative drop is small; the nearest
    // neighbours, which it pushes apart, show the change.
    assert!(u1 < 0.99 * u0, "energy {u0} -> {u1}");
    let dmin = |x: &PointSet| {
        let mut m = f64::INFINITY;
        for i in 0..x.n() {
            for j in i + 1..x.n() {
                m = m.min(Distance::Torus.squared(x.point(i), x.point(j)).sqrt());
            }
        }
        m
    };
    assert!(
        dmin(&out.points) > 2.0 * dmin(&start),
        "{} -> {}",
        dmin(&start),
        dmin(&out.points)
    );
    // Most steps lower the energy (restarts and momentum allow a few rises).
    let falls = out
        .trajectory
        .windows(2)
        .filter(|w| w[1].energy <= w[0].energy)
        .count();
    assert!(falls * 10 >= out.trajectory.len() * 9, "{falls}");
}

#[test]
fn restart_keeps_the_mean_within_eps() {
    let cube = PeriodicCube::new(3).unwrap();
    let start = cube.sample(40, 11).unwrap();
    let eps = 0.004;
    let e = Uqp::new(Distance::Q(0.5), 0.8).unwrap();
    let dem = Budget(
        200,
        Dem {
            restart: Restart::Threshold(eps),
            ..Dem::default()
        },
    );
    let mut worst: f64 = 0.0;
    let mut seen = 0;
    let out = dem
        .run(
            &e,
            &cube,
            start,
            &mut Check(|r: &Record, x: &PointSet| {
                if r.step > 0 {
                    worst = worst.max(mean_gap(x));
                    seen += 1;
                }
            }),
        )
        .unwrap();
    assert!(seen >= 200);
    assert!(worst <= eps + 1e-12, "mean gap {worst} > {eps}");
    assert!(out.info("restarts").unwrap() >= 1.0, "no restart happened");
    assert!(mean_gap(&out.points) <= eps + 1e-12);
}

#[test]
fn wrap_keeps_points_in_the_unit_cube_and_uses_the_torus() {
    // Two close points near the face repel until they are half a period apart on the
    // circle: one of them must cross the face to get there.
    let cube = PeriodicCube::new(1).unwrap();
    let start = PointSet::from_rows(&[[0.97], [0.99]]).unwrap();
    let e = Uqp::new(Distance::Torus, 1.0).unwrap();
    let dem = Budget(
        3000,
        Dem {
            restart: Restart::Off,
            ..Dem::default()
        },
    );
    let mut inside = true;
    let out = dem
        .run(
            &e,
            &cube,
            start,
            &mut Check(|_: &Record, x: &PointSet| {
                inside &= x.rows().all(|r| cube.contains(r));
            }),
        )
        .unwrap();
    assert!(inside);
    let (a, b) = (out.points.point(0)[0], out.points.point(1)[0]);
    let gap = (a - b).abs();
    assert!((gap - 0.5).abs() < 1e-3, "{a} {b}");
    assert!(a < 0.5 || b < 0.5, "no point crossed the face: {a} {b}");
}

#[test]
fn evenly_spaced_circle_is_reached() {
    // On the circle, n evenly spaced points minimise U_{q,p}: every gap is 1/n.
    let n = 9;
    let cube = PeriodicCube::new(1).unwrap();
    let start = cube.sample(n, 5).unwrap();
    for q in [Distance::Torus, Distance::Q(1.0), Distance::Q(0.3)] {
        let e = Uqp::new(q, 1.0).unwrap();
        let dem = Budget(5000, Dem { ..Dem::default() });
        let out = dem.run(&e, &cube, start.clone(), &mut NoObserver).unwrap();
        let mut v = out.points.as_slice().to_vec();
        v.sort_by(f64::total_cmp);
        let mut gaps: Vec<f64> = v.windows(2).map(|w| w[1] - w[0]).collect();
        gaps.push(1.0 - v[n - 1] + v[0]);
        for g in &gaps {
            assert!((g - 1.0 / n as f64).abs() < 1e-6, "{q:?}: gaps {gaps:?}");
        }
    }
}

#[test]
fn kappa_trial_enlarges_an_unstable_kappa() {
    let cube = PeriodicCube::new(2).unwrap();
    let start = cube.sample(50, 1).unwrap();
    let e = Uqp::new(Distance::Q(0.3), 1.0).unwrap();
    let dem = Budget(
        60,
        Dem {
            kappa: Kappa::Auto {
                start: 1.0,
                factor: 2.0,
                trial_steps: 20,
                max: 1e8,
            },
            ..Dem::default()
        },
    );
    let out = dem.run(&e, &cube, start, &mut NoObserver).unwrap();
    let kappa = out.info("kappa").unwrap();
    assert!(kappa > 1.0, "κ stayed at {kappa}");
    assert!(out.info("kappa_trials").unwrap() >= 2.0);
    for w in out.trajectory[..20].windows(2) {
        assert!(w[1].energy < w[0].energy);
    }
    assert_eq!(out.trajectory.len(), 61);
    assert_eq!(out.stop, StopReason::StepBudget);
}

#[test]
fn same_bits_for_one_and_two_threads() {
    let cube = PeriodicCube::new(3).unwrap();
    let start = cube.sample(150, 2).unwrap();
    let e = Uqp::new(Distance::Q(0.2), 0.7).unwrap();
    let dem = Budget(60, Dem { ..Dem::default() });
    let run = |t: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(t)
            .build()
            .unwrap()
            .install(|| {
                let out = dem.run(&e, &cube, start.clone(), &mut NoObserver).unwrap();
                out.points
                    .as_slice()
                    .iter()
                    .map(|v| v.to_bits())
                    .collect::<Vec<_>>()
            })
    };
    assert_eq!(run(1), run(2));
}

#[test]
fn bad_settings_are_refused() {
    let cube = PeriodicCube::new(2).unwrap();
    let e = Uqp::new(Distance::Q(0.3), 1.0).unwrap();
    let outside = PointSet::from_rows(&[[0.2, 0.3], [1.2, 0.5]]).unwrap();
    let err = Budget(1000, Dem::default())
        .run(&e, &cube, outside, &mut NoObserver)
        .unwrap_err();
    assert!(err.to_string().contains("start point 2"), "{err}");
    let wrong_dim = PointSet::from_rows(&[[0.2], [0.4]]).unwrap();
    assert!(Budget(1000, Dem::default())
        .run(&e, &cube, wrong_dim, &mut NoObserver)
        .is_err());
    let ok = cube.sample(5, 1).unwrap();
    let bad = Dem {
        kappa: Kappa::Fixed(0.5),
        ..Dem::default()
    };
    let err = Budget(1000, bad)
        .run(&e, &cube, ok.clone(), &mut NoObserver)
        .unwrap_err();
    assert!(err.to_string().contains("kappa"), "{err}");
    let coincident = PointSet::from_rows(&[[0.2, 0.3], [0.2, 0.3]]).unwrap();
    let err = Budget(1000, Dem::default())
        .run(&e, &cube, coincident, &mut NoObserver)
        .unwrap_err();
    assert!(err.to_string().contains("coincide"), "{err}");
}

/// Runs `dem` once with a snapshot every `every` steps, then continues from each
/// snapshot and checks that the points, energies and info are the same bits.
fn resumes_bit_for_bit(
    dem: &Budget<Dem>,
    e: &dyn stillpoint_energies::Energy,
    domain: &dyn Domain,
    start: &PointSet,
    every: usize,
) {
    let (full, states) = common::run_with_snapshots(dem, e, domain, start, every);
    let plain = dem.run(e, domain, start.clone(), &mut NoObserver).unwrap();
    assert_eq!(
        common::run_bits(&full),
        common::run_bits(&plain),
        "snapshots changed the run"
    );
    assert!(!states.is_empty(), "no snapshot was taken");
    for state in states {
        let step = state.step;
        let resumed = common::resume(dem, e, domain, start, state).unwrap();
        assert_eq!(
            common::run_bits(&resumed),
            common::run_bits(&full),
            "from step {step}"
        );
    }
}

#[test]
fn a_resumed_run_is_the_same_bits_as_an_uninterrupted_one() {
    // Restarts (tight ε_p), the κ trial and convergence all cross snapshots.
    let cube = PeriodicCube::new(2).unwrap();
    let start = cube.sample(40, 4).unwrap();
    let e = Uqp::new(Distance::Q(0.3), 0.8).unwrap();
    let dem = Budget(
        150,
        Dem {
            restart: Restart::Threshold(0.002),
            ..Dem::default()
        },
    );
    resumes_bit_for_bit(&dem, &e, &cube, &start, 7);
    // κ trial from 1: snapshots during failed trials are taken and continued too.
    let dem = Budget(
        60,
        Dem {
            kappa: Kappa::Auto {
                start: 1.0,
                factor: 2.0,
                trial_steps: 20,
                max: 1e8,
            },
            ..Dem::default()
        },
    );
    resumes_bit_for_bit(&dem, &e, &cube, &start, 3);
    // A non-smooth energy: the lowest state is kept and returned.
    let einf = stillpoint_energies::einf::UEInf::new(Distance::Torus).unwrap();
    let dem = Budget(80, Dem { ..Dem::default() });
    resumes_bit_for_bit(&dem, &einf, &cube, &start, 10);
}

#[test]
fn a_state_of_another_run_is_refused() {
    let cube = PeriodicCube::new(2).unwrap();
    let start = cube.sample(30, 1).unwrap();
    let e = Uqp::new(Distance::Q(0.3), 0.8).unwrap();
    let dem = Budget(40, Dem::default());
    let (_, snaps) = common::run_with_snapshots(&dem, &e, &cube, &start, 10);
    let state = snaps.last().unwrap().clone();
    let resume = |dem: &Budget<Dem>, e: &dyn Energy, start: &PointSet, st| {
        common::resume(dem, e, &cube, start, st)
            .map(|_| ())
            .unwrap_err()
            .to_string()
    };
    // Another energy, another start, a shorter budget, a damaged buffer.
    let other = Uqp::new(Distance::Q(0.4), 0.8).unwrap();
    assert!(resume(&dem, &other, &start, state.clone()).contains("another run"));
    let start2 = cube.sample(30, 2).unwrap();
    assert!(resume(&dem, &e, &start2, state.clone()).contains("another run"));
    let short = Budget(20, dem.1.clone());
    assert!(resume(&short, &e, &start, state.clone()).contains("step"));
    // A buffer cut short, or a coordinate that is not a finite number, does not even
    // read back: a point set is checked whenever it is made.
    let mut v = serde_json::to_value(&state).unwrap();
    v["state"]["current"]["data"].as_array_mut().unwrap().pop();
    let cut = serde_json::from_value::<stillpoint_integrators::Snapshot<DemState>>(v);
    assert!(cut.unwrap_err().to_string().contains("length"));
    let mut v = serde_json::to_value(&state).unwrap();
    v["state"]["previous"]["data"][3] = serde_json::Value::Null;
    assert!(serde_json::from_value::<stillpoint_integrators::Snapshot<DemState>>(v).is_err());
    // A forged coordinate far outside the torus is refused by the domain.
    let mut v = serde_json::to_value(&state).unwrap();
    v["state"]["current"]["data"][3] = serde_json::json!(1e300);
    let forged: stillpoint_integrators::Snapshot<DemState> = serde_json::from_value(v).unwrap();
    assert!(resume(&dem, &e, &start, forged).contains("inside the domain"));
    let fixed = Budget(
        40,
        Dem {
            kappa: Kappa::Fixed(300.0),
            ..dem.1.clone()
        },
    );
    assert!(resume(&fixed, &e, &start, state).contains("κ"));
}
