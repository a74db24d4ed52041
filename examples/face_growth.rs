//! The growth field G of a fit on the six faces, for analyses outside the crate (e.g.
//! `docs/tools/ring_floor.py`).
//!
//!     cargo run --release --example face_growth -- FIT.toml OUT.npy [SIZE]
//!
//! Writes OUT.npy, float32 `[6, SIZE, SIZE]` (default SIZE 256): G in years on faces A..F in
//! DESIGN's face order, each face in the orientation of its photo (`slice_face`).

use std::path::PathBuf;

use xylem::config::ConfigFile;
use xylem::field::{FieldConfig, GrowthField};
use xylem::frame::Face;
use xylem::io::npy::write_npy;
use xylem::slice::slice_face;

fn main() -> xylem::Result<()> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let usage = "usage: face_growth FIT.toml OUT.npy [SIZE]";
    let fit = PathBuf::from(args.first().expect(usage));
    let out = PathBuf::from(args.get(1).expect(usage));
    let size: usize = args.get(2).map_or(256, |s| s.parse().expect(usage));
    let field = GrowthField::from_config(&FieldConfig::load(&fit)?);
    // [6, SIZE, SIZE]
    let mut g = Vec::with_capacity(6 * size * size);
    for face in Face::ALL {
        let image = slice_face(&field, face, size);
        g.extend(image.data.chunks_exact(image.channels).map(|px| px[0]));
    }
    write_npy(&out, &[6, size, size], &g)
}
