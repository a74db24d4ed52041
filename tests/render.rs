//! Rendering and exports: cube and mesh renders are sane, the shipped bowl is what the code
//! generates, and every export format reads back with the right values and axis order.

mod common;

use glam::Vec3;
use xylem::Volume;
use xylem::export::{Format, Values, export, mitsuba, nrrd};
use xylem::render::lathe::{SHIPPED_SEGMENTS, turned_bowl};
use xylem::render::{RenderConfig, Shape, TriMesh, render, turntable};
use xylem::texture::SolidTexture;

/// Colour from position: a different colour on every face, smooth inside.
struct Gradient;
impl SolidTexture for Gradient {
    fn channels(&self) -> usize {
        3
    }
    fn eval(&self, p: Vec3, out: &mut [f32]) {
        out.copy_from_slice(
            &(p + Vec3::splat(0.5))
                .clamp(Vec3::ZERO, Vec3::ONE)
                .to_array(),
        );
    }
}

fn small_config() -> RenderConfig {
    let mut cfg = RenderConfig::default_config();
    cfg.samples_per_axis = 2;
    cfg
}

#[test]
fn cube_render_shows_three_lit_faces_on_the_background() {
    let cfg = small_config();
    let img = render(&Gradient, &Shape::Cube, &cfg.camera, &cfg, 64, 64);
    let bg = Vec3::from(cfg.background);
    let corner = Vec3::from_slice(img.pixel(0, 0));
    assert!((corner - bg).length() < 1e-5, "corner should be background");
    let centre = Vec3::from_slice(img.pixel(32, 32));
    assert!(
        (centre - bg).length() > 0.05,
        "the cube should cover the centre"
    );
    // Top face (+y, lit from above) is brighter than the two side faces on average.
    let mean = |r0: usize, r1: usize, c0: usize, c1: usize| {
        let mut s = 0.0;
        for r in r0..r1 {
            for c in c0..c1 {
                s += img.pixel(r, c).iter().sum::<f32>();
            }
        }
        s / ((r1 - r0) * (c1 - c0)) as f32
    };
    assert!(
        mean(14, 18, 30, 34) > mean(40, 44, 22, 26),
        "top face should be brighter"
    );
    // Deterministic.
    assert_eq!(
        img,
        render(&Gradient, &Shape::Cube, &cfg.camera, &cfg, 64, 64)
    );
}

#[test]
fn fibre_channel_adds_an_anisotropic_highlight() {
    struct WithFibre(Vec3);
    impl SolidTexture for WithFibre {
        fn channels(&self) -> usize {
            6
        }
        fn eval(&self, _p: Vec3, out: &mut [f32]) {
            out[..3].copy_from_slice(&[0.5, 0.35, 0.2]);
            out[3..].copy_from_slice(&self.0.to_array());
        }
    }
    let mut cfg = small_config();
    cfg.material.coat_strength = 0.0;
    let along = render(&WithFibre(Vec3::X), &Shape::Cube, &cfg.camera, &cfg, 48, 48);
    let across = render(&WithFibre(Vec3::Y), &Shape::Cube, &cfg.camera, &cfg, 48, 48);
    assert_ne!(along, across, "fibre direction must change the image");
}

#[test]
fn shipped_bowl_matches_the_generator_and_renders() {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/bowl.obj");
    let shipped = TriMesh::load_obj(&path).unwrap();
    let generated = turned_bowl(SHIPPED_SEGMENTS);
    assert_eq!(shipped.triangles.len(), generated.triangles.len());
    // The OBJ loader re-indexes vertices; compare the triangles' corner positions instead.
    for t in 0..generated.triangles.len() {
        for (a, b) in shipped.triangle(t).iter().zip(generated.triangle(t)) {
            assert!(
                (*a - b).length() < 3e-5,
                "triangle {t}: shipped {a} vs generated {b}"
            );
        }
    }
    let cfg = small_config();
    let shape = Shape::carved(&shipped, &cfg.carve);
    let img = render(&Gradient, &shape, &cfg.mesh_camera, &cfg, 48, 48);
    let bg = Vec3::from(cfg.background);
    let covered = img
        .data
        .chunks_exact(3)
        .filter(|p| (Vec3::from_slice(p) - bg).length() > 1e-3)
        .count();
    assert!(
        covered > 48 * 48 / 8,
        "the bowl should cover part of the image ({covered} px)"
    );
    let strip = turntable(
        &Gradient,
        &shape,
        &RenderConfig {
            turntable_views: 3,
            ..cfg
        },
        16,
        16,
    );
    assert_eq!((strip.width, strip.height), (48, 16));
}

#[test]
fn bad_meshes_are_clear_errors() {
    let dir = common::scratch_dir("mesh");
    assert_mesh_error(&dir, "none.obj", "not found");
    std::fs::write(dir.join("empty.obj"), "v 0 0 0\n").unwrap();
    assert_mesh_error(&dir, "empty.obj", "no faces");
    // Issue 16 item 11: a NaN vertex is an error, not an empty picture.
    std::fs::write(
        dir.join("nan.obj"),
        "v 0 0 0\nv 1 0 0\nv 0 nan 0\nf 1 2 3\n",
    )
    .unwrap();
    match TriMesh::load_obj(&dir.join("nan.obj")) {
        Ok(_) => panic!("a NaN vertex was accepted"),
        Err(e) => {
            let err = e.to_string();
            assert!(err.contains("nan.obj") && err.contains("finite"), "{err}");
        }
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Loading `dir/name` fails with an error naming the file and saying `what`.
fn assert_mesh_error(dir: &std::path::Path, name: &str, what: &str) {
    let err = TriMesh::load_obj(&dir.join(name)).unwrap_err().to_string();
    assert!(err.contains(name) && err.contains(what), "{err}");
}

#[test]
fn exports_read_back_with_values_and_axis_order() {
    let dir = common::scratch("export");
    let vol = Volume::from_texture(&Gradient, 5);
    // A non-cubic volume catches swapped axes.
    let mut odd = Volume::zeros([3, 4, 5], 2);
    for i in 0..3 {
        for j in 0..4 {
            for k in 0..5 {
                let o = odd.offset(i, j, k);
                odd.data[o] = (100 * i + 10 * j + k) as f32;
                odd.data[o + 1] = -(k as f32);
            }
        }
    }
    for (name, v) in [("cube", &vol), ("odd", &odd)] {
        export(
            v,
            Values::Data,
            Format::Vol,
            &dir.join(format!("{name}.vol")),
            name,
        )
        .unwrap();
        let (back, bbox) = mitsuba::read_vol(&dir.join(format!("{name}.vol"))).unwrap();
        assert_eq!(&back, v);
        assert_eq!(bbox, [-0.5, -0.5, -0.5, 0.5, 0.5, 0.5]);
        export(
            v,
            Values::Data,
            Format::Nrrd,
            &dir.join(format!("{name}.nrrd")),
            name,
        )
        .unwrap();
        assert_eq!(
            &nrrd::read_nrrd(&dir.join(format!("{name}.nrrd"))).unwrap(),
            v
        );
        export(
            v,
            Values::Data,
            Format::Npy,
            &dir.join(format!("{name}.npy")),
            name,
        )
        .unwrap();
        assert_eq!(
            &xylem::io::npy::read_volume(&dir.join(format!("{name}.npy"))).unwrap(),
            v
        );
    }
    // The .vol layout is x fastest: the second float of data is voxel (1, 0, 0), channel 0.
    let bytes = std::fs::read(dir.join("odd.vol")).unwrap();
    let float = |n: usize| f32::from_le_bytes(bytes[48 + 4 * n..52 + 4 * n].try_into().unwrap());
    assert_eq!(float(2), 100.0, "x must vary fastest in .vol");
    assert_eq!(float(2 * 3), 10.0, "then y");
    // Values at voxel centres equal the texture there.
    let (back, _) = mitsuba::read_vol(&dir.join("cube.vol")).unwrap();
    let p = back.voxel_point(4, 1, 2);
    assert_eq!(back.voxel(4, 1, 2), Gradient.eval_vec(p).as_slice());
    let header = std::fs::read(dir.join("cube.nrrd")).unwrap();
    let end = header.windows(2).position(|w| w == b"\n\n").unwrap();
    let text = String::from_utf8_lossy(&header[..end]);
    assert!(
        text.contains("sizes: 3 5 5 5") && text.contains("space origin: (-1.6,-1.6,-1.6)"),
        "{text}"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}
