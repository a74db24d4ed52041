//! `xylem synth`: unroll a trained NCA into a colour volume and its standard images.

use std::path::PathBuf;

use anyhow::Result;
use clap::Args;
use xylem::device::DeviceKind;
use xylem::nca::config::Engine;
use xylem::pipeline::{SynthStageOptions, synth_into};

use super::progress::CliReporter;

/// Synthesise a solid texture with a trained NCA: the volume, its faces, cuts and cross.
#[derive(Args, Debug)]
#[command(after_help = "Example:
  xylem synth --model out/cn03-nca --steps 90 --out out/cn03-synth

Writes DIR/volume.npy (float32 [N, N, N, 3], RGB; nothing is clamped: models trained with
the shipped configs ([model] readout = \"saturating\") or with \"bounded\" stay inside
[0, 1] by construction, models with readout = \"residual\" near it (BENCHMARKS.md: a few
hundred to a few thousand of 50 M values outside, by up to 0.25); the command prints the
range, how many values fall outside and how many lie within 0.005 of 0 or 1, and warns when
more than 1e-4 of them do: the state ran away and the saturating readout hides it as flat
white or black blotches (README, known limits); axes x, y, z as every xylem volume),
DIR/faces/A.png..F.png,
DIR/cuts/cut1.png, DIR/cuts/cut2.png, DIR/unfolded.png (PNGs clamp colour to [0, 1]; seen
with the fit's grain shading when it has one: end grain darker than side grain, DESIGN
\"Grain shading\"; volume.npy holds the plain colour) and DIR/model.toml (the model's
description). The texture scale is per voxel: a --size other
than the training grid scales pores and rays with it. `xylem export` clamps colour to [0, 1]
and converts it for other tools (.vdb, .vol, .nrrd, a Mitsuba scene).")]
pub struct SynthArgs {
    /// Folder written by `xylem train`.
    #[arg(long)]
    pub model: PathBuf,
    /// Volume side in voxels (default: the training grid).
    #[arg(long, value_parser = super::output_args::side_4_1024)]
    pub size: Option<u32>,
    /// Unroll steps (90, as the Mokume paper's inference).
    #[arg(long, default_value_t = 90, value_parser = clap::builder::RangedU64ValueParser::<usize>::new().range(1..=2048))]
    pub steps: usize,
    /// Seed of the initial state and of the grain-noise realisation (default: the training
    /// seed): another seed gives another draw of the same wood.
    #[arg(long)]
    pub seed: Option<u64>,
    /// Output folder.
    #[arg(long, short = 'o')]
    pub out: PathBuf,
    /// CPU backend of the burn engine (and for loading the weights).
    #[arg(long, default_value = "flex", value_parser = super::output_args::flagged::<DeviceKind>)]
    pub device: DeviceKind,
    /// Unroll with the fused CPU kernels (default) or with burn (the reference, slower).
    #[arg(long, default_value = "fused")]
    pub engine: Engine,
}

pub fn run(args: SynthArgs) -> Result<()> {
    let options = SynthStageOptions {
        size: args.size.map(|s| s as usize),
        steps: args.steps,
        seed: args.seed,
        device: args.device,
        engine: args.engine,
    };
    synth_into(&args.model, &options, &args.out, &CliReporter)?;
    Ok(())
}
