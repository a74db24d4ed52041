//! `xylem train`: train the NCA on a sample's faces, conditioned on its fit.

use std::path::PathBuf;

use anyhow::{Context, Result, bail};
use clap::Args;
use xylem::device::DeviceKind;
use xylem::io::{OutputDir, Provenance};
use xylem::nca::TrainConfig;
use xylem::nca::face_loss;
use xylem::nca::fit_source::{FIT_FILE, FitRecord, load_fit};
use xylem::nca::model_dir::ModelMeta;
use xylem::nca::session::{TrainOptions, run_training, saved_config};
use xylem::nca::targets::photo_mean;
use xylem::nca::train::TrainData;
use xylem::sample::{Needs, Sample, faces_or_all};

use super::json_out::{Summary, say};
use super::progress::Progress;

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
    #[arg(long, default_value = "flex")]
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

/// The photos a training uses (`OUT/sample.toml`: the sample folder and a hash of its files).
/// A fresh run records them; `--resume` must be given the same photos, or the rest of the
/// training would learn other wood under the same model.
const SAMPLE_RECORD: &str = "sample.toml";

fn check_sample_record(args: &TrainArgs, out: &OutputDir) -> Result<()> {
    let record = Provenance::default().with_folder("sample", &args.sample)?;
    let path = out.path(SAMPLE_RECORD);
    if !args.resume {
        let _ = std::fs::remove_file(&path); // a fresh run replaces the record
    }
    record.check_or_record(&path, args.resume)?;
    Ok(())
}

pub fn run(args: TrainArgs) -> Result<()> {
    if args.resume && !xylem::nca::snapshot::exists(&args.out) {
        bail!(
            "--resume: {} holds no checkpoint of a training run (expected {}/checkpoint/)",
            args.out.display(),
            args.out.display()
        );
    }
    xylem::nca::denormals::flush_denormals_to_zero();
    let out = OutputDir::prepare(&args.out)?;
    let (config, source, fit, faces) = if args.resume {
        if args.config.is_some() || args.fit.is_some() || args.faces.is_some() {
            bail!(
                "--resume continues with the run's own train.toml, fit.toml and faces; drop --config, --fit and --faces"
            );
        }
        let meta = ModelMeta::load(out.root())?;
        let fit = FitRecord::load(&out.path(FIT_FILE), None)?;
        let config = saved_config(out.root())?;
        (
            config,
            "the resumed run's train.toml".to_string(),
            Some(fit),
            meta.faces,
        )
    } else {
        let Some(path) = &args.config else {
            bail!("--config is required (e.g. configs/nca/quick.toml)");
        };
        if args.fit.is_none() {
            bail!("--fit is required (a field config or fit file; see --help)");
        }
        let faces = faces_or_all(args.faces.as_deref())?;
        (
            TrainConfig::load(path)?,
            path.display().to_string(),
            None,
            faces,
        )
    };
    let needs = Needs {
        photos: true,
        arl: false,
    };
    let sample = Sample::load(&args.sample, &faces, needs)?;
    check_sample_record(&args, &out)?;
    let fit = match fit {
        Some(f) => f,
        None => {
            let fit_path = args.fit.as_ref().expect("checked above");
            load_fit(fit_path, photo_mean(&sample))?
        }
    };
    let data = TrainData::prepare(&sample, fit, &config);
    let loss = face_loss(&config, &data, &args.device.device())?;
    let total = config.schedule.iterations as u64;
    let bar = Progress::new("train", total);
    let started = std::time::Instant::now();
    let options = TrainOptions {
        resume: args.resume,
        stop_after: args.stop_after,
    };
    let mut first = true;
    let outcome = run_training(
        &out,
        &config,
        &source,
        &data,
        args.device,
        loss.as_ref(),
        &options,
        &mut |row| {
            if first {
                bar.set_position(row.iteration as u64);
                bar.reset_eta();
                first = false;
            }
            bar.set_message(format!("loss {:.4}", row.loss));
            bar.set_position(row.iteration as u64 + 1);
        },
    )
    .with_context(|| format!("training into {}", args.out.display()))?;
    bar.finish();
    if outcome.finished {
        say(&format!(
            "trained {} iterations; model in {} (model.bpk, loss.png)",
            outcome.iterations,
            args.out.display()
        ));
    } else {
        say(&format!(
            "stopped after {} iterations; continue with --resume",
            outcome.iterations
        ));
    }
    let last_loss = outcome.rows.last().map_or(f64::NAN, |r| f64::from(r.loss));
    Summary::new("train")
        .text("out", &args.out.display().to_string())
        .integer("iterations", outcome.iterations as u64)
        .flag("finished", outcome.finished)
        .number("last_loss", last_loss)
        .number("seconds", started.elapsed().as_secs_f64())
        .emit();
    Ok(())
}
