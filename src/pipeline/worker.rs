//! A front end's call run on a worker thread that its user can interrupt: the calling
//! thread waits in short slices and looks at its signals between them (Python's Ctrl-C),
//! and the run's stages are shown as plain lines. What a front end adds is only how it
//! looks at its signals and how it raises the outcome.

use std::any::Any;
use std::io::Write;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::sync::mpsc::{channel, RecvTimeoutError};
use std::sync::{Mutex, MutexGuard};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use crate::solve::Event;

/// How long a call waits for its worker after a signal before it gives up on it: the
/// runs and the pair sums stop within a step or a tile, but a computation without such
/// checks must not keep the user waiting.
pub const STOP_GRACE: Duration = Duration::from_millis(300);

/// How often the waiting thread looks at its signals.
const SLICE: Duration = Duration::from_millis(50);

/// Why a watched call returned no value.
#[derive(Debug)]
pub enum Stopped<E> {
    /// The front end's signal (its error, to raise as it is).
    Signal(E),
    /// The library refused the call: its message.
    Refused(String),
    /// The computation panicked (a bug): what to tell the user.
    Panicked(String),
}

/// The workers of calls that were given up on before their worker stopped.
fn abandoned() -> MutexGuard<'static, Vec<JoinHandle<()>>> {
    static ABANDONED: Mutex<Vec<JoinHandle<()>>> = Mutex::new(Vec::new());
    ABANDONED.lock().unwrap_or_else(|e| e.into_inner())
}

/// Returns once every abandoned worker has stopped (the stop request stays set until
/// then), looking at the signals meanwhile.
fn wait_for_abandoned<E>(signals: &mut impl FnMut() -> Result<(), E>) -> Result<(), E> {
    loop {
        let running = {
            let mut workers = abandoned();
            workers.retain(|w| !w.is_finished());
            !workers.is_empty()
        };
        if !running {
            return Ok(());
        }
        std::thread::sleep(SLICE);
        signals()?;
    }
}

/// Runs `f` on a worker thread while this thread calls `signals` every 50 ms: a signal
/// asks the library's runs and pair sums to stop ([`crate::solve::cancel`]) and returns
/// as soon as the worker has stopped, or after [`STOP_GRACE`] at the latest (the
/// worker's result, when it comes, is dropped). A panic of `f` is caught.
pub fn watched<T: Send + 'static, E>(
    f: impl FnOnce() -> Result<T, String> + Send + 'static,
    mut signals: impl FnMut() -> Result<(), E>,
) -> Result<T, Stopped<E>> {
    // A worker given up on still holds the thread pool: clearing the stop request under
    // it would let it run on beside this call. It is asked to stop until it has.
    wait_for_abandoned(&mut signals).map_err(Stopped::Signal)?;
    crate::solve::clear_cancel();
    let mut signal: Option<(E, Instant)> = None;
    let (done, finished) = channel();
    let mut worker = Some(std::thread::spawn(move || {
        let _ = done.send(catch_unwind(AssertUnwindSafe(f)));
    }));
    let outcome = loop {
        match finished.recv_timeout(SLICE) {
            Ok(result) => break result,
            Err(RecvTimeoutError::Disconnected) => {
                break Err(
                    Box::new("the worker thread ended without a result") as Box<dyn Any + Send>
                )
            }
            Err(RecvTimeoutError::Timeout) => {}
        }
        match &signal {
            None => {
                if let Err(e) = signals() {
                    crate::solve::cancel();
                    signal = Some((e, Instant::now()));
                }
            }
            Some((_, since)) if since.elapsed() >= STOP_GRACE => {
                abandoned().extend(worker.take());
                break Err(Box::new("interrupted") as Box<dyn Any + Send>);
            }
            Some(_) => {}
        }
    };
    if let Some((e, _)) = signal {
        // The stop request stays set until the next call clears it, so that a worker
        // still running winds down meanwhile.
        return Err(Stopped::Signal(e));
    }
    match outcome {
        Ok(Ok(v)) => Ok(v),
        Ok(Err(message)) => Err(Stopped::Refused(message)),
        Err(panic) => {
            let what = panic
                .downcast_ref::<String>()
                .cloned()
                .or_else(|| panic.downcast_ref::<&str>().map(|s| s.to_string()))
                .unwrap_or_default();
            Err(Stopped::Panicked(format!(
                "internal error in stillpoint (please report it): {what}"
            )))
        }
    }
}

/// A run's stages as plain lines (`stillpoint: DEM 120/400`), each redrawn in place at
/// most five times a second: what a front end without a bar of its own shows.
#[derive(Debug, Default)]
pub struct StageLines {
    stage: &'static str,
    steps: Option<u64>,
    last: Option<Instant>,
}

impl StageLines {
    /// Writes what `e` changes to `out`.
    pub fn event(&mut self, e: Event, out: &mut impl Write) {
        let _ = match e {
            Event::Stage { name, steps } => {
                let newline = if self.last.is_some() { "\n" } else { "" };
                self.stage = name;
                self.steps = steps;
                self.last = Some(Instant::now());
                write!(out, "{newline}\rstillpoint: {name}")
            }
            Event::Progress(step) => {
                if self
                    .last
                    .is_some_and(|t| t.elapsed() < Duration::from_millis(200))
                {
                    return;
                }
                self.last = Some(Instant::now());
                match self.steps {
                    Some(total) => write!(out, "\rstillpoint: {} {step}/{total}", self.stage),
                    None => write!(out, "\rstillpoint: {} {step}", self.stage),
                }
            }
            Event::Record(_) => Ok(()),
        };
    }

    /// Ends the last line, if any was written.
    pub fn finish(&self, out: &mut impl Write) {
        if self.last.is_some() {
            let _ = writeln!(out);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_value_a_refusal_and_a_panic_come_back_as_such() {
        let never = || Ok::<(), ()>(());
        assert_eq!(watched(|| Ok(6 * 7), never).unwrap(), 42);
        match watched(|| Err::<u8, _>("n: too large".to_string()), never) {
            Err(Stopped::Refused(m)) => assert_eq!(m, "n: too large"),
            other => panic!("{other:?}"),
        }
        match watched(|| -> Result<u8, String> { panic!("lost {}", 7) }, never) {
            Err(Stopped::Panicked(m)) => assert!(m.ends_with("please report it): lost 7"), "{m}"),
            other => panic!("{other:?}"),
        }
    }

    #[test]
    fn stages_and_steps_are_lines_redrawn_in_place() {
        let mut out = Vec::new();
        let mut lines = StageLines::default();
        lines.finish(&mut out);
        assert!(out.is_empty(), "no stage, no line to end");
        let stage = |name| Event::Stage {
            name,
            steps: Some(400),
        };
        lines.event(stage("DEM"), &mut out);
        lines.event(stage("polish"), &mut out);
        lines.finish(&mut out);
        let text = String::from_utf8(out).unwrap();
        assert_eq!(text, "\rstillpoint: DEM\n\rstillpoint: polish\n");
    }
}
