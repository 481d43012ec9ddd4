//! The banded eigensolver against nalgebra's dense symmetric eigen-solution of the same
//! pencil (the reference), on pencils with the features bridge models have: a consistent
//! (banded) mass, a diagonal mass, massless DOFs, and repeated eigenvalues.

use nalgebra::{DMatrix, SymmetricEigen};

use super::*;

/// Dense reference: eigenvalues ascending and M-normalized vectors of `K x = l M x` with
/// M positive definite (Cholesky reduction).
fn dense_reference(k: &DMatrix<f64>, m: &DMatrix<f64>) -> (Vec<f64>, DMatrix<f64>) {
    let l = m.clone().cholesky().expect("M positive definite").l();
    let mut a = k.clone();
    l.solve_lower_triangular_mut(&mut a);
    let mut a = a.transpose();
    l.solve_lower_triangular_mut(&mut a);
    let eigen = SymmetricEigen::new((&a + a.transpose()) * 0.5);
    let mut order: Vec<usize> = (0..a.nrows()).collect();
    order.sort_by(|&i, &j| eigen.eigenvalues[i].total_cmp(&eigen.eigenvalues[j]));
    let mut vectors = DMatrix::zeros(a.nrows(), a.nrows());
    for (c, &i) in order.iter().enumerate() {
        vectors.set_column(c, &eigen.eigenvectors.column(i));
    }
    assert!(l.transpose().solve_upper_triangular_mut(&mut vectors));
    (
        order.iter().map(|&i| eigen.eigenvalues[i]).collect(),
        vectors,
    )
}

/// A 1-D Hermite-like pencil: a fixed-fixed chain of `n` nodes with (w, theta) DOFs,
/// stiffness and consistent mass of uniform beam elements of length `h`.
fn beam_pencil(elements: usize, h: f64) -> (SymBand, SymBand) {
    let n = 2 * (elements - 1);
    let mut k = SymBand::zeros(n, 3);
    let mut m = SymBand::zeros(n, 3);
    let (h2, h3) = (h * h, h * h * h);
    let ke = [
        [12.0 / h3, 6.0 / h2, -12.0 / h3, 6.0 / h2],
        [6.0 / h2, 4.0 / h, -6.0 / h2, 2.0 / h],
        [-12.0 / h3, -6.0 / h2, 12.0 / h3, -6.0 / h2],
        [6.0 / h2, 2.0 / h, -6.0 / h2, 4.0 / h],
    ];
    let c = h / 420.0;
    let me = [
        [156.0 * c, 22.0 * h * c, 54.0 * c, -13.0 * h * c],
        [22.0 * h * c, 4.0 * h2 * c, 13.0 * h * c, -3.0 * h2 * c],
        [54.0 * c, 13.0 * h * c, 156.0 * c, -22.0 * h * c],
        [-13.0 * h * c, -3.0 * h2 * c, -22.0 * h * c, 4.0 * h2 * c],
    ];
    for e in 0..elements {
        // Node e has DOFs 2(e-1), 2(e-1)+1; nodes 0 and `elements` are clamped.
        let dof = |local: usize| {
            let node = e + local / 2;
            (node >= 1 && node < elements).then(|| 2 * (node - 1) + local % 2)
        };
        // Each global pair (i >= j) takes its element entry once; add() mirrors it.
        for r in 0..4 {
            for s in 0..4 {
                if let (Some(i), Some(j)) = (dof(r), dof(s)) {
                    if i >= j {
                        k.add(i, j, ke[r][s]);
                        m.add(i, j, me[r][s]);
                    }
                }
            }
        }
    }
    (k, m)
}

/// MAC of column `j` of `a` and `b` in the inner product of `m`.
fn mac(a: &DMatrix<f64>, b: &DMatrix<f64>, m: &SymBand, j: usize) -> f64 {
    SymMatrix::Band(m.clone()).modal_assurance(&a.column(j).into_owned(), &b.column(j).into_owned())
}

#[test]
fn a_consistent_mass_pencil_matches_the_dense_solution() {
    // 30 clamped Hermite elements (58 DOFs): small enough that the dense reference's own
    // round-off (eps * lambda_max / lambda_j, 2e-10 for mode 1 here) stays below 1e-9.
    let (k, m) = beam_pencil(30, 1.0 / 30.0);
    let (kd, md) = (k.to_dense(), m.to_dense());
    let (reference, ref_vectors) = dense_reference(&kd, &md);
    let wanted = 20;
    let (values, vectors) = lowest_eigenpairs(&k, &m, wanted).unwrap();
    let gram = vectors.transpose() * &md * &vectors;
    assert!((gram - DMatrix::identity(wanted, wanted)).amax() < 1e-10);
    for j in 0..wanted {
        let rel = (values[j] - reference[j]).abs() / reference[j];
        assert!(rel < 1e-9, "mode {}: relative error {rel:e}", j + 1);
        let mac = mac(&vectors, &ref_vectors, &m, j);
        assert!(mac > 0.999_999, "mode {}: MAC {mac}", j + 1);
        // Residual of the pencil, relative to the size of the terms.
        let x = vectors.column(j);
        let r = &kd * x - &md * x * values[j];
        assert!(
            r.norm() < 1e-9 * (&kd * x).norm(),
            "mode {} residual",
            j + 1
        );
    }
    // The clamped beam's first eigenvalue, (4.7300 / L)^4 EI / (rho A) with L = EI = rho A
    // = 1, approached from above by the Hermite mesh: the leading eigenvalue error of
    // cubic elements is (k h)^4 / 720 with k h = 4.73 / 30 (8.6e-7).
    let beta = 4.730_040_744_862_704_f64;
    let err = values[0] / beta.powi(4) - 1.0;
    let leading = (beta / 30.0).powi(4) / 720.0;
    assert!(
        err > 0.0 && err <= leading,
        "clamped lambda1 error {err:e} vs {leading:e}"
    );
}

#[test]
fn counts_below_a_shift_match_the_dense_spectrum() {
    let (k, m) = beam_pencil(12, 0.1);
    let (reference, _) = dense_reference(&k.to_dense(), &m.to_dense());
    for sigma in [1.0, 1e3, 1e5, 1e7, 1e9] {
        let expected = reference.iter().filter(|&&l| l < sigma).count();
        assert_eq!(count_below(&k, &m, sigma), expected, "sigma {sigma}");
    }
}

#[test]
fn repeated_eigenvalues_get_an_m_orthonormal_basis() {
    // Two identical uncoupled beams side by side: every eigenvalue is double.
    let (k1, m1) = beam_pencil(10, 0.1);
    let n1 = k1.n();
    let (mut k, mut m) = (SymBand::zeros(2 * n1, 3), SymBand::zeros(2 * n1, 3));
    for copy in 0..2 {
        for i in 0..n1 {
            for j in i.saturating_sub(3)..=i {
                k.add(copy * n1 + i, copy * n1 + j, k1.get(i, j));
                m.add(copy * n1 + i, copy * n1 + j, m1.get(i, j));
            }
        }
    }
    let (values, vectors) = lowest_eigenpairs(&k, &m, 6).unwrap();
    for pair in values.chunks(2) {
        assert!((pair[0] - pair[1]).abs() < 1e-10 * pair[1], "{pair:?}");
    }
    let md = m.to_dense();
    let gram = vectors.transpose() * &md * &vectors;
    assert!((gram - DMatrix::identity(6, 6)).amax() < 1e-10);
}

#[test]
fn massless_dofs_have_no_finite_eigenvalue() {
    // Masses on the translations only (rotations massless): the pencil has as many finite
    // eigenvalues as masses, equal to those of the statically condensed system.
    let (k, _) = beam_pencil(8, 0.125);
    let n = k.n();
    let mut m = SymBand::zeros(n, 0);
    for i in (0..n).step_by(2) {
        m.add(i, i, 0.125);
    }
    let kd = k.to_dense();
    let (w, t): (Vec<usize>, Vec<usize>) =
        ((0..n).step_by(2).collect(), (1..n).step_by(2).collect());
    let k_tt = kd.select_rows(&t).select_columns(&t);
    let k_tw = kd.select_rows(&t).select_columns(&w);
    let k_ww = kd.select_rows(&w).select_columns(&w);
    let condensed = &k_ww - k_tw.transpose() * k_tt.cholesky().unwrap().solve(&k_tw);
    let masses = DMatrix::from_diagonal_element(w.len(), w.len(), 0.125);
    let (reference, _) = dense_reference(&((&condensed + condensed.transpose()) * 0.5), &masses);
    let (values, _) = lowest_eigenpairs(&k, &m, w.len()).unwrap();
    for (j, (v, r)) in values.iter().zip(&reference).enumerate() {
        assert!((v - r).abs() < 1e-11 * r, "mode {}: {v} vs {r}", j + 1);
    }
    assert_eq!(
        lowest_eigenpairs(&k, &m, w.len() + 1).err(),
        Some(EigenError::TooFewModes {
            wanted: w.len() + 1,
            available: w.len()
        })
    );
}

#[test]
fn a_stiffness_that_is_not_positive_definite_is_refused() {
    // A free-free element: two rigid-body modes, K singular.
    let mut k = SymBand::zeros(2, 1);
    k.add(0, 0, 1.0);
    k.add(1, 1, 1.0);
    k.add(1, 0, -1.0);
    let mut m = SymBand::zeros(2, 0);
    m.add(0, 0, 1.0);
    m.add(1, 1, 1.0);
    assert_eq!(
        lowest_eigenpairs(&k, &m, 1).err(),
        Some(EigenError::StiffnessNotPositiveDefinite)
    );
}
