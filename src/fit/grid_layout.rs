//! Where the fitted rate grid's nodes go, given the fitted pith.
//!
//! Heights and radii span the cube as the field's defaults do (`PithAxis::cube_height_range`,
//! `cube_radius_range`). Azimuths are the decision that matters: a cube 5 to 10 cm from the
//! pith (most Mokume samples) sees a wedge of only 25 to 45 degrees of azimuth, so 16 nodes
//! spread around the full circle would leave one or two nodes for the whole cube and no way
//! to bend the rings across a face. As in the authors' code (which limits its spokes to the
//! sample's angular range), the nodes are spread over the cube's wedge, widened by a small
//! margin; only when the pith passes through or close by the cube (wedge over 300 degrees)
//! do they go round the full circle. All three ranges are written to `fit.toml` so the field
//! does not move when reloaded.

use std::f32::consts::TAU;

use crate::field::{PithAxis, RateGrid};
use crate::frame::Face;

/// Face samples per side used to find the cube's azimuth wedge.
const WEDGE_SAMPLES: usize = 33;
/// Margin added on each side of the wedge, as a fraction of its width.
const WEDGE_MARGIN: f32 = 0.03;
/// Wedges wider than this become the full, periodic circle.
const FULL_CIRCLE_ABOVE: f32 = 300.0 * std::f32::consts::PI / 180.0;

/// The azimuth range `[start, end]` (radians) of the cube around `pith`, or `None` for the
/// full circle.
pub(crate) fn cube_azimuth_range(pith: &PithAxis) -> Option<[f32; 2]> {
    let mut phis = Vec::new();
    for face in Face::ALL {
        for r in 0..WEDGE_SAMPLES {
            for c in 0..WEDGE_SAMPLES {
                let p = face.pixel_point(r, c, WEDGE_SAMPLES);
                if pith.radius(p) > 1e-6 {
                    phis.push(pith.cylindrical(p).phi);
                }
            }
        }
    }
    phis.sort_by(f32::total_cmp);
    // The wedge is the circle minus the largest empty gap between sorted azimuths.
    let (mut gap, mut after) = (phis[0] + TAU - phis[phis.len() - 1], 0);
    for i in 1..phis.len() {
        let g = phis[i] - phis[i - 1];
        if g > gap {
            gap = g;
            after = i;
        }
    }
    let width = TAU - gap;
    if width > FULL_CIRCLE_ABOVE {
        return None;
    }
    let start = phis[after];
    let pad = WEDGE_MARGIN * width;
    Some([start - pad, start + width + pad])
}

/// A uniform (all rates 1) grid of `dims` laid out for `pith`.
pub fn fitted_grid(pith: &PithAxis, dims: [usize; 3], min_rate: f32) -> RateGrid {
    RateGrid::uniform(
        dims,
        min_rate,
        pith.cube_height_range(),
        pith.cube_radius_range(),
    )
    .with_azimuth_range(cube_azimuth_range(pith))
}
