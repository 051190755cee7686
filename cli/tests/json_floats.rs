//! JSON point files are read with serde_json's correctly rounded float parsing: every
//! hard case gives the bits Rust's own (correctly rounded) `str::parse::<f64>` gives, and
//! a key given twice or a number beyond f64 is refused, naming the file.

use proptest::prelude::*;
use stillpoint::io::parse_json as parse_text;

/// The bits the reader gives for one coordinate written as `text`.
fn read(text: &str) -> Result<u64, String> {
    parse_text(&format!("{{\"points\": [[{text}]]}}"), "f.json")
        .map(|p| p.as_slice()[0].to_bits())
        .map_err(|e| e.to_string())
}

#[test]
fn hard_floats_are_correctly_rounded() {
    let long = format!("0.{}1", "3".repeat(800));
    let cases = [
        "9007199254740993",
        "2.2250738585072011e-308",
        "2.2250738585072012e-308",
        "4.9e-324",
        "2.4703282292062328e-324",
        "2.4703282292062327e-324",
        "1.7976931348623157e308",
        "1e23",
        "8.98846567431158e307",
        "0.1",
        "0.30000000000000004",
        "123456789012345678901234567890",
        long.as_str(),
    ];
    for text in cases {
        let want = text.parse::<f64>().unwrap().to_bits();
        assert_eq!(read(text), Ok(want), "{text}");
    }
}

#[test]
fn numbers_beyond_f64_and_repeated_keys_are_refused() {
    let e = read("1e309").unwrap_err();
    assert!(e.starts_with("f.json: "), "{e}");
    let twice = parse_text(
        r#"{"points": [[0.1, 0.2]], "points": [[0.3, 0.4]]}"#,
        "g.json",
    )
    .unwrap_err()
    .to_string();
    assert!(twice.contains("\"points\" is given twice"), "{twice}");
    let hint = parse_text(r#"{"n": 2, "points": [[0.1, 0.2]]}"#, "h.json")
        .unwrap_err()
        .to_string();
    assert!(
        hint.contains("\"n\" is 2 but \"points\" holds 1 points"),
        "{hint}"
    );
}

proptest! {
    #[test]
    fn any_double_reads_back_bit_for_bit(bits in any::<u64>()) {
        let x = f64::from_bits(bits);
        prop_assume!(x.is_finite());
        for text in [format!("{x:?}"), format!("{x:.16e}"), format!("{x:e}")] {
            let want = text.parse::<f64>().unwrap().to_bits();
            prop_assert_eq!(read(&text), Ok(want), "{}", text);
        }
    }
}
