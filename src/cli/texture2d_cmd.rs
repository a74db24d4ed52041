//! `xylem texture2d`: the 2D proof of the style loss, an image optimised from noise against a
//! photo.

use std::path::{Path, PathBuf};

use anyhow::{Result, bail};
use clap::Args;
use xylem::config::{Checker, write_config_copy};
use xylem::device::DeviceKind;
use xylem::io::{OutputDir, load_rgb, save_png, write_bytes_atomic};
use xylem::loss::{LossConfig, Texture2dConfig, synthesize};
use xylem::report::captioned_row;

use super::progress::Progress;
use xylem::config::ConfigFile;

/// Optimise an image from noise until its style-loss statistics match a photo's.
#[derive(Args, Debug)]
#[command(after_help = "Examples:
  xylem texture2d --target ../shared/data/mokume/CN03/A_col.png --size 128 --steps 600 --out out/t2d-cn03
  xylem texture2d --target H11/C_col.png --loss configs/loss/default.toml --size 128 --out out/t2d-h11
  xylem texture2d --target H11/C_col.png --config out/t2d-h11/config.toml --out out/t2d-h11-again

Writes DIR/target.png (the photo as used), DIR/initial.png (the noise it started from),
DIR/result.png, DIR/side_by_side.png (target | start | result, captioned), DIR/loss.csv and DIR/config.toml.")]
pub struct Texture2dArgs {
    /// The target photo (PNG, RGB).
    #[arg(long)]
    pub target: PathBuf,
    /// A config written by an earlier run (its config.toml) to reproduce it; the options
    /// below override its values.
    #[arg(long)]
    pub config: Option<PathBuf>,
    /// Side of the synthesised image in pixels [default: 128].
    #[arg(long, value_parser = super::output_args::side_16_4096)]
    pub size: Option<u32>,
    /// Side the target is resized to [default: --size, so both show the wood at one scale].
    #[arg(long)]
    pub target_size: Option<usize>,
    /// Adam steps [default: 600].
    #[arg(long)]
    pub steps: Option<usize>,
    /// Adam learning rate [default: 0.02].
    #[arg(long)]
    pub lr: Option<f32>,
    /// Seed of the initial noise [default: 1] (the loss has its own seed in its config).
    #[arg(long)]
    pub seed: Option<u64>,
    /// Loss config [default: the built-in configs/loss/default.toml, or --config's].
    #[arg(long)]
    pub loss: Option<PathBuf>,
    /// CPU backend: flex (default) or ndarray.
    #[arg(long, default_value = "flex", value_parser = super::output_args::flagged::<DeviceKind>)]
    pub device: DeviceKind,
    /// Output folder (created; must be new, empty, or an earlier xylem output).
    #[arg(long, short = 'o')]
    pub out: PathBuf,
}

/// The run's config: --config (or the defaults), then the options given.
fn resolve(args: &Texture2dArgs) -> Result<(Texture2dConfig, String)> {
    let (mut cfg, mut origin) = match &args.config {
        Some(path) => (Texture2dConfig::load(path)?, path.display().to_string()),
        None => (
            Texture2dConfig::with_loss(LossConfig::default_config()),
            "defaults, built-in configs/loss/default.toml".to_string(),
        ),
    };
    if let Some(path) = &args.loss {
        cfg.loss = LossConfig::load(path)?;
        origin += &format!(", loss config {}", path.display());
    }
    if let Some(size) = args.size {
        cfg.size = size as usize;
        cfg.target_size = size as usize;
    }
    cfg.target_size = args.target_size.unwrap_or(cfg.target_size);
    cfg.steps = args.steps.unwrap_or(cfg.steps);
    cfg.learning_rate = args.lr.unwrap_or(cfg.learning_rate);
    cfg.seed = args.seed.unwrap_or(cfg.seed);
    cfg.validate(&Checker::new(Path::new("xylem texture2d options")))?;
    Ok((cfg, origin))
}

/// Smallest target side accepted.
const MIN_TARGET_SIDE: usize = 16;

pub fn run(args: Texture2dArgs) -> Result<()> {
    let (cfg, origin) = resolve(&args)?;
    let photo = load_rgb(&args.target)?;
    // A texture needs texels: below this the loss's pyramid has nothing to compare.
    if photo.width.min(photo.height) < MIN_TARGET_SIDE {
        bail!(
            "--target {}: is {}x{}; expected a photo of at least {MIN_TARGET_SIDE}x{MIN_TARGET_SIDE} pixels",
            args.target.display(),
            photo.width,
            photo.height
        );
    }
    let out = OutputDir::prepare(&args.out)?;

    let bar = Progress::new("texture2d", cfg.steps as u64);
    let synthesis = synthesize(&photo, &cfg, &args.device.device(), &mut |_, loss| {
        bar.set_message(format!("loss {loss:.4}"));
        bar.inc(1);
    })?;
    bar.finish();

    save_png(&synthesis.target, &out.path("target.png"))?;
    save_png(&synthesis.initial, &out.path("initial.png"))?;
    save_png(&synthesis.result, &out.path("result.png"))?;
    let row = captioned_row(&[
        ("target".to_string(), &synthesis.target),
        ("start".to_string(), &synthesis.initial),
        (format!("{} steps", cfg.steps), &synthesis.result),
    ]);
    save_png(&row, &out.path("side_by_side.png"))?;
    let mut csv = String::from("step,loss\n");
    for (i, l) in synthesis.losses.iter().enumerate() {
        csv += &format!("{i},{l}\n");
    }
    write_bytes_atomic(&out.path("loss.csv"), csv.as_bytes())?;
    let source = format!(
        "xylem texture2d --target {} --config config.toml; was: {origin}",
        args.target.display()
    );
    write_config_copy(&out.path("config.toml"), &cfg, &source)?;
    println!(
        "wrote {} (loss {:.4} -> {:.4})",
        out.root().display(),
        synthesis.losses.first().copied().unwrap_or(f32::NAN),
        synthesis.losses.last().copied().unwrap_or(f32::NAN)
    );
    Ok(())
}
