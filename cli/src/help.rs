//! `--help` and `-h` written from the option declarations
//! ([`stillpoint::pipeline::options::ALL`]): for every flag of every subcommand that
//! sets a declared option, the short help is the declaration's doc line (in the command
//! it is declared for first), and both helps show its default (`[default: …]`) and the
//! values it accepts: its words as clap's `[possible values: …]`, a number's range as
//! its refusal words it (`[values: …]`). The prose of the clap structs stays the long
//! help's explanation, so a value list or a default written there cannot go stale: the
//! declaration says them.

use clap::builder::{PossibleValue, TypedValueParser};
use stillpoint::pipeline::options::{Command, Declared, Kind, ALL};

/// The flag of `a` as the user types it (`--box`, `-n`); positional arguments have none.
pub(crate) fn flag_of(a: &clap::Arg) -> Option<String> {
    match (a.get_long(), a.get_short()) {
        (Some(long), _) => Some(format!("--{long}")),
        (None, Some(short)) => Some(format!("-{short}")),
        (None, None) => None,
    }
}

/// The command of the declarations that the subcommand `subcommand` runs, if it takes
/// declared options.
pub(crate) fn command_of(subcommand: &str) -> Option<Command> {
    match subcommand {
        // The library's `quad` is `integrate --expr` on the command line.
        "integrate" => Some(Command::Quad),
        name => Command::ALL.into_iter().find(|c| c.name() == name),
    }
}

/// The declaration behind the flag `flag` of the subcommand `subcommand`, if any.
pub(crate) fn declaration(subcommand: &str, flag: &str) -> Option<&'static Declared> {
    let command = command_of(subcommand)?;
    ALL.iter().find(|d| {
        d.takes(command) && d.flag().is_some() && (d.cli == flag || d.cli_also.contains(&flag))
    })
}

/// `cmd` and its subcommands, at any depth, with each declared flag's help written from
/// its declaration.
pub(crate) fn declared_help(cmd: clap::Command) -> clap::Command {
    let name = cmd.get_name().to_string();
    let declared: Vec<(clap::Id, &'static Declared)> = cmd
        .get_arguments()
        .filter_map(|a| Some((a.get_id().clone(), declaration(&name, &flag_of(a)?)?)))
        .collect();
    let cmd = declared.into_iter().fold(cmd, |cmd, (id, d)| {
        cmd.mut_arg(id, |a| described(a, d, command_of(&name)))
    });
    let subcommands: Vec<String> = cmd
        .get_subcommands()
        .map(|c| c.get_name().to_string())
        .collect();
    subcommands
        .iter()
        .fold(cmd, |cmd, sub| cmd.mut_subcommand(sub, declared_help))
}

/// The flag `a` of `command` described by its declaration `d`. The short help is the
/// declaration's doc line in the command the option is declared for first (another
/// command may give it another use, as `integrate --bounds` integrates over the box
/// that `generate --bounds` scales to: there it is the line written beside the flag);
/// the long help is the prose written beside the flag. A command the declaration gives a
/// line of its own ([`Declared::doc_in`]) shows that line in both. Both end with the declared
/// default and what the option accepts: its words as clap's possible values, or the
/// declaration's own words for a range ([`accepted`]).
fn described(a: clap::Arg, d: &Declared, command: Option<Command>) -> clap::Arg {
    let takes_value = a.get_action().takes_values();
    // A switch is off unless given: a default says nothing more.
    let default = command
        .and_then(d.default)
        .filter(|_| takes_value)
        .map_or_else(String::new, |t| format!(" [default: {t}]"));
    let values = accepted(d)
        .filter(|_| takes_value)
        .map_or_else(String::new, |t| format!(" [values: {t}]"));
    // A flag shared by several commands (one clap field flattened into each) says
    // there what the declaration gives the command as its own line.
    let own = command.and_then(|c| d.doc_in(c));
    let prose = match own {
        Some(line) => line.to_string(),
        None => a
            .get_long_help()
            .or(a.get_help())
            .map_or_else(|| d.doc.to_string(), |h| without_default(&h.to_string())),
    };
    let short = match command {
        _ if own.is_some() => prose.clone(),
        Some(c) if d.commands.first() != Some(&c) => prose.clone(),
        _ => d.doc.to_string(),
    };
    let said = format!("{default}{values}");
    // The long help sets them apart, as clap sets apart the possible values.
    let apart = match said.trim_start() {
        "" => String::new(),
        said => format!("\n\n{said}"),
    };
    let a = a
        .help(format!("{short}{said}"))
        .long_help(format!("{prose}{apart}"));
    // A word option read as text lists its words; its value stays the text typed, which
    // the library reads and refuses by the declaration (naming the flag as typed).
    let is_text = a.get_value_parser().type_id() == std::any::TypeId::of::<String>();
    match d.kind {
        Kind::Word(_) if is_text => a.value_parser(Listed(words(d))),
        _ => a,
    }
}

/// Every word `d` accepts, each once, in the order its table gives them.
pub(crate) fn words(d: &Declared) -> Vec<&'static str> {
    let mut words = d.words();
    let mut seen = std::collections::HashSet::new();
    words.retain(|w| seen.insert(*w));
    words
}

/// What `d` accepts where it is not a list of words: a number's range as its refusal
/// words it, the words beside a number or a point file. `None` for a list of words
/// (clap lists them) and for a value whose form the doc and the value name give (a
/// box, an expression, a file).
pub(crate) fn accepted(d: &Declared) -> Option<String> {
    let listed = || words(d).join(", ");
    match d.kind {
        Kind::Count { .. } | Kind::Seed | Kind::Real { .. } | Kind::Sizes => Some((d.expected)()),
        Kind::RealOrWord { min, closed, .. } => {
            let bound = if closed { "≥" } else { ">" };
            Some(format!("{}, or a number {bound} {min}", listed()))
        }
        Kind::WordOrPoints(_) => Some(format!("{}, or a point file", listed())),
        _ => None,
    }
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

/// A value read as the text typed whose help lists `words` (those of the table that
/// reads it): for the flags of the commands that take no declared options.
pub(crate) fn listed(words: Vec<&'static str>) -> clap::builder::ValueParser {
    clap::builder::ValueParser::new(Listed(words))
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Cli;

    /// Every subcommand that takes declared options, built as `main` builds it, with
    /// its name and the command of the declarations it runs.
    fn commands() -> Vec<(clap::Command, Command)> {
        let mut cli = Cli::command_with_declared_help();
        cli.build();
        cli.get_subcommands()
            .filter_map(|c| Some((c.clone(), command_of(c.get_name())?)))
            .collect()
    }

    /// The help of one flag alone, short (`-h`) and long (`--help`), as clap renders it.
    fn rendered(a: &clap::Arg) -> [String; 2] {
        let mut one = clap::Command::new("x").arg(a.clone());
        // Words joined by one space: a wrapped line breaks nothing a test looks for.
        let joined = |s: clap::builder::StyledStr| {
            s.to_string()
                .split_whitespace()
                .collect::<Vec<_>>()
                .join(" ")
        };
        [joined(one.render_help()), joined(one.render_long_help())]
    }

    /// Every declared flag of every command: (subcommand, flag, its argument, the
    /// declaration).
    fn declared_flags() -> Vec<(String, String, clap::Arg, &'static Declared)> {
        let mut out = Vec::new();
        for (c, _) in commands() {
            for a in c.get_arguments() {
                let Some(flag) = flag_of(a) else { continue };
                if let Some(d) = declaration(c.get_name(), &flag) {
                    out.push((c.get_name().to_string(), flag, a.clone(), d));
                }
            }
        }
        out
    }

    /// The flags of the commands that take declared options which set none, each with
    /// why it is the command line's own.
    const FRONT_END: [(&str, &str); 10] = [
        ("--output", "where the points are written"),
        ("--json", "how the report is printed"),
        ("--quiet", "whether progress is shown"),
        ("--progress", "how progress is shown"),
        ("--plot", "a picture drawn from the result"),
        (
            "--expr",
            "the integrand: what the command integrates, not how",
        ),
        (
            "--threads",
            "the size of the thread pool, which changes no byte",
        ),
        (
            "--checkpoint-every",
            "how often the checkpoint file is written, which changes no byte",
        ),
        ("--help", "clap's own"),
        ("--version", "clap's own"),
    ];

    #[test]
    fn every_flag_is_declared_for_its_command_or_the_front_ends_own() {
        for (c, command) in commands() {
            let flags: Vec<String> = c.get_arguments().filter_map(flag_of).collect();
            for f in &flags {
                assert!(
                    declaration(c.get_name(), f).is_some() || FRONT_END.iter().any(|(g, _)| g == f),
                    "{} {f} is neither declared for {} nor in FRONT_END",
                    c.get_name(),
                    command.name()
                );
            }
            for d in ALL.iter().filter(|d| d.takes(command)) {
                if let Some(flag) = d.flag() {
                    assert!(
                        flags.iter().any(|f| f == flag),
                        "the declared {flag} is not a flag of {}",
                        c.get_name()
                    );
                }
            }
        }
    }

    #[test]
    fn the_walk_reaches_every_command_that_takes_options() {
        let names: Vec<String> = commands()
            .iter()
            .map(|(c, _)| c.get_name().to_string())
            .collect();
        assert_eq!(names.len(), Command::ALL.len(), "{names:?}");
        for c in Command::ALL {
            let flags = declared_flags();
            let reached = ALL
                .iter()
                .filter(|d| d.takes(c) && d.flag().is_some())
                .all(|d| flags.iter().any(|f| std::ptr::eq(f.3, d)));
            assert!(reached, "{}: a declared flag is not described", c.name());
        }
    }

    #[test]
    fn help_lists_every_value_an_option_accepts() {
        let mut listed = 0;
        for (sub, flag, a, d) in declared_flags() {
            let possible: Vec<String> = a
                .get_possible_values()
                .iter()
                .map(|p| p.get_name().to_string())
                .collect();
            for help in rendered(&a) {
                for w in d.words() {
                    assert!(help.contains(w), "{sub} {flag} omits {w}: {help}");
                    if matches!(d.kind, Kind::Word(_)) {
                        assert!(possible.iter().any(|p| p == w), "{sub} {flag}: {w}");
                    }
                }
                if matches!(d.kind, Kind::Count { .. } | Kind::Seed | Kind::Real { .. }) {
                    let range = format!("[values: {}]", (d.expected)());
                    assert!(help.contains(&range), "{sub} {flag}: {help}");
                }
            }
            assert!(!a.is_hide_possible_values_set(), "{sub} {flag}");
            listed += usize::from(!d.words().is_empty());
        }
        // The word options of generate and the integration commands at the time of
        // writing (goal, method, target, energy, ...); more is fine.
        assert!(listed >= 10, "{listed}");
    }

    /// Every `[default: …]` in a flag's help is the declaration's; where the declaration
    /// has one, the prose beside the flag states none of its own.
    #[test]
    fn help_shows_the_declared_default_and_states_no_other() {
        for (c, command) in commands() {
            for a in c.get_arguments() {
                let Some(flag) = flag_of(a) else { continue };
                let Some(d) = declaration(c.get_name(), &flag) else {
                    continue;
                };
                let want = (d.default)(command)
                    .filter(|_| a.get_action().takes_values())
                    .map(|t| format!("[default: {t}]"));
                for help in rendered(a) {
                    let shown: Vec<String> = help
                        .match_indices("[default: ")
                        .map(|(i, _)| help[i..=i + help[i..].find(']').unwrap()].to_string())
                        .collect();
                    let name = c.get_name();
                    assert_eq!(shown, Vec::from_iter(want.clone()), "{name} {flag}: {help}");
                    if want.is_some() {
                        let said = help.to_lowercase().matches("default").count();
                        assert_eq!(said, 1, "{name} {flag} states a default of its own: {help}");
                    }
                }
            }
        }
    }

    #[test]
    fn short_help_is_the_declarations_doc_in_its_first_command() {
        for (sub, flag, a, d) in declared_flags() {
            let help = a.get_help().map(|h| h.to_string()).unwrap_or_default();
            let command = command_of(&sub);
            match command.and_then(|c| d.doc_in(c)) {
                Some(own) => assert!(help.starts_with(own), "{sub} {flag}: {help}"),
                None if command == d.commands.first().copied() => {
                    assert!(help.starts_with(d.doc), "{sub} {flag}: {help}")
                }
                None => {}
            }
            assert!(
                a.get_long_help().is_some(),
                "{sub} {flag} keeps a long help"
            );
        }
    }

    /// The values a reader found missing from `generate --help`.
    #[test]
    fn generate_help_lists_the_targets_and_energies_it_reads() {
        let (generate, _) = commands()
            .into_iter()
            .find(|(c, _)| c.get_name() == "generate")
            .unwrap();
        for (flag, word) in [
            ("--target", "smooth"),
            ("--target", "curved"),
            ("--target", "lattice"),
            ("--target", "wd"),
            ("--energy", "wd"),
            ("--method", "lattice"),
        ] {
            let a = generate
                .get_arguments()
                .find(|a| flag_of(a).as_deref() == Some(flag))
                .unwrap();
            let listed = a.get_possible_values().iter().any(|p| p.get_name() == word);
            assert!(listed, "{flag} omits {word}");
            for help in rendered(a) {
                assert!(help.contains("[possible values: "), "{flag}: {help}");
            }
        }
    }

    /// The commands without declared options list the words of the tables that read
    /// their values: every discrepancy `compare --energy` reads, every baseline name.
    #[test]
    fn the_other_commands_list_the_words_their_tables_read() {
        let mut cli = Cli::command_with_declared_help();
        cli.build();
        let possible = |sub: &str, id: &str| -> Vec<String> {
            let c = cli.find_subcommand(sub).unwrap();
            let a = c.get_arguments().find(|a| a.get_id() == id).unwrap();
            a.get_possible_values()
                .iter()
                .map(|p| p.get_name().to_string())
                .collect()
        };
        let energies = possible("compare", "energy");
        for w in stillpoint::pipeline::options::words::discrepancies() {
            assert!(
                energies.iter().any(|e| e == w),
                "compare --energy omits {w}"
            );
        }
        let names = possible("baseline", "name");
        for w in stillpoint::sequences::Baseline::names() {
            assert!(names.iter().any(|n| n == w), "baseline omits {w}");
        }
    }
}
