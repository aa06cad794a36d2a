//! Usage errors name what is wrong in one line; negative numbers are values; `geodesic` alone
//! lists the commands (exit 2); every command's `--help` ends with examples.

mod common;
use common::{geodesic, scratch};

/// Runs and asserts exit 2, nothing on standard output and one line on standard error holding
/// every `want`; returns the line.
fn usage_error(args: &[&str], want: &[&str]) -> String {
    let d = scratch("usage");
    let o = geodesic(args, &d);
    let e = String::from_utf8_lossy(&o.stderr).to_string();
    assert_eq!(o.status.code(), Some(2), "{args:?}: {e}");
    assert!(o.stdout.is_empty(), "{args:?}");
    assert_eq!(e.trim_end().lines().count(), 1, "{args:?}: {e}");
    for w in want {
        assert!(e.contains(w), "{args:?}: `{w}` not in {e}");
    }
    e
}

#[test]
fn a_missing_argument_is_named() {
    usage_error(
        &["montecarlo", "--shard", "1/2"],
        &["--out <PART.json>", "(see geodesic montecarlo --help)"],
    );
    usage_error(&["merge"], &["<PART.json>", "(see geodesic merge --help)"]);
    usage_error(&["fit"], &["--effects <EFFECTS>", "<DATASET>"]);
    usage_error(
        &["import", "reqif"],
        &["<FILE>", "(see geodesic import reqif --help)"],
    );
    usage_error(
        &["capture", "--vz"],
        &["a value is required for '--vz <VZ>'"],
    );
}

#[test]
fn a_wrong_argument_or_value_is_named() {
    usage_error(
        &["fit", "d.yaml", "--effects", "piezo", "--bund", "x"],
        &["'--bund'", "tip: a similar argument exists: '--bound'"],
    );
    usage_error(
        &["verify", "--mc-n", "abc"],
        &[
            "--mc-n takes a whole number",
            "`abc` is not one",
            "(see geodesic verify --help)",
        ],
    );
    usage_error(&["frobnicate"], &["unrecognized subcommand 'frobnicate'"]);
    // the commands' own checks name the flag too
    for (args, want) in [
        (
            &[
                "synth",
                "--scenario",
                "foo",
                "--effects",
                "piezo",
                "--out",
                "x.yaml",
            ][..],
            "--scenario foo: unknown scenario",
        ),
        (
            &[
                "synth",
                "--scenario",
                "rt-retraction",
                "--effects",
                "nope",
                "--out",
                "x.yaml",
            ],
            "--effects nope: unknown effect for rt-retraction",
        ),
        (
            &["montecarlo", "--shard", "3/2", "--out", "p.json"],
            "--shard 3/2",
        ),
        (
            &["fit", "d.yaml", "--effects", "piezo", "--fix", "piezo.R"],
            "--fix `piezo.R`",
        ),
    ] {
        let d = scratch("own");
        let o = common::geodesic(args, &d);
        let e = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {e}");
        assert_eq!(e.trim_end().lines().count(), 1, "{e}");
        assert!(e.contains(want), "{args:?}: `{want}` not in {e}");
    }
}

#[test]
fn negative_values_are_taken_where_they_mean_something_and_named_where_not() {
    // a count: refused, saying why
    usage_error(
        &["montecarlo", "--n", "-1"],
        &[
            "'-1' for '--n <N>'",
            "--n takes a whole number, 0 or more: `-1` is negative",
        ],
    );
    usage_error(&["verify", "--seed", "-3"], &["--seed", "`-3` is negative"]);
    // a sampling frequency, with or without its unit: refused, saying why
    for fs in ["-100", "-100Hz"] {
        usage_error(
            &[
                "synth",
                "--scenario",
                "rt-retraction",
                "--effects",
                "piezo",
                "--fs",
                fs,
                "--out",
                "x.yaml",
            ],
            &["--fs", "a sampling frequency must be > 0"],
        );
    }
    usage_error(
        &[
            "synth",
            "--scenario",
            "rt-retraction",
            "--effects",
            "piezo",
            "--pre",
            "-1ms",
            "--out",
            "x.yaml",
        ],
        &["--pre", "cannot be negative"],
    );
    // a radius: the command names it
    let d = scratch("neg");
    let o = geodesic(&["tip-radius", "--radii", "-1,2"], &d);
    let e = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2));
    assert!(e.contains("--radii: -1 mm is not a radius"), "{e}");
    // where negative is meaningful, it is a value: a charge to neutralise, a velocity, an angle
    let o = geodesic(
        &["charge", "--neutralise-e", "-1e8", "--n", "1000", "--json"],
        &d,
    );
    assert_eq!(o.status.code(), Some(0), "{o:?}");
    let o = geodesic(
        &["capture", "--vz", "-3um/s", "--thz", "-1mrad", "--json"],
        &d,
    );
    assert!(matches!(o.status.code(), Some(0 | 1)), "{o:?}");
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert!(v["quartic_sum"].as_f64().unwrap().is_finite());
}

#[test]
fn geodesic_alone_lists_the_commands_and_exits_2() {
    let d = scratch("bare");
    let o = geodesic(&[], &d);
    assert_eq!(o.status.code(), Some(2));
    assert!(o.stdout.is_empty());
    let e = String::from_utf8_lossy(&o.stderr);
    assert!(
        e.starts_with("geodesic: usage: `geodesic` needs one of the commands below"),
        "{e}"
    );
    assert!(e.contains("Commands:") && e.contains("verify") && e.contains("Examples:"));
    let o = geodesic(&["import"], &d);
    assert_eq!(o.status.code(), Some(2));
    let e = String::from_utf8_lossy(&o.stderr);
    assert!(e.starts_with("geodesic: usage: `geodesic import` needs one of the commands below"));
    assert!(e.contains("reqif"));
    // asked for, the help is on standard output with status 0
    let o = geodesic(&["--help"], &d);
    assert_eq!(o.status.code(), Some(0));
    assert!(String::from_utf8_lossy(&o.stdout).contains("Commands:"));
}

/// The commands `geodesic --help` lists (and their own subcommands), each with examples.
#[test]
fn every_help_ends_with_examples() {
    let d = scratch("help");
    let top = geodesic(&["--help"], &d);
    let text = String::from_utf8_lossy(&top.stdout).to_string();
    assert!(text.contains("Examples:"), "{text}");
    let commands: Vec<String> = text
        .lines()
        .skip_while(|l| !l.starts_with("Commands:"))
        .skip(1)
        .take_while(|l| l.starts_with("  "))
        .map(|l| l.split_whitespace().next().unwrap().to_string())
        .filter(|c| c != "help")
        .collect();
    assert!(commands.len() >= 20, "{commands:?}");
    let mut checked = 0;
    for c in &commands {
        let o = geodesic(&[c, "--help"], &d);
        assert_eq!(o.status.code(), Some(0), "{c}");
        let h = String::from_utf8_lossy(&o.stdout).to_string();
        assert!(
            h.contains("Examples:"),
            "geodesic {c} --help has no examples:\n{h}"
        );
        checked += 1;
        // nested commands (export reqif, import reqif)
        for sub in h
            .lines()
            .skip_while(|l| !l.starts_with("Commands:"))
            .skip(1)
            .take_while(|l| l.starts_with("  "))
            .map(|l| l.split_whitespace().next().unwrap().to_string())
            .filter(|s| s != "help")
        {
            let o = geodesic(&[c, &sub, "--help"], &d);
            let h = String::from_utf8_lossy(&o.stdout);
            assert!(
                h.contains("Examples:"),
                "geodesic {c} {sub} --help has no examples"
            );
            checked += 1;
        }
    }
    assert!(checked >= 22, "{checked}");
}
