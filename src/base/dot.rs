//! The dot product every hot loop uses (band products, block propagators, resampling
//! kernels): one summation order everywhere, so a result does not depend on which loop
//! computed it.

/// `a . b` over the shorter length, with four independent partial sums: a single running
/// sum would make every term wait for the previous addition, and four lanes let the
/// compiler use SIMD registers.
#[inline]
pub fn dot(a: &[f64], b: &[f64]) -> f64 {
    let n = a.len().min(b.len());
    let (a, b) = (&a[..n], &b[..n]);
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn matches_the_plain_sum_on_integers_and_handles_tails() {
        for n in 0..11 {
            let a: Vec<f64> = (0..n).map(|i| i as f64).collect();
            let b: Vec<f64> = (0..n).map(|i| (2 * i + 1) as f64).collect();
            let plain: f64 = a.iter().zip(&b).map(|(x, y)| x * y).sum();
            assert_eq!(dot(&a, &b), plain, "n = {n}");
        }
    }
}
