//! `xylem train`: train the NCA on a sample's faces, conditioned on its fit.

use std::path::PathBuf;

use anyhow::{Result, bail};
use clap::Args;
use xylem::device::DeviceKind;
use xylem::pipeline::{TrainStageOptions, TrainStart, train_into};
use xylem::sample::faces_or_all;

use super::json_out::{Summary, say};
use super::progress::CliReporter;

/// Train the 3D neural cellular automaton on the six (or fewer) face photos of a sample.
#[derive(Args, Debug)]
#[command(after_help = "Examples:
  xylem train --sample ../shared/data/mokume/CN03 --fit fit.toml \\
      --config configs/nca/quick.toml --out out/cn03-nca
  xylem train --sample S --fit fit.toml --config configs/nca/default.toml --out OUT --faces A,B,C,D,E
  xylem train --sample S --out OUT --resume        # continue a killed run

--fit: the growth field and base colour: the fit.toml written by `xylem fit` (or the folder
holding it); also accepted, for tests and ablations, a field config (configs/fields/*.toml;
base colour = a ring ramp in the photos' colours).

The face loss is the VGG-free style loss ([loss] face = \"style\", its settings in [loss.style],
default configs/loss/default.toml); face = \"moments\" selects the cheap moment baseline.

Writes OUT/model.bpk, OUT/model.toml, OUT/fit.toml, OUT/train.toml (the config used),
OUT/loss.csv, OUT/loss.png, and OUT/checkpoint/ every few minutes (checkpoint.minutes).")]
pub struct TrainArgs {
    /// Sample folder (A_col.png .. F_col.png).
    #[arg(long)]
    pub sample: PathBuf,
    /// The fit giving B and G (see below). Not needed with --resume.
    #[arg(long)]
    pub fit: Option<PathBuf>,
    /// Training config (TOML, see configs/nca/). Not needed with --resume.
    #[arg(long)]
    pub config: Option<PathBuf>,
    /// Output folder (the trained model).
    #[arg(long, short = 'o')]
    pub out: PathBuf,
    /// CPU backend.
    #[arg(long, default_value = "flex", value_parser = super::output_args::flagged::<DeviceKind>)]
    pub device: DeviceKind,
    /// Continue the run in --out from its last checkpoint (its own train.toml and fit.toml).
    #[arg(long)]
    pub resume: bool,
    /// Faces to train on, e.g. A,B,C,D,E to leave F out (default: all six).
    #[arg(long)]
    pub faces: Option<String>,
    /// Stop after this many iterations without finishing, as if killed (for testing --resume).
    #[arg(long, hide = true)]
    pub stop_after: Option<usize>,
}

pub fn run(args: TrainArgs) -> Result<()> {
    let options = TrainStageOptions {
        sample: &args.sample,
        start: start(&args)?,
        device: args.device,
        stop_after: args.stop_after,
    };
    let summary = train_into(&options, &args.out, &CliReporter)?;
    if !summary.finished {
        say(&format!(
            "stopped after {} iterations; continue with --resume",
            summary.iterations
        ));
    }
    Summary::new("train")
        .text("out", &args.out.display().to_string())
        .integer("iterations", summary.iterations as u64)
        .flag("finished", summary.finished)
        .number("last_loss", summary.last_loss)
        .number("seconds", summary.seconds)
        .emit();
    Ok(())
}

/// A fresh run needs --config and --fit; --resume takes the run's own and refuses them.
fn start(args: &TrainArgs) -> Result<TrainStart> {
    if args.resume {
        if !xylem::nca::train::snapshot::exists(&args.out) {
            bail!(
                "--resume: {} holds no checkpoint of a training run (expected {}/checkpoint/)",
                args.out.display(),
                args.out.display()
            );
        }
        if args.config.is_some() || args.fit.is_some() || args.faces.is_some() {
            bail!(
                "--resume continues with the run's own train.toml, fit.toml and faces; drop --config, --fit and --faces"
            );
        }
        return Ok(TrainStart::Resume);
    }
    let Some(config) = args.config.clone() else {
        bail!("--config is required (e.g. configs/nca/quick.toml)");
    };
    let Some(fit) = args.fit.clone() else {
        bail!("--fit is required (a field config or fit file; see --help)");
    };
    Ok(TrainStart::Fresh {
        fit,
        config,
        faces: faces_or_all(args.faces.as_deref())?,
    })
}
