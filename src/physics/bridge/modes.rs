//! Natural frequencies and mode shapes, and Rayleigh damping.
//!
//! A run needs a few modes (the Rayleigh fit, the reported frequencies, the ambient
//! calibration) or a few hundred (a modal model), never all of a fine mesh. The lowest
//! modes come from the model's band by Sturm bisection and inverse iteration
//! ([`crate::physics::linalg::lowest_eigenpairs`]: O(n b^2) per eigenvalue, O(n b) memory
//! beside the shapes). The dense eigen-solution of the whole pencil (O(n^3) time, O(n^2)
//! memory) is kept where it is cheaper, for models of at most [`DENSE_EIGEN_MAX_DOF`]
//! DOFs, and as the reference the banded route is tested against.

use nalgebra::{DMatrix, DVector, SymmetricEigen};

use crate::error::{Error, Result};
use crate::physics::linalg::{count_below, lowest_eigenpairs, EigenError, SymBand, SymMatrix};

/// Largest model solved by the dense eigen-solution (every mode at once, a few
/// milliseconds at this size). The bound keeps the modes of the small models the examples
/// and the default scenario use, and so their output, exactly as they were; it is not a
/// measured crossover of the two routes' costs.
pub const DENSE_EIGEN_MAX_DOF: usize = 200;

/// Which modes to compute.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Wanted {
    /// The lowest `n` modes.
    Lowest(usize),
    /// Every mode below this circular frequency (rad/s), and at least one.
    Below(f64),
}

/// Where a model's modes come from.
#[derive(Debug, Clone)]
pub enum EigenRoute {
    /// The model's own band K and M (finite elements).
    OwnBand,
    /// The condensation mesh of a lumped model, with the masses on its translations and
    /// its rotations massless (`model_dofs`: the mesh DOFs that are the model's DOFs, in
    /// order): its finite eigenpairs are those of the condensed stiffness.
    CondensationMesh {
        stiffness: SymBand,
        mass: SymBand,
        model_dofs: Vec<usize>,
    },
    /// Diagonal K and M (a modal model): the modes are the unit vectors.
    Diagonal,
}

impl EigenRoute {
    /// The wanted lowest modes of the model whose matrices are `stiffness` and `mass`.
    pub fn lowest(&self, stiffness: &SymMatrix, mass: &SymMatrix, wanted: Wanted) -> Result<Modes> {
        let n = mass.n();
        match self {
            _ if n <= DENSE_EIGEN_MAX_DOF => {
                let all = generalized_modes(&stiffness.to_dense(), &mass.to_dense())?;
                let count = match wanted {
                    Wanted::Lowest(count) => check_count(count, n)?,
                    Wanted::Below(omega) => count_up_to(&all.omega_rad_s, omega),
                };
                Ok(all.truncated(count))
            }
            EigenRoute::Diagonal => Ok(diagonal_modes(stiffness, mass, wanted)?),
            EigenRoute::OwnBand => match (stiffness, mass) {
                (SymMatrix::Band(k), SymMatrix::Band(m)) => banded_modes(k, m, None, n, wanted),
                _ => Err(Error::Factorization {
                    what: "bridge model".into(),
                    reason: "the banded eigen-solution needs band matrices (bug)".into(),
                }),
            },
            EigenRoute::CondensationMesh {
                stiffness: k,
                mass: m,
                model_dofs,
            } => banded_modes(k, m, Some(model_dofs), n, wanted),
        }
    }
}

/// The lowest modes of diagonal K and M: unit vectors, ordered by frequency.
fn diagonal_modes(stiffness: &SymMatrix, mass: &SymMatrix, wanted: Wanted) -> Result<Modes> {
    let n = mass.n();
    let omega = stiffness
        .diagonal()
        .zip_map(&mass.diagonal(), |k, m| (k / m).sqrt());
    let mut order: Vec<usize> = (0..n).collect();
    order.sort_by(|&i, &j| omega[i].total_cmp(&omega[j]));
    let sorted = DVector::from_iterator(n, order.iter().map(|&i| omega[i]));
    let count = match wanted {
        Wanted::Lowest(count) => check_count(count, n)?,
        Wanted::Below(cut) => count_up_to(&sorted, cut),
    };
    let mut shapes = DMatrix::zeros(n, count);
    for (c, &i) in order.iter().take(count).enumerate() {
        shapes[(i, c)] = 1.0 / mass.get(i, i).sqrt();
    }
    Ok(Modes {
        omega_rad_s: sorted.rows(0, count).into_owned(),
        shapes,
    })
}

/// The lowest modes of the band pencil `(k, m)`, restricted to `model_dofs` when given;
/// `n` is the model's number of DOFs.
fn banded_modes(
    k: &SymBand,
    m: &SymBand,
    model_dofs: Option<&Vec<usize>>,
    n: usize,
    wanted: Wanted,
) -> Result<Modes> {
    let count = match wanted {
        Wanted::Lowest(count) => check_count(count, n)?,
        Wanted::Below(omega) => count_below(k, m, omega * omega).clamp(1, n),
    };
    let (values, vectors) = lowest_eigenpairs(k, m, count).map_err(eigen_error)?;
    Ok(Modes {
        omega_rad_s: DVector::from_iterator(count, values.iter().map(|l| l.max(0.0).sqrt())),
        shapes: match model_dofs {
            Some(dofs) => vectors.select_rows(dofs),
            None => vectors,
        },
    })
}

/// A mode count must lie in 1..=n.
fn check_count(count: usize, n: usize) -> Result<usize> {
    match count <= n {
        true => Ok(count),
        false => Err(Error::invalid(
            "modes",
            count,
            format!("must not exceed the model's {n} DOFs"),
        )),
    }
}

/// How many of the ascending `omega` lie at or below `cut`, at least one.
fn count_up_to(omega: &DVector<f64>, cut: f64) -> usize {
    omega
        .iter()
        .take_while(|&&w| w <= cut)
        .count()
        .max(1)
        .min(omega.len())
}

fn eigen_error(e: EigenError) -> Error {
    match e {
        EigenError::StiffnessNotPositiveDefinite => Error::Factorization {
            what: "bridge stiffness".into(),
            reason: "not positive definite (the structure is a mechanism)".into(),
        },
        EigenError::TooFewModes { wanted, available } => Error::invalid(
            "modes",
            wanted,
            format!("must not exceed the model's {available} DOFs with mass"),
        ),
    }
}

/// Mass-normalized modes of `K phi = w^2 M phi`, sorted by frequency.
pub struct Modes {
    pub omega_rad_s: DVector<f64>,
    /// Columns are mode shapes with `phi^T M phi = 1`.
    pub shapes: DMatrix<f64>,
}

impl Modes {
    /// The lowest `count` modes.
    pub fn truncated(self, count: usize) -> Modes {
        Modes {
            omega_rad_s: self.omega_rad_s.rows(0, count).into_owned(),
            shapes: self.shapes.columns(0, count).into_owned(),
        }
    }
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
