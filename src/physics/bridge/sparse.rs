//! A small sparse vector used for point operators (load vectors, read-back weights).
//! Its buffers are reused between calls, so filling it in the time loop does not allocate.

use nalgebra::DVector;

/// Index/value pairs; `w(x) = sum val[k] * u[idx[k]]`.
#[derive(Debug, Clone, Default)]
pub struct SparseVec {
    pub idx: Vec<usize>,
    pub val: Vec<f64>,
}

impl SparseVec {
    /// An empty vector with room for `capacity` entries.
    pub fn with_capacity(capacity: usize) -> Self {
        SparseVec {
            idx: Vec::with_capacity(capacity),
            val: Vec::with_capacity(capacity),
        }
    }

    /// Removes all entries, keeping the capacity.
    #[inline]
    pub fn clear(&mut self) {
        self.idx.clear();
        self.val.clear();
    }

    /// Appends one entry (indices may repeat; they add up).
    #[inline]
    pub fn push(&mut self, index: usize, value: f64) {
        self.idx.push(index);
        self.val.push(value);
    }

    /// Number of stored entries.
    pub fn len(&self) -> usize {
        self.idx.len()
    }

    /// True when no entry is stored.
    pub fn is_empty(&self) -> bool {
        self.idx.is_empty()
    }

    /// `self . x`.
    #[inline]
    pub fn dot(&self, x: &DVector<f64>) -> f64 {
        self.idx
            .iter()
            .zip(&self.val)
            .map(|(&i, &v)| v * x[i])
            .sum()
    }

    /// `y += alpha * self`.
    #[inline]
    pub fn add_scaled_to(&self, alpha: f64, y: &mut DVector<f64>) {
        for (&i, &v) in self.idx.iter().zip(&self.val) {
            y[i] += alpha * v;
        }
    }

    /// Dense copy of length `n` (tests and diagnostics).
    pub fn to_dense(&self, n: usize) -> DVector<f64> {
        let mut y = DVector::zeros(n);
        self.add_scaled_to(1.0, &mut y);
        y
    }
}
