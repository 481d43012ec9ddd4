//! Hermite (cubic) Euler-Bernoulli beam elements: element matrices and shape functions.
//!
//! DOFs per node are (w, theta) with w the vertical displacement (upward positive) and
//! theta = dw/dx. Element matrices are the classic ones (e.g. Przemieniecki, "Theory of
//! Matrix Structural Analysis", 1968, ch. 5; docs/physics.md section 3).

use nalgebra::{SMatrix, SVector};

/// 4x4 element matrix in the DOF order (w_i, theta_i, w_j, theta_j).
pub type ElementMatrix = SMatrix<f64, 4, 4>;
/// Values of the four cubic shape functions (or their derivatives) at a point.
pub type ShapeValues = SVector<f64, 4>;

/// Element stiffness `EI/l^3 [[12, 6l, -12, 6l], [6l, 4l^2, -6l, 2l^2], ...]`.
pub fn element_stiffness(ei_n_m2: f64, length_m: f64) -> ElementMatrix {
    let l = length_m;
    let k = ei_n_m2 / (l * l * l);
    k * ElementMatrix::from_row_slice(&[
        12.0,
        6.0 * l,
        -12.0,
        6.0 * l,
        6.0 * l,
        4.0 * l * l,
        -6.0 * l,
        2.0 * l * l,
        -12.0,
        -6.0 * l,
        12.0,
        -6.0 * l,
        6.0 * l,
        2.0 * l * l,
        -6.0 * l,
        4.0 * l * l,
    ])
}

/// Consistent mass `m l / 420 [[156, 22l, 54, -13l], ...]`.
pub fn element_consistent_mass(mass_per_length_kg_m: f64, length_m: f64) -> ElementMatrix {
    let l = length_m;
    let c = mass_per_length_kg_m * l / 420.0;
    c * ElementMatrix::from_row_slice(&[
        156.0,
        22.0 * l,
        54.0,
        -13.0 * l,
        22.0 * l,
        4.0 * l * l,
        13.0 * l,
        -3.0 * l * l,
        54.0,
        13.0 * l,
        156.0,
        -22.0 * l,
        -13.0 * l,
        -3.0 * l * l,
        -22.0 * l,
        4.0 * l * l,
    ])
}

/// Cubic shape functions at local coordinate `xi = (x - x_i) / l` in [0, 1].
/// w(x) = N . (w_i, theta_i, w_j, theta_j).
#[inline]
pub fn shape(xi: f64, length_m: f64) -> ShapeValues {
    let l = length_m;
    let (x2, x3) = (xi * xi, xi * xi * xi);
    ShapeValues::new(
        1.0 - 3.0 * x2 + 2.0 * x3,
        l * (xi - 2.0 * x2 + x3),
        3.0 * x2 - 2.0 * x3,
        l * (x3 - x2),
    )
}

/// dN/dx at `xi` (slope of the interpolated deflection).
#[inline]
pub fn shape_dx(xi: f64, length_m: f64) -> ShapeValues {
    let l = length_m;
    let x2 = xi * xi;
    ShapeValues::new(
        (-6.0 * xi + 6.0 * x2) / l,
        1.0 - 4.0 * xi + 3.0 * x2,
        (6.0 * xi - 6.0 * x2) / l,
        3.0 * x2 - 2.0 * xi,
    )
}

/// d2N/dx2 at `xi` (curvature; bending moment = EI w'').
pub fn shape_dxx(xi: f64, length_m: f64) -> ShapeValues {
    let l = length_m;
    ShapeValues::new(
        (-6.0 + 12.0 * xi) / (l * l),
        (-4.0 + 6.0 * xi) / l,
        (6.0 - 12.0 * xi) / (l * l),
        (6.0 * xi - 2.0) / l,
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shape_functions_reproduce_rigid_motion_and_nodal_values() {
        let l = 2.5;
        for &xi in &[0.0, 0.3, 0.7, 1.0] {
            let n = shape(xi, l);
            // Translation: w = 1 everywhere.
            assert!((n[0] + n[2] - 1.0).abs() < 1e-14);
            // Rotation about node i: w = x, theta = 1.
            let w = n[1] + n[2] * l + n[3];
            assert!((w - xi * l).abs() < 1e-13);
        }
        let n0 = shape(0.0, l);
        assert!((n0[0] - 1.0).abs() < 1e-15 && n0[2].abs() < 1e-15);
    }

    #[test]
    fn derivatives_match_finite_differences() {
        let l = 1.7;
        let (xi, h) = (0.37, 1e-6);
        let fd = (shape(xi + h, l) - shape(xi - h, l)) / (2.0 * h * l);
        assert!((fd - shape_dx(xi, l)).norm() < 1e-8);
        let fd2 = (shape_dx(xi + h, l) - shape_dx(xi - h, l)) / (2.0 * h * l);
        assert!((fd2 - shape_dxx(xi, l)).norm() < 1e-6);
    }

    #[test]
    fn element_matrices_are_symmetric_and_mass_sums_to_element_mass() {
        let k = element_stiffness(3.0e9, 1.5);
        assert!((k - k.transpose()).norm() < 1e-6);
        let m = element_consistent_mass(1000.0, 1.5);
        // Rigid translation: u^T M u = total mass.
        let u = SVector::<f64, 4>::new(1.0, 0.0, 1.0, 0.0);
        assert!(((u.transpose() * m * u)[0] - 1500.0).abs() < 1e-9);
        // Rigid motion produces no elastic force.
        assert!((k * u).norm() < 1e-3);
    }
}
