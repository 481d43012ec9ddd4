//! The linear algebra a bridge time step needs, behind one small interface: matrix-vector
//! products with M and C, and solves with the effective matrix factorized once.
//! Dense (nalgebra Cholesky), banded/sparse (nalgebra-sparse CSC Cholesky, which keeps a
//! banded matrix banded in natural order) or diagonal (modal). The factorization is the
//! library's; the per-step kernels on sparse storage (matrix-vector product, the two
//! triangular solves) are short loops over the CSC arrays here, because the library's
//! generic sparse-times-dense routines cost several times more for a single vector and
//! they run every time step.

use nalgebra::{DMatrix, DVector};
use nalgebra_sparse::{factorization::CscCholesky, CooMatrix, CscMatrix};

use crate::error::{Error, Result};
use crate::physics::linalg::{half_bandwidth, BandCholesky, BandMatrix, SymBand, SymMatrix};

/// Widest half-bandwidth stored as a band: every beam model here is far below it (3 for
/// Hermite elements); wider sparse matrices keep the CSC form.
const MAX_BAND: usize = 32;

/// How a model's matrices are stored and solved.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Storage {
    /// Dense matrices, dense Cholesky factorized once.
    #[default]
    Dense,
    /// Sparse: a band matrix (half-bandwidth up to 32) in band form ([`super::band`]),
    /// else compressed sparse columns; either way a banded matrix factorizes in O(n) and
    /// solves in O(n).
    Sparse,
}

/// A matrix stored the way its structure deserves.
#[derive(Debug, Clone)]
pub enum Operator {
    Dense(DMatrix<f64>),
    Band(BandMatrix),
    Sparse(Csc),
    Diagonal(DVector<f64>),
}

impl Operator {
    /// Picks the storage: diagonal when the matrix is diagonal, else as asked.
    pub fn new(matrix: &SymMatrix, storage: Storage) -> Self {
        if matrix.is_diagonal() {
            return Operator::Diagonal(matrix.diagonal());
        }
        match (storage, matrix) {
            (Storage::Dense, _) => Operator::Dense(matrix.to_dense()),
            (Storage::Sparse, SymMatrix::Band(b)) if b.half_bandwidth() <= MAX_BAND => {
                Operator::Band(BandMatrix::from_band(b))
            }
            (Storage::Sparse, SymMatrix::Dense(m)) if half_bandwidth(m) <= MAX_BAND => {
                Operator::Band(BandMatrix::from_symmetric(m))
            }
            (Storage::Sparse, _) => Operator::Sparse(Csc::from(&to_csc(&matrix.to_dense()))),
        }
    }

    /// `y += alpha * A x`, without allocation.
    pub fn mul_add(&self, alpha: f64, x: &DVector<f64>, y: &mut DVector<f64>) {
        match self {
            Operator::Dense(a) => y.gemv(alpha, a, x, 1.0),
            Operator::Band(a) => a.mul_add(alpha, x.as_slice(), y.as_mut_slice()),
            Operator::Sparse(a) => a.mul_add(alpha, x.as_slice(), y.as_mut_slice()),
            Operator::Diagonal(d) => y.zip_zip_apply(d, x, |yi, di, xi| *yi += alpha * di * xi),
        }
    }
}

/// A factorized symmetric positive definite matrix.
pub enum Factor {
    Dense(nalgebra::linalg::Cholesky<f64, nalgebra::Dyn>),
    /// Band Cholesky factor (half-bandwidth up to 32).
    Band(BandCholesky),
    /// The Cholesky factor L (lower triangular, diagonal first in each column).
    Sparse(Csc),
    Diagonal(DVector<f64>),
}

impl Factor {
    /// Factorizes `matrix` once, in the storage its structure deserves.
    pub fn new(matrix: &SymMatrix, storage: Storage, what: &str) -> Result<Self> {
        let failed = |reason: &str| Error::Factorization {
            what: what.to_string(),
            reason: reason.to_string(),
        };
        if matrix.is_diagonal() {
            let d = matrix.diagonal();
            if d.iter().any(|&v| !(v > 0.0 && v.is_finite())) {
                return Err(failed("non-positive diagonal"));
            }
            return Ok(Factor::Diagonal(d.map(|v| 1.0 / v)));
        }
        let band = |b: &SymBand| {
            BandCholesky::factor(b)
                .map(Factor::Band)
                .map_err(|row| failed(&format!("not positive definite (pivot of row {row})")))
        };
        match (storage, matrix) {
            (Storage::Dense, _) => matrix
                .to_dense()
                .cholesky()
                .map(Factor::Dense)
                .ok_or_else(|| failed("not positive definite")),
            (Storage::Sparse, SymMatrix::Band(b)) if b.half_bandwidth() <= MAX_BAND => band(b),
            (Storage::Sparse, SymMatrix::Dense(m)) if half_bandwidth(m) <= MAX_BAND => {
                band(&SymBand::from_dense(m))
            }
            (Storage::Sparse, _) => CscCholesky::factor(&to_csc(&matrix.to_dense()))
                .map_err(|e| failed(&format!("{e:?}")))
                .map(|c| Csc::from(c.l()))
                .and_then(|l| match l.diagonal_leads_every_column() {
                    true => Ok(Factor::Sparse(l)),
                    false => Err(failed("factor without a leading diagonal (bug)")),
                }),
        }
    }

    /// Overwrites `b` with `A^-1 b`, without allocation.
    pub fn solve_in_place(&self, b: &mut DVector<f64>) {
        match self {
            Factor::Dense(c) => c.solve_mut(b),
            Factor::Band(l) => l.solve_in_place(b.as_mut_slice()),
            Factor::Sparse(l) => {
                l.solve_lower_in_place(b.as_mut_slice());
                l.solve_lower_transpose_in_place(b.as_mut_slice());
            }
            Factor::Diagonal(inv) => b.component_mul_assign(inv),
        }
    }
}

/// Compressed sparse columns, as plain arrays for the per-step loops.
#[derive(Debug, Clone)]
pub struct Csc {
    col_offsets: Vec<usize>,
    row_indices: Vec<usize>,
    values: Vec<f64>,
    /// 1 / first value of each column (the diagonal of a triangular factor): the solves
    /// multiply, because a division's latency would set the pace of the substitution.
    inv_first: Vec<f64>,
}

impl From<&CscMatrix<f64>> for Csc {
    fn from(m: &CscMatrix<f64>) -> Self {
        let offsets = m.col_offsets();
        let inv_first = (0..m.ncols())
            .map(|j| match offsets[j] < offsets[j + 1] {
                true => 1.0 / m.values()[offsets[j]],
                false => f64::NAN,
            })
            .collect();
        Csc {
            col_offsets: offsets.to_vec(),
            row_indices: m.row_indices().to_vec(),
            values: m.values().to_vec(),
            inv_first,
        }
    }
}

impl Csc {
    fn column(&self, j: usize) -> (&[usize], &[f64]) {
        let range = self.col_offsets[j]..self.col_offsets[j + 1];
        (&self.row_indices[range.clone()], &self.values[range])
    }

    /// Whether every column j starts with row j (what the triangular solves rely on).
    fn diagonal_leads_every_column(&self) -> bool {
        (0..self.col_offsets.len() - 1).all(|j| self.column(j).0.first() == Some(&j))
    }

    /// `y += alpha * A x`.
    fn mul_add(&self, alpha: f64, x: &[f64], y: &mut [f64]) {
        for (j, &xj) in x.iter().enumerate() {
            let (rows, values) = self.column(j);
            let ax = alpha * xj;
            for (&i, &v) in rows.iter().zip(values) {
                y[i] += v * ax;
            }
        }
    }

    /// `b <- L^-1 b` for lower-triangular L whose columns start with the diagonal.
    fn solve_lower_in_place(&self, b: &mut [f64]) {
        for j in 0..b.len() {
            let (rows, values) = self.column(j);
            let xj = b[j] * self.inv_first[j];
            b[j] = xj;
            for (&i, &v) in rows[1..].iter().zip(&values[1..]) {
                b[i] -= v * xj;
            }
        }
    }

    /// `b <- L^-T b`: column j of L is row j of L^T.
    fn solve_lower_transpose_in_place(&self, b: &mut [f64]) {
        for j in (0..b.len()).rev() {
            let (rows, values) = self.column(j);
            let mut sum = b[j];
            for (&i, &v) in rows[1..].iter().zip(&values[1..]) {
                sum -= v * b[i];
            }
            b[j] = sum * self.inv_first[j];
        }
    }
}

/// Dense to CSC, dropping exact zeros.
pub fn to_csc(m: &DMatrix<f64>) -> CscMatrix<f64> {
    let mut coo = CooMatrix::new(m.nrows(), m.ncols());
    for j in 0..m.ncols() {
        for i in 0..m.nrows() {
            let v = m[(i, j)];
            if v != 0.0 {
                coo.push(i, j, v);
            }
        }
    }
    CscMatrix::from(&coo)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn spd(n: usize) -> DMatrix<f64> {
        // Tridiagonal SPD (a 1-D Laplacian plus identity): banded, like FE matrices.
        DMatrix::from_fn(n, n, |i, j| match i.abs_diff(j) {
            0 => 3.0,
            1 => -1.0,
            _ => 0.0,
        })
    }

    #[test]
    fn dense_sparse_and_diagonal_solves_agree() {
        let a = spd(12);
        let b = DVector::from_fn(12, |i, _| (i as f64).sin());
        let exact = a.clone().lu().solve(&b).unwrap();
        for storage in [Storage::Dense, Storage::Sparse] {
            let f = Factor::new(&SymMatrix::from(a.clone()), storage, "test").unwrap();
            let mut x = b.clone();
            f.solve_in_place(&mut x);
            assert!((&x - &exact).norm() < 1e-12);
            let mut y = DVector::zeros(12);
            Operator::new(&SymMatrix::from(a.clone()), storage).mul_add(2.0, &x, &mut y);
            assert!((&y - &b * 2.0).norm() < 1e-12);
        }
        let d = DMatrix::from_diagonal(&DVector::from_element(3, 4.0));
        let f = Factor::new(&SymMatrix::from(d.clone()), Storage::Dense, "diag").unwrap();
        let mut x = DVector::from_element(3, 8.0);
        f.solve_in_place(&mut x);
        assert_eq!(x, DVector::from_element(3, 2.0));
    }

    #[test]
    fn banded_solves_match_dense_ones() {
        // Bandwidth 5 with 2 DOFs per node, like a Hermite FE matrix; SPD by dominance.
        let n = 40;
        let a = DMatrix::from_fn(n, n, |i, j| match i.abs_diff(j) {
            0 => 20.0 + i as f64,
            d @ 1..=5 => ((i * 7 + j * 3) % 5) as f64 - 2.0 + 0.1 * d as f64,
            _ => 0.0,
        });
        let a = (&a + a.transpose()) * 0.5;
        let b = DVector::from_fn(n, |i, _| (0.3 * i as f64).cos());
        let exact = a.clone().lu().solve(&b).unwrap();
        let mut x = b.clone();
        Factor::new(&SymMatrix::from(a.clone()), Storage::Sparse, "band")
            .unwrap()
            .solve_in_place(&mut x);
        assert!((&x - &exact).norm() < 1e-12 * exact.norm());
        let mut y = DVector::from_element(n, 1.0);
        Operator::new(&SymMatrix::from(a.clone()), Storage::Sparse).mul_add(-0.5, &b, &mut y);
        let expected = DVector::from_element(n, 1.0) - &a * &b * 0.5;
        assert!((&y - expected).norm() < 1e-12 * y.norm());
    }

    #[test]
    fn wide_sparse_matrices_keep_the_csc_path_and_agree_with_dense() {
        // Tridiagonal plus a far corner coupling: half-bandwidth n - 1 > MAX_BAND.
        let n = 50;
        let mut a = spd(n);
        a[(0, n - 1)] = 0.5;
        a[(n - 1, 0)] = 0.5;
        let f = Factor::new(&SymMatrix::from(a.clone()), Storage::Sparse, "wide").unwrap();
        assert!(matches!(f, Factor::Sparse(_)));
        let b = DVector::from_fn(n, |i, _| (i as f64).sin());
        let mut x = b.clone();
        f.solve_in_place(&mut x);
        let exact = a.clone().lu().solve(&b).unwrap();
        assert!((&x - &exact).norm() < 1e-12 * exact.norm());
        let op = Operator::new(&SymMatrix::from(a.clone()), Storage::Sparse);
        assert!(matches!(op, Operator::Sparse(_)));
        let mut y = DVector::zeros(n);
        op.mul_add(1.0, &x, &mut y);
        assert!((&y - &b).norm() < 1e-12 * b.norm());
    }

    #[test]
    fn indefinite_matrix_is_reported() {
        let mut a = spd(4);
        a[(2, 2)] = -5.0;
        for storage in [Storage::Dense, Storage::Sparse] {
            assert!(Factor::new(&SymMatrix::from(a.clone()), storage, "K_eff").is_err());
        }
    }
}

/// Panel width of the blocked LU: systems up to this size (every contact system) are
/// factorized column by column; larger ones (the paper's direct method solves the whole
/// coupled system) update the trailing block with one matrix product per panel, which
/// keeps the O(n^3) work in cache-friendly products instead of n rank-one passes over
/// the whole matrix (10x faster at 1000 unknowns).
const LU_PANEL: usize = 32;

/// Dense LU with partial pivoting for the small, nonsymmetric contact systems (a few
/// unknowns per vehicle) and the paper's direct method, on preallocated column-major
/// storage: solving a system of the size seen before does not allocate. Written out
/// rather than taken from a crate: nalgebra's LU allocates per factorization, and the crate
/// that did it in place cost a minute of every clean build.
pub struct SmallLu {
    /// The leading `n x n` block of the system; after `solve` it holds L (unit diagonal,
    /// below) and U (on and above the diagonal).
    matrix: DMatrix<f64>,
    /// Copies of the panel's L21 and U12 blocks for the trailing update (the product
    /// reads them while it writes the trailing block of `matrix`).
    l21: DMatrix<f64>,
    u12: DMatrix<f64>,
    capacity: usize,
}

impl SmallLu {
    /// Storage for systems up to `capacity` unknowns (it grows if a larger one comes).
    pub fn with_capacity(capacity: usize) -> Self {
        let n = capacity.max(1);
        let blocked = if n > LU_PANEL { n } else { 0 };
        SmallLu {
            matrix: DMatrix::zeros(n, n),
            l21: DMatrix::zeros(blocked, LU_PANEL),
            u12: DMatrix::zeros(LU_PANEL, blocked),
            capacity: n,
        }
    }

    /// Solves `A x = b` for the leading `n x n` block given by `a(i, j)`; `b` is overwritten
    /// by x. A singular system gives non-finite values, which the caller's checks report.
    pub fn solve(&mut self, n: usize, a: impl Fn(usize, usize) -> f64, b: &mut [f64]) {
        if n == 0 {
            return;
        }
        if n > self.capacity {
            *self = SmallLu::with_capacity(n.next_power_of_two());
        }
        let m = &mut self.matrix;
        for j in 0..n {
            for i in 0..n {
                m[(i, j)] = a(i, j);
            }
        }
        for k0 in (0..n).step_by(LU_PANEL) {
            let k1 = (k0 + LU_PANEL).min(n);
            factor_panel(&mut self.matrix, n, k0, k1, b);
            if k1 < n {
                self.update_trailing(n, k0, k1);
            }
        }
        substitute(&self.matrix, n, b);
    }

    /// After the panel of columns `k0..k1`: U12 = L11^-1 A12, then A22 -= L21 U12.
    fn update_trailing(&mut self, n: usize, k0: usize, k1: usize) {
        let m = &mut self.matrix;
        let (width, rest) = (k1 - k0, n - k1);
        for j in k1..n {
            for k in k0..k1 {
                let u_kj = m[(k, j)];
                for i in k + 1..k1 {
                    m[(i, j)] -= m[(i, k)] * u_kj;
                }
            }
        }
        let mut l21 = self.l21.view_mut((0, 0), (rest, width));
        l21.copy_from(&m.view((k1, k0), (rest, width)));
        let mut u12 = self.u12.view_mut((0, 0), (width, rest));
        u12.copy_from(&m.view((k0, k1), (width, rest)));
        m.view_mut((k1, k1), (rest, rest))
            .gemm(-1.0, &l21, &u12, 1.0);
    }
}

/// Unblocked LU of columns `k0..k1` (rows `k0..n`) with partial pivoting: the largest
/// magnitude at or below the diagonal; whole rows of the matrix and `b` are exchanged.
fn factor_panel(m: &mut DMatrix<f64>, n: usize, k0: usize, k1: usize, b: &mut [f64]) {
    for k in k0..k1 {
        let pivot = (k..n)
            .max_by(|&p, &q| m[(p, k)].abs().total_cmp(&m[(q, k)].abs()))
            .unwrap_or(k);
        if pivot != k {
            for j in 0..n {
                m.swap((k, j), (pivot, j));
            }
            b.swap(k, pivot);
        }
        let inv_pivot = 1.0 / m[(k, k)];
        for i in k + 1..n {
            m[(i, k)] *= inv_pivot;
        }
        for j in k + 1..k1 {
            let u_kj = m[(k, j)];
            if u_kj != 0.0 {
                for i in k + 1..n {
                    m[(i, j)] -= m[(i, k)] * u_kj;
                }
            }
        }
    }
}

/// `L y = P b` (unit diagonal), then `U x = y`, in place in `b`.
fn substitute(m: &DMatrix<f64>, n: usize, b: &mut [f64]) {
    for k in 0..n {
        let y_k = b[k];
        for i in k + 1..n {
            b[i] -= m[(i, k)] * y_k;
        }
    }
    for k in (0..n).rev() {
        b[k] /= m[(k, k)];
        let x_k = b[k];
        for i in 0..k {
            b[i] -= m[(i, k)] * x_k;
        }
    }
}

#[cfg(test)]
mod small_lu_tests {
    use super::SmallLu;

    #[test]
    fn solves_a_nonsymmetric_system_and_grows() {
        let a = [[4.0, 1.0, 0.5], [2.0, 5.0, 1.0], [0.0, 3.0, 6.0]];
        let x = [1.0, -2.0, 0.5];
        let mut b: Vec<f64> = (0..3)
            .map(|i| (0..3).map(|j| a[i][j] * x[j]).sum())
            .collect();
        let mut lu = SmallLu::with_capacity(2);
        lu.solve(3, |i, j| a[i][j], &mut b);
        for i in 0..3 {
            assert!((b[i] - x[i]).abs() < 1e-13);
        }
    }

    /// A zero leading entry: without the row exchange the first pivot would divide by zero.
    /// The reused storage must not leak the previous, larger system into the next one.
    #[test]
    fn pivots_and_reuses_its_storage() {
        let a = [[0.0, 2.0, 1.0], [1.0, 1.0, 0.0], [3.0, 0.0, 1.0]];
        let x = [2.0, -1.0, 4.0];
        let mut lu = SmallLu::with_capacity(4);
        for _ in 0..2 {
            let mut b: Vec<f64> = (0..3)
                .map(|i| (0..3).map(|j| a[i][j] * x[j]).sum())
                .collect();
            lu.solve(3, |i, j| a[i][j], &mut b);
            for i in 0..3 {
                assert!((b[i] - x[i]).abs() < 1e-13, "{b:?}");
            }
            let mut c = [5.0, 6.0];
            lu.solve(2, |i, j| [[2.0, 0.0], [0.0, 3.0]][i][j], &mut c);
            assert_eq!(c, [2.5, 2.0]);
        }
    }

    /// Past one panel the trailing block is updated by matrix products: a diagonally weak,
    /// nonsymmetric system of 100 unknowns (pivoting needed) against its known solution.
    #[test]
    fn blocked_factorization_solves_a_large_system() {
        let n = 100;
        let a = |i: usize, j: usize| {
            let (fi, fj) = (i as f64, j as f64);
            (0.37 * fi + 1.13 * fj).sin() + if i == (j + 7) % n { 3.0 } else { 0.0 }
        };
        let x: Vec<f64> = (0..n).map(|i| 1.0 + (i % 5) as f64).collect();
        let mut b: Vec<f64> = (0..n)
            .map(|i| (0..n).map(|j| a(i, j) * x[j]).sum())
            .collect();
        let mut lu = SmallLu::with_capacity(8);
        lu.solve(n, a, &mut b);
        let error = b
            .iter()
            .zip(&x)
            .map(|(u, v)| (u - v).abs())
            .fold(0.0, f64::max);
        assert!(error < 1e-10, "largest error {error:e}");
    }
}
