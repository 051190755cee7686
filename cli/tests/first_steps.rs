//! What a new user meets on the first wrong step: a command given nothing names every form
//! it takes, and a design's report counts what the user declared.

mod common;

use common::{bin, succeeded, TempDir};

/// `integrate` and `plot` run without a point file (`--expr`, `--trajectory`): given
/// nothing, their usage shows that form too, not only the file clap asks for.
#[test]
fn a_command_given_nothing_names_each_form_it_takes() {
    for (command, other) in [
        ("integrate", "stillpoint integrate --expr <EXPR> -s <S>"),
        ("plot", "stillpoint plot --trajectory <TRAJ> -o <OUT>"),
    ] {
        let o = bin().arg(command).output().unwrap();
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{command}: {err}");
        assert!(err.contains(other), "{command}: {err}");
        assert!(
            err.contains(&format!("stillpoint {command} [OPTIONS] <FILE")),
            "{command}: {err}"
        );
    }
}

/// A Brownian path is one variable written as m columns: the report says 2 variables and
/// 5 columns for a lognormal and a path of 4 steps, and only the variables when each is
/// one column.
#[test]
fn a_design_report_counts_the_variables_and_the_columns_of_a_path() {
    let d = TempDir::new("first-steps");
    let path = d.path("paths.csv");
    let (out, _) = succeeded(
        bin()
            .args([
                "generate",
                "-n",
                "64",
                "--var",
                "S0=lognormal(4.6,0.1)",
                "--var",
                "W=brownian(1,4)",
                "-q",
                "-o",
            ])
            .arg(&path),
        &"generate with a path",
    );
    assert!(
        out.contains("design of 64 points in 2 variables, 5 columns (S0="),
        "{out}"
    );
    let header = std::fs::read_to_string(&path).unwrap();
    let names = header.lines().find(|l| !l.starts_with('#')).unwrap();
    assert_eq!(names.split(',').count(), 5, "{names}");
    let (out, _) = succeeded(
        bin()
            .args([
                "generate",
                "-n",
                "20",
                "--var",
                "x=uniform(0,1)",
                "--var",
                "k=int(1,3)",
                "-q",
                "-o",
            ])
            .arg(d.path("plain.csv")),
        &"generate without a path",
    );
    assert!(
        out.contains("design of 20 points in 2 variables (x="),
        "{out}"
    );
}
