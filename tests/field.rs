//! Growth field: exactness of the minimal config, monotonicity in r for any rate grid, the
//! smooth minimum, knots (alive, dead, several), config checking and the presets.

use std::path::Path;

use glam::Vec3;
use xylem::config::ConfigFile;
use xylem::field::smin::{power_smin, smoothing};
use xylem::field::{
    FieldConfig, GrowthConfig, GrowthField, KnotConfig, PithConfig, RateGrid, Strand,
    ring_intensity,
};
use xylem::presets::{FIELD_PRESETS, load_field_preset};
use xylem::rng::Rng;

const MINIMAL: &str = r#"
[pith]
origin = [0.0, 0.0, -2.5]     # cube units (1 unit = 4 cm)
direction = [0.0, 1.0, 0.1]   # need not be normalised
[growth]
years_per_unit = 12.0
"#;

fn parse(text: &str) -> xylem::Result<FieldConfig> {
    FieldConfig::parse(text, Path::new("test.toml"))
}

fn random_point(rng: &mut Rng, half: f32) -> Vec3 {
    Vec3::new(
        rng.range(-half, half),
        rng.range(-half, half),
        rng.range(-half, half),
    )
}

/// Distance from p to the line through o along d, computed independently of the library.
fn line_distance(p: Vec3, o: Vec3, d: Vec3) -> f32 {
    (p - o).cross(d.normalize()).length()
}

#[test]
fn minimal_config_is_years_per_unit_times_distance() {
    let field = GrowthField::from_config(&parse(MINIMAL).unwrap());
    let (o, d) = (Vec3::new(0.0, 0.0, -2.5), Vec3::new(0.0, 1.0, 0.1));
    let mut rng = Rng::new(1);
    for _ in 0..2000 {
        let p = random_point(&mut rng, 2.0);
        let expected = 12.0 * line_distance(p, o, d);
        let g = field.value(p);
        assert!(
            (g - expected).abs() <= 1e-5 * expected.max(1.0),
            "G({p}) = {g}, expected {expected}"
        );
    }
}

fn ray_is_increasing(
    field: &GrowthField,
    h: f32,
    phi: f32,
    r_max: f32,
    steps: usize,
) -> Result<(), String> {
    let pith = &field.pith;
    let radial = phi.cos() * pith.e1 + phi.sin() * pith.e2;
    let mut previous = f32::NEG_INFINITY;
    for i in 0..=steps {
        let r = r_max * i as f32 / steps as f32;
        let g = field.value(pith.origin + h * pith.dir + r * radial);
        if g <= previous {
            return Err(format!(
                "G fell from {previous} to {g} at r = {r} (h = {h}, phi = {phi})"
            ));
        }
        previous = g;
    }
    Ok(())
}

#[test]
fn growth_increases_along_every_ray_for_random_rate_grids() {
    let mut rng = Rng::new(7);
    for trial in 0..20 {
        let dims = [1 + rng.below(8), 4 + rng.below(13), 2 + rng.below(15)];
        let len = dims.iter().product();
        // Wild values, negative ones included: the clamp must keep rings from crossing.
        let rates: Vec<f32> = (0..len).map(|_| rng.range(-2.0, 4.0)).collect();
        let mut growth = GrowthConfig::uniform(rng.range(3.0, 30.0));
        growth.grid = dims;
        growth.rates = Some(rates);
        let cfg = FieldConfig {
            pith: PithConfig {
                origin: random_point(&mut rng, 3.0).into(),
                direction: [rng.range(-0.5, 0.5), 1.0, rng.range(-0.5, 0.5)],
                fibre_direction: None,
            },
            growth,
            knots: vec![],
            base_colour: None,
        };
        cfg.validate(&xylem::config::Checker::new(Path::new("random")))
            .unwrap();
        let field = GrowthField::from_config(&cfg);
        for _ in 0..30 {
            let (h, phi) = (rng.range(-3.0, 3.0), rng.range(0.0, std::f32::consts::TAU));
            ray_is_increasing(&field, h, phi, 8.0, 400)
                .unwrap_or_else(|e| panic!("trial {trial}: {e}"));
        }
    }
}

#[test]
fn seeded_distortion_is_monotone_and_actually_distorts() {
    let field = GrowthField::from_config(&load_field_preset("distorted").unwrap());
    let mut rng = Rng::new(3);
    for _ in 0..50 {
        ray_is_increasing(
            &field,
            rng.range(-1.0, 1.0),
            rng.range(0.0, std::f32::consts::TAU),
            4.0,
            300,
        )
        .unwrap();
    }
    // The distortion must change G noticeably against the undistorted field.
    let mut plain = load_field_preset("distorted").unwrap();
    plain.growth.distortion = None;
    let plain = GrowthField::from_config(&plain);
    let max_diff = (0..500)
        .map(|_| {
            let p = random_point(&mut rng, 0.5);
            (field.value(p) - plain.value(p)).abs()
        })
        .fold(0.0f32, f32::max);
    assert!(
        max_diff > 1.0,
        "distortion changed G by at most {max_diff} years"
    );
}

#[test]
fn rate_gradient_matches_finite_differences() {
    let mut rng = Rng::new(11);
    let dims = [3, 6, 5];
    let rates: Vec<f32> = (0..90).map(|_| rng.range(0.3, 2.0)).collect();
    let grid = RateGrid::new(dims, rates.clone(), 0.05, [-0.8, 0.9], [0.4, 1.9]);
    let pith = xylem::field::PithAxis::new(Vec3::new(0.1, 0.0, -1.0), Vec3::new(0.0, 1.0, 0.2));
    let mut grad = Vec::new();
    for _ in 0..20 {
        let c = pith
            .cylindrical(random_point(&mut rng, 0.5) + Vec3::new(0.0, 0.0, rng.range(-1.5, 1.0)));
        grid.integral_gradient(&c, &mut grad);
        let mut dense = vec![0.0f64; rates.len()];
        for &(i, d) in &grad {
            dense[i] += d as f64;
        }
        for (i, &expected) in dense.iter().enumerate() {
            let eps = 1e-2f32;
            let mut plus = rates.clone();
            plus[i] += eps;
            let mut minus = rates.clone();
            minus[i] -= eps;
            let gp = RateGrid::new(dims, plus, 0.05, [-0.8, 0.9], [0.4, 1.9]).integral(&c) as f64;
            let gm = RateGrid::new(dims, minus, 0.05, [-0.8, 0.9], [0.4, 1.9]).integral(&c) as f64;
            let fd = (gp - gm) / (2.0 * eps as f64);
            assert!(
                (fd - expected).abs() < 2e-3,
                "rate {i}: analytic {expected}, finite difference {fd}"
            );
        }
    }
}

#[test]
fn smooth_minimum_is_below_min_and_continuous() {
    let mut rng = Rng::new(5);
    for _ in 0..5000 {
        let (a, b, k) = (
            rng.range(0.0, 50.0),
            rng.range(0.0, 50.0),
            rng.range(0.5, 8.0),
        );
        let s = power_smin(a, b, k);
        assert!(s <= a.min(b) + 1e-6, "smin({a}, {b}, {k}) = {s} > min");
        assert!(s >= 0.0);
        // Lipschitz-continuous: a small change of the inputs moves it by at most that much.
        let eps = 1e-3;
        let moved = power_smin(a + eps, b - eps.min(b), k);
        assert!(
            (moved - s).abs() <= 2.0 * eps + 1e-5,
            "jump at ({a}, {b}, {k}): {s} -> {moved}"
        );
    }
    assert_eq!(power_smin(0.0, 3.0, 2.0), 0.0);
    // Equal inputs: 2^(-1/k) of the value; far apart inputs: close to the minimum.
    assert!((power_smin(4.0, 4.0, 2.0) - 4.0 / 2f32.sqrt()).abs() < 1e-5);
    assert!(smoothing(1.0, 100.0, 4.0).abs() < 1e-6);
}

fn knot_field(death: Option<f32>) -> GrowthField {
    let mut knot = KnotConfig::alive([0.0, -0.5, -1.3], [0.0, 0.0, 1.0]);
    knot.speed = 0.18;
    knot.death = death;
    knot.dead_factor = -0.6;
    GrowthField::from_config(&FieldConfig {
        pith: PithConfig {
            origin: [0.0, 0.0, -1.3],
            direction: [0.0, 1.0, 0.0],
            fibre_direction: None,
        },
        growth: GrowthConfig::uniform(10.0),
        knots: vec![knot],
        base_colour: None,
    })
}

#[test]
fn dead_knot_inverts_the_bulge() {
    let alive = knot_field(None);
    let dead = knot_field(Some(8.0));
    // Above the knot (along the pith) at radius 1.4 (stem time 14 > death at 8), 0.3 from its
    // axis: outside the alive knot (radius 0.18 x 1.4 = 0.25) but within its reach.
    let p = Vec3::new(0.0, -0.5 + 0.3, 0.1);
    let (a, d) = (alive.sample(p), dead.sample(p));
    assert_eq!(a.strand, Strand::Stem);
    assert!(
        a.g < a.stem - 0.05,
        "alive knot must pull rings towards it: G {} vs stem {}",
        a.g,
        a.stem
    );
    assert!(
        d.g > d.stem + 0.05,
        "dead knot must push rings the other way: G {} vs stem {}",
        d.g,
        d.stem
    );
    // Before the death time both agree: the knot was alive then.
    let early = Vec3::new(0.0, -0.5 + 0.1, -0.7);
    assert!((alive.value(early) - dead.value(early)).abs() < 1e-4);
    // A point on the knot axis belongs to the knot; far from it, to the stem.
    assert_eq!(
        alive.sample(Vec3::new(0.0, -0.5, 0.2)).strand,
        Strand::Knot(0)
    );
    assert_eq!(alive.sample(Vec3::new(0.0, 0.4, 0.2)).strand, Strand::Stem);
    // The dead knot stops thickening: a point at 0.2 from the axis, far out, is inside the alive
    // knot (radius 0.18 x 1.8 = 0.32) but outside the dead one (radius frozen at 0.14).
    let side = Vec3::new(0.2, -0.5, 0.5);
    assert_eq!(alive.sample(side).strand, Strand::Knot(0));
    assert_eq!(dead.sample(side).strand, Strand::Stem);
    assert!(dead.sample(Vec3::new(0.0, -0.5, 0.5)).in_dead_knot);
}

#[test]
fn knots_lower_the_field_only_near_them() {
    let alive = knot_field(None);
    // 0.95 from the knot axis at stem radius 0.4: far beyond its reach (6 knot radii = 0.43).
    let far = Vec3::new(0.0, 0.45, -0.9);
    assert_eq!(
        alive.value(far),
        alive.sample(far).stem,
        "a knot must not shift rings far away"
    );
    let mut cfg = load_field_preset("knots").unwrap();
    assert_eq!(cfg.knots.len(), 3);
    for knot in &mut cfg.knots {
        knot.death = None;
    }
    let field = GrowthField::from_config(&cfg);
    let mut rng = Rng::new(9);
    let mut strands = [0usize; 4];
    for _ in 0..4000 {
        let s = field.sample(random_point(&mut rng, 0.5));
        // Alive knots only ever smooth downwards: G <= min of all strand times.
        assert!(
            s.g <= s.stem.min(s.knot_time) + 1e-4,
            "G {} above min({}, {})",
            s.g,
            s.stem,
            s.knot_time
        );
        match s.strand {
            Strand::Stem => strands[0] += 1,
            Strand::Knot(i) => strands[i + 1] += 1,
        }
    }
    assert!(
        strands.iter().all(|&n| n > 0),
        "every strand should dominate somewhere in the cube: {strands:?}"
    );
}

#[test]
fn ring_image_peaks_on_integer_years() {
    assert!((ring_intensity(3.0) - 1.0).abs() < 1e-6);
    assert!(ring_intensity(3.5) < 1e-6);
    assert!((ring_intensity(0.25) - 0.5f32.powi(10)).abs() < 1e-6);
}

#[test]
fn unknown_keys_and_bad_values_are_errors_naming_the_key() {
    let unknown = MINIMAL.replace("years_per_unit", "years_per_unt");
    assert_parse_error(&unknown, &["years_per_unt", "test.toml"]);

    let negative = MINIMAL.replace("12.0", "-3.0");
    assert_parse_error(&negative, &["growth.years_per_unit", "-3"]);

    let zero_dir = MINIMAL.replace("[0.0, 1.0, 0.1]", "[0.0, 0.0, 0.0]");
    assert_parse_error(&zero_dir, &["pith.direction"]);

    let short_rates = format!("{MINIMAL}grid = [2, 4, 2]\nrates = [1.0, 2.0]\n");
    assert_parse_error(&short_rates, &["growth.rates", "16"]);

    let bad_knot = format!(
        "{MINIMAL}[[knots]]\norigin = [0.0, 0.0, -2.5]\ndirection = [0.0, 0.0, 1.0]\nspeed = 3.0\n"
    );
    assert_parse_error(&bad_knot, &["knots[0].speed"]);

    // Issue 16 item 7: arrays longer than their field are errors, not truncated.
    let four = MINIMAL.replace("[0.0, 1.0, 0.1]", "[0.0, 1.0, 0.1, 5.0]");
    assert_parse_error(&four, &["pith.direction: 4 values given, expected 3"]);
    // Issue 16 item 8: a huge direction overflowed its length and became another one.
    let huge = MINIMAL.replace("[0.0, 1.0, 0.1]", "[1e30, 1e30, 0.0]");
    assert_parse_error(&huge, &["pith.direction", "1e6"]);
    let long_grid = format!("{MINIMAL}grid = [2, 4, 2, 8]\nrates = [1.0, 2.0]\n");
    assert_parse_error(&long_grid, &["growth.grid: 4 values given"]);

    let knot = "[[knots]]\norigin = [0.0, 0.0, -2.5]\ndirection = [0.0, 0.0, 1.0]\n";
    let many = format!("{MINIMAL}{}", knot.repeat(65));
    assert_parse_error(&many, &["number of [[knots]]", "65"]);

    let wrong_type = MINIMAL.replace("12.0", "\"twelve\"");
    assert_parse_error(&wrong_type, &["years_per_unit"]);
}

/// Parsing `text` fails with a message that holds every one of `parts`.
fn assert_parse_error(text: &str, parts: &[&str]) {
    let msg = parse(text).unwrap_err().to_string();
    for part in parts {
        assert!(msg.contains(part), "{part:?} missing: {msg}");
    }
}

#[test]
fn presets_load_and_round_trip_through_toml() {
    for (name, _) in FIELD_PRESETS {
        let cfg = load_field_preset(name).unwrap_or_else(|e| panic!("preset {name}: {e}"));
        let text = xylem::config::to_toml(&cfg).unwrap();
        let back = parse(&text).unwrap_or_else(|e| panic!("preset {name} re-read: {e}\n{text}"));
        assert_eq!(cfg, back, "preset {name} changed through TOML");
    }
}
