//! Bad input, through the command and through the library: every refusal names the
//! argument and what is accepted, ends with a non-zero exit status and no panic, and
//! leaves every file as it was (an existing output file keeps its bytes, no new or
//! temporary file appears).

use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::Arc;

mod common;
use common::tmpdir;

/// Every file under `d` with its bytes.
fn snapshot(d: &Path) -> Vec<(PathBuf, Vec<u8>)> {
    let mut out = Vec::new();
    let mut stack = vec![d.to_path_buf()];
    while let Some(dir) = stack.pop() {
        for e in std::fs::read_dir(&dir).unwrap() {
            let p = e.unwrap().path();
            if p.is_dir() {
                stack.push(p);
            } else {
                let bytes = std::fs::read(&p).unwrap();
                out.push((p, bytes));
            }
        }
    }
    out.sort();
    out
}

/// The fixtures: an existing output file and one bad input file of each kind.
struct Fixtures {
    dir: PathBuf,
}

impl Fixtures {
    fn new() -> Self {
        let dir = tmpdir("cli");
        let w = |name: &str, bytes: &[u8]| std::fs::write(dir.join(name), bytes).unwrap();
        w(
            "out.csv",
            b"# an earlier result that must survive\n0.5,0.5\n",
        );
        w("nan.csv", b"0.1,0.2\n0.3,nan\n");
        w("outside.csv", b"0.1,0.2\n0.3,1.5\n");
        w("empty.csv", b"# nothing but a comment\n");
        w("ragged.csv", b"0.1,0.2\n0.3\n");
        w("words.csv", b"0.1,0.2\n0.3,abc\n");
        w("two.csv", b"0.1,0.2\n0.3,0.4\n");
        w("malformed.json", b"{\"points\": [[0.1, 0.2], [0.3, 0.4]\n");
        w("shape.json", b"{\"points\": 3}");
        // A valid .npy header for 4 x 2 float64 with only 3 values after it.
        let mut npy = b"\x93NUMPY\x01\x00v\x00".to_vec();
        npy.extend_from_slice(b"{'descr': '<f8', 'fortran_order': False, 'shape': (4, 2), }");
        npy.resize(10 + 0x76 - 1, b' ');
        npy.push(b'\n');
        for v in [0.1f64, 0.2, 0.3] {
            npy.extend_from_slice(&v.to_le_bytes());
        }
        w("truncated.npy", &npy);
        // The same header with all 8 values and one more after them.
        npy.truncate(10 + 0x76);
        for v in [0.1f64, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9] {
            npy.extend_from_slice(&v.to_le_bytes());
        }
        w("trailing.npy", &npy);
        w("bad-trajectory.json", b"{\"records\": 3}");
        w("not-a-checkpoint.json", b"{\"points\": [[0.5, 0.5]]}");
        Fixtures { dir }
    }

    fn p(&self, name: &str) -> String {
        self.dir.join(name).to_str().unwrap().to_string()
    }
}

/// A small checkpoint written by a real run, for the resume cases.
fn write_checkpoint(f: &Fixtures) {
    let o = Command::new(env!("CARGO_BIN_EXE_stillpoint"))
        .args([
            "generate",
            "-n",
            "20",
            "-s",
            "2",
            "--steps",
            "20",
            "--checkpoint",
            &f.p("run.ckpt"),
            "--checkpoint-every",
            "10",
            "-o",
            &f.p("first.csv"),
            "-q",
        ])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let good = std::fs::read_to_string(f.dir.join("run.ckpt")).unwrap();
    std::fs::write(
        f.dir.join("truncated.ckpt"),
        &good.as_bytes()[..good.len() / 3],
    )
    .unwrap();
    let edited = good.replacen("\"step\":20", "\"step\":19", 1);
    assert_ne!(edited, good);
    std::fs::write(f.dir.join("edited.ckpt"), edited).unwrap();
}

#[test]
fn cli_refuses_bad_input_clearly_and_touches_no_file() {
    let f = Fixtures::new();
    write_checkpoint(&f);
    let out = f.p("out.csv");
    let gen = |extra: &[&str]| -> Vec<String> {
        let mut v: Vec<String> = vec!["generate".into()];
        v.extend(extra.iter().map(|s| s.to_string()));
        v.extend(["-o".into(), out.clone(), "-q".into()]);
        v
    };
    let cmd = |args: &[&str]| -> Vec<String> { args.iter().map(|s| s.to_string()).collect() };
    let ck = f.p("run.ckpt");
    let cases: Vec<(&str, Vec<String>, &str)> = vec![
        (
            "n = 0",
            gen(&["-n", "0", "-s", "2"]),
            "invalid -n = 0: expected at least 1",
        ),
        (
            "s = 0",
            gen(&["-n", "10", "-s", "0"]),
            "invalid -s = 0: expected at least 1",
        ),
        ("missing -s", gen(&["-n", "10"]), "invalid -s = none: expected the dimension"),
        (
            "p = 0",
            gen(&["-n", "10", "-s", "2", "--p", "0"]),
            "invalid --p = 0: expected a finite number > 0",
        ),
        (
            "p < 0",
            gen(&["-n", "10", "-s", "2", "--p", "-1"]),
            "invalid --p = -1",
        ),
        (
            "p = NaN",
            gen(&["-n", "10", "-s", "2", "--p", "nan"]),
            "invalid --p = nan",
        ),
        (
            "q = 0",
            gen(&["-n", "10", "-s", "2", "--q", "0"]),
            "invalid --q = 0: expected a number > 0, inf (the torus distance) or E",
        ),
        (
            "q = -2",
            gen(&["-n", "10", "-s", "2", "--q", "-2"]),
            "expected a number > 0",
        ),
        (
            "q = abc",
            gen(&["-n", "10", "-s", "2", "--q", "abc"]),
            "invalid --q = abc",
        ),
        (
            "unknown precision",
            gen(&["-n", "10", "-s", "2", "--precision", "half"]),
            "invalid --precision = half: expected fast or full",
        ),
        (
            "precision in a region",
            gen(&["-n", "10", "-s", "2", "--shape", "ball:1", "--precision", "fast"]),
            "invalid --precision = fast: expected not in a region",
        ),
        (
            "kappa < 1",
            gen(&["-n", "10", "-s", "2", "--kappa", "0.5"]),
            "invalid --kappa = 0.5: expected auto or a finite number ≥ 1",
        ),
        (
            "restart < 0",
            gen(&["-n", "10", "-s", "2", "--restart", "-1"]),
            "invalid --restart = -1",
        ),
        (
            "tolerance < 0",
            gen(&["-n", "10", "-s", "2", "--tolerance", "-1"]),
            "invalid --tolerance = -1: expected a number ≥ 0",
        ),
        (
            "unknown energy",
            gen(&["-n", "10", "-s", "2", "--energy", "foo"]),
            "invalid --energy = foo: expected in the cube uqp, e-inf, l2star, md, cd or periodic",
        ),
        (
            "region energy in the cube",
            gen(&["-n", "10", "-s", "2", "--energy", "e-inf-g"]),
            "e-inf-g and e-p-g are energies of a region",
        ),
        (
            "unknown integrator",
            gen(&["-n", "10", "-s", "2", "--integrator", "foo"]),
            "invalid --integrator = foo: expected dem or lbfgs",
        ),
        (
            "unknown polish",
            gen(&["-n", "10", "-s", "2", "--polish", "foo"]),
            "invalid --polish = foo: expected none, md, l2star, cd or periodic",
        ),
        (
            "NaN in --init file",
            gen(&["--init", &f.p("nan.csv")]),
            "expected a finite number",
        ),
        (
            "point outside [0,1] in --init file",
            gen(&["--init", &f.p("outside.csv")]),
            "invalid --init = 2 points in 2 dimensions: expected points in [0, 1]^s",
        ),
        (
            "ragged rows in --init file",
            gen(&["--init", &f.p("ragged.csv")]),
            "line 2 has 1 coordinate, line 1 has 2",
        ),
        (
            "word in --init file",
            gen(&["--init", &f.p("words.csv")]),
            "line 2, field 2: \"abc\" is not a number",
        ),
        (
            "--init file of another n",
            gen(&["-n", "3", "-s", "2", "--init", &f.p("two.csv")]),
            "invalid -n = 3: expected the number of init points, 2",
        ),
        (
            "output directory missing",
            cmd(&[
                "generate",
                "-n",
                "10",
                "-s",
                "2",
                "-o",
                "/nonexistent-dir/x.csv",
            ]),
            "invalid -o /nonexistent-dir/x.csv: the directory /nonexistent-dir does not exist",
        ),
        (
            "output is a directory",
            cmd(&[
                "generate",
                "-n",
                "10",
                "-s",
                "2",
                "-o",
                f.dir.to_str().unwrap(),
            ]),
            "it is a directory",
        ),
        (
            "--plot with an unknown picture format",
            gen(&["-n", "10", "-s", "2", "--plot", &f.p("pic.jpg")]),
            "expected a file name ending in .png or .svg",
        ),
        (
            "--plot with s = 1",
            gen(&["-n", "10", "-s", "1", "--plot", &f.p("pic.png")]),
            "plots need s ≥ 2",
        ),
        (
            "--threads 0",
            {
                let mut v = cmd(&["--threads", "0"]);
                v.extend(gen(&["-n", "10", "-s", "2"]));
                v
            },
            "invalid --threads = 0: expected 1 to 1024 threads",
        ),
        (
            "region with no interior",
            gen(&[
                "--region",
                "x^2 + y^2 + 1",
                "--box",
                "-1,1,-1,1",
                "-n",
                "10",
            ]),
            "holds no point with g ≤ 0",
        ),
        (
            "malformed expression",
            gen(&["--region", "x +* y", "--box", "-1,1,-1,1", "-n", "10"]),
            "syntax error: expected a number, a variable, a function or '(' after \"+\"",
        ),
        (
            "unknown variable",
            gen(&["--region", "x + w - 1", "--box", "-1,1,-1,1", "-n", "10"]),
            "unknown variable \"w\": with s = 2 the variables are x1, x2 (or x, y)",
        ),
        (
            "--region without --box",
            gen(&["--region", "x^2 + y^2 - 1", "-n", "10"]),
            "invalid --box = none: expected LO1,HI1,LO2,HI2,...: a region expression needs a bounding box",
        ),
        (
            "--box with LO ≥ HI",
            gen(&[
                "--region",
                "x^2 + y^2 - 1",
                "--box",
                "1,-1,-1,1",
                "-n",
                "10",
            ]),
            "dimension 1 has LO = 1 ≥ HI = -1",
        ),
        (
            "unknown shape",
            gen(&["--shape", "cube:3", "-n", "10"]),
            "invalid --shape = cube:3: expected ball:R",
        ),
        (
            "unknown region energy",
            gen(&[
                "--shape", "ball:1", "-s", "2", "-n", "10", "--energy", "uqp",
            ]),
            "invalid --energy = uqp: expected in a region e-inf-g",
        ),
        (
            "--checkpoint-every 0",
            gen(&[
                "-n",
                "10",
                "-s",
                "2",
                "--checkpoint",
                &f.p("new.ckpt"),
                "--checkpoint-every",
                "0",
            ]),
            "invalid --checkpoint-every = 0: expected a number of steps ≥ 1",
        ),
        (
            "--resume without a file",
            gen(&["-n", "10", "-s", "2", "--resume"]),
            "give --resume FILE or --checkpoint FILE --resume",
        ),
        (
            "--resume of a missing file",
            gen(&["-n", "10", "-s", "2", "--resume", &f.p("missing.ckpt")]),
            "no such checkpoint file",
        ),
        (
            "resume with another configuration",
            gen(&["-n", "20", "-s", "2", "--steps", "30", "--resume", &ck]),
            "it was made with --steps = 20 (this run: 30)",
        ),
        (
            "resume with another seed and start",
            gen(&[
                "-n", "20", "-s", "2", "--steps", "20", "--init", "random", "--seed", "4",
                "--resume", &ck,
            ]),
            "--init = halton (this run: random)",
        ),
        (
            "truncated checkpoint",
            gen(&[
                "-n",
                "20",
                "-s",
                "2",
                "--steps",
                "20",
                "--resume",
                &f.p("truncated.ckpt"),
            ]),
            "not valid JSON, the file is damaged or truncated",
        ),
        (
            "edited checkpoint",
            gen(&[
                "-n",
                "20",
                "-s",
                "2",
                "--steps",
                "20",
                "--resume",
                &f.p("edited.ckpt"),
            ]),
            "its checksum does not match its state",
        ),
        (
            "a point file as checkpoint",
            gen(&[
                "-n",
                "20",
                "-s",
                "2",
                "--resume",
                &f.p("not-a-checkpoint.json"),
            ]),
            "no \"format\": \"stillpoint checkpoint\" field",
        ),
        (
            "a DEM checkpoint resumed with L-BFGS",
            gen(&[
                "-n",
                "20",
                "-s",
                "2",
                "--steps",
                "20",
                "--integrator",
                "lbfgs",
                "--resume",
                &ck,
            ]),
            "--integrator = Dem (this run: Lbfgs)",
        ),
        (
            "eval: NaN",
            cmd(&["eval", &f.p("nan.csv")]),
            "expected a finite number",
        ),
        (
            "eval: point outside [0,1]",
            cmd(&["eval", &f.p("outside.csv")]),
            "invalid point 2, coordinate 2 = 1.5: expected a coordinate in [0, 1]",
        ),
        (
            "eval: point outside [0,1] names the options that read other scales",
            cmd(&["eval", &f.p("outside.csv")]),
            "read back with --bounds LO1,HI1,..., a design's values with its --var or --space",
        ),
        (
            "eval: empty file",
            cmd(&["eval", &f.p("empty.csv")]),
            "no points found",
        ),
        (
            "eval: ragged rows",
            cmd(&["eval", &f.p("ragged.csv")]),
            "line 2 has 1 coordinate",
        ),
        (
            "eval: malformed JSON",
            cmd(&["eval", &f.p("malformed.json")]),
            "not valid JSON",
        ),
        (
            "eval: JSON of the wrong shape",
            cmd(&["eval", &f.p("shape.json")]),
            "\"points\" is the number 3",
        ),
        (
            "eval: truncated .npy",
            cmd(&["eval", &f.p("truncated.npy")]),
            "truncated: shape [4, 2] needs 64 bytes of data, the file has 24",
        ),
        (
            "eval: .npy with bytes after the array",
            cmd(&["eval", &f.p("trailing.npy")]),
            "trailing.npy: 8 bytes after the array: the array's data must end the file \
             (expected 64 bytes of data for shape [4, 2] of float64, found 72)",
        ),
        (
            "eval: missing file",
            cmd(&["eval", &f.p("missing.csv")]),
            "missing.csv: cannot read",
        ),
        (
            "integrate: point outside [0,1]",
            cmd(&["integrate", &f.p("outside.csv")]),
            "[0, 1]",
        ),
        (
            "integrate: truncated .npy",
            cmd(&["integrate", &f.p("truncated.npy")]),
            "truncated",
        ),
        (
            "unknown baseline",
            cmd(&["baseline", "foo", "-n", "10", "-s", "2", "-o", &out]),
            "invalid baseline = foo: expected one of: random, halton",
        ),
        (
            "baseline n = 0",
            cmd(&["baseline", "sobol", "-n", "0", "-s", "2", "-o", &out]),
            "n = 0",
        ),
        (
            "unknown study",
            cmd(&["study", "foo", "--quick", "--out", &f.p("study")]),
            "invalid study = foo: expected one of: correlation",
        ),
        (
            "compare: bad case",
            cmd(&["compare", "--cases", "2x0", "--out", &f.p("cmp")]),
            "invalid --cases = 2x0: n \"0\" is not an integer ≥ 1",
        ),
        (
            "compare: unknown energy",
            cmd(&["compare", "--energy", "foo", "--out", &f.p("cmp")]),
            // Every energy the help lists, the three added after the first four too.
            "invalid --energy = foo: expected l2star, md, cd, periodic, wd, smooth or curved",
        ),
        (
            "plot: unknown picture format",
            cmd(&["plot", &f.p("out.csv"), "-o", &f.p("pic.jpg")]),
            "invalid -o",
        ),
        (
            "plot: --dims beyond s",
            cmd(&[
                "plot",
                &f.p("out.csv"),
                "--dims",
                "3",
                "-o",
                &f.p("pic.png"),
            ]),
            "invalid --dims = 3: expected 1 ≤ K ≤ s = 2",
        ),
        (
            "plot: NaN in the file",
            cmd(&["plot", &f.p("nan.csv"), "-o", &f.p("pic.png")]),
            "expected a finite number",
        ),
        (
            "plot: malformed trajectory",
            cmd(&[
                "plot",
                "--trajectory",
                &f.p("bad-trajectory.json"),
                "-o",
                &f.p("pic.png"),
            ]),
            "expected a trajectory written by generate --trajectory",
        ),
        (
            "plot: malformed region",
            cmd(&[
                "plot",
                &f.p("out.csv"),
                "--region",
                "x^^2",
                "--box",
                "0,1,0,1",
                "-o",
                &f.p("pic.png"),
            ]),
            "invalid --region",
        ),
        (
            "-n not a number",
            gen(&["-n", "ten", "-s", "2"]),
            "invalid -n = ten: expected at least 1 point",
        ),
    ];
    let before = snapshot(&f.dir);
    let mut table = String::from("| input | message |\n|---|---|\n");
    for (what, args, needle) in &cases {
        let o = Command::new(env!("CARGO_BIN_EXE_stillpoint"))
            .args(args)
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(!o.status.success(), "{what}: {args:?} succeeded");
        assert!(!err.contains("panicked"), "{what}: panicked: {err}");
        assert!(
            err.contains(needle),
            "{what}: message {err:?} does not contain {needle:?}"
        );
        assert!(
            snapshot(&f.dir) == before,
            "{what}: a file was written, changed or left behind"
        );
        let first = err.lines().next().unwrap_or("").replace('|', "\\|");
        table += &format!("| {what} | `{}` |\n", first.replace(&f.p(""), ""));
    }
    assert!(cases.len() >= 20);
    // `cargo test --test errors -- --nocapture` prints the table.
    println!("{table}");
}

/// `--seed` of every command that takes one is read by one declaration: a seed out of
/// range, negative, fractional or not a number gets the same refusal, naming the value
/// as typed and the range accepted, and the same status as every refused value.
#[test]
fn every_command_refuses_a_bad_seed_alike() {
    let dir = tmpdir("seed");
    let out = dir.join("out.csv");
    let out = out.to_str().unwrap();
    let study = dir.join("study");
    let commands: [&[&str]; 5] = [
        &["generate", "-n", "5", "-s", "2", "-q", "-o", out],
        &["baseline", "sobol", "-n", "4", "-s", "2", "-o", out],
        &["integrate", "--expr", "x1", "-s", "1"],
        &["sensitivity", "--expr", "x1 + x2", "-s", "2"],
        &[
            "study",
            "table5",
            "--quick",
            "-q",
            "--out",
            study.to_str().unwrap(),
        ],
    ];
    for seed in ["18446744073709551616", "-1", "1.5", "abc", ""] {
        for command in commands {
            let mut args = command.to_vec();
            args.extend(["--seed", seed]);
            let o = Command::new(env!("CARGO_BIN_EXE_stillpoint"))
                .args(&args)
                .output()
                .unwrap();
            let err = String::from_utf8_lossy(&o.stderr);
            assert_eq!(o.status.code(), Some(1), "{args:?}: {err}");
            assert_eq!(
                err.lines().next().unwrap_or_default(),
                format!("error: invalid --seed = {seed}: expected a whole number in [0, 2^64)"),
                "{args:?}"
            );
        }
    }
    let written: Vec<_> = std::fs::read_dir(&dir).unwrap().collect();
    assert!(written.is_empty(), "a refusal wrote {written:?}");
}

/// Every refused `--threads` states the one range accepted (the range its help gives),
/// with the status of every refused value.
#[test]
fn every_bad_thread_count_is_refused_with_the_one_range() {
    for typed in ["-1", "0", "1025", "abc", "2.5", "99999999999999999999999"] {
        let args = [
            "--threads",
            typed,
            "baseline",
            "sobol",
            "-n",
            "4",
            "-s",
            "2",
        ];
        let o = Command::new(env!("CARGO_BIN_EXE_stillpoint"))
            .args(args)
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(1), "{args:?}: {err}");
        assert_eq!(
            err.lines().next().unwrap_or_default(),
            format!("error: invalid --threads = {typed}: expected 1 to 1024 threads"),
            "{args:?}"
        );
    }
    for typed in ["1", "1024"] {
        let o = Command::new(env!("CARGO_BIN_EXE_stillpoint"))
            .args([
                "--threads",
                typed,
                "baseline",
                "sobol",
                "-n",
                "4",
                "-s",
                "2",
            ])
            .output()
            .unwrap();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    }
}

/// One numeric flag of one command: the command line it is given to, the values it
/// refuses (a negative number, a non-number and, where its range has one, a value past
/// the upper end) and one value it takes (`None` where a run is too long for a test).
struct Numeric {
    args: Vec<String>,
    flag: &'static str,
    refused: &'static [&'static str],
    valid: Option<&'static str>,
}

/// Every numeric flag of every command refuses a bad value as every refused value is
/// refused: status 1, one line `invalid FLAG = VALUE: expected …` naming the value as
/// typed and the one range of the flag (a value past the upper end may be told that end
/// too), and no file written; a value in range still runs.
#[test]
fn every_numeric_flag_refuses_a_bad_value_with_its_range() {
    let dir = tmpdir("numeric");
    let points = dir.join("p.csv");
    std::fs::write(&points, "0.1,0.2\n0.3,0.9\n0.6,0.4\n0.8,0.7\n").unwrap();
    let path = |name: &str| dir.join(name).to_str().unwrap().to_string();
    let (p, out, pic, ckpt, cmp) = (
        path("p.csv"),
        path("out.csv"),
        path("pic.png"),
        path("run.ckpt"),
        path("cmp"),
    );
    let line = |args: &[&str]| -> Vec<String> { args.iter().map(|a| a.to_string()).collect() };
    // The refused values of each kind of range.
    const COUNT: &[&str] = &["-3", "ten", "68719476721"];
    const SEED: &[&str] = &["-1", "abc", "18446744073709551616"];
    const STEPS: &[&str] = &["-1", "many", "18446744073709551616"];
    const REAL: &[&str] = &["-1", "abc"];
    const LEVEL: &[&str] = &["-0.5", "abc", "1.5"];
    const REPLICATES: &[&str] = &["-8", "abc", "16385"];
    let n = |flag, refused, valid| Numeric {
        args: line(&["generate", "-q", "-o", &out, "-n", "5", "-s", "2"]),
        flag,
        refused,
        valid: Some(valid),
    };
    let quad = |flag, refused, valid| Numeric {
        args: line(&["integrate", "--expr", "x1", "-s", "1"]),
        flag,
        refused,
        valid: Some(valid),
    };
    let sobol = |flag, refused, valid| Numeric {
        args: line(&["sensitivity", "--expr", "x1 + x2", "-s", "2"]),
        flag,
        refused,
        valid: Some(valid),
    };
    let flags = vec![
        Numeric {
            args: line(&["generate", "-q", "-o", &out, "-s", "2"]),
            flag: "-n",
            refused: COUNT,
            valid: Some("5"),
        },
        Numeric {
            args: line(&["generate", "-q", "-o", &out, "-n", "5"]),
            flag: "-s",
            refused: COUNT,
            valid: Some("2"),
        },
        n("--seed", SEED, "7"),
        n("--steps", COUNT, "20"),
        n("--shifts", &["-1", "some", "1048577"], "4"),
        n("--log-every", COUNT, "5"),
        n("--p", REAL, "2"),
        n("--q", REAL, "0.5"),
        n("--kappa", REAL, "100"),
        n("--restart", REAL, "off"),
        n("--tolerance", REAL, "0.001"),
        Numeric {
            args: line(&[
                "generate",
                "-q",
                "-o",
                &out,
                "-n",
                "5",
                "-s",
                "2",
                "--checkpoint",
                &ckpt,
            ]),
            flag: "--checkpoint-every",
            refused: STEPS,
            valid: Some("5"),
        },
        Numeric {
            args: line(&["baseline", "sobol", "-o", &out, "-s", "2"]),
            flag: "-n",
            refused: COUNT,
            valid: Some("4"),
        },
        Numeric {
            args: line(&["baseline", "sobol", "-o", &out, "-n", "4"]),
            flag: "-s",
            refused: COUNT,
            valid: Some("2"),
        },
        Numeric {
            args: line(&["baseline", "sobol", "-o", &out, "-n", "4", "-s", "2"]),
            flag: "--seed",
            refused: SEED,
            valid: Some("3"),
        },
        Numeric {
            args: line(&["study", "table5", "--quick", "-q", "--out", &cmp]),
            flag: "--seed",
            refused: SEED,
            valid: None,
        },
        Numeric {
            args: line(&["compare", "--cases", "2x10", "--out", &cmp]),
            flag: "--steps",
            refused: STEPS,
            // No step at all compares the starts.
            valid: Some("0"),
        },
        Numeric {
            args: line(&["integrate", "--expr", "x1"]),
            flag: "-s",
            refused: COUNT,
            valid: Some("1"),
        },
        Numeric {
            args: line(&["integrate", &p, "--expr", "x1"]),
            flag: "-s",
            refused: COUNT,
            valid: Some("2"),
        },
        quad("--rel-tol", REAL, "0.01"),
        quad("--abs-tol", REAL, "0.001"),
        quad("--level", LEVEL, "0.9"),
        quad("--replicates", REPLICATES, "4"),
        quad("--max-n", SEED, "4096"),
        quad("--seed", SEED, "1"),
        Numeric {
            args: line(&["sensitivity", "--expr", "x1 + x2"]),
            flag: "-s",
            refused: COUNT,
            valid: Some("2"),
        },
        sobol("--abs-tol", REAL, "0.01"),
        sobol("--level", LEVEL, "0.9"),
        sobol("--replicates", REPLICATES, "4"),
        sobol("--max-n", SEED, "4096"),
        sobol("--seed", SEED, "1"),
        Numeric {
            args: line(&["plot", &p, "-o", &pic]),
            flag: "--dims",
            refused: &["-1", "two", "3"],
            valid: Some("2"),
        },
        Numeric {
            args: line(&["plot", &p, "-o", &pic]),
            flag: "--split",
            refused: &["-1", "x", "5"],
            valid: Some("1"),
        },
        Numeric {
            args: line(&["bench", "--points", &p]),
            flag: "--reps",
            refused: &["-1", "abc", "100001"],
            valid: Some("1"),
        },
        Numeric {
            args: line(&["eval", &p]),
            flag: "--threads",
            refused: &["-1", "abc", "1025"],
            valid: Some("2"),
        },
    ];
    let run = |args: &[String], flag: &str, value: &str| {
        let mut all = args.to_vec();
        all.extend([flag.to_string(), value.to_string()]);
        let o = Command::new(env!("CARGO_BIN_EXE_stillpoint"))
            .args(&all)
            .output()
            .unwrap();
        (all, o)
    };
    let before = snapshot(&dir);
    for f in &flags {
        // The accepted range as the first refusal (of a negative number) words it.
        let mut range: Option<String> = None;
        for value in f.refused {
            let (all, o) = run(&f.args, f.flag, value);
            let err = String::from_utf8_lossy(&o.stderr);
            assert_eq!(o.status.code(), Some(1), "{all:?}: {err}");
            let first = err.lines().next().unwrap_or_default();
            let head = format!("error: invalid {} = {value}: expected ", f.flag);
            let expected = first
                .strip_prefix(&head)
                .unwrap_or_else(|| panic!("{all:?}: {first:?} does not start with {head:?}"));
            let range = range.get_or_insert_with(|| expected.to_string());
            assert!(
                expected.starts_with(range.as_str()),
                "{all:?}: {expected:?} is not the range {range:?}"
            );
            assert!(
                snapshot(&dir) == before,
                "{all:?}: a file was written, changed or left behind"
            );
        }
    }
    for f in &flags {
        let Some(value) = f.valid else { continue };
        let (all, o) = run(&f.args, f.flag, value);
        assert!(
            o.status.success(),
            "{all:?}: {}",
            String::from_utf8_lossy(&o.stderr)
        );
    }
}

#[test]
fn library_refuses_bad_input_clearly() {
    use stillpoint::config::{GenerateConfig, Init};
    use stillpoint::energies::region::ImplicitRegion;
    use stillpoint::integrators::{Dem, Kappa};
    use stillpoint::pipeline::run_config;
    let d = tmpdir("lib");
    let msg = |r: Result<(), String>| r.unwrap_err();
    let gen = |cfg: GenerateConfig| {
        run_config(&cfg, |_| {})
            .map(|_| ())
            .map_err(|e| e.to_string())
    };
    let mut cases: Vec<(&str, String, &str)> = Vec::new();
    cases.push((
        "n = 0",
        msg(gen(GenerateConfig::new(0, 2))),
        "invalid n = 0",
    ));
    cases.push((
        "s = 0",
        msg(gen(GenerateConfig::new(5, 0))),
        "invalid s = 0",
    ));
    let mut c = GenerateConfig::new(5, 2);
    c.p = Some(-1.0);
    cases.push(("p < 0", msg(gen(c)), "p"));
    let mut c = GenerateConfig::new(2, 2);
    c.init = Init::Points(stillpoint::PointSet::from_rows(&[[0.1, 0.2], [0.3, 1.5]]).unwrap());
    cases.push(("start outside [0,1]", msg(gen(c)), "[0, 1]"));
    let mut c = GenerateConfig::new(3, 2);
    c.init = Init::Points(stillpoint::PointSet::from_rows(&[[0.1, 0.2], [0.3, 0.5]]).unwrap());
    cases.push((
        "start of another n",
        msg(gen(c)),
        "3 points in 2 dimensions (-n, -s)",
    ));
    let mut c = GenerateConfig::new(5, 2);
    c.dem.kappa = Kappa::Fixed(0.5);
    cases.push(("kappa < 1", msg(gen(c)), "kappa"));
    let io_err = |r: Result<stillpoint::PointSet, stillpoint::io::IoError>| {
        r.map(|_| ()).map_err(|e| e.to_string())
    };
    cases.push((
        "empty text",
        msg(io_err(stillpoint::io::parse_text("", "input"))),
        "input: no points found",
    ));
    cases.push((
        "NaN in text",
        msg(io_err(stillpoint::io::parse_text("0.1 NaN\n", "input"))),
        "finite",
    ));
    let expr = |t: &str, s: usize| {
        stillpoint::parse::expr::RegionExpr::parse(t, s)
            .map(|_| ())
            .map_err(|e| e.to_string())
    };
    cases.push(("malformed expression", msg(expr("x + ", 2)), "x + "));
    cases.push((
        "unknown variable",
        msg(expr("x + q", 2)),
        "unknown variable \"q\"",
    ));
    cases.push(("expression in s = 0", msg(expr("x", 0)), ""));
    let empty = ImplicitRegion::new(
        Arc::new(|x: &[f64]| x[0] * x[0] + 1.0),
        vec![-1.0],
        vec![1.0],
    )
    .unwrap();
    cases.push((
        "region with no interior",
        msg(empty.check(1024, 0).map_err(|e| e.to_string())),
        "no point",
    ));
    cases.push((
        "unknown baseline",
        msg(stillpoint::sequences::Baseline::parse("foo")
            .map(|_| ())
            .map_err(|e| e.to_string())),
        "expected one of",
    ));
    cases.push((
        "unknown study",
        msg(stillpoint_paper::studies::Study::parse("foo")
            .map(|_| ())
            .map_err(|e| e.to_string())),
        "expected one of",
    ));
    let garbage = d.join("garbage.ckpt");
    std::fs::write(&garbage, b"\x00\x01not json").unwrap();
    cases.push((
        "corrupted checkpoint",
        msg(stillpoint::solve::checkpoint::read_checkpoint(&garbage)
            .map(|_| ())
            .map_err(|e| e.to_string())),
        "damaged or truncated",
    ));
    let pts = stillpoint::PointSet::from_rows(&[[0.1, 0.2], [0.3, 0.5]]).unwrap();
    cases.push((
        "write into a missing directory",
        msg(
            stillpoint::io::write_points(&d.join("missing/p.csv"), &pts, &serde_json::Value::Null)
                .map_err(|e| e.to_string()),
        ),
        "missing/p.csv",
    ));
    cases.push((
        "plot with too many dims",
        msg(stillpoint_plot::save_projection_matrix(
            &d.join("m.png"),
            "t",
            &pts,
            3,
            &[0.0; 3],
            &[1.0; 3],
        )
        .map_err(|e| e.to_string())),
        "1 ≤ dims ≤ s",
    ));
    let cube = stillpoint::PeriodicCube::new(2).unwrap();
    let e = stillpoint::Uqp::new(stillpoint::energies::Distance::Q(0.3), 1.0).unwrap();
    let coincident = stillpoint::PointSet::from_rows(&[[0.2, 0.3], [0.2, 0.3]]).unwrap();
    cases.push((
        "coincident start points",
        msg(stillpoint::integrators::Problem::borrowed(&e, &cube)
            .and_then(|p| {
                stillpoint::integrators::Executor::new(&p, Dem::default()).run(coincident)
            })
            .map(|_| ())
            .map_err(|e| e.to_string())),
        "coincide",
    ));
    for (what, message, needle) in &cases {
        assert!(
            message.contains(needle),
            "{what}: {message:?} lacks {needle:?}"
        );
    }
    assert!(cases.len() >= 15);
    // Nothing was written by any refusal.
    let names: Vec<_> = std::fs::read_dir(&d)
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    assert_eq!(names, vec![std::ffi::OsString::from("garbage.ckpt")]);
}
