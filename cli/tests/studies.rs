//! The paper's studies in their quick form: each runs end to end, writes its report, JSON
//! and pictures, and shows what must hold (the DEM beats random sampling, the references
//! converge, a catalog resumes to the same bytes).

use serde_json::Value;
use std::path::PathBuf;
use stillpoint_paper::studies::{self, spearman, Study, StudyOptions};

fn temp_dir(tag: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("stillpoint-studies-{tag}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn run_quick(study: Study, dir: &std::path::Path) -> Value {
    let mut opts = StudyOptions::new(true, dir.join(study.name()));
    opts.catalog_dir = dir.join("catalog");
    let out = studies::run(study, &opts, &mut |_| {}).unwrap();
    for f in &out.files {
        assert!(f.exists(), "{} missing", f.display());
    }
    assert!(out.markdown.contains("stillpoint study"));
    let written: Value = serde_json::from_slice(
        &std::fs::read(
            dir.join(study.name())
                .join(format!("{}.json", study.name())),
        )
        .unwrap(),
    )
    .unwrap();
    assert_eq!(written, out.json);
    out.json
}

#[test]
fn spearman_matches_reference_values_and_handles_ties() {
    // Reference values from scipy.stats.spearmanr.
    let r = spearman(&[1.0, 2.0, 2.0, 3.0], &[1.0, 3.0, 2.0, 4.0]).unwrap();
    assert!((r - 0.9486832980505139).abs() < 1e-12, "{r}");
    let r = spearman(
        &[3.1, 0.2, 5.5, 5.5, 1.0, 2.2],
        &[10.0, 2.0, 7.0, 9.0, 1.0, 1.0],
    )
    .unwrap();
    assert!((r - 0.6176470588235294).abs() < 1e-12, "{r}");
    // Any increasing map of one side keeps ρ = 1; a decreasing one gives −1.
    let a: Vec<f64> = (0..50).map(|i| (i as f64 * 0.37).sin()).collect();
    let b: Vec<f64> = a.iter().map(|x| x.exp()).collect();
    let c: Vec<f64> = a.iter().map(|x| -x * x * x).collect();
    assert!((spearman(&a, &b).unwrap() - 1.0).abs() < 1e-12);
    assert!((spearman(&a, &c).unwrap() + 1.0).abs() < 1e-12);
    assert!(spearman(&a, &vec![1.0; 50]).is_none());
    assert!(spearman(&a[..3], &b[..4]).is_none());
}

#[test]
fn study_names_parse_and_unknown_ones_are_refused() {
    for s in Study::all() {
        assert_eq!(Study::parse(s.name()).unwrap(), s);
    }
    assert_eq!(Study::parse("table7").unwrap(), Study::KraichnanOrszag);
    let e = Study::parse("table9").unwrap_err().to_string();
    assert!(e.contains("study") && e.contains("table5"), "{e}");
}

#[test]
fn correlation_quick_dem_beats_random_and_rho_is_computed() {
    let dir = temp_dir("corr");
    let v = run_quick(Study::Correlation, &dir);
    let cases = v["cases"].as_array().unwrap();
    assert_eq!(cases.len(), 5);
    for c in cases {
        for k in ["rho_1_l2", "rho_1_md", "rho_e_l2", "rho_e_md"] {
            let r = c[k].as_f64().unwrap();
            assert!((-1.0..=1.0).contains(&r), "{k} = {r}");
        }
        let fin = &c["final"];
        let dem = fin["DEM U_{1,1}"]["modified_l2"].as_f64().unwrap();
        let random = fin["random"]["modified_l2"].as_f64().unwrap();
        assert!(
            dem < random,
            "n={} s={}: DEM {dem} vs random {random}",
            c["n"],
            c["s"]
        );
        let start = c["dem_u11_start"]["modified_l2"].as_f64().unwrap();
        let end = c["dem_u11_end"]["modified_l2"].as_f64().unwrap();
        assert!(end < start, "the DEM must lower D_MD from its random start");
    }
    for f in ["fig3_p2_20.png", "fig4_by_n.png", "fig5_by_s.png"] {
        assert!(dir.join("correlation").join(f).exists(), "{f}");
    }
}

#[test]
fn table5_quick_dem_beats_random_halton_and_sobol() {
    let dir = temp_dir("t5");
    let v = run_quick(Study::Table5, &dir);
    for c in v["cases"].as_array().unwrap() {
        let dem = c["dem"]["modified_l2"].as_f64().unwrap();
        let pol = c["dem_polish_md"]["modified_l2"].as_f64().unwrap();
        assert!(pol <= dem + 1e-15, "the polish never makes D_MD worse");
        for b in ["random", "halton", "sobol", "halton-scrambled", "lhs"] {
            let x = c["baselines"][b]["modified_l2"].as_f64().unwrap();
            assert!(dem < x, "s={}: DEM {dem} vs {b} {x}", c["s"]);
        }
    }
}

#[test]
fn catalog_quick_builds_resumes_to_the_same_bytes_and_feeds_table6() {
    let dir = temp_dir("cat");
    let v = run_quick(Study::Catalog, &dir);
    let sets = v["manifest"]["sets"].as_array().unwrap();
    assert_eq!(sets.len(), 9, "s = 2..4, n ∈ {{10, 20, 50}}, n ≥ 2s");
    for e in sets {
        assert!(e["modified_l2"].as_f64().unwrap() < e["start_modified_l2"].as_f64().unwrap());
    }
    // Interrupt: lose one set's file and the last manifest entry, then resume.
    let cat = dir.join("catalog");
    let victim = cat.join(sets[4]["file"].as_str().unwrap());
    let before = std::fs::read(&victim).unwrap();
    std::fs::remove_file(&victim).unwrap();
    let last = cat.join(sets[8]["file"].as_str().unwrap());
    let last_before = std::fs::read(&last).unwrap();
    let mut m: Value =
        serde_json::from_slice(&std::fs::read(cat.join("manifest.json")).unwrap()).unwrap();
    m["sets"].as_array_mut().unwrap().pop();
    std::fs::write(cat.join("manifest.json"), serde_json::to_vec(&m).unwrap()).unwrap();
    std::fs::remove_file(&last).unwrap();
    let v2 = run_quick(Study::Catalog, &dir);
    assert_eq!(v2["manifest"]["sets"].as_array().unwrap().len(), 9);
    assert_eq!(std::fs::read(&victim).unwrap(), before);
    assert_eq!(std::fs::read(&last).unwrap(), last_before);

    let t6 = run_quick(Study::Table6, &dir);
    for b in t6["baselines"].as_array().unwrap() {
        let rar = b["rar"].as_array().unwrap();
        assert_eq!(rar.len(), 10);
        for r in rar.iter().filter_map(|r| r.as_f64()) {
            assert!((0.0..=1.0).contains(&r));
        }
        assert_eq!(b["b1"].as_array().unwrap().len(), 9);
        if b["baseline"] == "random" {
            // D_MD: random never beats the DEM set of the same size.
            assert_eq!(rar[8].as_f64().unwrap(), 0.0, "{b}");
        }
    }
}

#[test]
fn kraichnan_orszag_quick_references_agree_and_dem_beats_random() {
    let dir = temp_dir("ko");
    let v = run_quick(Study::KraichnanOrszag, &dir);
    for k in ["mean", "sd"] {
        for e in v["monte_carlo_vs_gauss"][k].as_array().unwrap() {
            assert!(
                e.as_f64().unwrap() < 0.01,
                "MC and Gauss references differ: {v}"
            );
        }
    }
    let methods = v["methods"].as_array().unwrap();
    let get = |name: &str| {
        methods
            .iter()
            .find(|m| m["method"] == name)
            .unwrap_or_else(|| panic!("{name} missing"))["vs_gauss"]["mean"]
            .as_array()
            .unwrap()
            .iter()
            .map(|x| x.as_f64().unwrap())
            .fold(0.0, f64::max)
    };
    assert!(get("DEM U_{q,p}") < get("random"));
}

#[test]
fn shear_frame_quick_dem_beats_random() {
    let dir = temp_dir("frame");
    let v = run_quick(Study::ShearFrame, &dir);
    let methods = v["methods"].as_array().unwrap();
    let get = |name: &str| {
        methods.iter().find(|m| m["method"] == name).unwrap()["e_max_mean"]
            .as_f64()
            .unwrap()
    };
    assert!(get("DEM U_{q,p}") < get("random"));
    let ref_mean = v["reference"]["mean"].as_array().unwrap();
    let f: Vec<f64> = ref_mean.iter().map(|x| x.as_f64().unwrap()).collect();
    assert!(
        f.windows(2).all(|w| w[0] < w[1]),
        "frequencies ascend: {f:?}"
    );
}

#[test]
fn regions_quick_spreads_points_inside_every_region() {
    let dir = temp_dir("reg");
    let v = run_quick(Study::Regions, &dir);
    let (mut fill_start, mut fill_end) = (0.0, 0.0);
    for r in v["regions"].as_array().unwrap() {
        let red: Vec<f64> = r["reduction"]
            .as_array()
            .unwrap()
            .iter()
            .map(|x| x.as_f64().unwrap())
            .collect();
        assert!(red.iter().all(|&x| x > 0.5), "{r}");
        // U_{E,∞,g} keeps points half a spacing off the boundary, which can leave a thin
        // lobe emptier than a lucky random point did: the holes close on the whole, not
        // necessarily in every region at n = 30.
        fill_start += r["fill_distance_start"].as_f64().unwrap();
        fill_end += r["fill_distance_result"].as_array().unwrap()[1]
            .as_f64()
            .unwrap();
    }
    assert!(fill_end < 0.9 * fill_start, "{fill_end} vs {fill_start}");
}
