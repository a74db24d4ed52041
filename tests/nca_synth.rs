//! Synthesis: an untrained NCA (second layer zero) from a zero seed reproduces the base
//! colour B exactly, in photo colours and in the volume axis order.

use burn::tensor::Device;
use xylem::field::{BaseColour, FieldConfig, WhiteBalance};
use xylem::frame::Face;
use xylem::nca::ModelSpec;
use xylem::nca::conditioning::CondChannel;
use xylem::nca::fit_source::{FitRecord, RampColours};
use xylem::nca::model::Nca;
use xylem::nca::model_dir::{ModelMeta, TrainedModel};
use xylem::nca::synth::{SynthOptions, synthesise};
use xylem::presets::load_field_preset;
use xylem::texture::SolidTexture;

/// A fitted field: a preset with a two-node base colour bar, as `xylem fit` writes it.
fn fitted(preset: &str) -> FieldConfig {
    let mut field = load_field_preset(preset).unwrap();
    let mean = [0.6, 0.45, 0.3];
    field.base_colour = Some(BaseColour {
        g_range: [0.0, 20.0],
        bar: vec![[0.6, 0.5, 0.45], [0.35, 0.3, 0.25]],
        knot_bar: vec![],
        knot_blend: 1.0,
        face_offsets: [[0.0; 3]; 6],
        white_balance: WhiteBalance {
            face_means: [mean; 6],
            mean,
        },
    });
    field
}

#[test]
fn identity_model_synthesises_the_base_colour() {
    let ramp = FitRecord {
        field: load_field_preset("knot_alive").unwrap(),
        base_colour: Some(RampColours {
            light: [0.8, 0.6, 0.4],
            dark: [0.3, 0.2, 0.1],
        }),
    };
    let real = FitRecord {
        field: fitted("knot_alive"),
        base_colour: None,
    };
    for fit in [ramp, real] {
        identity_reproduces_b(fit);
    }
}

/// An untrained model unrolled from a zero seed gives B (in photo colours) at every voxel.
fn identity_reproduces_b(fit: FitRecord) {
    let device = Device::flex();
    let spec = ModelSpec {
        hidden: 8,
        seed_amplitude: 0.0,
        conditioning: vec![CondChannel::GreyB, CondChannel::G, CondChannel::RingPhase],
        ..ModelSpec::default()
    };
    let normalisation = fit.conditioning().normalisation([0.6, 0.45, 0.3]);
    let trained = TrainedModel {
        meta: ModelMeta {
            spec: spec.clone(),
            normalisation,
            grid: 10,
            seed: 1,
            faces: Face::ALL.to_vec(),
            iterations: 0,
        },
        model: Nca::init(&spec, 1, &device),
        fit,
    };
    let options = SynthOptions {
        size: 10,
        steps: 3,
        seed: 1,
        slab_voxels: 300,
    };
    let mut seen = Vec::new();
    let volume = synthesise(&trained, &options, &device, |s| seen.push(s)).unwrap();
    assert_eq!(seen, vec![1, 2, 3]);
    assert_eq!((volume.dims, volume.channels), ([10, 10, 10], 3));
    let colour = trained.fit.conditioning().colour;
    for (i, j, k) in [(0, 0, 0), (9, 2, 5), (3, 9, 0), (5, 5, 9)] {
        let expected = colour.eval_vec(volume.voxel_point(i, j, k));
        for (got, want) in volume.voxel(i, j, k).iter().zip(&expected) {
            assert!(
                (got - want).abs() < 1e-5,
                "voxel ({i}, {j}, {k}): {got} vs {want}"
            );
        }
    }
}
