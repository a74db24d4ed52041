//! Stateless lattice noise for the procedural wood model: 1D value noise, 3D value noise,
//! 3D gradient (Perlin) noise and fractal sums of it.
//!
//! Every lattice value is a hash of the seed and the integer lattice coordinates, so a point
//! always gets the same value on any thread and in any evaluation order. One SplitMix64 round
//! per lattice point (rather than `rng::hash3`'s four) keeps noise cheap: the model evaluates
//! a few dozen lattice points per sample and must reach millions of samples per second.

use glam::Vec3;

use crate::rng::mix64;

const KX: u64 = 0x9E37_79B9_7F4A_7C15;
const KY: u64 = 0xC2B2_AE3D_27D4_EB4F;
const KZ: u64 = 0x1656_67B1_9E37_79F9;

/// floor(x) without a libm call: the default x86-64 target has no SSE4.1 `roundss`, so
/// `f32::floor` is a function call, and the model floors a few dozen times per point. Exact
/// for |x| < 2^31.
#[inline]
pub fn floor(x: f32) -> f32 {
    let t = x as i32 as f32;
    if t > x { t - 1.0 } else { t }
}

/// [`floor`] for each component.
#[inline]
pub(crate) fn floor3(p: Vec3) -> Vec3 {
    Vec3::new(floor(p.x), floor(p.y), floor(p.z))
}

/// Fractional part x - floor(x), in [0, 1).
#[inline]
pub(crate) fn fract(x: f32) -> f32 {
    x - floor(x)
}

/// One hash of a seed and a 3D lattice point.
#[inline]
pub(crate) fn lattice_hash(seed: u64, i: i32, j: i32, k: i32) -> u64 {
    mix64(
        seed ^ (i as i64 as u64).wrapping_mul(KX)
            ^ (j as i64 as u64).wrapping_mul(KY)
            ^ (k as i64 as u64).wrapping_mul(KZ),
    )
}

/// Three independent uniform numbers in [0, 1) (21 bits each) from one hash.
#[inline]
pub(crate) fn hash_units3(h: u64) -> Vec3 {
    let bits = mix64(h ^ KZ);
    let unit21 = |shift: u32| ((bits >> shift) & 0x1F_FFFF) as f32 / (1u32 << 21) as f32;
    Vec3::new(unit21(0), unit21(21), unit21(42))
}

/// A hash mapped to [-1, 1).
#[inline]
fn signed(h: u64) -> f32 {
    crate::rng::unit(h) * 2.0 - 1.0
}

/// Quintic fade 6t^5 - 15t^4 + 10t^3: C2 continuous interpolation between lattice points.
#[inline]
fn fade(t: f32) -> f32 {
    t * t * t * (t * (t * 6.0 - 15.0) + 10.0)
}

#[inline]
fn lerp(a: f32, b: f32, t: f32) -> f32 {
    a + (b - a) * t
}

/// Trilinear blend of the 8 lattice corners around a point, with fade weights (u, v, w).
#[inline]
fn trilinear(corner: impl Fn(i32, i32, i32) -> f32, u: f32, v: f32, w: f32) -> f32 {
    let face = |c: i32| {
        lerp(
            lerp(corner(0, 0, c), corner(1, 0, c), u),
            lerp(corner(0, 1, c), corner(1, 1, c), u),
            v,
        )
    };
    lerp(face(0), face(1), w)
}

/// Smooth 3D value noise in [-1, 1] with lattice spacing 1 (trilinear with quintic fade).
pub(crate) fn value3(seed: u64, p: Vec3) -> f32 {
    let f = floor3(p);
    let (i, j, k) = (f.x as i32, f.y as i32, f.z as i32);
    let d = p - f;
    let at = |a: i32, b: i32, c: i32| signed(lattice_hash(seed, i + a, j + b, k + c));
    trilinear(at, fade(d.x), fade(d.y), fade(d.z))
}

/// Dot product of one of the 12 cube-edge gradients of improved Perlin noise with (x, y, z).
#[inline]
fn grad(h: u64, x: f32, y: f32, z: f32) -> f32 {
    match (h >> 59) % 12 {
        0 => x + y,
        1 => -x + y,
        2 => x - y,
        3 => -x - y,
        4 => x + z,
        5 => -x + z,
        6 => x - z,
        7 => -x - z,
        8 => y + z,
        9 => -y + z,
        10 => y - z,
        _ => -y - z,
    }
}

/// 3D gradient noise (Perlin 2002) with lattice spacing 1, roughly in [-1, 1].
pub(crate) fn gradient3(seed: u64, p: Vec3) -> f32 {
    let f = floor3(p);
    let (i, j, k) = (f.x as i32, f.y as i32, f.z as i32);
    let d = p - f;
    let g = |a: i32, b: i32, c: i32| {
        grad(
            lattice_hash(seed, i + a, j + b, k + c),
            d.x - a as f32,
            d.y - b as f32,
            d.z - c as f32,
        )
    };
    // The raw range of improved Perlin noise is about [-1.04, 1.04]; most values lie well inside.
    trilinear(g, fade(d.x), fade(d.y), fade(d.z)).clamp(-1.0, 1.0)
}

/// Fractal sum of `octaves` gradient-noise octaves (each at twice the frequency and half the
/// amplitude of the previous), normalised so the amplitudes sum to 1.
pub fn fbm3(seed: u64, p: Vec3, octaves: u32) -> f32 {
    let (mut sum, mut amp, mut norm, mut q) = (0.0, 1.0, 0.0, p);
    for o in 0..octaves.max(1) {
        sum += amp * gradient3(seed.wrapping_add(o as u64), q);
        norm += amp;
        amp *= 0.5;
        q *= 2.0;
    }
    sum / norm
}

/// A vector of three independent [`fbm3`] components (for displacing lookup points).
pub(crate) fn vector_fbm3(seed: u64, p: Vec3, octaves: u32) -> Vec3 {
    Vec3::new(
        fbm3(mix64(seed ^ 1), p, octaves),
        fbm3(mix64(seed ^ 2), p, octaves),
        fbm3(mix64(seed ^ 3), p, octaves),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fast_floor_matches_floor() {
        for x in [
            -2.5f32,
            -2.0,
            -0.3,
            -0.0,
            0.0,
            0.7,
            1.0,
            3.999,
            1e6 + 0.5,
            -1e6 - 0.5,
        ] {
            assert_eq!(floor(x), x.floor(), "{x}");
            assert!((0.0..1.0).contains(&fract(x)), "{x}");
        }
    }

    #[test]
    fn noise_is_deterministic_bounded_and_continuous() {
        let p = Vec3::new(1.3, -2.7, 0.45);
        assert_eq!(gradient3(5, p), gradient3(5, p));
        assert_ne!(gradient3(5, p), gradient3(6, p));
        let eps = Vec3::splat(1e-3);
        for n in 0..200 {
            let q = Vec3::new(n as f32 * 0.37, n as f32 * -0.21, n as f32 * 0.13);
            for v in [gradient3(1, q), value3(1, q), fbm3(1, q, 3)] {
                assert!((-1.0..=1.0).contains(&v), "{v}");
            }
            assert!((gradient3(1, q) - gradient3(1, q + eps)).abs() < 0.02);
            assert!((value3(1, q) - value3(1, q + eps)).abs() < 0.02);
        }
    }

    #[test]
    fn gradient_noise_vanishes_on_the_lattice_and_varies_between() {
        assert_eq!(gradient3(3, Vec3::new(2.0, -1.0, 4.0)), 0.0);
        let spread: f32 = (0..100)
            .map(|n| gradient3(3, Vec3::new(n as f32 * 0.53 + 0.25, 0.5, 0.3)).abs())
            .sum::<f32>()
            / 100.0;
        assert!(spread > 0.1, "mean |noise| {spread}");
    }
}
