//! Held-out colour with and without grain shading (issue 14), on finished `xylem run` folders.
//!
//!     cargo run --release --example grain_shading_lofo -- SAMPLE FACES RUN [RUN...]
//!
//! SAMPLE is the sample folder, FACES the faces each run was fitted and trained on, as a
//! `+`-separated list per run (e.g. `B,C,D,E,F+A,C,D,E,F`, one list per RUN in order). For
//! each run it estimates the grain shading from the fitted faces' photos and the run's fitted
//! fibre direction (what `xylem fit` now does), prints the estimate, then the metrics of the
//! NCA and the base colour on the held-out faces with the plain colour (as the run's
//! `metrics.csv`, written before grain shading existed) and seen with the shading. The NCA
//! volume and the fit are the run's own: nothing is retrained.

use std::path::PathBuf;

use xylem::config::ConfigFile;
use xylem::device::DeviceKind;
use xylem::field::{FieldConfig, GrainShaded};
use xylem::fit::grain_shading_fit::shaded_white_balance;
use xylem::frame::Face;
use xylem::io::npy::read_volume;
use xylem::pipeline::{RunLayout, metrics_table};
use xylem::procedural::ProceduralWood;
use xylem::sample::{Needs, Sample, parse_faces};

fn main() -> xylem::Result<()> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let usage = "usage: SAMPLE FACES[+FACES...] RUN [RUN...]";
    let sample = PathBuf::from(args.first().expect(usage));
    let face_lists: Vec<&str> = args.get(1).expect(usage).split('+').collect();
    let runs = &args[2..];
    assert_eq!(face_lists.len(), runs.len(), "one face list per run");
    let device = DeviceKind::Flex.device();
    println!("run,shading,method,image,ring_ncc,swd,swd_L,dE_mean,style");
    for (run, list) in runs.iter().zip(face_lists) {
        let faces = parse_faces(list)?;
        let photos = Sample::load(
            &sample,
            &Face::ALL,
            Needs {
                photos: true,
                arl: false,
            },
        )?;
        let layout = RunLayout::new(run);
        let fit = FieldConfig::load(&layout.fit_file())?;
        let (wb, estimate) = shaded_white_balance(&photos.photos, &faces, fit.pith.fibre_axis());
        if let Some(e) = &estimate {
            eprintln!(
                "{run}: t {:.2} side {:?} end {:?} kept {}",
                e.model.t_statistic,
                e.model.side.map(|v| (v * 255.0).round()),
                e.model.end.map(|v| (v * 255.0).round()),
                e.is_shown()
            );
        }
        // The procedural rows are not printed; any species will do.
        let procedural = ProceduralWood::new(&xylem::presets::load_species_preset("chestnut")?);
        let volume = read_volume(&layout.volume())?;
        for (label, grain) in [("plain", None), ("shaded", wb.grain.clone())] {
            let mut fit = fit.clone();
            let colour = fit.base_colour.as_mut().expect("a fit with base colour");
            colour.white_balance.grain = grain;
            let nca = GrainShaded::new(&volume, Some(&colour.white_balance));
            let table = metrics_table(&sample, &faces, &fit, &procedural, &nca, &device)?;
            let col = |name: &str| table.header.iter().position(|h| h == name).unwrap();
            for row in table.rows.iter().filter(|r| r[0] != "procedural") {
                let v = |name: &str| row[col(name)].parse::<f32>().unwrap_or(f32::NAN);
                println!(
                    "{run},{label},{},{},{:.4},{:.4},{:.4},{:.3},{:.4}",
                    row[0],
                    row[1],
                    v("ring_ncc"),
                    v("swd"),
                    v("swd_L"),
                    v("dE_mean"),
                    v("style")
                );
            }
        }
    }
    Ok(())
}
