//! `xylem demo`: the built-in default job, needing no external data (`xylem::pipeline::demo`):
//! a synthetic sample cube from a species preset (with its hidden truth), then the whole
//! pipeline on it: fit, NCA training with the quick config, synthesis, the sheet of faces and
//! cuts beside the truth, renders, metrics and the HTML report.

use std::path::PathBuf;

use anyhow::Result;
use clap::Args;
use xylem::device::DeviceKind;
use xylem::nca::config::Engine;
use xylem::pipeline::{DemoOptions, RunLayout, demo};

use super::progress::CliReporter;

/// Run the built-in demo: synthetic sample -> fit -> NCA (quick) -> synthesis -> sheet,
/// renders, metrics and report, with no external data.
#[derive(Args, Debug)]
#[command(after_help = "Example:
  xylem demo --out out/demo      # then open out/demo/report/index.html

Writes DIR/sample/ (the synthetic photographed cube, Mokume layout, truth in truth/), and
everything `xylem run` writes: fit/, train/, synth/, unfolded.png (truth | NCA), sheet.png
(faces and cuts: truth, fitted rings, base colour, procedural truth, NCA), renders/,
metrics.csv, timings.csv and report/index.html (titled xylem demo: SPECIES). Re-running
continues where an interrupted demo stopped.")]
pub struct DemoArgs {
    /// Output folder.
    #[arg(long, short = 'o', default_value = "out/demo")]
    pub out: PathBuf,
    /// Species preset of the synthetic sample (oak, chestnut, maple, walnut, softwood, burl).
    #[arg(long, default_value = "chestnut", value_parser = super::presets::species_name)]
    pub species: String,
    /// Face image side of the synthetic sample, in pixels.
    #[arg(long, default_value_t = 256, value_parser = super::output_args::side_16_2048)]
    pub size: u32,
    /// NCA training config (default: the built-in configs/nca/quick.toml).
    #[arg(long)]
    pub nca_config: Option<PathBuf>,
    /// NCA unroll steps of the synthesis.
    #[arg(long, default_value_t = 90, value_parser = clap::builder::RangedU64ValueParser::<usize>::new().range(1..=2048))]
    pub synth_steps: usize,
    /// CPU backend of the NCA's burn parts (optimiser, loss; the whole NCA with --engine burn).
    #[arg(long, default_value = "flex", value_parser = super::output_args::flagged::<DeviceKind>)]
    pub device: DeviceKind,
    /// Synthesis unroll: the fused CPU kernels (default) or burn (the reference). Training
    /// uses the engine of the NCA config (`[compute] engine`, fused by default).
    #[arg(long, default_value = "fused")]
    pub engine: Engine,
}

pub fn run(args: DemoArgs) -> Result<()> {
    let options = DemoOptions {
        species: args.species,
        size: args.size as usize,
        nca_config: args.nca_config,
        synth_steps: args.synth_steps,
        device: args.device,
        engine: args.engine,
    };
    demo(&RunLayout::new(&args.out), &options, &CliReporter)?;
    Ok(())
}
