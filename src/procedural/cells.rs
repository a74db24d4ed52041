//! Cylindrical cells for stratified placement of pores and rays (Liu et al. 2016 section 4.6,
//! with Mokume's cylindrical cells so the density is uniform at every radius).
//!
//! Space around the pith is cut into shells of `radial` thickness in rho (the undistorted
//! radius, rho = G / years_per_unit, so shells follow the rings and bend around knots). Shell i
//! is cut into n_i = round(2 pi rho_i / tangential) equal azimuth sectors (whole cells all
//! around, no seam), and each sector column into `along` long pieces along the pith, with a
//! random offset per column so cell ends do not line up. Each cell holds at most one feature,
//! jittered inside it. Features kept whole inside their cell (pores) need only the point's own
//! cell: one hash per point instead of a 27-cell search. Features longer than a shell (rays
//! running outwards) are looked up in the few shells they can reach from, so shells do not
//! leave radial gaps where no ray exists.

use std::f32::consts::TAU;

use glam::Vec3;

use super::noise::{floor, hash_units3, lattice_hash};

#[derive(Clone, Copy, Debug)]
pub(crate) struct CylinderCells {
    seed: u64,
    /// Cell size (cube units): radial, tangential, along the pith.
    pub size: Vec3,
    /// 1 / size.x, 2 pi / size.y, 1 / size.z (the lookup runs per point and layer).
    inv_radial: f32,
    sectors_per_radius: f32,
    inv_along: f32,
}

/// A point located in its cell: the cell's hash and the point's offsets from the cell's
/// inner, first-azimuth, lower corner (cube units).
#[derive(Clone, Copy, Debug)]
pub(crate) struct CellPoint {
    pub hash: u64,
    /// Offset along the radius, in [0, size.x).
    pub radial: f32,
    /// Arc length along the azimuth, in [0, width).
    pub tangential: f32,
    /// Offset along the pith, in [0, size.z).
    pub along: f32,
    /// The cell's actual tangential width (n_i cells share the circumference).
    pub width: f32,
    /// rho of the cell's inner boundary.
    pub rho0: f32,
}

impl CylinderCells {
    pub(crate) fn new(seed: u64, size: Vec3) -> Self {
        Self {
            seed,
            size,
            inv_radial: 1.0 / size.x,
            sectors_per_radius: TAU / size.y,
            inv_along: 1.0 / size.z,
        }
    }

    /// The shell holding undistorted radius `rho`.
    #[inline]
    pub(crate) fn shell(&self, rho: f32) -> i32 {
        floor(rho.max(0.0) * self.inv_radial) as i32
    }

    /// The cell of a point at undistorted radius `rho`, azimuth `phi` in [0, 2 pi) and height
    /// `h`.
    #[inline]
    pub(crate) fn locate(&self, rho: f32, phi: f32, h: f32) -> CellPoint {
        self.locate_in_shell(self.shell(rho), rho, phi, h)
    }

    /// The cell of shell `shell` (not necessarily the point's own) at the point's azimuth and
    /// height, with the point's offsets from it; for features longer than a shell, which a
    /// point looks up in the neighbouring shells too.
    #[inline]
    pub(crate) fn locate_in_shell(&self, shell: i32, rho: f32, phi: f32, h: f32) -> CellPoint {
        let shell = shell as f32;
        let rho0 = shell * self.size.x;
        let mid = rho0 + 0.5 * self.size.x;
        let sectors = floor(mid * self.sectors_per_radius + 0.5).max(1.0);
        let a = phi * (1.0 / TAU) * sectors;
        let sector = floor(a).min(sectors - 1.0);
        let width = TAU * mid / sectors;
        let (i, j) = (shell as i32, sector as i32);
        let column = lattice_hash(self.seed, i, j, i32::MIN);
        let b = h * self.inv_along + crate::rng::unit(column);
        let k = floor(b);
        CellPoint {
            hash: lattice_hash(self.seed, i, j, k as i32),
            radial: rho - rho0,
            tangential: (a - sector) * width,
            along: (b - k) * self.size.z,
            width,
            rho0,
        }
    }
}

impl CellPoint {
    /// A feature centre inside the cell keeping a feature of half-extents `half` whole
    /// (radial, tangential, along), from the cell hash.
    #[inline]
    pub(crate) fn centre(&self, size: Vec3, half: Vec3) -> Vec3 {
        let extent = Vec3::new(size.x, self.width, size.z);
        let room = (extent - 2.0 * half).max(Vec3::ZERO);
        half + room * hash_units3(self.hash)
    }

    /// The point's offset from `centre` (radial, tangential, along).
    #[inline]
    pub(crate) fn offset(&self, centre: Vec3) -> Vec3 {
        Vec3::new(self.radial, self.tangential, self.along) - centre
    }
}

/// Wyvill's kernel (1 - d^2)^3 on the squared normalised distance (0 outside the unit ball).
#[inline]
pub(crate) fn wyvill(d2: f32) -> f32 {
    if d2 >= 1.0 {
        return 0.0;
    }
    let a = 1.0 - d2;
    a * a * a
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cells_tile_each_shell_without_a_seam() {
        let cells = CylinderCells::new(4, Vec3::new(0.01, 0.01, 0.05));
        let rho = 0.2345;
        let just_below = cells.locate(rho, TAU - 1e-5, 0.0);
        let at_zero = cells.locate(rho, 0.0, 0.0);
        assert!(just_below.tangential > just_below.width * 0.99);
        assert!(at_zero.tangential < 1e-3);
        assert_ne!(just_below.hash, at_zero.hash);
        // Same cell for nearby points, and local offsets inside the cell's extent.
        let a = cells.locate(rho, 1.0, 0.3);
        let b = cells.locate(rho + 1e-6, 1.0 + 1e-7, 0.3 + 1e-6);
        assert_eq!(a.hash, b.hash);
        assert!(a.radial >= 0.0 && a.radial < 0.01);
        assert!((a.width - 0.01).abs() < 0.001, "width {}", a.width);
    }

    #[test]
    fn kernel_is_one_at_the_centre_and_zero_outside() {
        assert_eq!(wyvill(0.0), 1.0);
        assert_eq!(wyvill(1.0), 0.0);
        assert!(wyvill(0.5) > 0.0 && wyvill(0.5) < 1.0);
    }
}
