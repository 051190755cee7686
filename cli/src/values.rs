//! How the command line spells the library's parameters: `log_every` is `--log-every`,
//! `s` is `-s`. The library names parameters in its errors; these functions turn those
//! names into flags, so a refusal reads as the command that was typed. Every flag is
//! read from the option's declaration ([`Opt`]), never written again here. A number
//! typed for a flag is read here too ([`whole`], [`declared`]), never by clap's types: a
//! refused number gets the wording and the exit status of every refused value.

use stillpoint::pipeline::options::{cli_name, Field, FromValue, Opt};
use stillpoint::pipeline::request::Arg;

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

/// A whole number typed for `flag`, one of `accepted`, or the refusal `invalid FLAG =
/// VALUE: expected {expected}`, whatever is wrong with it (negative, fractional, not a
/// number, out of range). `expected` words the range; where the range ends only where
/// `usize` does, `expected` leaves that end unsaid, so a value beyond it is told it.
pub(crate) fn whole(
    flag: &str,
    typed: &str,
    accepted: std::ops::RangeInclusive<usize>,
    expected: &str,
) -> anyhow::Result<usize> {
    let t = typed.trim();
    let digits = t.strip_prefix('+').unwrap_or(t);
    match t.parse::<usize>() {
        Ok(v) if accepted.contains(&v) => Ok(v),
        Err(_)
            if *accepted.end() == usize::MAX
                && !digits.is_empty()
                && digits.bytes().all(|b| b.is_ascii_digit()) =>
        {
            anyhow::bail!(
                "invalid {flag} = {typed}: expected {expected}, at most {}",
                usize::MAX
            )
        }
        _ => anyhow::bail!("invalid {flag} = {typed}: expected {expected}"),
    }
}

/// The value typed for the library's option `opt` by a command that passes it to no
/// library request (`baseline -n`, `study --seed`), read by the option's declaration:
/// the range, the refusal and the status of the commands that do (`generate -n`).
pub(crate) fn declared<T: FromValue + Clone>(opt: Opt, typed: &str) -> anyhow::Result<T> {
    match Field::<T>::read(opt, Some(&Arg::from(typed)), &flag_name).value()? {
        Some(v) => Ok(v),
        None => anyhow::bail!(
            "invalid {} = {typed}: expected {}",
            flag(opt),
            (opt.declared().expected)()
        ),
    }
}
