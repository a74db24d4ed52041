//! OpenVDB files (`.vdb`), written by hand: several named grids in one file, for Blender,
//! Houdini and anything else built on the OpenVDB library.
//!
//! Format choices (all checked against OpenVDB 10's reader, `io::Archive`):
//! - File format version 224 with grid offsets, so readers can list grids and load one grid
//!   without reading the others; library version 10.0 is recorded as the writer's, since
//!   that is the release whose format this follows.
//! - Values are stored uncompressed (per-grid compression flags 0), so the writer needs no
//!   zlib/blosc; each node value block then carries the "all values follow" marker byte.
//! - Trees are the standard 5-4-3 configuration (`Tree_float_5_4_3`, `Tree_vec3s_5_4_3`):
//!   leaves of 8^3 voxels, lower internal nodes of 16^3 leaves (128 voxels wide), upper
//!   internal nodes of 32^3 lower nodes (4096 voxels wide), under the root's table.
//! - Index (i, j, k) is volume voxel (i, j, k) of xylem's `[X, Y, Z, C]` layout. Every voxel
//!   of the volume is active and stored in a dense leaf; leaf voxels past the volume's edge
//!   are inactive background (0). There are no tiles: internal node values are all 0.
//! - The transform maps index (i, j, k) to the voxel centre in cube units,
//!   ((i + 0.5)/nx - 0.5, ...): a scale of 1/n per axis and a translation of -0.5 + 0.5/n,
//!   as a `UniformScaleTranslateMap` when nx = ny = nz, else a `ScaleTranslateMap`.
//! - The file's UUID is derived from a hash of the grids (names, dims, values), so the same
//!   input gives the same bytes.
//!
//! Layout of one grid, after the file header: descriptor (name, tree type, no instance
//! parent, absolute offsets of grid start, value blocks and end), compression flags,
//! metadata, transform, topology (node masks and internal node values, depth first), then
//! the leaf value blocks in the same depth-first order.

use std::io::{self, Write};
use std::ops::Range;
use std::path::Path;

use rayon::prelude::*;

use crate::error::{Result, XylemError};
use crate::io::write_atomic;
use crate::volume::Volume;

/// The voxel values of one grid: a 1-channel volume as a `FloatGrid`, a 3-channel volume as
/// a `Vec3SGrid`.
#[derive(Clone, Copy, Debug)]
pub enum VdbValues<'a> {
    Float(&'a Volume),
    Vec3(&'a Volume),
}

/// The grid's `class` metadata. Renderers treat fog volumes as densities (non-negative, 0
/// outside); anything else, colour or direction fields, is `Unknown`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum VdbClass {
    Unknown,
    FogVolume,
}

/// One named grid of a `.vdb` file.
#[derive(Clone, Copy, Debug)]
pub struct VdbGrid<'a> {
    pub name: &'a str,
    pub values: VdbValues<'a>,
    pub class: VdbClass,
}

const MAGIC: i64 = 0x5644_4220;
const FILE_VERSION: u32 = 224;
const LIBRARY_VERSION: [u32; 2] = [10, 0];
/// Per-node block marker: no active-mask compression, every value follows.
const ALL_VALUES: u8 = 6;
/// log2 of a node's edge in child units, by level: leaf, lower internal, upper internal.
const LOG2_DIM: [u32; 3] = [3, 4, 5];
/// log2 of a node's edge in voxels, by level.
const LOG2_SPAN: [u32; 3] = [3, 7, 12];
/// Largest edge accepted: node origins and bounding boxes must fit OpenVDB's int32 coords.
const MAX_EDGE: usize = 1 << 30;
/// Leaf blocks are gathered up to this many bytes before each write.
const BATCH_BYTES: usize = 1 << 20;

/// Writes grids to one OpenVDB file (atomically). Grids may have different dims; each one
/// spans the cube [-0.5, 0.5]^3.
pub fn write_vdb(path: &Path, grids: &[VdbGrid]) -> Result<()> {
    let plans = plan(grids)?;
    let uuid = uuid_string(content_hash(&plans));
    write_atomic(path, |w| {
        let mut w = Counting { inner: w, at: 0 };
        write_file(&mut w, &plans, &uuid)
    })
}

/// A validated grid with its node counts.
struct GridPlan<'a> {
    name: &'a str,
    volume: &'a Volume,
    class: VdbClass,
    /// `[level][axis]`: nodes along each axis at each level (leaf, lower, upper).
    nodes: [[usize; 3]; 3],
}

fn plan<'a>(grids: &[VdbGrid<'a>]) -> Result<Vec<GridPlan<'a>>> {
    if grids.is_empty() {
        return Err(XylemError::input("VDB grids", "no grids to write"));
    }
    let mut plans: Vec<GridPlan> = Vec::with_capacity(grids.len());
    for g in grids {
        let what = format!("VDB grid {:?}", g.name);
        let (volume, channels) = match g.values {
            VdbValues::Float(v) => (v, 1),
            VdbValues::Vec3(v) => (v, 3),
        };
        if g.name.is_empty() || g.name.contains('\x1e') {
            return Err(XylemError::input(
                what,
                "a grid name must be non-empty and free of the byte 0x1e",
            ));
        }
        if plans.iter().any(|p| p.name == g.name) {
            return Err(XylemError::input(what, "two grids with this name"));
        }
        if volume.channels != channels {
            let kind = if channels == 1 { "Float" } else { "Vec3" };
            return Err(XylemError::input(
                what,
                format!(
                    "a {kind} grid needs a {channels}-channel volume, got {} channels",
                    volume.channels
                ),
            ));
        }
        let [nx, ny, nz] = volume.dims;
        if volume.dims.iter().any(|&n| n == 0 || n > MAX_EDGE)
            || volume.data.len() != nx * ny * nz * channels
        {
            return Err(XylemError::input(
                what,
                format!(
                    "dims {:?} with {} values (each edge 1..={MAX_EDGE})",
                    volume.dims,
                    volume.data.len()
                ),
            ));
        }
        let nodes = std::array::from_fn(|level| volume.dims.map(|n| nodes_along(n, level)));
        plans.push(GridPlan {
            name: g.name,
            volume,
            class: g.class,
            nodes,
        });
    }
    Ok(plans)
}

/// Nodes of `level` needed along an axis of `n` voxels starting at index 0.
fn nodes_along(n: usize, level: usize) -> usize {
    n.div_ceil(1 << LOG2_SPAN[level])
}

/// Along one axis, the children (by index at the level below) of node `parent` at `level`,
/// clipped to the `count` children that exist.
fn children(parent: usize, level: usize, count: usize) -> Range<usize> {
    let d = LOG2_DIM[level];
    (parent << d).min(count)..((parent + 1) << d).min(count)
}

/// Position of a child (or voxel) in its node's table: x major, z fastest.
fn table_offset(local: [usize; 3], log2_dim: u32) -> usize {
    (local[0] << (2 * log2_dim)) | (local[1] << log2_dim) | local[2]
}

/// Bit `n` of a node mask lives in u64 word n / 64, bit n % 64.
fn set_bit(words: &mut [u64], n: usize) {
    words[n >> 6] |= 1 << (n & 63);
}

fn put_words(buf: &mut Vec<u8>, words: &[u64]) {
    for w in words {
        buf.extend_from_slice(&w.to_le_bytes());
    }
}

fn put_str(buf: &mut Vec<u8>, s: &str) {
    buf.extend_from_slice(&(s.len() as u32).to_le_bytes());
    buf.extend_from_slice(s.as_bytes());
}

/// One metadata entry: name, type name, byte count, raw little-endian value.
fn put_meta(buf: &mut Vec<u8>, name: &str, type_name: &str, value: &[u8]) {
    put_str(buf, name);
    put_str(buf, type_name);
    buf.extend_from_slice(&(value.len() as u32).to_le_bytes());
    buf.extend_from_slice(value);
}

impl GridPlan<'_> {
    fn channels(&self) -> usize {
        self.volume.channels
    }

    fn value_bytes(&self) -> usize {
        4 * self.channels()
    }

    fn tree_type(&self) -> &'static str {
        if self.channels() == 1 {
            "Tree_float_5_4_3"
        } else {
            "Tree_vec3s_5_4_3"
        }
    }

    fn node_count(&self, level: usize) -> u64 {
        self.nodes[level].iter().map(|&n| n as u64).product()
    }

    /// Bytes of a node's own topology record: child mask, value mask, marker, all values.
    fn internal_record_len(&self, level: usize) -> u64 {
        let table = 1u64 << (3 * LOG2_DIM[level]);
        2 * table / 8 + 1 + table * self.value_bytes() as u64
    }

    fn leaf_block_len(&self) -> u64 {
        64 + 1 + 512 * self.value_bytes() as u64
    }

    fn topology_len(&self) -> u64 {
        let root = 4 + self.value_bytes() as u64 + 8 + 12 * self.node_count(2);
        root + self.node_count(2) * self.internal_record_len(2)
            + self.node_count(1) * self.internal_record_len(1)
            + self.node_count(0) * 64
    }

    fn buffers_len(&self) -> u64 {
        self.node_count(0) * self.leaf_block_len()
    }

    /// The tree's in-memory size as OpenVDB counts it (`Tree::memUsage`, fitted on trees it
    /// built: table slots of 8 or 16 bytes, masks, leaf buffers, per-node overheads); readers
    /// only report it.
    fn mem_bytes(&self) -> u64 {
        let slot = self.value_bytes().next_multiple_of(8) as u64;
        let leaf = 512 * self.value_bytes() as u64 + 96;
        let lower = 4096 * slot + 2 * 512 + 16;
        let upper = 32768 * slot + 2 * 4096 + 16;
        self.node_count(0) * leaf + self.node_count(1) * lower + self.node_count(2) * upper + 1024
    }

    /// Compression flags, metadata and transform: everything between the descriptor and
    /// the topology.
    fn head(&self) -> Vec<u8> {
        let mut b = Vec::new();
        b.extend_from_slice(&0u32.to_le_bytes());
        let dims = self.volume.dims;
        let max: Vec<u8> = dims
            .iter()
            .flat_map(|&n| (n as i32 - 1).to_le_bytes())
            .collect();
        let voxels = dims.iter().map(|&n| n as i64).product::<i64>();
        let class = match self.class {
            VdbClass::Unknown => "unknown",
            VdbClass::FogVolume => "fog volume",
        };
        // Entries in name order, as OpenVDB's own map writes them.
        b.extend_from_slice(&9u32.to_le_bytes());
        put_meta(&mut b, "class", "string", class.as_bytes());
        put_meta(&mut b, "creator", "string", b"xylem");
        put_meta(&mut b, "file_bbox_max", "vec3i", &max);
        put_meta(&mut b, "file_bbox_min", "vec3i", &[0; 12]);
        put_meta(&mut b, "file_compression", "string", b"none");
        put_meta(
            &mut b,
            "file_mem_bytes",
            "int64",
            &(self.mem_bytes() as i64).to_le_bytes(),
        );
        put_meta(&mut b, "file_voxel_count", "int64", &voxels.to_le_bytes());
        put_meta(&mut b, "is_local_space", "bool", &[0]);
        put_meta(&mut b, "name", "string", self.name.as_bytes());

        let uniform = dims[0] == dims[1] && dims[1] == dims[2];
        put_str(
            &mut b,
            if uniform {
                "UniformScaleTranslateMap"
            } else {
                "ScaleTranslateMap"
            },
        );
        // The reader takes the derived vectors as stored, so they are written consistently:
        // translation, scale, voxel size, 1/scale, 1/scale^2, 1/(2 scale).
        let scale = dims.map(|n| 1.0 / n as f64);
        let translation = dims.map(|n| -0.5 + 0.5 / n as f64);
        let inverse = scale.map(|s| 1.0 / s);
        for v in [
            translation,
            scale,
            scale,
            inverse,
            inverse.map(|s| s * s),
            inverse.map(|s| s / 2.0),
        ] {
            for x in v {
                b.extend_from_slice(&x.to_le_bytes());
            }
        }
        b
    }

    /// Children of the internal node `parent` (node coords at `level`), by axis.
    fn child_ranges(&self, parent: [usize; 3], level: usize) -> [Range<usize>; 3] {
        std::array::from_fn(|a| children(parent[a], level, self.nodes[level - 1][a]))
    }

    /// An internal node's record; its children follow it in the topology.
    fn put_internal(&self, buf: &mut Vec<u8>, node: [usize; 3], level: usize) {
        let d = LOG2_DIM[level];
        let mut mask = vec![0u64; (1 << (3 * d)) / 64];
        let r = self.child_ranges(node, level);
        for x in r[0].clone() {
            for y in r[1].clone() {
                for z in r[2].clone() {
                    let local = [x, y, z].map(|c| c & ((1 << d) - 1));
                    set_bit(&mut mask, table_offset(local, d));
                }
            }
        }
        put_words(buf, &mask);
        put_words(buf, &vec![0; mask.len()]);
        buf.push(ALL_VALUES);
        buf.resize(buf.len() + (1 << (3 * d)) * self.value_bytes(), 0);
    }

    /// Active voxels of leaf `leaf` (leaf coords): those inside the volume.
    fn leaf_mask(&self, leaf: [usize; 3]) -> [u64; 8] {
        let dims = self.volume.dims;
        let inside = |a: usize| dims[a].saturating_sub(leaf[a] * 8).min(8);
        let [ix, iy, iz] = [0, 1, 2].map(inside);
        let row = (1u64 << iz) - 1; // 8 z bits per (x, y), so iz = 8 sets the whole byte
        let plane = (0..iy).fold(0u64, |m, y| m | (row << (8 * y)));
        std::array::from_fn(|x| if x < ix { plane } else { 0 })
    }

    /// A leaf's value block: mask, marker, 8^3 values (x major, z fastest; channels
    /// innermost, which is Vec3s's component order).
    fn put_leaf_values(&self, buf: &mut Vec<u8>, leaf: [usize; 3]) {
        let vol = self.volume;
        let [nx, ny, nz] = vol.dims;
        let c = vol.channels;
        put_words(buf, &self.leaf_mask(leaf));
        buf.push(ALL_VALUES);
        let [i0, j0, k0] = leaf.map(|l| l * 8);
        for i in i0..i0 + 8 {
            for j in j0..j0 + 8 {
                let run = if i < nx && j < ny {
                    nz.saturating_sub(k0).min(8)
                } else {
                    0
                };
                if run > 0 {
                    let o = vol.offset(i, j, k0);
                    for v in &vol.data[o..o + run * c] {
                        buf.extend_from_slice(&v.to_le_bytes());
                    }
                }
                buf.resize(buf.len() + (8 - run) * c * 4, 0);
            }
        }
    }

    /// Visits the nodes depth first as (level, node coords): each upper node, then its lower
    /// nodes, each followed by its leaves; children in table order, which for the upper
    /// nodes is also the root's coordinate order.
    fn walk(&self, mut visit: impl FnMut(usize, [usize; 3]) -> io::Result<()>) -> io::Result<()> {
        let [ux, uy, uz] = self.nodes[2];
        for u in grid_points([0..ux, 0..uy, 0..uz]) {
            visit(2, u)?;
            for l in grid_points(self.child_ranges(u, 2)) {
                visit(1, l)?;
                for f in grid_points(self.child_ranges(l, 1)) {
                    visit(0, f)?;
                }
            }
        }
        Ok(())
    }
}

/// Points of a box, x major, z fastest.
fn grid_points(r: [Range<usize>; 3]) -> impl Iterator<Item = [usize; 3]> {
    let [rx, ry, rz] = r;
    rx.flat_map(move |x| {
        let rz = rz.clone();
        ry.clone()
            .flat_map(move |y| rz.clone().map(move |z| [x, y, z]))
    })
}

/// A writer that knows its position, to fill in and check the descriptor's offsets.
struct Counting<'a> {
    inner: &'a mut dyn Write,
    at: u64,
}

impl Write for Counting<'_> {
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        let n = self.inner.write(buf)?;
        self.at += n as u64;
        Ok(n)
    }
    fn flush(&mut self) -> io::Result<()> {
        self.inner.flush()
    }
}

fn check_at(w: &Counting, expected: u64, what: &str) -> io::Result<()> {
    if w.at == expected {
        Ok(())
    } else {
        Err(io::Error::other(format!(
            "VDB writer bug: {what} at byte {} instead of {expected}",
            w.at
        )))
    }
}

fn write_file(w: &mut Counting, plans: &[GridPlan], uuid: &str) -> io::Result<()> {
    let mut b = Vec::new();
    b.extend_from_slice(&MAGIC.to_le_bytes());
    b.extend_from_slice(&FILE_VERSION.to_le_bytes());
    for v in LIBRARY_VERSION {
        b.extend_from_slice(&v.to_le_bytes());
    }
    b.push(1); // grid offsets present
    b.extend_from_slice(uuid.as_bytes());
    b.extend_from_slice(&0u32.to_le_bytes()); // file-level metadata: none
    b.extend_from_slice(&(plans.len() as i32).to_le_bytes());
    w.write_all(&b)?;
    for p in plans {
        write_grid(w, p)?;
    }
    Ok(())
}

fn write_when_full(w: &mut Counting, b: &mut Vec<u8>) -> io::Result<()> {
    if b.len() >= BATCH_BYTES {
        w.write_all(b)?;
        b.clear();
    }
    Ok(())
}

fn write_grid(w: &mut Counting, p: &GridPlan) -> io::Result<()> {
    let head = p.head();
    let mut b = Vec::new();
    put_str(&mut b, p.name);
    put_str(&mut b, p.tree_type());
    put_str(&mut b, "");
    let grid_at = w.at + b.len() as u64 + 24;
    let blocks_at = grid_at + head.len() as u64 + p.topology_len();
    let end_at = blocks_at + p.buffers_len();
    for at in [grid_at, blocks_at, end_at] {
        b.extend_from_slice(&(at as i64).to_le_bytes());
    }
    b.extend_from_slice(&head);

    // Topology: buffer count, root (background, tile count, child count, children with
    // their origins), then each node's record before its children.
    b.extend_from_slice(&1i32.to_le_bytes());
    b.resize(b.len() + p.value_bytes(), 0);
    b.extend_from_slice(&0u32.to_le_bytes());
    b.extend_from_slice(&(p.node_count(2) as u32).to_le_bytes());
    p.walk(|level, node| {
        match level {
            2 => {
                for c in node {
                    b.extend_from_slice(&((c << LOG2_SPAN[2]) as i32).to_le_bytes());
                }
                p.put_internal(&mut b, node, 2);
            }
            1 => p.put_internal(&mut b, node, 1),
            _ => put_words(&mut b, &p.leaf_mask(node)),
        }
        write_when_full(w, &mut b)
    })?;
    w.write_all(&b)?;
    b.clear();
    check_at(w, blocks_at, "leaf values")?;

    p.walk(|level, node| {
        if level == 0 {
            p.put_leaf_values(&mut b, node);
        }
        write_when_full(w, &mut b)
    })?;
    w.write_all(&b)?;
    check_at(w, end_at, "grid end")
}

/// FNV-1a over 32-bit words; chunks are hashed in parallel and combined in order, so the
/// result does not depend on the thread count.
fn hash_words(h: u64, words: impl Iterator<Item = u32>) -> u64 {
    words.fold(h, |h, v| (h ^ v as u64).wrapping_mul(0x0000_0100_0000_01b3))
}

fn splitmix(mut z: u64) -> u64 {
    z = z.wrapping_add(0x9e37_79b9_7f4a_7c15);
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

fn content_hash(plans: &[GridPlan]) -> u64 {
    let mut h = 0xcbf2_9ce4_8422_2325;
    for p in plans {
        h = hash_words(h, p.name.bytes().map(u32::from));
        h = hash_words(h, p.tree_type().bytes().map(u32::from));
        h = hash_words(h, p.volume.dims.iter().map(|&n| n as u32));
        h = hash_words(h, [p.class as u32].into_iter());
        let chunks: Vec<u64> = p
            .volume
            .data
            .par_chunks(1 << 16)
            .map(|c| hash_words(0xcbf2_9ce4_8422_2325, c.iter().map(|v| v.to_bits())))
            .collect();
        for c in chunks {
            h = splitmix(h ^ c);
        }
    }
    h
}

/// 36-character textual UUID (the form the reader parses) from a hash, marked as an
/// RFC 9562 version-8 (application-defined) UUID.
fn uuid_string(hash: u64) -> String {
    let mut bytes = [0u8; 16];
    bytes[..8].copy_from_slice(&splitmix(hash).to_be_bytes());
    bytes[8..].copy_from_slice(&splitmix(hash ^ 0x5644_4220).to_be_bytes());
    bytes[6] = (bytes[6] & 0x0f) | 0x80;
    bytes[8] = (bytes[8] & 0x3f) | 0x80;
    let mut s = String::with_capacity(36);
    for (i, b) in bytes.iter().enumerate() {
        if matches!(i, 4 | 6 | 8 | 10) {
            s.push('-');
        }
        s.push_str(&format!("{b:02x}"));
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ramp(dims: [usize; 3], channels: usize) -> Volume {
        let n = dims.iter().product::<usize>() * channels;
        Volume::from_data(dims, channels, (0..n).map(|v| v as f32).collect()).unwrap()
    }

    fn plan_of(vol: &Volume) -> GridPlan<'_> {
        let values = if vol.channels == 1 {
            VdbValues::Float(vol)
        } else {
            VdbValues::Vec3(vol)
        };
        plan(&[VdbGrid {
            name: "g",
            values,
            class: VdbClass::Unknown,
        }])
        .unwrap()
        .remove(0)
    }

    #[test]
    fn node_counts_per_level() {
        assert_eq!(
            [0, 1, 2].map(|l| nodes_along(1, l)),
            [1, 1, 1],
            "one voxel needs one node per level"
        );
        assert_eq!([0, 1, 2].map(|l| nodes_along(8, l)), [1, 1, 1]);
        assert_eq!([0, 1, 2].map(|l| nodes_along(9, l)), [2, 1, 1]);
        assert_eq!([0, 1, 2].map(|l| nodes_along(129, l)), [17, 2, 1]);
        assert_eq!([0, 1, 2].map(|l| nodes_along(4097, l)), [513, 33, 2]);
        assert_eq!(nodes_along(2048, 0), 256);
    }

    #[test]
    fn children_are_clipped_to_existing_nodes() {
        // 33 lower nodes along an axis: the first upper node has 32, the second 1.
        assert_eq!(children(0, 2, 33), 0..32);
        assert_eq!(children(1, 2, 33), 32..33);
        // 17 leaves: lower node 0 holds 16, lower node 1 holds 1.
        assert_eq!(children(0, 1, 17), 0..16);
        assert_eq!(children(1, 1, 17), 16..17);
    }

    #[test]
    fn table_offsets_are_x_major() {
        assert_eq!(table_offset([0, 0, 1], 3), 1);
        assert_eq!(table_offset([0, 1, 0], 3), 8);
        assert_eq!(table_offset([1, 0, 0], 3), 64);
        assert_eq!(table_offset([31, 31, 31], 5), 32767);
        let mut words = [0u64; 2];
        set_bit(&mut words, 65);
        assert_eq!(words, [0, 2]);
    }

    #[test]
    fn partial_leaf_masks_only_voxels_inside() {
        let vol = ramp([2, 3, 9], 1);
        let p = plan_of(&vol);
        // Leaf (0, 0, 0): x < 2, y < 3, z < 8: rows of 8 z bits for y = 0..3.
        let m = p.leaf_mask([0, 0, 0]);
        assert_eq!(m[0], 0xff_ffff);
        assert_eq!(m[1], 0xff_ffff);
        assert!(m[2..].iter().all(|&w| w == 0));
        // Leaf (0, 0, 1): only z = 8 (bit 0 of each y row).
        let m = p.leaf_mask([0, 0, 1]);
        assert_eq!(m[0], 0x01_0101);
        let active: u32 = [[0, 0, 0], [0, 0, 1]]
            .iter()
            .map(|&l| p.leaf_mask(l).iter().map(|w| w.count_ones()).sum::<u32>())
            .sum();
        assert_eq!(active, 2 * 3 * 9);
    }

    #[test]
    fn leaf_values_follow_the_table_order() {
        let vol = ramp([2, 1, 3], 3);
        let p = plan_of(&vol);
        let mut b = Vec::new();
        p.put_leaf_values(&mut b, [0, 0, 0]);
        assert_eq!(b.len() as u64, p.leaf_block_len());
        let value = |x: usize, y: usize, z: usize, ch: usize| {
            let at = 65 + ((table_offset([x, y, z], 3) * 3 + ch) * 4);
            f32::from_le_bytes(b[at..at + 4].try_into().unwrap())
        };
        assert_eq!(value(1, 0, 2, 1), vol.voxel(1, 0, 2)[1]);
        assert_eq!(value(0, 0, 1, 2), vol.voxel(0, 0, 1)[2]);
        assert_eq!(value(0, 1, 0, 0), 0.0, "outside the volume");
    }

    #[test]
    fn written_sizes_match_the_declared_offsets() {
        for dims in [[1, 1, 1], [5, 9, 13], [2, 130, 17]] {
            let vol = ramp(dims, 3);
            let plans = plan(&[VdbGrid {
                name: "a",
                values: VdbValues::Vec3(&vol),
                class: VdbClass::FogVolume,
            }])
            .unwrap();
            let mut out = Vec::new();
            let mut w = Counting {
                inner: &mut out,
                at: 0,
            };
            write_file(&mut w, &plans, &uuid_string(0)).unwrap();
            // The end offset is the last 8 bytes of the descriptor.
            let at = 65 + 4 + 1 + 4 + 16 + 4 + 16;
            let end = i64::from_le_bytes(out[at..at + 8].try_into().unwrap());
            assert_eq!(end as usize, out.len(), "dims {dims:?}");
        }
    }

    #[test]
    fn uuid_is_textual_and_deterministic() {
        let a = uuid_string(42);
        assert_eq!(a.len(), 36);
        assert_eq!(a, uuid_string(42));
        assert_ne!(a, uuid_string(43));
        assert_eq!(&a[14..15], "8");
        assert_eq!(a.matches('-').count(), 4);
    }

    #[test]
    fn wrong_channels_and_names_are_errors() {
        let rgb = ramp([2, 2, 2], 3);
        let one = ramp([2, 2, 2], 1);
        let grid = |name, values| VdbGrid {
            name,
            values,
            class: VdbClass::Unknown,
        };
        assert!(plan(&[grid("d", VdbValues::Float(&rgb))]).is_err());
        assert!(plan(&[grid("c", VdbValues::Vec3(&one))]).is_err());
        assert!(plan(&[grid("", VdbValues::Float(&one))]).is_err());
        assert!(
            plan(&[
                grid("d", VdbValues::Float(&one)),
                grid("d", VdbValues::Vec3(&rgb))
            ])
            .is_err()
        );
        assert!(plan(&[]).is_err());
    }
}
