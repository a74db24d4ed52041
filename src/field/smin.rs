//! The power smooth minimum of Larsson et al. 2022 (after Quilez) and its adaptive exponent.

/// smin(a, b, k) = (a^k b^k / (a^k + b^k))^(1/k) for a, b >= 0, written as
/// m / (1 + (m/M)^k)^(1/k) with m = min, M = max so it neither overflows nor divides by zero.
/// It is <= min(a, b), continuous, and 1-homogeneous (smin(c a, c b) = c smin(a, b)), so the
/// union's fillet grows with time as in real stem-to-knot joints.
pub fn power_smin(a: f32, b: f32, k: f32) -> f32 {
    let (m, big) = if a < b { (a, b) } else { (b, a) };
    if m <= 0.0 {
        return m.max(0.0);
    }
    m / (1.0 + (m / big).powf(k)).powf(1.0 / k)
}

/// The amount of smoothing delta = smin - min (<= 0).
pub fn smoothing(a: f32, b: f32, k: f32) -> f32 {
    power_smin(a, b, k) - a.min(b)
}

/// Adaptive exponent (Larsson 2022, section 4.2.1): `k_knot` inside the knot (t_s > t_b, a
/// sharp knot edge) and `k_stem` outside (a wide distortion), blended over `width` years of
/// t_delta = t_s - t_b.
pub(crate) fn adaptive_k(t_delta: f32, k_stem: f32, k_knot: f32, width: f32) -> f32 {
    0.5 * (k_knot - k_stem) * t_delta / (width + t_delta.abs()) + 0.5 * (k_knot + k_stem)
}

/// Smoothstep between edges e0 < e1.
pub fn smoothstep(e0: f32, e1: f32, x: f32) -> f32 {
    let t = ((x - e0) / (e1 - e0)).clamp(0.0, 1.0);
    t * t * (3.0 - 2.0 * t)
}
