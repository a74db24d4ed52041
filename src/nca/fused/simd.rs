//! Explicit SIMD vectors of one lane array (16 floats) for the matrix kernels.
//!
//! Why not plain lane arrays: LLVM vectorises `[f32; 16]` loops only while a register tile
//! stays tiny; with the 16-24 accumulators a kernel needs to hide FMA latency it stopped
//! unrolling, kept the accumulators on the stack and emitted scalar FMAs (measured: 0.15 M
//! cell-updates/s on AVX-512 against 0.57 M for the portable build with a 2-array tile).
//!
//! Soundness: an [`Avx512`] or [`Avx2`] value is a token that exists only for an
//! instruction set the CPU has (`from_isa` checks the `isa::Isa`, which is only made
//! after `is_x86_feature_detected!`), and every method takes the token. So the `unsafe`
//! intrinsic calls below run only on CPUs that support them; loads and stores go through
//! `&[f32; 16]` references, which are in bounds by type.

use super::isa::{Isa, Level};
use super::lanes::LANES;

/// The vector operations the kernels use, on one lane array.
pub trait Simd: Copy {
    type V: Copy;
    fn zero(self) -> Self::V;
    fn splat(self, x: f32) -> Self::V;
    fn load(self, x: &[f32; LANES]) -> Self::V;
    fn store(self, v: Self::V, out: &mut [f32; LANES]);
    /// `a * b + c`
    fn madd(self, a: Self::V, b: Self::V, c: Self::V) -> Self::V;
    fn add(self, a: Self::V, b: Self::V) -> Self::V;
    /// `max(a, 0)`
    fn relu(self, a: Self::V) -> Self::V;
    /// `b` where `m > 0`, else 0.
    fn select_positive(self, m: Self::V, b: Self::V) -> Self::V;
}

/// Plain arrays, no FMA: the baseline of any target (SSE2 on x86-64).
#[derive(Clone, Copy)]
pub(crate) struct Portable;

impl Simd for Portable {
    type V = [f32; LANES];
    #[inline(always)]
    fn zero(self) -> Self::V {
        [0.0; LANES]
    }
    #[inline(always)]
    fn splat(self, x: f32) -> Self::V {
        [x; LANES]
    }
    #[inline(always)]
    fn load(self, x: &[f32; LANES]) -> Self::V {
        *x
    }
    #[inline(always)]
    fn store(self, v: Self::V, out: &mut [f32; LANES]) {
        *out = v;
    }
    #[inline(always)]
    fn madd(self, a: Self::V, b: Self::V, mut c: Self::V) -> Self::V {
        for l in 0..LANES {
            c[l] += a[l] * b[l];
        }
        c
    }
    #[inline(always)]
    fn add(self, mut a: Self::V, b: Self::V) -> Self::V {
        for l in 0..LANES {
            a[l] += b[l];
        }
        a
    }
    #[inline(always)]
    fn relu(self, mut a: Self::V) -> Self::V {
        for x in a.iter_mut() {
            *x = x.max(0.0);
        }
        a
    }
    #[inline(always)]
    fn select_positive(self, m: Self::V, mut b: Self::V) -> Self::V {
        for l in 0..LANES {
            b[l] = if m[l] > 0.0 { b[l] } else { 0.0 };
        }
        b
    }
}

#[cfg(target_arch = "x86_64")]
pub use x86::{Avx2, Avx512};

#[cfg(target_arch = "x86_64")]
mod x86 {
    use std::arch::x86_64::*;

    use super::{Isa, LANES, Level, Simd};

    /// AVX-512F: one zmm register per lane array. Only exists on CPUs that have it.
    #[derive(Clone, Copy)]
    pub struct Avx512(());

    impl Avx512 {
        pub fn from_isa(isa: Isa) -> Option<Self> {
            (isa.level() == Level::Avx512).then_some(Self(()))
        }
    }

    // SAFETY (every block in this impl): `self` proves avx512f was detected (see module
    // docs); the pointers come from `&[f32; 16]` references.
    impl Simd for Avx512 {
        type V = __m512;
        #[inline(always)]
        fn zero(self) -> __m512 {
            unsafe { _mm512_setzero_ps() }
        }
        #[inline(always)]
        fn splat(self, x: f32) -> __m512 {
            unsafe { _mm512_set1_ps(x) }
        }
        #[inline(always)]
        fn load(self, x: &[f32; LANES]) -> __m512 {
            unsafe { _mm512_loadu_ps(x.as_ptr()) }
        }
        #[inline(always)]
        fn store(self, v: __m512, out: &mut [f32; LANES]) {
            unsafe { _mm512_storeu_ps(out.as_mut_ptr(), v) }
        }
        #[inline(always)]
        fn madd(self, a: __m512, b: __m512, c: __m512) -> __m512 {
            unsafe { _mm512_fmadd_ps(a, b, c) }
        }
        #[inline(always)]
        fn add(self, a: __m512, b: __m512) -> __m512 {
            unsafe { _mm512_add_ps(a, b) }
        }
        #[inline(always)]
        fn relu(self, a: __m512) -> __m512 {
            unsafe { _mm512_max_ps(a, _mm512_setzero_ps()) }
        }
        #[inline(always)]
        fn select_positive(self, m: __m512, b: __m512) -> __m512 {
            unsafe {
                let positive = _mm512_cmp_ps_mask::<_CMP_GT_OQ>(m, _mm512_setzero_ps());
                _mm512_maskz_mov_ps(positive, b)
            }
        }
    }

    /// AVX2 + FMA: two ymm registers per lane array. Only exists on CPUs that have them.
    #[derive(Clone, Copy)]
    pub struct Avx2(());

    impl Avx2 {
        pub fn from_isa(isa: Isa) -> Option<Self> {
            matches!(isa.level(), Level::Avx2 | Level::Avx512).then_some(Self(()))
        }
    }

    // SAFETY (every block in this impl): `self` proves avx2 and fma were detected (see
    // module docs); the pointers come from `&[f32; 16]` references (8 floats at 0 and 8).
    impl Simd for Avx2 {
        type V = [__m256; 2];
        #[inline(always)]
        fn zero(self) -> Self::V {
            unsafe { [_mm256_setzero_ps(); 2] }
        }
        #[inline(always)]
        fn splat(self, x: f32) -> Self::V {
            unsafe { [_mm256_set1_ps(x); 2] }
        }
        #[inline(always)]
        fn load(self, x: &[f32; LANES]) -> Self::V {
            unsafe {
                [
                    _mm256_loadu_ps(x.as_ptr()),
                    _mm256_loadu_ps(x.as_ptr().add(8)),
                ]
            }
        }
        #[inline(always)]
        fn store(self, v: Self::V, out: &mut [f32; LANES]) {
            unsafe {
                _mm256_storeu_ps(out.as_mut_ptr(), v[0]);
                _mm256_storeu_ps(out.as_mut_ptr().add(8), v[1]);
            }
        }
        #[inline(always)]
        fn madd(self, a: Self::V, b: Self::V, c: Self::V) -> Self::V {
            unsafe {
                [
                    _mm256_fmadd_ps(a[0], b[0], c[0]),
                    _mm256_fmadd_ps(a[1], b[1], c[1]),
                ]
            }
        }
        #[inline(always)]
        fn add(self, a: Self::V, b: Self::V) -> Self::V {
            unsafe { [_mm256_add_ps(a[0], b[0]), _mm256_add_ps(a[1], b[1])] }
        }
        #[inline(always)]
        fn relu(self, a: Self::V) -> Self::V {
            unsafe {
                let z = _mm256_setzero_ps();
                [_mm256_max_ps(a[0], z), _mm256_max_ps(a[1], z)]
            }
        }
        #[inline(always)]
        fn select_positive(self, m: Self::V, b: Self::V) -> Self::V {
            unsafe {
                let z = _mm256_setzero_ps();
                let keep = |m, b| _mm256_and_ps(_mm256_cmp_ps::<_CMP_GT_OQ>(m, z), b);
                [keep(m[0], b[0]), keep(m[1], b[1])]
            }
        }
    }
}
