//! `xylem sample`: a synthetic photographed cube in the Mokume layout, with its hidden truth.

use anyhow::{Context, Result};
use clap::Args;
use xylem::config::{Checker, ConfigFile};
use xylem::io::OutputDir;
use xylem::procedural::synthetic::{knot_crossings, rings_follow_field};
use xylem::procedural::{Photograph, write_photographed_sample};

use super::output_args::SizeAndOut;
use super::presets::SpeciesSource;

/// Write a synthetic sample folder from a species config: face photos, exact ring images,
/// knot markers, and the hidden truth (validation cuts, growth field, species config).
#[derive(Args, Debug)]
#[command(after_help = "Examples:
  xylem sample --preset chestnut --size 256 --out out/samples/chestnut
  xylem sample --config configs/species/softwood.toml --size 256 --out out/samples/softwood
  xylem sample --preset oak --end-grain 0.85 --out out/samples/oak_dark_end_grain

Writes DIR/A_col.png..F_col.png, DIR/A_arl.png..F_arl.png (exact ring localisation image),
DIR/X_knot.png for each face a knot axis crosses (white, one pixel of grey 186 - 8 i at knot
i's crossing), and DIR/truth/cut1.png, cut2.png, field.toml (for `xylem field --config`),
species.toml, photograph.toml. The folder loads like the real Mokume samples.")]
pub struct SampleArgs {
    #[command(flatten)]
    pub source: SpeciesSource,
    #[command(flatten)]
    pub target: SizeAndOut,
    /// Photograph end grain darker (< 1) or lighter than side grain by this factor, on the
    /// faces and the truth cuts alike (real wood: about 0.85; CN03 0.84). Surfaces get
    /// 1 + (F - 1) (n . t)^2, t the fibre axis.
    #[arg(long, value_name = "F", default_value_t = 1.0)]
    pub end_grain: f32,
}

pub fn run(args: SampleArgs) -> Result<()> {
    let (cfg, origin) = args.source.load()?;
    let photograph = Photograph {
        end_grain: args.end_grain,
    };
    photograph.validate(&Checker::new(std::path::Path::new(
        "xylem sample --end-grain",
    )))?;
    let out = OutputDir::prepare(&args.target.out)?;
    write_photographed_sample(&cfg, &photograph, &origin, args.target.size as usize, &out)
        .with_context(|| format!("writing the sample of {origin}"))?;
    let crossings = knot_crossings(&cfg.knots);
    println!(
        "wrote {} ({} knot crossings marked{})",
        out.root().display(),
        crossings.len(),
        if rings_follow_field(&cfg) {
            ""
        } else {
            "; ring images show the species' ring time, not exactly truth/field.toml's G"
        }
    );
    Ok(())
}
