//! Writing to standard output and standard error without panicking. Results go to
//! standard output through [`write_out`]: a write error becomes an error of the command
//! (`cannot write to standard output: …`, status 1), and a reader that went away (a
//! closed pipe, `| head -1`) ends the program quietly with status 141, as a program
//! killed by SIGPIPE would. Notes and reports on standard error are best effort: a
//! standard error that cannot be written loses the note, never a written result.

use std::io::Write;

/// The status of a program whose reader closed the pipe (128 + SIGPIPE).
pub(crate) const CLOSED_PIPE_STATUS: i32 = 141;

/// Writes `args` to standard output.
pub(crate) fn write_out(args: std::fmt::Arguments<'_>) -> anyhow::Result<()> {
    std::io::stdout()
        .lock()
        .write_fmt(args)
        .map_err(stdout_error)
}

/// Flushes standard output, so that a failing last write is reported, not lost at exit.
pub(crate) fn flush_out() -> anyhow::Result<()> {
    std::io::stdout().lock().flush().map_err(stdout_error)
}

fn stdout_error(e: std::io::Error) -> anyhow::Error {
    anyhow::Error::new(e).context("cannot write to standard output")
}

/// Writes `args` to standard error, ignoring a failure.
pub(crate) fn write_note(args: std::fmt::Arguments<'_>) {
    let _ = std::io::stderr().lock().write_fmt(args);
}

/// Whether an error comes from a reader that closed its end of a pipe.
pub(crate) fn is_closed_pipe(e: &anyhow::Error) -> bool {
    e.chain().any(|c| {
        c.downcast_ref::<std::io::Error>()
            .is_some_and(|io| io.kind() == std::io::ErrorKind::BrokenPipe)
    })
}

/// `print!` that returns an error instead of panicking.
macro_rules! out {
    ($($t:tt)*) => { $crate::streams::write_out(format_args!($($t)*))? };
}

/// `println!` that returns an error instead of panicking.
macro_rules! outln {
    () => { $crate::streams::write_out(format_args!("\n"))? };
    ($($t:tt)*) => {{
        $crate::streams::write_out(format_args!($($t)*))?;
        $crate::streams::write_out(format_args!("\n"))?;
    }};
}

/// `eprint!` that never panics (a note that cannot be shown is dropped).
macro_rules! note {
    ($($t:tt)*) => { $crate::streams::write_note(format_args!($($t)*)) };
}

/// `eprintln!` that never panics.
macro_rules! noteln {
    ($($t:tt)*) => {{
        $crate::streams::write_note(format_args!($($t)*));
        $crate::streams::write_note(format_args!("\n"));
    }};
}

pub(crate) use {note, noteln, out, outln};
