//! Checkpoints and resume: an interrupted run continued from its checkpoint ends with the
//! same bytes as an uninterrupted one, for the library and for the command (killed
//! part-way), in the cube and in a region; checkpoints of another configuration, damaged
//! or foreign files are refused with a clear message.

use std::path::Path;
use std::process::Stdio;
use std::sync::Arc;

use stillpoint::energies::shapes::Ball;
use stillpoint::io::{encode, Format};

use stillpoint::config::{GenerateConfig, Init};
use stillpoint::pipeline::{generate_with, run_config};
use stillpoint::solve::checkpoint::{read_checkpoint, CheckpointPlan};
use stillpoint::solve::Event;

mod common;
use common::{bin, tmpdir};

/// The bytes a point set is written as: the strictest comparison there is.
fn bytes(points: &stillpoint::PointSet) -> Vec<u8> {
    encode(points, &serde_json::Value::Null, Format::Npy)
}

fn energies(traj: &[stillpoint::integrators::Record]) -> Vec<(usize, u64)> {
    traj.iter().map(|r| (r.step, r.energy.to_bits())).collect()
}

/// A cube configuration with restarts, shift selection and a polish: everything that
/// runs after the DEM must run again after a resume.
fn cube_config() -> GenerateConfig {
    let mut cfg = GenerateConfig::new(60, 3);
    cfg.init = Init::Random;
    cfg.seed = 5;
    cfg.steps = 120;
    cfg.dem.tolerance = 0.0;
    cfg.log_every = 10;
    cfg.shifts = 16;
    cfg.polish = Some(stillpoint::energies::discrepancy::DiscrepancyKind::ModifiedL2);
    cfg
}

#[test]
fn library_resume_of_a_cube_run_is_bit_identical() {
    let d = tmpdir("lib-cube");
    let cfg = cube_config();
    let reference = run_config(&cfg, |_| {}).unwrap();
    // Run with checkpoints every 20 steps and keep a copy of the one written at step 60,
    // as if the process had died right after writing it.
    let ck = d.join("run.ckpt");
    let mid = d.join("mid.ckpt");
    let plan = CheckpointPlan::new(&ck, 20);
    let with_ck = generate_with(&cfg, Some(&plan), |e| {
        if let Event::Record(r) = e {
            if r.step == 60 {
                std::fs::copy(&ck, &mid).unwrap();
            }
        }
    })
    .unwrap();
    assert_eq!(
        bytes(&with_ck.output.points),
        bytes(&reference.output.points)
    );
    let saved = read_checkpoint(&mid).unwrap();
    assert_eq!(saved.state["step"], 60);
    assert_eq!(saved.state["trajectory"].as_array().unwrap().len(), 60);

    let mut resume = CheckpointPlan::new(&ck, 20);
    resume.resume = Some(mid.clone());
    let mut first_step = None;
    let resumed = generate_with(&cfg, Some(&resume), |e| {
        if let Event::Record(r) = e {
            first_step.get_or_insert(r.step);
        }
    })
    .unwrap();
    assert_eq!(
        first_step,
        Some(60),
        "the resumed run starts at its checkpoint"
    );
    assert_eq!(
        bytes(&resumed.output.points),
        bytes(&reference.output.points)
    );
    assert_eq!(
        energies(&resumed.output.trajectory),
        energies(&reference.output.trajectory)
    );
    assert_eq!(resumed.quality, reference.quality);
    assert_eq!(resumed.polish, reference.polish);
    assert_eq!(
        resumed.shift.as_ref().map(|s| s.shift.clone()),
        reference.shift.as_ref().map(|s| s.shift.clone())
    );
    // Logged discrepancies of the steps before the checkpoint come from the file.
    let logged = |r: &stillpoint::report::GenerateReport| {
        r.output
            .trajectory
            .iter()
            .flat_map(|t| t.metrics.iter().map(|(k, v)| (k.clone(), v.to_bits())))
            .collect::<Vec<_>>()
    };
    assert_eq!(logged(&resumed), logged(&reference));
}

#[test]
fn library_resume_of_a_region_run_is_bit_identical() {
    let d = tmpdir("lib-region");
    let ball = Ball::new(vec![0.0, 0.0], 1.0).unwrap();
    let mut cfg = GenerateConfig::in_region(Arc::new(ball), 40);
    cfg.steps = 300;
    cfg.dem.tolerance = 0.0;
    let reference = run_config(&cfg, |_| {}).unwrap();
    let ck = d.join("region.ckpt");
    let mid = d.join("mid.ckpt");
    let plan = CheckpointPlan::new(&ck, 50);
    generate_with(&cfg, Some(&plan), |e| {
        if let Event::Record(r) = e {
            if r.step == 150 {
                std::fs::copy(&ck, &mid).unwrap();
            }
        }
    })
    .unwrap();
    let mut resume = CheckpointPlan::new(&ck, 50);
    resume.resume = Some(mid);
    let resumed = generate_with(&cfg, Some(&resume), |_| {}).unwrap();
    assert_eq!(
        bytes(&resumed.output.points),
        bytes(&reference.output.points)
    );
    assert_eq!(
        energies(&resumed.output.trajectory),
        energies(&reference.output.trajectory)
    );
    assert_eq!(resumed.quality, reference.quality);
}

#[test]
fn library_refuses_other_configurations_and_damaged_checkpoints() {
    let d = tmpdir("lib-refuse");
    let mut cfg = cube_config();
    cfg.steps = 40;
    cfg.polish = None;
    let ck = d.join("run.ckpt");
    generate_with(&cfg, Some(&CheckpointPlan::new(&ck, 10)), |_| {}).unwrap();
    let good = std::fs::read(&ck).unwrap();
    let resume_err = |cfg: &GenerateConfig, file: &Path| {
        let mut plan = CheckpointPlan::new(d.join("out.ckpt"), 10);
        plan.resume = Some(file.to_path_buf());
        generate_with(cfg, Some(&plan), |_| {})
            .map(|_| ())
            .unwrap_err()
            .to_string()
    };
    // Another configuration: each difference is named with both values.
    let mut other = cfg.clone();
    other.seed = 6;
    other.steps = 50;
    let msg = resume_err(&other, &ck);
    assert!(msg.contains("seed = 5 (this run: 6)"), "{msg}");
    assert!(msg.contains("steps = 40 (this run: 50)"), "{msg}");
    assert!(
        !d.join("out.ckpt").exists(),
        "a refused resume wrote a checkpoint"
    );

    let write = |name: &str, b: &[u8]| {
        let p = d.join(name);
        std::fs::write(&p, b).unwrap();
        p
    };
    // Truncated (as if the disk filled up), edited, foreign, empty, missing.
    let truncated = write("truncated.ckpt", &good[..good.len() / 2]);
    assert!(resume_err(&cfg, &truncated).contains("damaged or truncated"));
    let text = String::from_utf8(good.clone()).unwrap();
    let key = "\"current\":{\"data\":[";
    let i = text.find(key).unwrap() + key.len();
    let mut edited = text.clone();
    edited.replace_range(i..i + 1, if &text[i..i + 1] == "1" { "2" } else { "1" });
    let edited = write("edited.ckpt", edited.as_bytes());
    assert!(resume_err(&cfg, &edited).contains("checksum"));
    let foreign = write("foreign.ckpt", br#"{"points": [[0.5, 0.5]]}"#);
    assert!(resume_err(&cfg, &foreign).contains("format"));
    let empty = write("empty.ckpt", b"");
    assert!(resume_err(&cfg, &empty).contains("checkpoint"));
    assert!(resume_err(&cfg, &d.join("missing.ckpt")).contains("cannot read"));
    // A checkpoint of the DEM is not resumed by L-BFGS.
    let mut lbfgs = cfg.clone();
    lbfgs.solver = stillpoint::solve::Solver::Lbfgs;
    let e = resume_err(&lbfgs, &ck);
    assert!(e.contains("integrator = Dem (this run: Lbfgs)"), "{e}");
    // The good checkpoint was never touched by the refusals.
    assert_eq!(std::fs::read(&ck).unwrap(), good);
}

fn args(v: &[String]) -> Vec<&str> {
    v.iter().map(String::as_str).collect()
}

/// Starts the command, waits until its checkpoint exists, kills it, and returns the step
/// the checkpoint holds.
fn kill_after_first_checkpoint(args: &[&str], checkpoint: &Path) -> usize {
    let mut child = bin()
        .args(args)
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .expect("start stillpoint");
    loop {
        if checkpoint.exists() {
            break;
        }
        if let Some(status) = child.try_wait().unwrap() {
            panic!("the run ended ({status}) before writing a checkpoint");
        }
        std::thread::sleep(std::time::Duration::from_millis(2));
    }
    child.kill().unwrap();
    child.wait().unwrap();
    // Written atomically: whatever is there is a whole checkpoint.
    read_checkpoint(checkpoint).unwrap().state["step"]
        .as_u64()
        .unwrap() as usize
}

fn run_ok(args: &[&str]) {
    let o = bin().args(args).output().unwrap();
    assert!(
        o.status.success(),
        "{args:?}: {}",
        String::from_utf8_lossy(&o.stderr)
    );
}

#[test]
fn killed_cli_run_resumes_to_the_same_bytes() {
    let step = killed_and_resumed_gives_the_same_bytes(
        "cli-cube",
        &[
            "generate",
            "-n",
            "400",
            "-s",
            "3",
            "--steps",
            "400",
            "--tolerance",
            "0",
            "--init",
            "random",
            "--seed",
            "3",
            "-q",
        ],
        "5",
    );
    assert!(
        step < 400,
        "the run was not interrupted (checkpoint at step {step})"
    );
}

#[test]
fn killed_cli_region_run_resumes_to_the_same_bytes() {
    let d = tmpdir("cli-region");
    let reference = d.join("reference.json");
    let resumed = d.join("resumed.json");
    let ck = d.join("region.ckpt");
    let other = d.join("other.ckpt");
    let (r, o, c) = (
        reference.to_str().unwrap(),
        resumed.to_str().unwrap(),
        ck.to_str().unwrap(),
    );
    let common = [
        "generate",
        "--region",
        "x^2 + y^2 - 1",
        "--box",
        "-1,1,-1,1",
        "-n",
        "30",
        "--steps",
        "300",
        "--tolerance",
        "0",
        "-q",
    ];
    let with = |extra: &[&str]| -> Vec<String> {
        common.iter().chain(extra).map(|s| s.to_string()).collect()
    };
    run_ok(&args(&with(&["-o", r])));
    let step = kill_after_first_checkpoint(
        &args(&with(&[
            "-o",
            o,
            "--checkpoint",
            c,
            "--checkpoint-every",
            "20",
        ])),
        &ck,
    );
    assert!(step < 300, "the run was not interrupted");
    // Another region under the same box is refused by its expression.
    std::fs::copy(&ck, &other).unwrap();
    let mut wrong = with(&["-o", o, "--resume", other.to_str().unwrap()]);
    wrong[2] = "x^2 + 2*y^2 - 1".into();
    let out = bin().args(args(&wrong)).output().unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success());
    assert!(
        err.contains("--region = x^2 + y^2 - 1 (this run: x^2 + 2*y^2 - 1)"),
        "{err}"
    );
    assert!(!resumed.exists());
    run_ok(&args(&with(&["-o", o, "--resume", c])));
    assert_eq!(
        std::fs::read(&resumed).unwrap(),
        std::fs::read(&reference).unwrap(),
        "resumed from step {step}"
    );
}

/// Runs `common` once to the end, once killed after its first checkpoint and resumed,
/// and checks that both outputs are the same bytes; returns the step it was killed at.
fn killed_and_resumed_gives_the_same_bytes(name: &str, common: &[&str], every: &str) -> usize {
    let d = tmpdir(name);
    let reference = d.join("reference.csv");
    let resumed = d.join("resumed.csv");
    let ck = d.join("run.ckpt");
    let (r, o, c) = (
        reference.to_str().unwrap(),
        resumed.to_str().unwrap(),
        ck.to_str().unwrap(),
    );
    let with = |extra: &[&str]| -> Vec<String> {
        common.iter().chain(extra).map(|s| s.to_string()).collect()
    };
    run_ok(&args(&with(&["-o", r])));
    let interrupted = with(&["-o", o, "--checkpoint", c, "--checkpoint-every", every]);
    let step = kill_after_first_checkpoint(&args(&interrupted), &ck);
    assert!(!resumed.exists(), "{name}: a killed run wrote its output");
    run_ok(&args(&with(&[
        "-o",
        o,
        "--checkpoint",
        c,
        "--checkpoint-every",
        every,
        "--resume",
    ])));
    assert_eq!(
        std::fs::read(&resumed).unwrap(),
        std::fs::read(&reference).unwrap(),
        "{name}: resumed from step {step}"
    );
    step
}

#[test]
fn killed_cli_lbfgs_run_resumes_to_the_same_bytes() {
    killed_and_resumed_gives_the_same_bytes(
        "cli-lbfgs",
        &[
            "generate",
            "-n",
            "400",
            "-s",
            "3",
            "--integrator",
            "lbfgs",
            "--steps",
            "300",
            "--init",
            "random",
            "--seed",
            "3",
            "-q",
        ],
        "2",
    );
    // A discrepancy energy in the closed cube: kinks, stalls and restarts.
    killed_and_resumed_gives_the_same_bytes(
        "cli-lbfgs-md",
        &[
            "generate",
            "-n",
            "300",
            "-s",
            "2",
            "--energy",
            "md",
            "--integrator",
            "lbfgs",
            "--steps",
            "300",
            "-q",
        ],
        "2",
    );
}

#[test]
fn killed_cli_region_lbfgs_run_resumes_to_the_same_bytes() {
    killed_and_resumed_gives_the_same_bytes(
        "cli-region-lbfgs",
        &[
            "generate",
            "--shape",
            "ball:1",
            "-s",
            "2",
            "-n",
            "200",
            "--energy",
            "e-p-g",
            "--integrator",
            "lbfgs",
            "--steps",
            "300",
            "-q",
        ],
        "2",
    );
}
