//! Lane arrays: the unit of SIMD work of the fused kernels.
//!
//! Cells are processed 16 at a time: a lane array `[f32; LANES]` is one zmm register
//! (AVX-512), two ymm (AVX2) or, in the portable build, whatever the compiler makes of
//! sixteen floats. The matrix kernels load and store lane arrays through [`super::simd`];
//! elementwise loops (perception, masks) are plain loops over slices, which the compiler
//! vectorises by itself.

/// Cells per lane array.
pub const LANES: usize = 16;

/// The `LANES` values starting at `at`.
#[inline(always)]
pub fn lane(data: &[f32], at: usize) -> &[f32; LANES] {
    data[at..at + LANES].try_into().expect("LANES values")
}

/// The `LANES` values starting at `at`, mutable.
#[inline(always)]
pub(crate) fn lane_mut(data: &mut [f32], at: usize) -> &mut [f32; LANES] {
    (&mut data[at..at + LANES])
        .try_into()
        .expect("LANES values")
}

/// `n` rounded up to a multiple of `m`.
pub(crate) fn round_up(n: usize, m: usize) -> usize {
    n.div_ceil(m) * m
}
