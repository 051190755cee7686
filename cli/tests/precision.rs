//! The DEM's `--precision`: the fast table drives the run by default, the energies a run
//! reports are the full formulas', and full precision is one option away.

use stillpoint::config::GenerateConfig;
use stillpoint::energies::{Distance, Energy, Precision};
use stillpoint::pipeline::run_config;
use stillpoint::plan::problem::choose_energy;

#[test]
fn a_fast_run_reports_full_precision_energies() {
    let mut cfg = GenerateConfig::new(120, 4);
    cfg.steps = 60;
    assert_eq!(cfg.precision, Precision::Fast);
    let r = run_config(&cfg, |_| {}).unwrap();
    let (full, _) = choose_energy(120, 4, None, None).unwrap();
    let Distance::Q(q) = full.distance() else {
        panic!("eq. 48 gives a numeric q");
    };
    assert!(Precision::fast_applies(q), "q = {q}");
    assert!(r.energy_name.contains("fast"), "{}", r.energy_name);
    assert_eq!(r.energy.0.to_bits(), full.value(&r.start).to_bits());
    // The result was shifted after the DEM; U_{q,p} is shift-invariant up to rounding.
    let end = full.value(&r.output.points);
    assert!(
        (r.energy.1 - end).abs() <= 1e-12 * end,
        "{} vs {end}",
        r.energy.1
    );
    // The trajectory's energies are the fast table's: within its bound, not equal.
    let last = r.output.trajectory.last().unwrap().energy;
    assert!((last - r.energy.1).abs() <= Precision::FAST_BOUND_H2 * end);
}

#[test]
fn full_precision_runs_the_formulas_and_differs_from_fast() {
    let mut cfg = GenerateConfig::new(120, 4);
    cfg.steps = 60;
    let fast = run_config(&cfg, |_| {}).unwrap();
    cfg.precision = Precision::Full;
    let full = run_config(&cfg, |_| {}).unwrap();
    assert!(!full.energy_name.contains("fast"));
    // Same start, same energy reported for it; the runs part in the last bits and more.
    assert_eq!(fast.energy.0.to_bits(), full.energy.0.to_bits());
    assert_ne!(fast.output.points.as_slice(), full.output.points.as_slice());
    // Both runs lower the energy from the same start by about as much.
    let drop = |r: &stillpoint::report::GenerateReport| (r.energy.0 - r.energy.1) / r.energy.0;
    let (a, b) = (drop(&fast), drop(&full));
    assert!(a > 0.0 && b > 0.0);
    assert!((a - b).abs() <= 0.05 * b, "{a} vs {b}");
}
