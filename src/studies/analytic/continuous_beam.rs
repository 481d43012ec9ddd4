//! Exact modes of a uniform Euler-Bernoulli beam in several pieces (continuous spans,
//! overhangs) on any supports, and the modal series of a force crossing it.
//!
//! In each piece `EI w'''' = m omega^2 w` has the exact solution
//! `w = A sin(b x) + B cos(b x) + C exp(-b x) + D exp(-b (l - x))`, `b^4 = m omega^2 / EI`
//! (the exponentials in place of sinh and cosh keep every coefficient of order one, so the
//! determinant below has no overflow for long pieces). Two conditions at each end and four
//! at each support between pieces (deflection, slope, moment and shear balance with the
//! support's springs, from the variation of the strain energy plus the springs' energy)
//! give a 4P x 4P system; a natural frequency is a root of its determinant, found by a
//! scan and bisection, and its mode the null vector (the textbook route of e.g. Blevins,
//! *Formulas for Natural Frequency and Mode Shape*, 1979, ch. 8, and Gorman, *Free
//! Vibration Analysis of Beams and Shafts*, 1975). Nothing here uses the `bridge` module.
//!
//! Sign convention of the module: deflection and loads DOWNWARD positive.

use nalgebra::DMatrix;

use super::dopri45::{Dopri45, Dopri45Options};
use crate::error::{Error, Result};

/// An end or a support of the beam.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Condition {
    /// Free end (no support).
    Free,
    /// w = 0, free rotation.
    Pinned,
    /// w = 0, slope = 0.
    Clamped,
    /// Vertical (N/m) and rotational (N m/rad) springs.
    Springs {
        vertical_n_m: f64,
        rotational_n_m_rad: f64,
    },
}

/// A uniform beam of pieces joined at supports.
#[derive(Debug, Clone, PartialEq)]
pub struct ContinuousBeam {
    /// Piece lengths, left to right (m).
    pub pieces_m: Vec<f64>,
    /// `pieces_m.len() + 1` conditions: left end, each joint (a support), right end.
    pub conditions: Vec<Condition>,
    pub flexural_rigidity_n_m2: f64,
    pub mass_per_length_kg_m: f64,
}

/// A mass-normalized mode: `omega` and the coefficients (A, B, C, D) of each piece.
#[derive(Debug, Clone)]
pub struct ExactMode {
    pub omega_rad_s: f64,
    beta: f64,
    coefficients: Vec<[f64; 4]>,
}

/// The four basis functions' k-th derivatives divided by `b^k` at `x` in a piece of length `l`.
fn basis(b: f64, l: f64, x: f64, k: usize) -> [f64; 4] {
    let (s, c) = (b * x).sin_cos();
    let (e1, e2) = ((-b * x).exp(), (-b * (l - x)).exp());
    match k {
        0 => [s, c, e1, e2],
        1 => [c, -s, -e1, e2],
        2 => [-s, -c, e1, e2],
        _ => [-c, s, -e1, e2],
    }
}

impl ContinuousBeam {
    fn check(&self) -> Result<()> {
        if self.pieces_m.is_empty() || self.conditions.len() != self.pieces_m.len() + 1 {
            return Err(Error::invalid(
                "conditions",
                self.conditions.len(),
                "needs one more condition than pieces",
            ));
        }
        Ok(())
    }

    /// The boundary and joint conditions at wavenumber `b` (1/m).
    fn matrix(&self, b: f64) -> DMatrix<f64> {
        let p = self.pieces_m.len();
        let ei = self.flexural_rigidity_n_m2;
        let mut a = DMatrix::zeros(4 * p, 4 * p);
        let mut row = 0;
        // Puts `factor * D_k` of piece `j` at its end `x` into the current row.
        let put = |a: &mut DMatrix<f64>, row: usize, j: usize, x: f64, k: usize, f: f64| {
            let v = basis(b, self.pieces_m[j], x, k);
            for (i, vi) in v.iter().enumerate() {
                a[(row, 4 * j + i)] += f * vi;
            }
        };
        for (n, cond) in self.conditions.iter().enumerate() {
            let left = n.checked_sub(1).map(|j| (j, self.pieces_m[j]));
            let right = (n < p).then_some((n, 0.0));
            let (kv, kr) = match *cond {
                Condition::Springs {
                    vertical_n_m,
                    rotational_n_m_rad,
                } => (
                    vertical_n_m / (ei * b * b * b),
                    rotational_n_m_rad / (ei * b),
                ),
                _ => (0.0, 0.0),
            };
            match (left, right, cond) {
                // An end: the piece on one side only; `sign` flips the shear and moment
                // balance between the left end and the right end.
                (None, Some((j, x)), _) | (Some((j, x)), None, _) => {
                    let sign = if left.is_none() { 1.0 } else { -1.0 };
                    match cond {
                        Condition::Free => {
                            put(&mut a, row, j, x, 2, 1.0);
                            put(&mut a, row + 1, j, x, 3, 1.0);
                        }
                        Condition::Pinned => {
                            put(&mut a, row, j, x, 0, 1.0);
                            put(&mut a, row + 1, j, x, 2, 1.0);
                        }
                        Condition::Clamped => {
                            put(&mut a, row, j, x, 0, 1.0);
                            put(&mut a, row + 1, j, x, 1, 1.0);
                        }
                        Condition::Springs { .. } => {
                            put(&mut a, row, j, x, 3, sign);
                            put(&mut a, row, j, x, 0, kv);
                            put(&mut a, row + 1, j, x, 2, -sign);
                            put(&mut a, row + 1, j, x, 1, kr);
                        }
                    }
                    row += 2;
                }
                (Some((jl, xl)), Some((jr, xr)), _) => {
                    match cond {
                        Condition::Pinned => {
                            put(&mut a, row, jl, xl, 0, 1.0);
                            put(&mut a, row + 1, jr, xr, 0, 1.0);
                            put(&mut a, row + 2, jl, xl, 1, 1.0);
                            put(&mut a, row + 2, jr, xr, 1, -1.0);
                            put(&mut a, row + 3, jl, xl, 2, 1.0);
                            put(&mut a, row + 3, jr, xr, 2, -1.0);
                        }
                        Condition::Clamped => {
                            put(&mut a, row, jl, xl, 0, 1.0);
                            put(&mut a, row + 1, jr, xr, 0, 1.0);
                            put(&mut a, row + 2, jl, xl, 1, 1.0);
                            put(&mut a, row + 3, jr, xr, 1, 1.0);
                        }
                        Condition::Free | Condition::Springs { .. } => {
                            put(&mut a, row, jl, xl, 0, 1.0);
                            put(&mut a, row, jr, xr, 0, -1.0);
                            put(&mut a, row + 1, jl, xl, 1, 1.0);
                            put(&mut a, row + 1, jr, xr, 1, -1.0);
                            put(&mut a, row + 2, jr, xr, 3, 1.0);
                            put(&mut a, row + 2, jl, xl, 3, -1.0);
                            put(&mut a, row + 2, jl, xl, 0, kv);
                            put(&mut a, row + 3, jl, xl, 2, 1.0);
                            put(&mut a, row + 3, jr, xr, 2, -1.0);
                            put(&mut a, row + 3, jl, xl, 1, kr);
                        }
                    }
                    row += 4;
                }
                (None, None, _) => {}
            }
        }
        a
    }

    fn determinant(&self, b: f64) -> f64 {
        self.matrix(b).lu().determinant()
    }

    /// Circular frequency (rad/s) of wavenumber `b`.
    fn omega(&self, b: f64) -> f64 {
        b * b * (self.flexural_rigidity_n_m2 / self.mass_per_length_kg_m).sqrt()
    }

    /// The lowest `count` natural frequencies (Hz): sign changes of the determinant on a
    /// scan in steps of 0.01 rad of the longest piece, refined by bisection to 1e-14.
    pub fn frequencies_hz(&self, count: usize) -> Result<Vec<f64>> {
        Ok(self
            .wavenumbers(count)?
            .iter()
            .map(|&b| self.omega(b) / (2.0 * std::f64::consts::PI))
            .collect())
    }

    fn wavenumbers(&self, count: usize) -> Result<Vec<f64>> {
        self.check()?;
        let longest = self.pieces_m.iter().copied().fold(0.0, f64::max);
        let step = 0.01 / longest;
        let mut roots = Vec::with_capacity(count);
        let mut b0 = 0.5 * step;
        let mut d0 = self.determinant(b0);
        while roots.len() < count {
            let b1 = b0 + step;
            let d1 = self.determinant(b1);
            if d0 == 0.0 || d0.signum() != d1.signum() {
                let (mut lo, mut hi, mut dlo) = (b0, b1, d0);
                while hi - lo > 1e-14 * hi {
                    let mid = 0.5 * (lo + hi);
                    let dm = self.determinant(mid);
                    if dm.signum() == dlo.signum() && dm != 0.0 {
                        (lo, dlo) = (mid, dm);
                    } else {
                        hi = mid;
                    }
                }
                roots.push(0.5 * (lo + hi));
            }
            (b0, d0) = (b1, d1);
            if b0 * longest > 1e4 {
                return Err(Error::invalid(
                    "count",
                    count,
                    "no more roots found below b L = 1e4",
                ));
            }
        }
        Ok(roots)
    }

    /// The lowest `count` modes, mass-normalized (the integral of m w^2 is 1).
    pub fn modes(&self, count: usize) -> Result<Vec<ExactMode>> {
        self.wavenumbers(count)?
            .into_iter()
            .map(|b| {
                let a = self.matrix(b);
                let svd = a.svd(false, true);
                let v_t = svd.v_t.ok_or_else(|| Error::invalid("svd", b, "failed"))?;
                let smallest = svd
                    .singular_values
                    .iter()
                    .enumerate()
                    .min_by(|x, y| x.1.total_cmp(y.1))
                    .map_or(0, |(i, _)| i);
                let null = v_t.row(smallest).transpose();
                let mut mode = ExactMode {
                    omega_rad_s: self.omega(b),
                    beta: b,
                    coefficients: (0..self.pieces_m.len())
                        .map(|j| {
                            [
                                null[4 * j],
                                null[4 * j + 1],
                                null[4 * j + 2],
                                null[4 * j + 3],
                            ]
                        })
                        .collect(),
                };
                let norm = self.mass_integral(&mode).sqrt();
                // Sign: positive where the shape is largest first.
                for c in mode.coefficients.iter_mut() {
                    for v in c.iter_mut() {
                        *v /= norm;
                    }
                }
                Ok(mode)
            })
            .collect()
    }

    /// The integral of m w^2 over the beam, by 16-point composite Gauss per piece.
    fn mass_integral(&self, mode: &ExactMode) -> f64 {
        const G: [(f64, f64); 2] = [
            (-0.577_350_269_189_625_8, 1.0),
            (0.577_350_269_189_625_8, 1.0),
        ];
        let cells = 64;
        let mut sum = 0.0;
        for (j, &l) in self.pieces_m.iter().enumerate() {
            let h = l / cells as f64;
            for c in 0..cells {
                let mid = (c as f64 + 0.5) * h;
                for (s, w) in G {
                    let x = mid + 0.5 * h * s;
                    let v = self.piece_value(mode, j, x, 0);
                    sum += w * 0.5 * h * v * v;
                }
            }
        }
        sum * self.mass_per_length_kg_m
    }

    fn piece_value(&self, mode: &ExactMode, j: usize, x: f64, k: usize) -> f64 {
        let v = basis(mode.beta, self.pieces_m[j], x, k);
        let c = mode.coefficients[j];
        mode.beta.powi(k as i32) * (0..4).map(|i| c[i] * v[i]).sum::<f64>()
    }

    /// The `k`-th derivative of the mode shape at `x_m` from the left end (k = 0: w).
    pub fn shape(&self, mode: &ExactMode, x_m: f64, k: usize) -> f64 {
        let mut start = 0.0;
        for (j, &l) in self.pieces_m.iter().enumerate() {
            if x_m <= start + l || j + 1 == self.pieces_m.len() {
                return self.piece_value(mode, j, (x_m - start).clamp(0.0, l), k);
            }
            start += l;
        }
        0.0
    }

    /// Deflection history (downward) at `probe_m` under a force `force_n` (downward)
    /// crossing from x = 0 at t = 0 at `speed_m_s`, by the series of the lowest `n_modes`
    /// exact modes with damping ratio `zeta` on each (the modal ODEs integrated to rtol
    /// 1e-10), sampled at `times_s`.
    pub fn moving_force_deflection(
        &self,
        modes: &[ExactMode],
        zeta: &[f64],
        force_n: f64,
        speed_m_s: f64,
        probe_m: f64,
        times_s: &[f64],
    ) -> Result<Vec<f64>> {
        let length: f64 = self.pieces_m.iter().sum();
        let n = modes.len();
        let at_probe: Vec<f64> = modes.iter().map(|m| self.shape(m, probe_m, 0)).collect();
        let mut solver = Dopri45::new(
            2 * n,
            Dopri45Options {
                rtol: 1e-10,
                atol: vec![1e-16; 2 * n],
                max_step_s: 1e-3,
                ..Default::default()
            },
        )?;
        let mut y = vec![0.0; 2 * n];
        let mut out = Vec::with_capacity(times_s.len());
        let mut t = 0.0;
        let mut rhs = |t: f64, y: &[f64], dy: &mut [f64]| {
            let x = speed_m_s * t;
            for (k, mode) in modes.iter().enumerate() {
                let load = if x <= length {
                    force_n * self.shape(mode, x, 0)
                } else {
                    0.0
                };
                let w = mode.omega_rad_s;
                dy[2 * k] = y[2 * k + 1];
                dy[2 * k + 1] = load - 2.0 * zeta[k] * w * y[2 * k + 1] - w * w * y[2 * k];
            }
        };
        let exit_s = length / speed_m_s;
        for &target in times_s {
            // Split at the exit, where the load stops.
            if t < exit_s && target > exit_s {
                solver.advance(&mut rhs, t, exit_s, &mut y, &mut |_, _| {})?;
                t = exit_s;
            }
            solver.advance(&mut rhs, t, target, &mut y, &mut |_, _| {})?;
            t = target.max(t);
            out.push((0..n).map(|k| at_probe[k] * y[2 * k]).sum());
        }
        Ok(out)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn beam(pieces: &[f64], conditions: &[Condition]) -> ContinuousBeam {
        ContinuousBeam {
            pieces_m: pieces.to_vec(),
            conditions: conditions.to_vec(),
            flexural_rigidity_n_m2: 1.0,
            mass_per_length_kg_m: 1.0,
        }
    }

    /// b1 L of the classic cases (Blevins 1979, table 8-1): the determinant route
    /// reproduces them to the bisection's tolerance.
    #[test]
    fn classic_single_span_roots() {
        use Condition::*;
        let cases = [
            ([Pinned, Pinned], std::f64::consts::PI),
            ([Clamped, Clamped], 4.730_040_744_862_704),
            ([Clamped, Free], 1.875_104_068_711_961),
            ([Free, Free], 4.730_040_744_862_704),
            ([Clamped, Pinned], 3.926_602_312_047_919),
        ];
        for (conditions, expected) in cases {
            let b = beam(&[1.0], &conditions).wavenumbers(1).unwrap()[0];
            assert!((b - expected).abs() < 1e-10, "{conditions:?}: {b}");
        }
    }

    /// Two equal spans: the first mode is the single span's (a node at the pier), the
    /// second the propped cantilever's, tan(bL) = tanh(bL), bL = 3.9266.
    #[test]
    fn two_equal_spans() {
        use Condition::*;
        let b = beam(&[1.0, 1.0], &[Pinned, Pinned, Pinned])
            .wavenumbers(2)
            .unwrap();
        assert!((b[0] - std::f64::consts::PI).abs() < 1e-10, "{b:?}");
        assert!((b[1] - 3.926_602_312_047_919).abs() < 1e-10, "{b:?}");
    }

    /// Three equal spans (docs/physics.md section 10): b L = pi, 3.5564, 4.2975.
    #[test]
    fn three_equal_spans() {
        use Condition::*;
        let b = beam(&[1.0, 1.0, 1.0], &[Pinned; 4]).wavenumbers(3).unwrap();
        for (got, expected) in b.iter().zip([std::f64::consts::PI, 3.5564, 4.2975]) {
            assert!((got - expected).abs() < 1e-4, "{b:?}");
        }
    }

    /// Stiff springs tend to pinned supports, soft ones to a free beam on springs.
    #[test]
    fn springs_bridge_the_limits() {
        use Condition::*;
        let spring = |k: f64| Springs {
            vertical_n_m: k,
            rotational_n_m_rad: 0.0,
        };
        let stiff = beam(&[1.0], &[spring(1e12), spring(1e12)])
            .wavenumbers(1)
            .unwrap()[0];
        assert!((stiff - std::f64::consts::PI).abs() < 1e-6, "{stiff}");
        // Soft springs: rigid-body bounce at omega^2 = 2 k / (m L).
        let k = 1e-3;
        let soft = beam(&[1.0], &[spring(k), spring(k)]);
        let f = soft.frequencies_hz(1).unwrap()[0] * 2.0 * std::f64::consts::PI;
        assert!((f / (2.0 * k).sqrt() - 1.0).abs() < 1e-3, "{f}");
    }

    #[test]
    fn modes_are_mass_normalized_and_satisfy_the_supports() {
        use Condition::*;
        let b = beam(&[1.0, 1.5, 1.0], &[Pinned, Pinned, Pinned, Pinned]);
        let modes = b.modes(3).unwrap();
        for m in &modes {
            assert!((b.mass_integral(m) - 1.0).abs() < 1e-9);
            for x in [0.0, 1.0, 2.5, 3.5] {
                assert!(
                    b.shape(m, x, 0).abs() < 1e-8,
                    "w({x}) = {}",
                    b.shape(m, x, 0)
                );
            }
        }
    }
}
