//! Choosing the instruction set at run time (`is_x86_feature_detected!`) and compiling each
//! kernel once per instruction set.
//!
//! The kernels are generic over [`Kernels`] (a `simd::Simd` token with tile sizes) and
//! `#[inline(always)]`; [`multiversion!`] wraps such a generic body in one function per
//! instruction set, each with its own `#[target_feature]`, so the same source compiles to
//! AVX-512, AVX2 + FMA, or the x86-64 baseline (SSE2, no FMA); the elementwise loops are
//! vectorised by LLVM for the enabled set. Nothing is built
//! with `-C target-cpu=native`: one binary runs everywhere and picks the best path.
//!
//! An [`Isa`] can only be obtained for an instruction set the CPU has, which is what makes
//! calling the `#[target_feature]` functions sound.

use super::gemm::{Block, Rows, Store, Tiled, gemm, reduce};
use super::isa::{Isa, Level};
#[cfg(target_arch = "x86_64")]
use super::simd::{Avx2, Avx512};
use super::simd::{Portable, Simd};

impl Isa {
    /// The tile sizes of this level (they decide the padded shapes, see `layout::Shapes`).
    pub fn tiles(self) -> Tiles {
        match self.level() {
            #[cfg(target_arch = "x86_64")]
            Level::Avx512 => <Avx512 as Kernels>::TILES,
            #[cfg(target_arch = "x86_64")]
            Level::Avx2 => <Avx2 as Kernels>::TILES,
            _ => <Portable as Kernels>::TILES,
        }
    }
}

/// Tile sizes of one instruction set, as run-time numbers.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Tiles {
    /// Rows per tile of the gemms with hidden-sized outputs (W1 forward, W2^T backward).
    pub rm_hidden: usize,
    /// Rows per tile of the gemms with state-sized outputs (W2 forward, W1^T backward).
    pub rm_state: usize,
    /// Rows of X and of Y per tile of the gradient reductions.
    pub reduce: (usize, usize),
}

/// One instruction set's kernels: tile sizes fixed at compile time. Implemented by the
/// [`Simd`] tokens, so a kernel can only run where its instructions exist.
pub trait Kernels: Simd {
    const TILES: Tiles;
    /// [`gemm`] with `TILES.rm_hidden` rows per tile.
    fn gemm_hidden(self, a: Tiled, b: &[f32], c: &mut [f32], block: Block, store: Store);
    /// [`gemm`] with `TILES.rm_state` rows per tile.
    fn gemm_state(self, a: Tiled, b: &[f32], c: &mut [f32], block: Block, store: Store);
    /// [`reduce`] with `TILES.reduce` tiles, over `nvec` lane arrays of rows `stride` apart.
    fn reduce(self, x: Rows, y: Rows, stride_nvec: (usize, usize), lanes: &mut [f32]);
}

/// Columns of C per gemm tile are `NV * LANES`; every level uses at most 2, so blocks are
/// multiples of `2 * LANES` cells.
pub(crate) const MAX_NV: usize = 2;

/// Implements [`Kernels`] for a [`Simd`] token from literal tile sizes, so the constants and
/// the const generic arguments cannot disagree.
macro_rules! kernels {
    ($name:ty, hidden = ($rmh:literal, $nvh:literal), state = ($rms:literal, $nvs:literal), reduce = ($rx:literal, $ry:literal)) => {
        impl Kernels for $name {
            const TILES: Tiles = Tiles {
                rm_hidden: $rmh,
                rm_state: $rms,
                reduce: ($rx, $ry),
            };
            #[inline(always)]
            fn gemm_hidden(self, a: Tiled, b: &[f32], c: &mut [f32], block: Block, store: Store) {
                gemm::<Self, $rmh, $nvh>(self, a, b, c, block, store)
            }
            #[inline(always)]
            fn gemm_state(self, a: Tiled, b: &[f32], c: &mut [f32], block: Block, store: Store) {
                gemm::<Self, $rms, $nvs>(self, a, b, c, block, store)
            }
            #[inline(always)]
            fn reduce(self, x: Rows, y: Rows, stride_nvec: (usize, usize), lanes: &mut [f32]) {
                reduce::<Self, $rx, $ry>(self, x, y, stride_nvec, lanes)
            }
        }
    };
}

// Register budgets: AVX-512 has 32 zmm (one per lane array): 8 x 2 = 16 and 12 x 2 = 24
// accumulators in the gemms, 4 x 6 = 24 in the reductions. AVX2 has 16 ymm (two per lane
// array): 4 x 1 lane arrays = 8 ymm, reductions 2 x 3 = 12 ymm. The portable build gets
// small tiles the compiler can keep in SSE registers.
#[cfg(target_arch = "x86_64")]
kernels!(Avx512, hidden = (8, 2), state = (12, 2), reduce = (4, 6));
#[cfg(target_arch = "x86_64")]
kernels!(Avx2, hidden = (4, 1), state = (4, 1), reduce = (2, 3));
kernels!(Portable, hidden = (2, 1), state = (2, 1), reduce = (1, 2));

/// Defines `fn $name(isa: Isa, args..)` that runs the generic `$body::<K>(token, args..)`
/// compiled for `isa`'s instruction set.
macro_rules! multiversion {
    ($(#[$meta:meta])* $vis:vis fn $name:ident($($arg:ident : $ty:ty),* $(,)?) $(-> $ret:ty)? => $body:ident) => {
        $(#[$meta])*
        #[allow(clippy::too_many_arguments)]
        $vis fn $name(isa: $crate::nca::fused::isa::Isa, $($arg: $ty),*) $(-> $ret)? {
            use $crate::nca::fused::simd::Portable;
            #[cfg(target_arch = "x86_64")]
            use $crate::nca::fused::simd::{Avx2, Avx512};
            #[cfg(target_arch = "x86_64")]
            #[target_feature(enable = "avx512f,avx2,fma")]
            #[allow(clippy::too_many_arguments)]
            fn avx512(k: Avx512, $($arg: $ty),*) $(-> $ret)? {
                $body(k, $($arg),*)
            }
            #[cfg(target_arch = "x86_64")]
            #[target_feature(enable = "avx2,fma")]
            #[allow(clippy::too_many_arguments)]
            fn avx2(k: Avx2, $($arg: $ty),*) $(-> $ret)? {
                $body(k, $($arg),*)
            }
            #[cfg(target_arch = "x86_64")]
            if let Some(k) = Avx512::from_isa(isa) {
                // SAFETY: the token exists only if avx512f (and avx2, fma) were detected.
                return unsafe { avx512(k, $($arg),*) };
            }
            #[cfg(target_arch = "x86_64")]
            if isa.level() == $crate::nca::fused::isa::Level::Avx2 {
                if let Some(k) = Avx2::from_isa(isa) {
                    // SAFETY: the token exists only if avx2 and fma were detected.
                    return unsafe { avx2(k, $($arg),*) };
                }
            }
            $body(Portable, $($arg),*)
        }
    };
}
pub(crate) use multiversion;
