//! Goals checked through the request that chooses them: the parts of the goals' tests
//! that need the resolver above them (the goals' crate sits below it).

use stillpoint::config::Goal;
use stillpoint::pipeline::request::Job;
use stillpoint::quality::target::Target;
use stillpoint::report::GenerateReport;
use stillpoint::Request;

#[test]
fn target_words_and_nested_sets_resolve_to_their_blends() {
    // `--target blend-smooth` by name weighs its smooth part as the smooth blend does
    // at that s, and `curved` names the default from s = 15.
    for (word, want) in [
        ("blend-smooth", Target::smooth_blend_for(15)),
        ("curved", Target::curved()),
    ] {
        let mut r = Request::new(200, 15);
        r.target = Some(word.into());
        let Job::Run(cfg) = r.resolve().unwrap().job else {
            panic!("a run")
        };
        assert_eq!(cfg.goal, Goal::Integration(want));
    }
    // A nested set, which no check against Sobol' sets guards, keeps the smooth blend.
    let mut r = Request::new(0, 10);
    r.n = None;
    r.nested = Some("16,32".into());
    let Job::Run(cfg) = r.resolve().unwrap().job else {
        panic!("a run")
    };
    assert_eq!(cfg.goal, Goal::Integration(Target::smooth_blend_for(10)));
}

fn run(shape: &str, s: usize, n: usize, seed: u64) -> GenerateReport {
    let r = Request {
        n: Some(n.into()),
        s: Some(s.into()),
        shape: Some(shape.into()),
        goal: Some("integration".into()),
        seed: Some(seed.into()),
        ..Request::default()
    };
    let Job::Run(cfg) = r.resolve().unwrap().job else {
        panic!("a run")
    };
    stillpoint::pipeline::generate_with(&cfg, None, |_| {}).unwrap()
}

/// A set in a region by the integration goal is inside, lower than its start, and seeded.
#[test]
fn a_region_set_is_inside_lower_than_its_start_and_seeded() {
    let a = run("ball:1", 3, 60, 4);
    let (q0, q1) = a.region_metrics().unwrap();
    assert_eq!(q1.fraction_inside, 1.0);
    assert!(
        q1.energy_distance < q0.energy_distance,
        "start {} result {}",
        q0.energy_distance,
        q1.energy_distance
    );
    assert!(a.energy.1 < a.energy.0);
    assert_eq!(a.output.points, run("ball:1", 3, 60, 4).output.points);
    assert_ne!(a.output.points, run("ball:1", 3, 60, 5).output.points);
}
