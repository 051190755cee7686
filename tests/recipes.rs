//! The recipes of ARCHITECTURE.md that no other test walks: each goal is reached by a
//! request and runs. A new `Goal` variant does not compile here until it is given a
//! request, and the test fails until that request reaches it and the run gives a set.

use stillpoint::config::Goal;
use stillpoint::pipeline::request::{Arg, Job};
use stillpoint::pipeline::run_config;
use stillpoint::Request;

/// The goals a request can reach, by index; exhaustive on purpose.
fn goal_index(g: &Goal) -> usize {
    match g {
        Goal::Paper => 0,
        Goal::Integration(_) => 1,
        Goal::SpaceFilling => 2,
    }
}

/// One request per goal, in [`goal_index`]'s order.
const REQUESTS: [&[(&str, &str)]; 3] = [&[("method", "paper")], &[], &[("goal", "space-filling")]];

#[test]
fn every_goal_is_reached_by_a_request_and_runs() {
    let mut seen = [false; REQUESTS.len()];
    for options in REQUESTS {
        let mut r = Request::new(24, 2);
        for (name, value) in options {
            r.set(name, Arg::from(*value)).unwrap();
        }
        let Job::Run(cfg) = r.resolve().unwrap().job else {
            panic!("{options:?} resolves to a baseline, not a run");
        };
        seen[goal_index(&cfg.goal)] = true;
        let report = run_config(&cfg, |_| {}).unwrap();
        let p = &report.output.points;
        assert_eq!((p.n(), p.s()), (24, 2), "{options:?}");
        assert!(
            p.as_slice().iter().all(|x| (0.0..1.0).contains(x)),
            "{options:?}: a point outside [0, 1)^2"
        );
    }
    let missing: Vec<usize> = (0..seen.len()).filter(|&k| !seen[k]).collect();
    assert!(missing.is_empty(), "goals no request reaches: {missing:?}");
}
