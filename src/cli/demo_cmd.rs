//! `xylem demo`: the built-in default job, needing no external data.

use std::path::PathBuf;

use anyhow::Result;
use clap::Args;
use indicatif::{ProgressBar, ProgressStyle};
use xylem::presets::{FIELD_PRESETS, load_field_preset};

use super::field_cmd::render_field;

/// Run the built-in demo: render every growth-field preset (faces, cuts, unfolded cross).
#[derive(Args, Debug)]
#[command(after_help = "Example:
  xylem demo --out out/demo      # then look at out/demo/*/unfolded.png")]
pub struct DemoArgs {
    /// Output folder.
    #[arg(long, default_value = "out/demo")]
    pub out: PathBuf,
    /// Image side in pixels.
    #[arg(long, default_value_t = 256, value_parser = clap::value_parser!(u32).range(2..=4096))]
    pub size: u32,
}

pub fn run(args: DemoArgs) -> Result<()> {
    let bar = ProgressBar::new(FIELD_PRESETS.len() as u64).with_style(
        ProgressStyle::with_template("{msg:>12} [{bar:30}] {pos}/{len} {elapsed}")?
            .progress_chars("=> "),
    );
    for (name, _) in FIELD_PRESETS {
        bar.set_message(name.to_string());
        let cfg = load_field_preset(name)?;
        render_field(
            &cfg,
            &format!("built-in preset {name}"),
            args.size as usize,
            &args.out.join(name),
        )?;
        bar.inc(1);
    }
    bar.finish_with_message("done");
    println!(
        "wrote {}/<preset>/unfolded.png for {} presets",
        args.out.display(),
        FIELD_PRESETS.len()
    );
    Ok(())
}
