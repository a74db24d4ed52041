//! The parts issue 12 added to make the NCA paint pores in their rings: the guided local loss
//! (pores at the right ring phase score better than the same pores at the wrong phase), crop
//! placement along the faces, the pore-anisotropy metric (dashes vs dots), the pixel-scale
//! energy term and speckle metric (dashes vs a stipple of them) and the pore density by
//! ring phase.

use burn::tensor::{Device, Tensor};

mod common;
use xylem::Image2;
use xylem::frame::Face;
use xylem::loss::{
    GuidedConfig, GuidedLoss, GuidedPatch, GuidedTerms, LossConfig, ProfileAxes, image_to_tensor,
};
use xylem::metrics::anisotropy::pore_anisotropy;
use xylem::metrics::phase_density::{PhaseDensity, curve_correlation, curve_slope};
use xylem::metrics::speckle::speckle;
use xylem::nca::faces::layout;
use xylem::nca::train::placement::{Placement, draw_fresh, draw_region};
use xylem::rng::{Rng, hash3, unit};

/// Rings every `period` columns (G = column / period); pores (dark pixels) only in the first
/// `early` of each ring, at hashed places; `shift` moves the pores by a fraction of a ring.
fn ring_porous(n: usize, period: f32, early: f32, shift: f32, seed: u64) -> Image2 {
    porous(n, period, early, shift, 0.0, seed)
}

/// [`ring_porous`] with pores also in the latewood, each pixel with probability `latewood`.
fn porous(n: usize, period: f32, early: f32, shift: f32, latewood: f32, seed: u64) -> Image2 {
    let mut img = Image2::filled(n, n, 3, 0.0);
    for r in 0..n {
        for c in 0..n {
            let phase = (c as f32 / period + shift).rem_euclid(1.0);
            let chance = if phase < early { 0.35 } else { latewood };
            let pore = unit(hash3(seed, r as i32, c as i32, 0)) < chance;
            let v = if pore { 0.3 } else { 0.7 };
            img.pixel_mut(r, c).copy_from_slice(&[v, 0.8 * v, 0.6 * v]);
        }
    }
    img
}

/// G = column / period (rings upright, one every `period` pixels).
fn growth_across_columns(n: usize, period: f32) -> Image2 {
    let mut growth = Image2::filled(n, n, 1, 0.0);
    for r in 0..n {
        for c in 0..n {
            growth.pixel_mut(r, c)[0] = c as f32 / period;
        }
    }
    growth
}

/// The phase guide (cos, sin of 2 pi G) of G = column / period.
fn guide(n: usize, period: f32) -> Image2 {
    let mut img = Image2::filled(n, n, 2, 0.0);
    for r in 0..n {
        for c in 0..n {
            let a = std::f32::consts::TAU * c as f32 / period;
            img.pixel_mut(r, c).copy_from_slice(&[a.cos(), a.sin()]);
        }
    }
    img
}

fn small_style() -> LossConfig {
    let mut cfg = LossConfig::default_config();
    cfg.octaves = 2;
    cfg.min_layer_pixels = 16;
    cfg
}

/// Loss of a 24 px patch of `generated` at (20, 20) against the 64 px target.
fn patch_loss(loss: &GuidedLoss, target: &Image2, generated: &Image2) -> f32 {
    let device = Device::flex();
    let t = loss.target(target, &guide(64, 8.0)).unwrap();
    let patch = image_to_tensor(&generated.crop(20, 20, 24, 24).unwrap(), &device);
    let p = GuidedPatch {
        image: patch,
        target: 0,
        origin: [20, 20],
        guide: None,
    };
    // Average over several calls: the random directions are redrawn per call.
    (0..8)
        .map(|call| {
            loss.terms(std::slice::from_ref(&p), std::slice::from_ref(&t), call)
                .unwrap()
                .total
                .into_scalar::<f32>()
        })
        .sum::<f32>()
        / 8.0
}

#[test]
fn guided_loss_prefers_pores_in_the_right_part_of_the_ring() {
    let target = ring_porous(64, 8.0, 0.3, 0.0, 1);
    // Same wood, other pore places: right phase vs pores moved half a ring.
    let right = ring_porous(64, 8.0, 0.3, 0.0, 2);
    let wrong = ring_porous(64, 8.0, 0.3, 0.5, 2);
    let guided = GuidedLoss::new(&small_style(), &GuidedConfig::default(), &Device::flex());
    let (good, bad) = (
        patch_loss(&guided, &target, &right),
        patch_loss(&guided, &target, &wrong),
    );
    assert!(
        bad > 1.5 * good,
        "guided: right phase {good}, wrong phase {bad}"
    );
    // Without the guide the two are nearly alike (same statistics, other places): the guide
    // is what sees the phase.
    let plain_cfg = GuidedConfig {
        guide_weight: 0.0,
        ..GuidedConfig::default()
    };
    let plain = GuidedLoss::new(&small_style(), &plain_cfg, &Device::flex());
    let (p_good, p_bad) = (
        patch_loss(&plain, &target, &right),
        patch_loss(&plain, &target, &wrong),
    );
    assert!(
        (p_bad / p_good) < 0.5 * (bad / good),
        "unguided ratio {} vs guided {}",
        p_bad / p_good,
        bad / good
    );
}

#[test]
fn guided_loss_rejects_patches_outside_their_target() {
    let device = Device::flex();
    let loss = GuidedLoss::new(&small_style(), &GuidedConfig::default(), &device);
    let t = loss
        .target(&ring_porous(32, 8.0, 0.3, 0.0, 1), &guide(32, 8.0))
        .unwrap();
    let p = GuidedPatch {
        image: image_to_tensor(&ring_porous(24, 8.0, 0.3, 0.0, 1), &device),
        target: 0,
        origin: [16, 0],
        guide: None,
    };
    let err = loss.terms(&[p], &[t], 0).unwrap_err().to_string();
    assert!(err.contains("patch 0") && err.contains("(16, 0)"), "{err}");
    let mismatch = loss.target(&ring_porous(32, 8.0, 0.3, 0.0, 1), &guide(16, 8.0));
    assert!(mismatch.is_err());
}

#[test]
fn face_placement_touches_a_trained_face_and_reaches_everywhere() {
    let faces = [Face::A, Face::C];
    let mut rng = Rng::new(3);
    let (grid, crop) = (20, 6);
    let mut starts = std::collections::HashSet::new();
    for _ in 0..400 {
        let r = draw_region(grid, crop, Placement::Faces, &faces, &mut rng);
        assert_eq!(r.dims, [crop; 3]);
        assert!((0..3).all(|a| r.offset[a] + crop <= grid), "{r:?}");
        assert!(
            faces.iter().any(|&f| layout(f).touches(&r)),
            "{r:?} touches no trained face"
        );
        starts.insert(r.offset);
    }
    // Not only the corners: many distinct places along the faces.
    assert!(starts.len() > 100, "{} distinct crops", starts.len());
    let corners: std::collections::HashSet<_> = (0..100)
        .map(|_| draw_region(grid, crop, Placement::Corners, &faces, &mut rng).offset)
        .collect();
    assert!(corners.len() <= 8);
    assert!(
        corners
            .iter()
            .all(|o| o.iter().all(|&v| v == 0 || v == grid - crop))
    );
}

#[test]
fn interior_fraction_draws_crops_inside_the_cube_and_zero_keeps_the_stream() {
    use xylem::config::ConfigFile;
    let faces = [Face::A, Face::C];
    let text = |fraction: f32| {
        format!(
            "seed = 1\n[volume]\nsize = 20\ncrop = 6\ninterior_fraction = {fraction}\n\
             [schedule]\niterations = 3\nsteps = [2, 3]\n[pool]\nsize = 0\n"
        )
    };
    let volume = |fraction: f32| {
        xylem::nca::TrainConfig::parse(&text(fraction), std::path::Path::new("<test>"))
            .unwrap()
            .volume
    };
    // 0: the same regions as `draw_region`, draw for draw (old configs keep their crops).
    let (mut a, mut b) = (Rng::new(7), Rng::new(7));
    for _ in 0..50 {
        let fresh = draw_fresh(&volume(0.0), &faces, &mut a);
        assert_eq!(fresh, draw_region(20, 6, Placement::Faces, &faces, &mut b));
    }
    // 1: every crop anywhere in the grid; most touch no face at all.
    let mut rng = Rng::new(7);
    let all = Face::ALL;
    let regions: Vec<_> = (0..400)
        .map(|_| draw_fresh(&volume(1.0), &faces, &mut rng))
        .collect();
    assert!(
        regions
            .iter()
            .all(|r| (0..3).all(|a| r.offset[a] + 6 <= 20))
    );
    let inside = regions
        .iter()
        .filter(|r| !all.iter().any(|&f| layout(f).touches(r)))
        .count();
    // (13/15)^3 = 0.65 of uniform offsets touch no face.
    assert!(inside > 200 && inside < 320, "{inside} of 400 inside");
    // Bad values are refused, naming the file and the key.
    let refused = |toml: &str, file: &str, key: &str| {
        let err = xylem::nca::TrainConfig::parse(toml, std::path::Path::new(file))
            .unwrap_err()
            .to_string();
        assert!(err.contains(file) && err.contains(key), "{err}");
    };
    refused(&text(1.5), "frac.toml", "volume.interior_fraction");
    // Planes inside the cube compared with the photos need the guided loss.
    let moments = format!(
        "{}[loss]\nface = \"moments\"\ninterior_style = true\n",
        text(0.5)
    );
    refused(&moments, "style.toml", "loss.interior_style");
}

/// Dark marks on a light ground: `len` px long vertical dashes, or single-pixel dots.
fn marks(len: usize, seed: u64) -> Image2 {
    let n = 256;
    let mut img = Image2::filled(n, n, 3, 0.75);
    let mut rng = Rng::new(seed);
    for _ in 0..600 {
        let (r, c) = (rng.below(n - len), rng.below(n));
        for k in 0..len {
            img.pixel_mut(r + k, c).copy_from_slice(&[0.3, 0.25, 0.2]);
        }
    }
    img
}

#[test]
fn anisotropy_tells_dashes_from_dots() {
    let (dashes, dots) = (pore_anisotropy(&marks(9, 1)), pore_anisotropy(&marks(1, 1)));
    assert!(dashes > dots + 0.25, "dashes {dashes}, dots {dots}");
    assert!((0.0..=1.0).contains(&dashes) && (0.0..=1.0).contains(&dots));
    assert_eq!(pore_anisotropy(&Image2::filled(64, 64, 3, 0.5)), 0.0);
}

/// `img` with every other pixel of its dark marks lit again, in a checkerboard: the stipple
/// the NCA drew instead of dashes.
fn stippled(img: &Image2) -> Image2 {
    let mut out = img.clone();
    for r in 0..img.height {
        for c in 0..img.width {
            if (r + c) % 2 == 1 && img.get(r, c, 0) < 0.5 {
                out.pixel_mut(r, c).copy_from_slice(&[0.75; 3]);
            }
        }
    }
    out
}

#[test]
fn speckle_tells_dashes_from_a_stipple_of_them() {
    let dashes = marks(9, 1);
    let (smooth, stipple) = (speckle(&dashes), speckle(&stippled(&dashes)));
    assert!(stipple > smooth + 0.5, "dashes {smooth}, stipple {stipple}");
}

/// The guided loss's terms, as scalars (term of interest, total), of a 24 px patch of
/// `generated` at (20, 20) against the 64 px `photo` with rings every 8 columns; `pick` names
/// the term.
fn patch_terms(
    cfg: &GuidedConfig,
    photo: &Image2,
    generated: &Image2,
    pick: fn(&GuidedTerms) -> Tensor<1>,
) -> (f32, f32) {
    let device = Device::flex();
    let loss = GuidedLoss::new(&small_style(), cfg, &device);
    let target = loss.target(photo, &guide(64, 8.0)).unwrap();
    let p = GuidedPatch {
        image: image_to_tensor(&generated.crop(20, 20, 24, 24).unwrap(), &device),
        target: 0,
        origin: [20, 20],
        guide: None,
    };
    let terms = loss.terms(&[p], &[target], 0).unwrap();
    (
        pick(&terms).into_scalar::<f32>(),
        terms.total.into_scalar::<f32>(),
    )
}

#[test]
fn the_fine_term_tells_dashes_from_a_stipple_of_them() {
    let weighted = |fine_weight: f32| GuidedConfig {
        fine_weight,
        ..GuidedConfig::default()
    };
    let photo = marks(9, 1).crop(0, 0, 64, 64).unwrap();
    let fine = |cfg: &GuidedConfig, generated: &Image2| {
        patch_terms(cfg, &photo, generated, |t| t.fine.clone())
    };
    let other = marks(9, 2).crop(0, 0, 64, 64).unwrap();
    let on = weighted(1.0);
    let ((dashes, _), (stipple, _)) = (fine(&on, &other), fine(&on, &stippled(&other)));
    assert!(
        stipple > 4.0 * dashes.max(0.05),
        "fine term: dashes {dashes}, stipple {stipple}"
    );
    // Off by default: nothing added to the total.
    let (zero, total_off) = fine(&weighted(0.0), &stippled(&other));
    let (_, total_on) = fine(&on, &stippled(&other));
    assert_eq!(zero, 0.0);
    assert!((total_on - total_off - stipple).abs() < 1e-3 * total_on.max(1.0));
}

/// `photo` with its pixels shuffled over the whole image: the same colours, and no ring
/// profile left (G = column / period, so the shuffle mixes every ring phase).
fn without_ring_profile(photo: &Image2, seed: u64) -> Image2 {
    let mut out = photo.clone();
    let mut rng = Rng::new(seed);
    let w = photo.width;
    for i in (1..w * photo.height).rev() {
        let j = rng.below(i + 1);
        let (a, b) = (
            out.pixel(i / w, i % w).to_vec(),
            out.pixel(j / w, j % w).to_vec(),
        );
        out.pixel_mut(i / w, i % w).copy_from_slice(&b);
        out.pixel_mut(j / w, j % w).copy_from_slice(&a);
    }
    out
}

#[test]
fn the_profile_term_sees_a_ring_profile_lost_and_adds_nothing_when_off() {
    let weighted = |profile_weight: f32| GuidedConfig {
        profile_weight,
        ..GuidedConfig::default()
    };
    // Pores in the first 30 % of each ring: the earlywood is darker on average.
    let photo = ring_porous(64, 8.0, 0.3, 0.0, 1);
    let profile = |cfg: &GuidedConfig, generated: &Image2| {
        patch_terms(cfg, &photo, generated, |t| t.profile.clone())
    };
    let same_wood = ring_porous(64, 8.0, 0.3, 0.0, 2);
    let flat = without_ring_profile(&same_wood, 3);
    let on = weighted(1.0);
    let ((kept, _), (lost, _)) = (profile(&on, &same_wood), profile(&on, &flat));
    assert!(
        lost > 4.0 * kept.max(0.01),
        "profile term: ring profile kept {kept}, lost {lost}"
    );
    let (zero, total_off) = profile(&weighted(0.0), &flat);
    let (_, total_on) = profile(&on, &flat);
    assert_eq!(zero, 0.0);
    assert!((total_on - total_off - lost).abs() < 1e-3 * total_on.max(1.0));
}

/// `img` with a uniform cast along a direction of no luminance (Rec. 709 weights): the
/// lightness of every pixel is kept, its chroma moved.
fn chroma_cast(img: &Image2, amount: f32) -> Image2 {
    let cast = [0.7152f32, -0.2126, 0.0];
    let norm = cast.iter().map(|v| v * v).sum::<f32>().sqrt();
    let mut out = img.clone();
    for r in 0..img.height {
        for c in 0..img.width {
            for (v, d) in out.pixel_mut(r, c).iter_mut().zip(cast) {
                *v += amount * d / norm;
            }
        }
    }
    out
}

#[test]
fn the_lightness_profile_sees_the_rings_and_not_a_chroma_cast() {
    let cfg = |profile_axes| GuidedConfig {
        profile_weight: 1.0,
        profile_axes,
        ..GuidedConfig::default()
    };
    let photo = ring_porous(64, 8.0, 0.3, 0.0, 1);
    let profile = |axes, generated: &Image2| {
        patch_terms(&cfg(axes), &photo, generated, |t| t.profile.clone()).0
    };
    let same_wood = ring_porous(64, 8.0, 0.3, 0.0, 2);
    let (flat, cast) = (
        without_ring_profile(&same_wood, 3),
        chroma_cast(&same_wood, 0.03),
    );
    let kept = profile(ProfileAxes::Lightness, &same_wood);
    let lost = profile(ProfileAxes::Lightness, &flat);
    assert!(
        lost > 4.0 * kept.max(0.01),
        "lightness: kept {kept}, lost {lost}"
    );
    let cast_lightness = profile(ProfileAxes::Lightness, &cast);
    assert!(
        (cast_lightness - kept).abs() < 1e-3 * kept.max(1e-3),
        "cast seen on lightness: {cast_lightness} against {kept}"
    );
    let (kept_all, cast_all) = (
        profile(ProfileAxes::All, &same_wood),
        profile(ProfileAxes::All, &cast),
    );
    assert!(
        cast_all > 4.0 * kept_all.max(0.01),
        "all axes: kept {kept_all}, cast {cast_all}"
    );
}

/// A tiny training config ending with `loss` (its `[loss]` tables).
fn tiny_train_config(loss: &str) -> String {
    format!(
        "seed = 1\n[volume]\nsize = 20\ncrop = 6\n[schedule]\niterations = 3\n\
         steps = [2, 3]\n[pool]\nsize = 0\n{loss}"
    )
}

/// `text` parsed as the training config file `name`, or the error's message.
fn parse_train(text: &str, name: &str) -> Result<xylem::nca::TrainConfig, String> {
    use xylem::config::ConfigFile;
    xylem::nca::TrainConfig::parse(text, std::path::Path::new(name)).map_err(|e| e.to_string())
}

#[test]
fn the_profile_axes_are_refused_while_the_profile_term_is_off() {
    let config = |guided: &str| {
        tiny_train_config(&format!(
            "[loss]\nface = \"guided\"\n[loss.guided]\n{guided}"
        ))
    };
    let parse = |text: &str| parse_train(text, "axes.toml").map(|c| c.loss.guided.profile_axes);
    let on = config("profile_weight = 1.0\nprofile_axes = \"lightness\"\n");
    assert_eq!(parse(&on), Ok(ProfileAxes::Lightness));
    let off = parse(&config("profile_axes = \"lightness\"\n")).unwrap_err();
    assert!(
        off.contains("axes.toml") && off.contains("loss.guided.profile_axes"),
        "{off}"
    );
    let unknown = parse(&config("profile_weight = 1.0\nprofile_axes = \"hue\"\n")).unwrap_err();
    assert!(
        unknown.contains("axes.toml") && unknown.contains("profile_axes"),
        "{unknown}"
    );
}

#[test]
fn loss_term_weights_are_refused_out_of_range_or_without_the_guided_loss() {
    let config = tiny_train_config;
    let parse = |text: &str| {
        parse_train(text, "weights.toml")
            .map(|c| (c.loss.guided.fine_weight, c.loss.guided.profile_weight))
    };
    for key in ["fine_weight", "profile_weight"] {
        let guided =
            |weight: &str| format!("[loss]\nface = \"guided\"\n[loss.guided]\n{key} = {weight}\n");
        let expected = if key == "fine_weight" {
            (0.05, 0.0)
        } else {
            (0.0, 0.05)
        };
        assert_eq!(parse(&config(&guided("0.05"))), Ok(expected));
        let moments = format!("[loss]\nface = \"moments\"\n[loss.guided]\n{key} = 0.05\n");
        for bad in [guided("-1.0"), moments] {
            let err = parse(&config(&bad)).unwrap_err();
            assert!(
                err.contains("weights.toml") && err.contains(&format!("loss.guided.{key}")),
                "{err}"
            );
        }
    }
}

#[test]
fn phase_density_finds_the_pores_ring_phase() {
    let n = 256;
    let period = 16.0;
    let growth = growth_across_columns(n, period);
    let curve = |shift: f32| {
        let mut d = PhaseDensity::new(8);
        d.add(&ring_porous(n, period, 0.25, shift, 4), &growth)
            .unwrap();
        d.curve()
    };
    let early = curve(0.0);
    // Pores in the first quarter of the ring: bins 0 and 1 of 8.
    assert!(early[0] > 0.1 && early[1] > 0.1, "{early:?}");
    assert!(early[3..].iter().all(|&v| v < 0.02), "{early:?}");
    assert!(curve_correlation(&early, &curve(0.0)) > 0.99);
    assert!(curve_correlation(&early, &curve(0.5)) < 0.0);
    assert_eq!(curve_correlation(&early, &[0.2; 8]), 0.0);
}

#[test]
fn phase_slope_tells_faint_pore_bands_from_strong_ones() {
    let n = 256;
    let period = 16.0;
    let growth = growth_across_columns(n, period);
    let curve = |latewood: f32, seed: u64| {
        let mut d = PhaseDensity::new(8);
        d.add(&porous(n, period, 0.25, 0.0, latewood, seed), &growth)
            .unwrap();
        d.curve()
    };
    let reference = curve(0.0, 4);
    // Another texture with the same bands: slope near 1.
    let same = curve_slope(&curve(0.0, 5), &reference);
    assert!((same - 1.0).abs() < 0.1, "{same}");
    // Pores also in the latewood: the same shape (correlation near 1), fainter bands.
    let faint = curve(0.15, 5);
    assert!(curve_correlation(&faint, &reference) > 0.95);
    let slope = curve_slope(&faint, &reference);
    assert!(slope > 0.3 && slope < 0.8, "{slope}");
    assert_eq!(curve_slope(&[0.1; 8], &reference), 0.0);
    assert_eq!(curve_slope(&reference, &[0.1; 8]), 0.0);
}

/// The six photos of a sample folder.
fn photos(dir: &std::path::Path) -> Vec<Image2> {
    let needs = xylem::sample::Needs {
        photos: true,
        arl: false,
    };
    let sample = xylem::sample::Sample::load(dir, &Face::ALL, needs).unwrap();
    sample.photos.into_iter().flatten().collect()
}

/// Whether the vessel gate closes on the quality model for these photos (grain noise left out
/// or turned into fibre lines, as the config says),
/// with the guide weights set apart (4 with vessels, 1.5 without): the weight it leaves.
fn gate_closes(photos: &[Image2]) -> (bool, f32) {
    use xylem::nca::train::vessel_gate::apply_vessel_gate;
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("configs/nca/quality.toml");
    let mut config = <xylem::nca::TrainConfig as xylem::config::ConfigFile>::load(&path).unwrap();
    config.loss.guided.guide_weight = 4.0;
    config.loss.guided.guide_weight_without_vessels = Some(1.5);
    let refs: Vec<&Image2> = photos.iter().collect();
    let shipped = config.model.grain_noise.clone();
    let closed = apply_vessel_gate(&mut config, &refs);
    let kept = config
        .model
        .conditioning
        .contains(&xylem::nca::CondChannel::GrainNoise);
    let spec = &config.model.grain_noise;
    match closed {
        // The gate reports what it did: the fibre cells or no channel.
        Some(closed) => {
            assert_eq!(closed.guide_weight, Some(1.5));
            assert_eq!(kept, closed.fibre_lines);
            assert_eq!(closed.fibre_lines, shipped.without_vessels.is_some());
            if let Some(fibres) = shipped.without_vessels {
                assert_eq!(
                    (spec.across_mm, spec.along_mm),
                    (fibres.across_mm, fibres.along_mm)
                );
            }
        }
        None => assert!(kept && *spec == shipped),
    }
    (closed.is_some(), config.loss.guided.guide_weight)
}

#[test]
fn the_vessel_gate_closes_on_wood_without_vessels() {
    // Synthetic photographed samples at the photos' 256 px: the ring-porous presets keep the
    // vessel noise, the gate closes on the softwood (no pores).
    for (preset, closes_on) in [("chestnut", false), ("oak", false), ("softwood", true)] {
        let dir = common::scratch(&format!("pore-gate-{preset}"));
        let species = xylem::presets::load_species_preset(preset).unwrap();
        let out = xylem::io::OutputDir::prepare(&dir).unwrap();
        xylem::procedural::synthetic::write_sample(&species, "test", 256, &out).unwrap();
        let photos = photos(&dir);
        let fractions: Vec<f32> = photos
            .iter()
            .map(xylem::metrics::vessels::vessel_fraction)
            .collect();
        eprintln!("{preset}: pore fraction per face {fractions:?}");
        let (closes, guide_weight) = gate_closes(&photos);
        assert_eq!(closes, closes_on, "{preset}");
        assert_eq!(guide_weight, if closes_on { 1.5 } else { 4.0 }, "{preset}");
    }
    // The real cubes: chestnut keeps the vessel noise, the gate closes on hinoki.
    let Some(mokume) = common::mokume_dir() else {
        return;
    };
    for (cube, closes_on) in [("CN03", false), ("H11", true)] {
        let photos = photos(&mokume.join(cube));
        let fractions: Vec<f32> = photos
            .iter()
            .map(xylem::metrics::vessels::vessel_fraction)
            .collect();
        eprintln!("{cube}: pore fraction per face {fractions:?}");
        let (closes, guide_weight) = gate_closes(&photos);
        assert_eq!(closes, closes_on, "{cube}");
        assert_eq!(guide_weight, if closes_on { 1.5 } else { 4.0 }, "{cube}");
    }
}
