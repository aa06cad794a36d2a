//! `geodesic new mission NAME --path DIR`: scaffolds a project outside this repository that
//! verifies its own system with geodesic ([`geodesic_verify::scaffold`]).

use crate::error::CmdResult;
use std::path::PathBuf;

/// Flags of `geodesic new`.
#[derive(clap::Args, Debug)]
pub struct Args {
    #[command(subcommand)]
    what: What,
}

#[derive(clap::Subcommand, Debug)]
enum What {
    /// A mission project: a requirement, an input file, one check with a small model, a traced
    /// test and a `main` that runs the verification.
    #[command(after_help = "Examples:
  geodesic new mission solar-hinge --path ../solar-hinge
  cd ../solar-hinge && cargo run -- test && cargo run -- verify --require-tests
The project depends on geodesic's framework crates by git (the checkout's remote `origin` at its
commit, or --geodesic-git URL --geodesic-rev COMMIT) when the checkout has a network remote,
else by the relative path to the checkout (--geodesic names another one); it copies the
checkout's Cargo.lock, so it builds with the tested versions.")]
    Mission(MissionArgs),
}

/// Flags of `geodesic new mission`.
#[derive(clap::Args, Debug)]
pub struct MissionArgs {
    /// The mission's name: lower-case letters, digits and `-` (the package name; requirement
    /// IDs start with it in capitals).
    pub name: String,
    /// The project's folder (new or empty).
    #[arg(long, value_name = "DIR")]
    pub path: PathBuf,
    /// The geodesic checkout the project depends on [default: the one this program was built
    /// from].
    #[arg(long, value_name = "DIR")]
    pub geodesic: Option<PathBuf>,
    /// Depend on geodesic by this git URL [default: the checkout's remote `origin` when it is a
    /// network URL, else a relative path].
    #[arg(long, value_name = "URL")]
    pub geodesic_git: Option<String>,
    /// The commit (or tag) of the git dependency [default: the checkout's HEAD].
    #[arg(long, value_name = "COMMIT")]
    pub geodesic_rev: Option<String>,
    /// Print `{"path", "files"}` as JSON.
    #[arg(long)]
    pub json: bool,
}

/// Runs the command.
pub fn run(args: Args) -> CmdResult {
    let What::Mission(a) = args.what;
    let framework = a
        .geodesic
        .clone()
        .unwrap_or_else(|| PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../..")));
    let (files, note) = geodesic_verify::scaffold::write(&geodesic_verify::scaffold::NewMission {
        name: a.name.clone(),
        path: a.path.clone(),
        framework,
        git: a.geodesic_git.clone(),
        rev: a.geodesic_rev.clone(),
    })?;
    if let Some(note) = note {
        eprintln!("geodesic: note: {note}");
    }
    if a.json {
        println!(
            "{}",
            serde_json::to_string_pretty(&geodesic_verify::scaffold::NewMissionDoc::new(
                &a.path, &files
            ))
            .map_err(crate::error::CliError::io)?
        );
    } else {
        for f in &files {
            println!("wrote {}", f.display());
        }
        println!(
            "next: cd {} && cargo run -- test && cargo run -- verify --require-tests",
            a.path.display()
        );
    }
    Ok(0)
}
