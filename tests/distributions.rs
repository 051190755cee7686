//! Marginal distributions: quantiles against known values and closed forms, CDF round
//! trips over grids reaching 1e-10 from either end, and refusals of bad parameters.

use stillpoint::design::dist::Marginal;
use stillpoint::Error;

const INF: f64 = f64::INFINITY;

fn normal(mu: f64, sigma: f64) -> Marginal {
    Marginal::Normal { mu, sigma }
}

fn beta(a: f64, b: f64) -> Marginal {
    Marginal::Beta {
        a,
        b,
        lo: 0.0,
        hi: 1.0,
    }
}

/// u from 1e-10 to 1 − 1e-10: a logarithmic grid toward each end plus a uniform one.
fn grid() -> Vec<f64> {
    let mut us = Vec::new();
    for k in 0..=50 {
        let t = 10f64.powf(-10.0 + 9.0 * k as f64 / 50.0);
        us.push(t);
        us.push(1.0 - t);
    }
    us.extend((1..100).map(|k| k as f64 / 100.0));
    us.sort_by(f64::total_cmp);
    us
}

/// Every variant with a range of parameters, all of them valid.
fn catalogue() -> Vec<Marginal> {
    let mut all = vec![
        Marginal::Uniform { lo: -3.0, hi: 7.5 },
        normal(0.0, 1.0),
        normal(3.0, 0.5),
        normal(-2.0, 10.0),
        Marginal::LogNormal {
            mu: 0.0,
            sigma: 1.0,
        },
        Marginal::LogNormal {
            mu: 2.0,
            sigma: 0.25,
        },
        Marginal::LogNormal {
            mu: -1.0,
            sigma: 2.0,
        },
        Marginal::Triangular {
            lo: 0.0,
            mode: 0.3,
            hi: 1.0,
        },
        Marginal::Triangular {
            lo: 0.0,
            mode: 0.0,
            hi: 1.0,
        },
        Marginal::Triangular {
            lo: -2.0,
            mode: 5.0,
            hi: 5.0,
        },
        Marginal::Beta {
            a: 2.0,
            b: 5.0,
            lo: -1.0,
            hi: 3.0,
        },
    ];
    for &(mu, sigma, lo, hi) in &[
        (0.0, 1.0, -1.0, 2.0),
        (0.0, 1.0, -INF, 0.5),
        (0.0, 1.0, -1.0, INF),
        (0.0, 1.0, 0.0, INF),
        (0.0, 1.0, 3.0, 5.0),
        (0.0, 1.0, -INF, -4.0),
        (0.0, 1.0, 8.0, INF),
        (2.0, 0.5, 2.5, 4.0),
    ] {
        all.push(Marginal::TruncNormal { mu, sigma, lo, hi });
    }
    let shapes = [0.3, 0.5, 1.0, 2.0, 5.0, 30.0];
    for &a in &shapes {
        for &b in &shapes {
            all.push(beta(a, b));
        }
    }
    all
}

/// Which variant a marginal is; exhaustive on purpose, so that a new variant does not
/// compile here until [`catalogue`] is told of it.
fn variant(m: &Marginal) -> usize {
    match m {
        Marginal::Uniform { .. } => 0,
        Marginal::Normal { .. } => 1,
        Marginal::TruncNormal { .. } => 2,
        Marginal::LogNormal { .. } => 3,
        Marginal::Beta { .. } => 4,
        Marginal::Triangular { .. } => 5,
    }
}

#[test]
fn the_catalogue_holds_every_variant() {
    let mut seen = [false; 6];
    for m in catalogue() {
        seen[variant(&m)] = true;
    }
    assert!(
        seen.iter().all(|&s| s),
        "variants missing from the catalogue: {seen:?}"
    );
}

fn close(x: f64, y: f64, rel: f64) -> bool {
    (x - y).abs() <= rel * y.abs().max(f64::MIN_POSITIVE)
}

#[test]
fn normal_quantiles_known_values() {
    let n = normal(0.0, 1.0);
    // Φ⁻¹ to 16 digits, as tabulated (and as SciPy's ndtri gives).
    for &(u, z) in &[
        (0.975, 1.959963984540054),
        (0.025, -1.959963984540054),
        (1e-10, -6.361340902404056),
        (0.5, 0.0),
        (0.841344746068543, 1.0),
    ] {
        let x = n.ppf(u);
        assert!(
            (x - z).abs() <= 2e-15 * z.abs().max(1.0),
            "Φ⁻¹({u}) = {x}, not {z}"
        );
    }
    let m = normal(10.0, 2.0);
    assert!(close(m.ppf(0.975), 10.0 + 2.0 * 1.959963984540054, 1e-15));
}

#[test]
fn normal_quantile_is_odd() {
    let n = normal(0.0, 1.0);
    for u in grid() {
        if u <= 0.5 {
            // 1 − u is exact for u ≤ 0.5 only when u is not too small; compare on the
            // double that 1 − u actually is.
            let v = 1.0 - u;
            let w = 1.0 - v;
            assert!(close(n.ppf(v), -n.ppf(w), 1e-15), "u = {u}");
        }
    }
}

#[test]
fn cdf_inverts_ppf_everywhere() {
    for m in catalogue() {
        m.check("x").unwrap();
        for u in grid() {
            let x = m.ppf(u);
            let back = m.cdf(x);
            // Where the density is steep (a beta shape below 1 next to its end) one ulp
            // of x moves the CDF by more than 1e-13: allow what the neighbours are worth.
            let ulp = m.cdf(x.next_up()) - m.cdf(x.next_down());
            assert!(
                (back - u).abs() <= 1e-13 + ulp,
                "{}: cdf(ppf({u})) = {back}",
                m.text()
            );
        }
    }
}

#[test]
fn lower_tails_keep_relative_precision() {
    // Where the lower end is 0 or −∞, a small u must come back to itself relatively, not
    // only to 1e-13: the quantile is not a rounded 0.
    let mut tails = vec![
        normal(0.0, 1.0),
        normal(-2.0, 10.0),
        Marginal::LogNormal {
            mu: 0.5,
            sigma: 0.7,
        },
        Marginal::TruncNormal {
            mu: 0.0,
            sigma: 1.0,
            lo: -INF,
            hi: 0.5,
        },
        Marginal::TruncNormal {
            mu: 0.0,
            sigma: 1.0,
            lo: 0.0,
            hi: INF,
        },
        Marginal::TruncNormal {
            mu: 0.0,
            sigma: 1.0,
            lo: 0.0,
            hi: 1.0,
        },
    ];
    for &a in &[0.3, 0.5, 1.0, 2.0, 5.0, 30.0] {
        for &b in &[0.3, 2.0, 30.0] {
            tails.push(beta(a, b));
        }
    }
    for m in tails {
        for k in 0..=60 {
            let u = 10f64.powf(-10.0 + 8.0 * k as f64 / 60.0);
            let back = m.cdf(m.ppf(u));
            assert!(
                close(back, u, 1e-12),
                "{}: cdf(ppf({u})) = {back}",
                m.text()
            );
        }
    }
}

#[test]
fn upper_tails_keep_relative_precision() {
    // Mirror image: 1 − cdf(ppf(1 − t)) = t where the upper end is +∞ (survival side).
    for m in [
        normal(0.0, 1.0),
        Marginal::TruncNormal {
            mu: 0.0,
            sigma: 1.0,
            lo: -1.0,
            hi: INF,
        },
        Marginal::TruncNormal {
            mu: 0.0,
            sigma: 1.0,
            lo: 1.0,
            hi: INF,
        },
    ] {
        for k in 0..=40 {
            let t = 10f64.powf(-10.0 + 8.0 * k as f64 / 40.0);
            let x = m.ppf(1.0 - t);
            // The reference is the exact survival of the standard normal from erfc.
            let (lo, z) = match m {
                Marginal::TruncNormal { lo, .. } => (lo, 0.5 * libm::erfc(lo / 2f64.sqrt())),
                _ => (-INF, 1.0),
            };
            assert!(lo < x);
            let sf = 0.5 * libm::erfc(x / 2f64.sqrt()) / z;
            // t itself is 1 − (1 − t) with 1 − t rounded: compare with what was asked.
            let asked = 1.0 - (1.0 - t);
            assert!(
                close(sf, asked, 1e-12),
                "{}: sf(ppf(1 − {t})) = {sf}",
                m.text()
            );
        }
    }
}

#[test]
fn quantiles_increase_and_stay_finite() {
    for m in catalogue() {
        let (lo, hi) = m.support();
        let mut last = f64::NEG_INFINITY;
        for k in 0..=20_000 {
            let u = k as f64 / 20_000.0;
            let x = m.ppf(u);
            assert!(x.is_finite(), "{}: ppf({u}) = {x}", m.text());
            assert!(x >= last, "{}: ppf decreases at {u}", m.text());
            assert!(lo <= x && x <= hi, "{}: ppf({u}) = {x} outside", m.text());
            last = x;
        }
        for u in [0.0, 1.0, -0.5, 2.0, 1.0 - f64::EPSILON / 2.0] {
            assert!(m.ppf(u).is_finite(), "{}: ppf({u})", m.text());
        }
        assert!(m.ppf(0.0) < m.ppf(1e-10) || m.bounded());
    }
    // A bounded distribution reaches its ends exactly.
    let b = Marginal::Beta {
        a: 2.0,
        b: 5.0,
        lo: -1.0,
        hi: 3.0,
    };
    assert_eq!((b.ppf(0.0), b.ppf(1.0)), (-1.0, 3.0));
    let t = Marginal::TruncNormal {
        mu: 0.0,
        sigma: 1.0,
        lo: -1.0,
        hi: 2.0,
    };
    assert_eq!((t.ppf(0.0), t.ppf(1.0)), (-1.0, 2.0));
    // An unbounded one stops 2⁻⁵³ short of them: Φ⁻¹(2⁻⁵³) ≈ −8.21.
    let z = normal(0.0, 1.0).ppf(0.0);
    assert!((-8.3..-8.1).contains(&z), "{z}");
    assert_eq!(normal(0.0, 1.0).ppf(1.0), -z);
}

#[test]
fn beta_special_cases_match_closed_forms() {
    // Beta(1, 1) is the uniform distribution.
    for u in grid() {
        assert!(close(beta(1.0, 1.0).ppf(u), u, 1e-14), "u = {u}");
    }
    // Beta(a, 1): F(x) = x^a, so ppf(u) = u^(1/a) (also solved by the general method).
    for &a in &[0.3, 0.5, 2.0, 5.0, 30.0] {
        for u in grid() {
            let x = beta(a, 1.0).ppf(u);
            assert!(close(x, u.powf(1.0 / a), 1e-13), "a = {a}, u = {u}: {x}");
        }
    }
    // Beta(1, b): F(x) = 1 − (1 − x)^b.
    for &b in &[0.3, 2.0, 30.0] {
        for u in grid() {
            let x = beta(1.0, b).ppf(u);
            let exact = -libm::expm1(libm::log1p(-u) / b);
            assert!(close(x, exact, 1e-13), "b = {b}, u = {u}: {x}");
        }
    }
    // Beta(2, 2): F(x) = 3x² − 2x³.
    for k in 0..=1000 {
        let x = k as f64 / 1000.0;
        let f = beta(2.0, 2.0).cdf(x);
        assert!(
            (f - (3.0 * x * x - 2.0 * x * x * x)).abs() < 1e-15,
            "x = {x}: {f}"
        );
    }
    // Beta(1/2, 1/2) is the arcsine law: F(x) = (2/π) asin(√x).
    for k in 1..1000 {
        let x = k as f64 / 1000.0;
        let exact = std::f64::consts::FRAC_2_PI * x.sqrt().asin();
        assert!(close(beta(0.5, 0.5).cdf(x), exact, 1e-14), "x = {x}");
    }
    // Symmetry: Beta(a, b) at u mirrors Beta(b, a) at 1 − u.
    for &(a, b) in &[(0.3, 5.0), (2.0, 30.0), (0.5, 2.0)] {
        for u in [1e-6, 0.1, 0.3, 0.5, 0.8] {
            let x = beta(a, b).ppf(u);
            let y = beta(b, a).ppf(1.0 - u);
            assert!(
                (x - (1.0 - y)).abs() < 1e-14,
                "{a},{b} at {u}: {x} vs 1 − {y}"
            );
        }
    }
    // Scaling to [lo, hi] is affine.
    let scaled = Marginal::Beta {
        a: 2.0,
        b: 5.0,
        lo: -1.0,
        hi: 3.0,
    };
    for u in [0.01, 0.5, 0.99] {
        assert!(close(
            scaled.ppf(u),
            -1.0 + 4.0 * beta(2.0, 5.0).ppf(u),
            1e-15
        ));
    }
}

#[test]
fn beta_known_quantile() {
    // Beta(2, 5)'s median (a reference value to 16 digits; the CDF 1 − 6(1−x)^5 +
    // 5(1−x)^6 at it is 1/2).
    let x = beta(2.0, 5.0).ppf(0.5);
    let y = 1.0 - x;
    let f = 1.0 - 6.0 * y.powi(5) + 5.0 * y.powi(6);
    assert!((f - 0.5).abs() < 1e-15, "{x}: F = {f}");
    assert!((x - 0.26444998329566).abs() < 1e-13, "{x}");
}

#[test]
fn triangular_matches_closed_form() {
    let t = Marginal::Triangular {
        lo: 1.0,
        mode: 2.0,
        hi: 5.0,
    };
    // F(mode) = (mode − lo)/(hi − lo) = 1/4; F(x) = (x − 1)²/4 below the mode and
    // 1 − (5 − x)²/12 above it.
    assert!(close(t.cdf(2.0), 0.25, 1e-15));
    assert!(close(t.ppf(0.25), 2.0, 1e-15));
    for u in grid() {
        let x = t.ppf(u);
        let exact = if u < 0.25 {
            1.0 + (4.0 * u).sqrt()
        } else {
            5.0 - (12.0 * (1.0 - u)).sqrt()
        };
        assert!(close(x, exact, 1e-15), "u = {u}: {x} vs {exact}");
    }
    // Degenerate modes at either end are right triangles.
    let right = Marginal::Triangular {
        lo: 0.0,
        mode: 0.0,
        hi: 1.0,
    };
    assert!(close(right.ppf(0.75), 0.5, 1e-15));
    let left = Marginal::Triangular {
        lo: 0.0,
        mode: 1.0,
        hi: 1.0,
    };
    assert!(close(left.ppf(0.25), 0.5, 1e-15));
}

#[test]
fn lognormal_is_exp_of_normal() {
    for &(mu, sigma) in &[(0.0, 1.0), (2.0, 0.25), (-1.0, 2.0)] {
        let l = Marginal::LogNormal { mu, sigma };
        for u in grid() {
            assert_eq!(l.ppf(u), normal(mu, sigma).ppf(u).exp());
        }
        assert_eq!(l.cdf(0.0), 0.0);
        assert_eq!(l.cdf(-1.0), 0.0);
    }
    // lognormal(0, 1)'s median is 1 and its 97.5% quantile e^1.959963984540054.
    let l = Marginal::LogNormal {
        mu: 0.0,
        sigma: 1.0,
    };
    assert!(close(l.ppf(0.5), 1.0, 1e-15));
    assert!(close(l.ppf(0.975), 7.099_071_384_231_335, 1e-14));
}

#[test]
fn truncnormal_reduces_to_normal() {
    // With one end at infinity and the other far away, nothing is truncated that a
    // double can see: the quantiles are the normal's.
    let n = normal(1.0, 2.0);
    for (lo, hi) in [(-INF, 1e3), (-1e3, INF)] {
        let t = Marginal::TruncNormal {
            mu: 1.0,
            sigma: 2.0,
            lo,
            hi,
        };
        for u in grid() {
            let (x, y) = (t.ppf(u), n.ppf(u));
            assert!(
                (x - y).abs() <= 1e-13 * y.abs().max(1.0),
                "u = {u}: {x} vs {y}"
            );
        }
    }
    // Truncated at the mean from below, it is the half-normal: F(x) = erf(x/√2).
    let half = Marginal::TruncNormal {
        mu: 0.0,
        sigma: 1.0,
        lo: 0.0,
        hi: INF,
    };
    for u in grid() {
        let x = half.ppf(u);
        assert!(close(libm::erf(x / 2f64.sqrt()), u, 1e-13), "u = {u}: {x}");
    }
    // Symmetric truncation about the mean has the mean as its median.
    let sym = Marginal::TruncNormal {
        mu: 3.0,
        sigma: 2.0,
        lo: 1.0,
        hi: 5.0,
    };
    assert!((sym.ppf(0.5) - 3.0).abs() < 1e-15);
}

#[test]
fn text_is_what_a_user_writes() {
    assert_eq!(normal(0.0, 1.0).text(), "normal(0,1)");
    assert_eq!(
        Marginal::LogNormal {
            mu: 0.0,
            sigma: 0.5
        }
        .text(),
        "lognormal(0,0.5)"
    );
    assert_eq!(beta(2.0, 5.0).text(), "beta(2,5)");
    assert_eq!(
        Marginal::Beta {
            a: 2.0,
            b: 5.0,
            lo: -1.0,
            hi: 3.0
        }
        .text(),
        "beta(2,5,-1,3)"
    );
    let t = Marginal::TruncNormal {
        mu: 0.0,
        sigma: 1.0,
        lo: -1.0,
        hi: 2.0,
    };
    assert_eq!(t.text(), "truncnormal(0,1,-1,2)");
    let t = Marginal::TruncNormal {
        mu: 0.0,
        sigma: 1.0,
        lo: -INF,
        hi: 2.0,
    };
    assert_eq!(t.text(), "truncnormal(0,1,-inf,2)");
    let tri = Marginal::Triangular {
        lo: 0.0,
        mode: 0.3,
        hi: 1.0,
    };
    assert_eq!(tri.text(), "triangular(0,0.3,1)");
    assert_eq!(
        Marginal::Uniform { lo: 0.0, hi: 1.0 }.text(),
        "uniform(0,1)"
    );
    assert_eq!(normal(0.1, 1e-3).text(), "normal(0.1,0.001)");
}

#[test]
fn support_and_boundedness() {
    assert_eq!(normal(0.0, 1.0).support(), (-INF, INF));
    assert!(!normal(0.0, 1.0).bounded());
    assert_eq!(
        Marginal::LogNormal {
            mu: 0.0,
            sigma: 1.0
        }
        .support(),
        (0.0, INF)
    );
    assert!(beta(2.0, 3.0).bounded());
    let half = Marginal::TruncNormal {
        mu: 0.0,
        sigma: 1.0,
        lo: 0.0,
        hi: INF,
    };
    assert_eq!(half.support(), (0.0, INF));
    assert!(!half.bounded());
    let tri = Marginal::Triangular {
        lo: -1.0,
        mode: 0.0,
        hi: 2.0,
    };
    assert_eq!((tri.support(), tri.bounded()), ((-1.0, 2.0), true));
}

/// The refusal's value and expectation, checking that it names the variable.
fn refusal(m: Marginal) -> (String, String) {
    match m.check("width") {
        Err(Error::InvalidArgument {
            name,
            value,
            expected,
        }) => {
            assert_eq!(name, "width");
            (value, expected)
        }
        other => panic!("{} accepted: {other:?}", m.text()),
    }
}

#[test]
fn bad_parameters_are_refused() {
    let nan = f64::NAN;
    let (value, expected) = refusal(normal(0.0, -1.0));
    assert_eq!(value, "normal(0,-1)");
    assert!(expected.contains("sigma > 0"), "{expected}");
    refusal(normal(0.0, 0.0));
    refusal(normal(nan, 1.0));
    refusal(normal(INF, 1.0));
    let (_, expected) = refusal(normal(0.0, 1e308));
    assert!(expected.contains("8.21 sigma finite"), "{expected}");

    let (_, expected) = refusal(Marginal::LogNormal {
        mu: 0.0,
        sigma: 0.0,
    });
    assert!(expected.starts_with("lognormal(mu,sigma)"), "{expected}");
    // exp(705 + 8.21) overflows.
    refusal(Marginal::LogNormal {
        mu: 705.0,
        sigma: 1.0,
    });

    let (value, expected) = refusal(beta(0.0, 2.0));
    assert_eq!(value, "beta(0,2)");
    assert!(expected.contains("a, b > 0"), "{expected}");
    refusal(beta(2.0, -1.0));
    refusal(beta(INF, 1.0));
    refusal(Marginal::Beta {
        a: 2.0,
        b: 2.0,
        lo: 1.0,
        hi: 1.0,
    });
    refusal(Marginal::Beta {
        a: 2.0,
        b: 2.0,
        lo: 0.0,
        hi: INF,
    });

    let (_, expected) = refusal(Marginal::Triangular {
        lo: 0.0,
        mode: 2.0,
        hi: 1.0,
    });
    assert!(expected.contains("lo ≤ mode ≤ hi"), "{expected}");
    refusal(Marginal::Triangular {
        lo: 1.0,
        mode: 1.0,
        hi: 1.0,
    });
    refusal(Marginal::Triangular {
        lo: 0.0,
        mode: nan,
        hi: 1.0,
    });

    refusal(Marginal::Uniform { lo: 1.0, hi: 0.0 });
    refusal(Marginal::Uniform {
        lo: -1e308,
        hi: 1e308,
    });

    let tn = |mu, sigma, lo, hi| Marginal::TruncNormal { mu, sigma, lo, hi };
    let (value, expected) = refusal(tn(0.0, 1.0, -INF, INF));
    assert_eq!(value, "truncnormal(0,1,-inf,inf)");
    assert!(expected.contains("not both infinite"), "{expected}");
    refusal(tn(0.0, 1.0, 2.0, 1.0));
    refusal(tn(0.0, 1.0, 1.0, 1.0));
    refusal(tn(0.0, 0.0, -1.0, 1.0));
    // An interval 40 standard deviations out holds about 1e-350: below what a double
    // can resolve, refused with a message that says so.
    let (_, expected) = refusal(tn(0.0, 1.0, 40.0, INF));
    assert!(expected.contains("too far in a tail"), "{expected}");
    refusal(tn(0.0, 1.0, -INF, -40.0));
    // 30 out still holds 5e-198, and works.
    let far = tn(0.0, 1.0, 30.0, INF);
    far.check("width").unwrap();
    assert!(far.ppf(0.5) > 30.0 && far.ppf(0.5) < 30.1);

    for ok in catalogue() {
        ok.check("width").unwrap();
    }
    let error = normal(0.0, -1.0).check("width").unwrap_err().to_string();
    assert!(
        error.contains("width") && error.contains("normal(0,-1)"),
        "{error}"
    );
}
