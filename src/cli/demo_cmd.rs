//! `xylem demo`: the built-in default job, needing no external data: a synthetic sample cube
//! from a species preset (with its hidden truth), then the whole pipeline on it (`xylem run`):
//! fit, NCA training with the quick config, synthesis, the sheet of faces and cuts beside
//! the truth, renders, metrics and the HTML report.

use std::path::PathBuf;

use anyhow::{Context, Result};
use clap::Args;
use xylem::device::DeviceKind;
use xylem::io::OutputDir;
use xylem::nca::config::Engine;
use xylem::presets::load_species_preset;
use xylem::procedural::write_sample;
use xylem::rings::RingSource;

use super::run_cmd::{self, NcaPreset, RunArgs};

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
    #[arg(long, default_value = "flex")]
    pub device: DeviceKind,
    /// Synthesis unroll: the fused CPU kernels (default) or burn (the reference). Training
    /// uses the engine of the NCA config (`[compute] engine`, fused by default).
    #[arg(long, default_value = "fused")]
    pub engine: Engine,
}

pub fn run(args: DemoArgs) -> Result<()> {
    let out = OutputDir::prepare(&args.out)?;
    let sample = out.path("sample");
    if !sample.join("truth/species.toml").is_file() {
        eprintln!("== sample ({})", args.species);
        let cfg = load_species_preset(&args.species)?;
        let origin = format!("built-in species preset {}", args.species);
        write_sample(
            &cfg,
            &origin,
            args.size as usize,
            &OutputDir::prepare(&sample)?,
        )
        .with_context(|| format!("writing the synthetic sample of {origin}"))?;
    }
    run_cmd::run(RunArgs {
        sample,
        out: args.out,
        faces: None,
        nca_config: args.nca_config,
        nca_preset: NcaPreset::Quick,
        fit_config: None,
        rings: RingSource::Auto,
        species: args.species,
        synth_steps: args.synth_steps,
        image_size: 160,
        device: args.device,
        engine: args.engine,
    })
}
