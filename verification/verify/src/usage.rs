//! Parsing a command line: negative numbers as values, and every usage error as one line that
//! names the argument or value at fault (the `geodesic` binary's, and any program built on
//! geodesic's commands).
//!
//! clap renders an error over several lines (the cause, the missing arguments one per line, a
//! tip, the usage); the rule of the house is one line on standard error, `PROGRAM: usage: ...`.
//! The line keeps every line of the cause (so `geodesic montecarlo --shard 1/2` says `--out
//! <PART.json>` is missing, `merge` says `<PART.json>...` is), the tip (`a similar argument
//! exists: '--bound'`), and names the subcommand whose `--help` to read.
//!
//! The program alone, or a command given without its subcommand (`geodesic import` without a
//! format), is a usage error too: the short help of that command (its commands and options)
//! goes to standard error and the exit status is 2, as for any usage error; `--help` prints it
//! on standard output with status 0.

use clap::error::{ContextKind, ContextValue, ErrorKind};
use clap::{ArgMatches, Command};

/// Every option that takes a value accepts a negative number as that value (`--n -1`,
/// `--neutralise-e -3e8`): clap would read `-1` as a flag and answer "unexpected argument
/// '-1'". The command then says why a negative value is meaningless where it is (a count, a
/// sampling frequency), naming the flag.
pub fn accept_negative_numbers(cmd: Command) -> Command {
    cmd.mut_args(|a| {
        if !a.is_positional() && a.get_action().takes_values() && !a.is_allow_hyphen_values_set() {
            a.allow_negative_numbers(true)
        } else {
            a
        }
    })
    .mut_subcommands(accept_negative_numbers)
}

/// Parses the process's arguments into matches with [`accept_negative_numbers`] (for a
/// command built at run time: the missions' own commands); a usage error (or `--help`,
/// `--version`) prints what [`report`] prints, with the command's name as the program's, and
/// returns the exit status.
pub fn parse_matches(cmd: Command) -> Result<ArgMatches, u8> {
    let cmd = accept_negative_numbers(cmd);
    let program = cmd.get_name().to_string();
    let args: Vec<std::ffi::OsString> = std::env::args_os().collect();
    let path = command_path(&cmd, &args);
    cmd.try_get_matches_from(&args)
        .map_err(|e| report(&e, &program, &path))
}

/// The (sub)command the arguments name, `geodesic montecarlo`: its `--help` is the one to read.
pub fn command_path(cmd: &Command, args: &[std::ffi::OsString]) -> String {
    let mut at = cmd;
    let mut path = vec![cmd.get_name().to_string()];
    for a in args.iter().skip(1) {
        if let Some(sub) = a.to_str().and_then(|a| at.find_subcommand(a)) {
            path.push(sub.get_name().to_string());
            at = sub;
        }
    }
    path.join(" ")
}

/// Prints a clap error as the house prints it and returns the exit status: help and version
/// on standard output (0); a command given without its subcommand prints its short help on
/// standard error after a line saying so (2); every other error one line on standard error
/// (2). `program` names the program (`geodesic`), `path` the command the arguments name
/// ([`command_path`]).
pub fn report(e: &clap::Error, program: &str, path: &str) -> u8 {
    match e.kind() {
        ErrorKind::DisplayHelp | ErrorKind::DisplayVersion => {
            let _ = e.print();
            0
        }
        ErrorKind::DisplayHelpOnMissingArgumentOrSubcommand | ErrorKind::MissingSubcommand => {
            eprintln!("{program}: usage: `{path}` needs one of the commands below\n");
            eprint!("{}", e.render());
            2
        }
        _ => {
            eprintln!("{}", line(e, program, path));
            2
        }
    }
}

/// A usage error as one line: `PROGRAM: usage: <every line of the cause>; <tip> (see PATH
/// --help)`.
pub fn line(e: &clap::Error, program: &str, path: &str) -> String {
    let text = e.render().to_string();
    let mut parts: Vec<String> = Vec::new();
    for l in text.lines().map(str::trim).filter(|l| !l.is_empty()) {
        if l.starts_with("Usage:") || l.starts_with("For more information") {
            continue;
        }
        let l = l.strip_prefix("error: ").unwrap_or(l);
        match parts.last_mut() {
            // "the following required arguments were not provided:" and its list
            Some(prev) if prev.ends_with(':') => {
                prev.push(' ');
                prev.push_str(l);
            }
            Some(prev) if prev.ends_with(", ") || !l.starts_with("tip:") && is_list_item(l) => {
                prev.push_str(", ");
                prev.push_str(l);
            }
            _ => parts.push(l.to_string()),
        }
    }
    if let Some((why, parser)) = number_cause(e) {
        // in place of the number parser's own words
        if let Some(first) = parts.first_mut()
            && let Some(cut) = first.rfind(&parser)
        {
            first.truncate(cut);
        }
        parts.push(why);
    }
    let cause = if parts.is_empty() {
        "invalid usage".to_string()
    } else {
        parts.join("; ")
    };
    format!(
        "{program}: usage: {} (see {path} --help)",
        geodesic_util::text::one_line(&cause)
    )
}

/// A line of clap's list of missing arguments (`--out <PART.json>`, `<PART.json>...`).
fn is_list_item(l: &str) -> bool {
    (l.starts_with("--") || l.starts_with('<') || l.starts_with('-')) && !l.contains(' ')
        || (l.starts_with("--") && l.split_whitespace().count() == 2 && l.ends_with('>'))
}

/// Why a value is refused by a flag that takes a number, in place of the number parsers'
/// "invalid digit found in string" and "invalid float literal": what the flag takes, and
/// whether the value is negative (`--n -1`: a count) or no number at all.
fn number_cause(e: &clap::Error) -> Option<(String, String)> {
    if e.kind() != ErrorKind::ValueValidation {
        return None;
    }
    let value = match e.get(ContextKind::InvalidValue) {
        Some(ContextValue::String(v)) => v.clone(),
        _ => return None,
    };
    let arg = match e.get(ContextKind::InvalidArg) {
        Some(ContextValue::String(a)) => a.split_whitespace().next().unwrap_or("").to_string(),
        _ => return None,
    };
    let source = std::error::Error::source(e)?;
    if let Some(pe) = source.downcast_ref::<std::num::ParseIntError>() {
        let why = if value.starts_with('-') && value[1..].parse::<f64>().is_ok() {
            format!("{arg} takes a whole number, 0 or more: `{value}` is negative")
        } else {
            format!("{arg} takes a whole number, 0 or more: `{value}` is not one")
        };
        return Some((why, format!(": {pe}")));
    }
    if source.downcast_ref::<std::num::ParseFloatError>().is_some() {
        return Some((
            format!("{arg} takes a number: `{value}` is not one"),
            ": invalid float literal".to_string(),
        ));
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;
    use clap::{Arg, ArgAction};

    fn cmd() -> Command {
        Command::new("geodesic")
            .subcommand_required(true)
            .arg_required_else_help(true)
            .subcommand(
                Command::new("montecarlo")
                    .arg(
                        Arg::new("n")
                            .long("n")
                            .value_parser(clap::value_parser!(usize)),
                    )
                    .arg(Arg::new("shard").long("shard").requires("out"))
                    .arg(Arg::new("out").long("out").value_name("PART.json"))
                    .arg(Arg::new("bound").long("bound").action(ArgAction::Append)),
            )
            .subcommand(
                Command::new("merge").arg(
                    Arg::new("parts")
                        .required(true)
                        .num_args(1..)
                        .value_name("PART.json"),
                ),
            )
            .subcommand(
                Command::new("synth").arg(
                    Arg::new("fs")
                        .long("fs")
                        .value_parser(clap::value_parser!(f64)),
                ),
            )
    }

    fn err(args: &[&str]) -> clap::Error {
        accept_negative_numbers(cmd())
            .try_get_matches_from(args)
            .unwrap_err()
    }

    fn line_of(args: &[&str]) -> String {
        let os: Vec<std::ffi::OsString> = args.iter().map(|a| a.into()).collect();
        line(&err(args), "geodesic", &command_path(&cmd(), &os))
    }

    #[test]
    fn a_missing_argument_is_named() {
        let l = line_of(&["geodesic", "montecarlo", "--shard", "1/2"]);
        assert!(l.contains("--out <PART.json>"), "{l}");
        assert!(l.ends_with("(see geodesic montecarlo --help)"), "{l}");
        let l = line_of(&["geodesic", "merge"]);
        assert!(l.contains("<PART.json>"), "{l}");
        assert!(l.ends_with("(see geodesic merge --help)"), "{l}");
    }

    #[test]
    fn negative_numbers_are_values() {
        let m = accept_negative_numbers(cmd())
            .try_get_matches_from(["geodesic", "synth", "--fs", "-100"])
            .unwrap();
        assert_eq!(
            m.subcommand_matches("synth").unwrap().get_one::<f64>("fs"),
            Some(&-100.0)
        );
        let l = line_of(&["geodesic", "montecarlo", "--n", "-1"]);
        assert!(
            l.contains("'-1' for '--n <n>'") && l.contains("--n takes a whole number, 0 or more"),
            "{l}"
        );
    }

    #[test]
    fn an_unknown_argument_keeps_its_tip() {
        let l = line_of(&["geodesic", "montecarlo", "--bund", "x"]);
        assert!(
            l.contains("'--bund'") && l.contains("tip: a similar argument exists: '--bound'"),
            "{l}"
        );
        assert_eq!(l.lines().count(), 1);
    }

    #[test]
    fn no_command_is_a_usage_error() {
        let e = err(&["geodesic"]);
        assert!(matches!(
            e.kind(),
            ErrorKind::DisplayHelpOnMissingArgumentOrSubcommand | ErrorKind::MissingSubcommand
        ));
    }
}
