//! Render time of an 800x800 cube view (3x3 samples per pixel, the default config) from
//! point-wise textures (the growth field's ring image; the procedural oak with its fibre
//! highlight) and from a 256^3 volume, on the machine's threads.
//!
//!     cargo run --release --example bench_render [-- SIZE]

use std::time::Instant;

use xylem::Volume;
use xylem::field::{GrowthField, RingImage};
use xylem::presets::{load_field_preset, load_species_preset};
use xylem::procedural::{ProceduralWood, WithFibreDirection};
use xylem::render::{RenderConfig, Shape, TriMesh, render};
use xylem::texture::SolidTexture;

fn time_render(
    name: &str,
    texture: &dyn SolidTexture,
    shape: &Shape,
    cfg: &RenderConfig,
    size: usize,
) {
    let best = (0..3)
        .map(|_| {
            let t = Instant::now();
            let img = render(texture, shape, shape.camera(cfg), cfg, size, size);
            std::hint::black_box(img);
            t.elapsed().as_secs_f64()
        })
        .fold(f64::INFINITY, f64::min);
    println!(
        "{name:>36}: {best:.3} s for {size}x{size} x {} spp",
        cfg.samples_per_axis.pow(2)
    );
}

fn main() {
    let size: usize = std::env::args()
        .nth(1)
        .and_then(|s| s.parse().ok())
        .unwrap_or(800);
    let cfg = RenderConfig::default_config();
    println!(
        "render time, best of 3, {} rayon threads",
        rayon::current_num_threads()
    );
    let field = GrowthField::from_config(&load_field_preset("knots").expect("preset"));
    let rings = RingImage(&field);
    time_render(
        "cube, growth field (point-wise)",
        &rings,
        &Shape::Cube,
        &cfg,
        size,
    );
    let oak = ProceduralWood::new(&load_species_preset("oak").expect("oak preset"));
    time_render(
        "cube, procedural oak + fibre highlight",
        &WithFibreDirection(&oak),
        &Shape::Cube,
        &cfg,
        size,
    );
    let t = Instant::now();
    let volume = Volume::from_texture(&rings, 256);
    println!(
        "{:>36}: {:.3} s",
        "sampling the 256^3 volume",
        t.elapsed().as_secs_f64()
    );
    time_render(
        "cube, 256^3 volume (trilinear)",
        &volume,
        &Shape::Cube,
        &cfg,
        size,
    );
    let bowl = TriMesh::load_obj(
        &std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/bowl.obj"),
    )
    .expect("bowl");
    time_render(
        "carved bowl, 256^3 volume",
        &volume,
        &Shape::carved(&bowl, &cfg.carve),
        &cfg,
        size,
    );
}
