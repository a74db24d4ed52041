//! Burl (Moyer 2003): wood that grew around a crowd of dormant buds. Each bud is a short
//! segment (a bud trace running outwards from the pith) that pushes the lookup point away
//! from itself; evaluated through these pushes, the rings eddy around the buds like a stream
//! around stones. Several levels of curl, each with a weaker push and its own noise on the
//! lookup point, are blended to give the depth of polished burl, and the buds themselves show
//! as small dark eyes with a few tight rings. Under the buds the growth is itself erratic
//! ("annual layering ... faster and more erratically", Moyer): the noise on the lookup point
//! is several ring widths strong.
//!
//! Differences from Moyer's shader:
//! - a bud's push fades to zero at `reach_mm` (Wyvill's kernel) instead of decaying as
//!   1/distance over the whole cube, so far buds do not add up to a large uniform shift, and
//!   `push_mm <= reach_mm / 2` keeps one bud's pushed lookup monotonic (no folds);
//! - buds are many (a real burl shows dozens of eyes per square centimetre), so they are
//!   placed once, from the seed, in the cube and a margin around it, gathered in clusters by
//!   a low-frequency noise, and binned in a grid where each cell lists the buds that can
//!   reach it: a point only looks at its own cell's list. Outside that region there are no
//!   buds (the region covers every lookup a point of the cube can make).

use glam::Vec3;
use serde::{Deserialize, Serialize};

use super::cells::wyvill;
use super::checks::{check_colour, check_sizes};
use super::noise::{fbm3, vector_fbm3};
use super::tree::radial_frame;
use crate::config::Checker;
use crate::error::Result;
use crate::field::PithAxis;
use crate::field::smin::smoothstep;
use crate::frame::HALF;
use crate::frame::mm;
use crate::rng::{Rng, mix64};

/// Most buds a burl may place (bounds memory and construction time).
const MAX_BUDS: f32 = 50_000.0;

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BurlConfig {
    /// Mean number of buds per cm^3 (a real burl shows dozens of eyes per cm^2).
    pub density: f32,
    /// How strongly buds gather in clusters (0: evenly spread, 1: only inside clusters).
    pub clustering: f32,
    /// Feature size of the clusters (mm).
    pub cluster_size_mm: f32,
    /// Smallest and largest bud radius (mm).
    pub bud_radius_mm: [f32; 2],
    /// Length of a bud trace along its axis (mm).
    pub bud_length_mm: f32,
    /// Displacement on the axis of the largest bud (mm); smaller buds push in proportion.
    pub push_mm: f32,
    /// Distance from the axis of the largest bud at which its push has faded out (mm);
    /// smaller buds reach in proportion.
    pub reach_mm: f32,
    /// Levels of curl blended together (1 to 4).
    pub levels: usize,
    /// Push factor from one level to the next.
    pub level_push: f32,
    /// Weight of each further level in the blend.
    pub balance: f32,
    /// Amplitude of the noise added to the lookup point of each level (mm).
    pub noise_mm: f32,
    /// Feature size of that noise (mm).
    pub noise_scale_mm: f32,
    /// Colour of a bud's eye.
    pub bud_colour: [f32; 3],
    /// How much a bud's centre takes the bud colour.
    pub bud_opacity: f32,
    /// Dark rings across a bud's radius.
    pub bud_rings: f32,
}

impl BurlConfig {
    pub fn validate(&self, check: &Checker) -> Result<()> {
        check.range("density", self.density, 0.0, 500.0, "buds per cm^3")?;
        check.range("clustering", self.clustering, 0.0, 1.0, "a share")?;
        check.range(
            "cluster_size_mm",
            self.cluster_size_mm,
            0.5,
            1000.0,
            "a size in mm",
        )?;
        check_sizes(
            check,
            "bud_radius_mm",
            self.bud_radius_mm,
            100.0,
            "bud radii",
        )?;
        if self.bud_radius_mm[0] > self.bud_radius_mm[1] {
            return Err(check.error(
                "bud_radius_mm",
                format!("= {:?}: expected [smallest, largest]", self.bud_radius_mm),
            ));
        }
        check.range(
            "bud_length_mm",
            self.bud_length_mm,
            0.0,
            100.0,
            "a length in mm",
        )?;
        check.range(
            "reach_mm",
            self.reach_mm,
            self.bud_radius_mm[1],
            100.0,
            "a distance in mm, at least the largest bud radius",
        )?;
        check.range(
            "push_mm",
            self.push_mm,
            0.0,
            0.5 * self.reach_mm,
            "a displacement in mm, at most reach_mm / 2 so the push never folds the wood",
        )?;
        check.count("levels", self.levels, 1, 4, "levels of curl")?;
        check.range("level_push", self.level_push, 0.0, 1.0, "a factor")?;
        check.range("balance", self.balance, 0.0, 1.0, "a blend weight")?;
        check.range(
            "noise_mm",
            self.noise_mm,
            0.0,
            100.0,
            "a displacement in mm",
        )?;
        check.range(
            "noise_scale_mm",
            self.noise_scale_mm,
            0.1,
            10_000.0,
            "a size in mm",
        )?;
        check_colour(check, "bud_colour", self.bud_colour)?;
        check.range("bud_opacity", self.bud_opacity, 0.0, 1.0, "an opacity")?;
        check.range("bud_rings", self.bud_rings, 0.0, 20.0, "a ring count")?;
        let count = self.bud_count();
        if count > MAX_BUDS {
            return Err(check.error(
                "density",
                format!(
                    "= {}: gives {count:.0} buds in the cube and its margin; at most {MAX_BUDS} \
                     are supported (lower density or reach_mm / noise_mm)",
                    self.density
                ),
            ));
        }
        Ok(())
    }

    /// Margin (cube units) around the cube where buds can still reach a lookup.
    fn margin(&self) -> f32 {
        mm(self.reach_mm + self.bud_length_mm + 2.0 * self.noise_mm)
    }

    /// Number of buds placed in the cube and its margin.
    fn bud_count(&self) -> f32 {
        let side_cm = (2.0 * (HALF + self.margin())) * crate::frame::CM_PER_UNIT;
        self.density * side_cm.powi(3)
    }
}

#[derive(Clone, Copy, Debug)]
struct Bud {
    centre: Vec3,
    /// Unit axis of the bud trace.
    axis: Vec3,
    half_length: f32,
    radius: f32,
    /// Push at the axis and the distance where it has faded out (cube units).
    push: f32,
    reach: f32,
}

impl Bud {
    /// Offset from the nearest point of the bud's trace to `p`.
    #[inline]
    fn offset(&self, p: Vec3) -> Vec3 {
        let v = p - self.centre;
        let along = v.dot(self.axis).clamp(-self.half_length, self.half_length);
        v - along * self.axis
    }
}

/// Buds binned in a uniform grid: cell c lists (in `indices[starts[c]..starts[c + 1]]`) every
/// bud whose reach overlaps it.
#[derive(Clone, Debug)]
struct BudGrid {
    buds: Vec<Bud>,
    lo: f32,
    cell: f32,
    n: usize,
    starts: Vec<u32>,
    indices: Vec<u32>,
}

impl BudGrid {
    fn new(buds: Vec<Bud>, lo: f32, hi: f32, cell: f32) -> Self {
        let n = (((hi - lo) / cell).ceil() as usize).max(1);
        let index = |v: f32| (((v - lo) / cell).floor().max(0.0) as usize).min(n - 1);
        let mut lists: Vec<Vec<u32>> = vec![Vec::new(); n * n * n];
        for (b, bud) in buds.iter().enumerate() {
            let extent = bud.axis.abs() * bud.half_length + Vec3::splat(bud.reach);
            let (a, z) = (bud.centre - extent, bud.centre + extent);
            for i in index(a.x)..=index(z.x) {
                for j in index(a.y)..=index(z.y) {
                    for k in index(a.z)..=index(z.z) {
                        lists[(i * n + j) * n + k].push(b as u32);
                    }
                }
            }
        }
        let mut starts = Vec::with_capacity(lists.len() + 1);
        let mut indices = Vec::new();
        for list in &lists {
            starts.push(indices.len() as u32);
            indices.extend_from_slice(list);
        }
        starts.push(indices.len() as u32);
        Self {
            buds,
            lo,
            cell,
            n,
            starts,
            indices,
        }
    }

    /// The buds that can reach `p` (none outside the grid).
    #[inline]
    fn near(&self, p: Vec3) -> impl Iterator<Item = &Bud> {
        let f = (p - Vec3::splat(self.lo)) / self.cell;
        let inside = f.min_element() >= 0.0 && f.max_element() < self.n as f32;
        let range = if inside {
            let c = (f.x as usize * self.n + f.y as usize) * self.n + f.z as usize;
            self.starts[c] as usize..self.starts[c + 1] as usize
        } else {
            0..0
        };
        self.indices[range].iter().map(|&b| &self.buds[b as usize])
    }
}

#[derive(Clone, Debug)]
pub struct Burl {
    grid: BudGrid,
    levels: usize,
    level_push: f32,
    pub balance: f32,
    seed: u64,
    noise: f32,
    noise_scale: f32,
    pub bud_colour: Vec3,
    pub bud_opacity: f32,
    bud_rings: f32,
}

impl Burl {
    /// Places the buds from the seed: uniformly in the cube and its margin, kept with a
    /// probability that follows the cluster noise. Bud traces run outwards from the pith.
    pub fn new(cfg: &BurlConfig, pith: &PithAxis, seed: u64) -> Self {
        let mut rng = Rng::substream(seed, 0x4255_4453);
        let [r_min, r_max] = cfg.bud_radius_mm.map(mm);
        let bound = HALF + cfg.margin();
        let cluster_seed = mix64(seed ^ 0x434c);
        let cluster_scale = 1.0 / mm(cfg.cluster_size_mm);
        let keep = |p: Vec3| {
            let n = fbm3(cluster_seed, p * cluster_scale, 2);
            let clustered = smoothstep(0.0, 0.35, n);
            1.0 - cfg.clustering * (1.0 - clustered)
        };
        let target = cfg.bud_count().round() as usize;
        let mut buds = Vec::with_capacity(target);
        // Rejection sampling; the attempt cap only matters for extreme clustering.
        let mut attempts = 0;
        while buds.len() < target && attempts < 50 * target.max(1) {
            attempts += 1;
            let centre = Vec3::new(
                rng.range(-bound, bound),
                rng.range(-bound, bound),
                rng.range(-bound, bound),
            );
            if rng.uniform() >= keep(centre) {
                continue;
            }
            let outward = radial_frame(pith, centre).map_or(Vec3::Z, |(r, _)| r);
            let tilt = 0.35 * Vec3::new(rng.normal(), rng.normal(), rng.normal());
            let axis = (outward + tilt).normalize_or(outward);
            let radius = rng.range(r_min, r_max);
            let size = radius / r_max;
            buds.push(Bud {
                centre,
                axis,
                half_length: 0.5 * mm(cfg.bud_length_mm) * rng.range(0.5, 1.5),
                radius,
                push: mm(cfg.push_mm) * size,
                reach: mm(cfg.reach_mm) * size,
            });
        }
        let cell = mm(cfg.reach_mm).max(1e-3);
        Self {
            grid: BudGrid::new(buds, -bound, bound, cell),
            levels: cfg.levels,
            level_push: cfg.level_push,
            balance: cfg.balance,
            seed,
            noise: mm(cfg.noise_mm),
            noise_scale: 1.0 / mm(cfg.noise_scale_mm),
            bud_colour: Vec3::from(cfg.bud_colour),
            bud_opacity: cfg.bud_opacity,
            bud_rings: cfg.bud_rings,
        }
    }

    pub fn levels(&self) -> usize {
        self.levels
    }

    /// The lookup point of curl level `level` (0 = strongest) for `p`.
    pub fn lookup(&self, p: Vec3, level: usize) -> Vec3 {
        let scale = self.level_push.powi(level as i32);
        let level_seed = mix64(self.seed ^ (level as u64 + 1));
        let q = if self.noise > 0.0 {
            p + self.noise * vector_fbm3(level_seed, p * self.noise_scale, 2)
        } else {
            p
        };
        let mut shift = Vec3::ZERO;
        for bud in self.grid.near(q) {
            let c = bud.offset(q);
            let d2 = c.length_squared();
            let reach2 = bud.reach * bud.reach;
            if d2 >= reach2 || d2 < 1e-14 {
                continue;
            }
            shift += c * (scale * bud.push * wyvill(d2 / reach2) / d2.sqrt());
        }
        q + shift
    }

    /// Weight and ring shade of the nearest bud's eye at `p`: (weight, shade).
    pub fn eye(&self, p: Vec3) -> (f32, f32) {
        let nearest = self
            .grid
            .near(p)
            .map(|b| b.offset(p).length() / b.radius)
            .fold(f32::INFINITY, f32::min);
        if nearest >= 1.0 {
            return (0.0, 1.0);
        }
        let weight = self.bud_opacity * (1.0 - smoothstep(0.6, 1.0, nearest));
        let shade = 0.8 + 0.2 * (std::f32::consts::TAU * self.bud_rings * nearest).cos();
        (weight, shade)
    }
}
