//! `xylem run`: the whole pipeline on one sample folder: fit -> NCA training -> synthesis ->
//! comparison sheet, renders, metrics -> HTML report, all inside one run folder. Steps whose
//! outputs exist are skipped and an interrupted training resumes, so re-running the same
//! command continues a killed run. Each stage's wall time and peak memory go into
//! `RUN/timings.csv` as it finishes, for the report and for planning bigger runs.

use std::path::{Path, PathBuf};

use anyhow::{Context, Result};
use clap::Args;
use xylem::device::DeviceKind;
use xylem::field::{BaseColourTexture, ColourSpace, FieldConfig, GrowthField, RingImage};
use xylem::frame::Face;
use xylem::io::{OutputDir, Provenance, load_rgb, save_png, write_bytes_atomic};
use xylem::nca::config::Engine;
use xylem::outputs::{CROSS_BACKGROUND, SliceSet};
use xylem::procedural::{ProceduralWood, SpeciesConfig};
use xylem::render::lathe::{SHIPPED_SEGMENTS, turned_bowl};
use xylem::render::{RenderConfig, Shape, render, turntable};
use xylem::report::{
    Column, MetricsTable, SHEET_ROWS, StageClock, TIMINGS_FILE, Timings, captioned_row,
    comparison_sheet, default_title, write_report,
};
use xylem::rings::RingSource;
use xylem::sample::faces_or_all;
use xylem::slice::unfold_cross;
use xylem::texture::SolidTexture;
use xylem::volume::Volume;

use super::json_out::{Summary, say};
use super::{fit_cmd, run_metrics, synth_cmd, train_cmd};

/// The built-in NCA configs: `configs/nca/quick.toml` (the demo) and
/// `configs/nca/quality.toml` (the default of `xylem run`).
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum NcaPreset {
    /// 128^3 grid, 1500 iterations: the demo, about 8 minutes in all.
    Quick,
    /// Native 256 px / 256^3, 3000 iterations: about 21 minutes for CN03 on 2 cores.
    Quality,
}

impl NcaPreset {
    fn name(self) -> &'static str {
        match self {
            NcaPreset::Quick => "quick",
            NcaPreset::Quality => "quality",
        }
    }

    fn text(self) -> &'static str {
        match self {
            NcaPreset::Quick => include_str!("../../configs/nca/quick.toml"),
            NcaPreset::Quality => include_str!("../../configs/nca/quality.toml"),
        }
    }
}

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
    pub nca_preset: NcaPreset,
    /// Fit config (default: the built-in defaults).
    #[arg(long)]
    pub fit_config: Option<PathBuf>,
    /// Ring images for the fit: auto (the folder's where present, predicted from the photos
    /// elsewhere, so six photos are enough), given, or predict (see `xylem rings`).
    #[arg(long, default_value = "auto", value_name = "SOURCE", value_parser = super::output_args::ring_source)]
    pub rings: RingSource,
    /// Species whose procedural colours are shown on the fitted field in the sheet (a
    /// synthetic sample shows its own truth instead).
    #[arg(long, default_value = "chestnut", value_parser = super::presets::species_name)]
    pub species: String,
    /// NCA unroll steps of the synthesis (90, as the Mokume paper's inference).
    #[arg(long, default_value_t = 90, value_parser = clap::builder::RangedU64ValueParser::<usize>::new().range(1..=2048))]
    pub synth_steps: usize,
    /// Tile size of the sheet and side of the renders, in pixels.
    #[arg(long, default_value_t = 160, value_parser = super::output_args::image_side_16_2048)]
    pub image_size: usize,
    /// CPU backend of the NCA's burn parts (optimiser, loss; the whole NCA with --engine burn).
    #[arg(long, default_value = "flex")]
    pub device: DeviceKind,
    /// Synthesis unroll: the fused CPU kernels (default) or burn (the reference). Training
    /// uses the engine of the NCA config (`[compute] engine`, fused by default).
    #[arg(long, default_value = "fused")]
    pub engine: Engine,
}

pub fn run(args: RunArgs) -> Result<()> {
    let faces = faces_or_all(args.faces.as_deref())?;
    let out = OutputDir::prepare(&args.out)?;
    let started = STAGES.iter().any(|d| out.path(d).exists());
    run_provenance(&args, &faces)?.check_or_record(&out.path(RUN_RECORD), started)?;
    let mut log = StageLog::open(&out);
    let clock = StageClock::start();
    let skipped = fit_step(&args, &out)?;
    log.finish(clock, "fit", skipped)?;
    let clock = StageClock::start();
    let skipped = train_step(&args, &out)?;
    log.finish(clock, "train", skipped)?;
    let clock = StageClock::start();
    let skipped = synth_step(&args, &out)?;
    log.finish(clock, "synth", skipped)?;

    step("sheet");
    let clock = StageClock::start();
    let fit = FieldConfig::load(&out.path("fit/fit.toml"))?;
    let nca = xylem::io::npy::read_volume(&out.path("synth/volume.npy"))?;
    let truth = truth_species(&args.sample)?;
    let species = match &truth {
        Some(t) => t.clone(),
        None => species_on_field(&args.species, &fit)?,
    };
    let procedural = ProceduralWood::new(&species);
    let base = base_colour(&fit)?;
    let reference = reference_column(&args.sample)?;
    let sheet = SheetInputs {
        fit: &fit,
        base: &base,
        procedural: &procedural,
        reference: &reference,
        synthetic: truth.is_some(),
        nca: &nca,
    };
    write_sheet(&args, &out, &sheet)?;
    write_unfolded(&args, &out, &reference, &nca)?;
    log.finish(clock, "sheet", false)?;

    step("renders");
    let clock = StageClock::start();
    write_renders(&args, &out, &base, &procedural, &nca)?;
    log.finish(clock, "renders", false)?;

    step("metrics");
    let clock = StageClock::start();
    let table = run_metrics::metrics_table(&args.sample, &faces, &fit, &procedural, &nca)?;
    write_bytes_atomic(&out.path("metrics.csv"), table.to_csv().as_bytes())?;
    let textures: [(&str, &dyn SolidTexture); 2] = [("nca", &nca), ("procedural", &procedural)];
    let phase = run_metrics::phase_table(&reference, &fit, &textures, 256)?;
    write_bytes_atomic(&out.path("phase.csv"), phase.to_csv().as_bytes())?;
    log.finish(clock, "metrics", false)?;

    step("report");
    let clock = StageClock::start();
    write_run_report(&out)?;
    log.finish(clock, "report", false)?;
    // Again, so that the page shows the report's own row: the same page `xylem report`
    // writes from the finished folder.
    let images = write_run_report(&out)?;
    say(&format!(
        "wrote {}/report/index.html ({images} images)",
        args.out.display()
    ));
    run_summary(&args, &log.now, &table).emit();
    Ok(())
}

/// `--json`: the run folder, its stages' cost and the NCA's metrics per reference image.
fn run_summary(args: &RunArgs, timings: &Timings, table: &MetricsTable) -> Summary {
    let stages: Vec<String> = timings
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
        .text("sample", &args.sample.display().to_string())
        .text("out", &args.out.display().to_string())
        .text(
            "report",
            &args.out.join("report/index.html").display().to_string(),
        )
        .raw("stages", format!("[{}]", stages.join(", ")))
        .raw("nca_metrics", format!("[{}]", nca_rows.join(", ")))
}

/// The report of the run folder, titled from its record like `xylem report` does.
fn write_run_report(out: &OutputDir) -> Result<usize> {
    let title = default_title(out.root());
    Ok(write_report(
        out.root(),
        &out.path("report/index.html"),
        &title,
    )?)
}

/// `RUN/timings.csv`, rewritten after every stage, so that a killed run keeps the cost of
/// the stages it finished and its resumption can show them (see [`Timings::record`]).
struct StageLog {
    path: PathBuf,
    earlier: Option<Timings>,
    now: Timings,
}

impl StageLog {
    /// Starts this call's table; an unreadable earlier table is reported and replaced
    /// (it only costs the earlier rows of skipped stages).
    fn open(out: &OutputDir) -> Self {
        let path = out.path(TIMINGS_FILE);
        let earlier = if path.is_file() {
            Timings::read(&path)
                .map_err(|e| eprintln!("warning: {e}; its rows are not kept"))
                .ok()
        } else {
            None
        };
        Self {
            path,
            earlier,
            now: Timings::default(),
        }
    }

    fn finish(&mut self, clock: StageClock, stage: &str, skipped: bool) -> Result<()> {
        self.now
            .record(clock.finish(stage, skipped), self.earlier.as_ref());
        Ok(write_bytes_atomic(
            &self.path,
            self.now.to_csv().as_bytes(),
        )?)
    }
}

/// What the run folder was made with (`RUN/run.toml`, compared on every re-run).
const RUN_RECORD: &str = "run.toml";
/// The stage folders whose results a re-run reuses.
const STAGES: [&str; 3] = ["fit", "train", "synth"];
/// Written into a stage folder after its last output: the stage is complete.
const DONE: &str = ".done";

/// Everything that decides the reused stages (fit, train, synth); the sheet, renders,
/// metrics and report are redone on every call.
fn run_provenance(args: &RunArgs, faces: &[Face]) -> Result<Provenance> {
    let letters: Vec<String> = faces.iter().map(|f| f.letter().to_string()).collect();
    let mut record = Provenance::default()
        .with_folder("sample", &args.sample)?
        .with("faces", letters.join(","))
        .with("synth_steps", args.synth_steps.to_string())
        .with("engine", format!("{:?}", args.engine))
        .with("device", format!("{:?}", args.device));
    record = match &args.nca_config {
        Some(path) => record.with_file("nca_config", path)?,
        None => record
            .with("nca_config", format!("built-in {}", args.nca_preset.name()))
            .with_text("nca_config_hash", args.nca_preset.text()),
    };
    // Recorded only when not the default, so run folders made before --rings existed resume.
    if args.rings != RingSource::Auto {
        record = record.with("rings", args.rings.to_string());
    }
    Ok(match &args.fit_config {
        Some(path) => record.with_file("fit_config", path)?,
        None => record.with("fit_config", "built-in defaults"),
    })
}

/// Whether the stage in `dir` finished (its completion marker exists).
fn done(dir: &Path) -> bool {
    dir.join(DONE).is_file()
}

fn mark_done(dir: &Path) -> Result<()> {
    Ok(write_bytes_atomic(&dir.join(DONE), b"complete\n")?)
}

fn step(name: &str) {
    eprintln!("== {name}");
}

/// Runs the fit unless it is done; returns whether it was skipped (as for the other
/// reusable stages).
fn fit_step(args: &RunArgs, out: &OutputDir) -> Result<bool> {
    let dir = out.path("fit");
    if done(&dir) {
        step("fit (done, skipped)");
        return Ok(true);
    }
    step("fit");
    fit_cmd::run(fit_cmd::FitArgs {
        sample: args.sample.clone(),
        out: dir.clone(),
        faces: args.faces.clone(),
        config: args.fit_config.clone(),
        rings: args.rings,
    })?;
    mark_done(&dir)?;
    Ok(false)
}

fn train_step(args: &RunArgs, out: &OutputDir) -> Result<bool> {
    let dir = out.path("train");
    // Training writes model.bpk, then model.toml, loss.csv and loss.png: only the marker
    // written after all of them says the stage is complete (a kill between them resumes
    // from the final checkpoint and writes the rest).
    if done(&dir) {
        step("train (done, skipped)");
        return Ok(true);
    }
    let resume = xylem::nca::snapshot::exists(&dir);
    step(if resume { "train (resuming)" } else { "train" });
    let config = match &args.nca_config {
        Some(path) => path.clone(),
        None => {
            let path = out.path(format!("nca_{}.toml", args.nca_preset.name()));
            write_bytes_atomic(&path, args.nca_preset.text().as_bytes())?;
            path
        }
    };
    train_cmd::run(train_cmd::TrainArgs {
        sample: args.sample.clone(),
        fit: (!resume).then(|| out.path("fit")),
        config: (!resume).then_some(config),
        out: dir.clone(),
        device: args.device,
        resume,
        faces: if resume { None } else { args.faces.clone() },
        stop_after: None,
    })?;
    if dir.join("model.bpk").is_file() {
        mark_done(&dir)?;
    }
    Ok(false)
}

fn synth_step(args: &RunArgs, out: &OutputDir) -> Result<bool> {
    let dir = out.path("synth");
    if done(&dir) {
        step("synth (done, skipped)");
        return Ok(true);
    }
    step("synth");
    synth_cmd::run(synth_cmd::SynthArgs {
        model: out.path("train"),
        size: None,
        steps: args.synth_steps,
        seed: None,
        out: dir.clone(),
        device: args.device,
        engine: args.engine,
    })?;
    mark_done(&dir)?;
    Ok(false)
}

/// The species config of a synthetic sample (`truth/species.toml`), if it has one.
fn truth_species(sample: &Path) -> Result<Option<SpeciesConfig>> {
    let path = sample.join("truth/species.toml");
    Ok(if path.is_file() {
        Some(SpeciesConfig::load(&path)?)
    } else {
        None
    })
}

/// A species preset's colours on the fitted growth field.
fn species_on_field(name: &str, fit: &FieldConfig) -> Result<SpeciesConfig> {
    let mut species = xylem::presets::load_species_preset(name)?;
    species.pith = fit.pith.clone();
    species.growth = fit.growth.clone();
    species.knots = fit.knots.clone();
    Ok(species)
}

/// The base colour of a fit in real colour, for cuts and volumes.
fn base_colour(fit: &FieldConfig) -> Result<BaseColourTexture> {
    let colour = fit
        .base_colour
        .clone()
        .context("fit.toml has no [base_colour] section")?;
    Ok(BaseColourTexture::new(
        GrowthField::from_config(fit),
        colour,
        ColourSpace::Real(None),
    ))
}

/// Photos of the faces, and the true cuts when the sample has them.
fn reference_column(sample: &Path) -> Result<Vec<Option<xylem::Image2>>> {
    SHEET_ROWS
        .iter()
        .map(|row| {
            let path = match Face::parse(row) {
                Some(face) => sample.join(format!("{face}_col.png")),
                None => sample.join(format!("truth/{row}.png")),
            };
            path.is_file()
                .then(|| load_rgb(&path))
                .transpose()
                .map_err(Into::into)
        })
        .collect()
}

/// What the sheet shows, loaded once by [`run`] and shared with the other outputs.
struct SheetInputs<'a> {
    fit: &'a FieldConfig,
    base: &'a BaseColourTexture,
    procedural: &'a ProceduralWood,
    /// Photos of the faces and, for a synthetic sample, the true cuts (SHEET_ROWS order).
    reference: &'a [Option<xylem::Image2>],
    synthetic: bool,
    nca: &'a Volume,
}

fn write_sheet(args: &RunArgs, out: &OutputDir, inputs: &SheetInputs) -> Result<()> {
    let field = GrowthField::from_config(inputs.fit);
    let rings = RingImage(&field);
    let reference = if inputs.synthetic { "truth" } else { "photo" };
    let columns = vec![
        (
            reference.to_string(),
            Column::Images(inputs.reference.to_vec()),
        ),
        ("fitted rings".to_string(), Column::Texture(&rings)),
        ("base colour".to_string(), Column::Texture(inputs.base)),
        ("procedural".to_string(), Column::Texture(inputs.procedural)),
        ("NCA".to_string(), Column::Texture(inputs.nca)),
    ];
    save_png(
        &comparison_sheet(&columns, args.image_size),
        &out.path("sheet.png"),
    )?;
    Ok(())
}

/// The reference faces (photos, or the synthetic truth) and the NCA's, both unfolded, side
/// by side.
fn write_unfolded(
    args: &RunArgs,
    out: &OutputDir,
    reference: &[Option<xylem::Image2>],
    nca: &Volume,
) -> Result<()> {
    let n = args.image_size;
    let faces: Vec<xylem::Image2> = Face::ALL
        .iter()
        .map(|f| {
            reference[f.index()]
                .as_ref()
                .map_or_else(|| xylem::Image2::filled(n, n, 3, 0.85), |i| i.resized(n, n))
        })
        .collect();
    let faces: [xylem::Image2; 6] = faces.try_into().expect("six faces");
    let photo_cross = unfold_cross(&faces, CROSS_BACKGROUND);
    let nca_cross = SliceSet::render(nca, n).cross();
    let items = [
        ("reference".to_string(), &photo_cross),
        ("NCA".to_string(), &nca_cross),
    ];
    save_png(&captioned_row(&items), &out.path("unfolded.png"))?;
    Ok(())
}

fn write_renders(
    args: &RunArgs,
    out: &OutputDir,
    base: &BaseColourTexture,
    procedural: &ProceduralWood,
    nca: &Volume,
) -> Result<()> {
    let cfg = RenderConfig::default_config();
    let n = args.image_size * 2;
    let textures: [(&str, &dyn SolidTexture); 3] = [
        ("NCA", nca),
        ("base colour", base),
        ("procedural", procedural),
    ];
    let cubes: Vec<(String, xylem::Image2)> = textures
        .iter()
        .map(|(name, t)| {
            (
                name.to_string(),
                render(*t, &Shape::Cube, &cfg.camera, &cfg, n, n),
            )
        })
        .collect();
    let items: Vec<(String, &xylem::Image2)> = cubes
        .iter()
        .map(|(c, i)| (format!("cube: {c}"), i))
        .collect();
    save_png(&captioned_row(&items), &out.path("renders/cubes.png"))?;
    let bowl = Shape::carved(&turned_bowl(SHIPPED_SEGMENTS), &cfg.carve);
    let bowls: Vec<(String, xylem::Image2)> = textures[..1]
        .iter()
        .chain(&textures[2..])
        .map(|(name, t)| {
            (
                name.to_string(),
                render(*t, &bowl, &cfg.mesh_camera, &cfg, n, n),
            )
        })
        .collect();
    let items: Vec<(String, &xylem::Image2)> = bowls
        .iter()
        .map(|(c, i)| (format!("bowl: {c}"), i))
        .collect();
    save_png(&captioned_row(&items), &out.path("renders/bowls.png"))?;
    let strip = turntable(nca, &Shape::Cube, &cfg, args.image_size, args.image_size);
    save_png(&strip, &out.path("renders/turntable_nca.png"))
        .with_context(|| format!("writing renders into {}", out.root().display()))?;
    Ok(())
}
