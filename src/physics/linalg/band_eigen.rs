//! The lowest eigenpairs of a banded pencil `K x = lambda M x` (K positive definite, M
//! positive semi-definite: massless DOFs give infinite eigenvalues, which are never
//! wanted), in O(n b^2) per step and O(n b + n k) memory, with no dense eigenproblem.
//!
//! Eigenvalues by bisection on Sturm counts: by Sylvester's law of inertia the number of
//! eigenvalues below `sigma` is the number of negative pivots of the `L D L^T`
//! factorization of `K - sigma M` (e.g. Bathe, Finite Element Procedures, 2nd ed., section
//! 11.4.3; Parlett, The Symmetric Eigenvalue Problem, section 3.3). Each count is one band
//! factorization, so a count never misses nor doubles an eigenvalue, clusters included,
//! which a Krylov method with a fixed subspace cannot promise. Eigenvectors by inverse
//! iteration with the converged eigenvalue as the shift (Parlett, section 4.2), each new
//! vector made M-orthogonal to the vectors already found within the same cluster (as
//! LAPACK's `dstein` does for tridiagonal matrices), so that close eigenvalues still give
//! an M-orthonormal basis.

use nalgebra::{DMatrix, DVector};

use super::band::SymBand;

/// Bisection stops when the bracket of an eigenvalue is narrower than this, relative: a
/// few ulps above the resolution of the Sturm count (the count itself carries the
/// round-off of the factorization, which sets the attainable accuracy).
const RELATIVE_BRACKET: f64 = 1e-13;

/// Inverse-iteration steps per vector: with the shift within 1e-13 of the eigenvalue and
/// the nearest other eigenvalue at least 1e-6 away (relative), each step multiplies the
/// wanted component by 1e7 against any other; three steps from any start leave less than
/// round-off of the others (clusters closer than that are handled by orthogonalization).
const INVERSE_ITERATIONS: usize = 3;

/// Eigenvalues closer than this (relative) are one cluster: their vectors are made
/// M-orthogonal to each other explicitly.
const CLUSTER_RELATIVE_GAP: f64 = 1e-3;

/// A pivot below this fraction of its diagonal entry makes a Sturm count unreliable (the
/// rows after it inherit round-off multiplied by its inverse); the shift is then moved
/// within its bracket and counted again. Pivots near 1e-13 arise legitimately as the
/// bisection closes on an eigenvalue, and their growth still leaves the later pivots'
/// signs right; the floor catches the (near) exact zeros of leading blocks.
pub const PIVOT_FLOOR: f64 = 1e-14;

/// Fractions of the bracket width by which a shift with a tiny pivot is moved, in turn.
const SHIFT_NUDGES: [f64; 4] = [0.013, -0.017, 0.031, -0.037];

/// Bisection steps per eigenvalue at most: 60 halvings shrink any bracket below the
/// relative tolerance, whatever the shifts' nudges.
const MAX_BISECTIONS: usize = 200;

/// Why the eigenpairs could not be computed.
#[derive(Debug, Clone, PartialEq)]
pub enum EigenError {
    /// `K` is not positive definite: the structure can move without deforming.
    StiffnessNotPositiveDefinite,
    /// Fewer finite eigenvalues exist than asked for (massless DOFs have none).
    TooFewModes { wanted: usize, available: usize },
}

/// The `L D L^T` factorization of a symmetric band matrix without pivoting (the band is
/// kept): the inertia for Sturm counts, and solves for inverse iteration.
pub struct BandLdl {
    n: usize,
    b: usize,
    /// Row i: `L[i][i - k]` at `i * (b + 1) + k`, `k = 1..=b` (the unit diagonal is implied).
    l: Vec<f64>,
    d: Vec<f64>,
}

impl BandLdl {
    /// Storage for matrices of order `n` and half-bandwidth `b`.
    pub fn new(n: usize, b: usize) -> Self {
        BandLdl {
            n,
            b,
            l: vec![0.0; n * (b + 1)],
            d: vec![0.0; n],
        }
    }

    /// Factorizes `K - sigma M` in place of the previous factorization. A pivot that is
    /// exactly zero (sigma on an eigenvalue of a leading block) is replaced by a tiny
    /// negative number, as LAPACK's bisection does (`dstebz`, pivmin): the solve stays
    /// defined. Returns whether every pivot kept at least [`PIVOT_FLOOR`] of its row's
    /// diagonal entry: a smaller pivot multiplies the round-off of the rows after it by
    /// its inverse, and the count at such a shift is not to be trusted.
    pub fn factor_shifted(&mut self, k: &SymBand, m: &SymBand, sigma: f64) -> bool {
        let (n, b) = (self.n, self.b);
        debug_assert!(k.n() == n && m.n() == n && k.half_bandwidth().max(m.half_bandwidth()) <= b);
        let w = b + 1;
        let (kb, mb) = (k.half_bandwidth(), m.half_bandwidth());
        let (kr, mr) = (k.lower_rows(), m.lower_rows());
        let entry = |i: usize, off: usize| {
            let kv = if off <= kb {
                kr[i * (kb + 1) + off]
            } else {
                0.0
            };
            let mv = if off <= mb {
                mr[i * (mb + 1) + off]
            } else {
                0.0
            };
            kv - sigma * mv
        };
        let tiny = f64::MIN_POSITIVE.sqrt();
        let mut sound = true;
        // `ld[c]` holds L[i][c] D[c] for the row being factorized.
        let mut ld = [0.0f64; 64];
        assert!(
            b < ld.len(),
            "half-bandwidth {b} above the inertia kernel's 63"
        );
        for i in 0..n {
            let first = i.saturating_sub(b);
            for j in first..i {
                // L[i][j] D[j] = A[i][j] - sum_{c < j} L[i][c] D[c] L[j][c]
                let mut s = entry(i, i - j);
                for c in first.max(j.saturating_sub(b))..j {
                    s -= ld[i - c] * self.l[j * w + (j - c)];
                }
                ld[i - j] = s;
                self.l[i * w + (i - j)] = s / self.d[j];
            }
            let diagonal = entry(i, 0);
            let mut di = diagonal;
            for c in first..i {
                di -= ld[i - c] * self.l[i * w + (i - c)];
            }
            sound &= di.abs() >= PIVOT_FLOOR * diagonal.abs();
            self.d[i] = if di == 0.0 { -tiny } else { di };
        }
        sound
    }

    /// Number of negative pivots: the eigenvalues of the pencil below the shift.
    pub fn negative_pivots(&self) -> usize {
        self.d.iter().filter(|&&d| d < 0.0).count()
    }

    /// `x <- (L D L^T)^-1 x`.
    pub fn solve_in_place(&self, x: &mut [f64]) {
        let (n, b, w) = (self.n, self.b, self.b + 1);
        for i in 0..n {
            let mut s = x[i];
            for k in 1..=b.min(i) {
                s -= self.l[i * w + k] * x[i - k];
            }
            x[i] = s;
        }
        for (xi, di) in x.iter_mut().zip(&self.d) {
            *xi /= di;
        }
        for i in (0..n).rev() {
            let xi = x[i];
            for k in 1..=b.min(i) {
                x[i - k] -= self.l[i * w + k] * xi;
            }
        }
    }
}

/// The pencil `(K, M)` with its Sturm counts and the points counted so far.
struct Sturm<'a> {
    k: &'a SymBand,
    m: &'a SymBand,
    ldl: BandLdl,
    /// `(sigma, eigenvalues below sigma)`, sorted by sigma (counts are then sorted too).
    counted: Vec<(f64, usize)>,
}

impl<'a> Sturm<'a> {
    fn new(k: &'a SymBand, m: &'a SymBand) -> Self {
        let b = k.half_bandwidth().max(m.half_bandwidth());
        Sturm {
            k,
            m,
            ldl: BandLdl::new(k.n(), b),
            counted: vec![(0.0, 0)],
        }
    }

    /// Counts the eigenvalues below `sigma` and records it; where `sigma` gives a tiny
    /// pivot, below a shift moved by a few percent of `width` instead.
    fn count(&mut self, sigma: f64, width: f64) -> usize {
        let mut shift = sigma;
        let mut nudges = SHIFT_NUDGES.iter();
        while !self.ldl.factor_shifted(self.k, self.m, shift) {
            match nudges.next() {
                Some(nudge) => shift = sigma + nudge * width,
                None => break,
            }
        }
        let sigma = shift;
        let c = self.ldl.negative_pivots();
        let at = self.counted.partition_point(|&(s, _)| s < sigma);
        // Round-off can make counts at nearly equal shifts disagree by one; keep the
        // sequence monotone so that every bracket below stays a bracket.
        let c = c
            .max(at.checked_sub(1).map_or(0, |p| self.counted[p].1))
            .min(self.counted.get(at).map_or(usize::MAX, |p| p.1));
        self.counted.insert(at, (sigma, c));
        c
    }

    /// The bracket `(lo, hi)` of eigenvalue `j` (0-based) from the points counted:
    /// `count(lo) <= j < count(hi)`.
    fn bracket(&self, j: usize) -> (f64, f64) {
        let above = self.counted.partition_point(|&(_, c)| c <= j);
        (self.counted[above - 1].0, self.counted[above].0)
    }

    /// Eigenvalue `j` by bisection of its bracket.
    fn bisect(&mut self, j: usize) -> f64 {
        for _ in 0..MAX_BISECTIONS {
            let (lo, hi) = self.bracket(j);
            let mid = match lo > 0.0 && hi > 2.0 * lo {
                // Across decades halve the exponent, not the value.
                true => (lo * hi).sqrt(),
                false => 0.5 * (lo + hi),
            };
            if hi - lo <= RELATIVE_BRACKET * hi || mid <= lo || mid >= hi {
                return 0.5 * (lo + hi);
            }
            self.count(mid, hi - lo);
        }
        let (lo, hi) = self.bracket(j);
        0.5 * (lo + hi)
    }
}

/// Number of eigenvalues of `K x = lambda M x` below `sigma`.
pub fn count_below(k: &SymBand, m: &SymBand, sigma: f64) -> usize {
    Sturm::new(k, m).count(sigma, 1e-9 * sigma)
}

/// The `count` lowest eigenvalues (ascending) and M-orthonormal eigenvectors (columns).
pub fn lowest_eigenpairs(
    k: &SymBand,
    m: &SymBand,
    count: usize,
) -> Result<(Vec<f64>, DMatrix<f64>), EigenError> {
    let n = k.n();
    let available = m.diagonal().iter().filter(|&&v| v > 0.0).count().min(n);
    if count > available {
        return Err(EigenError::TooFewModes {
            wanted: count,
            available,
        });
    }
    let mut sturm = Sturm::new(k, m);
    // K positive definite: its factorization at sigma = 0 has no negative pivot.
    sturm.ldl.factor_shifted(k, m, 0.0);
    if sturm.ldl.negative_pivots() > 0
        || sturm
            .ldl
            .d
            .iter()
            .any(|d| d.abs() < f64::MIN_POSITIVE.sqrt() * 2.0)
    {
        return Err(EigenError::StiffnessNotPositiveDefinite);
    }
    if count == 0 {
        return Ok((Vec::new(), DMatrix::zeros(n, 0)));
    }
    // An upper bound of the count-th eigenvalue: a diagonal Rayleigh quotient bounds the
    // first from above; grow it until `count` eigenvalues lie below.
    let mut hi = (0..n)
        .filter(|&i| m.get(i, i) > 0.0)
        .map(|i| k.get(i, i) / m.get(i, i))
        .fold(f64::INFINITY, f64::min);
    while sturm.count(hi, 1e-9 * hi) < count {
        hi *= 4.0;
    }
    let values: Vec<f64> = (0..count).map(|j| sturm.bisect(j)).collect();
    let vectors = inverse_iteration(k, m, &values);
    Ok((values, vectors))
}

/// M-orthonormal eigenvectors for converged eigenvalues `values` (ascending).
fn inverse_iteration(k: &SymBand, m: &SymBand, values: &[f64]) -> DMatrix<f64> {
    let n = k.n();
    let b = k.half_bandwidth().max(m.half_bandwidth());
    let mut ldl = BandLdl::new(n, b);
    let mut vectors = DMatrix::zeros(n, values.len());
    let mut x = DVector::zeros(n);
    let mut mx = DVector::zeros(n);
    let mut cluster_start = 0;
    for (j, &lambda) in values.iter().enumerate() {
        if j > 0 && lambda - values[j - 1] > CLUSTER_RELATIVE_GAP * lambda {
            cluster_start = j;
        }
        ldl.factor_shifted(k, m, lambda);
        start_vector(j, &mut x);
        for _ in 0..INVERSE_ITERATIONS {
            mx.fill(0.0);
            m.mul_add(1.0, x.as_slice(), mx.as_mut_slice());
            x.copy_from(&mx);
            ldl.solve_in_place(x.as_mut_slice());
            orthogonalize(&mut x, &mut mx, m, &vectors, cluster_start..j);
            normalize(&mut x, &mut mx, m);
        }
        fix_sign(&mut x);
        vectors.set_column(j, &x);
    }
    vectors
}

/// A deterministic start with a component along every eigenvector in practice: a
/// pseudo-random sequence (SplitMix64), different per eigenvalue.
fn start_vector(j: usize, x: &mut DVector<f64>) {
    let mut state = 0x9E37_79B9_7F4A_7C15u64 ^ (j as u64).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    for xi in x.iter_mut() {
        state = state.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = state;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^= z >> 31;
        *xi = (z >> 11) as f64 / (1u64 << 53) as f64 - 0.5;
    }
}

/// `x -= sum_i (phi_i^T M x) phi_i` over the vectors `range` (modified Gram-Schmidt).
fn orthogonalize(
    x: &mut DVector<f64>,
    mx: &mut DVector<f64>,
    m: &SymBand,
    vectors: &DMatrix<f64>,
    range: std::ops::Range<usize>,
) {
    for i in range {
        mx.fill(0.0);
        m.mul_add(1.0, x.as_slice(), mx.as_mut_slice());
        let phi = vectors.column(i);
        let c = phi.dot(mx);
        x.axpy(-c, &phi, 1.0);
    }
}

/// Scales `x` to `x^T M x = 1`. The largest entry is brought to 1 first: a shift that
/// lands on an eigenvalue to the last bit leaves a zero pivot (replaced by a tiny one), and
/// the solve's entries of 1e150 would overflow the norm's squares.
fn normalize(x: &mut DVector<f64>, mx: &mut DVector<f64>, m: &SymBand) {
    let largest = x.amax();
    if largest > 0.0 && largest.is_finite() {
        *x /= largest;
    }
    mx.fill(0.0);
    m.mul_add(1.0, x.as_slice(), mx.as_mut_slice());
    let norm = x.dot(mx).sqrt();
    *x /= norm;
}

/// A sign that does not depend on the start: the first entry of at least half the largest
/// magnitude is positive.
fn fix_sign(x: &mut DVector<f64>) {
    let largest = x.amax();
    if let Some(first) = x.iter().find(|v| v.abs() >= 0.5 * largest) {
        if *first < 0.0 {
            x.neg_mut();
        }
    }
}
