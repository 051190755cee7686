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
    Ok(())
}
