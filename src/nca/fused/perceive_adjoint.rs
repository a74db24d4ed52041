//! The adjoint (transpose) of the perception with replicate padding: from the gradients of
//! the five filter responses of a channel, the gradient of the channel itself.
//!
//! Every filter is a sum of products of 1D operators along x, y, z with clamped indices:
//! I (identity), E (the two neighbours), S = E + 2 I, B = E + I and D (neighbour above minus
//! neighbour below). Replicate padding makes E, and so S and B, symmetric matrices: a
//! clamped neighbour of a border cell is the cell itself, on both sides of the transpose. D
//! is not: its transpose is D^T w[i] = w[i - 1] - w[i + 1] with w[-1] = -w[0] and
//! w[N] = -w[N - 1] (the border contributions, summed). So, for the gradients p0..p4 of
//! identity, Sobel x, y, z and the Laplacian of one channel,
//!
//! ds = p0 + (D^T S S p1 + S D^T S p2 + S S D^T p3) / 4
//!         + (B B B + S S S + E I I + I E I + I I E - 97 I) p4 / 8
//!
//! evaluated like the forward filters: xy combinations of the 3 x 3 neighbouring z-lines
//! (with the sign rule of D^T at the x and y borders), then along z (the z sign rule is
//! applied to the one-past-the-end values of the Sobel z line).

use super::perceive::{Lines, MAX_PIECE, slice_lines, window};
use crate::nca::perception::FILTERS;

/// Scratch values per xy line of a group of pieces (24 KB for the six).
pub(crate) const GROUP_FLOATS: usize = 1024;
const _: () = assert!(MAX_PIECE + 2 <= GROUP_FLOATS, "a piece fits a group");

/// xy combinations of a group of pieces, each piece with one value beyond each end
/// (piece at offset o: index o + j is z = clamp(z0 - 1 + j)). A whole group goes through
/// the xy stage before any of it goes through the z stage: reading values back right
/// after writing them, at the one-float shifts the z stage needs, stalled on store
/// forwarding (measured: 17% of the adjoint on one load).
pub(crate) struct AdjointScratch {
    /// Sobel x and y parts (both get [1,2,1] along z).
    sxy: Vec<f32>,
    /// Sobel z part (gets D^T along z).
    sz: Vec<f32>,
    /// Laplacian parts: box, [1,2,1]^2, xy face neighbours, centre.
    lb: Vec<f32>,
    ls: Vec<f32>,
    lf: Vec<f32>,
    lc: Vec<f32>,
}

impl Default for AdjointScratch {
    fn default() -> Self {
        let line = || vec![0.0f32; GROUP_FLOATS];
        Self {
            sxy: line(),
            sz: line(),
            lb: line(),
            ls: line(),
            lf: line(),
            lc: line(),
        }
    }
}

/// Signs of D^T's lower and upper neighbour at index i of an axis of n cells (-1 where the
/// neighbour is the clamped cell itself).
#[inline(always)]
pub fn border_signs(i: usize, n: usize) -> (f32, f32) {
    (
        if i == 0 { -1.0 } else { 1.0 },
        if i + 1 == n { -1.0 } else { 1.0 },
    )
}

/// xy combinations of the four non-identity gradient fields at z in [z0, z0 + len),
/// written to `at..at + len` of each scratch line. `signs` = (x lower, x upper, y lower,
/// y upper) of D^T.
#[inline(always)]
fn xy_adjoint(
    fields: &[Lines; FILTERS],
    signs: [f32; 4],
    z0: usize,
    len: usize,
    t: &mut AdjointScratch,
    at: usize,
) {
    let [[p00, p01, p02], _, [p20, p21, p22]] = slice_lines(&fields[1], z0, len);
    let [[q00, _, q02], [q10, _, q12], [q20, _, q22]] = slice_lines(&fields[2], z0, len);
    let [[r00, r01, r02], [r10, r11, r12], [r20, r21, r22]] = slice_lines(&fields[3], z0, len);
    let [[u00, u01, u02], [u10, u11, u12], [u20, u21, u22]] = slice_lines(&fields[4], z0, len);
    let [sxm, sxp, sym, syp] = signs;
    let sxy = &mut t.sxy[at..at + len];
    let sz = &mut t.sz[at..at + len];
    let (lb, ls) = (&mut t.lb[at..at + len], &mut t.ls[at..at + len]);
    let (lf, lc) = (&mut t.lf[at..at + len], &mut t.lc[at..at + len]);
    // Four loops of at most twelve input lines each: one loop over all of them had too many
    // pointers to vectorise (measured: scalar code, 14% of a training iteration).
    for j in 0..len {
        // D^T along x of [1,2,1] along y, and the reverse.
        let px = sxm * (p00[j] + 2.0 * p01[j] + p02[j]) - sxp * (p20[j] + 2.0 * p21[j] + p22[j]);
        let qy = sym * (q00[j] + 2.0 * q10[j] + q20[j]) - syp * (q02[j] + 2.0 * q12[j] + q22[j]);
        sxy[j] = px + qy;
    }
    for j in 0..len {
        let r0 = r00[j] + 2.0 * r01[j] + r02[j];
        let r1 = r10[j] + 2.0 * r11[j] + r12[j];
        let r2 = r20[j] + 2.0 * r21[j] + r22[j];
        sz[j] = r0 + 2.0 * r1 + r2;
    }
    for j in 0..len {
        let u0 = u00[j] + 2.0 * u01[j] + u02[j];
        let u1 = u10[j] + 2.0 * u11[j] + u12[j];
        let u2 = u20[j] + 2.0 * u21[j] + u22[j];
        ls[j] = u0 + 2.0 * u1 + u2;
        lb[j] =
            (u00[j] + u01[j] + u02[j]) + (u10[j] + u11[j] + u12[j]) + (u20[j] + u21[j] + u22[j]);
    }
    for j in 0..len {
        lf[j] = u01[j] + u21[j] + u10[j] + u12[j];
        lc[j] = u11[j];
    }
}

/// The xy stage of the adjoint of one piece z0..z0 + len into the scratch at offset `o`
/// (`o .. o + len + 2`): `fields[f]` are the neighbour lines of filter f's gradient,
/// `signs` from [`border_signs`] for x and y.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
pub(crate) fn adjoint_xy(
    fields: &[Lines; FILTERS],
    signs: [f32; 4],
    z0: usize,
    len: usize,
    nz: usize,
    t: &mut AdjointScratch,
    o: usize,
) {
    xy_adjoint(fields, signs, z0, len, t, o + 1);
    xy_adjoint(fields, signs, z0.saturating_sub(1), 1, t, o);
    xy_adjoint(fields, signs, (z0 + len).min(nz - 1), 1, t, o + len + 1);
    // D^T along z: a clamped end value (the cell itself) enters with the opposite sign.
    if z0 == 0 {
        t.sz[o] = -t.sz[o];
    }
    if z0 + len == nz {
        t.sz[o + len + 1] = -t.sz[o + len + 1];
    }
}

/// The z stage of the adjoint of a piece whose xy stage is at scratch offset `o`:
/// `out[j] = g[j] + identity[j] + (the filters' adjoints)` for j < len, `identity` being the
/// identity filter's gradient on the piece.
#[inline(always)]
pub(crate) fn adjoint_z(
    t: &AdjointScratch,
    o: usize,
    len: usize,
    identity: &[f32],
    g: &[f32],
    out: &mut [f32],
) {
    let (am, ac, ap) = (
        window(&t.sxy, o, len),
        window(&t.sxy, o + 1, len),
        window(&t.sxy, o + 2, len),
    );
    let (zm, zp) = (window(&t.sz, o, len), window(&t.sz, o + 2, len));
    let (bm, bc, bp) = (
        window(&t.lb, o, len),
        window(&t.lb, o + 1, len),
        window(&t.lb, o + 2, len),
    );
    let (sm, sc, sp) = (
        window(&t.ls, o, len),
        window(&t.ls, o + 1, len),
        window(&t.ls, o + 2, len),
    );
    let (cm, cc, cp) = (
        window(&t.lc, o, len),
        window(&t.lc, o + 1, len),
        window(&t.lc, o + 2, len),
    );
    let fc = window(&t.lf, o + 1, len);
    let (identity, g, out) = (&identity[..len], &g[..len], &mut out[..len]);
    for j in 0..len {
        let sobel = am[j] + 2.0 * ac[j] + ap[j] + zm[j] - zp[j];
        let boxed = bm[j] + bc[j] + bp[j];
        let smooth = sm[j] + 2.0 * sc[j] + sp[j];
        let lap = boxed + smooth + fc[j] + cm[j] + cp[j] - 97.0 * cc[j];
        out[j] = g[j] + identity[j] + 0.25 * sobel + 0.125 * lap;
    }
}

/// A piece of a z-line of an x-plane and its place in the group scratch.
#[derive(Clone, Copy, Debug)]
pub(crate) struct GroupPiece {
    pub y: usize,
    pub z0: usize,
    pub len: usize,
    /// Offset in the scratch lines.
    pub at: usize,
}

/// The pieces of all z-lines of an x-plane (`ny` lines of `nz` cells), in groups that fit
/// the scratch.
pub(crate) fn piece_groups(ny: usize, nz: usize) -> Vec<Vec<GroupPiece>> {
    let mut groups: Vec<Vec<GroupPiece>> = vec![Vec::new()];
    let mut used = 0;
    for y in 0..ny {
        for (z0, len) in piece_starts(nz) {
            if used + len + 2 > GROUP_FLOATS {
                groups.push(Vec::new());
                used = 0;
            }
            let group = groups.last_mut().expect("a group");
            group.push(GroupPiece {
                y,
                z0,
                len,
                at: used,
            });
            used += len + 2;
        }
    }
    groups
}

/// Start and length of the z-pieces of a line of `nz` cells.
pub(crate) fn piece_starts(nz: usize) -> impl Iterator<Item = (usize, usize)> {
    (0..nz)
        .step_by(MAX_PIECE)
        .map(move |z0| (z0, MAX_PIECE.min(nz - z0)))
}
