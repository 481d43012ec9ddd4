//! A symmetric matrix in the storage its structure deserves: dense (the lumped-mass
//! model's stiffness, which couples every mass to every other), band (finite elements:
//! O(n b) memory) or diagonal (lumped and modal masses, modal stiffness). Bridge models
//! are built and kept in it; the solver picks its per-step kernels from it.

use nalgebra::{DMatrix, DVector};

use super::band::SymBand;

/// A symmetric matrix, dense, banded or diagonal.
#[derive(Debug, Clone, PartialEq)]
pub enum SymMatrix {
    Dense(DMatrix<f64>),
    Band(SymBand),
    Diagonal(DVector<f64>),
}

impl From<DMatrix<f64>> for SymMatrix {
    fn from(m: DMatrix<f64>) -> Self {
        SymMatrix::Dense(m)
    }
}

impl SymMatrix {
    /// Order of the matrix.
    pub fn n(&self) -> usize {
        match self {
            SymMatrix::Dense(m) => m.nrows(),
            SymMatrix::Band(b) => b.n(),
            SymMatrix::Diagonal(d) => d.len(),
        }
    }

    /// Entry `(i, j)`.
    pub fn get(&self, i: usize, j: usize) -> f64 {
        match self {
            SymMatrix::Dense(m) => m[(i, j)],
            SymMatrix::Band(b) => b.get(i, j),
            SymMatrix::Diagonal(d) => match i == j {
                true => d[i],
                false => 0.0,
            },
        }
    }

    /// The dense matrix (O(n^2) memory: small models, tests and the paper's baseline).
    pub fn to_dense(&self) -> DMatrix<f64> {
        match self {
            SymMatrix::Dense(m) => m.clone(),
            SymMatrix::Band(b) => b.to_dense(),
            SymMatrix::Diagonal(d) => DMatrix::from_diagonal(d),
        }
    }

    /// Whether every entry off the diagonal is zero.
    pub fn is_diagonal(&self) -> bool {
        match self {
            SymMatrix::Dense(m) => m
                .column_iter()
                .enumerate()
                .all(|(j, col)| col.iter().enumerate().all(|(i, &v)| i == j || v == 0.0)),
            SymMatrix::Band(b) => b.is_diagonal(),
            SymMatrix::Diagonal(_) => true,
        }
    }

    /// The diagonal.
    pub fn diagonal(&self) -> DVector<f64> {
        match self {
            SymMatrix::Dense(m) => m.diagonal(),
            SymMatrix::Band(b) => DVector::from_vec(b.diagonal()),
            SymMatrix::Diagonal(d) => d.clone(),
        }
    }

    /// `y += alpha A x`.
    pub fn mul_add(&self, alpha: f64, x: &DVector<f64>, y: &mut DVector<f64>) {
        match self {
            SymMatrix::Dense(m) => y.gemv(alpha, m, x, 1.0),
            SymMatrix::Band(b) => b.mul_add(alpha, x.as_slice(), y.as_mut_slice()),
            SymMatrix::Diagonal(d) => y.zip_zip_apply(d, x, |yi, di, xi| *yi += alpha * di * xi),
        }
    }

    /// `A x`.
    pub fn mul(&self, x: &DVector<f64>) -> DVector<f64> {
        let mut y = DVector::zeros(self.n());
        self.mul_add(1.0, x, &mut y);
        y
    }

    /// `x^T A x`.
    pub fn quadratic_form(&self, x: &DVector<f64>) -> f64 {
        x.dot(&self.mul(x))
    }

    /// `sum_k c_k A_k`, entry by entry in the order given (so a banded or diagonal sum
    /// rounds exactly as the dense sum of the same matrices), in the widest storage of the
    /// terms: dense if any term is dense, else band, else diagonal.
    pub fn linear_combination(terms: &[(f64, &SymMatrix)]) -> SymMatrix {
        let any = |f: fn(&SymMatrix) -> bool| terms.iter().any(|(_, m)| f(m));
        if any(|m| matches!(m, SymMatrix::Dense(_))) {
            let mut sum = terms[0].1.to_dense() * terms[0].0;
            for (c, m) in &terms[1..] {
                sum += m.to_dense() * *c;
            }
            return SymMatrix::Dense(sum);
        }
        if any(|m| matches!(m, SymMatrix::Band(_))) {
            let bands: Vec<SymBand> = terms.iter().map(|(_, m)| m.to_band()).collect();
            let scaled: Vec<(f64, &SymBand)> = terms
                .iter()
                .zip(&bands)
                .map(|((c, _), b)| (*c, b))
                .collect();
            return SymMatrix::Band(SymBand::linear_combination(&scaled));
        }
        let mut sum = terms[0].1.diagonal() * terms[0].0;
        for (c, m) in &terms[1..] {
            sum += m.diagonal() * *c;
        }
        SymMatrix::Diagonal(sum)
    }

    /// The band form (a dense matrix as wide as its nonzeros, a diagonal of width 0).
    pub fn to_band(&self) -> SymBand {
        match self {
            SymMatrix::Dense(m) => SymBand::from_dense(m),
            SymMatrix::Band(b) => b.clone(),
            SymMatrix::Diagonal(d) => {
                let mut band = SymBand::zeros(d.len(), 0);
                for (i, &v) in d.iter().enumerate() {
                    band.add(i, i, v);
                }
                band
            }
        }
    }

    /// The modal assurance criterion of two vectors in the inner product of this
    /// (mass) matrix: `(x^T A y)^2 / ((x^T A x)(y^T A y))`, 1 for parallel shapes and
    /// insensitive to their signs and scales.
    pub fn modal_assurance(&self, x: &DVector<f64>, y: &DVector<f64>) -> f64 {
        let xy = x.dot(&self.mul(y));
        xy * xy / (self.quadratic_form(x) * self.quadratic_form(y))
    }

    /// Bytes the stored values take.
    pub fn stored_bytes(&self) -> usize {
        let values = match self {
            SymMatrix::Dense(m) => m.len(),
            SymMatrix::Band(b) => b.lower_rows().len(),
            SymMatrix::Diagonal(d) => d.len(),
        };
        values * std::mem::size_of::<f64>()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_storage_gives_the_same_products_and_sums() {
        let dense = DMatrix::from_fn(6, 6, |i, j| match i.abs_diff(j) {
            0 => 4.0 + i as f64,
            1 => -1.0,
            _ => 0.0,
        });
        let band = SymMatrix::Band(SymBand::from_dense(&dense));
        let diag = SymMatrix::Diagonal(DVector::from_fn(6, |i, _| 1.0 + i as f64));
        let x = DVector::from_fn(6, |i, _| (i as f64).cos());
        let full = SymMatrix::Dense(dense.clone());
        assert!((band.mul(&x) - full.mul(&x)).norm() < 1e-14);
        assert_eq!(band.to_dense(), dense);
        // Band + diagonal stays a band, and equals the dense sum to the last bit.
        let sum = SymMatrix::linear_combination(&[(1.0, &band), (0.5, &diag)]);
        assert!(matches!(sum, SymMatrix::Band(_)));
        assert_eq!(sum.to_dense(), &dense + diag.to_dense() * 0.5);
        let dense_sum = SymMatrix::linear_combination(&[(1.0, &full), (0.5, &diag)]);
        assert!(matches!(dense_sum, SymMatrix::Dense(_)));
        assert_eq!(dense_sum.to_dense(), sum.to_dense());
        let diag_sum = SymMatrix::linear_combination(&[(2.0, &diag), (1.0, &diag)]);
        assert!(matches!(diag_sum, SymMatrix::Diagonal(_)) && diag_sum.is_diagonal());
        assert!(!band.is_diagonal());
        assert_eq!(band.stored_bytes(), 6 * 2 * 8);
    }
}
