//! How the command line spells the library's parameters: `log_every` is `--log-every`,
//! `s` is `-s`. The library names parameters in its errors; these functions turn those
//! names into flags, so a refusal reads as the command that was typed.

/// The flag that sets a library parameter (as the library names it in its settings and
/// errors, [`stillpoint::pipeline::options::OPTIONS`]), or the name itself when no flag
/// sets it.
pub(crate) fn flag_name(parameter: &str) -> String {
    match parameter {
        // The checkpoint a resume reads, named by a checkpoint's mismatch.
        "resume checkpoint" => "--resume".to_string(),
        other => stillpoint::pipeline::options::cli_name(other),
    }
}

/// A library error with the parameter it names shown as the flag that sets it.
pub(crate) fn with_flag_names(e: anyhow::Error) -> anyhow::Error {
    // An error with context says which option it concerns already.
    if e.chain().count() > 1 {
        return e;
    }
    match e.downcast::<stillpoint::Error>() {
        Ok(stillpoint::Error::InvalidArgument {
            name,
            value,
            expected,
        }) => stillpoint::Error::invalid(flag_name(&name), value, expected).into(),
        Ok(other) => other.into(),
        Err(e) => e,
    }
}
