//! The training stage: the NCA trained on a sample's faces, conditioned on its fit, into one
//! folder that can be resumed after a kill (`xylem train`, and `train/` of a run).

use std::path::{Path, PathBuf};
use std::time::Instant;

use super::reporter::Reporter;
use crate::Result;
use crate::config::ConfigFile;
use crate::device::DeviceKind;
use crate::frame::Face;
use crate::image2::Image2;
use crate::io::{OutputDir, Provenance};
use crate::nca::TrainConfig;
use crate::nca::face_loss;
use crate::nca::fit_source::{FIT_FILE, FitRecord, load_fit};
use crate::nca::model_dir::ModelMeta;
use crate::nca::train::TrainData;
use crate::nca::train::session::{TrainOptions, run_training, saved_config};
use crate::nca::train::targets::photo_mean;
use crate::nca::train::vessel_gate::apply_vessel_gate;
use crate::sample::{Needs, Sample};

/// A fresh training or the continuation of the folder's own.
#[derive(Clone, Debug)]
pub enum TrainStart {
    Fresh {
        /// The fit giving B and G: a `fit.toml` (or its folder), or a field config.
        fit: PathBuf,
        /// The training config (TOML).
        config: PathBuf,
        /// The faces trained on.
        faces: Vec<Face>,
    },
    /// From the folder's last checkpoint, with its own config, fit and faces.
    Resume,
}

/// What to train.
#[derive(Clone, Debug)]
pub struct TrainStageOptions<'a> {
    /// The sample folder (its photos are the targets).
    pub sample: &'a Path,
    pub start: TrainStart,
    /// CPU backend of burn's parts.
    pub device: DeviceKind,
    /// Stop after this many iterations without finishing, as if killed (tests of resume).
    pub stop_after: Option<usize>,
}

/// How the stage ended.
#[derive(Clone, Debug)]
pub struct TrainSummary {
    pub iterations: usize,
    /// The schedule ran to its end and the final model is written.
    pub finished: bool,
    pub last_loss: f64,
    pub seconds: f64,
}

/// The photos a training uses (`OUT/sample.toml`: the sample folder and a hash of its files).
/// A fresh run records them; a resumed one must be given the same photos, or the rest of the
/// training would learn other wood under the same model.
const SAMPLE_RECORD: &str = "sample.toml";

/// Trains into `out` (model.bpk, model.toml, fit.toml, train.toml, loss.csv, loss.png,
/// checkpoint/), showing the loss as it goes.
pub fn train_into(
    options: &TrainStageOptions,
    out: &Path,
    reporter: &dyn Reporter,
) -> Result<TrainSummary> {
    let resume = matches!(options.start, TrainStart::Resume);
    let dir = OutputDir::prepare(out)?;
    let (mut config, source, faces) = match &options.start {
        TrainStart::Resume => (
            saved_config(dir.root())?,
            "the resumed run's train.toml".to_string(),
            ModelMeta::load(dir.root())?.faces,
        ),
        TrainStart::Fresh { config, faces, .. } => (
            TrainConfig::load(config)?,
            config.display().to_string(),
            faces.clone(),
        ),
    };
    let needs = Needs {
        photos: true,
        arl: false,
    };
    let sample = Sample::load(options.sample, &faces, needs)?;
    check_sample_record(options.sample, &dir, resume)?;
    let fit = match &options.start {
        TrainStart::Resume => FitRecord::load(&dir.path(FIT_FILE), None)?,
        // A fresh fit's ramp colours (field configs) need the photos' mean colour.
        TrainStart::Fresh { fit, .. } => load_fit(fit, photo_mean(&sample))?,
    };
    if !resume {
        // A resumed run's train.toml already holds what the gate chose (channel, guide weight).
        let photos: Vec<&Image2> = sample.photos.iter().flatten().collect();
        if let Some(closed) = apply_vessel_gate(&mut config, &photos) {
            let guide = closed.guide_weight.map_or(String::new(), |w| {
                format!(" and the ring-phase guide weight {w} (loss.guided.guide_weight_without_vessels)")
            });
            let noise = if closed.fibre_lines {
                "with the grain_noise channel as fibre lines \
                 (model.grain_noise.without_vessels)"
            } else {
                "without the grain_noise channel"
            };
            reporter.note(&format!(
                "the photos show few vessels ({:.1} % of pixels, below \
                 model.grain_noise.min_vessel_fraction = {:.1} %): training {noise}{guide} \
                 (train.toml records the settings used)",
                100.0 * closed.vessel_fraction,
                100.0 * closed.min_vessel_fraction
            ));
        }
    }
    let data = TrainData::prepare(&sample, fit, &config);
    let loss = face_loss(&config, &data, &options.device.device())?;
    let bar = reporter.counter("train", config.schedule.iterations as u64);
    let started = Instant::now();
    let train_options = TrainOptions {
        resume,
        stop_after: options.stop_after,
    };
    let mut first = true;
    let outcome = run_training(
        &dir,
        &config,
        &source,
        &data,
        options.device,
        loss.as_ref(),
        &train_options,
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
    .map_err(|e| e.during(format!("training into {}", out.display())))?;
    bar.finish();
    if outcome.skipped() > 0 {
        reporter.note(&format!(
            "{} of {} iterations had a non-finite loss; their updates were skipped and their \
             pool states reseeded (loss.csv shows them as inf or NaN)",
            outcome.skipped(),
            outcome.iterations
        ));
    }
    let runaways = outcome.runaways(&config.pool);
    if runaways > 0 {
        reporter.note(&format!(
            "{runaways} of {} unrolls ran away (overflow above pool.reseed_overflow = {}); \
             they were not stored back in the pool, their slots restart from fresh seeds",
            outcome.iterations, config.pool.reseed_overflow
        ));
    }
    if outcome.finished {
        reporter.say(&format!(
            "trained {} iterations; model in {} (model.bpk, loss.png)",
            outcome.iterations,
            out.display()
        ));
    }
    Ok(TrainSummary {
        iterations: outcome.iterations,
        finished: outcome.finished,
        last_loss: outcome.rows.last().map_or(f64::NAN, |r| f64::from(r.loss)),
        seconds: started.elapsed().as_secs_f64(),
    })
}

fn check_sample_record(sample: &Path, out: &OutputDir, resume: bool) -> Result<()> {
    let record = Provenance::default().with_folder("sample", sample)?;
    let path = out.path(SAMPLE_RECORD);
    if !resume {
        let _ = std::fs::remove_file(&path); // a fresh run replaces the record
    }
    record.check_or_record(&path, resume)
}
