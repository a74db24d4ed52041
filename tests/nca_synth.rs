//! Synthesis: an untrained NCA (second layer zero) from a zero seed reproduces the base
//! colour B exactly, in photo colours and in the volume axis order, with both engines; a
//! trained-like model gives the same volume with both.

mod common;

use burn::module::Param;
use burn::tensor::Device;
use xylem::field::FieldConfig;
use xylem::frame::Face;
use xylem::nca::CondChannel;
use xylem::nca::ModelSpec;
use xylem::nca::config::Engine;
use xylem::nca::fit_source::{FitRecord, RampColours};
use xylem::nca::model::Nca;
use xylem::nca::model_dir::{ModelMeta, TrainedModel};
use xylem::nca::synth::{SynthOptions, synthesise};
use xylem::nca::tensors::tensor_from;
use xylem::presets::load_field_preset;
use xylem::rng::Rng;
use xylem::texture::SolidTexture;

/// A model of `spec` with the second layer zero, on the fit `fit`.
fn trained(spec: &ModelSpec, fit: FitRecord, device: &Device) -> TrainedModel {
    let normalisation = fit.conditioning().normalisation([0.6, 0.45, 0.3]);
    TrainedModel {
        meta: ModelMeta {
            spec: spec.clone(),
            normalisation,
            grid: 10,
            seed: 1,
            faces: Face::ALL.to_vec(),
            iterations: 0,
            weights_hash: None,
        },
        model: Nca::init(spec, 1, device),
        fit,
    }
}

/// The stand-in ramp fit: a preset field with a light-to-dark ramp as base colour.
fn ramp_fit() -> FitRecord {
    FitRecord {
        field: load_field_preset("knot_alive").unwrap(),
        base_colour: Some(RampColours {
            light: [0.8, 0.6, 0.4],
            dark: [0.3, 0.2, 0.1],
        }),
    }
}

fn options(engine: Engine) -> SynthOptions {
    SynthOptions {
        size: 10,
        steps: 3,
        seed: 1,
        slab_voxels: 300,
        engine,
    }
}

/// A fitted field: a preset with a two-node base colour bar, as `xylem fit` writes it.
fn fitted(preset: &str) -> FieldConfig {
    let mut field = load_field_preset(preset).unwrap();
    let mut colour = common::flat_base_colour([0.6, 0.45, 0.3]);
    colour.bar = vec![[0.6, 0.5, 0.45], [0.35, 0.3, 0.25]];
    field.base_colour = Some(colour);
    field
}

#[test]
fn identity_model_synthesises_the_base_colour() {
    for fit in [ramp_fit(), real_fit()] {
        identity_reproduces_b(fit);
    }
}

/// The fit `xylem fit` writes: the base colour lives in the field, no stand-in ramp.
fn real_fit() -> FitRecord {
    FitRecord {
        field: fitted("knot_alive"),
        base_colour: None,
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
    let trained = trained(&spec, fit, &device);
    for engine in [Engine::Fused, Engine::Burn] {
        let mut seen = Vec::new();
        let volume = synthesise(&trained, &options(engine), &device, |s| seen.push(s)).unwrap();
        assert_eq!(seen, vec![1, 2, 3]);
        assert_eq!((volume.dims, volume.channels), ([10, 10, 10], 3));
        let colour = trained.fit.conditioning().colour;
        for (i, j, k) in [(0, 0, 0), (9, 2, 5), (3, 9, 0), (5, 5, 9)] {
            let expected = colour.eval_vec(volume.voxel_point(i, j, k));
            for (got, want) in volume.voxel(i, j, k).iter().zip(&expected) {
                assert!(
                    (got - want).abs() < 1e-5,
                    "{engine:?}, voxel ({i}, {j}, {k}): {got} vs {want}"
                );
            }
        }
    }
}

#[test]
fn fused_and_burn_synthesis_agree() {
    let device = Device::flex();
    // Every conditioning channel, so both engines must also see the same grain and ray noise.
    let spec = ModelSpec {
        hidden: 16,
        conditioning: vec![
            CondChannel::GreyB,
            CondChannel::G,
            CondChannel::RingPhase,
            CondChannel::GrainNoise,
            CondChannel::RayNoise,
        ],
        ..ModelSpec::default()
    };
    let mut trained = trained(&spec, real_fit(), &device);
    let mut rng = Rng::new(3);
    let w2: Vec<f32> = (0..spec.state_channels * 16)
        .map(|_| 0.2 * rng.normal())
        .collect();
    trained.model.w2 = Param::from_tensor(tensor_from(w2, [spec.state_channels, 16], &device));
    let run = |engine| synthesise(&trained, &options(engine), &device, |_| {}).unwrap();
    let (fused, burn) = (run(Engine::Fused), run(Engine::Burn));
    let base = run_identity(&trained, &device);
    let change: Vec<f32> = burn.data.iter().zip(&base).map(|(a, b)| a - b).collect();
    let scale = change.iter().map(|v| v.abs()).fold(0.0f32, f32::max);
    let worst = common::max_abs_diff(&fused.data, &burn.data);
    assert!(scale > 0.01, "the model must change the colours ({scale})");
    assert!(
        worst <= 1e-5 * scale,
        "max difference {worst} for changes up to {scale}"
    );
}

/// The volume of the same model with its second layer zeroed (B plus the seed).
fn run_identity(trained: &TrainedModel, device: &Device) -> Vec<f32> {
    let spec = &trained.meta.spec;
    let identity = TrainedModel {
        meta: trained.meta.clone(),
        fit: trained.fit.clone(),
        model: Nca::init(spec, 1, device),
    };
    synthesise(&identity, &options(Engine::Burn), device, |_| {})
        .unwrap()
        .data
}
