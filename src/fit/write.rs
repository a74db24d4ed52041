//! The files of a fit (`xylem fit --out OUT`):
//!
//! - `fit.toml`: the fitted field (pith, rate grid with pinned ranges, rings, knots, base
//!   colour), loadable by `xylem field --config` and `FieldConfig::load`;
//! - `config.toml`: the resolved fit config;
//! - `faces/A_arl.png`..`F_arl.png`, `faces/A_base.png`..`F_base.png`: fitted ring image and
//!   base colour (real colour, each face with its offset and white balance; faces left out
//!   of the fit with the fitted faces' mean);
//! - `cuts/cut1_arl.png`, `cut2_arl.png`, `cut1_base.png`, `cut2_base.png`;
//! - `sheet.png` (see `sheet`), `loss.csv` (stage, iteration, total, iso, image, smooth).

use super::config::FitConfig;
use super::run::FitResult;
use super::sheet::{SheetRow, fit_sheet};
use crate::config::write_config_copy;
use crate::error::{Result, XylemError};
use crate::field::{GrowthField, RingImage, base_colour_as_seen};
use crate::frame::{Face, Plane};
use crate::image2::Image2;
use crate::io::{OutputDir, save_png, write_bytes_atomic};
use crate::report::MetricsTable;
use crate::slice::{slice_face, slice_plane};

/// Photos and target ring images to show in the sheet, indexed by `Face::index` (faces the fit
/// did not use may be shown too).
pub struct Display {
    pub photos: [Option<Image2>; 6],
    pub targets: [Option<Image2>; 6],
}

/// Writes every output of a fit at `size` x `size` pixels. `source` names the sample in the
/// config headers.
pub(crate) fn write_fit(
    out: &OutputDir,
    result: &FitResult,
    fit_cfg: &FitConfig,
    faces: &[Face],
    display: &Display,
    size: usize,
    source: &str,
) -> Result<()> {
    write_config_copy(&out.path("config.toml"), fit_cfg, source)?;
    let field = GrowthField::from_config(&result.field);
    let colour =
        result.field.base_colour.clone().ok_or_else(|| {
            XylemError::numeric("fit", "the fit result has no base colour to write")
        })?;
    let rings = RingImage(&field);
    let base_in = |face| base_colour_as_seen(&field, colour.clone(), face);
    let mut rows = Vec::new();
    for face in Face::ALL {
        let used = faces.contains(&face);
        let fitted = slice_face(&rings, face, size);
        let base = slice_face(&base_in(used.then_some(face)), face, size);
        save_png(&fitted, &out.path(format!("faces/{face}_arl.png")))?;
        save_png(&base, &out.path(format!("faces/{face}_base.png")))?;
        rows.push(SheetRow {
            photo: display.photos[face.index()].clone(),
            target: display.targets[face.index()].clone(),
            fitted,
            base,
            held_out: !used,
        });
    }
    let volume = base_in(None);
    for (name, plane) in [("cut1", Plane::cut1()), ("cut2", Plane::cut2())] {
        save_png(
            &slice_plane(&rings, &plane, size, size),
            &out.path(format!("cuts/{name}_arl.png")),
        )?;
        save_png(
            &slice_plane(&volume, &plane, size, size),
            &out.path(format!("cuts/{name}_base.png")),
        )?;
    }
    save_png(&fit_sheet(&rows), &out.path("sheet.png"))?;
    write_bytes_atomic(&out.path("loss.csv"), loss_csv(result).as_bytes())?;
    // Last: fit.toml is what later stages read, so its presence means the fit is complete.
    write_config_copy(&out.path("fit.toml"), &result.field, source)
}

/// `loss.csv`: one row per logged iteration.
pub(crate) fn loss_csv(result: &FitResult) -> String {
    let header = ["stage", "iteration", "total", "iso", "image", "smooth"];
    let rows = result
        .loss_log
        .iter()
        .map(|row| {
            let p = &row.parts;
            MetricsTable::row(&[
                &row.stage,
                &row.iteration,
                &p.total,
                &p.iso,
                &p.image,
                &p.smooth,
            ])
        })
        .collect();
    MetricsTable::new(&header, rows).to_csv()
}
