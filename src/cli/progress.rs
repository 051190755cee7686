//! Progress display and checks of output paths before a run starts.

use super::*;

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

/// A progress bar on standard error with the stage, steps and ETA; hidden with --quiet or
/// when standard error is not a terminal.
pub(crate) struct Progress {
    pub(crate) bar: ProgressBar,
    pub(crate) visible: bool,
    /// The first position of a stage may jump (a resumed run), which must not count
    /// towards the rate the ETA is computed from.
    pub(crate) fresh: bool,
}

impl Progress {
    pub(crate) fn new(quiet: bool) -> Self {
        let visible = !quiet && std::io::stderr().is_terminal();
        // Drawn from the first stage on, so that no empty bar flashes up before it.
        let bar = ProgressBar::with_draw_target(Some(0), ProgressDrawTarget::hidden());
        Progress {
            bar,
            visible,
            fresh: true,
        }
    }

    pub(crate) fn event(&mut self, e: run::Event) {
        if !self.visible {
            return;
        }
        match e {
            run::Event::Stage {
                name,
                steps: Some(len),
            } => {
                self.bar.disable_steady_tick();
                self.bar.set_length(len);
                self.bar.set_position(0);
                self.bar.set_style(
                    ProgressStyle::with_template(
                        "{msg:>15} {wide_bar} {pos}/{len} steps, {elapsed} elapsed, ETA {eta}",
                    )
                    .unwrap_or_else(|_| ProgressStyle::default_bar()),
                );
                self.bar.set_message(name);
                self.bar.reset_elapsed();
                self.bar.reset_eta();
                self.fresh = true;
                self.show();
            }
            run::Event::Stage { name, steps: None } => {
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
            run::Event::Progress(p) => {
                self.bar.set_position(p);
                if self.fresh {
                    self.bar.reset_eta();
                    self.fresh = false;
                }
            }
            run::Event::Record(_) => {}
        }
    }

    pub(crate) fn show(&self) {
        if self.bar.is_hidden() {
            self.bar.set_draw_target(ProgressDrawTarget::stderr());
        }
    }

    pub(crate) fn finish(&self) {
        self.bar.finish_and_clear();
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
            let resumed_checkpoint = *input == "--resume" && *o == "--checkpoint";
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
