//! The solver comparison on a small case: every run improves on its Halton start, the
//! discrepancy energy equals the squared metric, and the files are written.

use stillpoint::energies::discrepancy::DiscrepancyKind;
use stillpoint::{metrics, sequences};
use stillpoint_paper::compare::{run_and_write, CompareSettings};

#[test]
fn small_comparison_improves_on_halton_and_writes_its_files() {
    let dir = std::env::temp_dir().join(format!("stillpoint-compare-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let settings = CompareSettings {
        cases: vec![(2, 120)],
        steps: 150,
        log_every: 10,
        discrepancy: DiscrepancyKind::ModifiedL2,
    };
    let table = run_and_write(&settings, &dir, false).unwrap();
    let halton = metrics::modified_l2(&sequences::halton(120, 2).unwrap());
    let json: serde_json::Value =
        serde_json::from_slice(&std::fs::read(dir.join("comparison.json")).unwrap()).unwrap();
    let rows = json.as_array().unwrap();
    assert_eq!(rows.len(), 5, "{table}");
    for r in rows {
        let md = r["modified_l2"].as_f64().unwrap();
        assert!(md < halton, "{}: D_MD {md} vs Halton {halton}", r["solver"]);
        if r["energy"].as_str().unwrap().contains("D²")
            || r["energy"].as_str().unwrap().contains("MD")
        {
            let e = r["final_energy"].as_f64().unwrap();
            assert!(
                (e - md * md).abs() < 1e-10,
                "energy {e} vs D_MD² {}",
                md * md
            );
        }
    }
    assert!(std::fs::read(dir.join("convergence_s2_n120.png"))
        .unwrap()
        .starts_with(b"\x89PNG"));
    assert!(table.contains("L-BFGS") && table.contains("DEM"));
    let _ = std::fs::remove_dir_all(&dir);
}
