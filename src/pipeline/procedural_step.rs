//! The fit stage's inverse procedural step: the procedural model fitted to the photos on the
//! fitted field (`fit::procedural_fit`), written as `procedural.toml` (a species config for
//! `xylem procedural --config`) with its faces and cuts beside the fit's (seen with the fit's
//! grain shading, like the base colour's).

use super::reporter::Reporter;
use crate::Result;
use crate::config::write_config_copy;
use crate::device::DeviceKind;
use crate::field::FieldConfig;
use crate::fit::ProceduralFitConfig;
use crate::fit::procedural_fit::{ProceduralFit, fit_procedural, seen_procedural};
use crate::fit::procedural_search::describe;
use crate::frame::{Face, Plane};
use crate::io::{OutputDir, save_png};
use crate::loss::LossConfig;
use crate::metrics::Comparer;
use crate::procedural::ProceduralWood;
use crate::sample::Sample;
use crate::slice::{slice_face, slice_plane};

/// File name of the fitted procedural config inside a fit folder.
pub(crate) const PROCEDURAL_FILE: &str = "procedural.toml";

/// Fits the procedural model to the fitted faces of `sample` on `field` and writes
/// `procedural.toml`, `faces/X_procedural.png` and `cuts/cutN_procedural.png` into `dir`
/// at `size` pixels; says which preset won.
pub(crate) fn fit_and_write_procedural(
    sample: &Sample,
    field: &FieldConfig,
    cfg: &ProceduralFitConfig,
    dir: &OutputDir,
    source: &str,
    reporter: &dyn Reporter,
) -> Result<Option<ProceduralFit>> {
    let photos: Vec<(Face, &crate::image2::Image2)> = sample
        .faces
        .iter()
        .filter_map(|&f| sample.photo(f).map(|p| (f, p)))
        .collect();
    if cfg.presets.is_empty() {
        remove_stale(dir, reporter)?;
        return Ok(None);
    }
    let comparer = Comparer::new(&LossConfig::default_config(), &DeviceKind::Flex.device());
    let presets = cfg.presets.len() as u64;
    let bar = reporter.counter("procedural fit", presets);
    let fitted = fit_procedural(&photos, field, cfg, &comparer, |done, _| {
        bar.set_position(done as u64)
    })?;
    bar.finish();
    let Some(fitted) = fitted else {
        return Ok(None);
    };
    let species = &fitted.best.species;
    write_config_copy(&dir.path(PROCEDURAL_FILE), species, source)?;
    let wood = ProceduralWood::new(species);
    // Seen with the grain shading, as the run's sheet shows it.
    let white_balance = field.base_colour.as_ref().map(|c| &c.white_balance);
    let rgb = seen_procedural(&wood, white_balance);
    let size = sample.size;
    for face in Face::ALL {
        let path = dir.path(format!("faces/{face}_procedural.png"));
        save_png(&slice_face(&rgb, face, size), &path)?;
    }
    for (name, plane) in [("cut1", Plane::cut1()), ("cut2", Plane::cut2())] {
        let path = dir.path(format!("cuts/{name}_procedural.png"));
        save_png(&slice_plane(&rgb, &plane, size, size), &path)?;
    }
    let scores: Vec<String> = fitted
        .candidates
        .iter()
        .map(|c| {
            let offset = c.species.rings.phase_offset;
            format!("{} {:.3} (phase {offset:+.2})", c.preset, c.style)
        })
        .collect();
    reporter.say(&format!(
        "procedural model fitted: preset {} (style loss by preset: {}), ring phase offset \
         {:+.2} years (pore curves correlate {:.2}), {}, colours matched to the photos' \
         mean; wrote procedural.toml",
        fitted.best.preset,
        scores.join(", "),
        species.rings.phase_offset,
        fitted.best.phase_correlation,
        describe(species)
    ));
    Ok(Some(fitted))
}

/// A fit without a procedural model, written over an earlier fit that had one: its
/// `procedural.toml` would otherwise be shown by `xylem run` beside the new field.
fn remove_stale(dir: &OutputDir, reporter: &dyn Reporter) -> Result<()> {
    let path = dir.path(PROCEDURAL_FILE);
    if !path.is_file() {
        reporter.say("no procedural model fitted ([procedural] presets is empty)");
        return Ok(());
    }
    let mut stale = vec![path];
    stale.extend(Face::ALL.map(|f| dir.path(format!("faces/{f}_procedural.png"))));
    stale.extend(["cut1", "cut2"].map(|c| dir.path(format!("cuts/{c}_procedural.png"))));
    for file in stale.iter().filter(|p| p.is_file()) {
        std::fs::remove_file(file).map_err(|e| crate::XylemError::io(file, e))?;
    }
    reporter.say(
        "no procedural model fitted ([procedural] presets is empty): removed the earlier \
         fit's procedural.toml and its images from this folder",
    );
    Ok(())
}
