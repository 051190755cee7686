//! How the command line spells the library's parameters: `log_every` is `--log-every`,
//! `s` is `-s`. The library names parameters in its errors; these functions turn those
//! names into flags, so a refusal reads as the command that was typed. Every flag is
//! read from the option's declaration ([`Opt`]), never written again here.

use stillpoint::pipeline::options::{cli_name, Opt};

/// The flag that sets a library parameter (as the library names it in its settings and
/// errors, [`stillpoint::pipeline::options::OPTIONS`]), or the name itself when no flag
/// sets it.
pub(crate) fn flag_name(parameter: &str) -> String {
    match parameter {
        // The checkpoint a resume reads, named by a checkpoint's mismatch.
        "resume checkpoint" => other_flag(Opt::checkpoint).to_string(),
        other => cli_name(other),
    }
}

/// `values` written into the JSON object `v` under their options' names: a report or a
/// header records the options of its run as the library names them.
pub(crate) fn record(
    v: &mut serde_json::Value,
    values: impl IntoIterator<Item = (Opt, serde_json::Value)>,
) {
    for (opt, value) in values {
        v[opt.name()] = value;
    }
}

/// The command line's flag of `opt` (every option the command line reads has one).
pub(crate) fn flag(opt: Opt) -> &'static str {
    opt.declared().flag().unwrap_or_default()
}

/// The long flag of `opt` without its dashes, as clap declares it (`box` of `--box`).
pub(crate) fn long(opt: Opt) -> &'static str {
    flag(opt).trim_start_matches('-')
}

/// The other flag that sets `opt`: the file of a design space's variables (`--space`
/// beside `--var`), the resume of a checkpoint (`--resume` beside `--checkpoint`).
pub(crate) fn other_flag(opt: Opt) -> &'static str {
    opt.declared().cli_also.first().copied().unwrap_or_default()
}

/// How a command that reads a design space spells the library's parameters: as
/// [`flag_name`], but the space by the flag that gave it (`--space FILE` when
/// `space_file`, else `--var`).
pub(crate) fn spelling(space_file: bool) -> impl Fn(&str) -> String {
    move |p| match p {
        p if space_file && p == Opt::space.name() => other_flag(Opt::space).to_string(),
        other => flag_name(other),
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
