//! The radial growth-rate grid R (n_h x n_a x n_r) of Mokume section 5.2.1: R discretises
//! dG/dr (relative to `years_per_unit`); G is its integral along r from the pith.
//!
//! Interpolation (a decision, see docs/DESIGN.md): cubic B-splines over height (end nodes
//! repeated) and over azimuth (periodic, or end nodes repeated when the grid covers only a
//! pinned azimuth range, as fitted grids do), and linear in r between radial nodes (so G is
//! piecewise quadratic and C1 in r). The reference code uses smoothstep in height and
//! Catmull-Rom in azimuth; smoothstep's flat ends turned smooth height variation into visible
//! ring staircases, and Catmull-Rom can undershoot between nodes, whereas B-spline weights
//! are smooth and never negative.
//! With every node clamped to at least `min_rate`, the interpolated rate is then at least
//! `min_rate` everywhere, so G is strictly increasing along r whatever R holds: rings never
//! cross. Because G is linear in the clamped nodes, each (height, azimuth) column's integral
//! is precomputed at the radial nodes and a point costs 8 column lookups.

use std::f32::consts::TAU;

use super::pith::Cylindrical;

/// Uniform cubic B-spline weights for nodes j-1, j, j+1, j+2 at fraction t in [0, 1).
fn bspline_weights(t: f32) -> [f32; 4] {
    let t2 = t * t;
    let t3 = t2 * t;
    [
        (1.0 - t).powi(3) / 6.0,
        (3.0 * t3 - 6.0 * t2 + 4.0) / 6.0,
        (-3.0 * t3 + 3.0 * t2 + 3.0 * t + 1.0) / 6.0,
        t3 / 6.0,
    ]
}

/// The (flat grid column index, weight) pairs of the height/azimuth interpolation: up to
/// 4 heights x 4 azimuths (repeated indices at the height ends are allowed).
#[derive(Clone, Copy, Debug)]
pub(crate) struct ColumnWeights {
    pub columns: [usize; 16],
    pub weights: [f32; 16],
    pub len: usize,
}

#[derive(Clone, Debug, PartialEq)]
pub struct RateGrid {
    pub n_h: usize,
    pub n_a: usize,
    pub n_r: usize,
    /// Raw rates as configured or fitted, `(ih * n_a + ia) * n_r + ir`.
    pub rates: Vec<f32>,
    pub min_rate: f32,
    pub height_range: [f32; 2],
    pub radius_range: [f32; 2],
    /// Azimuths (radians, `[start, end]`, end - start <= 2 pi) spanned by the azimuth nodes,
    /// clamped at both ends like heights; `None`: nodes evenly around the full circle
    /// (periodic). A fitted cube far from the pith sees only a narrow wedge of azimuths, so
    /// the fit spreads all n_a nodes over that wedge instead of over 360 degrees.
    pub azimuth_range: Option<[f32; 2]>,
    /// Integral of the clamped rate from r = 0 to each radial node, per column.
    cumulative: Vec<f32>,
}

impl RateGrid {
    /// `rates.len()` must be n_h * n_a * n_r (configs are validated before this is called).
    pub fn new(
        [n_h, n_a, n_r]: [usize; 3],
        rates: Vec<f32>,
        min_rate: f32,
        height_range: [f32; 2],
        radius_range: [f32; 2],
    ) -> Self {
        assert_eq!(rates.len(), n_h * n_a * n_r, "rate grid size");
        let mut grid = Self {
            n_h,
            n_a,
            n_r,
            rates,
            min_rate,
            height_range,
            radius_range,
            azimuth_range: None,
            cumulative: Vec::new(),
        };
        grid.cumulative = grid.integrate_columns();
        grid
    }

    /// The uniform grid (every rate 1): G = years_per_unit x r.
    pub fn uniform(
        dims: [usize; 3],
        min_rate: f32,
        height_range: [f32; 2],
        radius_range: [f32; 2],
    ) -> Self {
        Self::new(
            dims,
            vec![1.0; dims.iter().product()],
            min_rate,
            height_range,
            radius_range,
        )
    }

    /// The same grid with its azimuth nodes spread over `[start, end]` (radians) instead of
    /// the full circle.
    pub fn with_azimuth_range(mut self, range: Option<[f32; 2]>) -> Self {
        self.azimuth_range = range;
        self
    }

    fn radial_step(&self) -> f32 {
        (self.radius_range[1] - self.radius_range[0]) / (self.n_r - 1) as f32
    }

    fn clamped(&self, index: usize) -> f32 {
        self.rates[index].max(self.min_rate)
    }

    fn integrate_columns(&self) -> Vec<f32> {
        let dr = self.radial_step();
        let mut cumulative = vec![0.0; self.rates.len()];
        for column in 0..self.n_h * self.n_a {
            let base = column * self.n_r;
            let mut acc = self.radius_range[0] * self.clamped(base);
            cumulative[base] = acc;
            for k in 1..self.n_r {
                acc += 0.5 * dr * (self.clamped(base + k - 1) + self.clamped(base + k));
                cumulative[base + k] = acc;
            }
        }
        cumulative
    }

    /// Height and azimuth interpolation weights at a point.
    pub(crate) fn column_weights(&self, c: &Cylindrical) -> ColumnWeights {
        let [h0, h1] = self.height_range;
        let last = self.n_h as isize - 1;
        let xh = if self.n_h == 1 {
            0.0
        } else {
            ((c.h - h0) / (h1 - h0) * last as f32).clamp(0.0, last as f32)
        };
        let ih = xh.floor();
        let wh = bspline_weights(xh - ih);
        let ih = ih as isize;
        let (x, periodic) = self.azimuth_coordinate(c.phi);
        let j = x.floor();
        let wa = bspline_weights(x - j);
        let j = j as isize;
        let last_a = self.n_a as isize - 1;
        let mut out = ColumnWeights {
            columns: [0; 16],
            weights: [0.0; 16],
            len: 0,
        };
        for (mh, wh) in wh.iter().enumerate() {
            if *wh == 0.0 {
                continue;
            }
            let ih = (ih - 1 + mh as isize).clamp(0, last) as usize;
            for (m, w) in wa.iter().enumerate() {
                let ia = j - 1 + m as isize;
                let ia = if periodic {
                    ia.rem_euclid(self.n_a as isize) as usize
                } else {
                    ia.clamp(0, last_a) as usize
                };
                out.columns[out.len] = ih * self.n_a + ia;
                out.weights[out.len] = wh * w;
                out.len += 1;
            }
        }
        out
    }

    /// The continuous azimuth node coordinate of `phi` and whether the nodes wrap around.
    /// With an azimuth range, phi is first brought within a turn after the range start; an
    /// angle outside the range is clamped to the end it is angularly closer to.
    fn azimuth_coordinate(&self, phi: f32) -> (f32, bool) {
        let Some([start, end]) = self.azimuth_range else {
            return (phi / TAU * self.n_a as f32, true);
        };
        let mut a = start + (phi - start).rem_euclid(TAU);
        if a > end {
            let past_end = a - end;
            let before_start = start + TAU - a;
            a = if past_end < before_start { end } else { start };
        }
        let last = (self.n_a - 1) as f32;
        (((a - start) / (end - start) * last).clamp(0.0, last), false)
    }

    /// Where r falls among the radial nodes: (cell k, fraction in the cell), or the ends.
    fn radial_cell(&self, r: f32) -> RadialCell {
        let [r0, r1] = self.radius_range;
        if r <= r0 {
            RadialCell::Inside
        } else if r >= r1 {
            RadialCell::Outside
        } else {
            let x = (r - r0) / self.radial_step();
            let k = (x.floor() as usize).min(self.n_r - 2);
            RadialCell::Cell(k, x - k as f32)
        }
    }

    /// Integral of one column's clamped rate from 0 to r (`cell` = `radial_cell(r)`).
    fn column_integral(&self, column: usize, r: f32, cell: &RadialCell) -> f32 {
        let base = column * self.n_r;
        match *cell {
            RadialCell::Inside => r * self.clamped(base),
            RadialCell::Outside => {
                let last = base + self.n_r - 1;
                self.cumulative[last] + (r - self.radius_range[1]) * self.clamped(last)
            }
            RadialCell::Cell(k, f) => {
                let dr = self.radial_step();
                let (a, b) = (self.clamped(base + k), self.clamped(base + k + 1));
                self.cumulative[base + k] + dr * (a * (f - 0.5 * f * f) + b * 0.5 * f * f)
            }
        }
    }

    /// G / years_per_unit at a point: the interpolated integral of the rate from the pith.
    pub fn integral(&self, c: &Cylindrical) -> f32 {
        let w = self.column_weights(c);
        let cell = self.radial_cell(c.r);
        (0..w.len)
            .map(|i| w.weights[i] * self.column_integral(w.columns[i], c.r, &cell))
            .sum()
    }

    /// The interpolated (clamped) rate dG/dr / years_per_unit at a point.
    pub fn rate(&self, c: &Cylindrical) -> f32 {
        let w = self.column_weights(c);
        let cell = self.radial_cell(c.r);
        (0..w.len)
            .map(|i| {
                let base = w.columns[i] * self.n_r;
                let value = match cell {
                    RadialCell::Inside => self.clamped(base),
                    RadialCell::Outside => self.clamped(base + self.n_r - 1),
                    RadialCell::Cell(k, f) => {
                        (1.0 - f) * self.clamped(base + k) + f * self.clamped(base + k + 1)
                    }
                };
                w.weights[i] * value
            })
            .sum()
    }

    /// Gradient of [`RateGrid::integral`] with respect to the raw rates: pushes
    /// (flat rate index, d integral / d rate) pairs into `out` (cleared first). Rates below
    /// `min_rate` are clamped and get zero gradient. Used by the fit (G is linear in R).
    pub fn integral_gradient(&self, c: &Cylindrical, out: &mut Vec<(usize, f32)>) {
        out.clear();
        let w = self.column_weights(c);
        let dr = self.radial_step();
        let cell = self.radial_cell(c.r);
        let mut push = |index: usize, d: f32| {
            if d != 0.0 && self.rates[index] > self.min_rate {
                out.push((index, d));
            }
        };
        for i in 0..w.len {
            let base = w.columns[i] * self.n_r;
            let wt = w.weights[i];
            match cell {
                RadialCell::Inside => push(base, wt * c.r),
                cell => {
                    let (full, partial) = match cell {
                        RadialCell::Cell(k, f) => (k, Some((k, f))),
                        _ => (self.n_r - 1, None),
                    };
                    // r0 * R_0 plus the trapezoids of the `full` complete cells.
                    let mut d = vec![0.0f32; self.n_r];
                    d[0] += self.radius_range[0];
                    for m in 0..full {
                        d[m] += 0.5 * dr;
                        d[m + 1] += 0.5 * dr;
                    }
                    match partial {
                        Some((k, f)) => {
                            d[k] += dr * (f - 0.5 * f * f);
                            d[k + 1] += dr * 0.5 * f * f;
                        }
                        None => d[self.n_r - 1] += c.r - self.radius_range[1],
                    }
                    for (m, dm) in d.into_iter().enumerate() {
                        push(base + m, wt * dm);
                    }
                }
            }
        }
    }
}

#[derive(Clone, Copy)]
enum RadialCell {
    Inside,
    Outside,
    Cell(usize, f32),
}
