//! Every declared option of `generate` and `eval` ([`stillpoint::pipeline::options::ALL`])
//! walked through the command line. The values come from the option's declaration:
//! each word it accepts, and numbers at and beyond the bounds of its kind (a count's
//! bad values are one below its least and `x`, a word's `nope`, ...); the combinations
//! its groups' rules refuse come from its groups (a baseline refuses every option
//! outside the baseline group and the design space's, a goal every option of the
//! paper's pipeline, a design space every option that places the unit-cube set). So a new option is walked without
//! a line here, unless its kind has no value to make up (an expression, a file, a
//! variable's law): then [`EXAMPLES`] gives one, and the test fails until it does.

mod common;

use common::{bin, TempDir};
use std::path::Path;
use stillpoint::pipeline::options::{Command, Declared, Group, Kind, ALL};

/// Values of the options whose kind has none to make up, for the command line:
/// (option, good values, bad values). `{old}` is a file of 2-D points in the unit square,
/// `{far}` one with a point outside it, `{dir}` a scratch directory.
const EXAMPLES: &[(&str, &[&str], &[&str])] = &[
    ("region", &["x^2 + y^2 - 1"], &["x^^"]),
    ("shape", &["ball:1"], &["nope:1"]),
    ("constraints", &["x1 + x2 <= 1.5"], &["x1 * x2 <= 1"]),
    ("space", &["a=normal(0,1)", "a=uniform(-1,1)"], &["a=nope"]),
    ("correlation", &["1,0.5;0.5,1"], &["1,x"]),
    // The command line's flags of these take the file the library is told of.
    (
        "trajectory",
        &["{dir}/t.json"],
        &["{dir}/no/such/dir/t.json"],
    ),
    (
        "checkpoint",
        &["{dir}/c.ckpt"],
        &["{dir}/no/such/dir/c.ckpt"],
    ),
];

/// The other arguments with which an option's good value runs, where those of its
/// groups ([`context`]) do not do: each option named here needs company of its own.
const COMPANY: &[(&str, &[&str])] = &[
    ("extend", &["-n", "3"]),
    ("nested", &["-s", "2"]),
    ("region", &["-n", "8", "--box", "-1,1,-1,1", "--steps", "5"]),
    (
        "box",
        &["-n", "8", "--region", "x^2 + y^2 - 1", "--steps", "5"],
    ),
    ("shape", &["-n", "8", "-s", "2", "--steps", "5"]),
    (
        "constraints",
        &["-n", "8", "--box", "0,1,0,1", "--steps", "5"],
    ),
    ("mixture", &["-n", "8", "-s", "3", "--steps", "5"]),
    ("space", &["-n", "8"]),
    (
        "correlation",
        &[
            "-n",
            "8",
            "--var",
            "a=normal(0,1)",
            "--var",
            "b=normal(0,1)",
        ],
    ),
];

/// The same for `eval`: the file measured, and what else the option needs.
const EVAL_COMPANY: &[(&str, &[&str])] = &[
    ("region", &["{old}", "--box", "-1,1,-1,1"]),
    ("box", &["{old}", "--region", "x^2 + y^2 - 1"]),
    ("constraints", &["{old}", "--box", "0,1,0,1"]),
    ("mixture", &["{mix}"]),
    ("space", &["{design}", "--var", "b=normal(0,1)"]),
    (
        "correlation",
        &[
            "{design}",
            "--var",
            "a=normal(0,1)",
            "--var",
            "b=normal(0,1)",
        ],
    ),
];

/// A region in which every option of the paper's pipeline runs.
const REGION: &[&str] = &["-n", "8", "-s", "2", "--shape", "ball:1", "--steps", "5"];

/// Rules of one option (or two) rather than of a group, with the combination refused
/// and the other option the refusal names: `(option, command, arguments, other)`.
const RULES: &[(&str, &str, &[&str], &str)] = &[
    (
        "n",
        "generate",
        &["-n", "9", "-s", "2", "--nested", "4,8"],
        "nested",
    ),
    (
        "s",
        "generate",
        &["-n", "3", "-s", "3", "--extend", "{old}"],
        "--extend",
    ),
    (
        "method",
        "generate",
        &[
            "-n",
            "8",
            "-s",
            "2",
            "--method",
            "paper",
            "--goal",
            "integration",
        ],
        "--goal",
    ),
    (
        "correlation",
        "generate",
        &["-n", "8", "-s", "2", "--correlation", "1,0.5;0.5,1"],
        "--var",
    ),
    (
        "exact",
        "eval",
        &["{old}", "--exact", "--shape", "ball:1"],
        "region",
    ),
    (
        "correlation",
        "eval",
        &["{old}", "--correlation", "1,0.5;0.5,1"],
        "--var",
    ),
    (
        "space",
        "eval",
        &[
            "{design}",
            "--var",
            "a=normal(0,1)",
            "--var",
            "b=normal(0,1)",
            "--box",
            "0,1,0,1",
        ],
        "--box",
    ),
];

/// A number as the command line would be given it (`1`, not `1.0`).
fn num(v: f64) -> String {
    format!("{v}")
}

/// The values of the option's kind that it accepts and that it refuses, or `None` for a
/// kind with none to make up (the option then needs [`EXAMPLES`]).
fn values(d: &Declared) -> Option<(Vec<String>, Vec<String>)> {
    if let Some((_, good, bad)) = EXAMPLES.iter().find(|e| e.0 == d.name) {
        let all = |v: &[&str]| v.iter().map(|s| s.to_string()).collect();
        return Some((all(good), all(bad)));
    }
    let words = || d.words().iter().map(|w| w.to_string()).collect::<Vec<_>>();
    let nope = || "nope".to_string();
    Some(match d.kind {
        Kind::Count { min, max } => {
            let mut bad = vec!["x".to_string(), "1.5".to_string()];
            bad.push(if min > 0 {
                (min - 1).to_string()
            } else {
                "-1".into()
            });
            if max < u64::MAX {
                bad.push((max + 1).to_string());
            }
            (vec![min.to_string(), (min + 3).min(max).to_string()], bad)
        }
        Kind::Seed => (vec!["0".into(), "3".into()], vec!["-1".into(), "x".into()]),
        Kind::Real { min, closed, below } => {
            let inside = match below {
                Some(b) => (min + b) / 2.0,
                None => min + 1.0,
            };
            let mut good = vec![num(inside)];
            let mut bad = vec!["x".to_string()];
            if closed {
                good.push(num(min));
                bad.push(num(min - 1.0));
            } else {
                bad.push(num(min));
            }
            bad.extend(below.map(num));
            (good, bad)
        }
        Kind::RealOrWord { min, closed, .. } => {
            let mut good = words();
            good.push(num(min + 1.0));
            let below = if closed { min - 1.0 } else { min };
            (good, vec![nope(), num(below)])
        }
        Kind::Word(_) => (words(), vec![nope()]),
        Kind::WordOrPoints(_) => (words(), vec![nope(), "{far}".into()]),
        Kind::Points => (
            vec!["{old}".into()],
            vec!["{far}".into(), "{dir}/none.csv".into()],
        ),
        Kind::Numbers | Kind::Bounds => (vec!["0,1,0,1".into()], vec!["0,x".into()]),
        Kind::Sizes => (
            vec!["4,8".into()],
            vec!["8,4".into(), "0,4".into(), "x".into()],
        ),
        // A flag without a value: given is its good value, and it has no bad one.
        Kind::Flag => (Vec::new(), Vec::new()),
        _ => return None,
    })
}

/// The other arguments of `command` with which a good value of `d` runs.
fn context(d: &Declared, command: &str) -> Vec<&'static str> {
    let own = if command == "eval" {
        EVAL_COMPANY
    } else {
        COMPANY
    };
    if let Some((_, args)) = own.iter().find(|c| c.0 == d.name) {
        return args.to_vec();
    }
    if command == "eval" {
        return vec!["{old}"];
    }
    let mut pairs = vec![["-n", "8"], ["-s", "2"]];
    if d.is(Group::Paper) {
        // A short descent: the walk checks the options, not the pipeline.
        pairs.push(["--steps", "5"]);
    }
    // The option's own flag is the walk's to give.
    pairs
        .into_iter()
        .filter(|p| p[0] != d.cli)
        .flatten()
        .collect()
}

/// The combinations `d`'s groups refuse in `command`, each with the option the refusal
/// names besides `d` (or what it names it by).
fn group_rules(d: &Declared, command: &str, given: &[String]) -> Vec<(Vec<String>, &'static str)> {
    let with = |pre: &[&str]| -> Vec<String> {
        pre.iter()
            .map(|s| s.to_string())
            .chain(given.iter().cloned())
            .collect()
    };
    let space = ["--var", "a=normal(0,1)", "--var", "b=normal(0,1)"];
    let mut rules = Vec::new();
    if command == "eval" {
        if d.is(Group::Placement) {
            let mut pre = vec!["{design}"];
            pre.extend(space);
            rules.push((with(&pre), "--var"));
        }
        return rules;
    }
    let cube = ["-n", "8", "-s", "2"];
    // A design space is dealt from a baseline's set as from any other.
    if !d.is(Group::Baseline) && !d.is(Group::Design) {
        let mut pre = cube.to_vec();
        pre.extend(["--method", "sobol"]);
        rules.push((with(&pre), "sobol"));
    }
    if d.is(Group::Paper) || d.is(Group::Descent) {
        let mut pre = cube.to_vec();
        pre.extend(["--goal", "integration"]);
        rules.push((with(&pre), "--goal"));
    }
    if d.is(Group::Placement) {
        let mut pre = vec!["-n", "8"];
        pre.extend(space);
        rules.push((with(&pre), "--var"));
    }
    rules
}

/// Runs `stillpoint SUBCOMMAND ARGS` with the placeholders filled in: (success, stderr).
fn run(dir: &Path, subcommand: &str, args: &[String]) -> (bool, String) {
    let mut cmd = bin();
    cmd.args(["--threads", "1", subcommand]);
    if subcommand == "generate" {
        cmd.arg("-q").arg("-o").arg(dir.join("out.csv"));
    }
    let o = cmd
        .args(args.iter().map(|a| fill(dir, a)))
        .output()
        .unwrap();
    (
        o.status.success(),
        String::from_utf8_lossy(&o.stderr).into_owned(),
    )
}

/// `a` with its placeholders replaced by the scratch files of `dir`.
fn fill(dir: &Path, a: &str) -> String {
    let file = |name: &str| dir.join(name).display().to_string();
    a.replace("{old}", &file("old.csv"))
        .replace("{mix}", &file("mix.csv"))
        .replace("{design}", &file("design.csv"))
        .replace("{far}", &file("far.csv"))
        .replace("{dir}", &dir.display().to_string())
}

/// What the walk of one option in one command found wrong.
fn walk(dir: &Path, d: &Declared, command: &str) -> Result<(), String> {
    let Some((good, bad)) = values(d) else {
        return Err(format!(
            "{}: no values to walk (add it to EXAMPLES)",
            d.name
        ));
    };
    let flag = d.cli;
    let named = |e: &str| {
        std::iter::once(flag)
            .chain(d.cli_also.iter().copied())
            .any(|f| e.contains(f))
    };
    let given = |v: Option<&String>| -> Vec<String> {
        std::iter::once(flag.to_string())
            .chain(v.cloned())
            .collect()
    };
    let with = |v: Option<&String>, others: &[&str]| -> Vec<String> {
        let mut a = given(v);
        a.extend(others.iter().map(|s| s.to_string()));
        a
    };
    let args = |v: Option<&String>| with(v, &context(d, command));
    // Every good value runs: with the option's own company, or, for an option of the
    // paper's pipeline, in a region (whose energies the cube refuses).
    let goods: Vec<Option<&String>> = if good.is_empty() {
        vec![None]
    } else {
        good.iter().map(Some).collect()
    };
    for v in &goods {
        let (ok, e) = run(dir, command, &args(*v));
        let in_region = || {
            command == "generate" && d.is(Group::Paper) && run(dir, command, &with(*v, REGION)).0
        };
        if !ok && !in_region() {
            return Err(format!("{command} {flag} {v:?} does not run: {e}"));
        }
    }
    for v in &bad {
        let (ok, e) = run(dir, command, &args(Some(v)));
        let typed = fill(dir, v);
        if ok {
            return Err(format!("{command} {flag} {typed} ran"));
        }
        // A file's points are echoed by what they are (`2 points in 2 dimensions`).
        let echoed = e.contains(&typed) || matches!(d.kind, Kind::Points | Kind::WordOrPoints(_));
        if !e.starts_with("error: ") || !named(&e) || !echoed {
            return Err(format!("{command} {flag} {typed}: {e}"));
        }
    }
    let first = goods[0];
    let mut rules = group_rules(d, command, &given(first));
    for (name, cmd, argv, other) in RULES {
        if *name == d.name && *cmd == command {
            rules.push((argv.iter().map(|s| s.to_string()).collect(), *other));
        }
    }
    for (argv, other) in rules {
        let (ok, e) = run(dir, command, &argv);
        if ok {
            return Err(format!("{command} {argv:?} ran"));
        }
        if !e.starts_with("error: invalid ") || !named(&e) || !e.contains(other) {
            return Err(format!(
                "{command} {argv:?} is not refused naming {flag} and {other}: {e}"
            ));
        }
    }
    Ok(())
}

#[test]
fn every_option_of_generate_and_eval_is_walked_from_its_declaration() {
    let tmp = TempDir::new("walk");
    let dir = tmp.0.as_path();
    std::fs::write(dir.join("old.csv"), "0.1,0.2\n0.6,0.7\n").unwrap();
    std::fs::write(dir.join("far.csv"), "0.1,0.2\n3,0.7\n").unwrap();
    std::fs::write(dir.join("mix.csv"), "0.2,0.3,0.5\n0.5,0.25,0.25\n").unwrap();
    std::fs::write(dir.join("design.csv"), "a,b\n0.1,0.5\n-0.3,1.2\n").unwrap();
    let mut failed = Vec::new();
    let mut walked = 0;
    for d in ALL.iter().filter(|d| d.flag().is_some()) {
        for (command, c) in [("generate", Command::Generate), ("eval", Command::Eval)] {
            if d.takes(c) {
                walked += 1;
                if let Err(e) = walk(dir, d, command) {
                    failed.push(e);
                }
            }
        }
    }
    // Every option of generate and eval at the time of writing; more is fine.
    assert!(walked >= 40, "{walked} walks");
    assert!(failed.is_empty(), "{}", failed.join("\n"));
}
