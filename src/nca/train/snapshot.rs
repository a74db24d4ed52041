//! Training checkpoints for `--resume`: everything an uninterrupted run would still have in
//! memory, so a resumed run continues bit for bit (tested):
//! - `model.bpk`: the weights (with their parameter ids, which key the optimiser state);
//! - `optimiser.bpk`: Adam's moments and step counts;
//! - `pool.npy`: the pool states `[P, C, X, Y, Z]` (empty slots are zeros);
//! - `progress.toml`: the next iteration and each pool slot's region offset (-1: empty);
//! - `loss.csv`: the log so far.
//!
//! The random draws need no saving: iteration i draws from its own stream (see `train`).
//! A checkpoint is written to `checkpoint.tmp/` and then renamed into place, the previous
//! one kept as `checkpoint.old/` until the rename is done, so a kill at any moment leaves a
//! complete checkpoint.

use std::fs;
use std::path::{Path, PathBuf};

use burn::tensor::Bytes;
use serde::{Deserialize, Serialize};

use super::iteration::{Trainer, adam};
use super::loss_log::{LossRow, read_csv, write_csv};
use super::pool::Pool;
use crate::config::{load_toml, write_config_copy};
use crate::error::{Result, XylemError};
use crate::io::npy::{read_npy, write_npy};
use crate::io::write_bytes_atomic;
use crate::nca::model::Nca;
use crate::nca::model_dir::{load_weights, save_weights};
use crate::nca::region::Region;

pub(crate) const SNAPSHOT_DIR: &str = "checkpoint";

#[derive(Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct Progress {
    /// The next iteration to run.
    iteration: usize,
    /// First voxel (x, y, z) of each pool slot's region in the training grid, [-1, -1, -1]
    /// for empty slots.
    pool_offsets: Vec<[i64; 3]>,
    /// Shape of one pool state `[C, X, Y, Z]`.
    state_dims: [usize; 4],
}

fn dirs(root: &Path) -> (PathBuf, PathBuf, PathBuf) {
    (
        root.join(SNAPSHOT_DIR),
        root.join(format!("{SNAPSHOT_DIR}.tmp")),
        root.join(format!("{SNAPSHOT_DIR}.old")),
    )
}

fn io(path: &Path) -> impl FnOnce(std::io::Error) -> XylemError + '_ {
    move |e| XylemError::io(path, e)
}

/// The same burnpack with its tensors' data in name order. burn writes the optimiser's
/// tensors in hash-map order, so two identical trainings wrote different bytes (same
/// tensors, other offsets); in name order the checkpoint is the same file every time.
fn canonical_burnpack(bytes: &[u8]) -> std::result::Result<Vec<u8>, burn::store::burn_pack::Error> {
    use burn::store::burn_pack::{Reader, Writer};
    let reader = Reader::from_bytes(Bytes::from_bytes_vec(bytes.to_vec()))?;
    let metadata = reader.metadata().clone();
    let scalars = reader.scalars().clone();
    let mut tensors = reader.into_tensors()?;
    tensors.sort_by(|a, b| a.name.cmp(&b.name));
    let mut writer = Writer::new(tensors);
    for (key, value) in &metadata {
        writer = writer.with_metadata(key, value);
    }
    for (key, value) in scalars {
        writer = writer.with_scalar(&key, value);
    }
    Ok(writer.into_bytes()?.to_vec())
}

/// Writes the trainer's state and the log into `root/checkpoint/`.
pub fn save(root: &Path, trainer: &Trainer, rows: &[LossRow]) -> Result<()> {
    let (dir, tmp, old) = dirs(root);
    if tmp.exists() {
        fs::remove_dir_all(&tmp).map_err(io(&tmp))?;
    }
    fs::create_dir_all(&tmp).map_err(io(&tmp))?;
    save_weights(&trainer.plain_model(), &tmp.join("model.bpk"))?;
    let state_error = |e: String| XylemError::numeric("optimiser state", e);
    let optimiser = trainer
        .optimiser
        .into_bytes()
        .map_err(|e| state_error(format!("{e:?}")))?;
    let optimiser = canonical_burnpack(&optimiser).map_err(|e| state_error(format!("{e:?}")))?;
    write_bytes_atomic(&tmp.join("optimiser.bpk"), &optimiser)?;
    let slots = trainer.pool.to_data()?;
    let state_dims = trainer.state_dims();
    let per = state_dims.iter().product::<usize>();
    let mut values = vec![0.0f32; slots.len() * per];
    let mut regions = Vec::with_capacity(slots.len());
    for (i, slot) in slots.into_iter().enumerate() {
        match slot {
            Some((region, _, v)) => {
                values[i * per..(i + 1) * per].copy_from_slice(&v);
                regions.push(region.offset.map(|o| o as i64));
            }
            None => regions.push([-1; 3]),
        }
    }
    let mut shape = vec![regions.len()];
    shape.extend(state_dims);
    write_npy(&tmp.join("pool.npy"), &shape, &values)?;
    let progress = Progress {
        iteration: trainer.iteration,
        pool_offsets: regions,
        state_dims,
    };
    write_config_copy(
        &tmp.join("progress.toml"),
        &progress,
        "xylem train checkpoint",
    )?;
    write_csv(&tmp.join("loss.csv"), rows)?;
    if dir.exists() {
        if old.exists() {
            fs::remove_dir_all(&old).map_err(io(&old))?;
        }
        fs::rename(&dir, &old).map_err(io(&dir))?;
    }
    fs::rename(&tmp, &dir).map_err(io(&dir))?;
    if old.exists() {
        fs::remove_dir_all(&old).map_err(io(&old))?;
    }
    Ok(())
}

/// Is there a checkpoint to resume from?
pub fn exists(root: &Path) -> bool {
    let (dir, _, old) = dirs(root);
    dir.join("progress.toml").is_file() || old.join("progress.toml").is_file()
}

/// Checks `progress.toml` against the trainer it is restored into, before anything is
/// read by its values: the iteration within the config's, one pool slot per configured
/// slot, states of the config's shape (a crafted shape would otherwise size the pool).
fn check_progress(progress: &Progress, trainer: &Trainer, path: &Path) -> Result<()> {
    let bad = |message: String| XylemError::input(path.display().to_string(), message);
    let total = trainer.config.schedule.iterations;
    if progress.iteration > total {
        return Err(bad(format!(
            "iteration = {}: expected at most the config's {total} iterations",
            progress.iteration
        )));
    }
    let slots = trainer.config.pool.size;
    if progress.pool_offsets.len() != slots {
        return Err(bad(format!(
            "pool_offsets has {} entries: expected one per pool slot of the config ({slots})",
            progress.pool_offsets.len()
        )));
    }
    let dims = trainer.state_dims();
    if progress.state_dims != dims {
        return Err(bad(format!(
            "state_dims = {:?}: expected {dims:?} (the config's state channels and crop)",
            progress.state_dims
        )));
    }
    Ok(())
}

/// Reads the optimiser state's burnpack container on its own first and checks it against
/// the model's parameters: burn's optimiser panics on a damaged or foreign record (a
/// tensor without a parameter id, a rank it has no code for) instead of returning an
/// error, and a state of another shape would panic at the next training step.
fn check_optimiser_record(bytes: &[u8], model: &Nca, path: &Path) -> Result<()> {
    use burn::store::burn_pack::Reader;
    let bad = |message: String| {
        XylemError::input(
            path.display().to_string(),
            format!("not the optimiser state of this checkpoint's model: {message}"),
        )
    };
    let params: [(u64, Vec<usize>); 3] = [
        (model.w1.id.val(), model.w1.dims().to_vec()),
        (model.b1.id.val(), model.b1.dims().to_vec()),
        (model.w2.id.val(), model.w2.dims().to_vec()),
    ];
    let shape_of = |id: u64| params.iter().find(|(p, _)| *p == id).map(|(_, s)| s);
    let reader = Reader::from_bytes(Bytes::from_bytes_vec(bytes.to_vec()))
        .map_err(|e| bad(format!("{e:?}")))?;
    for (name, value) in reader.scalars() {
        let Some(id) = name.strip_suffix(".__rank") else {
            continue;
        };
        let expected = id.parse::<u64>().ok().and_then(shape_of).map(Vec::len);
        if expected.is_none() || usize::try_from(*value).ok() != expected {
            return Err(bad(format!(
                "{name} = {value:?} is not the rank of a parameter"
            )));
        }
    }
    for tensor in reader.into_tensors().map_err(|e| bad(format!("{e:?}")))? {
        let (name, _, shape, param_id, _) =
            tensor.into_parts().map_err(|e| bad(format!("{e:?}")))?;
        // The loader reads a tensor by its name, "<parameter id>.momentum.moment_N", into a
        // slot of that parameter's rank: the name's parameter must have the tensor's shape
        // too, not only the one its `param_id` field names (a file whose name and field
        // disagree made burn panic on a rank mismatch).
        let by_name = name
            .split('.')
            .next()
            .and_then(|id| id.parse::<u64>().ok())
            .and_then(shape_of);
        let expected = param_id.and_then(shape_of);
        let shape = shape.as_slice();
        if expected.map(Vec::as_slice) != Some(shape) || by_name.map(Vec::as_slice) != Some(shape) {
            return Err(bad(format!(
                "tensor {name:?} of shape {shape:?} belongs to no parameter of that shape"
            )));
        }
    }
    Ok(())
}

/// Restores the trainer from `root/checkpoint/` (or the previous checkpoint if a save was
/// interrupted) and returns the log so far.
pub fn load(root: &Path, trainer: &mut Trainer) -> Result<Vec<LossRow>> {
    let (dir, _, old) = dirs(root);
    let dir = if dir.join("progress.toml").is_file() {
        dir
    } else {
        old
    };
    let progress_path = dir.join("progress.toml");
    let progress: Progress = load_toml(&progress_path)?;
    check_progress(&progress, trainer, &progress_path)?;
    let spec = trainer.config.model.clone();
    trainer.model = load_weights(
        &spec,
        &dir.join("model.bpk"),
        &trainer.kind.autodiff_device(),
    )?;
    let path = dir.join("optimiser.bpk");
    let bytes = crate::io::read_bytes(&path, "the optimiser state of a checkpoint")?;
    check_optimiser_record(&bytes, &trainer.model, &path)?;
    trainer.optimiser = adam()
        .from_bytes(Bytes::from_bytes_vec(bytes))
        .map_err(|e| XylemError::input(path.display().to_string(), format!("{e:?}")))?;
    let pool_path = dir.join("pool.npy");
    let (shape, values) = read_npy(&pool_path)?;
    // check_progress made state_dims the trainer's, so this product is small.
    let per = progress.state_dims.iter().product::<usize>();
    if shape.len() != 5
        || shape[0] != progress.pool_offsets.len()
        || shape[1..] != progress.state_dims
    {
        return Err(XylemError::input(
            pool_path.display().to_string(),
            format!(
                "pool shape {shape:?} does not match progress.toml ({} slots of {:?})",
                progress.pool_offsets.len(),
                progress.state_dims
            ),
        ));
    }
    let grid = trainer.config.volume.size;
    let [_, dx, dy, dz] = progress.state_dims;
    let dims = [dx, dy, dz];
    let mut slots = Vec::with_capacity(progress.pool_offsets.len());
    for (i, offset) in progress.pool_offsets.iter().enumerate() {
        if offset.iter().all(|&o| o < 0) {
            slots.push(None);
            continue;
        }
        let inside = (0..3).all(|a| offset[a] >= 0 && offset[a] as usize + dims[a] <= grid);
        if !inside {
            return Err(XylemError::input(
                dir.join("progress.toml").display().to_string(),
                format!(
                    "pool_offsets[{i}] = {offset:?}: expected a region of {dims:?} voxels inside the {grid}^3 training grid"
                ),
            ));
        }
        let region = Region {
            grid,
            offset: offset.map(|o| o as usize),
            dims,
        };
        slots.push(Some((
            region,
            progress.state_dims,
            values[i * per..(i + 1) * per].to_vec(),
        )));
    }
    trainer.pool = Pool::from_data(slots, trainer.device())?;
    trainer.iteration = progress.iteration;
    let loss_path = dir.join("loss.csv");
    let rows = read_csv(&loss_path)?;
    // A shorter log would leave a gap in the final loss.csv.
    if rows.len() < progress.iteration {
        return Err(XylemError::input(
            loss_path.display().to_string(),
            format!(
                "has {} rows, but the checkpoint is at iteration {}: the checkpoint is damaged; \
                 start the training again",
                rows.len(),
                progress.iteration
            ),
        ));
    }
    Ok(rows)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::device::DeviceKind;
    use crate::nca::config::ModelSpec;
    use burn::store::burn_pack::{DType, Scalar, Tensor as PackTensor, Writer};

    /// A moment tensor stored under the bias b1's name but with the shape and `param_id` of
    /// the weight w2: the loader would read it into b1's rank-1 slot and burn panicked on the
    /// rank (found by the reliability fuzz); the check refuses it instead.
    #[test]
    fn a_moment_named_for_one_parameter_but_shaped_like_another_is_refused() {
        let device = DeviceKind::Flex.device();
        let model = Nca::init(&ModelSpec::default(), 1, &device);
        let (b1, w2) = (model.b1.id.val(), model.w2.id.val());
        let shape = model.w2.dims().to_vec();
        let bytes = vec![0u8; 4 * shape.iter().product::<usize>()];
        let moment = PackTensor::new(
            format!("{b1}.momentum.moment_1"),
            DType::F32,
            shape,
            Some(w2),
            Bytes::from_bytes_vec(bytes),
        );
        let file = Writer::new(vec![moment])
            .with_scalar(&format!("{b1}.__rank"), Scalar::UInt(1))
            .into_bytes()
            .unwrap();
        let err = check_optimiser_record(&file, &model, Path::new("optimiser.bpk")).unwrap_err();
        assert!(err.to_string().contains("belongs to no parameter"), "{err}");
    }
}
