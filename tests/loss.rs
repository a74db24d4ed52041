//! The style loss: self-distance zero, gradients against finite differences, size
//! independence, determinism, errors, both CPU backends, and the ranking on the real photos.

mod common;

use burn::tensor::{Device, Tensor};
use xylem::Image2;
use xylem::config::ConfigFile;
use xylem::config::{Checker, parse_toml};
use xylem::io::load_rgb;
use xylem::loss::{LossConfig, Nonlinearity, StyleLoss, image_to_tensor};

/// A small deterministic wood-like image: diagonal bands with dots, in brown tones.
fn banded(w: usize, h: usize, phase: f32) -> Image2 {
    let mut img = Image2::filled(w, h, 3, 0.0);
    for r in 0..h {
        for c in 0..w {
            let t = ((c as f32 + 0.6 * r as f32) * 0.35 + phase).sin();
            let dot = if (r * 7 + c * 13) % 11 == 0 {
                -0.2
            } else {
                0.0
            };
            let v = 0.55 + 0.15 * t + dot;
            img.pixel_mut(r, c)
                .copy_from_slice(&[v + 0.1, v, v - 0.12 + 0.02 * (c % 3) as f32]);
        }
    }
    img
}

/// Every term switched on, small enough for tiny images.
fn all_terms() -> LossConfig {
    let mut cfg = LossConfig::default_config();
    cfg.octaves = 2;
    cfg.min_layer_pixels = 16;
    cfg.filters.kernel_sizes = vec![3];
    cfg.filters.random = 4;
    cfg.filters.orientations = 1;
    cfg.filters.chroma = 1.0;
    cfg.joint_colour = true;
    cfg.swd.projections = 4;
    cfg.weights.gram = 1.0;
    cfg.weights.mean = 1.0;
    cfg.weights.covariance = 1.0;
    cfg.weights.swd = 1.0;
    cfg.weights.colour = 1.0;
    cfg
}

fn value(t: Tensor<1>) -> f32 {
    t.into_scalar::<f32>()
}

/// [`all_terms`] with every weight 0 but the sliced Wasserstein and colour terms'.
fn swd_and_colour(swd: f32, colour: f32) -> LossConfig {
    let mut cfg = all_terms();
    cfg.weights = xylem::loss::config::LossWeights {
        gram: 0.0,
        mean: 0.0,
        covariance: 0.0,
        swd,
        colour,
    };
    cfg
}

/// The loss under `cfg` of `img` against the single target `target`.
fn loss_against(cfg: &LossConfig, target: &Image2, img: &Image2, device: &Device) -> f32 {
    let loss = StyleLoss::new(cfg, device);
    let targets = loss.targets(std::slice::from_ref(target)).unwrap();
    value(
        loss.loss(&[image_to_tensor(img, device)], &targets, &[0])
            .unwrap(),
    )
}

#[test]
fn every_term_of_an_image_against_itself_is_zero() {
    let device = Device::flex();
    let img = banded(40, 36, 0.0);
    for nonlinearity in [Nonlinearity::Relu, Nonlinearity::Abs, Nonlinearity::None] {
        let mut cfg = all_terms();
        cfg.filters.nonlinearity = nonlinearity;
        let loss = StyleLoss::new(&cfg, &device);
        let targets = loss.targets(std::slice::from_ref(&img)).unwrap();
        let terms = loss
            .terms(&[image_to_tensor(&img, &device)], &targets, &[0], 0)
            .unwrap();
        let values = terms.values();
        assert_eq!(values.len(), 5, "all five terms computed: {values:?}");
        for (name, v) in values {
            assert!(v.abs() < 1e-6, "{name} of an image against itself = {v}");
        }
        // and a different image (finer, stronger bands, darker, noisy) is not at zero
        let other = banded(40, 36, 1.3);
        let noisy = Image2 {
            data: other
                .data
                .iter()
                .enumerate()
                .map(|(i, v)| {
                    let (r, c) = (i / (3 * 40), (i / 3) % 40);
                    let fine = ((r + 2 * c) as f32 * 1.1).sin();
                    0.2 + 0.6 * v + 0.15 * fine + 0.1 * ((i * 7919 % 101) as f32 / 101.0 - 0.5)
                })
                .collect(),
            ..other
        };
        let terms = loss
            .terms(&[image_to_tensor(&noisy, &device)], &targets, &[0], 0)
            .unwrap();
        for (name, v) in terms.values() {
            // linear responses of zero-mean filters average to ~0 on any image, so the mean
            // term carries information only after a nonlinearity
            if nonlinearity == Nonlinearity::None && name == "mean" {
                continue;
            }
            assert!(
                v > 1e-3,
                "{nonlinearity:?}: {name} of a different image = {v}"
            );
        }
    }
}

/// The loss of a `[3, h, w]` image given as data.
fn loss_of(
    loss: &StyleLoss,
    targets: &xylem::loss::StyleTargets,
    data: &[f32],
    h: usize,
    w: usize,
) -> f32 {
    let device = Device::flex();
    let x = Tensor::<3>::from_data(
        burn::tensor::TensorData::new(data.to_vec(), [3, h, w]),
        &device,
    );
    value(loss.loss(&[x], targets, &[0]).unwrap())
}

#[test]
fn gradients_match_finite_differences() {
    let (h, w) = (14, 16);
    for nonlinearity in [Nonlinearity::None, Nonlinearity::Relu] {
        let mut cfg = all_terms();
        cfg.filters.nonlinearity = nonlinearity;
        if nonlinearity == Nonlinearity::Relu {
            // The chroma-edge responses of this nearly grey image sit at ReLU's kink, where
            // finite differences straddle it (autodiff and differences differ by ~2x there).
            cfg.filters.chroma = 0.0;
        }
        check_gradients(&cfg, h, w);
    }
}

/// Autodiff against central differences at every 37th input value.
fn check_gradients(cfg: &LossConfig, h: usize, w: usize) {
    let device = Device::flex().autodiff();
    let loss = StyleLoss::new(cfg, &device);
    let targets = loss.targets(&[banded(24, 24, 0.0)]).unwrap();
    let generated = banded(w, h, 2.0);
    let x = image_to_tensor(&generated, &device).require_grad();
    let grads = loss
        .loss(std::slice::from_ref(&x), &targets, &[0])
        .unwrap()
        .backward();
    let analytic: Vec<f32> = x
        .grad(&grads)
        .unwrap()
        .into_data()
        .convert::<f32>()
        .try_to_vec()
        .unwrap();
    let base: Vec<f32> = image_to_tensor(&generated, &Device::flex())
        .into_data()
        .try_to_vec()
        .unwrap();
    let eps = 1e-3f32;
    let mut checked = 0;
    for index in (0..base.len()).step_by(37) {
        let mut plus = base.clone();
        plus[index] += eps;
        let mut minus = base.clone();
        minus[index] -= eps;
        let numeric = (loss_of(&loss, &targets, &plus, h, w)
            - loss_of(&loss, &targets, &minus, h, w))
            / (2.0 * eps);
        let a = analytic[index];
        let tolerance = 0.05 * a.abs().max(numeric.abs()) + 2e-3;
        assert!(
            (a - numeric).abs() <= tolerance,
            "{:?} pixel value {index}: autodiff {a}, finite differences {numeric}",
            cfg.filters.nonlinearity
        );
        checked += 1;
    }
    assert!(checked >= 15);
    let largest = analytic.iter().fold(0f32, |m, v| m.max(v.abs()));
    assert!(largest > 1e-3, "gradient is not trivially zero ({largest})");
}

#[test]
fn a_crop_is_compared_with_the_whole_target_by_distribution() {
    let device = Device::flex();
    let cfg = LossConfig::default_config();
    let loss = StyleLoss::new(&cfg, &device);
    let face = banded(96, 96, 0.0);
    let targets = loss.targets(std::slice::from_ref(&face)).unwrap();
    let crop = face.crop(30, 20, 48, 48).unwrap();
    let flat = Image2::filled(48, 48, 3, 0.5);
    let l_crop = value(
        loss.loss(&[image_to_tensor(&crop, &device)], &targets, &[0])
            .unwrap(),
    );
    let l_flat = value(
        loss.loss(&[image_to_tensor(&flat, &device)], &targets, &[0])
            .unwrap(),
    );
    assert!(
        l_crop < 0.1 * l_flat,
        "a crop of the target ({l_crop}) should be far closer than a flat image ({l_flat})"
    );
}

#[test]
fn projections_are_fixed_or_redrawn_per_call_deterministically() {
    let device = Device::flex();
    let target = banded(64, 64, 0.0);
    let generated = image_to_tensor(&banded(40, 40, 1.0), &device);
    let mut cfg = LossConfig::default_config();
    for redraw in [false, true] {
        cfg.swd.redraw = redraw;
        let a = StyleLoss::new(&cfg, &device);
        let b = StyleLoss::new(&cfg, &device);
        let ta = a.targets(std::slice::from_ref(&target)).unwrap();
        let tb = b.targets(std::slice::from_ref(&target)).unwrap();
        let at = |l: &StyleLoss, t, call| {
            value(
                l.loss_at(std::slice::from_ref(&generated), t, &[0], call)
                    .unwrap(),
            )
        };
        assert_eq!(
            at(&a, &ta, 3),
            at(&b, &tb, 3),
            "same seed and call, same loss"
        );
        let differs = at(&a, &ta, 3) != at(&a, &ta, 4);
        assert_eq!(
            differs, redraw,
            "redraw = {redraw}: calls 3 and 4 differ = {differs}"
        );
    }
    cfg.seed += 1;
    let c = StyleLoss::new(&cfg, &device);
    let tc = c.targets(std::slice::from_ref(&target)).unwrap();
    let other_seed = value(
        c.loss_at(std::slice::from_ref(&generated), &tc, &[0], 3)
            .unwrap(),
    );
    cfg.seed -= 1;
    let d = StyleLoss::new(&cfg, &device);
    let td = d.targets(std::slice::from_ref(&target)).unwrap();
    assert_ne!(
        other_seed,
        value(d.loss_at(&[generated], &td, &[0], 3).unwrap())
    );
}

#[test]
fn bad_inputs_are_errors_not_panics() {
    let device = Device::flex();
    let loss = StyleLoss::new(&LossConfig::default_config(), &device);
    let err = loss.targets(&[Image2::filled(4, 4, 3, 0.5)]).unwrap_err();
    assert!(err.to_string().contains("style target 0"), "{err}");
    let targets = loss.targets(&[banded(64, 64, 0.0)]).unwrap();
    let x = image_to_tensor(&banded(32, 32, 0.0), &device);
    let err = loss
        .loss(std::slice::from_ref(&x), &targets, &[1])
        .unwrap_err();
    assert!(err.to_string().contains("target index below 1"), "{err}");
    let err = loss
        .loss(std::slice::from_ref(&x), &targets, &[])
        .unwrap_err();
    assert!(err.to_string().contains("pairs"), "{err}");
    let tiny = image_to_tensor(&Image2::filled(3, 3, 3, 0.5), &device);
    let err = loss.loss(&[tiny], &targets, &[0]).unwrap_err();
    assert!(err.to_string().contains("generated image 0"), "{err}");
    let text = LossConfig::default_config();
    let bad = toml::to_string(&text)
        .unwrap()
        .replace("projections = 32", "projections = 0");
    let parsed: LossConfig = parse_toml(&bad, std::path::Path::new("bad.toml")).unwrap();
    let err = parsed
        .validate(&Checker::new(std::path::Path::new("bad.toml")))
        .unwrap_err();
    assert!(err.to_string().contains("swd.projections"), "{err}");
}

#[test]
fn flex_and_ndarray_agree() {
    let cfg = all_terms();
    let target = banded(32, 32, 0.0);
    let generated = banded(24, 24, 1.0);
    let values: Vec<f32> = [Device::flex(), {
        #[allow(deprecated)]
        Device::ndarray()
    }]
    .iter()
    .map(|device| {
        let ad = device.clone().autodiff();
        let loss = StyleLoss::new(&cfg, &ad);
        let targets = loss.targets(std::slice::from_ref(&target)).unwrap();
        let x = image_to_tensor(&generated, &ad).require_grad();
        let l = loss.loss(std::slice::from_ref(&x), &targets, &[0]).unwrap();
        let grads = l.backward();
        assert!(x.grad(&grads).is_some(), "gradient on {device:?}");
        value(l)
    })
    .collect();
    assert!(
        (values[0] - values[1]).abs() <= 1e-4 * values[0].abs().max(1.0),
        "flex {} vs ndarray {}",
        values[0],
        values[1]
    );
}

#[test]
fn loss_ranks_real_photos_same_wood_closer_than_the_other_cube() {
    let Some(dir) = common::mokume_dir() else {
        return;
    };
    let load = |cube: &str, face: &str| {
        load_rgb(&dir.join(cube).join(format!("{face}_col.png")))
            .unwrap()
            .white_balanced()
    };
    let device = Device::flex();
    let loss = StyleLoss::new(&LossConfig::default_config(), &device);
    let faces = ["A", "B", "C", "D", "E", "F"];
    for (cube, other) in [("CN03", "H11"), ("H11", "CN03")] {
        let reference = load(cube, "A");
        let score = |targets: &xylem::loss::StyleTargets, img: &Image2| {
            value(
                loss.loss(&[image_to_tensor(img, &device)], targets, &[0])
                    .unwrap(),
            )
        };
        // a crop: the top-left quarter of face A as the target, the bottom-right quarter
        // against the centres of the other cube's faces
        let targets = loss
            .targets(&[reference.crop(0, 0, 128, 128).unwrap()])
            .unwrap();
        let same_photo = score(&targets, &reference.crop(128, 128, 128, 128).unwrap());
        let closest_other = faces
            .iter()
            .map(|f| score(&targets, &load(other, f).crop(64, 64, 128, 128).unwrap()))
            .fold(f32::INFINITY, f32::min);
        assert!(
            same_photo < closest_other,
            "{cube} A: other crop {same_photo}, closest {other} face {closest_other}"
        );
        // whole faces at 128 px (as the NCA trains): the face closest to A is of its own cube
        let targets = loss.targets(&[reference.resized(128, 128)]).unwrap();
        let scores: Vec<(String, f32)> = [(cube, &faces[1..]), (other, &faces[..])]
            .iter()
            .flat_map(|(c, fs)| fs.iter().map(move |f| (c.to_string(), f.to_string())))
            .map(|(c, f)| {
                let s = score(&targets, &load(&c, &f).resized(128, 128));
                (format!("{c}{f}"), s)
            })
            .collect();
        let best = scores.iter().min_by(|a, b| a.1.total_cmp(&b.1)).unwrap();
        eprintln!(
            "{cube} A: other crop {same_photo}, closest {other} crop {closest_other}; whole faces {scores:?}"
        );
        assert!(
            best.0.starts_with(cube),
            "{cube} A: closest whole face {best:?} of {scores:?}"
        );
    }
}

/// The chroma-edge filters (`filters.chroma`) make pink-green speckle on a smooth face cost
/// what the random RGB filters let through: grey speckle of the same size is seen either way.
#[test]
fn chroma_filters_see_chroma_speckle() {
    let device = Device::flex();
    let target = banded(48, 48, 0.0);
    let speckled = |opponent: [f32; 3]| {
        let mut img = target.clone();
        for (n, px) in img.data.chunks_mut(3).enumerate() {
            let s = if (n * 7919 + n / 48 * 104729) % 3 == 0 {
                0.06
            } else {
                -0.03
            };
            for (c, o) in px.iter_mut().zip(opponent) {
                *c = (*c + s * o).clamp(0.0, 1.0);
            }
        }
        img
    };
    let pink_green = speckled([1.0, -1.0, 0.0]);
    let loss_at = |chroma: f32, img: &Image2| {
        let mut cfg = swd_and_colour(1.0, 0.0);
        cfg.swd.projections = 32;
        cfg.filters.chroma = chroma;
        loss_against(&cfg, &target, img, &device)
    };
    let without = loss_at(0.0, &pink_green);
    let with = loss_at(4.0, &pink_green);
    assert!(
        with > 3.0 * without,
        "chroma speckle: loss {with} with chroma filters vs {without} without"
    );
    assert!(loss_at(4.0, &target) < 1e-6, "the target against itself");
}

/// `joint_colour` axes see how lightness and chroma go together: dark pixels that are
/// yellower (the photo's brown pores) against dark pixels that are bluer, with the same
/// lightness and nearly the same chroma marginals.
#[test]
fn joint_colour_axes_see_the_coupling_of_lightness_and_chroma() {
    let device = Device::flex();
    let coupled = |sign: f32| {
        let mut img = Image2::filled(32, 32, 3, 0.0);
        for (n, px) in img.data.chunks_mut(3).enumerate() {
            let l = 0.5 + 0.25 * ((n as f32) * 0.37).sin();
            // Move along the yellow-blue axis (1, 1, -2)/sqrt(6) against lightness.
            let yb = sign * 0.3 * (l - 0.5);
            let [r, g, b] = [yb, yb, -2.0 * yb].map(|d| d / 6f32.sqrt());
            px.copy_from_slice(&[l + r, l + g, l + b]);
        }
        img
    };
    let (brown, blue) = (coupled(-1.0), coupled(1.0));
    let loss_at = |joint: bool, img: &Image2| {
        let mut cfg = swd_and_colour(0.0, 1.0);
        cfg.joint_colour = joint;
        loss_against(&cfg, &brown, img, &device)
    };
    let (six, ten) = (loss_at(false, &blue), loss_at(true, &blue));
    // R, G and B already see part of it (their marginals change with the coupling); the
    // mixed axes add the rest.
    assert!(
        ten > 1.15 * six,
        "blue pores on a brown target: {ten} with the joint axes vs {six} without"
    );
    assert!(loss_at(true, &brown) < 1e-6);
}
