//! How the style loss ranks real photos: for every face of CN03 and H11 as the target (its
//! top-left 128 px, white-balanced), the loss of the bottom-right 128 px of the same photo
//! and of the centre 128 px of all twelve faces. Prints one row per target; the evidence
//! behind the ranking test and docs/DESIGN.md.
//!
//!     XYLEM_MOKUME_DIR=/work/shared/data/mokume cargo run --release --example loss_ranking [-- LOSS.toml]

use std::path::PathBuf;

use burn::tensor::Device;
use xylem::Image2;
use xylem::config::ConfigFile;
use xylem::io::load_rgb;
use xylem::loss::{LossConfig, StyleLoss, image_to_tensor};

fn main() {
    let dir = std::env::var_os("XYLEM_MOKUME_DIR")
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from("../shared/data/mokume"));
    let cfg = match std::env::args().nth(1) {
        Some(path) => LossConfig::load(std::path::Path::new(&path)).expect("loss config"),
        None => LossConfig::default_config(),
    };
    let names: Vec<(String, String)> = ["CN03", "H11"]
        .iter()
        .flat_map(|c| ["A", "B", "C", "D", "E", "F"].map(|f| (c.to_string(), f.to_string())))
        .collect();
    let faces: Vec<Image2> = names
        .iter()
        .map(|(c, f)| {
            load_rgb(&dir.join(c).join(format!("{f}_col.png")))
                .expect("face")
                .white_balanced()
        })
        .collect();
    let device = Device::flex();
    let loss = StyleLoss::new(&cfg, &device);
    print!("{:>8} {:>9}", "target", "crop");
    for (c, f) in &names {
        print!(" {:>9}", format!("{c}{f}"));
    }
    println!("   holds");
    let mut holds = 0;
    for (i, face) in faces.iter().enumerate() {
        let targets = loss
            .targets(&[face.crop(0, 0, 128, 128).unwrap()])
            .expect("targets");
        let score = |img: &Image2| {
            loss.loss(&[image_to_tensor(img, &device)], &targets, &[0])
                .expect("loss")
                .into_scalar::<f32>()
        };
        let same_crop = score(&face.crop(128, 128, 128, 128).unwrap());
        let row: Vec<f32> = faces
            .iter()
            .map(|f| score(&f.crop(64, 64, 128, 128).unwrap()))
            .collect();
        let cube = i / 6;
        let closest_other = closest(&row, |j| j / 6 != cube);
        let same_cube_closer = (0..12)
            .filter(|&j| j / 6 == cube && j != i)
            .filter(|&j| row[j] < closest_other)
            .count();
        print!(
            "{:>8} {same_crop:>9.4}",
            format!("{}{}", names[i].0, names[i].1)
        );
        for v in &row {
            print!(" {v:>9.4}");
        }
        let ok = same_crop < closest_other;
        holds += ok as usize;
        println!(
            "   crop<other: {ok}, same-cube faces closer than any other-cube face: {same_cube_closer}/5"
        );
    }
    println!("other crop closer than every face of the other cube: {holds}/12 targets");
    whole_faces(&loss, &names, &faces, &device);
}

/// The smallest score among the columns `keep` accepts.
fn closest(row: &[f32], keep: impl Fn(usize) -> bool) -> f32 {
    (0..row.len())
        .filter(|&j| keep(j))
        .map(|j| row[j])
        .fold(f32::INFINITY, f32::min)
}

/// The same with whole faces: each face's statistics as the target (what the NCA trains
/// against), every other whole face as the candidate.
fn whole_faces(loss: &StyleLoss, names: &[(String, String)], faces: &[Image2], device: &Device) {
    println!("\nwhole faces (256 px) against whole faces:");
    print!("{:>8}", "target");
    for (c, f) in names {
        print!(" {:>9}", format!("{c}{f}"));
    }
    println!();
    let mut holds = 0;
    for (i, face) in faces.iter().enumerate() {
        let targets = loss.targets(std::slice::from_ref(face)).expect("targets");
        let row: Vec<f32> = faces
            .iter()
            .map(|f| {
                loss.loss(&[image_to_tensor(f, device)], &targets, &[0])
                    .expect("loss")
                    .into_scalar::<f32>()
            })
            .collect();
        let cube = i / 6;
        let closest_other = closest(&row, |j| j / 6 != cube);
        let closest_same = closest(&row, |j| j / 6 == cube && j != i);
        print!("{:>8}", format!("{}{}", names[i].0, names[i].1));
        for v in &row {
            print!(" {v:>9.4}");
        }
        let ok = closest_same < closest_other;
        holds += ok as usize;
        println!("   closest face is of the same cube: {ok}");
    }
    println!("closest other face is of the same cube: {holds}/12 targets");
}
