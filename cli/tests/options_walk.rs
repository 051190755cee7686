//! Every declared option ([`stillpoint::pipeline::options::OPTIONS`]) walked through the
//! command line: a good value runs, a bad value and a refused combination are refused
//! with an error naming the option as the command line spells it. The list comes from
//! the declarations, so a new option fails here until its walk is written.

mod common;

use common::{bin, TempDir};
use std::path::Path;
use stillpoint::pipeline::options::{Group, OPTIONS};

/// How one option is walked: arguments of `generate` (and of `eval` for the options
/// `eval` takes) that succeed, carry a bad value, or make a refused combination.
/// `{old}` is a file of 2-D points in the unit disc, `{dir}` a scratch directory,
/// `{far}` a 2-D file with a point outside the unit cube, `{mix}` a file of
/// 3-component mixtures, `{design}` a design of two normal variables.
struct Walk {
    good: &'static [&'static str],
    /// `None` for a flag without a value.
    bad: Option<&'static [&'static str]>,
    /// `None` for an option that no other option excludes.
    refused: Option<&'static [&'static str]>,
    /// `eval`: the good arguments and a refused combination, for the options of `eval`.
    eval: Option<(&'static [&'static str], &'static [&'static str])>,
}

const fn walk(
    good: &'static [&'static str],
    bad: Option<&'static [&'static str]>,
    refused: Option<&'static [&'static str]>,
) -> Walk {
    Walk {
        good,
        bad,
        refused,
        eval: None,
    }
}

/// The paper's options: a good value with the paper's method, refused with a goal.
fn paper(flag: &'static str, good: &'static str, bad: &'static str) -> Walk {
    let good: &'static [&'static str] =
        Box::leak(vec!["-n", "8", "-s", "2", "--steps", "5", flag, good].into_boxed_slice());
    let bad_args: &'static [&'static str] =
        Box::leak(vec!["-n", "8", "-s", "2", flag, bad].into_boxed_slice());
    // Without --steps, which a goal refuses as well (and would be named first).
    let mut refused: Vec<&'static str> = good
        .iter()
        .copied()
        .filter(|a| *a != "--steps" && *a != "5")
        .collect();
    refused.extend(["--goal", "integration"]);
    walk(
        good,
        Some(bad_args),
        Some(Box::leak(refused.into_boxed_slice())),
    )
}

fn walk_of(name: &str) -> Option<Walk> {
    Some(match name {
        "n" => walk(
            &["-n", "8", "-s", "2"],
            Some(&["-n", "0", "-s", "2"]),
            Some(&["-n", "9", "-s", "2", "--nested", "4,8"]),
        ),
        "s" => walk(
            &["-n", "8", "-s", "2"],
            Some(&["-n", "8", "-s", "0"]),
            Some(&["-n", "3", "-s", "3", "--extend", "{old}"]),
        ),
        "seed" => walk(
            &["-n", "8", "-s", "2", "--seed", "3"],
            Some(&["-n", "8", "-s", "2", "--seed", "-1"]),
            None,
        ),
        "method" => walk(
            &["-n", "8", "-s", "2", "--method", "sobol"],
            Some(&["-n", "8", "-s", "2", "--method", "nope"]),
            Some(&[
                "-n",
                "8",
                "-s",
                "2",
                "--method",
                "paper",
                "--goal",
                "integration",
            ]),
        ),
        "goal" => walk(
            &[
                "-n",
                "8",
                "-s",
                "2",
                "--goal",
                "space-filling",
                "--steps",
                "5",
            ],
            Some(&["-n", "8", "-s", "2", "--goal", "nope"]),
            Some(&["-n", "8", "-s", "2", "--goal", "integration", "--q", "1"]),
        ),
        "target" => walk(
            &["-n", "8", "-s", "2", "--target", "md"],
            Some(&["-n", "8", "-s", "2", "--target", "nope"]),
            Some(&["-n", "8", "-s", "2", "--target", "md", "--method", "paper"]),
        ),
        "randomize" => walk(
            &["-n", "8", "-s", "2", "--randomize", "shift"],
            Some(&["-n", "8", "-s", "2", "--randomize", "nope"]),
            Some(&[
                "-n",
                "8",
                "-s",
                "2",
                "--randomize",
                "shift",
                "--shape",
                "ball:1",
            ]),
        ),
        "extend" => walk(
            &["-n", "3", "--extend", "{old}"],
            Some(&["-n", "3", "--extend", "{far}"]),
            Some(&["-n", "3", "--extend", "{old}", "--goal", "space-filling"]),
        ),
        "nested" => walk(
            &["-s", "2", "--nested", "4,8"],
            Some(&["-s", "2", "--nested", "8,4"]),
            Some(&["-s", "2", "--nested", "4,8", "--goal", "space-filling"]),
        ),
        "bounds" => Walk {
            eval: Some((
                &["{old}", "--bounds", "0,1,0,1"],
                &["{old}", "--bounds", "0,1,0,1", "--shape", "ball:1"],
            )),
            ..walk(
                &["-n", "8", "-s", "2", "--bounds", "0,2,-1,1"],
                Some(&["-n", "8", "-s", "2", "--bounds", "0,x"]),
                Some(&[
                    "-n", "8", "-s", "2", "--bounds", "0,1,0,1", "--shape", "ball:1",
                ]),
            )
        },
        "region" => Walk {
            eval: Some((
                &["{old}", "--region", "x^2 + y^2 - 1", "--box", "-1,1,-1,1"],
                &[
                    "{old}",
                    "--region",
                    "x",
                    "--box",
                    "0,1,0,1",
                    "--constraint",
                    "x1 <= 1",
                ],
            )),
            ..walk(
                &[
                    "-n",
                    "8",
                    "--region",
                    "x^2 + y^2 - 1",
                    "--box",
                    "-1,1,-1,1",
                    "--steps",
                    "5",
                ],
                Some(&["-n", "8", "--region", "x^^", "--box", "-1,1,-1,1"]),
                Some(&[
                    "-n",
                    "8",
                    "--region",
                    "x",
                    "--box",
                    "0,1,0,1",
                    "--constraint",
                    "x1 <= 1",
                ]),
            )
        },
        "box" => Walk {
            eval: Some((
                &["{old}", "--region", "x^2 + y^2 - 1", "--box", "-1,1,-1,1"],
                &["{old}", "--box", "0,1,0,1"],
            )),
            ..walk(
                &[
                    "-n",
                    "8",
                    "--region",
                    "x^2 + y^2 - 1",
                    "--box",
                    "-1,1,-1,1",
                    "--steps",
                    "5",
                ],
                Some(&["-n", "8", "--region", "x^2 + y^2 - 1", "--box", "-1,x"]),
                Some(&["-n", "8", "-s", "2", "--box", "0,1,0,1"]),
            )
        },
        "shape" => Walk {
            eval: Some((
                &["{old}", "--shape", "ball:1"],
                &[
                    "{design}",
                    "--shape",
                    "ball:1",
                    "--var",
                    "a=normal(0,1)",
                    "--var",
                    "b=normal(0,1)",
                ],
            )),
            ..walk(
                &["-n", "8", "-s", "2", "--shape", "ball:1", "--steps", "5"],
                Some(&["-n", "8", "-s", "2", "--shape", "nope:1"]),
                Some(&[
                    "-n",
                    "8",
                    "--shape",
                    "ball:1",
                    "--constraint",
                    "x1 <= 1",
                    "--box",
                    "0,1,0,1",
                ]),
            )
        },
        "constraints" => Walk {
            eval: Some((
                &[
                    "{old}",
                    "--constraint",
                    "x1 + x2 <= 1.5",
                    "--box",
                    "0,1,0,1",
                ],
                &[
                    "{old}",
                    "--constraint",
                    "x1 <= 1",
                    "--box",
                    "0,1,0,1",
                    "--shape",
                    "ball:1",
                ],
            )),
            ..walk(
                &[
                    "-n",
                    "8",
                    "--constraint",
                    "x1 + x2 <= 1.5",
                    "--box",
                    "0,1,0,1",
                    "--steps",
                    "5",
                ],
                Some(&[
                    "-n",
                    "8",
                    "--constraint",
                    "x1 * x2 <= 1",
                    "--box",
                    "0,1,0,1",
                ]),
                Some(&[
                    "-n",
                    "8",
                    "--constraint",
                    "x1 <= 1",
                    "--box",
                    "0,1,0,1",
                    "--region",
                    "x",
                ]),
            )
        },
        "mixture" => Walk {
            eval: Some((
                &["{mix}", "--mixture"],
                &["{mix}", "--mixture", "--region", "x"],
            )),
            ..walk(
                &["-n", "8", "-s", "3", "--mixture", "--steps", "5"],
                None,
                Some(&["-n", "3", "--mixture", "--extend", "{old}"]),
            )
        },
        "energy" => paper("--energy", "e-inf", "nope"),
        "integrator" => paper("--integrator", "lbfgs", "nope"),
        "q" => paper("--q", "1", "-1"),
        "p" => paper("--p", "1", "0"),
        "precision" => paper("--precision", "full", "nope"),
        "steps" => walk(
            &["-n", "8", "-s", "2", "--steps", "5"],
            Some(&["-n", "8", "-s", "2", "--steps", "0"]),
            Some(&[
                "-n",
                "8",
                "-s",
                "2",
                "--steps",
                "5",
                "--goal",
                "integration",
            ]),
        ),
        "init" => paper("--init", "random", "{far}"),
        "kappa" => paper("--kappa", "100", "0.5"),
        "restart" => paper("--restart", "off", "-1"),
        "tolerance" => paper("--tolerance", "0", "-1"),
        "polish" => paper("--polish", "md", "nope"),
        "shifts" => paper("--shifts", "2", "-1"),
        "log_every" => paper("--log-every", "2", "-1"),
        "exact" => Walk {
            eval: Some((
                &["{old}", "--exact"],
                &["{old}", "--exact", "--shape", "ball:1"],
            )),
            ..walk(
                &["-n", "8", "-s", "2", "--exact"],
                None,
                Some(&["-n", "8", "-s", "2", "--method", "sobol", "--exact"]),
            )
        },
        "space" => Walk {
            eval: Some((
                &[
                    "{design}",
                    "--var",
                    "a=normal(0,1)",
                    "--var",
                    "b=normal(0,1)",
                ],
                &[
                    "{design}",
                    "--var",
                    "a=normal(0,1)",
                    "--var",
                    "b=normal(0,1)",
                    "--box",
                    "0,1,0,1",
                ],
            )),
            ..walk(
                &["-n", "8", "--var", "a=normal(0,1)", "--var", "b=int(1,3)"],
                Some(&["-n", "8", "--var", "a=nope"]),
                Some(&["-n", "8", "--var", "a=normal(0,1)", "--nested", "4,8"]),
            )
        },
        "correlation" => Walk {
            eval: Some((
                &[
                    "{design}",
                    "--var",
                    "a=normal(0,1)",
                    "--var",
                    "b=normal(0,1)",
                    "--correlation",
                    "1,0.5;0.5,1",
                ],
                &["{old}", "--correlation", "1,0.5;0.5,1"],
            )),
            ..walk(
                &[
                    "-n",
                    "8",
                    "--var",
                    "a=normal(0,1)",
                    "--var",
                    "b=normal(0,1)",
                    "--correlation",
                    "1,0.5;0.5,1",
                ],
                Some(&[
                    "-n",
                    "8",
                    "--var",
                    "a=normal(0,1)",
                    "--var",
                    "b=normal(0,1)",
                    "--correlation",
                    "1,x",
                ]),
                Some(&["-n", "8", "-s", "2", "--correlation", "1,0.5;0.5,1"]),
            )
        },
        "trajectory" => walk(
            &[
                "-n",
                "8",
                "-s",
                "2",
                "--steps",
                "5",
                "--trajectory",
                "{dir}/t.json",
            ],
            Some(&[
                "-n",
                "8",
                "-s",
                "2",
                "--trajectory",
                "{dir}/no/such/dir/t.json",
            ]),
            Some(&[
                "-n",
                "8",
                "-s",
                "2",
                "--goal",
                "integration",
                "--trajectory",
                "{dir}/t.json",
            ]),
        ),
        "checkpoint" => walk(
            &[
                "-n",
                "8",
                "-s",
                "2",
                "--steps",
                "5",
                "--checkpoint",
                "{dir}/c.ckpt",
            ],
            Some(&[
                "-n",
                "8",
                "-s",
                "2",
                "--checkpoint",
                "{dir}/no/such/dir/c.ckpt",
            ]),
            Some(&[
                "-n",
                "8",
                "-s",
                "2",
                "--goal",
                "integration",
                "--checkpoint",
                "{dir}/c.ckpt",
            ]),
        ),
        _ => return None,
    })
}

/// Runs `stillpoint SUBCOMMAND ARGS` with the placeholders filled in: (success, stderr).
fn run(dir: &Path, subcommand: &str, args: &[&str]) -> (bool, String) {
    let fill = |a: &str| {
        a.replace("{old}", &dir.join("old.csv").display().to_string())
            .replace("{mix}", &dir.join("mix.csv").display().to_string())
            .replace("{design}", &dir.join("design.csv").display().to_string())
            .replace("{far}", &dir.join("far.csv").display().to_string())
            .replace("{dir}", &dir.display().to_string())
    };
    let mut cmd = bin();
    cmd.args(["--threads", "1", subcommand]);
    if subcommand == "generate" {
        cmd.arg("-q").arg("-o").arg(dir.join("out.csv"));
    }
    let o = cmd.args(args.iter().map(|a| fill(a))).output().unwrap();
    (
        o.status.success(),
        String::from_utf8_lossy(&o.stderr).into_owned(),
    )
}

#[test]
fn every_option_is_walked_through_the_command_line() {
    let tmp = TempDir::new("walk");
    let dir = tmp.0.as_path();
    std::fs::write(dir.join("old.csv"), "0.1,0.2\n0.6,0.7\n").unwrap();
    std::fs::write(dir.join("far.csv"), "0.1,0.2\n3,0.7\n").unwrap();
    std::fs::write(dir.join("mix.csv"), "0.2,0.3,0.5\n0.5,0.25,0.25\n").unwrap();
    std::fs::write(dir.join("design.csv"), "a,b\n0.1,0.5\n-0.3,1.2\n").unwrap();
    let mut unwalked = Vec::new();
    for d in OPTIONS {
        let Some(w) = walk_of(d.name) else {
            unwalked.push(d.name);
            continue;
        };
        let flags: Vec<&str> = std::iter::once(d.cli)
            .chain(d.cli_also.iter().copied())
            .collect();
        let names_it = |e: &str| flags.iter().any(|f| e.contains(f));
        let (ok, e) = run(dir, "generate", w.good);
        assert!(ok, "{} good {:?}: {e}", d.name, w.good);
        if let Some(bad) = w.bad {
            let (ok, e) = run(dir, "generate", bad);
            assert!(!ok, "{} bad {bad:?} ran", d.name);
            assert!(
                e.contains(&format!("invalid {}", d.cli)),
                "{} bad {bad:?}: {e}",
                d.name
            );
        }
        if let Some(refused) = w.refused {
            let (ok, e) = run(dir, "generate", refused);
            assert!(!ok, "{} refused {refused:?} ran", d.name);
            assert!(e.starts_with("error: invalid "), "{}: {e}", d.name);
            assert!(names_it(&e), "{} refused {refused:?}: {e}", d.name);
        }
        match (d.is(Group::Eval), &w.eval) {
            (true, Some((good, refused))) => {
                let (ok, e) = run(dir, "eval", good);
                assert!(ok, "{} eval {good:?}: {e}", d.name);
                let (ok, e) = run(dir, "eval", refused);
                assert!(!ok, "{} eval {refused:?} ran", d.name);
                assert!(e.starts_with("error: invalid "), "{}: {e}", d.name);
                assert!(names_it(&e), "{} eval {refused:?}: {e}", d.name);
            }
            (true, None) => unwalked.push(d.name),
            (false, Some(_)) => panic!("{} is walked through eval but not declared for it", d.name),
            (false, None) => {}
        }
    }
    assert!(unwalked.is_empty(), "options with no walk: {unwalked:?}");
}
