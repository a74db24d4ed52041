//! The procedural wood model: presets, determinism, and measured anatomy (pores in
//! earlywood, ray shapes on radial and tangential cuts, dark knots, burl is not stripes),
//! plus synthetic sample folders that load like real ones.

mod common;

use glam::Vec3;
use xylem::config::ConfigFile;
use xylem::field::{FieldConfig, GrowthField, ring_intensity};
use xylem::frame::{Face, Plane};
use xylem::image2::Image2;
use xylem::io::OutputDir;
use xylem::presets::{SPECIES_PRESETS, load_species_preset};
use xylem::procedural::synthetic::knot_crossings;
use xylem::procedural::{ProceduralWood, SpeciesConfig, WithFibreDirection, write_sample};
use xylem::sample::{Needs, Sample, marker_value};
use xylem::slice::{slice_face, slice_plane};
use xylem::texture::SolidTexture;

fn preset(name: &str) -> SpeciesConfig {
    load_species_preset(name).unwrap_or_else(|e| panic!("preset {name}: {e}"))
}

/// Luminance minus its mean over a (2r+1)^2 window: negative where a pixel is darker than
/// its surroundings (pores, rays, fine dark features).
fn local_contrast(lum: &Image2, r: usize) -> Vec<f32> {
    let (w, h) = (lum.width, lum.height);
    let mut out = vec![0.0; w * h];
    for y in 0..h {
        for x in 0..w {
            let (y0, y1) = (y.saturating_sub(r), (y + r).min(h - 1));
            let (x0, x1) = (x.saturating_sub(r), (x + r).min(w - 1));
            let mut sum = 0.0;
            for yy in y0..=y1 {
                for xx in x0..=x1 {
                    sum += lum.get(yy, xx, 0);
                }
            }
            let count = ((y1 - y0 + 1) * (x1 - x0 + 1)) as f32;
            out[y * w + x] = lum.get(y, x, 0) - sum / count;
        }
    }
    out
}

/// The points of an n x n image of `plane`, row-major.
fn plane_points(plane: &Plane, n: usize) -> Vec<Vec3> {
    (0..n * n)
        .map(|i| plane.pixel_point(i / n, i % n, n, n))
        .collect()
}

#[test]
fn presets_all_load_render_and_round_trip() {
    assert!(SPECIES_PRESETS.len() >= 6);
    for (name, _) in SPECIES_PRESETS {
        let cfg = preset(name);
        let text = xylem::config::to_toml(&cfg).unwrap();
        let again = SpeciesConfig::parse(&text, std::path::Path::new("copy.toml")).unwrap();
        assert_eq!(
            again, cfg,
            "{name}: the resolved config does not round-trip"
        );
        let model = ProceduralWood::new(&cfg);
        let img = slice_face(&model, Face::A, 24);
        assert!(
            img.data
                .iter()
                .all(|v| v.is_finite() && (0.0..=1.0).contains(v)),
            "{name}: colours outside [0, 1]"
        );
        let lum = img.luminance();
        let mean = lum.data.iter().sum::<f32>() / lum.data.len() as f32;
        let spread = lum.data.iter().map(|v| (v - mean).abs()).sum::<f32>() / lum.data.len() as f32;
        assert!(spread > 0.005, "{name}: face A is flat (spread {spread})");
        assert!(
            (0.15..0.95).contains(&mean),
            "{name}: mean luminance {mean}"
        );
    }
}

#[test]
fn same_seed_same_pixels_other_seed_other_pores_same_rings() {
    let cfg = preset("chestnut");
    let a = slice_face(&ProceduralWood::new(&cfg), Face::B, 48);
    let b = slice_face(&ProceduralWood::new(&cfg), Face::B, 48);
    assert_eq!(a, b, "same config, different pixels");
    let mut other = cfg.clone();
    other.seed += 1;
    let (m1, m2) = (ProceduralWood::new(&cfg), ProceduralWood::new(&other));
    let points = plane_points(&Plane::face(Face::B), 96);
    let (mut pores_differ, mut pore_pixels) = (0, 0);
    for p in &points {
        let (s1, s2) = (m1.sample(*p), m2.sample(*p));
        assert_eq!(s1.time, s2.time, "the seed must not move the rings");
        if s1.pore > 0.1 || s2.pore > 0.1 {
            pore_pixels += 1;
            if (s1.pore - s2.pore).abs() > 0.1 {
                pores_differ += 1;
            }
        }
    }
    println!("pore pixels {pore_pixels}, differing {pores_differ}");
    assert!(pore_pixels > 100);
    assert!(
        pores_differ as f32 > 0.8 * pore_pixels as f32,
        "another seed should place other pores: {pores_differ} of {pore_pixels} differ"
    );
}

/// Density of dark specks (pixels clearly darker than their neighbourhood) in earlywood
/// (ring phase below `ew_end`) over that in latewood (phase 0.5..0.97), on end grain.
fn speck_density_ratio(name: &str, ew_end: f32) -> f32 {
    let cfg = preset(name);
    let model = ProceduralWood::new(&cfg);
    let n = 256;
    let plane = Plane::face(Face::B);
    let lum = slice_plane(&model, &plane, n, n).luminance();
    let contrast = local_contrast(&lum, 3);
    let (mut ew, mut ew_specks, mut lw, mut lw_specks) = (0, 0, 0, 0);
    for (i, p) in plane_points(&plane, n).iter().enumerate() {
        let s = model.sample(*p);
        let speck = contrast[i] < -0.08;
        if s.knot > 0.0 {
            continue;
        }
        if s.phase < ew_end {
            ew += 1;
            ew_specks += speck as usize;
        } else if (0.5..0.97).contains(&s.phase) {
            lw += 1;
            lw_specks += speck as usize;
        }
    }
    let ratio = (ew_specks as f32 / ew as f32) / (lw_specks.max(1) as f32 / lw as f32);
    println!(
        "{name}: earlywood specks {ew_specks}/{ew}, latewood {lw_specks}/{lw}, density ratio {ratio:.2}"
    );
    ratio
}

#[test]
fn ring_porous_pores_sit_in_the_earlywood_and_diffuse_porous_do_not() {
    for name in ["oak", "chestnut"] {
        let ratio = speck_density_ratio(name, 0.25);
        assert!(
            ratio > 4.0,
            "{name}: pores not concentrated in earlywood ({ratio})"
        );
    }
    let maple = speck_density_ratio("maple", 0.25);
    assert!(
        (0.4..2.5).contains(&maple),
        "maple is diffuse-porous; earlywood/latewood speck density ratio {maple}"
    );
}

/// Extent across the grain over extent along it of the visible rays on a plane through the
/// cube centre spanned by `across` and the pith direction. The rays are the pixels that
/// change when the ray layers are removed. Scanning that mask across the grain, each row
/// through a feature has two edges, so the edge count across is proportional to the
/// features' extent along the grain and vice versa: the ratio of the two edge counts is the
/// mean across/along extent ratio (a x b rectangles give a / b).
fn ray_elongation(cfg: &SpeciesConfig, across: Vec3) -> (f32, f32) {
    let model = ProceduralWood::new(cfg);
    let mut plain_cfg = cfg.clone();
    plain_cfg.rays.clear();
    let plain = ProceduralWood::new(&plain_cfg);
    let along = model.field.pith.dir;
    let size = 0.9;
    let plane = Plane::new(-0.5 * size * (across + along), size * across, size * along);
    let n = 192;
    let mask: Vec<f32> = plane_points(&plane, n)
        .iter()
        .map(|p| {
            let d = model.colour(*p) - plain.colour(*p);
            (d.abs().max_element() > 0.02) as u8 as f32
        })
        .collect();
    let (mut e_across, mut e_along) = (0.0f32, 0.0f32);
    for r in 0..n - 1 {
        for c in 0..n - 1 {
            let m = mask[r * n + c];
            e_across += (mask[r * n + c + 1] - m).powi(2);
            e_along += (mask[(r + 1) * n + c] - m).powi(2);
        }
    }
    let coverage = mask.iter().sum::<f32>() / mask.len() as f32;
    (e_along / e_across.max(1.0), coverage)
}

#[test]
fn rays_are_lines_on_radial_cuts_and_spots_on_tangential_cuts() {
    let cfg = preset("oak");
    let model = ProceduralWood::new(&cfg);
    let (radial, tangential) =
        xylem::procedural::tree::radial_frame(&model.field.pith, Vec3::ZERO).unwrap();
    let (on_radial, cover_r) = ray_elongation(&cfg, radial);
    let (on_tangential, cover_t) = ray_elongation(&cfg, tangential);
    println!(
        "across/along extent ratio: radial cut {on_radial:.2} (coverage {cover_r:.3}), \
         tangential cut {on_tangential:.2} (coverage {cover_t:.3})"
    );
    assert!(cover_r > 0.005 && cover_t > 0.005, "rays barely visible");
    assert!(
        on_radial > 2.0,
        "rays should be long across the grain on a radial cut"
    );
    assert!(
        on_tangential < 0.5,
        "rays should be narrow spindles on a tangential cut"
    );
}

#[test]
fn knots_darken_the_wood_inside_them() {
    let cfg = preset("softwood");
    let model = ProceduralWood::new(&cfg);
    let field = GrowthField::from_config(&cfg.field_config());
    for face in [Face::C, Face::F] {
        let n = 128;
        let plane = Plane::face(face);
        let lum = slice_plane(&model, &plane, n, n).luminance();
        let (mut inside, mut ni, mut outside, mut no) = (0.0, 0, 0.0, 0);
        for (i, p) in plane_points(&plane, n).iter().enumerate() {
            let s = field.sample(*p);
            if s.stem - s.knot_time > 1.0 {
                inside += lum.data[i];
                ni += 1;
            } else if s.knot_time - s.stem > 2.0 {
                outside += lum.data[i];
                no += 1;
            }
        }
        let (inside, outside) = (inside / ni as f32, outside / no as f32);
        println!("face {face}: knot {ni} px luminance {inside:.3}, wood {no} px {outside:.3}");
        assert!(ni > 100, "face {face} should show the knot");
        assert!(
            inside < outside - 0.1,
            "the knot is not darker on face {face}"
        );
    }
}

#[test]
fn dead_knots_get_a_dark_outline() {
    let mut cfg = preset("softwood");
    cfg.knots[0].death = Some(14.0);
    let outline = cfg.knot_colour.outline_years;
    let model = ProceduralWood::new(&cfg);
    let n = 160;
    let plane = Plane::face(Face::C);
    let lum = slice_plane(&model, &plane, n, n).luminance();
    let (mut band, mut nb, mut core, mut nc) = (0.0, 0, 0.0, 0);
    for (i, p) in plane_points(&plane, n).iter().enumerate() {
        let f = model.sample(*p).field;
        let inside = f.stem - f.knot_time;
        if f.in_dead_knot && inside > 0.4 * outline && inside < 0.6 * outline {
            band += lum.data[i];
            nb += 1;
        } else if f.in_dead_knot && inside > 3.0 * outline {
            core += lum.data[i];
            nc += 1;
        }
    }
    let (band, core) = (band / nb as f32, core / nc as f32);
    println!("dead knot on C: outline band {nb} px luminance {band:.3}, inside {nc} px {core:.3}");
    assert!(nb > 20 && nc > 100, "the dead knot should cross face C");
    assert!(band < core - 0.1, "no dark outline around the dead knot");
}

/// Mean local orientation coherence of an image's grain, in [0, 1]: the luminance is blurred
/// (box 5 x 5, twice) so pores and fibres do not count, then in each 32 x 32 block the
/// structure tensor of the gradients gives |sum (gx^2 - gy^2, 2 gx gy)| / sum (gx^2 + gy^2):
/// 1 when the block's edges all run one way (rings, stripes), near 0 when they turn every
/// way. Blocks are weighted by their gradient energy.
fn coherence(img: &Image2) -> f32 {
    let blurred = box_blur(&box_blur(&img.luminance(), 2), 2);
    let (w, h) = (blurred.width, blurred.height);
    let (mut weighted, mut energy) = (0.0f64, 0.0f64);
    for by in (0..h - 32).step_by(32) {
        for bx in (0..w - 32).step_by(32) {
            let (mut a, mut b, mut c) = (0.0f64, 0.0f64, 0.0f64);
            for y in by + 1..by + 31 {
                for x in bx + 1..bx + 31 {
                    let gx = (blurred.get(y, x + 1, 0) - blurred.get(y, x - 1, 0)) as f64;
                    let gy = (blurred.get(y + 1, x, 0) - blurred.get(y - 1, x, 0)) as f64;
                    a += gx * gx;
                    b += gy * gy;
                    c += gx * gy;
                }
            }
            if a + b > 0.0 {
                weighted += ((a - b).powi(2) + 4.0 * c * c).sqrt();
                energy += a + b;
            }
        }
    }
    (weighted / energy) as f32
}

fn box_blur(img: &Image2, r: usize) -> Image2 {
    let mean = local_contrast(img, r);
    let data = img.data.iter().zip(&mean).map(|(v, m)| v - m).collect();
    Image2::from_data(img.width, img.height, 1, data).unwrap()
}

fn side_coherence(cfg: &SpeciesConfig) -> f32 {
    let model = ProceduralWood::new(cfg);
    [Face::A, Face::C, Face::F]
        .iter()
        .map(|f| coherence(&slice_face(&model, *f, 160)))
        .sum::<f32>()
        / 3.0
}

#[test]
fn burl_is_not_stripes() {
    let oak = side_coherence(&preset("oak"));
    let chestnut = side_coherence(&preset("chestnut"));
    let burl_cfg = preset("burl");
    let burl = side_coherence(&burl_cfg);
    let mut unburled = burl_cfg.clone();
    unburled.burl = None;
    let stem = side_coherence(&unburled);
    println!(
        "mean side-face grain coherence: oak {oak:.3}, chestnut {chestnut:.3}, burl {burl:.3}, \
         the burl's wood without its buds {stem:.3}"
    );
    assert!(
        oak > 0.5 && chestnut > 0.5,
        "straight grain should be coherent"
    );
    assert!(
        stem > 0.5,
        "without buds the burl preset's wood should be plain stripes"
    );
    assert!(
        burl < 0.6 * oak.min(chestnut).min(stem),
        "burl looks like stripes"
    );
}

#[test]
fn fibre_direction_follows_pith_knots_and_figure() {
    let chestnut = ProceduralWood::new(&preset("chestnut"));
    let pith = chestnut.field.pith.dir;
    let d = chestnut.fibre_direction(Vec3::new(0.1, 0.2, 0.3));
    assert!((d.length() - 1.0).abs() < 1e-4);
    assert!(
        d.dot(pith) > 0.95,
        "straight grain runs along the pith: {d}"
    );

    let softwood_cfg = preset("softwood");
    let softwood = ProceduralWood::new(&softwood_cfg);
    let crossing = knot_crossings(&softwood_cfg.knots)[0];
    let inside = crossing.point * 0.97;
    let knot_dir = softwood.field.knots[0].dir;
    let d = softwood.fibre_direction(inside);
    assert!(
        d.dot(knot_dir).abs() > 0.95,
        "inside the knot fibres follow the branch: {d}"
    );

    let maple = ProceduralWood::new(&preset("maple"));
    let texture = WithFibreDirection(&maple);
    assert_eq!(texture.channels(), 6);
    let largest_turn = plane_points(&Plane::face(Face::A), 24)
        .iter()
        .map(|p| {
            let v = texture.eval_vec(*p);
            Vec3::new(v[3], v[4], v[5])
                .dot(maple.field.pith.dir)
                .clamp(-1.0, 1.0)
                .acos()
        })
        .fold(0.0f32, f32::max);
    println!(
        "maple: largest fibre turn from the pith {:.1} deg",
        largest_turn.to_degrees()
    );
    assert!(
        largest_turn > 3f32.to_radians(),
        "curly figure should turn the fibres"
    );
}

#[test]
fn synthetic_sample_loads_like_a_real_one_with_exact_rings() {
    let cfg = preset("softwood");
    let dir = common::scratch("synthetic-sample");
    let n = 32;
    write_sample(&cfg, "test", n, &OutputDir::prepare(&dir).unwrap()).unwrap();
    let all = Needs {
        photos: true,
        arl: true,
    };
    let sample = Sample::load(&dir, &Face::ALL, all).unwrap();
    assert_eq!(sample.size, n);
    let marked: Vec<Face> = sample.knot_markers.iter().map(|m| m.face).collect();
    let crossed: Vec<Face> = knot_crossings(&cfg.knots).iter().map(|c| c.face).collect();
    assert_eq!(marked, crossed);
    assert_eq!(
        marked,
        vec![Face::C, Face::F],
        "like H11, the knot crosses C and F"
    );
    assert!(
        sample
            .knot_markers
            .iter()
            .all(|m| m.value == marker_value(0))
    );
    for m in &sample.knot_markers {
        let c = knot_crossings(&cfg.knots)
            .into_iter()
            .find(|c| c.face == m.face)
            .unwrap();
        assert!(
            (m.point - c.point).length() < 1.5 / n as f32,
            "marker off its crossing"
        );
    }
    let truth = FieldConfig::load(&dir.join("truth/field.toml")).unwrap();
    assert_eq!(truth, cfg.field_config());
    let species = SpeciesConfig::load(&dir.join("truth/species.toml")).unwrap();
    assert_eq!(species, cfg);
    // The ring images are exactly I(G) of the truth field (to 8-bit rounding).
    let field = GrowthField::from_config(&truth);
    for face in Face::ALL {
        let arl = sample.ring_image(face).unwrap();
        for (row, col) in [(0, 0), (5, 17), (31, 31), (20, 3)] {
            let expected = ring_intensity(field.value(face.pixel_point(row, col, n)));
            assert!((arl.get(row, col, 0) - expected).abs() <= 0.5 / 255.0 + 1e-6);
        }
    }
    for f in ["truth/cut1.png", "truth/cut2.png"] {
        assert!(dir.join(f).is_file(), "{f}");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn species_config_errors_name_file_and_key() {
    let base = SPECIES_PRESETS[0].1;
    let origin = std::path::Path::new("bad.toml");
    let unknown = format!("{base}\n[rings.extra]\nx = 1\n");
    let err = SpeciesConfig::parse(&unknown, origin)
        .unwrap_err()
        .to_string();
    assert!(err.contains("bad.toml") && err.contains("extra"), "{err}");
    let big_pores = base.replace("radius_mm = [0.18, 0.05]", "radius_mm = [0.5, 0.05]");
    assert_ne!(big_pores, base, "the oak preset changed; update this test");
    let err = SpeciesConfig::parse(&big_pores, origin)
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("pores.radius_mm") && err.contains("fit"),
        "{err}"
    );
    let bad_colour = base.replace("colour = [0.33, 0.22, 0.13]", "colour = [1.33, 0.22, 0.13]");
    let err = SpeciesConfig::parse(&bad_colour, origin)
        .unwrap_err()
        .to_string();
    assert!(err.contains("pores.colour"), "{err}");
}
