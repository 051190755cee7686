//! The command never panics on its output streams: a full device is a one-line error
//! with status 1, a reader that closes the pipe ends it quietly with status 141, and a
//! standard error that cannot be written loses only the notes, never a written result.

mod common;

use common::{bin, TempDir};
use std::io::{BufRead, BufReader};
use std::process::Stdio;

/// Every command that prints a result, with a file it may read.
fn commands(dir: &TempDir) -> Vec<Vec<String>> {
    let base = dir.0.join("base.csv").display().to_string();
    let o = bin()
        .args(["baseline", "sobol", "-n", "64", "-s", "3", "-o", &base])
        .output()
        .unwrap();
    assert!(o.status.success());
    let v = |a: &[&str]| a.iter().map(|s| s.to_string()).collect::<Vec<_>>();
    vec![
        v(&["generate", "-n", "600", "-s", "3", "-q"]),
        v(&["generate", "-n", "40", "-s", "2", "-q", "--json"]),
        v(&["generate", "-n", "40", "-s", "2", "--method", "sobol"]),
        v(&["baseline", "sobol", "-n", "5000", "-s", "5"]),
        v(&["baseline", "--list"]),
        v(&["eval", &base]),
        v(&["eval", &base, &base, "--json"]),
        v(&["integrate", &base]),
        v(&["integrate", &base, "--json"]),
    ]
}

#[test]
fn a_full_device_is_a_one_line_error() {
    let dir = TempDir::new("streams-full");
    for args in commands(&dir) {
        let full = std::fs::OpenOptions::new()
            .write(true)
            .open("/dev/full")
            .unwrap();
        let o = bin().args(&args).stdout(full).output().unwrap();
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(1), "{args:?}: {err}");
        assert!(!err.contains("panicked"), "{args:?}: {err}");
        let errors: Vec<&str> = err.lines().filter(|l| l.starts_with("error:")).collect();
        assert_eq!(errors.len(), 1, "{args:?}: {err}");
        assert!(errors[0].contains("standard output"), "{args:?}: {err}");
    }
}

#[test]
fn a_closed_pipe_ends_the_program_quietly() {
    let dir = TempDir::new("streams-pipe");
    for args in commands(&dir) {
        let mut child = bin()
            .args(&args)
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        let mut first = String::new();
        BufReader::new(child.stdout.take().unwrap())
            .read_line(&mut first)
            .unwrap();
        // The reader is dropped here: the pipe's read end closes.
        let o = child.wait_with_output().unwrap();
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(!err.contains("panicked"), "{args:?}: {err}");
        // A command whose whole output fitted in the pipe may finish first.
        assert!(
            matches!(o.status.code(), Some(141) | Some(0)),
            "{args:?}: {:?} {err}",
            o.status
        );
        if o.status.code() == Some(141) {
            assert!(!err.contains("error:"), "{args:?}: {err}");
        }
    }
}

#[test]
fn a_large_output_into_a_closed_pipe_is_status_141() {
    let mut child = bin()
        .args(["baseline", "sobol", "-n", "100000", "-s", "5"])
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    drop(child.stdout.take());
    assert_eq!(child.wait().unwrap().code(), Some(141));
}

#[test]
fn an_unwritable_standard_error_loses_notes_not_results() {
    let dir = TempDir::new("streams-stderr");
    for (args, rows) in [
        (vec!["generate", "-n", "300", "-s", "3"], 300),
        (
            vec![
                "generate", "-n", "50", "-s", "2", "--method", "paper", "--steps", "20",
            ],
            50,
        ),
        (vec!["baseline", "sobol", "-n", "100", "-s", "2"], 100),
    ] {
        let out = dir.0.join("pts.csv");
        let full = std::fs::OpenOptions::new()
            .write(true)
            .open("/dev/full")
            .unwrap();
        let o = bin()
            .args(&args)
            .stdout(std::fs::File::create(&out).unwrap())
            .stderr(full)
            .output()
            .unwrap();
        assert_eq!(o.status.code(), Some(0), "{args:?}");
        let text = std::fs::read_to_string(&out).unwrap();
        let data = text
            .lines()
            .filter(|l| !l.starts_with('#') && !l.starts_with('x'))
            .count();
        assert_eq!(data, rows, "{args:?}");
    }
}
