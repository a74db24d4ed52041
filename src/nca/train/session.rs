//! A whole training run into a model folder: the files of `model_dir`, checkpoints every few
//! minutes (and every `checkpoint.every` iterations if set), and `--resume`.
//!
//! A resumed run restores the last checkpoint and redoes the iterations after it; since
//! every draw is a function of (seed, iteration) and the checkpoint holds the weights,
//! optimiser moments and pool, the result is the same as an uninterrupted run
//! (`tests/nca_train.rs` compares the loss logs and the weights byte for byte).

use std::path::Path;
use std::time::Instant;

use super::iteration::{TrainData, Trainer, check_data};
use super::loss::FaceLoss;
use super::loss_log::{LossRow, write_csv};
use super::plot::loss_plot;
use super::snapshot;
use crate::config::ConfigFile;
use crate::config::write_config_copy;
use crate::device::DeviceKind;
use crate::error::{Result, XylemError};
use crate::io::{OutputDir, save_png};
use crate::nca::config::{PoolConfig, TrainConfig};
use crate::nca::fit_source::FIT_FILE;
use crate::nca::model_dir::{ModelMeta, WEIGHTS_FILE, save_weights, weights_hash};

pub(crate) const CONFIG_FILE: &str = "train.toml";
pub(crate) const LOSS_FILE: &str = "loss.csv";
pub(crate) const PLOT_FILE: &str = "loss.png";

/// How to run.
#[derive(Clone, Debug, Default)]
pub struct TrainOptions {
    /// Continue from the folder's last checkpoint.
    pub resume: bool,
    /// Stop (without a final checkpoint, as if killed) once this many iterations are done.
    pub stop_after: Option<usize>,
}

/// Iterations in a row whose loss may be non-finite before the run stops: one such
/// iteration is skipped (no update, its pool slot reseeded, see `Trainer::iterate`); a
/// rule whose every unroll overflows has diverged, and more iterations cannot mend it.
pub const MAX_NON_FINITE_IN_A_ROW: usize = 8;

/// How a run ended.
#[derive(Clone, Debug)]
pub struct TrainOutcome {
    pub iterations: usize,
    /// The run reached `schedule.iterations` and wrote the final model.
    pub finished: bool,
    pub rows: Vec<LossRow>,
}

impl TrainOutcome {
    /// Iterations whose loss was not finite (their updates were skipped).
    pub fn skipped(&self) -> usize {
        self.rows.iter().filter(|r| !r.loss.is_finite()).count()
    }

    /// Iterations whose state ran away (finite, [`PoolConfig::ran_away`]): updated, but
    /// their pool slot reseeded.
    pub fn runaways(&self, pool: &PoolConfig) -> usize {
        self.rows
            .iter()
            .filter(|r| r.loss.is_finite() && pool.ran_away(r.overflow))
            .count()
    }
}

/// Stops the run once the last [`MAX_NON_FINITE_IN_A_ROW`] rows all have a non-finite loss.
fn check_divergence(rows: &[LossRow]) -> Result<()> {
    let recent = rows.iter().rev().take(MAX_NON_FINITE_IN_A_ROW);
    if rows.len() < MAX_NON_FINITE_IN_A_ROW || recent.clone().any(|r| r.loss.is_finite()) {
        return Ok(());
    }
    let last = &rows[rows.len() - 1];
    Err(XylemError::numeric(
        "nca training",
        format!(
            "the loss was not finite ({}) for {MAX_NON_FINITE_IN_A_ROW} iterations in a row, \
             the last at iteration {}: the rule has diverged (lower schedule.learning_rate \
             or raise loss.overflow)",
            last.loss, last.iteration
        ),
    ))
}

/// Trains into `out`, calling `on_iteration` after each iteration (for progress display).
/// Denormal floats are flushed to zero from here on in this process (see
/// [`flush_denormals_to_zero`](crate::nca::denormals::flush_denormals_to_zero)).
#[allow(clippy::too_many_arguments)]
pub fn run_training(
    out: &OutputDir,
    config: &TrainConfig,
    config_source: &str,
    data: &TrainData,
    kind: DeviceKind,
    loss: &dyn FaceLoss,
    options: &TrainOptions,
    on_iteration: &mut dyn FnMut(&LossRow),
) -> Result<TrainOutcome> {
    check_data(data)?;
    crate::nca::denormals::flush_denormals_to_zero();
    let root = out.root();
    let mut trainer = Trainer::new(config, data, kind)?;
    let meta = |iterations, weights_hash| ModelMeta {
        spec: config.model.clone(),
        normalisation: data.normalisation.clone(),
        grid: config.volume.size,
        seed: config.seed,
        faces: data.faces.clone(),
        iterations,
        weights_hash,
    };
    let mut rows = if options.resume {
        if !snapshot::exists(root) {
            return Err(XylemError::input(
                root.display().to_string(),
                "$resume: no checkpoint in this folder (expected checkpoint/progress.toml)",
            ));
        }
        snapshot::load(root, &mut trainer)?
    } else {
        if snapshot::exists(root) || root.join(WEIGHTS_FILE).exists() {
            return Err(XylemError::input(
                root.display().to_string(),
                "already holds a training run; pass $resume to continue it or choose a new $out",
            ));
        }
        write_config_copy(&out.path(CONFIG_FILE), config, config_source)?;
        data.fit
            .save(&out.path(FIT_FILE), "the fit given to xylem train")?;
        meta(0, None).save(root)?;
        Vec::new()
    };
    rows.truncate(trainer.iteration);
    let total = config.schedule.iterations;
    let interval = config.checkpoint.minutes as f64 * 60.0;
    let mut last_save = Instant::now();
    while trainer.iteration < total {
        if options.stop_after.is_some_and(|n| trainer.iteration >= n) {
            return Ok(TrainOutcome {
                iterations: trainer.iteration,
                finished: false,
                rows,
            });
        }
        let row = trainer.iterate(loss)?;
        on_iteration(&row);
        rows.push(row);
        check_divergence(&rows)?;
        let every = config.checkpoint.every;
        let due_by_count = every > 0 && trainer.iteration % every == 0;
        if due_by_count || last_save.elapsed().as_secs_f64() >= interval {
            snapshot::save(root, &trainer, &rows)?;
            write_csv(&out.path(LOSS_FILE), &rows)?;
            last_save = Instant::now();
        }
    }
    snapshot::save(root, &trainer, &rows)?;
    save_weights(&trainer.plain_model(), &out.path(WEIGHTS_FILE))?;
    let hash = weights_hash(&out.path(WEIGHTS_FILE))?;
    meta(trainer.iteration, Some(hash)).save(root)?;
    write_csv(&out.path(LOSS_FILE), &rows)?;
    let losses: Vec<f32> = rows.iter().map(|r| r.loss).collect();
    save_png(&loss_plot(&losses, 480, 240), &out.path(PLOT_FILE))?;
    Ok(TrainOutcome {
        iterations: trainer.iteration,
        finished: true,
        rows,
    })
}

/// The config a model folder was trained with (for `--resume`).
pub(crate) fn saved_config(root: &Path) -> Result<TrainConfig> {
    TrainConfig::load(&root.join(CONFIG_FILE))
}
