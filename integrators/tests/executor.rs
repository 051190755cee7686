//! The executor runs any integrator: a new one defined here (plain gradient descent with a
//! fixed step) gets records, observers, keep-best and checkpoints without touching any
//! other file; the DEM and L-BFGS resume bit for bit from any snapshot; forged snapshots
//! are refused, never a panic.

mod common;
use common::{resume, run_bits, run_with_snapshots, Budget};
use serde::{Deserialize, Serialize};
use stillpoint_energies::discrepancy::{DiscrepancyEnergy, DiscrepancyKind};
use stillpoint_energies::shapes::{Ball, BoxRegion};
use stillpoint_energies::{Distance, Domain, Energy, Error, PeriodicCube, PointSet, Result, Uqp};
use stillpoint_integrators::lbfgs::Lbfgs;
use stillpoint_integrators::{
    Control, Dem, Executor, Integrator, Move, Observer, Problem, Record, Snapshot, Step, StopReason,
};

/// Gradient descent x ← x − h ∇U(x), each point kept inside by the domain's rule.
#[derive(Debug, Clone)]
struct Descent {
    h: f64,
}

#[derive(Debug, Clone, Serialize, Deserialize)]
struct DescentState {
    points: PointSet,
}

impl Integrator for Descent {
    type State = DescentState;

    fn name(&self) -> String {
        format!("descent(h={})", self.h)
    }

    fn init(&self, problem: &Problem<'_>, start: PointSet) -> Result<(DescentState, f64)> {
        problem.check_inside("start point", &start)?;
        let u = problem.energy().value(&start);
        Ok((DescentState { points: start }, u))
    }

    fn step(&self, problem: &Problem<'_>, st: &mut DescentState) -> Result<Step> {
        let s = st.points.s();
        let mut grad = vec![0.0; st.points.coordinate_count()];
        problem.energy().value_and_gradient(&st.points, &mut grad);
        let mut max_move: f64 = 0.0;
        let mut prev = vec![0.0; s];
        let mut to = vec![0.0; s];
        for (x, g) in st
            .points
            .as_mut_slice()
            .chunks_exact_mut(s)
            .zip(grad.chunks_exact(s))
        {
            for k in 0..s {
                to[k] = x[k] - self.h * g[k];
            }
            prev.copy_from_slice(x);
            problem.domain().keep_inside(x, &mut to, &mut prev);
            for k in 0..s {
                max_move = max_move.max((to[k] - x[k]).abs());
            }
            x.copy_from_slice(&to);
        }
        let energy = problem.energy().value(&st.points);
        let mv = Move {
            energy,
            max_move,
            restarted: false,
        };
        Ok(if max_move < 1e-15 {
            Step::Converged(mv)
        } else {
            Step::Moved(mv)
        })
    }

    fn points<'s>(&self, st: &'s DescentState) -> &'s PointSet {
        &st.points
    }

    fn info(&self, _st: &DescentState) -> Vec<(String, f64)> {
        vec![("h".to_string(), self.h)]
    }

    fn check_state(
        &self,
        problem: &Problem<'_>,
        start: &PointSet,
        st: &DescentState,
    ) -> Result<()> {
        if st.points.n() != start.n() {
            return Err(Error::invalid("checkpoint n", st.points.n(), "the run's n"));
        }
        problem.check_inside("checkpoint point", &st.points)
    }
}

/// Counts records and stops after `stop_at` of them.
struct Counter {
    seen: Vec<usize>,
    stop_at: usize,
}

impl Observer for Counter {
    fn observe(&mut self, record: &mut Record, points: &PointSet) -> Control {
        record.metrics.push(("n".into(), points.n() as f64));
        self.seen.push(record.step);
        if self.seen.len() >= self.stop_at {
            Control::Stop
        } else {
            Control::Continue
        }
    }
}

fn cube_problem() -> (Uqp, PeriodicCube, PointSet) {
    let cube = PeriodicCube::new(2).unwrap();
    let start = cube.sample(30, 3).unwrap();
    (Uqp::new(Distance::Q(0.3), 0.8).unwrap(), cube, start)
}

#[test]
fn a_new_integrator_gets_records_observers_and_checkpoints() {
    let (e, cube, start) = cube_problem();
    let problem = Problem::borrowed(&e, &cube).unwrap();
    // Fixed step small enough for this energy's scale (its gradient is about 1e2).
    let h = 1e-6;
    let mut obs = Counter {
        seen: Vec::new(),
        stop_at: usize::MAX,
    };
    let out = Executor::new(&problem, Descent { h })
        .max_steps(25)
        .observe(&mut obs)
        .run(start.clone())
        .unwrap();
    assert_eq!(out.stop, StopReason::StepBudget);
    assert_eq!(out.trajectory.len(), 26);
    assert_eq!(obs.seen, (0..=25).collect::<Vec<_>>());
    assert!(out
        .trajectory
        .iter()
        .all(|r| r.metrics == [("n".into(), 30.0)]));
    assert!(out.trajectory.last().unwrap().energy < out.trajectory[0].energy);
    assert!(out.points.rows().all(|r| cube.contains(r)));
    assert_eq!(out.info[0], ("returned_step".to_string(), 25.0));
    assert_eq!(out.info[1], ("h".to_string(), h));
    // The observer stops the run.
    let mut obs = Counter {
        seen: Vec::new(),
        stop_at: 4,
    };
    let stopped = Executor::new(&problem, Descent { h })
        .max_steps(25)
        .observe(&mut obs)
        .run(start.clone())
        .unwrap();
    assert_eq!(stopped.stop, StopReason::Observer);
    assert_eq!(stopped.trajectory.len(), 4);
    // Checkpoints and resume, through JSON, to the same bits from every snapshot.
    let b = Budget(25, Descent { h });
    let (full, snaps) = run_with_snapshots(&b, &e, &cube, &start, 4);
    assert_eq!(run_bits(&full), run_bits(&out));
    assert_eq!(snaps.len(), 6);
    for snap in snaps {
        let step = snap.step;
        let resumed = resume(&b, &e, &cube, &start, snap).unwrap();
        assert_eq!(run_bits(&resumed), run_bits(&full), "from step {step}");
    }
}

#[test]
fn lbfgs_resumes_bit_for_bit_from_every_snapshot() {
    // A discrepancy in the closed cube (kinks, stalls and restarts) and U_{q,p} on the
    // torus, then a ball where iterates leave and are projected back.
    let (e, cube, start) = cube_problem();
    let closed = BoxRegion::new(vec![0.0; 2], vec![1.0; 2]).unwrap();
    let md = DiscrepancyEnergy::new(DiscrepancyKind::ModifiedL2);
    let ball = Ball::new(vec![0.0, 0.0], 1.0).unwrap();
    let ball_arc: std::sync::Arc<dyn Domain> = std::sync::Arc::new(ball.clone());
    let in_ball = ball.sample(25, 2).unwrap();
    let epg = stillpoint_energies::boundary::UEpG::new(ball_arc.clone(), 4.0).unwrap();
    let cases: Vec<(&dyn Energy, &dyn Domain, &PointSet)> = vec![
        (&md, &closed, &start),
        (&e, &cube, &start),
        (&epg, ball_arc.as_ref(), &in_ball),
    ];
    for (k, (energy, domain, x0)) in cases.into_iter().enumerate() {
        let b = Budget(60, Lbfgs::default());
        let (full, snaps) = run_with_snapshots(&b, energy, domain, x0, 3);
        let plain = b
            .run(
                energy,
                domain,
                x0.clone(),
                &mut stillpoint_integrators::NoObserver,
            )
            .unwrap();
        assert_eq!(run_bits(&full), run_bits(&plain), "case {k}");
        assert!(!snaps.is_empty(), "case {k}: no snapshot");
        for snap in snaps {
            let step = snap.step;
            let resumed = resume(&b, energy, domain, x0, snap).unwrap();
            assert_eq!(
                run_bits(&resumed),
                run_bits(&full),
                "case {k}, from step {step}"
            );
        }
    }
}

#[test]
fn forged_snapshots_are_refused_without_a_panic() {
    let (e, cube, start) = cube_problem();
    for which in ["dem", "lbfgs"] {
        let text = match which {
            "dem" => {
                let (_, s) = run_with_snapshots(&Budget(30, Dem::default()), &e, &cube, &start, 10);
                serde_json::to_value(s.last().unwrap()).unwrap()
            }
            _ => {
                let (_, s) =
                    run_with_snapshots(&Budget(30, Lbfgs::default()), &e, &cube, &start, 2);
                serde_json::to_value(s.last().unwrap()).unwrap()
            }
        };
        let forge = |path: &[&str], value: serde_json::Value| {
            let mut v = text.clone();
            let mut cur = &mut v;
            for p in path {
                cur = match p.parse::<usize>() {
                    Ok(i) => &mut cur[i],
                    Err(_) => &mut cur[*p],
                };
            }
            *cur = value;
            v
        };
        let forged = [
            forge(&["state", "current", "data", "0"], serde_json::json!(1e300)),
            forge(&["state", "current", "data", "0"], serde_json::json!(-0.5)),
            forge(&["state", "current", "n"], serde_json::json!(7)),
            forge(&["step"], serde_json::json!(100000)),
            forge(&["trajectory"], serde_json::json!([])),
            forge(&["integrator"], serde_json::json!("something else")),
            forge(&["seconds"], serde_json::json!(-1.0)),
        ];
        for (i, v) in forged.into_iter().enumerate() {
            let err = match which {
                "dem" => serde_json::from_value::<Snapshot<stillpoint_integrators::DemState>>(v)
                    .map_err(|e| e.to_string())
                    .and_then(|s| {
                        resume(&Budget(30, Dem::default()), &e, &cube, &start, s)
                            .map_err(|e| e.to_string())
                    }),
                _ => {
                    serde_json::from_value::<Snapshot<stillpoint_integrators::lbfgs::LbfgsState>>(v)
                        .map_err(|e| e.to_string())
                        .and_then(|s| {
                            resume(&Budget(30, Lbfgs::default()), &e, &cube, &start, s)
                                .map_err(|e| e.to_string())
                        })
                }
            };
            assert!(err.is_err(), "{which} forgery {i} was accepted");
        }
    }
}

#[test]
fn a_problem_checks_that_energy_and_domain_agree() {
    let ball: std::sync::Arc<dyn Domain> =
        std::sync::Arc::new(Ball::new(vec![0.0, 0.0], 1.0).unwrap());
    let other: std::sync::Arc<dyn Domain> =
        std::sync::Arc::new(Ball::new(vec![0.0, 0.0], 2.0).unwrap());
    let e: std::sync::Arc<dyn Energy> =
        std::sync::Arc::new(stillpoint_energies::boundary::UEInfG::new(ball.clone()).unwrap());
    assert!(Problem::shared(e.clone(), ball.clone()).is_ok());
    let err = Problem::shared(e.clone(), other).unwrap_err().to_string();
    assert!(err.contains("domain"), "{err}");
    let tied = Problem::tied(e).unwrap();
    assert_eq!(tied.dim(), 2);
    let cube = PeriodicCube::new(2).unwrap();
    let u = Uqp::new(Distance::Q(0.3), 0.8).unwrap();
    assert!(Problem::tied(std::sync::Arc::new(u)).is_err());
    assert!(Problem::new(Uqp::new(Distance::Q(0.3), 0.8).unwrap(), cube).is_ok());
}
