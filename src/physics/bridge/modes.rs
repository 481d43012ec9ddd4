//! Natural frequencies and mode shapes from the library eigen-solver, and Rayleigh damping.

use nalgebra::{DMatrix, DVector, SymmetricEigen};

use crate::error::{Error, Result};

/// Mass-normalized modes of `K phi = w^2 M phi`, sorted by frequency.
pub struct Modes {
    pub omega_rad_s: DVector<f64>,
    /// Columns are mode shapes with `phi^T M phi = 1`.
    pub shapes: DMatrix<f64>,
}

/// Solves the generalized symmetric eigenproblem by Cholesky reduction
/// (`M = L L^T`, `A = L^-1 K L^-T`) and nalgebra's symmetric eigen-solver.
pub fn generalized_modes(stiffness: &DMatrix<f64>, mass: &DMatrix<f64>) -> Result<Modes> {
    let chol = mass
        .clone()
        .cholesky()
        .ok_or_else(|| Error::Factorization {
            what: "mass matrix".into(),
            reason: "not positive definite".into(),
        })?;
    let l = chol.l();
    // A = L^-1 K L^-T, by two triangular solves.
    let mut a = stiffness.clone();
    l.solve_lower_triangular_mut(&mut a);
    let mut a = a.transpose();
    l.solve_lower_triangular_mut(&mut a);
    let a = (&a + a.transpose()) * 0.5;
    let eigen = SymmetricEigen::new(a);
    let mut order: Vec<usize> = (0..eigen.eigenvalues.len()).collect();
    order.sort_by(|&i, &j| eigen.eigenvalues[i].total_cmp(&eigen.eigenvalues[j]));
    let n = order.len();
    let mut omega = DVector::zeros(n);
    let mut psi = DMatrix::zeros(n, n);
    for (k, &i) in order.iter().enumerate() {
        omega[k] = eigen.eigenvalues[i].max(0.0).sqrt();
        psi.set_column(k, &eigen.eigenvectors.column(i));
    }
    // phi = L^-T psi
    let lt = l.transpose();
    if !lt.solve_upper_triangular_mut(&mut psi) {
        return Err(Error::Factorization {
            what: "mass Cholesky factor".into(),
            reason: "singular".into(),
        });
    }
    Ok(Modes {
        omega_rad_s: omega,
        shapes: psi,
    })
}

/// Rayleigh damping `C = a0 M + a1 K` (docs/physics.md section 4).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Rayleigh {
    /// Mass-proportional coefficient (1/s).
    pub a0_per_s: f64,
    /// Stiffness-proportional coefficient (s).
    pub a1_s: f64,
}

impl Rayleigh {
    /// Fits the same ratio `zeta` on two circular frequencies.
    pub fn fit(zeta: f64, omega1_rad_s: f64, omega2_rad_s: f64) -> Self {
        let sum = omega1_rad_s + omega2_rad_s;
        Rayleigh {
            a0_per_s: 2.0 * zeta * omega1_rad_s * omega2_rad_s / sum,
            a1_s: 2.0 * zeta / sum,
        }
    }

    /// Damping ratio this curve gives at `omega`.
    pub fn ratio_at(&self, omega_rad_s: f64) -> f64 {
        self.a0_per_s / (2.0 * omega_rad_s) + self.a1_s * omega_rad_s / 2.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rayleigh_fit_hits_both_frequencies() {
        let r = Rayleigh::fit(0.02, 23.75, 95.0);
        assert!((r.ratio_at(23.75) - 0.02).abs() < 1e-15);
        assert!((r.ratio_at(95.0) - 0.02).abs() < 1e-15);
        // Between the two fitted modes the curve dips below zeta.
        assert!(r.ratio_at(50.0) < 0.02);
    }

    #[test]
    fn two_dof_modes_are_mass_normalized() {
        let k = DMatrix::from_row_slice(2, 2, &[2.0, -1.0, -1.0, 1.0]);
        let m = DMatrix::from_row_slice(2, 2, &[1.0, 0.0, 0.0, 2.0]);
        let modes = generalized_modes(&k, &m).unwrap();
        let gram = modes.shapes.transpose() * &m * &modes.shapes;
        assert!((gram - DMatrix::identity(2, 2)).norm() < 1e-12);
        // det(K - l M) = 2 l^2 - 5 l + 1 = 0
        let expected = (5.0 - 17f64.sqrt()) / 4.0;
        assert!((modes.omega_rad_s[0].powi(2) - expected).abs() < 1e-12);
    }
}
