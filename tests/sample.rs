//! Sample folders: the real Mokume layout loads, knot markers are found, bad folders give
//! errors naming the file.

mod common;

use xylem::frame::Face;
use xylem::sample::{Needs, Sample, parse_faces};

const ALL: Needs = Needs {
    photos: true,
    arl: true,
};

#[test]
fn real_samples_load_with_knot_markers() {
    let Some(dir) = common::mokume_dir() else {
        return;
    };
    let cn03 = Sample::load(&dir.join("CN03"), &Face::ALL, ALL).unwrap();
    assert_eq!(cn03.size, 256);
    assert!(cn03.knot_markers.is_empty());
    let h11 = Sample::load(&dir.join("H11"), &Face::ALL, ALL).unwrap();
    let knots = h11.knots();
    assert_eq!(knots.len(), 1, "H11 has one knot marked on two faces");
    let faces: Vec<Face> = knots[0].iter().map(|m| m.face).collect();
    assert_eq!(faces, vec![Face::C, Face::F]);
    let c = knots[0][0];
    assert_eq!((c.row, c.col), (184.0, 71.0));
    assert!(
        (c.point.x + 0.5).abs() < 1e-6,
        "a marker on C lies on x = -0.5"
    );
}

#[test]
fn broken_sample_folders_are_clear_errors() {
    let Some(dir) = common::mokume_dir() else {
        return;
    };
    let tmp = common::scratch_dir("sample");
    for f in Face::ALL {
        for kind in ["col", "arl-unet"] {
            let name = format!("{f}_{kind}.png");
            std::fs::copy(dir.join("CN03").join(&name), tmp.join(&name)).unwrap();
        }
    }
    std::fs::remove_file(tmp.join("D_col.png")).unwrap();
    let err = Sample::load(&tmp, &Face::ALL, ALL).unwrap_err().to_string();
    assert!(
        err.contains("D_col.png") && err.contains("missing"),
        "{err}"
    );
    std::fs::create_dir(tmp.join("D_col.png")).unwrap();
    let err = Sample::load(&tmp, &Face::ALL, ALL).unwrap_err().to_string();
    assert!(
        err.contains("D_col.png") && err.contains("not a regular file"),
        "{err}"
    );
    std::fs::remove_dir(tmp.join("D_col.png")).unwrap();
    // A subset without D loads.
    Sample::load(&tmp, &parse_faces("A,B,C,E,F").unwrap(), ALL).unwrap();
    // An ARL image of another size.
    let small = image::imageops::resize(
        &image::open(tmp.join("E_arl-unet.png")).unwrap().to_luma8(),
        100,
        100,
        image::imageops::FilterType::Triangle,
    );
    small.save(tmp.join("E_arl-unet.png")).unwrap();
    let err = Sample::load(&tmp, &parse_faces("A,E").unwrap(), ALL)
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("E_arl-unet.png") && err.contains("100x100") && err.contains("256x256"),
        "{err}"
    );
    // Issue 16 item 9: black, flat and tiny photos are refused, naming the file.
    let photo = |rgb: [u8; 3], side: u32| image::RgbImage::from_pixel(side, side, image::Rgb(rgb));
    for (img, expected) in [
        (photo([0, 0, 0], 256), "black"),
        (photo([180, 150, 120], 256), "flat"),
        (photo([180, 150, 120], 1), "at least 16x16"),
    ] {
        img.save(tmp.join("B_col.png")).unwrap();
        let err = Sample::load(&tmp, &parse_faces("B").unwrap(), ALL)
            .unwrap_err()
            .to_string();
        assert!(err.contains("B_col.png") && err.contains(expected), "{err}");
    }
    // Issue 16 item 6: stray pixels in a knot image are refused, not fitted as knots.
    let mut knots = image::GrayImage::from_pixel(256, 256, image::Luma([255]));
    for i in 0..12 {
        knots.put_pixel(10 + 20 * i, 30, image::Luma([100]));
    }
    knots.save(tmp.join("A_knot.png")).unwrap();
    let err = Sample::load(&tmp, &parse_faces("A").unwrap(), ALL)
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("A_knot.png") && err.contains("12 marker spots"),
        "{err}"
    );
    assert!(
        parse_faces("A,G")
            .unwrap_err()
            .to_string()
            .contains("\"G\"")
    );
    std::fs::remove_dir_all(&tmp).unwrap();
}
