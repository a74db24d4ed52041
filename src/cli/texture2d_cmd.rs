//! `xylem texture2d`: the 2D proof of the style loss, an image optimised from noise against a
//! photo.

use std::path::PathBuf;

use anyhow::Result;
use clap::Args;
use indicatif::{ProgressBar, ProgressStyle};
use xylem::config::{Checker, write_config_copy};
use xylem::device::DeviceKind;
use xylem::image2::Image2;
use xylem::io::{OutputDir, load_rgb, save_png, write_bytes_atomic};
use xylem::loss::{LossConfig, Texture2dConfig, synthesize};

/// Optimise an image from noise until its style-loss statistics match a photo's.
#[derive(Args, Debug)]
#[command(after_help = "Examples:
  xylem texture2d --target ../shared/data/mokume/CN03/A_col.png --size 128 --steps 600 --out out/t2d-cn03
  xylem texture2d --target H11/C_col.png --loss configs/loss/default.toml --size 128 --out out/t2d-h11

Writes DIR/target.png (the photo as used), DIR/initial.png (the noise it started from),
DIR/result.png, DIR/side_by_side.png (target | result), DIR/loss.csv and DIR/config.toml.")]
pub struct Texture2dArgs {
    /// The target photo (PNG, RGB).
    #[arg(long)]
    pub target: PathBuf,
    /// Side of the synthesised image in pixels.
    #[arg(long, default_value_t = 128)]
    pub size: usize,
    /// Side the target is resized to (default: --size, so both show the wood at one scale).
    #[arg(long)]
    pub target_size: Option<usize>,
    /// Adam steps.
    #[arg(long, default_value_t = 600)]
    pub steps: usize,
    /// Adam learning rate.
    #[arg(long, default_value_t = 0.02)]
    pub lr: f32,
    /// Seed of the initial noise (the loss has its own seed in its config).
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Loss config (default: the built-in configs/loss/default.toml).
    #[arg(long)]
    pub loss: Option<PathBuf>,
    /// CPU backend: flex (default) or ndarray.
    #[arg(long, default_value = "flex")]
    pub device: DeviceKind,
    /// Output folder (created; must be new, empty, or an earlier xylem output).
    #[arg(long)]
    pub out: PathBuf,
}

pub fn run(args: Texture2dArgs) -> Result<()> {
    let (loss, loss_origin) = match &args.loss {
        Some(path) => (LossConfig::load(path)?, path.display().to_string()),
        None => (
            LossConfig::default_config(),
            "built-in configs/loss/default.toml".to_string(),
        ),
    };
    let cfg = Texture2dConfig {
        size: args.size,
        target_size: args.target_size.unwrap_or(args.size),
        steps: args.steps,
        learning_rate: args.lr,
        init_noise: 0.1,
        seed: args.seed,
        loss,
    };
    cfg.validate(&Checker::new(std::path::Path::new("texture2d arguments")))?;
    let photo = load_rgb(&args.target)?;
    let out = OutputDir::prepare(&args.out)?;

    let bar = ProgressBar::new(cfg.steps as u64).with_style(
        ProgressStyle::with_template(
            "texture2d {pos}/{len} [{bar:30}] loss {msg} {elapsed} (eta {eta})",
        )?
        .progress_chars("=> "),
    );
    let synthesis = synthesize(&photo, &cfg, &args.device.device(), &mut |_, loss| {
        bar.set_message(format!("{loss:.4}"));
        bar.inc(1);
    })?;
    bar.finish();

    save_png(&synthesis.target, &out.path("target.png"))?;
    save_png(&synthesis.initial, &out.path("initial.png"))?;
    save_png(&synthesis.result, &out.path("result.png"))?;
    let pair = Image2::hstack(&[&synthesis.target, &synthesis.result], 4, 1.0);
    save_png(&pair, &out.path("side_by_side.png"))?;
    let mut csv = String::from("step,loss\n");
    for (i, l) in synthesis.losses.iter().enumerate() {
        csv += &format!("{i},{l}\n");
    }
    write_bytes_atomic(&out.path("loss.csv"), csv.as_bytes())?;
    let source = format!(
        "xylem texture2d --target {} (loss config: {loss_origin})",
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
