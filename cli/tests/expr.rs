//! Region expressions: the grammar documented in `stillpoint::parse::expr` holds, the paper's
//! regions evaluate as their closed forms, and every refusal names what is wrong.

use stillpoint::parse::expr::{ExprError, RegionExpr};

fn eval(text: &str, s: usize, x: &[f64]) -> f64 {
    RegionExpr::parse(text, s)
        .unwrap_or_else(|e| panic!("{text:?} should parse:\n{e}"))
        .eval(x)
}

fn refusal(text: &str, s: usize) -> String {
    match RegionExpr::parse(text, s) {
        Ok(_) => panic!("{text:?} with s = {s} should be refused"),
        Err(e) => e.to_string(),
    }
}

/// Deterministic points covering [-8, 8]², including the axes where `abs` has its kink.
fn sample_points() -> Vec<[f64; 2]> {
    let mut points = Vec::new();
    for i in -16..=16 {
        for j in -16..=16 {
            points.push([i as f64 * 0.5, j as f64 * 0.5]);
        }
    }
    let mut state = 0x2545_f491_4f6c_dd1du64;
    for _ in 0..2000 {
        let mut next = || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 11) as f64 / (1u64 << 53) as f64 * 16.0 - 8.0
        };
        points.push([next(), next()]);
    }
    points
}

fn assert_close(a: f64, b: f64, what: &str) {
    assert!(
        (a - b).abs() <= 1e-12 * (1.0 + b.abs()),
        "{what}: got {a}, expected {b}"
    );
}

#[test]
fn paper_regions_of_eq_58_match_their_closed_forms() {
    type G = fn(f64, f64) -> f64;
    let regions: [(&str, G); 4] = [
        ("17*x^2 - 16*abs(x)*y + 17*y^2 - 225", |x, y| {
            17.0 * x * x - 16.0 * x.abs() * y + 17.0 * y * y - 225.0
        }),
        ("x^2*abs(x) + 10*y^2 - 100", |x, y| {
            x * x * x.abs() + 10.0 * y * y - 100.0
        }),
        ("y^2 + 2*|x| - 20", |x, y| y * y + 2.0 * x.abs() - 20.0),
        ("|x| + 2*|y| - 5", |x, y| x.abs() + 2.0 * y.abs() - 5.0),
    ];
    let points = sample_points();
    for (text, g) in regions {
        let e = RegionExpr::parse(text, 2).unwrap();
        let indexed = RegionExpr::parse(&text.replace('x', "x1").replace('y', "x2"), 2).unwrap();
        for p in &points {
            let expected = g(p[0], p[1]);
            assert_close(e.eval(p), expected, &format!("{text} at {p:?}"));
            assert_eq!(indexed.eval(p), e.eval(p), "{text}: x1/x2 vs x/y at {p:?}");
        }
    }
}

#[test]
fn unary_minus_binds_looser_than_power() {
    assert_eq!(eval("-x^2", 1, &[3.0]), -9.0);
    assert_eq!(eval("-x1^2", 1, &[3.0]), -9.0);
    assert_eq!(eval("(-x)^2", 1, &[3.0]), 9.0);
    assert_eq!(eval("-2^2", 1, &[0.0]), -4.0);
    assert_eq!(eval("1 - x^2", 1, &[3.0]), -8.0);
    assert_eq!(eval("2*-x^2", 1, &[3.0]), -18.0);
    assert_eq!(eval("-x^2 - -y^2", 2, &[3.0, 2.0]), -5.0);
    assert_eq!(eval("--x", 1, &[3.0]), 3.0);
    assert_eq!(eval("+x", 1, &[3.0]), 3.0);
    assert_eq!(eval("x*-y", 2, &[3.0, 2.0]), -6.0);
    assert_eq!(eval("−x^2", 1, &[3.0]), -9.0, "Unicode minus sign");
}

#[test]
fn power_is_right_associative_and_takes_a_signed_exponent() {
    assert_eq!(eval("2^3^2", 1, &[0.0]), 512.0);
    assert_eq!(eval("2^-1", 1, &[0.0]), 0.5);
    assert_eq!(eval("x^-2", 1, &[2.0]), 0.25);
    assert_eq!(eval("2^-x^2", 1, &[2.0]), 2f64.powi(-4));
    assert_eq!(eval("x**3", 1, &[2.0]), 8.0);
    assert_eq!(eval("x^0.5", 1, &[4.0]), 2.0);
    assert_eq!(eval("x^y", 2, &[2.0, 1.5]), 2f64.powf(1.5));
    assert!(eval("(-8)^(1/3)", 1, &[0.0]).is_nan());
}

#[test]
fn precedence_and_associativity_of_the_four_operations() {
    assert_eq!(eval("1 + 2*3", 1, &[0.0]), 7.0);
    assert_eq!(eval("(1 + 2)*3", 1, &[0.0]), 9.0);
    assert_eq!(eval("8/4/2", 1, &[0.0]), 1.0);
    assert_eq!(eval("8 - 4 - 2", 1, &[0.0]), 2.0);
    assert_eq!(eval("2*x^2/4", 1, &[3.0]), 4.5);
    assert_eq!(eval("  x1\t*\n2  ", 1, &[3.0]), 6.0, "whitespace anywhere");
}

#[test]
fn constant_operands_on_either_side_give_exact_results() {
    type F = fn(f64) -> f64;
    let cases: [(&str, F); 10] = [
        ("1 - x", |x| 1.0 - x),
        ("x - 1", |x| x - 1.0),
        ("0.1 + x", |x| 0.1 + x),
        ("x + 0.1", |x| x + 0.1),
        ("3*x", |x| 3.0 * x),
        ("x*0.3", |x| x * 0.3),
        ("2/x", |x| 2.0 / x),
        ("x/3", |x| x / 3.0),
        ("(1 + 2)*x - 4/2", |x| 3.0 * x - 2.0),
        ("max(0.5, x, 1 - x)", |x| x.max(0.5).max(1.0 - x)),
    ];
    for (text, f) in cases {
        let e = RegionExpr::parse(text, 1).unwrap();
        for x in [-2.5, -0.0, 0.0, 0.1, 0.7, 1.0 / 3.0, 1e300] {
            let (got, want) = (e.eval(&[x]), f(x));
            assert!(
                got.to_bits() == want.to_bits() || (got.is_nan() && want.is_nan()),
                "{text} at {x}: got {got}, expected {want}"
            );
        }
    }
}

#[test]
fn scientific_notation_is_read() {
    assert_eq!(eval("1e-3*x1", 1, &[5.0]), 5.0 * 1e-3);
    assert_eq!(eval("2.5E+2", 1, &[0.0]), 250.0);
    assert_eq!(eval("1E3 - x", 1, &[1.0]), 999.0);
    assert_eq!(eval("3e0 + .5 + 1.", 1, &[0.0]), 4.5);
    assert_eq!(eval("1.5e-300*1e300", 1, &[0.0]), 1.5e-300 * 1e300);
}

#[test]
fn aliases_and_indexed_names_agree_and_mix() {
    let p = [0.3, -1.7, 2.9];
    assert_eq!(
        eval("x^2 + 2*y - z/3", 3, &p),
        eval("x1^2 + 2*x2 - x3/3", 3, &p)
    );
    assert_eq!(eval("x + x2 - z", 3, &p), p[0] + p[1] - p[2]);
    assert_eq!(eval("x12 - x", 12, &[1.0; 12]), 0.0);
    assert_eq!(eval("x", 1, &[4.0]), 4.0);
}

#[test]
fn absolute_value_bars_nest() {
    assert_eq!(eval("|x|", 1, &[-2.0]), 2.0);
    assert_eq!(eval("|-x|", 1, &[2.0]), 2.0);
    assert_eq!(eval("|x|*|y|", 2, &[-2.0, -3.0]), 6.0);
    assert_eq!(eval("||x| - 3|", 1, &[-1.0]), 2.0);
    assert_eq!(eval("|x*|y||", 2, &[-2.0, -3.0]), 6.0);
    assert_eq!(eval("| x - y |", 2, &[1.0, 4.0]), 3.0);
    assert_eq!(eval("-|x|^2", 1, &[-3.0]), -9.0);
    assert_eq!(eval("abs(x) - |x|", 1, &[-3.0]), 0.0);
}

#[test]
fn functions_and_constants() {
    let x = 0.7f64;
    let cases: [(&str, f64); 14] = [
        ("sqrt(x)", x.sqrt()),
        ("exp(x)", x.exp()),
        ("ln(x)", x.ln()),
        ("log(x)", x.ln()),
        ("log10(x)", x.log10()),
        ("sin(x) + cos(x) + tan(x)", x.sin() + x.cos() + x.tan()),
        ("atan(x)", x.atan()),
        ("cbrt(-x)", (-x).cbrt()),
        ("min(x, 1, -2)", -2.0),
        ("max(x, 0.5)", x),
        ("sign(-x) + sign(0)", -1.0),
        ("floor(x) + ceil(x)", 1.0),
        ("pi*x", std::f64::consts::PI * x),
        ("sin ( x ) ^ 2", x.sin().powi(2)),
    ];
    for (text, expected) in cases {
        assert_close(eval(text, 1, &[x]), expected, text);
    }
    assert!(eval("max(sqrt(-1), 1)", 1, &[x]).is_nan(), "NaN propagates");
    assert!(eval("min(1, ln(-x))", 1, &[x]).is_nan(), "NaN propagates");
}

#[test]
fn deep_programs_fall_back_to_a_heap_stack() {
    let levels = 40;
    let text = format!("{}x{}", "x^(".repeat(levels - 1), ")".repeat(levels - 1));
    let x = 1.01f64;
    let mut expected = x;
    for _ in 1..levels {
        expected = x.powf(expected);
    }
    assert_eq!(eval(&text, 1, &[x]), expected);
}

#[test]
fn evaluation_handles_odd_slices_without_panicking() {
    let e = RegionExpr::parse("x1 + x2", 2).unwrap();
    assert!(e.eval(&[1.0]).is_nan(), "too few coordinates");
    assert_eq!(e.eval(&[1.0, 2.0, 100.0]), 3.0, "extra coordinates ignored");
    assert_eq!(e.text(), "x1 + x2");
    assert_eq!(e.s(), 2);
}

#[test]
fn into_fn_is_shareable_across_threads() {
    let g = RegionExpr::parse("x^2 + y^2 - 1", 2).unwrap().into_fn();
    let handles: Vec<_> = (0..4)
        .map(|t| {
            let g = g.clone();
            std::thread::spawn(move || g(&[t as f64, 0.0]))
        })
        .collect();
    let values: Vec<f64> = handles.into_iter().map(|h| h.join().unwrap()).collect();
    assert_eq!(values, vec![-1.0, 0.0, 3.0, 8.0]);
}

#[test]
fn unknown_variables_are_named_with_the_accepted_ones() {
    let m = refusal("x1 + x4", 3);
    assert!(m.contains("\"x4\""), "{m}");
    assert!(m.contains("x1, x2, x3") && m.contains("x, y, z"), "{m}");
    assert!(m.contains("\n  x1 + x4\n       ^^"), "caret under x4:\n{m}");

    let m = refusal("w - 1", 2);
    assert!(m.contains("\"w\"") && m.contains("x1, x2"), "{m}");
    let m = refusal("x + y", 1);
    assert!(m.contains("\"y\"") && m.contains("s = 1"), "{m}");
    for bad in ["x0", "x01", "X1", "e"] {
        let m = refusal(bad, 3);
        assert!(m.contains(&format!("{bad:?}")), "{m}");
    }
    assert!(matches!(
        RegionExpr::parse("x7", 5),
        Err(ExprError::UnknownVariable { .. })
    ));
    let m = refusal("x7", 5);
    assert!(m.contains("x1, x2, …, x5"), "{m}");
}

#[test]
fn syntax_errors_point_at_the_offending_token() {
    let m = refusal("x1 +* 2", 1);
    assert!(m.contains("\"*\"") && m.contains("after \"+\""), "{m}");
    assert!(m.contains("\n  x1 +* 2\n      ^"), "caret under '*':\n{m}");

    let m = refusal("(x1", 1);
    assert!(m.contains("missing ')'"), "{m}");
    assert!(m.contains("\n  (x1\n  ^"), "caret under '(':\n{m}");

    let cases: [(&str, &str); 16] = [
        ("x1 )", "')' closes no '('"),
        ("|x", "missing '|'"),
        ("(|x)", "missing '|'"),
        ("x|", "'|' closes no '|'"),
        ("x1 +", "ends too early"),
        ("2x", "missing operator before \"x\""),
        ("x y", "missing operator before \"y\""),
        ("x(2)", "x is not a function"),
        ("1e", "malformed number \"1e\""),
        ("1e+ x", "malformed number \"1e+\""),
        ("1e999", "out of the range"),
        ("x^2 <= 1", "the region is where g ≤ 0"),
        ("x # y", "unexpected character '#'"),
        ("()", "found \")\""),
        ("sin x", "sin is a function"),
        ("x, y", "','"),
    ];
    for (text, needle) in cases {
        let m = refusal(text, 2);
        assert!(m.contains(needle), "{text:?}: expected {needle:?} in\n{m}");
        assert!(m.contains('^'), "{text:?}: no caret line in\n{m}");
    }
}

#[test]
fn functions_are_checked_by_name_and_argument_count() {
    let m = refusal("foo(x)", 1);
    assert!(
        m.contains("unknown function \"foo\"") && m.contains("sqrt"),
        "{m}"
    );
    assert!(refusal("min(x)", 1).contains("2 or more arguments"));
    assert!(refusal("sin(x, x)", 1).contains("takes 1 argument, 2 were given"));
    assert!(refusal("sqrt()", 1).contains("needs an argument"));
    assert!(refusal("max(x,)", 1).contains("but found \")\""));
}

#[test]
fn empty_text_and_zero_dimension_are_refused() {
    assert!(matches!(RegionExpr::parse("", 2), Err(ExprError::Empty)));
    assert!(matches!(
        RegionExpr::parse(" \t ", 2),
        Err(ExprError::Empty)
    ));
    assert!(refusal("", 2).contains("empty"));
    assert!(matches!(
        RegionExpr::parse("x - 1", 0),
        Err(ExprError::NoDimension)
    ));
    assert!(refusal("x - 1", 0).contains("s = 0"));
}

#[test]
fn hostile_input_is_refused_without_panicking() {
    let deep = format!("{}x{}", "(".repeat(100_000), ")".repeat(100_000));
    assert!(refusal(&deep, 1).contains("nested"));
    let minus = format!("{}x", "-".repeat(100_000));
    assert!(refusal(&minus, 1).contains("nested"));
    let bars = "|".repeat(10_001);
    let _ = RegionExpr::parse(&bars, 1);
    let long_sum = vec!["x"; 50_000].join(" + ");
    assert_eq!(eval(&long_sum, 1, &[1.0]), 50_000.0);
    for junk in [
        "\u{0}", "é", "x\u{301}", "+", "-", "^", "|", ",", ".", "1.2.3",
    ] {
        let _ = RegionExpr::parse(junk, 2);
    }
}
