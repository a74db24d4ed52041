//! The trained-model folder written by `xylem train` and read by `xylem synth`:
//! - `model.bpk`: the weights (burnpack, burn's `ModuleRecord`), written atomically;
//! - `model.toml`: what is needed to use them: architecture, normalisation of B and G,
//!   training grid side, seed;
//! - `fit.toml`: the B and G source (see `fit_source`);
//! - `train.toml`, `loss.csv`, `loss.png`, `checkpoint/`: the training record.

use std::path::Path;

use burn::module::Module;
use burn::store::ModuleRecord;
use burn::tensor::{Bytes, Device};
use serde::{Deserialize, Serialize};

use super::conditioning::Normalisation;
use super::config::ModelSpec;
use super::fit_source::{FIT_FILE, FitRecord};
use super::model::Nca;
use crate::config::{Checker, load_toml, write_config_copy};
use crate::error::{Result, XylemError};
use crate::frame::Face;
use crate::io::provenance::content_hash;
use crate::io::{read_bytes, write_bytes_atomic};

pub(crate) const WEIGHTS_FILE: &str = "model.bpk";
pub(crate) const META_FILE: &str = "model.toml";

/// Everything besides the weights that a trained model needs.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ModelMeta {
    pub spec: ModelSpec,
    pub normalisation: Normalisation,
    /// Side of the training grid: one voxel = 4 cm / grid, the scale the texture was learnt at.
    pub grid: usize,
    /// The training seed (synthesis derives its seed state from it unless told otherwise).
    pub seed: u64,
    /// The faces trained on (the others were left out).
    pub faces: Vec<Face>,
    /// Training iterations done.
    pub iterations: usize,
    /// Hash of model.bpk's bytes (`io::provenance::content_hash`), written when training
    /// finishes; loading checks it, so damaged weights are an error, not a wrong volume.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub weights_hash: Option<String>,
}

/// A model ready to unroll.
pub struct TrainedModel {
    pub meta: ModelMeta,
    pub fit: FitRecord,
    pub model: Nca,
}

/// Compares model.bpk's bytes with the hash model.toml recorded (models written before
/// the hash existed have none and are not checked).
fn check_weights_hash(path: &Path, expected: Option<&str>) -> Result<()> {
    let Some(expected) = expected else {
        return Ok(());
    };
    let bytes = read_bytes(path, "a burnpack weights file (model.bpk)")?;
    let actual = content_hash(&bytes);
    if actual != expected {
        return Err(XylemError::input(
            path.display().to_string(),
            format!(
                "content hash {actual} differs from weights_hash = \"{expected}\" in model.toml: \
                 the weights were damaged or replaced; retrain or restore the file"
            ),
        ));
    }
    Ok(())
}

/// Hash of the weights file as written (for [`ModelMeta::weights_hash`]).
pub fn weights_hash(path: &Path) -> Result<String> {
    let bytes = read_bytes(path, "a burnpack weights file (model.bpk)")?;
    Ok(content_hash(&bytes))
}

/// Writes weights atomically as burnpack.
pub fn save_weights(model: &Nca, path: &Path) -> Result<()> {
    let bytes = model
        .clone()
        .into_record()
        .into_bytes()
        .map_err(|e| XylemError::input(path.display().to_string(), format!("{e:?}")))?;
    write_bytes_atomic(path, &bytes)
}

/// Loads weights of the architecture `spec`.
pub fn load_weights(spec: &ModelSpec, path: &Path, device: &Device) -> Result<Nca> {
    let bytes = read_bytes(path, "a burnpack weights file (model.bpk)")?;
    let bad = |e: String| {
        XylemError::input(
            path.display().to_string(),
            format!("not a burnpack model of this architecture: {e}"),
        )
    };
    let record = ModuleRecord::from_bytes(Bytes::from_bytes_vec(bytes))
        .map_err(|e| bad(format!("{e:?}")))?;
    let model = Nca::init(spec, 0, device)
        .try_load_record(record)
        .map_err(|e| bad(format!("{e:?}")))?;
    if !model.matches(spec) {
        return Err(bad(format!(
            "weights are {:?}/{:?}, model.toml asks for hidden {} and {} inputs",
            model.w1.dims(),
            model.w2.dims(),
            spec.hidden,
            spec.inputs()
        )));
    }
    Ok(model)
}

impl ModelMeta {
    pub fn save(&self, dir: &Path) -> Result<()> {
        write_config_copy(&dir.join(META_FILE), self, "xylem train")
    }

    pub fn load(dir: &Path) -> Result<Self> {
        let path = dir.join(META_FILE);
        let meta: ModelMeta = load_toml(&path)?;
        meta.validate(&Checker::new(&path))?;
        Ok(meta)
    }

    /// Every value a synthesis relies on: a grid a volume can have (the training configs'
    /// bounds), a finite, increasing G range and positive, finite white-balance factors (a
    /// zero factor would divide the volume by zero).
    fn validate(&self, check: &Checker) -> Result<()> {
        self.spec.validate(&check.nested("spec"))?;
        check.count("grid", self.grid, 4, 1024, "training grid side")?;
        let n = check.nested("normalisation");
        let [lo, hi] = self.normalisation.g_range;
        if !(lo.is_finite() && hi.is_finite() && hi > lo) {
            return Err(n.error(
                "g_range",
                format!("= [{lo}, {hi}]: expected [low, high], finite, with low < high"),
            ));
        }
        for (c, &w) in self.normalisation.white_balance.iter().enumerate() {
            n.positive(
                &format!("white_balance[{c}]"),
                w,
                1e3,
                "factor from photo to white-balanced colour",
            )?;
        }
        if let Some(p) = &self.normalisation.colour_projection
            && p.iter()
                .flatten()
                .any(|v| !(v.is_finite() && v.abs() <= 1.0))
        {
            return Err(n.error(
                "colour_projection",
                format!("= {p:?}: expected a 3x3 projection, every entry finite in [-1, 1]"),
            ));
        }
        Ok(())
    }
}

impl TrainedModel {
    /// Reads a model folder written by `xylem train`.
    pub fn load(dir: &Path, device: &Device) -> Result<Self> {
        if !dir.join(WEIGHTS_FILE).is_file() {
            return Err(XylemError::input(
                dir.display().to_string(),
                format!("no {WEIGHTS_FILE} here; expected a folder written by `xylem train`"),
            ));
        }
        let meta = ModelMeta::load(dir)?;
        check_weights_hash(&dir.join(WEIGHTS_FILE), meta.weights_hash.as_deref())?;
        let fit = FitRecord::load(&dir.join(FIT_FILE), None)?;
        let model = load_weights(&meta.spec, &dir.join(WEIGHTS_FILE), device)?;
        Ok(Self { meta, fit, model })
    }
}
