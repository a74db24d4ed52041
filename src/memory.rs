//! Memory estimates, checked before a long job starts so that a size the machine cannot
//! hold ends in an error that says how much it needs, instead of an abort hours later.
//!
//! The per-voxel figures are measured (BENCHMARKS.md): training keeps about 1.5 kB per
//! crop voxel and unroll step on the autodiff tape (32^3 x 19 steps: 878 MB; 64^3 with
//! segments of 6 steps: 2.29 GB); synthesis about 130 bytes per voxel (the state twice,
//! conditioning and the colour volume; 256^3 peaked at 2.19 GB with the rest of `xylem run`).

use crate::error::{Result, XylemError};

/// Bytes on the tape per crop voxel and recorded step.
const TRAIN_BYTES_PER_VOXEL_STEP: f64 = 1500.0;
/// Bytes per voxel of a synthesis.
const SYNTH_BYTES_PER_VOXEL: f64 = 130.0;
/// Share of the machine's memory a job may plan to use.
const BUDGET_SHARE: f64 = 0.8;
/// Assumed when the machine's memory cannot be read.
const FALLBACK_BYTES: f64 = 16.0 * GB;
const GB: f64 = 1024.0 * 1024.0 * 1024.0;

/// Estimated peak bytes of training on `crop`^3 crops with `tape_steps` steps recorded
/// at once (the whole unroll, or one segment).
pub(crate) fn training_bytes(crop: usize, tape_steps: usize) -> f64 {
    (crop as f64).powi(3) * tape_steps as f64 * TRAIN_BYTES_PER_VOXEL_STEP
}

/// Estimated peak bytes of synthesising a `size`^3 volume.
pub(crate) fn synthesis_bytes(size: usize) -> f64 {
    (size as f64).powi(3) * SYNTH_BYTES_PER_VOXEL
}

/// Total memory of this machine (Linux `/proc/meminfo`), if readable.
pub(crate) fn machine_bytes() -> Option<f64> {
    let text = std::fs::read_to_string("/proc/meminfo").ok()?;
    let line = text.lines().find(|l| l.starts_with("MemTotal:"))?;
    let kb: f64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb * 1024.0)
}

/// Fails when `needed` bytes exceed the share of this machine's memory a job may use,
/// naming `what`, the estimate, the machine's memory and `lower` (how to ask for less).
pub(crate) fn check_fits(what: &str, needed: f64, lower: &str) -> Result<()> {
    let total = machine_bytes().unwrap_or(FALLBACK_BYTES);
    if needed <= BUDGET_SHARE * total {
        return Ok(());
    }
    Err(XylemError::input(
        what,
        format!(
            "needs ~{:.1} GB, this machine has {:.1} GB; {lower}",
            needed / GB,
            total / GB
        ),
    ))
}

/// Resets this process's peak resident memory (Linux `VmHWM`) to the current resident
/// size, so that [`peak_resident_bytes`] afterwards measures one stage of a job, not the
/// whole process. `None` where the kernel does not offer it (no `/proc`, not permitted).
pub fn reset_peak_resident() -> Option<()> {
    std::fs::write("/proc/self/clear_refs", "5").ok()
}

/// The peak resident memory of this process since it started or since the last
/// [`reset_peak_resident`], in bytes (Linux `VmHWM`); `None` where it cannot be read.
pub fn peak_resident_bytes() -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kb: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb * 1024)
}
