//! The paper's claim for the DEM with U_{q,p} from plain Halton (Table 5).
//!
//! CI runs a small version (n = 300) that checks the direction and size of the effect;
//! the full P_{2,1500} and P_{3,1500} runs are `#[ignore]`d and run with
//! `cargo test --release --test paper -- --ignored --nocapture`.

use stillpoint::config::GenerateConfig;
use stillpoint::pipeline::run_config;
use stillpoint::quality::metrics;

struct Outcome {
    start: (f64, f64),
    dem: f64,
    result: (f64, f64),
    kappa: f64,
    steps: usize,
}

fn run(n: usize, s: usize) -> Outcome {
    let cfg = GenerateConfig::new(n, s);
    let r = run_config(&cfg, |_| {}).expect("generate");
    let sh = r
        .shift
        .as_ref()
        .expect("the default runs a shift selection");
    Outcome {
        start: (
            r.cube_metrics().unwrap().0.modified_l2,
            r.cube_metrics().unwrap().0.star_l2,
        ),
        dem: sh.modified_l2_before,
        result: (
            metrics::modified_l2(&r.output.points),
            metrics::star_l2(&r.output.points),
        ),
        kappa: r.output.info("kappa").unwrap(),
        steps: r.output.trajectory.last().unwrap().step,
    }
}

fn report(name: &str, o: &Outcome, paper: (f64, f64)) {
    eprintln!(
        "{name}: Halton D_MD {:.6} D_L2 {:.6} | DEM D_MD {:.6} | DEM + shift D_MD {:.6} D_L2 {:.6} \
         | paper U_qp row D_MD {:.6} D_L2 {:.6} | κ {} | {} steps",
        o.start.0, o.start.1, o.dem, o.result.0, o.result.1, paper.0, paper.1, o.kappa, o.steps
    );
}

#[test]
fn small_dem_from_halton_lowers_both_discrepancies() {
    for s in [2, 3] {
        let o = run(300, s);
        report(&format!("P_{{{s},300}}"), &o, (f64::NAN, f64::NAN));
        assert!(
            o.dem < 0.8 * o.start.0,
            "s={s}: DEM D_MD {} vs Halton {}",
            o.dem,
            o.start.0
        );
        assert!(o.result.0 <= o.dem);
        assert!(
            o.result.1 < 0.8 * o.start.1,
            "s={s}: D_L2 {} vs {}",
            o.result.1,
            o.start.1
        );
    }
}

#[test]
#[ignore = "about two minutes in release: cargo test --release --test paper -- --ignored"]
fn table5_p2_1500() {
    let o = run(1500, 2);
    report("P_{2,1500}", &o, (0.000932, 0.000652));
    // An independent implementation of the same equations reached D_MD 0.00113 and
    // D_L2 0.00091 after 1000 steps; the paper's row is 0.000932 and 0.000652.
    assert!(o.result.0 < 0.00113 && o.result.1 < 0.00091);
    assert!(o.result.0 < 0.000932 && o.result.1 < 0.000652);
}

#[test]
#[ignore = "about four minutes in release: cargo test --release --test paper -- --ignored"]
fn table5_p3_1500() {
    let o = run(1500, 3);
    report("P_{3,1500}", &o, (0.001986, 0.000965));
    assert!(o.result.0 < 0.00204 && o.result.1 < 0.00103);
}

#[test]
fn polish_lowers_the_chosen_discrepancy() {
    use stillpoint::energies::discrepancy::DiscrepancyKind;
    let mut cfg = GenerateConfig::new(300, 3);
    let plain = run_config(&cfg, |_| {}).unwrap();
    cfg.polish = Some(DiscrepancyKind::ModifiedL2);
    let polished = run_config(&cfg, |_| {}).unwrap();
    let (before, after, _) = polished.polish.unwrap();
    let md_plain = metrics::modified_l2(&plain.output.points);
    let md_polished = metrics::modified_l2(&polished.output.points);
    assert!((before.sqrt() - md_plain).abs() < 1e-12);
    assert!((after.sqrt() - md_polished).abs() < 1e-12);
    assert!(md_polished < 0.95 * md_plain, "{md_plain} -> {md_polished}");
    assert!(polished.output.points.check_unit_cube().is_ok());
}
