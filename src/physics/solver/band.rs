//! Symmetric band matrices: the mass, damping and effective stiffness of a finite-element
//! beam couple each node only to its neighbours (half-bandwidth 3 with two DOFs per node).
//!
//! Stored by rows of the lower band, `b + 1` values per row (`row[i][k]` is entry
//! `(i, i - k)`, zero-padded before column 0), so the per-step kernels are fixed-length
//! loops over contiguous memory with no index arrays: the matrix-vector product, and the
//! two triangular solves with the Cholesky factor computed once in band form
//! (`L L^T`, Golub and Van Loan, Matrix Computations, 4th ed., algorithm 4.3.5: the factor
//! of a band matrix keeps its band, so the cost is O(n b^2) once and O(n b) per solve).
//! The transposed solve reads a second copy of the factor stored by columns, so that it
//! too runs forward through memory.

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

/// Lower band rows of `m` (half-bandwidth `b`): `(n, b + 1)` values, entry `(i, i - k)` at
/// `i * (b + 1) + k`.
fn lower_rows(m: &DMatrix<f64>, b: usize) -> Vec<f64> {
    let n = m.nrows();
    let mut rows = vec![0.0; n * (b + 1)];
    for i in 0..n {
        for k in 0..=b.min(i) {
            rows[i * (b + 1) + k] = m[(i, i - k)];
        }
    }
    rows
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
    /// The band of symmetric `m` (the lower triangle is read, the upper taken equal).
    pub fn from_symmetric(m: &DMatrix<f64>) -> Self {
        let (n, b) = (m.nrows(), half_bandwidth(m));
        let w = 2 * b + 1;
        let mut rows = vec![0.0; n * w];
        for i in 0..n {
            for j in i.saturating_sub(b)..=(i + b).min(n - 1) {
                let (r, c) = if j <= i { (i, j) } else { (j, i) };
                rows[i * w + j + b - i] = m[(r, c)];
            }
        }
        BandMatrix { n, b, rows }
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

/// Dot product with four independent partial sums: a single running sum would make every
/// term wait for the previous addition.
fn dot(a: &[f64], b: &[f64]) -> f64 {
    let mut partial = [0.0; 4];
    let (a4, b4) = (a.chunks_exact(4), b.chunks_exact(4));
    let tail: f64 = a4
        .remainder()
        .iter()
        .zip(b4.remainder())
        .map(|(x, y)| x * y)
        .sum();
    for (ca, cb) in a4.zip(b4) {
        for k in 0..4 {
            partial[k] += ca[k] * cb[k];
        }
    }
    (partial[0] + partial[1]) + (partial[2] + partial[3]) + tail
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
    pub fn factor(m: &DMatrix<f64>) -> Result<Self, usize> {
        let n = m.nrows();
        let b = half_bandwidth(m);
        let w = b + 1;
        let mut l = lower_rows(m, b);
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
            BandCholesky::factor(&a)
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
    fn an_indefinite_matrix_names_its_row() {
        let mut a = banded_spd(10, 2);
        a[(6, 6)] = -50.0;
        assert_eq!(BandCholesky::factor(&a).err(), Some(6));
    }
}
