//! `geodesic capture`: evaluates the DFACS quartic capture criterion (thesis ch. 7; physics.md
//! section 6) for one TM state after release, and optionally the capture probability of a set
//! of release z velocities. Thin: the physics is in `geodesic-capture`.

use std::path::PathBuf;

use geodesic_capture::report::CaptureReport;
use geodesic_capture::{
    CaptureInputs, CaptureProbability, Evaluation, StateModel, StateName, TmState, Xlim,
    consistency_sum, evaluate, max_box_scale,
};

use crate::error::{CliError, CmdResult};

/// Flags of `geodesic capture`. State values are SI (m, m/s, rad, rad/s); unset states are 0.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// TM state as YAML (`vz: -3.0e-6`, ...); the flags below override its values.
    #[arg(long, value_name = "FILE.yaml")]
    pub state: Option<PathBuf>,
    /// The capture inputs (`--capture`, the flag the descriptor's input declares: added by
    /// `Reading::reading` in `cmd/mod.rs`).
    #[arg(skip)]
    pub capture: Option<PathBuf>,
    /// Requirement directory the TM state box is read from (rows TMS-*) [default:
    /// ./requirements if present, else the built-in set].
    #[arg(long, value_name = "DIR")]
    pub requirements: Option<PathBuf>,
    /// Offset along x [m; or with a unit: 20um].
    #[arg(long, allow_hyphen_values = true, value_parser = crate::quantity::length())]
    pub x: Option<f64>,
    /// Offset along y [m; or with a unit: 20um].
    #[arg(long, allow_hyphen_values = true, value_parser = crate::quantity::length())]
    pub y: Option<f64>,
    /// Offset along z [m; or with a unit: 20um].
    #[arg(long, allow_hyphen_values = true, value_parser = crate::quantity::length())]
    pub z: Option<f64>,
    /// Velocity along x [m/s; or with a unit: 3um/s].
    #[arg(long, allow_hyphen_values = true, value_parser = crate::quantity::velocity())]
    pub vx: Option<f64>,
    /// Velocity along y [m/s; or with a unit: 3um/s].
    #[arg(long, allow_hyphen_values = true, value_parser = crate::quantity::velocity())]
    pub vy: Option<f64>,
    /// Velocity along z (release axis) [m/s; or with a unit: 3um/s].
    #[arg(long, allow_hyphen_values = true, value_parser = crate::quantity::velocity())]
    pub vz: Option<f64>,
    /// Angle around x [rad; or with a unit: 1.5mrad].
    #[arg(long, allow_hyphen_values = true, value_parser = crate::quantity::angle())]
    pub thx: Option<f64>,
    /// Angle around y [rad; or with a unit: 1.5mrad].
    #[arg(long, allow_hyphen_values = true, value_parser = crate::quantity::angle())]
    pub thy: Option<f64>,
    /// Angle around z [rad; or with a unit: 1.5mrad].
    #[arg(long, allow_hyphen_values = true, value_parser = crate::quantity::angle())]
    pub thz: Option<f64>,
    /// Angular rate around x [rad/s; or with a unit: 50urad/s].
    #[arg(long, allow_hyphen_values = true, value_parser = crate::quantity::angular_rate())]
    pub wx: Option<f64>,
    /// Angular rate around y [rad/s; or with a unit: 50urad/s].
    #[arg(long, allow_hyphen_values = true, value_parser = crate::quantity::angular_rate())]
    pub wy: Option<f64>,
    /// Angular rate around z [rad/s; or with a unit: 50urad/s].
    #[arg(long, allow_hyphen_values = true, value_parser = crate::quantity::angular_rate())]
    pub wz: Option<f64>,
    /// Release z velocities [m/s], one per line (`#` comments allowed): also print the capture
    /// probability with the other states from the capture inputs' sources (as `verify` does).
    #[arg(long, value_name = "FILE")]
    pub vz_samples: Option<PathBuf>,
    /// Seed of the other states' draws for the capture probability.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Print exactly one JSON document on standard output.
    #[arg(long)]
    pub json: bool,
}

impl Args {
    fn flag_values(&self) -> [(StateName, Option<f64>); 12] {
        [
            (StateName::X, self.x),
            (StateName::Y, self.y),
            (StateName::Z, self.z),
            (StateName::Vx, self.vx),
            (StateName::Vy, self.vy),
            (StateName::Vz, self.vz),
            (StateName::Thx, self.thx),
            (StateName::Thy, self.thy),
            (StateName::Thz, self.thz),
            (StateName::Wx, self.wx),
            (StateName::Wy, self.wy),
            (StateName::Wz, self.wz),
        ]
    }
}

/// Runs the command.
pub fn run(args: Args) -> CmdResult {
    let file = crate::inputs::resolve(
        crate::inputs::ModelInput::capture(),
        args.capture.as_deref(),
    )?;
    crate::inputs::announce(args.json, crate::inputs::ModelInput::capture(), &file);
    let inputs = CaptureInputs::from_yaml_str(&file.text, &file.label)
        .map_err(|e| CliError::malformed(e.to_string()).in_file(&file.label, 0))?;
    let (reqs, _, _) = crate::missions::load_requirements(args.requirements.as_ref())?;
    let req = geodesic_checks::capture::requirement_box(&reqs).map_err(CliError::evidence)?;
    let xlim = inputs.xlim(req);
    let mut state = match &args.state {
        Some(p) => {
            TmState::load(p).map_err(|e| CliError::malformed(e.to_string()).in_file(p, 0))?
        }
        None => TmState::zero(),
    };
    for (name, v) in args.flag_values() {
        if let Some(v) = v {
            if !v.is_finite() {
                return Err(CliError::usage(format!("--{name} {v}: must be finite")));
            }
            state.set(name, v);
        }
    }
    let eval = evaluate(&xlim, &state);
    let prob = match &args.vz_samples {
        Some(p) => {
            let vz = read_samples(p)?;
            let model = StateModel::new(&inputs, req);
            Some((
                model.capture_probability(&vz, &xlim, args.seed),
                format!("state sources of {}", file.label),
            ))
        }
        None => None,
    };
    if args.json {
        let doc = CaptureReport::new(&xlim, &state, &eval, prob.as_ref(), &file);
        let doc = serde_json::to_value(&doc).map_err(CliError::io)?;
        println!("{doc}");
    } else {
        print_text(&xlim, &eval, prob.as_ref());
        println!(
            "{}",
            crate::inputs::line(crate::inputs::ModelInput::capture(), &file)
        );
    }
    // exit 1 is the verdict of a command that judges: this state is not captured
    Ok(u8::from(!eval.captured))
}

/// Reads one velocity per line [m/s]; blank lines and `#` comments are skipped.
fn read_samples(path: &std::path::Path) -> Result<Vec<f64>, CliError> {
    let file = path.display().to_string();
    let text = std::fs::read_to_string(path)
        .map_err(|e| CliError::unreadable(format!("{file}: {e}")).in_file(path, 0))?;
    let mut out = Vec::new();
    for (i, line) in text.lines().enumerate() {
        let t = line.split('#').next().unwrap_or("").trim();
        if t.is_empty() {
            continue;
        }
        let v: f64 = t.parse().map_err(|_| {
            CliError::malformed(format!("{file}:{}: `{t}` is not a velocity in m/s", i + 1))
                .in_file(path, i + 1)
        })?;
        if !v.is_finite() {
            return Err(
                CliError::not_finite(format!("{file}:{}: `{t}` is not finite", i + 1))
                    .in_file(path, i + 1),
            );
        }
        out.push(v);
    }
    if out.is_empty() {
        return Err(CliError::malformed(format!("{file}: no velocity samples")).in_file(path, 0));
    }
    Ok(out)
}

fn print_text(xlim: &Xlim, eval: &Evaluation, prob: Option<&(CaptureProbability, String)>) {
    // six decimals where the sum is near the boundary; powers of ten where it is far beyond
    // (a state far outside the box gives sums up to the largest float, 309 digits in `{:.6}`)
    let sum = if eval.quartic_sum.abs() < 1e6 {
        format!("{:.6}", eval.quartic_sum)
    } else {
        format!("{:.6e}", eval.quartic_sum)
    };
    println!(
        "quartic sum {sum} -> {}",
        if eval.captured {
            "captured"
        } else {
            "NOT captured"
        }
    );
    println!("xlim: {}", xlim.source);
    println!(
        "{:<5} {:>11} {:<5} {:>11} {:>12} {:>7}",
        "state", "value", "unit", "xlim", "term", "share"
    );
    for t in &eval.dominant {
        println!(
            "{:<5} {:>11.4e} {:<5} {:>11.4e} {:>12.4e} {:>6.1}%",
            t.state.as_str(),
            t.value,
            t.state.unit(),
            t.xlim,
            t.term,
            100.0 * t.share
        );
    }
    if eval.dominant.is_empty() {
        println!("(all states zero)");
    }
    println!(
        "largest capturable box scale {:.6} (consistency sum {:.6})",
        max_box_scale(xlim),
        consistency_sum(xlim)
    );
    if let Some((p, source)) = prob {
        println!(
            "capture probability {:.6} ({} of {}; 95 % lower bound {:.6}); other states: {}",
            p.probability, p.captured, p.n, p.lower_95, source
        );
    }
}
