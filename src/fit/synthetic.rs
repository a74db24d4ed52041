//! Synthetic sample folders with known truth, for tests and accuracy figures.
//!
//! From a growth-field config this writes the Mokume layout the fit reads: `X_arl.png` (the
//! exact ring image I(G) of the face), `X_col.png` (a plain wood colour from the ring phase of
//! G: light early wood darkening into late wood, knots darker), `X_knot.png` markers where
//! each knot strand crosses the cube surface (grey `sample::marker_value(i)` for knot i), and
//! `truth/field.toml`. The colour model is deliberately simple: it exists to exercise the
//! colour fit, not to look like a particular wood (`xylem sample` is the detailed generator).

use std::path::Path;

use glam::Vec3;

use crate::config::write_config_copy;
use crate::error::Result;
use crate::field::smin::smoothstep;
use crate::field::{FieldConfig, GrowthField, Knot, RingImage, Strand};
use crate::frame::{Face, HALF};
use crate::image2::Image2;
use crate::io::{OutputDir, save_png};
use crate::sample::marker_value;
use crate::slice::slice_face;
use crate::texture::SolidTexture;

/// The synthetic wood colour of a field: RGB from the ring phase and the dominant strand.
struct SyntheticColour<'a>(&'a GrowthField);

impl SolidTexture for SyntheticColour<'_> {
    fn channels(&self) -> usize {
        3
    }

    fn eval(&self, p: Vec3, out: &mut [f32]) {
        let s = self.0.sample(p);
        let phase = s.g - s.g.floor();
        let late = smoothstep(0.55, 0.9, phase) * (1.0 - smoothstep(0.95, 1.0, phase));
        let shade = 1.0 - 0.28 * late;
        let knot = if matches!(s.strand, Strand::Knot(_)) {
            0.7
        } else {
            1.0
        };
        let base = [0.80, 0.62, 0.44];
        for c in 0..3 {
            out[c] = base[c] * shade * knot;
        }
    }
}

/// Writes a synthetic sample of `cfg` with `size` x `size` faces into `dir` (a new or earlier
/// xylem output folder).
pub fn write_synthetic_sample(dir: &Path, cfg: &FieldConfig, size: usize) -> Result<()> {
    let out = OutputDir::prepare(dir)?;
    let field = GrowthField::from_config(cfg);
    let mut markers: [Option<Image2>; 6] = Default::default();
    for (i, knot) in field.knots.iter().enumerate() {
        for (face, p) in surface_crossings(knot) {
            let img =
                markers[face.index()].get_or_insert_with(|| Image2::filled(size, size, 1, 1.0));
            let (r, c) = face.point_pixel(p, size);
            let (r, c) = (
                r.round().clamp(0.0, (size - 1) as f32),
                c.round().clamp(0.0, (size - 1) as f32),
            );
            img.pixel_mut(r as usize, c as usize)[0] = marker_value(i) as f32 / 255.0;
        }
    }
    for face in Face::ALL {
        let arl = slice_face(&RingImage(&field), face, size);
        save_png(&arl, &out.path(format!("{face}_arl.png")))?;
        let col = slice_face(&SyntheticColour(&field), face, size);
        save_png(&col, &out.path(format!("{face}_col.png")))?;
        if let Some(m) = &markers[face.index()] {
            save_png(m, &out.path(format!("{face}_knot.png")))?;
        }
    }
    write_config_copy(&out.path("truth/field.toml"), cfg, "xylem::fit::synthetic")
}

/// Where a knot's strand (a ray) crosses the cube surface, with the face crossed.
pub(crate) fn surface_crossings(knot: &Knot) -> Vec<(Face, Vec3)> {
    let (o, d) = (knot.origin, knot.dir);
    let (mut t_in, mut t_out) = (f32::NEG_INFINITY, f32::INFINITY);
    for a in 0..3 {
        if d[a].abs() < 1e-9 {
            if o[a].abs() > HALF {
                return Vec::new();
            }
            continue;
        }
        let (t0, t1) = ((-HALF - o[a]) / d[a], (HALF - o[a]) / d[a]);
        t_in = t_in.max(t0.min(t1));
        t_out = t_out.min(t0.max(t1));
    }
    if t_in > t_out || t_out < 0.0 {
        return Vec::new();
    }
    [t_in, t_out]
        .into_iter()
        .filter(|&t| t >= 0.0)
        .map(|t| {
            let p = o + t * d;
            (face_of(p), p)
        })
        .collect()
}

/// The face a surface point lies on (its largest coordinate).
fn face_of(p: Vec3) -> Face {
    let a = p.abs();
    if a.x >= a.y && a.x >= a.z {
        if p.x > 0.0 { Face::E } else { Face::C }
    } else if a.y >= a.z {
        if p.y > 0.0 { Face::B } else { Face::D }
    } else if p.z > 0.0 {
        Face::A
    } else {
        Face::F
    }
}
