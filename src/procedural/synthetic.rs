//! Synthetic "photographed cubes": a species model written as a sample folder in the Mokume
//! layout that `sample::Sample::load` reads, with the hidden truth beside it.
//!
//! - `A_col.png`..`F_col.png`: the model's colour on the six faces;
//! - `A_arl.png`..`F_arl.png`: the exact ring localisation image I(T) of the model's ring
//!   time (what the U-Net approximates on real photos);
//! - `X_knot.png`: for each face a knot axis crosses, a white image with one pixel of value
//!   `sample::marker_value(i)` at the crossing of knot i (the H11 encoding);
//! - `truth/cut1.png`, `truth/cut2.png`: the validation cuts in colour;
//! - `truth/field.toml`: the growth field (`xylem field --config` loads it);
//! - `truth/species.toml`: the full species config;
//! - `truth/photograph.toml`: how faces and cuts were photographed (`photograph`: the
//!   end-grain factor, 1 unless asked for).
//!
//! The ring images show T, which equals the field's G unless the species varies ring widths
//! per year, has figure or is a burl; `truth/field.toml` says in its header which is the case.

use glam::Vec3;

use super::config::SpeciesConfig;
use super::model::{ProceduralWood, RingTime};
use super::photograph::{Photograph, photographed};
use crate::config::{ConfigFile, to_toml, write_config_copy};
use crate::error::Result;
use crate::field::{KnotConfig, RingImage};
use crate::frame::{Face, HALF, Plane};
use crate::image2::Image2;
use crate::io::{OutputDir, save_png, write_bytes_atomic};
use crate::sample::marker_value;
use crate::slice::{slice_face, slice_plane};

/// Where a knot's axis crosses a face.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct KnotCrossing {
    pub knot: usize,
    pub face: Face,
    pub point: Vec3,
}

/// The faces each knot's axis (a ray from its origin) passes through.
pub fn knot_crossings(knots: &[KnotConfig]) -> Vec<KnotCrossing> {
    let mut out = Vec::new();
    for (knot, k) in knots.iter().enumerate() {
        let origin = Vec3::from(k.origin);
        let dir = Vec3::from(k.direction).normalize();
        for face in Face::ALL {
            let normal = face.normal();
            let denom = dir.dot(normal);
            if denom.abs() < 1e-9 {
                continue;
            }
            let t = (HALF - origin.dot(normal)) / denom;
            let point = origin + t * dir;
            let inside = point.abs().max_element() <= HALF + 1e-6;
            if t > 0.0 && inside {
                out.push(KnotCrossing { knot, face, point });
            }
        }
    }
    out
}

/// One marker image per face that has crossings (white, one pixel per crossing).
pub(crate) fn marker_images(crossings: &[KnotCrossing], n: usize) -> Vec<(Face, Image2)> {
    let mut images: Vec<(Face, Image2)> = Vec::new();
    for c in crossings {
        let (row, col) = c.face.point_pixel(c.point, n);
        let clamp = |v: f32| (v.round().max(0.0) as usize).min(n - 1);
        let value = marker_value(c.knot) as f32 / 255.0;
        let slot = match images.iter().position(|(f, _)| *f == c.face) {
            Some(i) => i,
            None => {
                images.push((c.face, Image2::filled(n, n, 1, 1.0)));
                images.len() - 1
            }
        };
        images[slot].1.pixel_mut(clamp(row), clamp(col))[0] = value;
    }
    images
}

/// Whether the ring images of `cfg` show exactly the G of its growth field.
pub fn rings_follow_field(cfg: &SpeciesConfig) -> bool {
    let figure = cfg
        .figure
        .as_ref()
        .is_some_and(|f| f.radial_mm > 0.0 || f.tangential_mm > 0.0);
    cfg.rings.width_variation == 0.0 && !figure && cfg.burl.is_none()
}

/// Writes the sample folder of `cfg` at `n` x `n` pixels per face into `out`, photographed
/// plainly (no end-grain factor).
pub fn write_sample(cfg: &SpeciesConfig, origin: &str, n: usize, out: &OutputDir) -> Result<()> {
    write_photographed_sample(cfg, &Photograph::default(), origin, n, out)
}

/// [`write_sample`] with the faces and truth cuts seen through `photograph`.
pub fn write_photographed_sample(
    cfg: &SpeciesConfig,
    photograph: &Photograph,
    origin: &str,
    n: usize,
    out: &OutputDir,
) -> Result<()> {
    let model = ProceduralWood::new(cfg);
    let seen = photographed(&model, photograph, cfg.pith.fibre_axis());
    let time = RingTime(&model);
    let rings = RingImage(&time);
    for face in Face::ALL {
        save_png(
            &slice_face(&seen, face, n),
            &out.path(format!("{face}_col.png")),
        )?;
        save_png(
            &slice_face(&rings, face, n),
            &out.path(format!("{face}_arl.png")),
        )?;
    }
    for (face, image) in marker_images(&knot_crossings(&cfg.knots), n) {
        save_png(&image, &out.path(format!("{face}_knot.png")))?;
    }
    save_png(
        &slice_plane(&seen, &Plane::cut1(), n, n),
        &out.path("truth/cut1.png"),
    )?;
    save_png(
        &slice_plane(&seen, &Plane::cut2(), n, n),
        &out.path("truth/cut2.png"),
    )?;
    let note = if rings_follow_field(cfg) {
        "The ring images X_arl.png are exactly I(G) of this field."
    } else {
        "The ring images X_arl.png show the species' ring time T, which differs from this G \
         (year-to-year ring widths, figure or burl); see species.toml."
    };
    let text = format!(
        "# Growth field of the synthetic sample (from {origin}).\n# {note}\n\n{}",
        to_toml(&cfg.field_config())?
    );
    write_bytes_atomic(&out.path("truth/field.toml"), text.as_bytes())?;
    write_config_copy(&out.path("truth/species.toml"), cfg, origin)?;
    photograph.save_copy(&out.path("truth/photograph.toml"), origin)
}
