//! Lumped-mass model: N equal masses at equal spacing, stiffness by the flexibility
//! method (the paper's route) or by static condensation of a Hermite mesh with a node at
//! every mass (the general route: non-uniform EI, more supports).

use nalgebra::DMatrix;

use super::beam::BeamProperties;
use super::mesh::HermiteMesh;
use crate::error::{Error, Result};

/// Deflection at `x` under a unit load at `a` on a uniform simply supported beam
/// (docs/physics.md section 2; e.g. Gere & Timoshenko, Mechanics of Materials, table G-2).
pub fn unit_load_deflection_m_per_n(beam: &BeamProperties, x_m: f64, a_m: f64) -> f64 {
    let l = beam.span_m;
    let ei = beam.flexural_rigidity_n_m2;
    let b = l - a_m;
    if x_m <= a_m {
        b * x_m * (l * l - b * b - x_m * x_m) / (6.0 * ei * l)
    } else {
        a_m * (l - x_m) * (2.0 * l * x_m - x_m * x_m - a_m * a_m) / (6.0 * ei * l)
    }
}

/// Abscissae of the N interior masses: spacing L / (N + 1).
pub fn mass_positions_m(span_m: f64, n_masses: usize) -> Vec<f64> {
    (1..=n_masses)
        .map(|i| span_m * i as f64 / (n_masses + 1) as f64)
        .collect()
}

/// The flexibility matrix F (m/N) of the masses: F_ij = deflection at x_i under unit load at x_j.
pub fn flexibility_matrix(beam: &BeamProperties, n_masses: usize) -> DMatrix<f64> {
    let x = mass_positions_m(beam.span_m, n_masses);
    DMatrix::from_fn(n_masses, n_masses, |i, j| {
        unit_load_deflection_m_per_n(beam, x[i], x[j])
    })
}

/// K = F^-1 by Cholesky (F is symmetric positive definite). Only for uniform EI.
pub fn stiffness_by_flexibility(beam: &BeamProperties, n_masses: usize) -> Result<DMatrix<f64>> {
    if !beam.is_uniform() {
        return Err(Error::invalid(
            "bridge.stiffness_regions",
            beam.stiffness_regions.len(),
            "closed-form flexibility needs a uniform beam; use the condensation route",
        ));
    }
    let f = flexibility_matrix(beam, n_masses);
    let chol = f.cholesky().ok_or_else(|| Error::Factorization {
        what: "flexibility matrix".into(),
        reason: "not positive definite".into(),
    })?;
    let k = chol.inverse();
    // Symmetrize the round-off so that later Cholesky factorizations see an exact mirror.
    Ok((&k + k.transpose()) * 0.5)
}

/// The Hermite mesh with nodes at the supports and at every mass.
pub fn condensation_mesh(beam: &BeamProperties, n_masses: usize) -> HermiteMesh {
    let mut nodes = vec![0.0];
    nodes.extend(mass_positions_m(beam.span_m, n_masses));
    nodes.push(beam.span_m);
    HermiteMesh::new(beam, nodes, &[0.0, beam.span_m])
}

/// Static condensation of a Hermite model onto its translational DOFs.
///
/// `K_c = K_ww - K_wt K_tt^-1 K_tw`; also returns `T` (n_full x n_w) such that the full
/// DOF vector of a state loaded only at the masses is `T w`: it maps point operators of
/// the mesh onto the condensed DOFs (`h_c = T^T h`).
pub struct Condensation {
    pub stiffness: DMatrix<f64>,
    pub transform: DMatrix<f64>,
}

/// Condenses `mesh` onto its w DOFs.
pub fn condense(mesh: &HermiteMesh) -> Result<Condensation> {
    let k = mesh.stiffness();
    let (w, t) = mesh.split_dofs();
    let k_tt = k.select_rows(&t).select_columns(&t);
    let k_tw = k.select_rows(&t).select_columns(&w);
    let k_ww = k.select_rows(&w).select_columns(&w);
    let chol = k_tt.cholesky().ok_or_else(|| Error::Factorization {
        what: "rotational stiffness block".into(),
        reason: "not positive definite".into(),
    })?;
    // theta = -K_tt^-1 K_tw w
    let theta_from_w = -chol.solve(&k_tw);
    let stiffness = &k_ww + k_tw.transpose() * &theta_from_w;
    let mut transform = DMatrix::zeros(mesh.n_dof, w.len());
    for (col, &dof) in w.iter().enumerate() {
        transform[(dof, col)] = 1.0;
    }
    for (row, &dof) in t.iter().enumerate() {
        transform.row_mut(dof).copy_from(&theta_from_w.row(row));
    }
    let stiffness = (&stiffness + stiffness.transpose()) * 0.5;
    Ok(Condensation {
        stiffness,
        transform,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn flexibility_is_symmetric_and_matches_midspan_formula() {
        let beam = BeamProperties::paper_default();
        // P L^3 / 48 EI at midspan for a load at midspan.
        let l = beam.span_m;
        let d = unit_load_deflection_m_per_n(&beam, l / 2.0, l / 2.0);
        let expected = l.powi(3) / (48.0 * beam.flexural_rigidity_n_m2);
        assert!((d - expected).abs() < 1e-12 * expected);
        // Maxwell reciprocity.
        let a = unit_load_deflection_m_per_n(&beam, 7.0, 19.0);
        let b = unit_load_deflection_m_per_n(&beam, 19.0, 7.0);
        assert!((a - b).abs() < 1e-12 * a.abs());
    }

    #[test]
    fn flexibility_and_condensation_give_the_same_stiffness() {
        // Both routes are exact for a uniform beam (Hermite cubics are the exact static
        // solution between nodal loads), so only round-off separates them: 1e-9 relative
        // (the condition number of K grows as N^4: ~1e8 at N = 100).
        let beam = BeamProperties::paper_default();
        for n in [7, 20, 50, 100] {
            let kf = stiffness_by_flexibility(&beam, n).unwrap();
            let kc = condense(&condensation_mesh(&beam, n)).unwrap().stiffness;
            let rel = (&kf - &kc).norm() / kc.norm();
            assert!(rel < 1e-9, "n = {n}: relative difference {rel:e}");
        }
    }
}
