//! Adversarial inputs and outputs: every reader finishes quickly on hostile bytes (no
//! hang, no stack overflow, bounded size), and every output path is written the way its
//! kind allows (through links, into FIFOs and devices) or refused before the run.

mod common;
use common::TempDir;
use proptest::prelude::*;
use std::collections::BTreeMap;
use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// Every file of the directory with its bytes (links by their target's name).
fn snapshot(dir: &Path) -> BTreeMap<String, Vec<u8>> {
    std::fs::read_dir(dir)
        .unwrap()
        .map(|e| {
            let e = e.unwrap();
            let bytes = match std::fs::read_link(e.path()) {
                Ok(target) => target.to_string_lossy().as_bytes().to_vec(),
                Err(_) => std::fs::read(e.path()).unwrap_or_default(),
            };
            (e.file_name().to_string_lossy().into_owned(), bytes)
        })
        .collect()
}

/// Runs the command with a hang guard; returns (success, stderr).
fn run_bounded(dir: &Path, args: &[&str]) -> (bool, String) {
    let mut child = Command::new(env!("CARGO_BIN_EXE_stillpoint"))
        .current_dir(dir)
        .args(args)
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let clock = Instant::now();
    loop {
        if let Some(status) = child.try_wait().unwrap() {
            let mut err = String::new();
            use std::io::Read;
            child
                .stderr
                .take()
                .unwrap()
                .read_to_string(&mut err)
                .unwrap();
            assert!(
                !err.contains("panicked") && !err.contains("overflow"),
                "{args:?}: {err}"
            );
            return (status.success(), err);
        }
        if clock.elapsed() > Duration::from_secs(30) {
            let _ = child.kill();
            panic!("{args:?} did not finish within 30 s");
        }
        std::thread::sleep(Duration::from_millis(5));
    }
}

/// The readers of one file: eval, integrate, plot, and --init of generate.
fn every_reader(file: &str) -> Vec<Vec<String>> {
    let v = |a: &[&str]| a.iter().map(|s| s.to_string()).collect::<Vec<_>>();
    vec![
        v(&["eval", file]),
        v(&["integrate", file]),
        v(&["plot", file, "-o", "pic.png"]),
        v(&["generate", "--init", file, "-o", "out.csv", "-q"]),
    ]
}

fn refused_by_every_reader(dir: &Path, file: &str, needle: &str) -> usize {
    let before = snapshot(dir);
    let mut count = 0;
    for args in every_reader(file) {
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        let (ok, err) = run_bounded(dir, &args);
        assert!(!ok, "{args:?} accepted {file}");
        assert!(err.contains(file), "{args:?}: {err:?} does not name {file}");
        assert!(err.contains(needle), "{args:?}: {err:?} lacks {needle:?}");
        assert_eq!(snapshot(dir), before, "{args:?} changed a file");
        count += 1;
    }
    count
}

/// A .npy file: magic, version 1.0, the header padded to 16 bytes, and the data.
fn npy(header: &str, data: &[u8]) -> Vec<u8> {
    let mut h = header.to_string();
    while !(10 + h.len() + 1).is_multiple_of(16) {
        h.push(' ');
    }
    h.push('\n');
    let mut out = b"\x93NUMPY\x01\x00".to_vec();
    out.extend_from_slice(&(h.len() as u16).to_le_bytes());
    out.extend_from_slice(h.as_bytes());
    out.extend_from_slice(data);
    out
}

#[test]
fn hostile_npy_headers_are_refused_quickly_by_every_reader() {
    let d = TempDir::new("npy");
    let mut cases: Vec<(String, Vec<u8>)> = vec![(
        "repro.npy".into(),
        b"\x93NUMPY\x01\x00\x11\x00{{{{{{{{{{{{{{{{\n".to_vec(),
    )];
    for depth in [1, 8, 30, 200] {
        let nested = format!("{}{}", "{".repeat(depth), "}".repeat(depth));
        cases.push((format!("braces{depth}.npy"), npy(&nested, &[])));
        cases.push((
            format!("shape{depth}.npy"),
            npy(
                &format!(
                    "{{'descr': '<f8', 'fortran_order': False, 'shape': {}(2, 2){}, }}",
                    "(".repeat(depth),
                    ")".repeat(depth)
                ),
                &[0u8; 32],
            ),
        ));
    }
    cases.push((
        "extra_key.npy".into(),
        npy(
            "{'descr': '<f8', 'fortran_order': False, 'shape': (1, 2), 'x': 1, }",
            &[0u8; 16],
        ),
    ));
    cases.push((
        "no_shape.npy".into(),
        npy("{'descr': '<f8', 'fortran_order': False, }", &[]),
    ));
    cases.push((
        "binary_header.npy".into(),
        npy(
            "{'descr': '<f8', \u{1}'fortran_order': False, 'shape': (1, 2), }",
            &[],
        ),
    ));
    let mut long = b"\x93NUMPY\x02\x00".to_vec();
    long.extend_from_slice(&(1u32 << 30).to_le_bytes());
    long.extend_from_slice(b"{'descr'");
    cases.push(("huge_header.npy".into(), long));
    cases.push((
        "version9.npy".into(),
        b"\x93NUMPY\x09\x00\x10\x00{}".to_vec(),
    ));
    cases.push(("truncated.npy".into(), b"\x93NUMPY\x01".to_vec()));
    let mut count = 0;
    for (name, bytes) in &cases {
        std::fs::write(d.path(name), bytes).unwrap();
        count += refused_by_every_reader(&d.0, name, "not a valid .npy file");
    }
    // A well-formed file still reads.
    let good = npy(
        "{'descr': '<f8', 'fortran_order': False, 'shape': (2, 2), }",
        &[0.25f64, 0.5, 0.75, 0.125]
            .iter()
            .flat_map(|v| v.to_le_bytes())
            .collect::<Vec<_>>(),
    );
    std::fs::write(d.path("good.npy"), good).unwrap();
    let (ok, err) = run_bounded(&d.0, &["eval", "good.npy"]);
    assert!(ok, "{err}");
    eprintln!("npy: {count} refusals");
}

#[test]
fn deeply_nested_json_is_refused_quickly_by_every_reader() {
    let d = TempDir::new("json");
    let mut count = 0;
    for depth in [65, 1000, 60_000] {
        for (key, open, close) in [("m", "[", "]"), ("m", "{\"a\":", "}")] {
            let name = format!("deep_{depth}_{}.json", open.len());
            let text = format!(
                "{{\"points\":[[0.1,0.2],[0.3,0.4]],\"{key}\":{}1{}}}",
                open.repeat(depth),
                close.repeat(depth)
            );
            std::fs::write(d.path(&name), text).unwrap();
            count += refused_by_every_reader(&d.0, &name, "nested more than 64 levels");
        }
        // Nested point arrays themselves.
        let name = format!("points_{depth}.json");
        std::fs::write(d.path(&name), "[".repeat(depth) + &"]".repeat(depth)).unwrap();
        count += refused_by_every_reader(&d.0, &name, "nested more than 64 levels");
    }
    eprintln!("json: {count} refusals");
}

#[test]
fn an_escaped_points_key_is_the_points_key() {
    let d = TempDir::new("escaped");
    std::fs::write(
        d.path("esc.json"),
        r#"{"po\u0069nts": [[0.1, 0.2], [0.3, 0.4]], "\u006e": 2}"#,
    )
    .unwrap();
    let p = stillpoint::io::read_points(&d.path("esc.json")).unwrap();
    assert_eq!((p.n(), p.s()), (2, 2));
    assert_eq!(p.point(1), [0.3, 0.4]);
}

#[test]
fn endless_inputs_stop_at_the_size_bound() {
    let d = TempDir::new("endless");
    for args in [
        vec!["eval", "/dev/zero"],
        vec!["integrate", "/dev/zero"],
        vec!["generate", "--init", "/dev/zero", "-o", "out.csv", "-q"],
        vec!["plot", "--trajectory", "/dev/zero", "-o", "t.png"],
    ] {
        let (ok, err) = run_bounded(&d.0, &args);
        assert!(!ok, "{args:?} accepted /dev/zero");
        assert!(
            err.contains("/dev/zero") && err.contains("MiB"),
            "{args:?}: {err}"
        );
    }
    // A directory given as a point file.
    std::fs::create_dir(d.path("sub")).unwrap();
    let (ok, err) = run_bounded(&d.0, &["eval", "sub"]);
    assert!(!ok && err.contains("directory"), "{err}");
    assert_eq!(d.entries(), ["sub"]);
}

fn generate_to(dir: &Path, out: &str) -> (bool, String) {
    run_bounded(
        dir,
        &[
            "generate", "-n", "12", "-s", "2", "--steps", "30", "-o", out, "-q",
        ],
    )
}

#[test]
fn outputs_are_written_as_their_kind_allows() {
    let d = TempDir::new("outputs");
    // Through a link: the target is replaced, the link stays a link.
    std::fs::write(d.path("t.csv"), "ORIG\n").unwrap();
    std::os::unix::fs::symlink("t.csv", d.path("link.csv")).unwrap();
    let (ok, err) = generate_to(&d.0, "link.csv");
    assert!(ok, "{err}");
    assert!(std::fs::symlink_metadata(d.path("link.csv"))
        .unwrap()
        .file_type()
        .is_symlink());
    let text = std::fs::read_to_string(d.path("t.csv")).unwrap();
    assert!(text.starts_with("# stillpoint"), "{text}");
    // A link to a link, and a dangling link (the file appears where it points).
    std::os::unix::fs::symlink("link.csv", d.path("link2.csv")).unwrap();
    assert!(generate_to(&d.0, "link2.csv").0);
    std::os::unix::fs::symlink("later.csv", d.path("dangling.csv")).unwrap();
    assert!(generate_to(&d.0, "dangling.csv").0);
    assert!(d.path("later.csv").is_file());
    // A character device and a FIFO are written to, not replaced.
    assert!(generate_to(&d.0, "/dev/null").0);
    let fifo = d.path("fifo");
    assert!(Command::new("mkfifo")
        .arg(&fifo)
        .status()
        .unwrap()
        .success());
    let reader = std::thread::spawn({
        let fifo = fifo.clone();
        move || std::fs::read_to_string(fifo).unwrap()
    });
    assert!(generate_to(&d.0, "fifo").0);
    let streamed = reader.join().unwrap();
    assert_eq!(streamed.lines().filter(|l| l.starts_with("0.")).count(), 12);
    use std::os::unix::fs::FileTypeExt;
    assert!(std::fs::symlink_metadata(&fifo)
        .unwrap()
        .file_type()
        .is_fifo());
    // No temporary file is left by any of them.
    assert!(
        d.entries().iter().all(|e| !e.contains(".tmp-")),
        "{:?}",
        d.entries()
    );
}

#[test]
fn outputs_that_cannot_be_written_are_refused_before_the_run() {
    let d = TempDir::new("refused-outputs");
    std::fs::create_dir(d.path("sub")).unwrap();
    let _socket = std::os::unix::net::UnixListener::bind(d.path("sock")).unwrap();
    std::os::unix::fs::symlink("sock", d.path("to_sock.csv")).unwrap();
    let long = format!("{}.csv", "a".repeat(250));
    let cases: Vec<(&str, &str)> = vec![
        ("sub", "directory"),
        ("sock", "socket"),
        ("to_sock.csv", "socket"),
        ("out.xlsx", ".csv, .tsv, .json or .npy"),
        ("out.txt", ".csv, .tsv, .json or .npy"),
        ("missing/out.csv", "does not exist"),
        // A directory that takes no new file (even for root).
        ("/proc/out.csv", "no file can be created"),
        (&long, "bytes"),
    ];
    for (out, needle) in cases {
        let before = snapshot(&d.0);
        let clock = Instant::now();
        let (ok, err) = generate_to(&d.0, out);
        assert!(!ok, "-o {out} accepted");
        assert!(err.contains(needle), "-o {out}: {err:?} lacks {needle:?}");
        assert!(clock.elapsed() < Duration::from_secs(20));
        assert_eq!(snapshot(&d.0), before, "-o {out} changed a file");
    }
}

#[test]
fn stale_temporaries_of_an_output_are_removed_by_its_next_write() {
    let d = TempDir::new("stale");
    // A process id that is not running: beyond the kernel's largest.
    let stale = d.path(".out.csv.tmp-4194305-0");
    std::fs::write(&stale, "half").unwrap();
    let other = d.path(".other.csv.tmp-4194305-0");
    std::fs::write(&other, "another output's").unwrap();
    let (ok, err) = generate_to(&d.0, "out.csv");
    assert!(ok, "{err}");
    assert!(
        !stale.exists(),
        "the stale temporary of out.csv is still there"
    );
    assert!(other.exists(), "a temporary of another output was removed");
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    /// Arbitrary bytes under every extension never panic and end quickly.
    #[test]
    fn arbitrary_bytes_never_panic(bytes in prop::collection::vec(any::<u8>(), 0..400),
                                   ext in prop::sample::select(vec!["csv", "tsv", "json", "npy", "dat"])) {
        let dir = std::env::temp_dir().join(format!("stillpoint-readers-fuzz-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let file = dir.join(format!("f.{ext}"));
        std::fs::write(&file, &bytes).unwrap();
        let clock = Instant::now();
        let _ = stillpoint::io::read_points(&file);
        prop_assert!(clock.elapsed() < Duration::from_secs(5));
    }

    /// Structured mutations of valid files: a byte replaced, inserted or cut anywhere.
    #[test]
    fn mutated_valid_files_never_panic(which in 0usize..3, at in 0usize..10_000, byte in any::<u8>(), op in 0u8..3) {
        let points = stillpoint::sequences::halton(7, 3).unwrap();
        let (ext, valid) = match which {
            0 => ("csv", stillpoint::io::encode(&points, &serde_json::json!({"a": [1, 2]}), stillpoint::io::Format::Csv)),
            1 => ("json", stillpoint::io::encode(&points, &serde_json::json!({"a": [1, 2]}), stillpoint::io::Format::Json)),
            _ => ("npy", stillpoint::io::encode(&points, &serde_json::Value::Null, stillpoint::io::Format::Npy)),
        };
        let mut bytes = valid;
        let i = at % (bytes.len() + 1);
        match op {
            0 if i < bytes.len() => bytes[i] = byte,
            1 => bytes.insert(i, byte),
            _ => bytes.truncate(i),
        }
        let dir = std::env::temp_dir().join(format!("stillpoint-readers-mut-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let file = dir.join(format!("m.{ext}"));
        std::fs::write(&file, &bytes).unwrap();
        let clock = Instant::now();
        let _ = stillpoint::io::read_points(&file);
        prop_assert!(clock.elapsed() < Duration::from_secs(5));
    }
}

#[test]
fn extreme_trajectories_are_drawn_in_bounded_time() {
    let d = TempDir::new("trajectory");
    let (ok, err) = run_bounded(
        &d.0,
        &[
            "generate",
            "-n",
            "10",
            "-s",
            "2",
            "--steps",
            "20",
            "--trajectory",
            "t.json",
            "-o",
            "o.csv",
            "-q",
        ],
    );
    assert!(ok, "{err}");
    let v: serde_json::Value =
        serde_json::from_slice(&std::fs::read(d.path("t.json")).unwrap()).unwrap();
    for (k, (e0, e1, m)) in [
        (1e308, -1e308, 1e-308),
        (1e300, 1e-300, 1e308),
        (5.0, 5.0, -1e308),
    ]
    .into_iter()
    .enumerate()
    {
        let mut t = v.clone();
        let recs = t["records"].as_array_mut().unwrap();
        recs[0]["energy"] = e0.into();
        recs[1]["energy"] = e1.into();
        recs[2]["metrics"] = serde_json::json!([["star_l2", m], ["modified_l2", -m]]);
        let name = format!("t{k}.json");
        std::fs::write(d.path(&name), serde_json::to_vec(&t).unwrap()).unwrap();
        let png = format!("p{k}.png");
        // Drawn or refused, in bounded time and without a panic.
        let _ = run_bounded(&d.0, &["plot", "--trajectory", &name, "-o", &png]);
    }
}

#[test]
fn interrupted_runs_leave_no_temporary_file() {
    let d = TempDir::new("signals");
    for (k, signal) in ["TERM", "INT", "TERM", "INT", "TERM", "INT", "TERM", "INT"]
        .iter()
        .enumerate()
    {
        let mut child = Command::new(env!("CARGO_BIN_EXE_stillpoint"))
            .current_dir(&d.0)
            .args([
                "generate",
                "-n",
                "300",
                "-s",
                "3",
                "--steps",
                "3000",
                "--tolerance",
                "0",
                "--checkpoint",
                "c.ckpt",
                "--checkpoint-every",
                "1",
                "-o",
                "out.csv",
                "-q",
            ])
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .unwrap();
        // Until the first checkpoint is there, however long the start takes on this
        // machine (the run is thousands of steps past it, each written).
        while !d.path("c.ckpt").exists() {
            if let Some(status) = child.try_wait().unwrap() {
                panic!("the run ended ({status}) before writing a checkpoint");
            }
            std::thread::sleep(Duration::from_millis(1));
        }
        // Vary the moment: some signals land in the middle of a checkpoint write.
        std::thread::sleep(Duration::from_millis(3 * k as u64));
        let killed = Command::new("kill")
            .args([&format!("-{signal}"), &child.id().to_string()])
            .status()
            .unwrap();
        assert!(killed.success());
        let status = child.wait().unwrap();
        assert!(!status.success(), "the run ended before the signal");
        let left: Vec<String> = d
            .entries()
            .into_iter()
            .filter(|e| e.contains(".tmp-"))
            .collect();
        assert!(left.is_empty(), "after SIG{signal}: {left:?}");
        assert!(
            !d.path("out.csv").exists(),
            "an interrupted run wrote its output"
        );
        // What is there is a whole checkpoint.
        let text = std::fs::read(d.path("c.ckpt")).unwrap();
        assert!(serde_json::from_slice::<serde_json::Value>(&text).is_ok());
        std::fs::remove_file(d.path("c.ckpt")).unwrap();
    }
}

#[test]
fn staged_outputs_appear_together_or_not_at_all() {
    use stillpoint::io::{write_atomic, Staging};
    let d = TempDir::new("staging");
    std::fs::write(d.path("old.csv"), "old").unwrap();
    // Dropped without a commit (an error returned early): nothing appears or changes.
    {
        let _staging = Staging::begin();
        write_atomic(&d.path("a.json"), b"a").unwrap();
        write_atomic(&d.path("old.csv"), b"new").unwrap();
        let failed = write_atomic(&d.path("missing/b.csv"), b"b");
        assert!(failed.is_err());
    }
    assert_eq!(d.entries(), ["old.csv"]);
    assert_eq!(std::fs::read(d.path("old.csv")).unwrap(), b"old");
    // Committed: all appear at once, with no temporary left.
    let staging = Staging::begin();
    write_atomic(&d.path("a.json"), b"a").unwrap();
    write_atomic(&d.path("old.csv"), b"new").unwrap();
    assert!(
        !d.path("a.json").exists(),
        "a staged file appeared before the commit"
    );
    staging.commit().unwrap();
    assert_eq!(d.entries(), ["a.json", "old.csv"]);
    assert_eq!(std::fs::read(d.path("old.csv")).unwrap(), b"new");
    // Outside a staging a write is in place at once.
    write_atomic(&d.path("c.csv"), b"c").unwrap();
    assert!(d.path("c.csv").exists());
}
