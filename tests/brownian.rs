//! Brownian paths in design spaces: the mapped columns have the Brownian covariance, are
//! named W_1 … W_m, read back from every file format, count as m dimensions (up to
//! 1 000 through the pipeline and the cubature), and bad parameters are refused naming
//! the option, the text as typed and what is accepted.

use stillpoint::cubature::{quad, Cubature, QuadOptions};
use stillpoint::design::path::{Brownian, Construction};
use stillpoint::design::{Column, Design, DesignSpace};
use stillpoint::pipeline::request::Arg;
use stillpoint::{PointSet, Request};

/// The design the library's pipeline makes for `items` at `n` points.
fn design(n: usize, items: &[&str], seed: u64) -> Design {
    let mut r = Request::default();
    r.set("n", Arg::Int(n as i128)).unwrap();
    r.set(
        "space",
        Arg::Texts(items.iter().map(|s| s.to_string()).collect()),
    )
    .unwrap();
    r.set("seed", Arg::Int(seed.into())).unwrap();
    r.resolve()
        .unwrap()
        .run(None, |_| {})
        .unwrap()
        .design
        .unwrap()
}

/// The design of `space` on an existing unit-scale set, as a mapping (no dealing).
fn mapped(space: &DesignSpace, unit: PointSet) -> Design {
    Design {
        levels: vec![Vec::new(); space.dim()],
        space: space.clone(),
        unit,
    }
}

fn reals(c: &Column) -> &[f64] {
    match c {
        Column::Real(v) => v,
        other => panic!("not a real column: {other:?}"),
    }
}

#[test]
fn the_mapped_columns_have_the_brownian_covariance() {
    // 2^16 random points: each covariance within 5 standard errors of min(t_i, t_j)
    // (the product of two normals with covariance c has variance ≤ 2 t_i t_j).
    let n = 1 << 16;
    for construction in ["standard", "bridge", "pca"] {
        let text = format!("W=brownian(2,6,{construction})");
        let space = DesignSpace::parse("--var", &[text.as_str()]).unwrap();
        let d = mapped(&space, stillpoint::sequences::random(n, 6, 11).unwrap());
        let cols = d.columns();
        let t: Vec<f64> = (1..=6).map(|i| i as f64 / 3.0).collect();
        for i in 0..6 {
            for j in 0..6 {
                let (a, b) = (reals(&cols[i]), reals(&cols[j]));
                let cov = a.iter().zip(b).map(|(x, y)| x * y).sum::<f64>() / n as f64;
                let se = (2.0 * t[i] * t[j] / n as f64).sqrt();
                let want = t[i].min(t[j]);
                assert!(
                    (cov - want).abs() < 5.0 * se,
                    "{construction} ({i},{j}): {cov} vs {want} ± {se}"
                );
            }
        }
    }
}

#[test]
fn columns_are_named_by_coordinate_and_the_space_shows_the_path_as_typed() {
    let d = design(32, &["S0=lognormal(0,0.2)", "W=brownian(1,8,bridge)"], 3);
    let names: Vec<&str> = d.space.vars.iter().map(|v| v.name.as_str()).collect();
    let want: Vec<String> = std::iter::once("S0".to_string())
        .chain((1..=8).map(|i| format!("W_{i}")))
        .collect();
    assert_eq!(names, want);
    assert_eq!(d.space.dim(), 9);
    assert_eq!(
        d.space.texts(),
        ["S0=lognormal(0,0.2)", "W=brownian(1,8,bridge)"]
    );
    // The texts parse back to the same space.
    assert_eq!(
        DesignSpace::parse("--var", &d.space.texts()).unwrap(),
        d.space
    );
    // The default construction is pca.
    let s = DesignSpace::parse("space", &["W=brownian(1,4)"]).unwrap();
    assert_eq!(s.texts(), ["W=brownian(1,4,pca)"]);
    // Every path column is the path of its own point: W = A Φ⁻¹(u) row by row.
    let path = Brownian {
        t: 1.0,
        m: 8,
        construction: Construction::Bridge,
    };
    let cols = d.columns();
    let u: Vec<f64> = (0..d.n())
        .flat_map(|i| d.unit.point(i)[1..9].to_vec())
        .collect();
    let w = path.paths(&u);
    for (k, col) in cols[1..].iter().enumerate() {
        for (i, &v) in reals(col).iter().enumerate() {
            assert_eq!(v, w[i * 8 + k]);
        }
    }
}

#[test]
fn a_design_with_a_path_reads_back_from_text_and_numbers() {
    let d = design(
        24,
        &["x=uniform(0,1)", "W=brownian(0.5,5,pca)", "c={a,b,c}"],
        9,
    );
    let text = d.to_text(&serde_json::json!({"space": d.space.texts()}), ',');
    let header = text.lines().find(|l| !l.starts_with('#')).unwrap();
    assert_eq!(header, "x,W_1,W_2,W_3,W_4,W_5,c");
    assert!(text.contains("W=brownian(0.5,5,pca)"), "{text}");
    let back = Design::from_text(&d.space, &text, "file").unwrap();
    for (a, b) in d.unit.as_slice().iter().zip(back.unit.as_slice()) {
        assert!((a - b).abs() < 1e-9, "{a} vs {b}");
    }
    assert_eq!(back.levels, d.levels);
    // Without labels, the numbers (as .npy and .json hold them) read back too.
    let d = design(16, &["W=brownian(3,4,standard)"], 1);
    let back = Design::from_numbers(&d.space, &d.numbers().unwrap(), "file.npy").unwrap();
    for (a, b) in d.unit.as_slice().iter().zip(back.unit.as_slice()) {
        assert!((a - b).abs() < 1e-9, "{a} vs {b}");
    }
}

#[test]
fn bad_paths_are_refused_naming_the_option_the_text_and_what_is_accepted() {
    for (item, says) in [
        ("W=brownian(0,4)", "T = 0"),
        ("W=brownian(-2,4,bridge)", "T = -2"),
        ("W=brownian(1,0)", "m = 0"),
        ("W=brownian(1,5000)", "m = 5000"),
        ("W=brownian(1,4,cholesky)", "cholesky"),
        ("W=brownian(1,4", "closing parenthesis"),
    ] {
        let e = DesignSpace::parse("--var", &[item])
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("--var") && e.contains(item) && e.contains(says),
            "{item}: {e}"
        );
    }
    let e = DesignSpace::parse("--var", &["W=brownian(1,4,cholesky)"])
        .unwrap_err()
        .to_string();
    assert!(e.contains("pca (the default), bridge or standard"), "{e}");
    // A name the path's columns would take twice.
    let e = DesignSpace::parse("--var", &["W_2=normal(0,1)", "W=brownian(1,3)"])
        .unwrap_err()
        .to_string();
    assert!(e.contains("W_2 is already a variable"), "{e}");
}

#[test]
fn a_correlation_never_takes_a_path() {
    let mut s = DesignSpace::parse(
        "--var",
        &["x=normal(0,1)", "y=normal(0,1)", "W=brownian(1,2)"],
    )
    .unwrap();
    // A matrix that counts W_1, W_2 is refused naming the path.
    let eye4: Vec<f64> = (0..16)
        .map(|k| if k % 5 == 0 { 1.0 } else { 0.0 })
        .collect();
    let e = s
        .correlate("--correlation", "I4", eye4)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("--correlation") && e.contains("W=brownian(1,2,pca)") && e.contains("2 × 2"),
        "{e}"
    );
    // The other continuous variables take theirs; the path stays a Brownian motion.
    s.correlate_rows("--correlation", "1,0.8;0.8,1").unwrap();
    let n = 1 << 14;
    let d = mapped(&s, stillpoint::sequences::random(n, 4, 5).unwrap());
    let cols = d.columns();
    let cov = |a: usize, b: usize| {
        reals(&cols[a])
            .iter()
            .zip(reals(&cols[b]))
            .map(|(x, y)| x * y)
            .sum::<f64>()
            / n as f64
    };
    assert!((cov(0, 1) - 0.8).abs() < 0.05, "{}", cov(0, 1));
    assert!((cov(2, 3) - 0.5).abs() < 0.05, "{}", cov(2, 3));
    assert!(cov(0, 3).abs() < 0.05, "{}", cov(0, 3));
    // A space with a path and one other continuous variable has nothing to correlate.
    let mut s = DesignSpace::parse("--var", &["x=normal(0,1)", "W=brownian(1,2)"]).unwrap();
    assert!(s.correlate_rows("--correlation", "1,0.5;0.5,1").is_err());
}

#[test]
fn a_thousand_step_path_goes_through_the_pipeline_and_the_cubature() {
    let d = design(8, &["W=brownian(1,1000,pca)"], 2);
    assert_eq!(d.unit.s(), 1000);
    let cols = d.columns();
    assert_eq!(cols.len(), 1000);
    assert_eq!(d.space.vars[999].name, "W_1000");
    assert!(cols.iter().all(|c| reals(c).iter().all(|x| x.is_finite())));
    // The cubature reaches 1 000 dimensions: E[W(1)²] = 1 from the path of a 1000-step
    // space (the sum over the pca coordinates of λ_k v_k(m)² is exactly T).
    let space = DesignSpace::parse("space", &["W=brownian(1,1000,pca)"]).unwrap();
    let options = QuadOptions {
        abs_tol: 0.05,
        rel_tol: 0.0,
        max_n: 1 << 14,
        ..QuadOptions::default()
    };
    let r = quad(
        |batch: &PointSet| {
            // The cube's points stay off 1 (as quad's front ends keep them).
            let w = mapped(&space, batch.clone()).columns();
            reals(&w[999]).iter().map(|x| x * x).collect()
        },
        1000,
        options,
    )
    .unwrap();
    assert!(r.met, "{r:?}");
    assert!((r.estimate[0] - 1.0).abs() < 0.1, "{r:?}");
    assert!(Cubature::new(1001, QuadOptions::default()).is_err());
}
