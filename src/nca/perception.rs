//! The fixed depthwise perception: five 3x3x3 filters applied to every channel with replicate
//! padding (DESIGN section 6):
//! - identity;
//! - Sobel along x, y, z: [-1, 0, 1] along the axis times [1, 2, 1] along the other two, / 4;
//! - the 27-point Laplacian, layers [[2,3,2],[3,6,3],[2,3,2]], [[3,6,3],[6,-88,6],[3,6,3]],
//!   [[2,3,2],[3,6,3],[2,3,2]], / 8.
//!
//! Output channel `c * 5 + f` is filter f of input channel c (the order of a grouped
//! convolution, and of the PyTorch reference).
//!
//! Two implementations give the same numbers:
//! - [`PerceptionImpl::Shifted`]: the filters are separable or sums of separable parts, so the
//!   padded input is filtered axis by axis with shifted slices (`narrow`) and additions. The
//!   Laplacian is written as box + [1,2,1]^3 + face neighbours - 97 centre (corner 1+1 = 2,
//!   edge 1+2 = 3, face 1+4+1 = 6, centre 1+8-97 = -88).
//! - [`PerceptionImpl::Conv`]: one grouped `conv3d` with the 5 kernels per channel.
//!
//! BURN-NOTES measured conv3d's backward on ndarray as a slow scalar loop (18 s vs 5 s); on
//! flex the two were close. Our own figures are in BENCHMARKS.md; the default is the faster.

use burn::tensor::module::conv3d;
use burn::tensor::ops::{ConvOptions, PadMode};
use burn::tensor::{Device, Tensor};
use serde::{Deserialize, Serialize};

use super::tensors::tensor_from;

/// Number of fixed filters per perceived channel (identity, Sobel x, y, z, Laplacian).
pub(crate) const FILTERS: usize = 5;
/// Position channels appended to the perception (x, y, z in [-1, 1]).
pub(crate) const POSITION_CHANNELS: usize = 3;

/// How the filters are computed.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum PerceptionImpl {
    #[default]
    Shifted,
    Conv,
}

/// The five kernels `[filter][a][b][c]`, weight of input voxel (x + a - 1, y + b - 1, z + c - 1).
// The kernels are written as the formula over their three offsets; iterators over the
// nested arrays would hide which offset is which.
#[allow(clippy::needless_range_loop)]
pub fn kernels() -> [[[[f32; 3]; 3]; 3]; FILTERS] {
    let smooth = [1.0, 2.0, 1.0];
    let diff = [-1.0, 0.0, 1.0];
    let mut k = [[[[0.0f32; 3]; 3]; 3]; FILTERS];
    k[0][1][1][1] = 1.0;
    for axis in 0..3 {
        for a in 0..3 {
            for b in 0..3 {
                for c in 0..3 {
                    let pick = |ax: usize, i: usize| if ax == axis { diff[i] } else { smooth[i] };
                    k[1 + axis][a][b][c] = pick(0, a) * pick(1, b) * pick(2, c) / 4.0;
                }
            }
        }
    }
    let outer = [[2.0, 3.0, 2.0], [3.0, 6.0, 3.0], [2.0, 3.0, 2.0]];
    let middle = [[3.0, 6.0, 3.0], [6.0, -88.0, 6.0], [3.0, 6.0, 3.0]];
    for b in 0..3 {
        for c in 0..3 {
            k[4][0][b][c] = outer[b][c] / 8.0;
            k[4][1][b][c] = middle[b][c] / 8.0;
            k[4][2][b][c] = outer[b][c] / 8.0;
        }
    }
    k
}

/// Replicate padding by one voxel on each side of x, y, z: `[C, X, Y, Z]` ->
/// `[C, X+2, Y+2, Z+2]`.
pub(crate) fn pad_replicate(x: Tensor<4>) -> Tensor<4> {
    x.pad([(1, 1), (1, 1), (1, 1)], PadMode::Edge)
}

impl PerceptionImpl {
    /// Perception of an already padded tensor `[C, X+2, Y+2, Z+2]` -> `[5 C, X, Y, Z]`.
    pub(crate) fn perceive_padded(self, padded: Tensor<4>) -> Tensor<4> {
        match self {
            PerceptionImpl::Shifted => shifted(padded),
            PerceptionImpl::Conv => grouped_conv(padded),
        }
    }

    /// Perception with replicate padding: `[C, X, Y, Z]` -> `[5 C, X, Y, Z]`.
    pub fn perceive(self, x: Tensor<4>) -> Tensor<4> {
        self.perceive_padded(pad_replicate(x))
    }
}

/// The three shifted views (offset -1, 0, +1) of a padded tensor along `dim`.
fn shifts(t: &Tensor<4>, dim: usize) -> [Tensor<4>; 3] {
    let n = t.dims()[dim] - 2;
    [0, 1, 2].map(|s| t.clone().narrow(dim, s, n))
}

/// 1D responses along one axis: i = centre, e = both neighbours, d = [-1, 0, 1],
/// s = [1, 2, 1], b = [1, 1, 1].
struct Axis {
    i: Tensor<4>,
    e: Tensor<4>,
    d: Tensor<4>,
}

impl Axis {
    fn of(t: &Tensor<4>, dim: usize) -> Self {
        let [lo, mid, hi] = shifts(t, dim);
        Self {
            e: lo.clone() + hi.clone(),
            d: hi - lo,
            i: mid,
        }
    }
    fn s(&self) -> Tensor<4> {
        self.e.clone() + self.i.clone().mul_scalar(2.0)
    }
    fn b(&self) -> Tensor<4> {
        self.e.clone() + self.i.clone()
    }
}

/// Separable evaluation on shifted slices. Names give the 1D filter along x, y, z in order
/// (e.g. `dss` = d along x, s along y, s along z = Sobel x before / 4).
fn shifted(padded: Tensor<4>) -> Tensor<4> {
    let [c, x2, y2, z2] = padded.dims();
    let (x, y, z) = (x2 - 2, y2 - 2, z2 - 2);
    let ax = Axis::of(&padded, 1); // each [C, X, Y+2, Z+2]
    let (xs, xb) = (ax.s(), ax.b());
    // y stage: [C, X, Y, Z+2]
    let from_i = Axis::of(&ax.i, 2);
    let ii = from_i.i.clone();
    let ie = from_i.e;
    let ds = Axis::of(&ax.d, 2).s();
    let from_s = Axis::of(&xs, 2);
    let sd = from_s.d.clone();
    let ss = from_s.s();
    let bb = Axis::of(&xb, 2).b();
    let ei = Axis::of(&ax.e, 2).i;
    // z stage: [C, X, Y, Z]
    let z_ii = Axis::of(&ii, 3);
    let iii = z_ii.i.clone();
    let iie = z_ii.e;
    let iei = Axis::of(&ie, 3).i;
    let dss = Axis::of(&ds, 3).s();
    let sds = Axis::of(&sd, 3).s();
    let z_ss = Axis::of(&ss, 3);
    let ssd = z_ss.d.clone();
    let sss = z_ss.s();
    let bbb = Axis::of(&bb, 3).b();
    let eii = Axis::of(&ei, 3).i;
    let lap = (bbb + sss + iie + iei + eii - iii.clone().mul_scalar(97.0)).mul_scalar(1.0 / 8.0);
    let filters = vec![
        iii,
        dss.mul_scalar(0.25),
        sds.mul_scalar(0.25),
        ssd.mul_scalar(0.25),
        lap,
    ];
    // [C, 5, X, Y, Z] -> [5 C, X, Y, Z]
    Tensor::stack::<5>(filters, 1).reshape([c * FILTERS, x, y, z])
}

/// The kernels as a grouped-convolution weight `[5 C, 1, 3, 3, 3]`.
fn conv_weight(channels: usize, device: &Device) -> Tensor<5> {
    let k = kernels();
    let mut data = Vec::with_capacity(channels * FILTERS * 27);
    for _ in 0..channels {
        for f in k.iter() {
            data.extend(f.iter().flatten().flatten());
        }
    }
    tensor_from(data, [channels * FILTERS, 1, 3, 3, 3], device)
}

/// One grouped (depthwise) `conv3d` without padding on the padded input.
fn grouped_conv(padded: Tensor<4>) -> Tensor<4> {
    let [c, x2, y2, z2] = padded.dims();
    let weight = conv_weight(c, &padded.device());
    let out = conv3d(
        padded.reshape([1, c, x2, y2, z2]),
        weight,
        None,
        ConvOptions::new([1; 3], [0; 3], [1; 3], c),
    );
    out.reshape([c * FILTERS, x2 - 2, y2 - 2, z2 - 2])
}
