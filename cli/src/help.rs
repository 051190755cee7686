//! `--help` and `-h` written from the option declarations
//! ([`stillpoint::pipeline::options::OPTIONS`]): for every flag of every subcommand that
//! sets a declared option, the short help is the declaration's doc line, and both helps
//! list the values the declaration accepts (clap's `[possible values: …]`) and its
//! default (`[default: …]`). The prose of the clap structs stays the long help's
//! explanation, so a value list or a default written there cannot go stale: the
//! declaration says them.

use clap::builder::{PossibleValue, TypedValueParser};
use stillpoint::pipeline::options::{Declared, Group, OPTIONS};

/// The flag of `a` as the user types it (`--box`, `-n`); positional arguments have none.
pub(crate) fn flag_of(a: &clap::Arg) -> Option<String> {
    match (a.get_long(), a.get_short()) {
        (Some(long), _) => Some(format!("--{long}")),
        (None, Some(short)) => Some(format!("-{short}")),
        (None, None) => None,
    }
}

/// Whether the subcommand `command` takes the declared option `d`.
fn takes(d: &Declared, command: &str) -> bool {
    match command {
        "generate" => true,
        "eval" => d.is(Group::Eval),
        _ => false,
    }
}

/// The declaration behind the flag `flag` of the subcommand `command`, if any.
pub(crate) fn declaration(command: &str, flag: &str) -> Option<&'static Declared> {
    OPTIONS
        .iter()
        .find(|d| (d.cli == flag || d.cli_also.contains(&flag)) && takes(d, command))
}

/// Every word the declaration `d` accepts as its value (empty for a number, a file, an
/// expression: their form is the doc's to say).
pub(crate) fn accepted(_d: &Declared) -> Vec<&'static str> {
    Vec::new()
}

/// The declaration's default as help shows it, if it has one to show.
pub(crate) fn default_text(_d: &Declared) -> Option<String> {
    None
}

/// `cmd` and its subcommands, at any depth, with each declared flag's help written from
/// its declaration.
pub(crate) fn declared_help(cmd: clap::Command) -> clap::Command {
    let name = cmd.get_name().to_string();
    let declared: Vec<(clap::Id, &'static Declared)> = cmd
        .get_arguments()
        .filter_map(|a| Some((a.get_id().clone(), declaration(&name, &flag_of(a)?)?)))
        .collect();
    let cmd = declared
        .into_iter()
        .fold(cmd, |cmd, (id, d)| cmd.mut_arg(id, |a| described(a, d)));
    let subcommands: Vec<String> = cmd
        .get_subcommands()
        .map(|c| c.get_name().to_string())
        .collect();
    subcommands
        .iter()
        .fold(cmd, |cmd, sub| cmd.mut_subcommand(sub, declared_help))
}

/// The flag `a` described by its declaration `d`: the doc line as short help, the prose
/// written beside the flag (without a default of its own) as long help, both ending
/// with the declared default, and the accepted words as clap's possible values.
fn described(a: clap::Arg, d: &Declared) -> clap::Arg {
    let default = default_text(d).map_or_else(String::new, |t| format!(" [default: {t}]"));
    let prose = a
        .get_long_help()
        .or(a.get_help())
        .map_or_else(|| d.doc.to_string(), |h| without_default(&h.to_string()));
    let a = a
        .help(format!("{}{default}", d.doc))
        .long_help(format!("{prose}{default}"));
    let words = accepted(d);
    // A flag read as text lists the words; its value stays the text typed, which the
    // library reads and refuses by the declaration (naming the flag as typed).
    if words.is_empty() || a.get_value_parser().type_id() != std::any::TypeId::of::<String>() {
        return a;
    }
    a.value_parser(Listed(words))
}

/// `text` without a `[default: …]` written in it: the declaration gives the default.
fn without_default(text: &str) -> String {
    let Some(start) = text.find("[default:") else {
        return text.to_string();
    };
    let end = text[start..]
        .find(']')
        .map_or(text.len(), |e| start + e + 1);
    without_default(&format!("{}{}", text[..start].trim_end(), &text[end..]))
}

/// A value read as the text typed, with the words it may be listed as clap's possible
/// values (for the help; the library checks the value).
#[derive(Clone)]
struct Listed(Vec<&'static str>);

impl TypedValueParser for Listed {
    type Value = String;

    fn parse_ref(
        &self,
        cmd: &clap::Command,
        arg: Option<&clap::Arg>,
        value: &std::ffi::OsStr,
    ) -> Result<String, clap::Error> {
        clap::builder::StringValueParser::new().parse_ref(cmd, arg, value)
    }

    fn possible_values(&self) -> Option<Box<dyn Iterator<Item = PossibleValue> + '_>> {
        Some(Box::new(self.0.iter().map(|w| PossibleValue::new(*w))))
    }
}
