//! The fixed cube frame: face table, shared edges, cuts, planes, volumes, and the check of the
//! face table against the real Mokume ring images.

mod common;

use glam::Vec3;
use xylem::frame::{
    Face, FaceImageTransform, Plane, PlaneSpec, cube_edges, edge_agreement, pixel_centre,
};
use xylem::io::load_gray;
use xylem::slice::{slice_plane, unfold_cross};
use xylem::texture::SolidTexture;
use xylem::{Image2, Volume};

#[test]
fn face_table_round_trips_pixel_point_pixel() {
    for n in [1, 7, 256] {
        for face in Face::ALL {
            for (r, c) in [
                (0, 0),
                (n - 1, 0),
                (0, n - 1),
                (n / 2, n / 3),
                (n - 1, n - 1),
            ] {
                let p = face.pixel_point(r, c, n);
                assert!(
                    (p.dot(face.normal()) - 0.5).abs() < 1e-6,
                    "{face} pixel not on its face"
                );
                let (rr, cc) = face.point_pixel(p, n);
                assert!(
                    (rr - r as f32).abs() < 1e-3 && (cc - c as f32).abs() < 1e-3,
                    "{face} {r},{c} -> {rr},{cc}"
                );
            }
        }
    }
}

#[test]
fn face_table_matches_design() {
    // Spot checks of DESIGN section 2: top-left pixel centre of a 2x2 image is (u, v) = (-1/4, -1/4).
    let (u, v) = (pixel_centre(0, 2), pixel_centre(0, 2));
    assert_eq!((u, v), (-0.25, -0.25));
    assert_eq!(Face::A.pixel_point(0, 0, 2), Vec3::new(u, -v, 0.5));
    assert_eq!(Face::B.pixel_point(0, 0, 2), Vec3::new(u, 0.5, v));
    assert_eq!(Face::C.pixel_point(0, 0, 2), Vec3::new(-0.5, -v, u));
    assert_eq!(Face::D.pixel_point(0, 0, 2), Vec3::new(u, -0.5, -v));
    assert_eq!(Face::E.pixel_point(0, 0, 2), Vec3::new(0.5, -v, -u));
    assert_eq!(Face::F.pixel_point(0, 0, 2), Vec3::new(-u, -v, -0.5));
}

#[test]
fn shared_cube_edges_hold_the_same_points() {
    let edges = cube_edges();
    assert_eq!(edges.len(), 12);
    for face in Face::ALL {
        assert_eq!(
            edges
                .iter()
                .filter(|(a, b)| *a == face || *b == face)
                .count(),
            4
        );
    }
    let n = 64;
    for (a, b) in edges {
        // Walk face a's border lines; the one lying in face b's plane must consist of points of
        // face b's border, at the same pixel-centre positions.
        let mut matched = 0;
        for t in 0..n {
            let s = pixel_centre(t, n);
            for (u, v) in [(s, -0.5), (s, 0.5), (-0.5, s), (0.5, s)] {
                let p = a.point(u, v);
                if (p.dot(b.normal()) - 0.5).abs() > 1e-6 {
                    continue;
                }
                let (ub, vb) = b.uv(p);
                assert!(
                    ub.abs() <= 0.5 + 1e-6 && vb.abs() <= 0.5 + 1e-6,
                    "{a}/{b}: {p} outside face {b}"
                );
                assert!((b.point(ub, vb) - p).length() < 1e-6);
                let on_border = (ub.abs() - 0.5).abs() < 1e-6 || (vb.abs() - 0.5).abs() < 1e-6;
                assert!(on_border, "{a}/{b}: {p} is not on the border of {b}");
                let along = if (ub.abs() - 0.5).abs() < 1e-6 {
                    vb
                } else {
                    ub
                };
                let k = ((along + 0.5) * n as f32 - 0.5).round();
                assert!(
                    (pixel_centre(k as usize, n) - along).abs() < 1e-5,
                    "{a}/{b}: not a pixel centre of {b}"
                );
                matched += 1;
            }
        }
        assert_eq!(matched, n, "edge {a}/{b} should have {n} shared points");
    }
}

#[test]
fn cuts_follow_their_plane_equations_and_pixel_layout() {
    let n = 16;
    for (plane, along_z) in [(Plane::cut1(), false), (Plane::cut2(), true)] {
        for r in 0..n {
            for c in 0..n {
                let p = plane.pixel_point(r, c, n, n);
                assert!((p.z - pixel_centre(r, n)).abs() < 1e-6, "row -> z");
                assert!((p.y + pixel_centre(c, n)).abs() < 1e-6, "column -> -y");
                let driver = if along_z { p.z } else { p.y };
                assert!(
                    (p.x - (0.575 * (driver + 0.5) - 0.375)).abs() < 1e-6,
                    "plane equation"
                );
            }
        }
    }
}

#[test]
fn plane_specs_parse_and_reject_bad_input() {
    assert_eq!("cut1".parse::<PlaneSpec>().unwrap(), PlaneSpec::Cut1);
    assert_eq!("c".parse::<PlaneSpec>().unwrap(), PlaneSpec::Face(Face::C));
    let custom: PlaneSpec = "-0.5,0,0.5; 1,0,0; 0,0,-1".parse().unwrap();
    assert_eq!(
        custom.plane(),
        Plane::new(Vec3::new(-0.5, 0.0, 0.5), Vec3::X, Vec3::NEG_Z)
    );
    for bad in [
        "cut3",
        "1,2,3;4,5,6",
        "1,2;3,4,5;6,7,8",
        "0,0,0;1,0,0;2,0,0",
        "a,b,c;1,0,0;0,1,0",
    ] {
        let err = bad.parse::<PlaneSpec>().unwrap_err().to_string();
        assert!(
            err.contains("`plane`") && err.contains("expected"),
            "{bad}: {err}"
        );
    }
    // The face plane samples exactly the face table's pixels.
    let p = Plane::face(Face::E);
    assert!((p.pixel_point(3, 5, 8, 8) - Face::E.pixel_point(3, 5, 8)).length() < 1e-6);
}

/// A texture returning the point itself, to check what slices sample.
struct Coordinates;
impl SolidTexture for Coordinates {
    fn channels(&self) -> usize {
        3
    }
    fn eval(&self, p: Vec3, out: &mut [f32]) {
        out.copy_from_slice(&p.to_array());
    }
}

#[test]
fn slices_and_cross_place_pixels_where_the_table_says() {
    let n = 8;
    let img = slice_plane(&Coordinates, &Plane::face(Face::D), n, n);
    assert_eq!(img.pixel(2, 5), Face::D.pixel_point(2, 5, n).to_array());
    let faces = Face::ALL.map(|f| slice_plane(&Coordinates, &Plane::face(f), n, n));
    let cross = unfold_cross(&faces, -9.0);
    assert_eq!((cross.width, cross.height), (4 * n, 3 * n));
    // B is above A, F is the last tile of the middle row, corners are background.
    assert_eq!(
        cross.pixel(1, n + 1),
        Face::B.pixel_point(1, 1, n).to_array()
    );
    assert_eq!(
        cross.pixel(n + 2, 3 * n + 4),
        Face::F.pixel_point(2, 4, n).to_array()
    );
    assert_eq!(cross.pixel(0, 0), [-9.0, -9.0, -9.0]);
    // Neighbouring tiles meet on shared edges: the last column of A and the first of E are
    // one pixel apart across the cube edge x = 0.5, z = 0.5.
    let a_edge = Vec3::from_slice(cross.pixel(n + 3, 2 * n - 1));
    let e_edge = Vec3::from_slice(cross.pixel(n + 3, 2 * n));
    assert!(
        (a_edge - e_edge).length() < 1.5 / n as f32,
        "{a_edge} vs {e_edge}"
    );
}

#[test]
fn volume_trilinear_reproduces_voxels_and_linear_functions() {
    let n = 6;
    let linear = |p: Vec3| 0.3 * p.x - 2.0 * p.y + 0.7 * p.z + 1.0;
    let mut vol = Volume::zeros([n, n, n], 2);
    for i in 0..n {
        for j in 0..n {
            for k in 0..n {
                let p = vol.voxel_point(i, j, k);
                let o = vol.offset(i, j, k);
                vol.data[o] = linear(p);
                vol.data[o + 1] = (i * 100 + j * 10 + k) as f32;
            }
        }
    }
    assert_eq!(vol.eval_vec(vol.voxel_point(1, 4, 2))[1], 142.0);
    let mut rng = xylem::rng::Rng::new(2);
    let inner = 0.5 - 0.5 / n as f32;
    for _ in 0..200 {
        let p = Vec3::new(
            rng.range(-inner, inner),
            rng.range(-inner, inner),
            rng.range(-inner, inner),
        );
        assert!((vol.eval_vec(p)[0] - linear(p)).abs() < 1e-4);
    }
    let from_tex = Volume::from_texture(&Coordinates, 4);
    assert_eq!(from_tex.voxel(3, 0, 1), [0.375, -0.375, -0.125]);
}

#[test]
fn npy_round_trip_keeps_shape_values_and_axis_order() {
    let dir = std::env::temp_dir().join(format!("xylem-npy-{}", std::process::id()));
    let vol = Volume::from_texture(&Coordinates, 5);
    let path = dir.join("v.npy");
    xylem::io::npy::write_volume(&path, &vol).unwrap();
    let back = xylem::io::npy::read_volume(&path).unwrap();
    assert_eq!(back, vol);
    // vol[i, j, k] is the value at (x_i, y_j, z_k).
    let expected = Vec3::new(0.4, -0.2, -0.4);
    assert!((Vec3::from_slice(back.voxel(4, 1, 0)) - expected).length() < 1e-6);
    std::fs::write(dir.join("bad.npy"), b"not numpy").unwrap();
    let err = xylem::io::npy::read_volume(&dir.join("bad.npy"))
        .unwrap_err()
        .to_string();
    assert!(err.contains("bad.npy") && err.contains("NUMPY"), "{err}");
    // Issue 16 items 5 and 11: crafted headers are refused, not read as something else.
    let crafted = |dict: &str| {
        let mut text = dict.to_string();
        while !(10 + text.len() + 1).is_multiple_of(64) {
            text.push(' ');
        }
        text.push('\n');
        let mut bytes = b"\x93NUMPY\x01\x00".to_vec();
        bytes.extend_from_slice(&(text.len() as u16).to_le_bytes());
        bytes.extend_from_slice(text.as_bytes());
        let path = dir.join("crafted.npy");
        std::fs::write(&path, bytes).unwrap();
        xylem::io::npy::read_volume(&path).unwrap_err().to_string()
    };
    let err = crafted(
        "{'descr': '<f4', 'fortran_order': False, 'shape': (4611686018427387904, 4, 1, 1), }",
    );
    assert!(err.contains("too large"), "{err}");
    let err = crafted("{'descr': '<f8', 'fortran_order': False, 'shape': (1, 1, 1, 3), }");
    assert!(err.contains("float32"), "{err}");
    let err = crafted(
        "{'descr': '<f8', 'x': '<f4', 'descr': '<f4', 'fortran_order': False, 'shape': (1, 1, 1, 3), }",
    );
    assert!(err.contains("float32"), "{err}");
    std::fs::remove_dir_all(&dir).unwrap();
}

fn mean(v: &[f32]) -> f32 {
    v.iter().sum::<f32>() / v.len() as f32
}

#[test]
fn design_table_makes_real_rings_most_continuous_across_cube_edges() {
    let Some(dir) = common::mokume_dir() else {
        return;
    };
    for sample in ["CN03", "H11"] {
        let images: [Image2; 6] = Face::ALL.map(|f| {
            load_gray(&dir.join(sample).join(format!("{f}_arl-unet.png"))).expect("ARL image")
        });
        let design = mean(&edge_agreement(&images, FaceImageTransform::Identity));
        for t in &FaceImageTransform::ALL[1..] {
            let other = mean(&edge_agreement(&images, *t));
            eprintln!("{sample}: DESIGN table {design:.3}, {t:?} {other:.3}");
            assert!(
                design > other + 0.1,
                "{sample}: edge agreement under the DESIGN table ({design:.3}) should clearly beat {t:?} ({other:.3})"
            );
        }
    }
}

/// Issue 16 item 11: temporary files a killed xylem left in an output folder are removed
/// when the folder is used again; those of a running process are kept.
#[test]
fn output_folders_drop_temporary_files_of_dead_processes() {
    let dir = std::env::temp_dir().join(format!("xylem-temps-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let out = xylem::io::OutputDir::prepare(&dir).unwrap();
    std::fs::create_dir_all(out.path("synth")).unwrap();
    // 4194304 is above Linux's largest process id, so no process has it.
    let stale = out.path("synth/.volume.npy.4194305.tmp");
    let live = out.path(format!(".loss.csv.{}.tmp", std::process::id()));
    let user = out.path("notes.tmp");
    for f in [&stale, &live, &user] {
        std::fs::write(f, b"x").unwrap();
    }
    xylem::io::OutputDir::prepare(&dir).unwrap();
    if std::path::Path::new("/proc/self").exists() {
        assert!(!stale.exists(), "stale temporary file kept");
    }
    assert!(live.exists() && user.exists());
    std::fs::remove_dir_all(&dir).unwrap();
}
