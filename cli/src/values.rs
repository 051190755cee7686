//! How the command line spells the library's parameters: `log_every` is `--log-every`,
//! `s` is `-s`. The library names parameters in its errors; these functions turn those
//! names into flags, so a refusal reads as the command that was typed.

/// The flag that sets a library parameter (as the library names it in its settings and
/// errors), or the name itself when no flag sets it.
pub(crate) fn flag_name(parameter: &str) -> String {
    match parameter {
        "n" => "-n".to_string(),
        "s" => "-s".to_string(),
        "bbox" => "--box".to_string(),
        "expression" => "--region".to_string(),
        "log_every" => "--log-every".to_string(),
        "constraints" | "constraint" => "--constraint".to_string(),
        "mixture" => "--mixture".to_string(),
        "resume checkpoint" => "--resume".to_string(),
        // A design's variables come from --var (or a --space file, which its caller names).
        "space" => "--var".to_string(),
        "correlation" => "--correlation".to_string(),
        "energy" | "q" | "p" | "precision" | "init" | "seed" | "integrator" | "shifts"
        | "polish" | "steps" | "kappa" | "restart" | "tolerance" | "box" | "shape" | "goal"
        | "method" | "target" | "randomize" | "extend" | "nested" | "bounds" | "region"
        | "trajectory" | "checkpoint" => format!("--{parameter}"),
        other => other.to_string(),
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
