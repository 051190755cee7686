//! File I/O of point sets: bit-exact round trips, the tolerant text grammar, the error
//! messages users see, and atomic writes that never leave partial or temporary files.

use std::fs;
use std::path::Path;

use npyz::WriterBuilder;
use serde_json::json;
use stillpoint::io::{
    encode, parse_text, read_points, to_csv_string, write_atomic, write_points, Format, IoError,
};
use stillpoint::PointSet;

mod common;
use common::TempDir;

impl TempDir {
    fn assert_no_temp_files(&self) {
        let temps: Vec<String> = self
            .entries()
            .into_iter()
            .filter(|n| n.contains(".tmp"))
            .collect();
        assert!(temps.is_empty(), "temporary files left behind: {temps:?}");
    }
}

fn splitmix(state: &mut u64) -> u64 {
    *state = state.wrapping_add(0x9E37_79B9_7F4A_7C15);
    let mut z = *state;
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// Random coordinates in [0, 1) with every bit pattern of the mantissa exercised, plus
/// the values that printing most easily gets wrong.
fn awkward_points(n: usize, s: usize, seed: u64) -> PointSet {
    let mut state = seed;
    let mut data: Vec<f64> = (0..n * s)
        .map(|_| (splitmix(&mut state) >> 11) as f64 / (1u64 << 53) as f64)
        .collect();
    let special = [
        0.0,
        1.0,
        1.0 - f64::EPSILON / 2.0, // 1 - 2^-53, the largest double below 1
        1e-300,
        f64::MIN_POSITIVE,
        5e-324, // smallest subnormal
        0.1,
        1.0 / 3.0,
        0.9856906946328695, // misread by serde_json without float_roundtrip
        2f64.powi(-30),
        -0.0,
        123456789.123,
    ];
    let m = special.len().min(data.len());
    data[..m].copy_from_slice(&special[..m]);
    PointSet::new(n, s, data).unwrap()
}

fn assert_bits_equal(a: &PointSet, b: &PointSet, what: &str) {
    assert_eq!((a.n(), a.s()), (b.n(), b.s()), "{what}: shape");
    for (idx, (x, y)) in a.as_slice().iter().zip(b.as_slice()).enumerate() {
        assert_eq!(
            x.to_bits(),
            y.to_bits(),
            "{what}: element {idx} wrote {x:e} read {y:e}"
        );
    }
}

fn err_text(r: Result<PointSet, IoError>) -> String {
    match r {
        Ok(p) => panic!("expected an error, got {} points", p.n()),
        Err(e) => e.to_string(),
    }
}

fn npy_bytes_f64(shape: &[u64], order: npyz::Order, values: &[f64]) -> Vec<u8> {
    let mut buf = Vec::new();
    let mut w = npyz::WriteOptions::<f64>::new()
        .default_dtype()
        .shape(shape)
        .order(order)
        .writer(&mut buf)
        .begin_nd()
        .unwrap();
    w.extend(values.iter().copied()).unwrap();
    w.finish().unwrap();
    buf
}

#[test]
fn format_from_extension() {
    assert_eq!(Format::from_path(Path::new("a.csv")), Format::Csv);
    assert_eq!(Format::from_path(Path::new("a.TSV")), Format::Tsv);
    assert_eq!(Format::from_path(Path::new("a.tab")), Format::Tsv);
    assert_eq!(Format::from_path(Path::new("dir.x/a.json")), Format::Json);
    assert_eq!(Format::from_path(Path::new("a.npy")), Format::Npy);
    assert_eq!(Format::from_path(Path::new("a.txt")), Format::Csv);
    assert_eq!(Format::from_path(Path::new("points")), Format::Csv);
}

#[test]
fn round_trip_is_bit_exact_in_every_format() {
    let dir = TempDir::new("round_trip");
    let meta = json!({"energy": 1.25, "q": 2, "domain": "periodic cube", "note": null});
    for (s, seed) in [(1, 1u64), (3, 2), (7, 3)] {
        let points = awkward_points(400, s, seed);
        for name in ["p.csv", "p.tsv", "p.json", "p.npy", "p.txt", "p"] {
            let path = dir.path(&format!("s{s}-{name}"));
            write_points(&path, &points, &meta).unwrap();
            let back = read_points(&path).unwrap_or_else(|e| panic!("{e}"));
            assert_bits_equal(&points, &back, &format!("s = {s}, {name}"));
        }
        // Null metadata is allowed and changes nothing about the data.
        let path = dir.path(&format!("s{s}-nometa.json"));
        write_points(&path, &points, &serde_json::Value::Null).unwrap();
        assert_bits_equal(&points, &read_points(&path).unwrap(), "null meta");
    }
    dir.assert_no_temp_files();
}

#[test]
fn text_layout_has_version_meta_and_header() {
    let points = PointSet::from_rows(&[[0.25, 0.5, 1.0], [0.0, 0.125, 0.75]]).unwrap();
    let meta = json!({"energy": 1.5, "name": "uqp", "sizes": [1, 2]});
    let csv = to_csv_string(&points, &meta);
    let lines: Vec<&str> = csv.lines().collect();
    assert_eq!(
        lines,
        [
            &format!("# stillpoint {}", env!("CARGO_PKG_VERSION")) as &str,
            "# energy: 1.5",
            "# name: \"uqp\"",
            "# sizes: [1,2]",
            "x1,x2,x3",
            "0.25,0.5,1",
            "0,0.125,0.75",
        ]
    );
    assert_eq!(encode(&points, &meta, Format::Csv), csv.as_bytes());
    let tsv = String::from_utf8(encode(&points, &meta, Format::Tsv)).unwrap();
    assert!(tsv.contains("\nx1\tx2\tx3\n0.25\t0.5\t1\n"), "{tsv}");

    // A newline inside a key must not end the comment and leak into the data.
    let sneaky = json!({"a\nb": 1});
    let back = parse_text(&to_csv_string(&points, &sneaky), "mem").unwrap();
    assert_eq!(back, points);

    // to_csv_string is exactly what write_points puts in a .csv.
    let dir = TempDir::new("text_layout");
    let path = dir.path("p.csv");
    write_points(&path, &points, &meta).unwrap();
    assert_eq!(fs::read_to_string(&path).unwrap(), csv);
}

#[test]
fn json_layout_keeps_meta_apart_from_the_data() {
    let points = PointSet::from_rows(&[[0.25, 0.5], [0.0, 1.0]]).unwrap();
    // Keys named like the data must not clobber it.
    let meta = json!({"n": 99, "points": "not these", "energy": 2.0});
    let text = String::from_utf8(encode(&points, &meta, Format::Json)).unwrap();
    let v: serde_json::Value = serde_json::from_str(&text).unwrap();
    assert_eq!(v["n"], 2);
    assert_eq!(v["s"], 2);
    assert_eq!(v["stillpoint"], env!("CARGO_PKG_VERSION"));
    assert_eq!(v["meta"], meta);
    assert_eq!(v["points"], json!([[0.25, 0.5], [0.0, 1.0]]));
    assert_eq!(parse_json_via_file("layout", &text).unwrap(), points);
}

fn parse_json_via_file(test: &str, text: &str) -> Result<PointSet, IoError> {
    let dir = TempDir::new(test);
    let path = dir.path("points.json");
    fs::write(&path, text).unwrap();
    read_points(&path)
}

#[test]
fn npy_layout_is_float64_c_order() {
    let points = awkward_points(5, 3, 9);
    let bytes = encode(&points, &json!({"ignored": true}), Format::Npy);
    assert_eq!(
        bytes.len() % 64,
        (5 * 3 * 8) % 64,
        "data must start 64-byte aligned"
    );
    let npy = npyz::NpyFile::new(&bytes[..]).unwrap();
    assert_eq!(npy.shape(), &[5, 3]);
    assert_eq!(npy.order(), npyz::Order::C);
    assert_eq!(npy.dtype().descr(), "'<f8'");
    let flat: Vec<f64> = npy.into_vec().unwrap();
    let back = PointSet::new(5, 3, flat).unwrap();
    assert_bits_equal(&points, &back, "npyz reading our .npy");
}

#[test]
fn reads_whitespace_semicolon_tab_and_comma_text() {
    let expected = PointSet::from_rows(&[[0.5, 0.25], [0.125, 1.0], [0.0, 0.75]]).unwrap();
    let inputs = [
        ("spaces", "0.5 0.25\n  0.125    1\n0\t 0.75\n"),
        ("semicolons", "0.5;0.25\n0.125 ; 1\n0;0.75\n"),
        ("decimal comma", "0,5;0,25\n0,125;1\n0;0,75\n"),
        ("tabs", "0.5\t0.25\n0.125\t1\n0\t0.75\n"),
        ("commas", "0.5, 0.25\n0.125 ,1\n0,0.75\n"),
        ("crlf and bom", "\u{feff}0.5,0.25\r\n0.125,1\r\n0,0.75\r\n"),
        ("quoted", "\"0.5\",\"0.25\"\n0.125,\"1\"\n0,0.75\n"),
        ("trailing delimiter", "0.5,0.25,\n0.125,1,\n0,0.75,\n"),
        ("exponents", "5e-1 2.5E-1\n1.25e-1 1e0\n0 +0.75\n"),
    ];
    for (what, text) in inputs {
        let p = parse_text(text, what).unwrap_or_else(|e| panic!("{what}: {e}"));
        assert_eq!(p, expected, "{what}");
    }
    // One column is s = 1.
    let p = parse_text("0.1\n0.2\n0.3\n", "one column").unwrap();
    assert_eq!((p.n(), p.s()), (3, 1));
}

#[test]
fn skips_comments_blank_lines_and_a_header() {
    let text = "# made by hand\n\n   # indented comment\nx,y\n0.1,0.2\n\n# between\n0.3,0.4\n";
    let p = parse_text(text, "mem").unwrap();
    assert_eq!(p, PointSet::from_rows(&[[0.1, 0.2], [0.3, 0.4]]).unwrap());

    let p = parse_text("\"x1\"\t\"x2\"\n0.1\t0.2\n", "quoted header").unwrap();
    assert_eq!(p, PointSet::from_rows(&[[0.1, 0.2]]).unwrap());

    // Only the first data line may be a header: a later name is an error.
    let e = err_text(parse_text("x,y\n0.1,0.2\nx,y\n", "twice.csv"));
    assert!(e.contains("twice.csv: line 3, field 1"), "{e}");

    // pandas' default to_csv: an unnamed index column, named or numbered columns.
    for header in [",x1,x2", ",0,1", "\t0\t1"] {
        let sep = if header.starts_with('\t') { "\t" } else { "," };
        let text = format!("{header}\n0{sep}0.1{sep}0.2\n1{sep}0.3{sep}0.4\n");
        let p = parse_text(&text, "pandas").unwrap_or_else(|e| panic!("{header:?}: {e}"));
        assert_eq!(
            p,
            PointSet::from_rows(&[[0.1, 0.2], [0.3, 0.4]]).unwrap(),
            "{header:?}"
        );
    }
}

#[test]
fn unknown_extension_is_sniffed() {
    let dir = TempDir::new("sniff");
    let expected = PointSet::from_rows(&[[0.1, 0.2], [0.3, 0.4]]).unwrap();
    let cases: [(&str, Vec<u8>); 4] = [
        ("a.dat", b"0.1 0.2\n0.3 0.4\n".to_vec()),
        ("b.txt", b"  [[0.1, 0.2], [0.3, 0.4]]".to_vec()),
        ("c", br#"{"points": [[0.1, 0.2], [0.3, 0.4]]}"#.to_vec()),
        (
            "d.csv",
            npy_bytes_f64(&[2, 2], npyz::Order::C, &[0.1, 0.2, 0.3, 0.4]),
        ),
    ];
    for (name, bytes) in cases {
        let path = dir.path(name);
        fs::write(&path, bytes).unwrap();
        assert_eq!(read_points(&path).unwrap(), expected, "{name}");
    }
}

#[test]
fn json_shapes() {
    let flat = parse_json_via_file("json_flat", "[0.1, 0.2, 0.3]").unwrap();
    assert_eq!((flat.n(), flat.s()), (3, 1));
    let obj = parse_json_via_file("json_obj", r#"{"points": [0.5], "other": {"a": [1, "x"]}}"#);
    assert_eq!(obj.unwrap().as_slice(), &[0.5]);
    let bare = parse_json_via_file("json_bare", "[[1, 0], [0, 1e-300]]").unwrap();
    assert_eq!(bare.as_slice(), &[1.0, 0.0, 0.0, 1e-300]);
    let escaped = parse_json_via_file("json_esc", r#"{"k\"ey": "a\\", "points": [[0.5]]}"#);
    assert_eq!(escaped.unwrap().as_slice(), &[0.5]);
}

#[test]
fn npy_variants() {
    let dir = TempDir::new("npy_variants");
    // Fortran order: (i, k) stored at k·n + i; must come back as rows.
    let rows = [[0.1, 0.2, 0.3], [0.4, 0.5, 0.6]];
    let column_major = [0.1, 0.4, 0.2, 0.5, 0.3, 0.6];
    let path = dir.path("f.npy");
    fs::write(
        &path,
        npy_bytes_f64(&[2, 3], npyz::Order::Fortran, &column_major),
    )
    .unwrap();
    assert_eq!(
        read_points(&path).unwrap(),
        PointSet::from_rows(&rows).unwrap()
    );

    // 1-D is s = 1.
    let path = dir.path("one.npy");
    fs::write(&path, npy_bytes_f64(&[3], npyz::Order::C, &[0.1, 0.2, 0.3])).unwrap();
    let p = read_points(&path).unwrap();
    assert_eq!((p.n(), p.s()), (3, 1));

    // float32 widens exactly.
    let mut buf = Vec::new();
    let mut w = npyz::WriteOptions::<f32>::new()
        .default_dtype()
        .shape(&[2, 2])
        .writer(&mut buf)
        .begin_nd()
        .unwrap();
    w.extend([0.1f32, 0.2, 0.3, 0.4]).unwrap();
    w.finish().unwrap();
    let path = dir.path("f32.npy");
    fs::write(&path, buf).unwrap();
    let p = read_points(&path).unwrap();
    assert_eq!(
        p.as_slice(),
        &[0.1f32 as f64, 0.2f32 as f64, 0.3f32 as f64, 0.4f32 as f64]
    );
}

#[test]
fn text_errors_name_file_line_and_field() {
    let e = err_text(parse_text("# c\nx,y\n0.1,0.2\n0.3,abc\n", "points.csv"));
    assert_eq!(e, "points.csv: line 4, field 2: \"abc\" is not a number");

    let e = err_text(parse_text(
        "x,y\n0.1,0.2\n0.3,0.4\n\n0.5,0.6,0.7\n",
        "points.csv",
    ));
    assert_eq!(
        e,
        "points.csv: line 5 has 3 coordinates, line 2 has 2 (every point needs the same number)"
    );
    let e = err_text(parse_text("0.1 0.2\n0.3\n", "short.txt"));
    assert!(
        e.contains("short.txt: line 2 has 1 coordinate, line 1 has 2"),
        "{e}"
    );

    let e = err_text(parse_text("0.1,,0.3\n", "gap.csv"));
    assert!(e.contains("gap.csv: line 1, field 2: empty field"), "{e}");

    for text in ["", "\n\n", "# only\n# comments\n", "x,y\n"] {
        let e = err_text(parse_text(text, "points.csv"));
        assert_eq!(e, "points.csv: no points found", "{text:?}");
    }

    let e = err_text(parse_text("0.1,0.2\nnan,0.4\n", "nan.csv"));
    assert!(e.starts_with("nan.csv: "), "{e}");
    assert!(
        e.contains("point 2, coordinate 1") && e.contains("line 2"),
        "{e}"
    );
    assert!(e.contains("NaN") && e.contains("finite"), "{e}");
    let e = err_text(parse_text("0.1 -inf\n", "inf.txt"));
    assert!(
        e.contains("point 1, coordinate 2") && e.contains("-inf"),
        "{e}"
    );
}

#[test]
fn json_errors_say_what_is_accepted() {
    let accepted = r#"expected {"points": [[x1, x2, ...], ...]} or [[x1, x2, ...], ...]"#;
    let cases = [
        (r#"{"pts": [[0.1]]}"#, "no \"points\" key"),
        (r#""hello""#, "got a string"),
        ("3", "got the number 3"),
        (r#"{"points": 3}"#, "\"points\" is the number 3"),
        ("[[0.1, 0.2], 0.3]", "point 2 is the number 0.3, not a list"),
        ("[0.1, [0.2]]", "point 2 is a list but point 1 is a number"),
    ];
    for (i, (text, detail)) in cases.into_iter().enumerate() {
        let e = err_text(parse_json_via_file(&format!("json_err{i}"), text));
        assert!(e.contains("points.json: "), "{e}");
        assert!(e.contains(accepted), "{text}: {e}");
        assert!(e.contains(detail), "{text}: {e}");
    }
    let other = [
        (
            "[[0.1, 0.2], [0.3]]",
            "point 2 has 1 coordinate, point 1 has 2",
        ),
        (
            r#"[[0.1, "x"]]"#,
            "point 1, coordinate 2: \"x\" is not a number",
        ),
        (
            "[[0.1, null]]",
            "point 1, coordinate 2: null is not a number",
        ),
        ("[]", "no points found"),
        (r#"{"points": []}"#, "no points found"),
        ("[[]]", "point 1 has no coordinates"),
        ("[[0.1, NaN]]", "point 1, coordinate 2: not valid JSON"),
        ("[[0.1, 0.2]", "not valid JSON"),
        ("[[1e400]]", "finite"),
        (
            r#"{"n": 3, "points": [[0.1], [0.2]]}"#,
            "\"n\" is 3 but \"points\" holds 2 points",
        ),
    ];
    for (i, (text, detail)) in other.into_iter().enumerate() {
        let e = err_text(parse_json_via_file(&format!("json_other{i}"), text));
        assert!(e.contains("points.json: "), "{e}");
        assert!(e.contains(detail), "{text}: {e}");
    }
}

#[test]
fn a_repeated_points_key_is_refused() {
    // JSON leaves a repeated key's meaning open; reading either copy would be a guess.
    let cases = [
        (r#"{"points": [[0.5]], "points": [[0.25]]}"#, "points"),
        (
            r#"{"points": [[0.5]], "meta": {}, "points": [[0.5]]}"#,
            "points",
        ),
        (r#"{"po\u0069nts": [[0.5]], "points": [[0.25]]}"#, "points"),
        (r#"{"n": 1, "points": [[0.5]], "n": 1}"#, "n"),
        (r#"{"s": 1, "s": 2, "points": [[0.5]]}"#, "s"),
    ];
    for (i, (text, key)) in cases.into_iter().enumerate() {
        let e = err_text(parse_json_via_file(&format!("dup{i}"), text));
        assert!(
            e.ends_with(&format!(
                "points.json: duplicate key \"{key}\"; a point file has each key once"
            )),
            "{text}: {e}"
        );
    }
    // Keys the reader skips may repeat: they change nothing it reads.
    let p = parse_json_via_file(
        "dup_meta",
        r#"{"meta": 1, "points": [[0.5, 0.25]], "meta": 2}"#,
    );
    assert_eq!(p.unwrap().as_slice(), &[0.5, 0.25]);
}

#[test]
fn npy_errors_give_shape_and_dtype() {
    let dir = TempDir::new("npy_errors");
    let path = dir.path("x.npy");
    fs::write(&path, npy_bytes_f64(&[2, 3, 4], npyz::Order::C, &[0.5; 24])).unwrap();
    let e = err_text(read_points(&path));
    assert!(
        e.ends_with("x.npy: expected a 2-D array of float64 or float32 (got shape [2, 3, 4])"),
        "{e}"
    );

    let mut buf = Vec::new();
    let mut w = npyz::WriteOptions::<i64>::new()
        .default_dtype()
        .shape(&[2, 2])
        .writer(&mut buf)
        .begin_nd()
        .unwrap();
    w.extend([0i64, 1, 1, 0]).unwrap();
    w.finish().unwrap();
    fs::write(&path, buf).unwrap();
    let e = err_text(read_points(&path));
    assert!(e.contains("float64 or float32 (got dtype '<i8')"), "{e}");

    fs::write(&path, npy_bytes_f64(&[0, 2], npyz::Order::C, &[])).unwrap();
    assert!(err_text(read_points(&path)).ends_with("x.npy: no points found"));

    let mut truncated = npy_bytes_f64(&[4, 2], npyz::Order::C, &[0.5; 8]);
    truncated.truncate(truncated.len() - 8);
    fs::write(&path, truncated).unwrap();
    let e = err_text(read_points(&path));
    assert!(e.contains("truncated") && e.contains("[4, 2]"), "{e}");

    fs::write(&path, "0.1,0.2\n").unwrap();
    let e = err_text(read_points(&path));
    assert!(e.contains("x.npy: not a NumPy .npy file"), "{e}");

    fs::write(
        &path,
        npy_bytes_f64(&[1, 2], npyz::Order::C, &[0.5, f64::NAN]),
    )
    .unwrap();
    let e = err_text(read_points(&path));
    assert!(
        e.contains("point 1, coordinate 2") && e.contains("NaN"),
        "{e}"
    );
}

#[test]
fn missing_or_binary_file_is_named() {
    let dir = TempDir::new("missing");
    let path = dir.path("nowhere.csv");
    let e = err_text(read_points(&path));
    assert!(
        e.starts_with(&format!("{}: cannot read: ", path.display())),
        "{e}"
    );
    assert!(matches!(read_points(&path), Err(IoError::Io { .. })));

    let path = dir.path("binary.csv");
    fs::write(&path, [0x30, 0x2e, 0x31, 0xff, 0xfe]).unwrap();
    let e = err_text(read_points(&path));
    assert!(
        e.contains("binary.csv: not UTF-8 text (invalid byte at offset 3)"),
        "{e}"
    );
}

#[test]
fn atomic_write_into_missing_directory_leaves_nothing() {
    let dir = TempDir::new("atomic_missing");
    let target = dir.path("no/such/dir/out.csv");
    let points = awkward_points(3, 2, 5);
    let e = write_points(&target, &points, &json!({})).unwrap_err();
    let msg = e.to_string();
    assert!(msg.starts_with(&target.display().to_string()), "{msg}");
    assert!(matches!(e, IoError::Io { .. }), "{msg}");
    assert!(!target.exists());
    assert!(dir.entries().is_empty(), "{:?}", dir.entries());
}

#[test]
fn atomic_write_replaces_fully_and_cleans_up() {
    let dir = TempDir::new("atomic_replace");
    let target = dir.path("out.csv");
    fs::write(&target, "x".repeat(100_000)).unwrap();
    write_atomic(&target, b"short").unwrap();
    assert_eq!(fs::read(&target).unwrap(), b"short");

    let points = awkward_points(50, 4, 6);
    write_points(&target, &points, &json!({"run": 1})).unwrap();
    write_points(&target, &points, &json!({"run": 2})).unwrap();
    let text = fs::read_to_string(&target).unwrap();
    assert!(text.contains("# run: 2") && !text.contains("# run: 1"));
    assert_bits_equal(&points, &read_points(&target).unwrap(), "rewritten");
    assert_eq!(dir.entries(), ["out.csv"]);

    // Failure at the rename (the target is a directory) removes the temporary file.
    let blocker = dir.path("blocked.json");
    fs::create_dir(&blocker).unwrap();
    fs::write(blocker.join("keep"), "kept").unwrap();
    let e = write_points(&blocker, &points, &serde_json::Value::Null).unwrap_err();
    assert!(
        e.to_string().starts_with(&blocker.display().to_string()),
        "{e}"
    );
    assert_eq!(fs::read_to_string(blocker.join("keep")).unwrap(), "kept");
    dir.assert_no_temp_files();
    assert_eq!(dir.entries(), ["blocked.json", "out.csv"]);

    // A path without a file name has nowhere to put the temporary file.
    let e = write_atomic(Path::new("/"), b"x").unwrap_err();
    assert!(e.to_string().contains("not a file name"), "{e}");
}

#[test]
fn a_large_file_round_trips() {
    let points = awkward_points(10_000, 20, 11);
    let text = to_csv_string(&points, &json!({}));
    let back = parse_text(&text, "big.csv").unwrap();
    assert_bits_equal(&points, &back, "big");
}
