//! The stem time at fixed points as a linear function of the rate grid.
//!
//! In step 2 the pith axis is fixed, so each point's cylindrical coordinates and its
//! interpolation weights never change, and t_s(p) = years_per_unit x sum_e c_pe max(R_e,
//! min_rate) is linear in the clamped rates (`field::rate_grid`). The coefficients c_pe are
//! exactly `RateGrid::integral_gradient` of a grid whose rates all lie above the clamp, so they
//! are computed once and stored sparsely (one row per point); every iteration then costs one
//! sparse product for the values and one for the gradient.

use glam::Vec3;
use rayon::prelude::*;

use crate::field::{PithAxis, RateGrid};

/// Rows of (rate index, coefficient), one row per point.
#[derive(Clone, Debug, Default)]
pub struct StemBasis {
    offsets: Vec<usize>,
    index: Vec<u32>,
    coef: Vec<f32>,
}

impl StemBasis {
    /// Coefficients of `points` for a grid with the layout (dims, ranges) of `grid`.
    pub fn new(grid: &RateGrid, pith: &PithAxis, points: &[Vec3]) -> Self {
        let unclamped = RateGrid::new(
            [grid.n_h, grid.n_a, grid.n_r],
            // Any rates above the clamp: the coefficients do not depend on them.
            vec![1.0 + grid.min_rate; grid.rates.len()],
            grid.min_rate,
            grid.height_range,
            grid.radius_range,
        )
        .with_azimuth_range(grid.azimuth_range);
        let rows: Vec<Vec<(usize, f32)>> = points
            .par_iter()
            .map_init(Vec::new, |buf, &p| {
                unclamped.integral_gradient(&pith.cylindrical(p), buf);
                merge_duplicates(buf)
            })
            .collect();
        let mut basis = StemBasis {
            offsets: Vec::with_capacity(points.len() + 1),
            ..Default::default()
        };
        basis.offsets.push(0);
        for row in rows {
            for (i, c) in row {
                basis.index.push(i as u32);
                basis.coef.push(c);
            }
            basis.offsets.push(basis.index.len());
        }
        basis
    }

    pub fn len(&self) -> usize {
        self.offsets.len() - 1
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Integral of the clamped rates at every point (the stem time / years_per_unit).
    pub fn integrals(&self, clamped: &[f32]) -> Vec<f32> {
        (0..self.len())
            .into_par_iter()
            .map(|p| {
                let (a, b) = (self.offsets[p], self.offsets[p + 1]);
                (a..b)
                    .map(|e| self.coef[e] * clamped[self.index[e] as usize])
                    .sum()
            })
            .collect()
    }

    /// sum_p weight_p x d integral_p / d clamped rate, for every rate (length `n_rates`).
    /// Points are summed in fixed chunks, each chunk in parallel and the chunks in order, so
    /// the result does not depend on thread scheduling (the fit must be deterministic).
    pub fn gradient(&self, weights: &[f32], n_rates: usize) -> Vec<f32> {
        let chunks: Vec<Vec<f32>> = (0..self.len())
            .collect::<Vec<usize>>()
            .par_chunks(REDUCE_CHUNK)
            .map(|points| {
                let mut acc = vec![0.0f32; n_rates];
                for &p in points {
                    let w = weights[p];
                    if w != 0.0 {
                        for e in self.offsets[p]..self.offsets[p + 1] {
                            acc[self.index[e] as usize] += w * self.coef[e];
                        }
                    }
                }
                acc
            })
            .collect();
        let mut total = vec![0.0f32; n_rates];
        for chunk in chunks {
            total.iter_mut().zip(chunk).for_each(|(t, c)| *t += c);
        }
        total
    }
}

/// Points per partial sum of a deterministic parallel reduction.
pub(crate) const REDUCE_CHUNK: usize = 4096;

/// Sums the coefficients of repeated indices (the height interpolation repeats end nodes).
fn merge_duplicates(entries: &[(usize, f32)]) -> Vec<(usize, f32)> {
    let mut sorted = entries.to_vec();
    sorted.sort_unstable_by_key(|e| e.0);
    let mut out: Vec<(usize, f32)> = Vec::with_capacity(sorted.len());
    for (i, c) in sorted {
        match out.last_mut() {
            Some(last) if last.0 == i => last.1 += c,
            _ => out.push((i, c)),
        }
    }
    out
}
