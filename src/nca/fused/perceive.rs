//! The fixed depthwise perception of a block of cells, written into the block's input
//! matrix (`nca::perception` has the filters; here they are evaluated line by line).
//!
//! A block is cut into pieces of z-lines. For one channel and one piece, the 3 x 3
//! neighbouring z-lines (x +- 1, y +- 1, replicate-clamped) are first combined across x and
//! y into six lines (the xy parts of the filters), one value beyond each end of the piece
//! (z clamped), then combined along z:
//! - identity = C(z)
//! - Sobel x = [1,2,1]_z (Dx) / 4, Sobel y = [1,2,1]_z (Dy) / 4, Sobel z = (S(z+1) - S(z-1)) / 4
//! - Laplacian = (box + [1,2,1]^3 + the six face neighbours - 97 centre) / 8
//!   = (B(z-1) + B(z) + B(z+1) + S(z-1) + 2 S(z) + S(z+1) + F(z) + C(z-1) + C(z+1) - 97 C(z)) / 8
//!
//! where, over the 3 x 3 lines L[a][b] (a along x, b along y), S = [1,2,1] x [1,2,1],
//! Dx = [-1,0,1] x [1,2,1], Dy = [1,2,1] x [-1,0,1], B = box, F = the four xy face
//! neighbours, C = centre. The loops over z run over contiguous slices and vectorise.

use super::inputs::FixedInputs;
use super::layout::{Dims, Shapes};
use crate::nca::perception::FILTERS;

/// Longest z-piece (cells); at least the largest block.
pub(crate) const MAX_PIECE: usize = 256;

/// The 3 x 3 z-lines around (x, y), replicate-clamped: `[a][b]` is (x + a - 1, y + b - 1).
pub(crate) type Lines<'a> = [[&'a [f32]; 3]; 3];

/// Offsets of the 3 x 3 z-lines around (x, y) in a channel plane `[X, Y, Z]`,
/// replicate-clamped: `[a][b]` is line (x + a - 1, y + b - 1).
#[inline(always)]
pub fn neighbour_offsets(dims: Dims, x: usize, y: usize) -> [[usize; 3]; 3] {
    let [nx, ny, _] = dims.0;
    let xs = [x.saturating_sub(1), x, (x + 1).min(nx - 1)];
    let ys = [y.saturating_sub(1), y, (y + 1).min(ny - 1)];
    let at = |a: usize, b: usize| dims.line(xs[a], ys[b]);
    [
        [at(0, 0), at(0, 1), at(0, 2)],
        [at(1, 0), at(1, 1), at(1, 2)],
        [at(2, 0), at(2, 1), at(2, 2)],
    ]
}

/// The lines at `offsets` (from [`neighbour_offsets`]) of one channel plane, `nz` long.
#[inline(always)]
pub(crate) fn lines_at<'a>(plane: &'a [f32], offsets: &[[usize; 3]; 3], nz: usize) -> Lines<'a> {
    let line = |a: usize, b: usize| &plane[offsets[a][b]..][..nz];
    [
        [line(0, 0), line(0, 1), line(0, 2)],
        [line(1, 0), line(1, 1), line(1, 2)],
        [line(2, 0), line(2, 1), line(2, 2)],
    ]
}

/// The six xy lines of the forward filters, over a piece plus one value at each end:
/// index j is z = clamp(z0 - 1 + j). One piece at a time: staging a whole block through
/// the xy stage first (to avoid store-forwarding stalls in the z stage) measured slower.
pub struct ForwardScratch {
    s: Vec<f32>,
    dx: Vec<f32>,
    dy: Vec<f32>,
    b: Vec<f32>,
    f: Vec<f32>,
    c: Vec<f32>,
}

impl Default for ForwardScratch {
    fn default() -> Self {
        let line = || vec![0.0f32; MAX_PIECE + 2];
        Self {
            s: line(),
            dx: line(),
            dy: line(),
            b: line(),
            f: line(),
            c: line(),
        }
    }
}

/// The lines restricted to z in [z0, z0 + len).
#[inline(always)]
pub(crate) fn slice_lines<'a>(l: &Lines<'a>, z0: usize, len: usize) -> Lines<'a> {
    let cut = |a: usize, b: usize| &l[a][b][z0..z0 + len];
    [
        [cut(0, 0), cut(0, 1), cut(0, 2)],
        [cut(1, 0), cut(1, 1), cut(1, 2)],
        [cut(2, 0), cut(2, 1), cut(2, 2)],
    ]
}

/// xy combinations of the lines at z in [z0, z0 + len), written to `at..at + len` of each
/// scratch line. (Written out term by term: array `map`s in this loop were not inlined.)
#[inline(always)]
fn xy_forward(l: &Lines, z0: usize, len: usize, t: &mut ForwardScratch, at: usize) {
    let [[l00, l01, l02], [l10, l11, l12], [l20, l21, l22]] = slice_lines(l, z0, len);
    let (s, dx, dy) = (
        &mut t.s[at..at + len],
        &mut t.dx[at..at + len],
        &mut t.dy[at..at + len],
    );
    let (b, f, c) = (
        &mut t.b[at..at + len],
        &mut t.f[at..at + len],
        &mut t.c[at..at + len],
    );
    // Two loops of nine input lines each vectorise; one loop writing all six did not.
    for j in 0..len {
        let sy0 = l00[j] + 2.0 * l01[j] + l02[j];
        let sy1 = l10[j] + 2.0 * l11[j] + l12[j];
        let sy2 = l20[j] + 2.0 * l21[j] + l22[j];
        s[j] = sy0 + 2.0 * sy1 + sy2;
        dx[j] = sy2 - sy0;
        dy[j] = (l02[j] - l00[j]) + 2.0 * (l12[j] - l10[j]) + (l22[j] - l20[j]);
    }
    for j in 0..len {
        b[j] = (l00[j] + l01[j] + l02[j]) + (l10[j] + l11[j] + l12[j]) + (l20[j] + l21[j] + l22[j]);
        f[j] = l01[j] + l21[j] + l10[j] + l12[j];
        c[j] = l11[j];
    }
}

/// The five filter responses of one channel on the piece z0..z0 + len of line (x, y):
/// `out[f][j]` is filter f at z0 + j.
#[inline(always)]
fn perceive_piece(
    l: &Lines,
    z0: usize,
    len: usize,
    nz: usize,
    t: &mut ForwardScratch,
    out: [&mut [f32]; FILTERS],
) {
    xy_forward(l, z0, len, t, 1);
    xy_forward(l, z0.saturating_sub(1), 1, t, 0);
    xy_forward(l, (z0 + len).min(nz - 1), 1, t, len + 1);
    let [id, sx, sy, sz, lap] = out;
    let (id, sx, sy, sz, lap) = (
        &mut id[..len],
        &mut sx[..len],
        &mut sy[..len],
        &mut sz[..len],
        &mut lap[..len],
    );
    let (sm, sc, sp) = neighbours(&t.s, len);
    let (xm, xc, xp) = neighbours(&t.dx, len);
    let (ym, yc, yp) = neighbours(&t.dy, len);
    let (bm, bc, bp) = neighbours(&t.b, len);
    let (cm, cc, cp) = neighbours(&t.c, len);
    let fc = window(&t.f, 1, len);
    for j in 0..len {
        id[j] = cc[j];
        sx[j] = (xm[j] + 2.0 * xc[j] + xp[j]) * 0.25;
        sy[j] = (ym[j] + 2.0 * yc[j] + yp[j]) * 0.25;
        sz[j] = (sp[j] - sm[j]) * 0.25;
        let boxed = bm[j] + bc[j] + bp[j];
        let smooth = sm[j] + 2.0 * sc[j] + sp[j];
        lap[j] = (boxed + smooth + fc[j] + cm[j] + cp[j] - 97.0 * cc[j]) * 0.125;
    }
}

/// The `len` values of `v` from 0, 1 and 2: each z's lower neighbour, itself and its
/// upper neighbour in a line padded by one value at each end.
#[inline(always)]
fn neighbours(v: &[f32], len: usize) -> (&[f32], &[f32], &[f32]) {
    (window(v, 0, len), window(v, 1, len), window(v, 2, len))
}

/// `len` values of `v` from `o`.
#[inline(always)]
pub fn window(v: &[f32], o: usize, len: usize) -> &[f32] {
    &v[o..o + len]
}

/// A piece of a z-line inside a block: line (y, z0..z0 + len) of the block's x-plane,
/// at block column `col`.
#[derive(Clone, Copy, Debug)]
pub struct Piece {
    pub y: usize,
    pub z0: usize,
    pub len: usize,
    pub col: usize,
}

/// The z-line pieces of the cells `q0..q0 + n` of an x-plane (`q = y Z + z`).
pub fn pieces(dims: Dims, q0: usize, n: usize) -> impl Iterator<Item = Piece> {
    let nz = dims.0[2];
    let mut q = q0;
    std::iter::from_fn(move || {
        (q < q0 + n).then(|| {
            let (y, z0) = (q / nz, q % nz);
            let len = (nz - z0).min(q0 + n - q).min(MAX_PIECE);
            let piece = Piece {
                y,
                z0,
                len,
                col: q - q0,
            };
            q += len;
            piece
        })
    })
}

/// Fills the input matrix `[input_rows][stride]` of the block of cells `q0..q0 + n` of
/// x-plane `x`: perceived state (rows 5c + f), perceived conditioning, positions; the
/// columns from n to `cols` are zero (rows beyond the inputs are never written and stay zero).
#[allow(clippy::too_many_arguments)]
#[inline(always)]
pub(crate) fn fill_inputs(
    shapes: &Shapes,
    fixed: &FixedInputs,
    state: &[f32],
    x: usize,
    (q0, n): (usize, usize),
    inp: &mut [f32],
    (stride, cols): (usize, usize),
    t: &mut ForwardScratch,
) {
    let dims = fixed.dims;
    let cells = dims.cells();
    let nz = dims.0[2];
    for row in inp.chunks_exact_mut(stride).take(shapes.inputs) {
        row[n..cols].fill(0.0);
    }
    let channels = shapes.state + shapes.cond;
    let plane_of = |ch: usize| {
        if ch < shapes.state {
            &state[ch * cells..(ch + 1) * cells]
        } else {
            fixed.cond_plane(ch - shapes.state)
        }
    };
    for piece in pieces(dims, q0, n) {
        let offsets = neighbour_offsets(dims, x, piece.y);
        for ch in 0..channels {
            let lines = lines_at(plane_of(ch), &offsets, nz);
            let rows = &mut inp[FILTERS * ch * stride..FILTERS * (ch + 1) * stride];
            let (r0, rest) = rows.split_at_mut(stride);
            let (r1, rest) = rest.split_at_mut(stride);
            let (r2, rest) = rest.split_at_mut(stride);
            let (r3, r4) = rest.split_at_mut(stride);
            let cols = piece.col..piece.col + piece.len;
            let out = [r0, r1, r2, r3, r4].map(|r| &mut r[cols.clone()]);
            perceive_piece(&lines, piece.z0, piece.len, nz, t, out);
        }
        let pos = shapes.position_row();
        let [px, py, pz] = &fixed.positions;
        let cols_of = |r: usize| piece.col + r * stride..piece.col + piece.len + r * stride;
        inp[cols_of(pos)].fill(px[x]);
        inp[cols_of(pos + 1)].fill(py[piece.y]);
        inp[cols_of(pos + 2)].copy_from_slice(&pz[piece.z0..piece.z0 + piece.len]);
    }
}
