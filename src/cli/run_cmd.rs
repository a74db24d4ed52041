//! `xylem run`: the whole pipeline on one sample folder (`xylem::pipeline::run`): fit -> NCA
//! training -> synthesis -> comparison sheet, renders, metrics -> HTML report, all inside one
//! run folder; re-running the same command continues a killed run.

use std::path::PathBuf;

use anyhow::Result;
use clap::Args;
use xylem::device::DeviceKind;
use xylem::nca::config::Engine;
use xylem::pipeline::{NcaSource, RunLayout, RunOptions, RunOutcome, run as run_pipeline};
use xylem::rings::RingSource;
use xylem::sample::faces_or_all;

use super::json_out::Summary;
use super::presets::NcaPresetArg;
use super::progress::CliReporter;

/// Run the whole pipeline on a sample folder and write a report.
#[derive(Args, Debug, Clone)]
#[command(after_help = "Examples:
  xylem run --sample ../shared/data/mokume/CN03 --out out/cn03
  xylem run --sample ../shared/data/mokume/H11 --out out/h11-noC --faces A,B,D,E,F

Writes into RUN: fit/ (xylem fit), train/ (xylem train), synth/ (xylem synth), sheet.png
(rows: faces A-F, cut1, cut2; columns: photo or truth, fitted rings, base colour,
procedural, NCA), renders/, metrics.csv, phase.csv, timings.csv (time and peak memory per
stage) and report/index.html. Re-running the same command skips finished steps and resumes
an interrupted training; RUN/run.toml records the sample (with a hash of its files), faces,
configs and options, and a call with other ones is refused with the differences named (use
another --out).")]
pub struct RunArgs {
    /// Sample folder (Mokume layout; a `truth/` folder, as `xylem sample` writes, adds the
    /// true cuts to the sheet and the metrics).
    #[arg(long)]
    pub sample: PathBuf,
    /// Run folder.
    #[arg(long, short = 'o')]
    pub out: PathBuf,
    /// Faces to fit and train on (leave-one-face-out), e.g. A,B,C,D,E; default all six.
    #[arg(long)]
    pub faces: Option<String>,
    /// NCA training config (default: the built-in config named by --nca-preset).
    #[arg(long)]
    pub nca_config: Option<PathBuf>,
    /// Built-in NCA config used when --nca-config is not given.
    #[arg(long, default_value = "quality")]
    pub nca_preset: NcaPresetArg,
    /// Fit config (default: the built-in defaults).
    #[arg(long)]
    pub fit_config: Option<PathBuf>,
    /// Ring images for the fit: auto (the folder's where present, predicted from the photos
    /// elsewhere, so six photos are enough), given, or predict (see `xylem rings`).
    #[arg(long, default_value = "auto", value_name = "SOURCE", value_parser = super::output_args::ring_source)]
    pub rings: RingSource,
    /// Species preset shown on the fitted field in the sheet's procedural column when the fit
    /// wrote no procedural.toml (its `[procedural] presets = []`); by default the fit chooses
    /// and fits a preset itself (inverse procedural), and a synthetic sample shows its truth.
    #[arg(long, default_value = "chestnut", value_parser = super::presets::species_name)]
    pub species: String,
    /// NCA unroll steps of the synthesis (90, as the Mokume paper's inference).
    #[arg(long, default_value_t = 90, value_parser = clap::builder::RangedU64ValueParser::<usize>::new().range(1..=2048))]
    pub synth_steps: usize,
    /// Tile size of the sheet and side of the renders, in pixels.
    #[arg(long, default_value_t = 160, value_parser = super::output_args::image_side_16_2048)]
    pub image_size: usize,
    /// CPU backend of the NCA's burn parts (optimiser, loss; the whole NCA with --engine burn).
    #[arg(long, default_value = "flex", value_parser = super::output_args::flagged::<DeviceKind>)]
    pub device: DeviceKind,
    /// Synthesis unroll: the fused CPU kernels (default) or burn (the reference). Training
    /// uses the engine of the NCA config (`[compute] engine`, fused by default).
    #[arg(long, default_value = "fused")]
    pub engine: Engine,
}

pub fn run(args: RunArgs) -> Result<()> {
    let options = RunOptions {
        sample: args.sample.clone(),
        faces: faces_or_all(args.faces.as_deref())?,
        nca: match &args.nca_config {
            Some(path) => NcaSource::File(path.clone()),
            None => NcaSource::Preset(args.nca_preset.into()),
        },
        fit_config: args.fit_config.clone(),
        rings: args.rings,
        species: args.species.clone(),
        synth_steps: args.synth_steps,
        image_size: args.image_size,
        device: args.device,
        engine: args.engine,
    };
    let layout = RunLayout::new(&args.out);
    let outcome = run_pipeline(&layout, &options, &CliReporter)?;
    run_summary(&layout, &options, &outcome).emit();
    Ok(())
}

/// `--json`: the run folder, its stages' cost and the NCA's metrics per reference image.
fn run_summary(layout: &RunLayout, options: &RunOptions, outcome: &RunOutcome) -> Summary {
    let stages: Vec<String> = outcome
        .timings
        .stages
        .iter()
        .map(|t| {
            Summary::new_object()
                .text("stage", &t.stage)
                .number("seconds", t.seconds)
                .number("peak_mb", t.peak_mb.unwrap_or(f64::NAN))
                .flag("skipped", t.skipped)
                .to_json()
        })
        .collect();
    let table = &outcome.metrics;
    let nca_rows: Vec<String> = table
        .rows
        .iter()
        .filter(|row| row.first().is_some_and(|m| m == "nca"))
        .map(|row| {
            let mut object = Summary::new_object();
            for (key, value) in table.header.iter().zip(row).skip(1) {
                object = match value.parse::<f64>() {
                    Ok(v) => object.number(key, v),
                    Err(_) => object.text(key, value),
                };
            }
            object.to_json()
        })
        .collect();
    Summary::new("run")
        .text("sample", &options.sample.display().to_string())
        .text("out", &layout.root().display().to_string())
        .text("report", &layout.report_page().display().to_string())
        .raw("stages", format!("[{}]", stages.join(", ")))
        .raw("nca_metrics", format!("[{}]", nca_rows.join(", ")))
}
