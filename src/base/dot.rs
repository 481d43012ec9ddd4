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

/// [`dot`] of each of `R` rows with the same `b`, each summed exactly as [`dot`] sums it
/// (the same bits), interleaved: one row's partial sums wait on their own additions, so
/// several rows at once keep the adder busy where a short row alone would leave it idle
/// (a vehicle block's rows are 30 long).
#[inline]
pub fn dots<const R: usize>(rows: [&[f64]; R], b: &[f64]) -> [f64; R] {
    // Rows of unequal lengths would each be cut to the shortest, unlike `dot`.
    debug_assert!(rows.iter().all(|row| row.len() == rows[0].len()));
    let n = rows.iter().fold(b.len(), |n, row| n.min(row.len()));
    let whole = n - n % 4;
    let mut partial = [[0.0; 4]; R];
    for start in (0..whole).step_by(4) {
        let cb = &b[start..start + 4];
        for (p, row) in partial.iter_mut().zip(&rows) {
            let ca = &row[start..start + 4];
            for k in 0..4 {
                p[k] += ca[k] * cb[k];
            }
        }
    }
    std::array::from_fn(|r| {
        let tail: f64 = rows[r][whole..n]
            .iter()
            .zip(&b[whole..n])
            .map(|(x, y)| x * y)
            .sum();
        let p = &partial[r];
        (p[0] + p[1]) + (p[2] + p[3]) + tail
    })
}

/// `out += sum_t w_t c_t` over the `(w_t, c_t)` of `terms()` (or `out = w_0 c_0 + sum_{t>0}`
/// with `overwrite`; zero when there are no terms), each entry summed term by term in
/// order: the bits of successive axpys `out = w_t c_t + out`, in one pass over `out`
/// (eight entries stay in registers across the terms instead of one load and store per
/// term). `terms` is called once per eight entries; each `c_t` is at least as long as `out`.
#[inline]
pub fn add_columns<'a, I>(out: &mut [f64], overwrite: bool, terms: impl Fn() -> I)
where
    I: Iterator<Item = (f64, &'a [f64])>,
{
    const CHUNK: usize = 8;
    fn chunk<'a, const L: usize>(
        out: &mut [f64],
        lo: usize,
        overwrite: bool,
        terms: impl Iterator<Item = (f64, &'a [f64])>,
    ) {
        let mut acc = [0.0; L];
        if !overwrite {
            acc.copy_from_slice(&out[..L]);
        }
        for (t, (w, column)) in terms.enumerate() {
            let column = &column[lo..lo + L];
            match (t, overwrite) {
                (0, true) => (0..L).for_each(|i| acc[i] = w * column[i]),
                _ => (0..L).for_each(|i| acc[i] += w * column[i]),
            }
        }
        out[..L].copy_from_slice(&acc);
    }
    let whole = out.len() - out.len() % CHUNK;
    let (body, tail) = out.split_at_mut(whole);
    for (c, part) in body.chunks_exact_mut(CHUNK).enumerate() {
        chunk::<CHUNK>(part, c * CHUNK, overwrite, terms());
    }
    for (i, y) in tail.iter_mut().enumerate() {
        chunk::<1>(std::slice::from_mut(y), whole + i, overwrite, terms());
    }
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

    #[test]
    fn column_sums_are_the_bits_of_successive_axpys() {
        let columns: Vec<Vec<f64>> = (0..5)
            .map(|t| {
                (0..21)
                    .map(|i| ((t * 21 + i) as f64).sin() * 10f64.powi(t))
                    .collect()
            })
            .collect();
        let weights = [0.3, -1.7, 2.9e-3, 11.0, -0.01];
        let start: Vec<f64> = (0..21).map(|i| (i as f64).cos()).collect();
        for overwrite in [false, true] {
            let mut expected = start.clone();
            for (t, (w, c)) in weights.iter().zip(&columns).enumerate() {
                for (y, x) in expected.iter_mut().zip(c) {
                    *y = match (t, overwrite) {
                        (0, true) => w * x,
                        _ => w * x + *y,
                    };
                }
            }
            let mut got = start.clone();
            add_columns(&mut got, overwrite, || {
                weights
                    .iter()
                    .copied()
                    .zip(columns.iter().map(|c| c.as_slice()))
            });
            let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
            assert_eq!(bits(&got), bits(&expected), "overwrite = {overwrite}");
        }
        let mut none = start.clone();
        add_columns(&mut none, true, std::iter::empty);
        assert!(none.iter().all(|&x| x == 0.0));
    }

    #[test]
    fn interleaved_rows_sum_as_the_single_dot_bit_for_bit() {
        // Values whose sums round differently in another order.
        let b: Vec<f64> = (0..31).map(|i| (0.1 * i as f64).sin() * 1e3).collect();
        let rows: Vec<Vec<f64>> = (0..4)
            .map(|r| (0..31).map(|i| ((r * 31 + i) as f64).cos() / 7.0).collect())
            .collect();
        for n in [0, 3, 4, 29, 30, 31] {
            let got = dots(
                [&rows[0][..n], &rows[1][..n], &rows[2][..n], &rows[3][..n]],
                &b,
            );
            for (r, row) in rows.iter().enumerate() {
                assert_eq!(
                    got[r].to_bits(),
                    dot(&row[..n], &b).to_bits(),
                    "row {r}, n = {n}"
                );
            }
        }
    }
}
