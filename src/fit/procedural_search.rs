//! The appearance parameters the inverse procedural fit searches (`procedural_fit`): pore
//! contrast and occurrence, fibre contrast and pigment noise of a species config, changed by
//! a derivative-free pattern search on a loss the caller gives (the faces' style loss).
//!
//! Why a pattern search: four scalars, a loss that is a rendering followed by a texture
//! statistic (no gradient through the procedural model), and one clear rule that is
//! deterministic: each round walks every parameter up (or, if the first step up does not
//! help, down) for as long as the loss falls, at most `MAX_MOVES` steps; steps halve after
//! every round. A preset's own values are the
//! start, so a preset that already matches stays as it is. On CN03 the chestnut preset's
//! pores are too dark: its pore opacity 0.95 gives style 0.72-0.95 on faces A, C, E, 0.6
//! gives 0.13-0.20.

use crate::config::{Checker, ConfigFile};
use crate::error::Result;
use crate::procedural::SpeciesConfig;

/// Most steps one parameter walks in one direction in one round.
const MAX_MOVES: usize = 4;

/// One searched parameter: how to read it, write it, and its first step.
struct Param {
    name: &'static str,
    get: fn(&SpeciesConfig) -> Option<f32>,
    set: fn(&mut SpeciesConfig, f32),
    /// First step (added; halves every round).
    step: f32,
    bounds: [f32; 2],
}

/// A [`Param`] that is one field of one optional section of the species config, read and
/// written as it is: `plain!(pores.opacity, step 0.2, bounds [0.0, 1.0])`.
macro_rules! plain {
    ($section:ident . $field:ident, step $step:expr, bounds $bounds:expr) => {
        Param {
            name: concat!(stringify!($section), ".", stringify!($field)),
            get: |s| Some(s.$section.as_ref()?.$field),
            set: |s, v| s.$section.iter_mut().for_each(|x| x.$field = v),
            step: $step,
            bounds: $bounds,
        }
    };
}

fn params() -> [Param; 4] {
    [
        plain!(pores.opacity, step 0.2, bounds [0.0, 1.0]),
        Param {
            // Both occurrences (earlywood, latewood) scale together: the ratio is the
            // species' ring-porosity, which the preset choice already says.
            name: "pores.occurrence[0]",
            get: |s| s.pores.as_ref().map(|p| p.occurrence[0]),
            set: |s, v| {
                if let Some(p) = &mut s.pores {
                    let ratio = p.occurrence[1] / p.occurrence[0].max(1e-6);
                    p.occurrence = [v, (v * ratio).clamp(0.0, 1.0)];
                }
            },
            step: 0.2,
            bounds: [0.05, 1.0],
        },
        plain!(fibres.strength, step 0.1, bounds [0.0, 2.0]),
        plain!(pigment.amplitude, step 0.1, bounds [0.0, 2.0]),
    ]
}

/// The searched values of a config, `name = value` (for messages).
pub fn describe(species: &SpeciesConfig) -> String {
    params()
        .iter()
        .filter_map(|p| (p.get)(species).map(|v| format!("{} {v:.2}", p.name)))
        .collect::<Vec<_>>()
        .join(", ")
}

/// The pattern search from `start` for `rounds` rounds (each walks every parameter up, or
/// else down, while the loss falls, then halves the steps); `loss` scores a config (lower is
/// better). Returns the best config and its loss. Configs that fail validation are skipped.
pub fn search(
    start: SpeciesConfig,
    rounds: usize,
    mut loss: impl FnMut(&SpeciesConfig) -> Result<f32>,
) -> Result<(SpeciesConfig, f32)> {
    let params = params();
    let check = Checker::new(std::path::Path::new("procedural.toml"));
    let mut best = start;
    let mut best_loss = loss(&best)?;
    for round in 0..rounds {
        let scale = 0.5f32.powi(round as i32);
        for p in &params {
            for dir in [1.0f32, -1.0] {
                let mut moved = false;
                for _ in 0..MAX_MOVES {
                    let Some(value) = (p.get)(&best) else { break };
                    let v = (value + dir * p.step * scale).clamp(p.bounds[0], p.bounds[1]);
                    if v == value {
                        break;
                    }
                    let mut trial = best.clone();
                    (p.set)(&mut trial, v);
                    if trial.validate(&check).is_err() {
                        break;
                    }
                    let l = loss(&trial)?;
                    if l >= best_loss {
                        break;
                    }
                    (best, best_loss, moved) = (trial, l, true);
                }
                if moved {
                    break;
                }
            }
        }
    }
    Ok((best, best_loss))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::presets::load_species_preset;

    #[test]
    fn the_search_walks_to_the_minimum_of_a_known_loss() {
        let start = load_species_preset("chestnut").unwrap();
        // A loss with its minimum at pore opacity 0.55 and fibre strength 0.3.
        let loss = |s: &SpeciesConfig| {
            let o = s.pores.as_ref().unwrap().opacity;
            let f = s.fibres.as_ref().unwrap().strength;
            Ok((o - 0.55).powi(2) + (f - 0.3).powi(2))
        };
        let (best, l) = search(start.clone(), 3, loss).unwrap();
        let o = best.pores.as_ref().unwrap().opacity;
        let f = best.fibres.as_ref().unwrap().strength;
        assert!((o - 0.55).abs() <= 0.051, "opacity {o}");
        assert!((f - 0.3).abs() <= 0.051, "fibre strength {f}");
        assert!(l < loss(&start).unwrap());
        // Deterministic.
        assert_eq!(search(start, 3, loss).unwrap().0, best);
    }
}
