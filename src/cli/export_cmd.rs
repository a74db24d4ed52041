//! `xylem export`: convert a volume for other tools.

use std::path::PathBuf;

use anyhow::{Result, bail};
use clap::{Args, ValueEnum};
use xylem::Volume;
use xylem::export::vdb::{VdbClass, VdbGrid, VdbValues, write_vdb};
use xylem::export::{
    ExportSummary, Format, SceneSize, Values, export, export_scene, main_grid,
    values::{check_looks_like_colour, prepare},
};
use xylem::field::{FieldConfig, GrowthField};
use xylem::io::{OutputDir, check_new_file};
use xylem::render::RenderConfig;

use super::output_args::parse_size;
use xylem::config::ConfigFile;

/// Export a volume for other tools: NumPy .npy, Mitsuba 3 .vol or a whole Mitsuba scene,
/// NRRD (VTK/ParaView, 3D Slicer), OpenVDB .vdb (Blender, Houdini).
#[derive(Args, Debug)]
#[command(after_help = "Examples:
  xylem export --volume out/demo/synth/volume.npy -o wood.vdb
  xylem export --volume out/demo/synth/volume.npy -o wood.vdb --field out/demo/fit/field.toml
  xylem export --volume out/demo/synth/volume.npy -o wood.nrrd
  xylem export --volume out/demo/synth/volume.npy --format mitsuba -o scene/   # then: mitsuba scene/scene.xml

Colour (3-channel volumes, unless --values data): values outside [0, 1] are clamped to it
(the count is printed); .vol, .vdb and the Mitsuba scene hold linear RGB (what renderers
integrate), .npy and .nrrd display sRGB (what viewers show). Without --values, a 3-channel
volume with more than 1 % of its values outside [0, 1] (a fibre direction?) is refused:
say --values data or --values colour.

Layouts: .npy [X, Y, Z, C] (z fastest; as xylem writes it). .vol x fastest, bounding box
[-0.5, 0.5]^3 in cube units (Mitsuba gridvolume; the scene sets use_grid_bbox). .nrrd sizes
'C X Y Z' (x fastest), space directions and origin in cm (1 cube unit = 4 cm), kind
RGB-color. .vdb: grid 'color' (Vec3S, linear RGB) or 'values', index (i, j, k) = voxel
(i, j, k) of the volume, transform voxel size 1/N cube units with index (0, 0, 0) at the
centre of the first voxel (the cube is [-0.5, 0.5]^3: scale by 4 for centimetres); with
--field a FloatGrid 'growth' (years), with --fibre a Vec3SGrid 'fibre'.")]
pub struct ExportArgs {
    /// Input volume (.npy, float32 [X, Y, Z, C]).
    #[arg(long, value_name = "V.npy")]
    pub volume: PathBuf,
    /// Output format; default: from the extension of --out (.npy, .vol, .nrrd, .vdb).
    /// `mitsuba` writes a folder with scene.xml and color.vol.
    #[arg(long)]
    pub format: Option<Format>,
    /// What the values are: colour (clamped, converted per format) or data (as they are).
    /// Default: colour for 3-channel volumes, data otherwise.
    #[arg(long, value_enum)]
    pub values: Option<ValuesArg>,
    /// .vdb only: a growth-field config (e.g. RUN/fit/field.toml) whose field G is added
    /// as the FloatGrid `growth`, evaluated at the voxel centres.
    #[arg(long, value_name = "FIELD.toml")]
    pub field: Option<PathBuf>,
    /// .vdb only: a fibre-direction volume (e.g. `xylem procedural`'s fibre_direction.npy,
    /// same size) added as the Vec3SGrid `fibre`.
    #[arg(long, value_name = "F.npy")]
    pub fibre: Option<PathBuf>,
    /// Mitsuba scene only: render config for the camera, light and coat (default: the
    /// built-in configs/render/default.toml, the view of `xylem render`).
    #[arg(long, value_name = "FILE")]
    pub render_config: Option<PathBuf>,
    /// Mitsuba scene only: image size WIDTHxHEIGHT (Mitsuba's -D resx=.. -D resy=.. too).
    #[arg(long, default_value = "800x800")]
    pub image_size: String,
    /// Output file (a folder for --format mitsuba).
    #[arg(long, short = 'o')]
    pub out: PathBuf,
    /// Replace the output file (or the scene in the folder) if it exists.
    #[arg(long)]
    pub force: bool,
}

#[derive(Clone, Copy, Debug, ValueEnum)]
pub enum ValuesArg {
    Colour,
    Data,
}

pub fn run(args: ExportArgs) -> Result<()> {
    let format = match args.format {
        Some(f) => f,
        None => Format::from_path(&args.out)?,
    };
    if format != Format::Vdb && (args.field.is_some() || args.fibre.is_some()) {
        bail!("--field and --fibre add grids to a .vdb file; {format:?} has no place for them");
    }
    let volume = xylem::io::npy::read_volume(&args.volume)?;
    let what = args.volume.display().to_string();
    let values = match args.values {
        Some(ValuesArg::Colour) => Values::Colour,
        Some(ValuesArg::Data) => Values::Data,
        None if volume.channels == 3 => {
            check_looks_like_colour(&volume, &what)?;
            Values::Colour
        }
        None => Values::Data,
    };
    let summary = match format {
        Format::Mitsuba => write_scene(&args, &volume, &what)?,
        Format::Vdb => {
            check_new_file(&args.out, args.force)?;
            write_vdb_with_extras(&args, &volume, values, &what)?
        }
        _ => {
            check_new_file(&args.out, args.force)?;
            export(&volume, values, format, &args.out, &what)?
        }
    };
    report(&args, format, values, summary);
    Ok(())
}

fn write_scene(args: &ExportArgs, volume: &Volume, what: &str) -> Result<ExportSummary> {
    // Checked before the folder is made, so a wrong volume leaves nothing behind.
    if volume.channels != 3 {
        bail!(
            "{what}: a Mitsuba scene shows colour (3 channels); this volume has {}",
            volume.channels
        );
    }
    let (width, height) = parse_size("--image-size", &args.image_size)?;
    let cfg = match &args.render_config {
        Some(path) => RenderConfig::load(path)?,
        None => RenderConfig::default_config(),
    };
    let dir = OutputDir::prepare(&args.out)?;
    let scene = dir.path(xylem::export::mitsuba_scene::SCENE_FILE);
    check_new_file(&scene, args.force)?;
    let size = SceneSize {
        width,
        height,
        spp: 64,
    };
    Ok(export_scene(volume, dir.root(), &cfg, size, what)?)
}

/// The volume's own grid plus the optional `growth` and `fibre` grids, in one file.
fn write_vdb_with_extras(
    args: &ExportArgs,
    volume: &Volume,
    values: Values,
    what: &str,
) -> Result<ExportSummary> {
    let prepared = prepare(volume, values, Format::Vdb.encoding(), what)?;
    let mut grids = vec![main_grid(prepared.volume.as_ref(), values, what)?];
    let growth = match &args.field {
        Some(path) => {
            let field = GrowthField::from_config(&FieldConfig::load(path)?);
            Some(Volume::from_texture_dims(&field, volume.dims))
        }
        None => None,
    };
    if let Some(g) = &growth {
        grids.push(VdbGrid {
            name: "growth",
            values: VdbValues::Float(g),
            class: VdbClass::Unknown,
        });
    }
    let fibre = match &args.fibre {
        Some(path) => {
            let f = xylem::io::npy::read_volume(path)?;
            if f.dims != volume.dims || f.channels != 3 {
                bail!(
                    "--fibre {}: expected a 3-channel volume of {:?} voxels like --volume, got {:?} x {}",
                    path.display(),
                    volume.dims,
                    f.dims,
                    f.channels
                );
            }
            Some(f)
        }
        None => None,
    };
    if let Some(f) = &fibre {
        grids.push(VdbGrid {
            name: "fibre",
            values: VdbValues::Vec3(f),
            class: VdbClass::Unknown,
        });
    }
    write_vdb(&args.out, &grids)?;
    Ok(ExportSummary {
        clamped: prepared.clamped,
        total: volume.data.len(),
    })
}

fn report(args: &ExportArgs, format: Format, values: Values, summary: ExportSummary) {
    let encoding = match (values, format.encoding()) {
        (Values::Data, _) => "values as they are".to_string(),
        (Values::Colour, xylem::export::Encoding::Linear) => "colour, linear RGB".to_string(),
        (Values::Colour, xylem::export::Encoding::DisplaySrgb) => {
            "colour, display sRGB".to_string()
        }
    };
    let clamped = if values == Values::Colour {
        format!(
            "; {} of {} values ({:.2e}) clamped to [0, 1]",
            summary.clamped,
            summary.total,
            summary.clamped as f64 / summary.total as f64
        )
    } else {
        String::new()
    };
    println!("wrote {} ({encoding}{clamped})", args.out.display());
}
