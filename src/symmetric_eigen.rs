//! Eigenvalues and eigenvectors of a symmetric 3x3 matrix (cyclic Jacobi rotations): the
//! fibre direction of the fit and the colour axes of the NCA's readout both need them, and a
//! 3x3 solver is smaller than a linear-algebra dependency.

use glam::{DMat3, DVec3};

/// Eigenvalues in ascending order and their eigenvectors (columns, in the same order) of a
/// symmetric 3x3 matrix by cyclic Jacobi rotations.
pub(crate) fn symmetric_eigen(m: &DMat3) -> ([f64; 3], DMat3) {
    let mut a = m.to_cols_array_2d(); // a[col][row], symmetric so the same as [row][col]
    let mut v = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    for _ in 0..50 {
        let off = a[0][1].powi(2) + a[0][2].powi(2) + a[1][2].powi(2);
        if off < 1e-30 {
            break;
        }
        for (p, q) in [(0, 1), (0, 2), (1, 2)] {
            if a[p][q].abs() < 1e-300 {
                continue;
            }
            let theta = (a[q][q] - a[p][p]) / (2.0 * a[p][q]);
            let t = theta.signum() / (theta.abs() + (theta * theta + 1.0).sqrt());
            let c = 1.0 / (t * t + 1.0).sqrt();
            rotate(&mut a, &mut v, p, q, c, t * c);
        }
    }
    let values = [a[0][0], a[1][1], a[2][2]];
    let mut order = [0, 1, 2];
    order.sort_by(|&i, &j| values[i].total_cmp(&values[j]));
    let column = |j: usize| DVec3::new(v[0][j], v[1][j], v[2][j]);
    (
        order.map(|j| values[j]),
        DMat3::from_cols(column(order[0]), column(order[1]), column(order[2])),
    )
}

/// Applies the Jacobi rotation J (p, q, c, s): a <- J^T a J, v <- v J (`v[row][col]`, the
/// eigenvectors in its columns).
fn rotate(a: &mut [[f64; 3]; 3], v: &mut [[f64; 3]; 3], p: usize, q: usize, c: f64, s: f64) {
    let columns = |m: &mut [[f64; 3]; 3]| {
        for row in m.iter_mut() {
            let (mp, mq) = (row[p], row[q]);
            row[p] = c * mp - s * mq;
            row[q] = s * mp + c * mq;
        }
    };
    columns(a);
    columns(v);
    let (rp, rq) = (a[p], a[q]);
    a[p] = std::array::from_fn(|k| c * rp[k] - s * rq[k]);
    a[q] = std::array::from_fn(|k| s * rp[k] + c * rq[k]);
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    /// `(R, R diag(3, 1, 0.2) R^T)` with R a rotation: eigenvalues 3, 1, 0.2 on R's columns.
    pub(crate) fn rotated_diagonal() -> (DMat3, DMat3) {
        let r = DMat3::from_axis_angle(DVec3::new(1.0, 2.0, 0.5).normalize(), 0.7);
        (
            r,
            r * DMat3::from_diagonal(DVec3::new(3.0, 1.0, 0.2)) * r.transpose(),
        )
    }

    #[test]
    fn jacobi_gives_back_a_rotated_diagonal_in_ascending_order() {
        let (r, m) = rotated_diagonal();
        let (values, vectors) = symmetric_eigen(&m);
        for (j, (want, axis)) in [(0.2, r.z_axis), (1.0, r.y_axis), (3.0, r.x_axis)]
            .into_iter()
            .enumerate()
        {
            assert!((values[j] - want).abs() < 1e-9, "{values:?}: ascending");
            assert!(vectors.col(j).dot(axis).abs() > 1.0 - 1e-9, "{want}");
        }
    }
}
