//! A species config with every colour scaled per channel: how the inverse procedural fit
//! (`fit::procedural_fit`) brings a preset's palette to a sample's mean colour while keeping
//! the preset's contrasts between earlywood, latewood, pores, rays and knots.

use super::colour_map::ColourMapConfig;
use super::config::SpeciesConfig;

fn scale(rgb: [f32; 3], factor: [f32; 3]) -> [f32; 3] {
    std::array::from_fn(|c| (rgb[c] * factor[c]).clamp(0.0, 1.0))
}

fn scale_map(map: &mut ColourMapConfig, factor: [f32; 3]) {
    for stop in &mut map.stops {
        let [t, r, g, b] = *stop;
        let [r, g, b] = scale([r, g, b], factor);
        *stop = [t, r, g, b];
    }
}

impl SpeciesConfig {
    /// Every colour of the config (display sRGB) times `factor` per channel, clamped to
    /// [0, 1]: ring colour maps, pores, rays, burl buds, knot map and outline.
    pub(crate) fn recoloured(&self, factor: [f32; 3]) -> SpeciesConfig {
        let mut cfg = self.clone();
        scale_map(&mut cfg.rings.earlywood, factor);
        scale_map(&mut cfg.rings.latewood, factor);
        if let Some(p) = &mut cfg.pores {
            p.colour = scale(p.colour, factor);
        }
        for r in &mut cfg.rays {
            r.colour = scale(r.colour, factor);
        }
        if let Some(b) = &mut cfg.burl {
            b.bud_colour = scale(b.bud_colour, factor);
        }
        cfg.recoloured_knots(factor)
    }

    /// The knots' colours alone (map and dead-knot outline) times `factor` per channel.
    pub fn recoloured_knots(&self, factor: [f32; 3]) -> SpeciesConfig {
        let mut cfg = self.clone();
        scale_map(&mut cfg.knot_colour.map, factor);
        cfg.knot_colour.outline_colour = scale(cfg.knot_colour.outline_colour, factor);
        cfg
    }
}

#[cfg(test)]
mod tests {
    use crate::presets::load_species_preset;

    #[test]
    fn every_colour_is_scaled_and_nothing_else_changes() {
        let oak = load_species_preset("oak").unwrap();
        let factor = [0.5, 1.0, 2.0];
        let scaled = oak.recoloured(factor);
        let early = (&oak.rings.earlywood.stops, &scaled.rings.earlywood.stops);
        for (a, b) in early.0.iter().zip(early.1) {
            assert_eq!(a[0], b[0]);
            for c in 0..3 {
                assert!((b[c + 1] - (a[c + 1] * factor[c]).min(1.0)).abs() < 1e-6);
            }
        }
        let (pa, pb) = (oak.pores.as_ref().unwrap(), scaled.pores.as_ref().unwrap());
        assert!((pb.colour[0] - 0.5 * pa.colour[0]).abs() < 1e-6);
        assert_eq!(pa.radius_mm, pb.radius_mm);
        // The identity factor gives the same config back.
        assert_eq!(oak.recoloured([1.0; 3]), oak);
    }
}
