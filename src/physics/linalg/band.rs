//! Symmetric band matrices: the mass, damping and effective stiffness of a finite-element
//! beam couple each node only to its neighbours (half-bandwidth 3 with two DOFs per node).
//!
//! [`SymBand`] is the storage a model is built in: the lower band by rows, `b + 1` values
//! per row (`row[i][k]` is entry `(i, i - k)`, zero-padded before column 0), O(n b) memory
//! where a dense matrix would take O(n^2). [`BandMatrix`] and [`BandCholesky`] are the
//! forms the per-step kernels run on: fixed-length loops over contiguous memory with no
//! index arrays, for the matrix-vector product and the two triangular solves with the
//! Cholesky factor computed once in band form (`L L^T`, Golub and Van Loan, Matrix
//! Computations, 4th ed., algorithm 4.3.5: the factor of a band matrix keeps its band,
//! so the cost is O(n b^2) once and O(n b) per solve). The transposed solve reads a
//! second copy of the factor stored by columns, so that it too runs forward through
//! memory.

use crate::base::dot::dot;
use nalgebra::DMatrix;

/// Half-bandwidth of a square matrix: the largest `|i - j|` with a nonzero entry.
pub fn half_bandwidth(m: &DMatrix<f64>) -> usize {
    let mut b = 0;
    for j in 0..m.ncols() {
        for i in 0..m.nrows() {
            if m[(i, j)] != 0.0 {
                b = b.max(i.abs_diff(j));
            }
        }
    }
    b
}

/// A symmetric band matrix stored as its lower band by rows: entry `(i, i - k)` at
/// `i * (b + 1) + k` for `k = 0..=b` (slots before column 0 stay zero).
#[derive(Debug, Clone, PartialEq)]
pub struct SymBand {
    n: usize,
    b: usize,
    rows: Vec<f64>,
}

impl SymBand {
    /// The zero matrix of order `n` with room for half-bandwidth `b`.
    pub fn zeros(n: usize, b: usize) -> Self {
        SymBand {
            n,
            b,
            rows: vec![0.0; n * (b + 1)],
        }
    }

    /// The band of symmetric `m` (its lower triangle is read), as narrow as its nonzeros.
    pub fn from_dense(m: &DMatrix<f64>) -> Self {
        let (n, b) = (m.nrows(), half_bandwidth(m));
        let mut band = SymBand::zeros(n, b);
        for i in 0..n {
            for k in 0..=b.min(i) {
                band.rows[i * (b + 1) + k] = m[(i, i - k)];
            }
        }
        band
    }

    /// Order of the matrix.
    pub fn n(&self) -> usize {
        self.n
    }

    /// Half-bandwidth the storage has room for.
    pub fn half_bandwidth(&self) -> usize {
        self.b
    }

    /// Entry `(i, j)` (zero outside the band).
    pub fn get(&self, i: usize, j: usize) -> f64 {
        let (r, c) = if j <= i { (i, j) } else { (j, i) };
        match r - c <= self.b {
            true => self.rows[r * (self.b + 1) + r - c],
            false => 0.0,
        }
    }

    /// Adds `value` to entries `(i, j)` and `(j, i)`; `|i - j|` must lie within the band.
    pub fn add(&mut self, i: usize, j: usize, value: f64) {
        let (r, c) = if j <= i { (i, j) } else { (j, i) };
        assert!(
            r - c <= self.b,
            "entry ({i}, {j}) outside half-bandwidth {}",
            self.b
        );
        self.rows[r * (self.b + 1) + r - c] += value;
    }

    /// The same matrix in the narrowest band that holds its nonzeros.
    pub fn trimmed(&self) -> SymBand {
        let w = self.b + 1;
        let b = (0..self.n)
            .flat_map(|i| (1..=self.b.min(i)).map(move |k| (i, k)))
            .filter(|&(i, k)| self.rows[i * w + k] != 0.0)
            .map(|(_, k)| k)
            .max()
            .unwrap_or(0);
        let mut out = SymBand::zeros(self.n, b);
        for i in 0..self.n {
            for k in 0..=b.min(i) {
                out.rows[i * (b + 1) + k] = self.rows[i * w + k];
            }
        }
        out
    }

    /// The lower band, row by row (`b + 1` values per row).
    pub fn lower_rows(&self) -> &[f64] {
        &self.rows
    }

    /// `sum_k c_k A_k` over matrices of one order, entry by entry in the order given (so
    /// that `K + a0 M + a1 C` rounds as the same sum of dense matrices does); the result
    /// has the widest band of the terms.
    pub fn linear_combination(terms: &[(f64, &SymBand)]) -> SymBand {
        let n = terms.first().map_or(0, |(_, m)| m.n);
        let b = terms.iter().map(|(_, m)| m.b).max().unwrap_or(0);
        let mut sum = SymBand::zeros(n, b);
        for (t, &(c, m)) in terms.iter().enumerate() {
            assert_eq!(m.n, n, "band matrices of different orders");
            for i in 0..n {
                for k in 0..=m.b.min(i) {
                    let slot = &mut sum.rows[i * (b + 1) + k];
                    let term = c * m.rows[i * (m.b + 1) + k];
                    *slot = if t == 0 { term } else { *slot + term };
                }
            }
        }
        sum
    }

    /// The dense matrix (tests, the paper's per-step baseline, small models).
    pub fn to_dense(&self) -> DMatrix<f64> {
        DMatrix::from_fn(self.n, self.n, |i, j| self.get(i, j))
    }

    /// `y += alpha A x` (set-up and diagnostics; the time loop uses [`BandMatrix`]).
    pub fn mul_add(&self, alpha: f64, x: &[f64], y: &mut [f64]) {
        let w = self.b + 1;
        for i in 0..self.n {
            let row = &self.rows[i * w..(i + 1) * w];
            y[i] += alpha * row[0] * x[i];
            for k in 1..=self.b.min(i) {
                y[i] += alpha * row[k] * x[i - k];
                y[i - k] += alpha * row[k] * x[i];
            }
        }
    }

    /// Whether every entry off the diagonal is zero.
    pub fn is_diagonal(&self) -> bool {
        let w = self.b + 1;
        (0..self.n).all(|i| self.rows[i * w + 1..(i + 1) * w].iter().all(|&v| v == 0.0))
    }

    /// The diagonal.
    pub fn diagonal(&self) -> Vec<f64> {
        (0..self.n).map(|i| self.rows[i * (self.b + 1)]).collect()
    }
}

/// A symmetric band matrix for `y += alpha A x`, stored as full band rows (`2 b + 1`
/// values, entry `(i, i + c - b)` at `c`): each output is a dot product over contiguous
/// memory, with no scattered updates that would chain one row to the next.
#[derive(Debug, Clone)]
pub struct BandMatrix {
    n: usize,
    b: usize,
    rows: Vec<f64>,
}

impl BandMatrix {
    /// The full rows of `band`.
    pub fn from_band(band: &SymBand) -> Self {
        let (n, b) = (band.n, band.b);
        let w = 2 * b + 1;
        let mut rows = vec![0.0; n * w];
        for i in 0..n {
            for j in i.saturating_sub(b)..=(i + b).min(n - 1) {
                rows[i * w + j + b - i] = band.get(i, j);
            }
        }
        BandMatrix { n, b, rows }
    }

    /// The band of symmetric `m` (the lower triangle is read, the upper taken equal).
    pub fn from_symmetric(m: &DMatrix<f64>) -> Self {
        Self::from_band(&SymBand::from_dense(m))
    }

    /// `y += alpha A x`.
    pub fn mul_add(&self, alpha: f64, x: &[f64], y: &mut [f64]) {
        match self.b {
            // Hermite beam elements: two DOFs per node, neighbours only.
            3 => self.mul_add_fixed::<7>(alpha, x, y),
            1 => self.mul_add_fixed::<3>(alpha, x, y),
            _ => self.mul_add_rows(alpha, x, y, 0..self.n),
        }
    }

    /// Rows `range` of `y += alpha A x`, clipping the band at the matrix edges.
    fn mul_add_rows(&self, alpha: f64, x: &[f64], y: &mut [f64], range: std::ops::Range<usize>) {
        let (n, b, w) = (self.n, self.b, 2 * self.b + 1);
        for i in range {
            let lo = i.saturating_sub(b);
            let hi = (i + b).min(n - 1);
            let row = &self.rows[i * w + lo + b - i..=i * w + hi + b - i];
            y[i] += alpha * dot(row, &x[lo..=hi]);
        }
    }

    /// The product with the band width `W = 2 b + 1` known at compile time: the interior
    /// rows become straight-line code; the `b` rows at each edge take the general path.
    fn mul_add_fixed<const W: usize>(&self, alpha: f64, x: &[f64], y: &mut [f64]) {
        let (n, b) = (self.n, self.b);
        if n < W {
            return self.mul_add_rows(alpha, x, y, 0..n);
        }
        self.mul_add_rows(alpha, x, y, 0..b);
        for i in b..n - b {
            let row: &[f64; W] = self.rows[i * W..(i + 1) * W].try_into().expect("W");
            let xs: &[f64; W] = x[i - b..i - b + W].try_into().expect("W");
            y[i] += alpha * dot(row, xs);
        }
        self.mul_add_rows(alpha, x, y, n - b..n);
    }
}

/// The Cholesky factor `L` of a symmetric positive definite band matrix, stored for the
/// substitutions' critical path: each row is divided by its diagonal beforehand, and the
/// sums run from the farthest neighbour to the nearest, so that the value just computed
/// enters last, through a single multiply-add (the substitution is a chain of dependent
/// rows: its speed is the latency of that chain, not the number of operations).
#[derive(Debug, Clone)]
pub struct BandCholesky {
    n: usize,
    b: usize,
    /// Row i: `L[i][i - k] / L[i][i]` at `k = 1..=b` (slot 0 unused).
    lower: Vec<f64>,
    /// Column j: `L[j + k][j] / L[j][j]` at `k = 1..=b` (slot 0 unused), for the
    /// transposed solve.
    upper: Vec<f64>,
    inv_diagonal: Vec<f64>,
}

impl BandCholesky {
    /// Factorizes `m`; `Err(row)` names the first row whose pivot is not positive.
    pub fn factor(m: &SymBand) -> Result<Self, usize> {
        let (n, b) = (m.n, m.b);
        let w = b + 1;
        let mut l = m.rows.clone();
        for i in 0..n {
            for k in (0..=b.min(i)).rev() {
                let j = i - k;
                // L[i][j] = (A[i][j] - sum_{c < j} L[i][c] L[j][c]) / L[j][j]
                let mut sum = l[i * w + k];
                for c in (i.saturating_sub(b))..j {
                    sum -= l[i * w + (i - c)] * l[j * w + (j - c)];
                }
                if k == 0 {
                    if !(sum > 0.0 && sum.is_finite()) {
                        return Err(i);
                    }
                    l[i * w] = sum.sqrt();
                } else {
                    l[i * w + k] = sum / l[j * w];
                }
            }
        }
        let inv_diagonal: Vec<f64> = (0..n).map(|i| 1.0 / l[i * w]).collect();
        let mut upper = vec![0.0; n * w];
        for i in 0..n {
            for k in 1..=b.min(i) {
                upper[(i - k) * w + k] = l[i * w + k] * inv_diagonal[i - k];
                l[i * w + k] *= inv_diagonal[i];
            }
        }
        Ok(BandCholesky {
            n,
            b,
            lower: l,
            upper,
            inv_diagonal,
        })
    }

    /// `x <- A^-1 x`: forward substitution with L, then backward with L^T.
    pub fn solve_in_place(&self, x: &mut [f64]) {
        if self.b == 3 {
            return self.solve_bandwidth_3(x);
        }
        let (n, b, w) = (self.n, self.b, self.b + 1);
        for i in 0..n {
            let row = &self.lower[i * w..(i + 1) * w];
            let mut sum = x[i] * self.inv_diagonal[i];
            for k in (1..=b.min(i)).rev() {
                sum -= row[k] * x[i - k];
            }
            x[i] = sum;
        }
        for i in (0..n).rev() {
            let column = &self.upper[i * w..(i + 1) * w];
            let mut sum = x[i] * self.inv_diagonal[i];
            for k in (1..=b.min(n - 1 - i)).rev() {
                sum -= column[k] * x[i + k];
            }
            x[i] = sum;
        }
    }
}

impl BandCholesky {
    /// [`BandCholesky::solve_in_place`] for half-bandwidth 3 (Hermite beam elements), with
    /// the three previous unknowns held in registers: the chain from one row to the next
    /// is then one multiply-add, not a store and a reload. Rows and columns are
    /// zero-padded beyond the matrix edges, so the first and last rows need no test.
    fn solve_bandwidth_3(&self, x: &mut [f64]) {
        let (mut p1, mut p2, mut p3) = (0.0, 0.0, 0.0);
        for (i, xi) in x.iter_mut().enumerate() {
            let r = &self.lower[4 * i..4 * i + 4];
            let v = *xi * self.inv_diagonal[i] - r[3] * p3 - r[2] * p2 - r[1] * p1;
            *xi = v;
            (p3, p2, p1) = (p2, p1, v);
        }
        let (mut p1, mut p2, mut p3) = (0.0, 0.0, 0.0);
        for (i, xi) in x.iter_mut().enumerate().rev() {
            let c = &self.upper[4 * i..4 * i + 4];
            let v = *xi * self.inv_diagonal[i] - c[3] * p3 - c[2] * p2 - c[1] * p1;
            *xi = v;
            (p3, p2, p1) = (p2, p1, v);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::DVector;

    /// Symmetric, diagonally dominant (so SPD), half-bandwidth `b`.
    fn banded_spd(n: usize, b: usize) -> DMatrix<f64> {
        let a = DMatrix::from_fn(n, n, |i, j| match i.abs_diff(j) {
            0 => 4.0 * b as f64 + 1.0 + (i % 3) as f64,
            d if d <= b => ((i * 7 + j * 3) % 5) as f64 - 2.0 + 0.1 * d as f64,
            _ => 0.0,
        });
        (&a + a.transpose()) * 0.5
    }

    #[test]
    fn band_solve_and_product_match_dense_for_several_bandwidths() {
        for (n, b) in [(1, 0), (7, 1), (40, 3), (33, 5), (12, 11)] {
            let a = banded_spd(n, b);
            assert!(half_bandwidth(&a) <= b);
            let rhs = DVector::from_fn(n, |i, _| (0.3 * i as f64).cos());
            let exact = a.clone().lu().solve(&rhs).unwrap();
            let mut x = rhs.clone();
            BandCholesky::factor(&SymBand::from_dense(&a))
                .unwrap()
                .solve_in_place(x.as_mut_slice());
            // Residual of a well-conditioned system: a few ulps times the size.
            assert!((&x - &exact).norm() < 1e-12 * exact.norm(), "n {n} b {b}");
            let mut y = DVector::from_element(n, 1.0);
            BandMatrix::from_symmetric(&a).mul_add(-0.5, rhs.as_slice(), y.as_mut_slice());
            let expected = DVector::from_element(n, 1.0) - &a * &rhs * 0.5;
            assert!((&y - expected).norm() < 1e-12 * y.norm(), "n {n} b {b}");
        }
    }

    #[test]
    fn band_storage_round_trips_and_combines_as_dense_matrices_do() {
        let (a, c) = (banded_spd(9, 2), banded_spd(9, 3));
        let (ba, bc) = (SymBand::from_dense(&a), SymBand::from_dense(&c));
        assert_eq!((ba.half_bandwidth(), bc.half_bandwidth()), (2, 3));
        assert_eq!(ba.to_dense(), a);
        // The same entry-by-entry sums, in the same order: equal to the last bit.
        let sum = SymBand::linear_combination(&[(1.0, &ba), (0.3, &bc), (-2.0, &ba)]);
        assert_eq!(sum.to_dense(), (&a + &c * 0.3) + &a * -2.0);
        let x: Vec<f64> = (0..9).map(|i| (0.7 * i as f64).sin()).collect();
        let mut y = vec![1.0; 9];
        bc.mul_add(2.0, &x, &mut y);
        let expected = DVector::from_element(9, 1.0) + &c * DVector::from_column_slice(&x) * 2.0;
        assert!((DVector::from_column_slice(&y) - expected).norm() < 1e-13);
        let mut d = SymBand::zeros(3, 1);
        d.add(1, 0, 2.0);
        assert_eq!((d.get(0, 1), d.get(1, 0), d.get(2, 0)), (2.0, 2.0, 0.0));
        assert!(!d.is_diagonal() && SymBand::zeros(3, 2).is_diagonal());
    }

    #[test]
    fn an_indefinite_matrix_names_its_row() {
        let mut a = banded_spd(10, 2);
        a[(6, 6)] = -50.0;
        assert_eq!(
            BandCholesky::factor(&SymBand::from_dense(&a)).err(),
            Some(6)
        );
    }
}
