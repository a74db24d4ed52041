//! The iso-contour loss (Mokume 5.2.2, DESIGN section 5): every contour should lie on one
//! iso-surface of G. For contour C with median m_C of G over its points,
//!
//!   L = sum_C sum_{p in C} |G(p) - m_C| / (number of points).
//!
//! The median (as in the authors' code) rather than the mean keeps a few stray pixels of a
//! merged band from pulling the reference value. Gradient: with m_C = G(p_k) for the median
//! point p_k,
//!
//!   dL/dG(p) = sign(G(p) - m_C) / N for p != p_k,
//!   dL/dG(p_k) = (#points below m_C - #points above m_C) / N,
//!
//! the second line because moving the median point moves the reference of all the others.
//! For an odd count it is 0 (the median minimises the sum, so its own change does not move
//! L to first order); for an even count (upper middle) it is +-1. This is exact wherever no
//! two values of a contour coincide.

use super::contours::ContourSet;

/// The median of `values` (the upper middle one for an even count).
pub fn median(values: &[f32]) -> f32 {
    let mut v = values.to_vec();
    let k = v.len() / 2;
    let (_, m, _) = v.select_nth_unstable_by(k, f32::total_cmp);
    *m
}

/// The median of G over each contour.
pub(crate) fn contour_medians(set: &ContourSet, values: &[f32]) -> Vec<f32> {
    set.ranges
        .iter()
        .map(|&(a, b)| median(&values[a..b]))
        .collect()
}

/// The loss for G values at `set.points` (`values[i]` at point i). With `grad`, also writes
/// dL/dG at every point (overwriting).
pub fn iso_loss(set: &ContourSet, values: &[f32], mut grad: Option<&mut [f32]>) -> f32 {
    let total = set.points.len().max(1) as f64;
    let mut sum = 0.0f64;
    for &(a, b) in &set.ranges {
        let v = &values[a..b];
        let m = median(v);
        sum += v.iter().map(|x| (x - m).abs() as f64).sum::<f64>();
        if let Some(g) = grad.as_deref_mut() {
            let below = v.iter().filter(|&&x| x < m).count() as f32;
            let above = v.iter().filter(|&&x| x > m).count() as f32;
            let k = v.iter().position(|&x| x == m).unwrap_or(0);
            for (i, x) in v.iter().enumerate() {
                g[a + i] = sign(x - m) / total as f32;
            }
            g[a + k] = (below - above) / total as f32;
        }
    }
    (sum / total) as f32
}

/// -1, 0 or 1 (`f32::signum` gives 1 for 0).
pub fn sign(x: f32) -> f32 {
    if x > 0.0 {
        1.0
    } else if x < 0.0 {
        -1.0
    } else {
        0.0
    }
}
