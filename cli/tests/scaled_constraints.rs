//! Linear constraints at extreme scales: coefficients near the ends of the float range
//! mean what they say (1e300*x1 <= 1e299 is x1 <= 0.1), and a polytope that fills a
//! tiny share of its box (a simplex of side 1e-6 in [0, 1]^6) is run like any other.

mod common;
use common::*;

/// The points `generate` writes for `args` (a `-o` file is added), failing the test with
/// its standard error when it fails.
fn points(d: &TempDir, args: &[&str]) -> stillpoint::PointSet {
    let out = d.path("p.csv");
    let _ = std::fs::remove_file(&out);
    succeeded(
        bin()
            .args(["generate", "-q"])
            .args(args)
            .arg("-o")
            .arg(&out),
        &args,
    );
    stillpoint::io::read_points(&out).unwrap()
}

#[test]
fn huge_and_tiny_coefficients_are_the_constraint_they_write() {
    let d = TempDir::new("scaled");
    // Each constraint with the coordinate it bounds and the bound, x_k <= 0.1.
    for (text, k) in [
        ("1e300*x1 <= 1e299", 0),
        ("1e-300*x1 <= 1e-301", 0),
        ("-1e300*x2 >= -1e299", 1),
    ] {
        let p = points(&d, &["-n", "12", "--constraint", text, "--box", "0,1,0,1"]);
        assert_eq!(p.n(), 12, "{text}");
        for x in p.rows() {
            assert!(x[k] <= 0.1 + 1e-12 && x[k] >= 0.0, "{text}: {x:?}");
        }
        // The cut leaves the rest of the box open: the points are not squeezed into it.
        let other = p.rows().map(|x| x[1 - k]).fold(0.0, f64::max);
        assert!(other > 0.5, "{text}: largest other coordinate {other}");
    }
}

#[test]
fn a_polytope_in_a_tiny_share_of_its_box_is_run() {
    let d = TempDir::new("tiny-simplex");
    let unit6 = "0,1,0,1,0,1,0,1,0,1,0,1";
    for (text, bound) in [
        ("x1+x2+x3+x4+x5+x6 <= 1e-6", 1e-6),
        ("x1+x2+x3+x4+x5+x6 <= 1e-3", 1e-3),
        ("2*x1+x2+x3+x4+x5+x6 <= 1e-5", 1e-5),
    ] {
        let started = std::time::Instant::now();
        let p = points(&d, &["-n", "15", "--constraint", text, "--box", unit6]);
        assert!(started.elapsed().as_secs() < 60, "{text}");
        assert_eq!(p.n(), 15);
        for x in p.rows() {
            let weighted = x.iter().sum::<f64>() + if text.starts_with('2') { x[0] } else { 0.0 };
            assert!(
                x.iter().all(|&v| v >= 0.0) && weighted <= bound * (1.0 + 1e-9),
                "{text}: {x:?}"
            );
        }
        // Spread, not stacked: the points are distinct.
        let mut seen: Vec<Vec<u64>> = p
            .rows()
            .map(|x| x.iter().map(|v| v.to_bits()).collect())
            .collect();
        seen.sort();
        seen.dedup();
        assert_eq!(seen.len(), 15, "{text}");
    }
}
