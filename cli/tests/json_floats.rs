//! JSON coordinates are read correctly rounded: each number in a JSON point file gives the
//! same bits as Rust's `str::parse::<f64>` (itself correctly rounded), on the inputs where
//! a fast float parser goes wrong — halfway cases, subnormals, the ends of the range, very
//! long mantissas — and on random doubles in the forms writers use. A number beyond the
//! finite range is refused, never read as infinity.

use std::path::PathBuf;

use proptest::prelude::*;
use stillpoint::io::read_points;

mod common;
use common::TempDir;

/// The exact decimal value of `m · 2^e`, as digits with an exponent (`123e-45`), by
/// schoolbook arithmetic on base-10^9 limbs: an independent source of numbers that lie
/// exactly halfway between two doubles.
fn exact(m: u64, e: i32) -> String {
    let mut limbs: Vec<u64> = vec![m % 1_000_000_000, m / 1_000_000_000 % 1_000_000_000];
    limbs.push(m / 1_000_000_000_000_000_000);
    // m · 2^e = m · 2^e for e >= 0, and m · 5^-e · 10^e for e < 0.
    let factor = if e >= 0 { 2 } else { 5 };
    for _ in 0..e.unsigned_abs() {
        let mut carry = 0;
        for limb in &mut limbs {
            let v = *limb * factor + carry;
            *limb = v % 1_000_000_000;
            carry = v / 1_000_000_000;
        }
        if carry > 0 {
            limbs.push(carry);
        }
    }
    while limbs.len() > 1 && *limbs.last().unwrap() == 0 {
        limbs.pop();
    }
    let mut digits = limbs.last().unwrap().to_string();
    for limb in limbs.iter().rev().skip(1) {
        digits.push_str(&format!("{limb:09}"));
    }
    if e >= 0 {
        digits
    } else {
        format!("{digits}e{e}")
    }
}

/// `number` (as [`exact`] writes it) with a 1 appended `extra` digits further down, so
/// that it lies just above its value.
fn nudged_up(number: &str, extra: usize) -> String {
    let (digits, exp) = number.split_once('e').unwrap_or((number, "0"));
    let exp: i64 = exp.parse().unwrap();
    format!("{digits}{}1e{}", "0".repeat(extra - 1), exp - extra as i64)
}

/// `number` (as [`exact`] writes it, ending in a non-zero digit) lowered in its last digit
/// and continued with nines, so that it lies just below its value.
fn nudged_down(number: &str, extra: usize) -> String {
    let (digits, exp) = number.split_once('e').unwrap_or((number, "0"));
    let exp: i64 = exp.parse().unwrap();
    let (head, last) = digits.split_at(digits.len() - 1);
    let last = last.parse::<u8>().unwrap();
    assert!(last > 0, "{number} ends in 0");
    format!(
        "{head}{}{}e{}",
        last - 1,
        "9".repeat(extra),
        exp - extra as i64
    )
}

/// Writes `text` to `dir/name` and reads it back as a point set's coordinates.
fn read_json(dir: &TempDir, name: &str, text: &str) -> Result<Vec<f64>, String> {
    let path: PathBuf = dir.path(name);
    std::fs::write(&path, text).unwrap();
    read_points(&path)
        .map(|p| p.as_slice().to_vec())
        .map_err(|e| e.to_string())
}

/// Reads each number in three layouts (a bare list of points, under `"points"`, a flat
/// list) and compares the bits with `str::parse`; returns what was read.
fn assert_read_like_parse(dir: &TempDir, numbers: &[&str]) -> Vec<f64> {
    let mut read = Vec::new();
    for (i, number) in numbers.iter().enumerate() {
        let expected: f64 = number.parse().unwrap();
        assert!(expected.is_finite(), "{number} is not a finite test case");
        for (j, text) in [
            format!("[[{number}]]"),
            format!("{{\"points\": [[0.5, {number}]], \"n\": 1}}"),
            format!("[0.5, {number}]"),
        ]
        .iter()
        .enumerate()
        {
            let got = read_json(dir, &format!("case{i}_{j}.json"), text)
                .unwrap_or_else(|e| panic!("{number}: {e}"));
            let got = *got.last().unwrap();
            assert_eq!(
                got.to_bits(),
                expected.to_bits(),
                "{number}: read {got:e}, correctly rounded is {expected:e}"
            );
        }
        read.push(expected);
    }
    read
}

fn bits(values: &[f64]) -> Vec<u64> {
    values.iter().map(|v| v.to_bits()).collect()
}

#[test]
fn halfway_cases_round_to_even() {
    let d = TempDir::new("halfway");
    let written = [
        "9007199254740993",        // 2^53 + 1: halfway, rounds down to 2^53
        "9007199254740995",        // 2^53 + 3: halfway, rounds up to 2^53 + 4
        "9007199254740993.0",      // the same as a decimal
        "2.2250738585072011e-308", // just below the smallest normal
        "2.2250738585072012e-308", // rounds to the smallest normal
        "1e23",                    // close to the midpoint of two doubles
        "8.98846567431158e307",    // 2^1023 to 15 digits
        "18446744073709551617",    // 2^64 + 1, past u64
        "-9223372036854775809",    // -(2^63 + 1), past i64
        "123456789012345678901234567890",
    ];
    let read = assert_read_like_parse(&d, &written);
    assert_eq!(read[0], 2f64.powi(53));
    assert_eq!(read[1], 2f64.powi(53) + 4.0);
    assert_eq!(read[4], f64::MIN_POSITIVE);
    assert_eq!(read[5], 1e23);

    // Exact midpoints, and the numbers just above and below them.
    let one = exact((1 << 53) + 1, -53); // between 1 and 1 + 2^-52
    let normal = exact((1 << 53) - 1, -1075); // between the largest subnormal and 2^-1022
    let cases = [
        one.clone(),
        nudged_up(&one, 30),
        nudged_down(&one, 30),
        normal.clone(),
        nudged_down(&normal, 30),
        exact((1 << 54) - 3, 970), // between the two largest doubles: to even, the lower
    ];
    let cases: Vec<&str> = cases.iter().map(String::as_str).collect();
    let read = assert_read_like_parse(&d, &cases);
    let expected = [
        1.0,
        1.0 + f64::EPSILON,
        1.0,
        f64::MIN_POSITIVE,
        f64::from_bits(f64::MIN_POSITIVE.to_bits() - 1),
        f64::from_bits(f64::MAX.to_bits() - 1),
    ];
    assert_eq!(bits(&read), bits(&expected));
}

#[test]
fn subnormals_and_the_ends_of_the_range() {
    let d = TempDir::new("ends");
    let half_min = exact(1, -1075); // half the smallest subnormal, 752 digits
    let cases = [
        "4.9e-324".to_string(),
        "2.4703282292062328e-324".to_string(), // above half the smallest subnormal: up
        "2.4703282292062327e-324".to_string(), // below it: zero
        half_min.clone(),                      // exactly half: to even, zero
        nudged_up(&half_min, 40),
        exact(3, -1075), // between subnormals 1 and 2: to even, 2
        "1e-400".to_string(),
        "2.2250738585072009e-308".to_string(), // the largest subnormal
        "1.7976931348623157e308".to_string(),  // the largest finite
        "1.7976931348623158e308".to_string(),  // still rounds to it
        nudged_down(&exact((1 << 54) - 1, 970), 20), // just below the overflow threshold
        "-1.7976931348623157e308".to_string(),
    ];
    let cases: Vec<&str> = cases.iter().map(String::as_str).collect();
    let read = assert_read_like_parse(&d, &cases);
    let expected = [
        f64::from_bits(1),
        f64::from_bits(1),
        0.0,
        0.0,
        f64::from_bits(1),
        f64::from_bits(2),
        0.0,
        f64::from_bits(f64::MIN_POSITIVE.to_bits() - 1),
        f64::MAX,
        f64::MAX,
        f64::MAX,
        -f64::MAX,
    ];
    assert_eq!(bits(&read), bits(&expected));
}

#[test]
fn a_mantissa_of_800_digits_is_rounded_on_all_of_it() {
    let d = TempDir::new("long");
    // The midpoint of 1 and 1 + 2^-52 with a 1 or a run of nines far down: only a
    // parser that weighs every digit rounds these two apart.
    let one = exact((1 << 53) + 1, -53);
    let digits = one.split_once('e').unwrap().0.len();
    let above = nudged_up(&one, 800 - digits);
    let below = nudged_down(&one, 800 - digits);
    assert_eq!(above.split_once('e').unwrap().0.len(), 800);
    let read = assert_read_like_parse(&d, &[&above, &below]);
    assert_eq!(read, [1.0 + f64::EPSILON, 1.0]);
    // 800 significant digits of an ordinary number, positional and with an exponent.
    let digits: String = (0..800u32)
        .map(|k| char::from(b'1' + (k * 7 % 9) as u8))
        .collect();
    assert_read_like_parse(
        &d,
        &[
            &format!("0.{digits}"),
            &format!("{digits}e-805"),
            &format!("-{digits}e-500"),
        ],
    );
}

#[test]
fn negative_zero_keeps_its_sign() {
    let d = TempDir::new("zero");
    for text in ["[-0.0]", "[-0]", "[-0e10]", "[-1e-400]", "[[-0.0, 0.0]]"] {
        let got = read_json(&d, "z.json", text).unwrap();
        assert_eq!(got[0].to_bits(), (-0.0f64).to_bits(), "{text}");
        assert!(got[1..].iter().all(|v| v.to_bits() == 0), "{text}");
    }
}

#[test]
fn numbers_beyond_the_finite_range_are_refused() {
    let d = TempDir::new("overflow");
    let huge = format!("1{}", "0".repeat(400));
    let threshold = exact((1 << 54) - 1, 970); // halfway from the largest double to 2^1024
    let cases = [
        ("[[1e309]]".to_string(), "point 1, coordinate 1", "1e309"),
        (
            "[[0.5, 0.25], [0.5, -1e309]]".to_string(),
            "point 2, coordinate 2",
            "-1e309",
        ),
        (
            "[0.5, 1.8e308]".to_string(),
            "point 2, coordinate 1",
            "1.8e308",
        ),
        (
            r#"{"points": [[0.5, 0.25, 1e99999999999]]}"#.to_string(),
            "point 1, coordinate 3",
            "1e99999999999",
        ),
        (
            format!("[[0.5, {huge}]]"),
            "point 1, coordinate 2",
            "10000000000",
        ),
        (
            format!("[[{threshold}]]"),
            "point 1, coordinate 1",
            "179769313486231580793",
        ),
        // On a later line, after characters of several bytes.
        (
            format!(
                "{{\"meta\": 1,\n \"{}\": [], \"points\": [[0.5], [-2e400]]\n}}",
                "\u{e9}\u{2202}".repeat(20)
            ),
            "point 2, coordinate 1",
            "-2e400",
        ),
    ];
    for (i, (text, place, shown)) in cases.iter().enumerate() {
        let name = format!("big{i}.json");
        let e = read_json(&d, &name, text).expect_err(text);
        assert!(
            e.starts_with(&format!("{}: ", d.path(&name).display())),
            "{e}"
        );
        assert!(e.contains(place), "{text}: {e}");
        assert!(e.contains(shown), "{text}: {e}");
        assert!(e.contains("finite"), "{text}: {e}");
        assert!(!e.contains("inf"), "{text}: {e}");
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    /// Any finite double, written shortest-round-trip (`{:?}`) and with 17 significant
    /// digits, reads back as `str::parse` reads it — which for both forms is the double
    /// itself.
    #[test]
    fn random_doubles_read_back_exactly(bits in prop::collection::vec(any::<u64>(), 1..40)) {
        let values: Vec<f64> = bits
            .iter()
            .map(|&b| f64::from_bits(b))
            .filter(|v| v.is_finite())
            .collect();
        prop_assume!(!values.is_empty());
        let shortest: Vec<String> = values.iter().map(|v| format!("{v:?}")).collect();
        let seventeen: Vec<String> = values.iter().map(|v| format!("{v:.16e}")).collect();
        let d = TempDir::new("random");
        for (name, texts) in [("shortest.json", &shortest), ("seventeen.json", &seventeen)] {
            let got = read_json(&d, name, &format!("[{}]", texts.join(", "))).unwrap();
            prop_assert_eq!(got.len(), values.len());
            for ((g, t), v) in got.iter().zip(texts).zip(&values) {
                let parsed: f64 = t.parse().unwrap();
                prop_assert_eq!(g.to_bits(), parsed.to_bits(), "{} read as {:e}", t, g);
                prop_assert_eq!(g.to_bits(), v.to_bits(), "{} read as {:e}", t, g);
            }
        }
    }

    /// Doubles in [0, 1), the range point sets live in, with every mantissa bit random.
    #[test]
    fn random_unit_doubles_read_back_exactly(bits in prop::collection::vec(any::<u64>(), 1..40)) {
        let values: Vec<f64> = bits.iter().map(|&b| (b >> 11) as f64 / (1u64 << 53) as f64).collect();
        let text = values.iter().map(|v| format!("[{v:?}, {v:.16e}]")).collect::<Vec<_>>().join(", ");
        let d = TempDir::new("unit");
        let got = read_json(&d, "unit.json", &format!("{{\"points\": [{text}]}}")).unwrap();
        prop_assert_eq!(got.len(), 2 * values.len());
        for (pair, v) in got.chunks(2).zip(&values) {
            prop_assert_eq!(pair[0].to_bits(), v.to_bits());
            prop_assert_eq!(pair[1].to_bits(), v.to_bits());
        }
    }
}

/// serde_json itself, as the workspace builds it, parses every case correctly rounded:
/// the property the JSON reader relies on.
#[test]
fn serde_json_with_float_roundtrip_is_correctly_rounded() {
    let mut state = 0x2545_f491_4f6c_dd1du64;
    let mut count = 0;
    while count < 20_000 {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        let v = f64::from_bits(state);
        if !v.is_finite() {
            continue;
        }
        for text in [format!("{v:?}"), format!("{v:.16e}"), format!("{v:.20e}")] {
            let ours: f64 = serde_json::from_str(&text).unwrap();
            let std: f64 = text.parse().unwrap();
            assert_eq!(ours.to_bits(), std.to_bits(), "{text}");
        }
        count += 1;
    }
    assert!(serde_json::from_str::<f64>("1e309").is_err());
}
