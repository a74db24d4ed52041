//! `xylem gallery`: synthetic sample cubes from the species presets, loaded back like real
//! samples and rendered (a quick look at every preset; the full pipeline is `xylem demo`).

use std::path::{Path, PathBuf};

use anyhow::{Context, Result, bail};
use clap::Args;
use xylem::config::write_config_copy;
use xylem::frame::Face;
use xylem::image2::Image2;
use xylem::io::{OutputDir, load_rgb, save_png};
use xylem::outputs::CROSS_BACKGROUND;
use xylem::presets::{SPECIES_PRESETS, load_species_preset, species_preset_names};
use xylem::procedural::{SpeciesConfig, write_sample};
use xylem::sample::{Needs, Sample};
use xylem::slice::unfold_cross;

use super::progress::Progress;

/// For each species preset, write a synthetic sample cube (Mokume
/// layout, with its hidden truth), load it back like a real sample and render its unfolded
/// faces, ring images and validation cuts.
#[derive(Args, Debug)]
#[command(after_help = "Example:
  xylem gallery --out out/gallery      # then look at out/gallery/<species>/unfolded.png

For each species writes DIR/<species>/sample/ (A_col.png.., A_arl.png.., knot markers,
truth/), DIR/<species>/unfolded.png (the sample's photos as a cross: B above A, row C A E F,
D below A), unfolded_arl.png (its ring images), cuts.png (cut1 | cut2) and config.toml.")]
pub struct GalleryArgs {
    /// Output folder.
    #[arg(long, short = 'o', default_value = "out/gallery")]
    pub out: PathBuf,
    /// Image side in pixels.
    #[arg(long, default_value_t = 256, value_parser = super::output_args::side_16_4096)]
    pub size: u32,
    /// Species presets to render, comma-separated (default: all).
    #[arg(long, value_delimiter = ',')]
    pub species: Vec<String>,
}

pub fn run(args: GalleryArgs) -> Result<()> {
    let names: Vec<String> = if args.species.is_empty() {
        SPECIES_PRESETS.iter().map(|(n, _)| n.to_string()).collect()
    } else {
        args.species.clone()
    };
    for name in &names {
        if !species_preset_names().contains(&name.as_str()) {
            bail!(
                "--species {name:?}: unknown species preset; built-in presets: {}",
                species_preset_names().join(", ")
            );
        }
    }
    // The gallery folder itself must be new, empty or xylem's, like every output folder.
    OutputDir::prepare(&args.out)?;
    let bar = Progress::new("gallery", names.len() as u64);
    for name in &names {
        bar.set_message(name.clone());
        let cfg = load_species_preset(name)?;
        demo_species(&cfg, name, args.size as usize, &args.out.join(name))
            .with_context(|| format!("gallery of species preset {name}"))?;
        bar.inc(1);
    }
    bar.finish();
    println!(
        "wrote {}/<species>/unfolded.png for {}",
        args.out.display(),
        names.join(", ")
    );
    Ok(())
}

/// One species: the sample folder, then the renders made from it.
fn demo_species(cfg: &SpeciesConfig, name: &str, n: usize, dir: &Path) -> Result<()> {
    let out = OutputDir::prepare(dir)?;
    let origin = format!("built-in species preset {name}");
    let sample_dir = out.path("sample");
    write_sample(cfg, &origin, n, &OutputDir::prepare(&sample_dir)?)?;
    let sample = Sample::load(
        &sample_dir,
        &Face::ALL,
        Needs {
            photos: true,
            arl: true,
        },
    )?;
    let photos = faces_of(&sample.photos, &sample_dir)?;
    let rings = faces_of(&sample.arl, &sample_dir)?;
    save_png(
        &unfold_cross(&photos, CROSS_BACKGROUND),
        &out.path("unfolded.png"),
    )?;
    save_png(
        &unfold_cross(&rings, CROSS_BACKGROUND),
        &out.path("unfolded_arl.png"),
    )?;
    let cut1 = load_rgb(&sample_dir.join("truth/cut1.png"))?;
    let cut2 = load_rgb(&sample_dir.join("truth/cut2.png"))?;
    save_png(
        &Image2::hstack(&[&cut1, &cut2], n / 32, CROSS_BACKGROUND),
        &out.path("cuts.png"),
    )?;
    write_config_copy(&out.path("config.toml"), cfg, &origin)?;
    Ok(())
}

/// The six loaded images of a sample in file order.
fn faces_of(images: &[Option<Image2>; 6], dir: &Path) -> Result<[Image2; 6]> {
    let mut out = Vec::with_capacity(6);
    for face in Face::ALL {
        let image = images[face.index()]
            .clone()
            .with_context(|| format!("{}: face {face} was not loaded", dir.display()))?;
        out.push(image);
    }
    Ok(out.try_into().expect("six faces"))
}
