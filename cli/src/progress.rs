//! Progress display and checks of output paths before a run starts.

use super::*;
use std::io::Write as _;

/// Refuses a picture path that is not `.png` or `.svg` before any work is done.
pub(crate) fn check_picture_extension(path: &std::path::Path, option: &str) -> Result<()> {
    let ext = path
        .extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase())
        .unwrap_or_default();
    if ext != "png" && ext != "svg" {
        bail!(
            "invalid {option} {}: expected a file name ending in .png or .svg",
            path.display()
        );
    }
    Ok(())
}

/// How a run shows its progress on standard error (`--progress`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub(crate) enum ProgressMode {
    /// A bar redrawn in place (the default on a terminal).
    Bar,
    /// A plain line when a stage starts and at most every [`PLAIN_EVERY`] (the default
    /// off a terminal: notebooks, pipes, a scheduler's log).
    Plain,
    /// Nothing (also `-q`).
    None,
}

impl ProgressMode {
    /// The mode of a command's progress: an explicit `--progress` wins (`-q --progress
    /// plain` writes the lines: a script that adds `-q` to every command can still ask
    /// one for a log), else `-q` shows none, else a bar on a terminal and `off_terminal`
    /// off one. Every command with both flags (`generate`, `integrate --expr`) decides by
    /// this one rule.
    pub(crate) fn chosen(quiet: bool, mode: Option<ProgressMode>, off_terminal: Self) -> Self {
        match (mode, quiet) {
            (Some(m), _) => m,
            (None, true) => ProgressMode::None,
            (None, false) if std::io::stderr().is_terminal() => ProgressMode::Bar,
            (None, false) => off_terminal,
        }
    }
}

/// The least time between two plain progress lines of one stage.
pub(crate) const PLAIN_EVERY: std::time::Duration = std::time::Duration::from_secs(10);

/// A run's progress on standard error: the stage, steps, elapsed time and ETA, as a bar
/// or as plain lines (see [`ProgressMode`]).
pub(crate) struct Progress {
    pub(crate) bar: ProgressBar,
    pub(crate) mode: ProgressMode,
    /// The first position of a stage may jump (a resumed run), which must not count
    /// towards the rate the ETA is computed from.
    pub(crate) fresh: bool,
    stage: &'static str,
    len: Option<u64>,
    started: std::time::Instant,
    /// Where the rate is measured from: (time, position) of the first progress event.
    origin: Option<(std::time::Instant, u64)>,
    last_line: Option<std::time::Instant>,
    eta_shown: bool,
}

impl Progress {
    /// The mode [`ProgressMode::chosen`] gives, plain lines off a terminal.
    pub(crate) fn new(quiet: bool, mode: Option<ProgressMode>) -> Self {
        let mode = ProgressMode::chosen(quiet, mode, ProgressMode::Plain);
        // Drawn from the first stage on, so that no empty bar flashes up before it.
        let bar = ProgressBar::with_draw_target(Some(0), ProgressDrawTarget::hidden());
        Progress {
            bar,
            mode,
            fresh: true,
            stage: "",
            len: None,
            started: std::time::Instant::now(),
            origin: None,
            last_line: None,
            eta_shown: false,
        }
    }

    /// The estimated time left, once a rate has been measured (never a bare "0s" at the
    /// start of a stage).
    fn eta(&self, pos: u64) -> Option<std::time::Duration> {
        let (t0, p0) = self.origin?;
        let (len, done) = (self.len?, pos.checked_sub(p0)?);
        let elapsed = t0.elapsed();
        if done == 0 || elapsed < std::time::Duration::from_millis(500) {
            return None;
        }
        let left = len.saturating_sub(pos) as f64;
        Some(elapsed.mul_f64(left / done as f64))
    }

    fn plain_line(&mut self, pos: Option<u64>) {
        let mut line = format!("stillpoint: {}", self.stage);
        if let (Some(p), Some(len)) = (pos, self.len) {
            line += &format!(", step {p}/{len}");
        }
        line += &format!(
            ", {} elapsed",
            studies::human_seconds(self.started.elapsed().as_secs_f64())
        );
        if let Some(eta) = pos.and_then(|p| self.eta(p)) {
            line += &format!(", ETA {}", studies::human_seconds(eta.as_secs_f64()));
        }
        // A closed standard error must not end the run.
        let _ = writeln!(std::io::stderr(), "{line}");
        self.last_line = Some(std::time::Instant::now());
    }

    pub(crate) fn event(&mut self, e: Event) {
        if let Event::Stage { name, steps } = e {
            self.stage = name;
            self.len = steps;
            self.started = std::time::Instant::now();
            self.origin = None;
            self.eta_shown = false;
        }
        match self.mode {
            ProgressMode::None => {}
            ProgressMode::Plain => match e {
                Event::Stage { .. } => self.plain_line(None),
                Event::Progress(p) => {
                    if self.origin.is_none() {
                        self.origin = Some((std::time::Instant::now(), p));
                    }
                    if self.last_line.is_none_or(|t| t.elapsed() >= PLAIN_EVERY) {
                        self.plain_line(Some(p));
                    }
                }
                Event::Record(_) => {}
            },
            ProgressMode::Bar => self.bar_event(e),
        }
    }

    fn bar_event(&mut self, e: Event) {
        const WITHOUT_ETA: &str = "{msg:>15} {wide_bar} {pos}/{len} steps, {elapsed} elapsed";
        match e {
            Event::Stage {
                name,
                steps: Some(len),
            } => {
                self.bar.disable_steady_tick();
                self.bar.set_length(len);
                self.bar.set_position(0);
                // No ETA until a rate is measured: indicatif would show "0s".
                self.bar.set_style(
                    ProgressStyle::with_template(WITHOUT_ETA)
                        .unwrap_or_else(|_| ProgressStyle::default_bar()),
                );
                self.bar.set_message(name);
                self.bar.reset_elapsed();
                self.bar.reset_eta();
                self.fresh = true;
                self.show();
            }
            Event::Stage { name, steps: None } => {
                self.bar.set_style(
                    ProgressStyle::with_template("{msg:>15} {spinner} {elapsed}")
                        .unwrap_or_else(|_| ProgressStyle::default_spinner()),
                );
                self.bar.set_message(name);
                self.bar.reset_elapsed();
                self.show();
                self.bar
                    .enable_steady_tick(std::time::Duration::from_millis(120));
            }
            Event::Progress(p) => {
                if self.origin.is_none() {
                    self.origin = Some((std::time::Instant::now(), p));
                }
                self.bar.set_position(p);
                if self.fresh {
                    self.bar.reset_eta();
                    self.fresh = false;
                }
                if !self.eta_shown && self.eta(p).is_some() {
                    self.bar.set_style(
                        ProgressStyle::with_template(&format!("{WITHOUT_ETA}, ETA {{eta}}"))
                            .unwrap_or_else(|_| ProgressStyle::default_bar()),
                    );
                    self.eta_shown = true;
                }
            }
            Event::Record(_) => {}
        }
    }

    pub(crate) fn show(&self) {
        if self.bar.is_hidden() {
            self.bar.set_draw_target(ProgressDrawTarget::stderr());
        }
    }

    pub(crate) fn finish(&self) {
        if self.mode == ProgressMode::Bar {
            self.bar.finish_and_clear();
        }
    }
}

/// Refuses an output path (of `option`) whose directory does not exist, or that is a
/// directory, before any work is done.
pub(crate) fn check_writable(path: &std::path::Path, option: &str) -> Result<()> {
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => std::path::Path::new("."),
    };
    if !dir.is_dir() {
        bail!(
            "invalid {option} {}: the directory {} does not exist",
            path.display(),
            dir.display()
        );
    }
    if path.is_dir() {
        bail!(
            "invalid {option} {}: it is a directory, expected a file name",
            path.display()
        );
    }
    io::check_output(path).map_err(|e| anyhow::anyhow!("invalid {option}: {e}"))?;
    Ok(())
}

/// Refuses an output file name whose extension names no point format (it would be
/// written as CSV under a misleading name); no extension at all means CSV.
pub(crate) fn check_points_extension(path: &std::path::Path, option: &str) -> Result<()> {
    if path.extension().is_some() && io::Format::from_extension(path).is_none() {
        bail!(
            "invalid {option} {}: expected a file name ending in .csv, .tsv, .json or .npy \
             (or no extension for CSV)",
            path.display()
        );
    }
    Ok(())
}

/// The file a path names: links followed and relative parts resolved; a file that does
/// not exist yet is named by its resolved directory and its own name.
fn resolved(path: &std::path::Path) -> PathBuf {
    if let Ok(p) = std::fs::canonicalize(path) {
        return p;
    }
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => std::path::Path::new("."),
    };
    match (std::fs::canonicalize(dir), path.file_name()) {
        (Ok(d), Some(name)) => d.join(name),
        _ => path.to_path_buf(),
    }
}

/// Refuses one file in two roles before any work is done: the outputs must be distinct
/// files, and no input may be an output, except the checkpoint a run resumes from (the
/// `--checkpoint` file, which the run goes on writing).
pub(crate) fn check_distinct(
    outputs: &[(&str, Option<&std::path::Path>)],
    inputs: &[(&str, Option<&std::path::Path>)],
) -> Result<()> {
    let outs: Vec<(&str, PathBuf)> = outputs
        .iter()
        .filter_map(|(o, p)| p.map(|p| (*o, resolved(p))))
        .collect();
    for (i, (a, pa)) in outs.iter().enumerate() {
        if let Some((b, _)) = outs[..i].iter().find(|(_, pb)| pb == pa) {
            bail!(
                "invalid {a} {}: it is also the {b} file; give each output its own file",
                pa.display()
            );
        }
    }
    for (input, path) in inputs {
        let Some(path) = path else { continue };
        let p = resolved(path);
        for (o, po) in &outs {
            let resumed_checkpoint =
                *input == other_flag(Opt::checkpoint) && *o == flag(Opt::checkpoint);
            if *po == p && !resumed_checkpoint {
                bail!(
                    "invalid {o} {}: it is also the {input} file, which the run reads; \
                     write the output to another file",
                    po.display()
                );
            }
        }
    }
    Ok(())
}
