//! Year-to-year variation (Liu et al. 2016 section 4.4): each year gets its own ring width and
//! its own pigment offset, drawn once from the seed.
//!
//! The growth field gives G (years). Year y spans [B_y, B_y + w_y) of G, with widths w_y =
//! exp(sigma z_y - sigma^2 / 2) (mean 1) and z_y an AR(1) sequence (correlated neighbouring
//! years, as in real ring-width series). The ring time is T = y + (G - B_y) / w_y: its integer
//! crossings are the ring boundaries the colour model and the ring localisation image of a
//! synthetic sample use. Without width variation T = G exactly, so the sample's rings are
//! those of its `field.toml`.

use crate::rng::Rng;

/// Years with their own width and colour; later years repeat width 1 and no colour offset.
pub const TABLE_YEARS: usize = 4096;

const STREAM_WIDTHS: u64 = 0x5945_4152;

#[derive(Clone, Debug)]
pub struct YearTable {
    /// Start of year y in G (`TABLE_YEARS + 1` entries; empty when widths do not vary).
    starts: Vec<f32>,
    /// For each whole G value k below the last start, the year containing G = k: the search
    /// for a year starts there and is only a step or two (widths are near 1).
    first_year: Vec<u32>,
    /// Pigment exponent offset of each year (empty when colours do not vary).
    colour: Vec<f32>,
}

impl YearTable {
    /// `width_sigma`: std of the log width; `correlation`: AR(1) coefficient; `colour_sigma`:
    /// std of the per-year pigment offset.
    pub fn new(seed: u64, width_sigma: f32, correlation: f32, colour_sigma: f32) -> Self {
        let mut rng = Rng::substream(seed, STREAM_WIDTHS);
        let mut starts = Vec::new();
        let mut colour = Vec::new();
        if width_sigma > 0.0 {
            let innovation = (1.0 - correlation * correlation).sqrt();
            let (mut z, mut start) = (rng.normal(), 0.0f64);
            starts.reserve(TABLE_YEARS + 1);
            for _ in 0..TABLE_YEARS {
                starts.push(start as f32);
                let width = (width_sigma * z - 0.5 * width_sigma * width_sigma).exp();
                start += width as f64;
                z = correlation * z + innovation * rng.normal();
            }
            starts.push(start as f32);
        }
        let mut first_year = Vec::new();
        if let Some(&end) = starts.last() {
            let mut y = 0;
            for k in 0..end.floor() as usize + 1 {
                while y + 1 < TABLE_YEARS && starts[y + 1] <= k as f32 {
                    y += 1;
                }
                first_year.push(y as u32);
            }
        }
        if colour_sigma > 0.0 {
            colour = (0..TABLE_YEARS)
                .map(|_| colour_sigma * rng.normal())
                .collect();
        }
        Self {
            starts,
            first_year,
            colour,
        }
    }

    /// The ring time T of growth time `g` (years).
    #[inline]
    pub fn time(&self, g: f32) -> f32 {
        if self.starts.is_empty() || g <= 0.0 {
            return g;
        }
        let last = TABLE_YEARS as f32;
        if g >= self.starts[TABLE_YEARS] {
            return last + (g - self.starts[TABLE_YEARS]);
        }
        // The last start <= g, walking up from the year containing floor(g).
        let mut y = self.first_year[(g as usize).min(self.first_year.len() - 1)] as usize;
        while self.starts[y + 1] <= g {
            y += 1;
        }
        let (s0, s1) = (self.starts[y], self.starts[y + 1]);
        y as f32 + (g - s0) / (s1 - s0)
    }

    /// The pigment exponent offset of the year containing ring time `time`.
    #[inline]
    pub(crate) fn colour_offset(&self, time: f32) -> f32 {
        let y = super::noise::floor(time);
        if self.colour.is_empty() || y < 0.0 || y >= TABLE_YEARS as f32 {
            return 0.0;
        }
        self.colour[y as usize]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn without_variation_the_ring_time_is_g() {
        let t = YearTable::new(1, 0.0, 0.5, 0.0);
        for g in [0.0, 0.3, 7.25, 5000.5] {
            assert_eq!(t.time(g), g);
        }
        assert_eq!(t.colour_offset(3.2), 0.0);
    }

    #[test]
    fn widths_vary_but_time_stays_monotonic_and_continuous() {
        let t = YearTable::new(9, 0.4, 0.5, 0.2);
        let mut previous = t.time(0.0);
        let mut widths = Vec::new();
        let mut last_boundary = 0.0;
        for n in 1..20_000 {
            let g = n as f32 * 0.005;
            let time = t.time(g);
            assert!(time >= previous, "T decreases at G = {g}");
            assert!(time - previous < 0.1, "T jumps at G = {g}");
            if time.floor() > previous.floor() {
                widths.push(g - last_boundary);
                last_boundary = g;
            }
            previous = time;
        }
        let mean = widths.iter().sum::<f32>() / widths.len() as f32;
        let spread = widths.iter().map(|w| (w - mean).abs()).sum::<f32>() / widths.len() as f32;
        assert!((0.7..1.3).contains(&mean), "mean ring width {mean}");
        assert!(spread > 0.1, "ring widths barely vary: {spread}");
        assert_ne!(t.colour_offset(2.5), t.colour_offset(3.5));
    }
}
