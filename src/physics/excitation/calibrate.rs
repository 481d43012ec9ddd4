//! Stationary acceleration variance of the bridge under the ambient force, computed from
//! the model (no trial simulation), so the force level that gives a target RMS is known
//! before the first step.
//!
//! Random-vibration theory (e.g. Newland, An Introduction to Random Vibrations, Spectral
//! and Wavelet Analysis, 3rd ed., ch. 7): for independent load channels i with one-sided
//! PSD `S_y(f)` each, entering the model as load vectors `b_i`, the acceleration at x has
//! variance `integral_0^{fs/2} sum_i |H_a,i(x, f)|^2 S_y(f) df` with
//! `H_a,i(x, f) = sum_n r_n(x) g_ni H_n(f)`, `r_n(x) = h(x) . phi_n`, `g_ni = phi_n . b_i`
//! (mass-normalised modes of `K phi = w^2 M phi`) and the modal acceleration receptance
//! `H_n = -W^2 / (w_n^2 - W^2 + 2 i zeta_n w_n W)`.
//!
//! The solver's average-acceleration Newmark rule is the trapezoidal rule on (u, v), i.e.
//! the bilinear transform of the continuous system, and the step's acceleration follows
//! from equilibrium; so the discrete response is exactly the continuous one evaluated at
//! the warped frequency `W = (2 / dt) tan(pi f dt)`. Using it makes the prediction exact
//! for the simulation at any step (Newmark's period elongation included), not only as
//! dt -> 0.
//!
//! Since `sum_i g_ni g_mi = Q_nm` does not depend on x, the variance at any point is the
//! quadratic form `r(x)^T A r(x)` with
//! `A_nm = Q_nm * integral Re(conj(H_n) H_m) S_y df`, computed once.

use std::f64::consts::PI;

use nalgebra::{Complex, DMatrix, DVector};

use super::bandpass::BandPass;
use crate::error::{num, Error, Result};
use crate::physics::bridge::{BridgeModel, PointQuantity, SparseVec, Wanted};

/// Modes kept: every mode below this multiple of the band's high edge. Above the band a
/// mode answers quasi-statically, `|H_n| ~ (f / f_n)^2 <= 1 / 100` at the edge, and the
/// band-pass has cut the force by 24 dB per octave beyond it, so the dropped modes change
/// the variance by well under 0.1 %.
const MODE_COVER_FACTOR: f64 = 10.0;

/// Grid points per half-power bandwidth `2 zeta_n f_n` at a resonance.
const POINTS_PER_WIDTH: f64 = 20.0;

/// Away from a feature the step grows as `distance / GRADING`: a geometric grid whose
/// trapezoid-rule error on a Lorentzian tail is ~ 1 / (12 GRADING^2) ~ 2e-4 relative.
const GRADING: f64 = 20.0;

/// Something in the integrand that needs resolution: a resonance or a band edge.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Feature {
    /// Where it is (Hz).
    pub center_hz: f64,
    /// Width of its peak or transition (Hz); the finest step is `width / POINTS_PER_WIDTH`.
    pub width_hz: f64,
}

/// A grid on `[0, f_max]` whose step is `min(max_step, min_j max(w_j / P, |f - c_j| / G))`
/// (`P` = [`POINTS_PER_WIDTH`], `G` = [`GRADING`]): fine across every feature, geometric
/// away from it, so a lightly damped resonance costs a few hundred points instead of the
/// millions a uniform grid would need.
pub fn graded_grid(features: &[Feature], f_max_hz: f64, max_step_hz: f64) -> Vec<f64> {
    let step_at = |f: f64| {
        features
            .iter()
            .map(|feature| {
                (feature.width_hz / POINTS_PER_WIDTH).max((f - feature.center_hz).abs() / GRADING)
            })
            .fold(max_step_hz, f64::min)
    };
    let mut grid = vec![0.0];
    let mut f = 0.0;
    while f < f_max_hz {
        f = (f + step_at(f)).min(f_max_hz);
        grid.push(f);
    }
    grid
}

/// Trapezoid-rule weights of a grid.
pub fn trapezoid_weights(grid: &[f64]) -> Vec<f64> {
    let n = grid.len();
    (0..n)
        .map(|k| {
            let left = if k > 0 { grid[k] - grid[k - 1] } else { 0.0 };
            let right = if k + 1 < n {
                grid[k + 1] - grid[k]
            } else {
                0.0
            };
            0.5 * (left + right)
        })
        .collect()
}

/// Modal data of the model that the variance needs.
struct ModalBasis {
    omega_rad_s: Vec<f64>,
    zeta: Vec<f64>,
    /// Kept mass-normalised shapes (n_dof x modes).
    shapes: DMatrix<f64>,
}

/// Mass-normalised modes below `MODE_COVER_FACTOR * f_high`, with the damping ratios of
/// the model's damping matrix projected on them (`phi^T C phi = 2 zeta w`; exact for the
/// Rayleigh damping the models use, which the modes diagonalise).
fn modal_basis(model: &BridgeModel, high_hz: f64) -> Result<ModalBasis> {
    let cover_rad_s = 2.0 * PI * MODE_COVER_FACTOR * high_hz;
    let modes = model.modes(Wanted::Below(cover_rad_s))?;
    let count = modes.omega_rad_s.len();
    let shapes = modes.shapes;
    let omega_rad_s: Vec<f64> = modes.omega_rad_s.iter().copied().collect();
    let mut zeta = Vec::with_capacity(count);
    for (n, &w) in omega_rad_s.iter().enumerate() {
        let c_n = model.damping.quadratic_form(&shapes.column(n).into_owned());
        let z = c_n / (2.0 * w);
        if !(z.is_finite() && z > 0.0 && w > 0.0) {
            return Err(Error::invalid(
                "bridge.damping_ratio",
                num(model.damping_ratio),
                format!(
                    "gives mode {} ({} Hz) a damping ratio of {}: ambient excitation needs \
                     every mode damped (> 0) to reach a stationary response",
                    n + 1,
                    num(w / (2.0 * PI)),
                    num(z)
                ),
            ));
        }
        zeta.push(z);
    }
    Ok(ModalBasis {
        omega_rad_s,
        zeta,
        shapes,
    })
}

/// The acceleration variance of the bridge per unit input, as a quadratic form in the
/// modal read-back weights (module doc).
#[derive(Debug, Clone)]
pub struct ResponseModel {
    shapes: DMatrix<f64>,
    /// `A` of the module doc (modes x modes), for unit-variance channel signals.
    variance_form: DMatrix<f64>,
    /// Natural frequencies of the kept modes (Hz).
    frequencies_hz: Vec<f64>,
    /// Variance of the band-pass output for unit discrete white noise input.
    filter_variance: f64,
    /// Points of the frequency grid (diagnostics, setup cost).
    grid_points: usize,
}

impl ResponseModel {
    /// Builds the model for load channels `loads` (load vector of a unit channel signal
    /// each), each channel the output of `band` driven by unit discrete white noise and
    /// then divided by its own RMS (so every channel has unit variance).
    pub fn new(model: &BridgeModel, loads: &[SparseVec], band: &BandPass) -> Result<Self> {
        let [low_hz, high_hz] = band.band_hz();
        let basis = modal_basis(model, high_hz)?;
        let dt = band.dt_s();
        let nyquist_hz = 0.5 / dt;
        let mut features = vec![
            Feature {
                center_hz: low_hz,
                width_hz: 0.5 * low_hz,
            },
            Feature {
                center_hz: high_hz,
                width_hz: 0.5 * high_hz,
            },
        ];
        for (&w, &z) in basis.omega_rad_s.iter().zip(&basis.zeta) {
            features.push(warped_resonance(w, z, dt));
        }
        let grid = graded_grid(&features, nyquist_hz, nyquist_hz / 200.0);
        let weights = trapezoid_weights(&grid);
        // One-sided PSD of a unit-variance channel: 2 dt |H_bp|^2 / var(unit white -> H_bp).
        let psd: Vec<f64> = grid
            .iter()
            .map(|&f| 2.0 * dt * band.gain_squared(f))
            .collect();
        let filter_variance: f64 = psd.iter().zip(&weights).map(|(s, w)| s * w).sum();
        let spectral = spectral_form(&basis, &grid, &weights, &psd, dt, filter_variance);
        let coupling = load_coupling(&basis.shapes, loads);
        Ok(ResponseModel {
            variance_form: spectral.component_mul(&coupling),
            frequencies_hz: basis.omega_rad_s.iter().map(|w| w / (2.0 * PI)).collect(),
            shapes: basis.shapes,
            grid_points: grid.len(),
            filter_variance,
        })
    }

    /// Variance of the acceleration at `x_m` (read with the model's deflection operator,
    /// as the solver's point read-back does) per unit channel variance ((m/s^2)^2).
    pub fn acceleration_variance_at(&self, model: &BridgeModel, x_m: f64) -> f64 {
        let mut op = SparseVec::with_capacity(model.n_dof());
        model.point_operator(x_m, PointQuantity::Deflection, &mut op);
        let mut r = DVector::zeros(self.shapes.ncols());
        for (&i, &v) in op.idx.iter().zip(&op.val) {
            r.axpy(v, &self.shapes.row(i).transpose(), 1.0);
        }
        r.dot(&(&self.variance_form * &r)).max(0.0)
    }

    /// Natural frequencies of the modes the prediction uses (Hz).
    pub fn frequencies_hz(&self) -> &[f64] {
        &self.frequencies_hz
    }

    /// Variance of the band-pass output for unit discrete white noise input:
    /// `2 dt integral |H_bp|^2 df`, what a channel is divided by to have unit variance.
    pub fn filter_variance(&self) -> f64 {
        self.filter_variance
    }

    /// Number of frequency-grid points of the integral.
    pub fn grid_points(&self) -> usize {
        self.grid_points
    }
}

/// The resonance of mode (w, zeta) as the discrete scheme sees it: at the f whose warped
/// frequency is w, with the half-power width mapped through `dW/df`.
fn warped_resonance(omega_rad_s: f64, zeta: f64, dt_s: f64) -> Feature {
    let center_hz = (0.5 * omega_rad_s * dt_s).atan() / (PI * dt_s);
    let cos = (PI * center_hz * dt_s).cos();
    Feature {
        center_hz,
        width_hz: 2.0 * zeta * omega_rad_s / (2.0 * PI) * cos * cos,
    }
}

/// `integral Re(conj(H_n) H_m) S_y df / var_y` over the grid (modes x modes).
fn spectral_form(
    basis: &ModalBasis,
    grid: &[f64],
    weights: &[f64],
    psd: &[f64],
    dt_s: f64,
    filter_variance: f64,
) -> DMatrix<f64> {
    let k = basis.omega_rad_s.len();
    let mut form = DMatrix::zeros(k, k);
    let mut h = vec![Complex::new(0.0, 0.0); k];
    for ((&f, &w), &s) in grid.iter().zip(weights).zip(psd) {
        let weight = w * s / filter_variance;
        if weight == 0.0 {
            continue;
        }
        let big_w = 2.0 / dt_s * (PI * f * dt_s).tan();
        for (hn, (&wn, &zn)) in h.iter_mut().zip(basis.omega_rad_s.iter().zip(&basis.zeta)) {
            let den = Complex::new(wn * wn - big_w * big_w, 2.0 * zn * wn * big_w);
            *hn = Complex::new(-big_w * big_w, 0.0) / den;
        }
        for n in 0..k {
            for m in n..k {
                let v = weight * (h[n].conj() * h[m]).re;
                form[(n, m)] += v;
                if m != n {
                    form[(m, n)] += v;
                }
            }
        }
    }
    form
}

/// `Q = G G^T` with `G_ni = phi_n . b_i`.
fn load_coupling(shapes: &DMatrix<f64>, loads: &[SparseVec]) -> DMatrix<f64> {
    let k = shapes.ncols();
    let mut g = DMatrix::<f64>::zeros(k, loads.len());
    for (i, load) in loads.iter().enumerate() {
        for (&dof, &v) in load.idx.iter().zip(&load.val) {
            for n in 0..k {
                g[(n, i)] += v * shapes[(dof, n)];
            }
        }
    }
    &g * g.transpose()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn graded_grid_integrates_a_resonance_to_its_closed_form() {
        // integral_0^inf dw / ((w_n^2 - w^2)^2 + (2 zeta w_n w)^2) = pi / (4 zeta w_n^3)
        // (Newland, table 7.1 case of displacement under white force). In Hz that is
        // divided by 2 pi. Truncating at 100 f_n loses ~ (4 zeta / 3 pi) 1e-6 relative;
        // the grid's trapezoid error is ~2e-4 (see GRADING), so 1e-3 can only fail if
        // the grid misses or under-resolves the peak.
        for zeta in [0.002, 0.02, 0.2] {
            let f_n = 3.78;
            let w_n = 2.0 * PI * f_n;
            let features = [Feature {
                center_hz: f_n,
                width_hz: 2.0 * zeta * f_n,
            }];
            let f_max = 100.0 * f_n;
            let grid = graded_grid(&features, f_max, f_max / 200.0);
            let weights = trapezoid_weights(&grid);
            let integral: f64 = grid
                .iter()
                .zip(&weights)
                .map(|(&f, &w)| {
                    let om = 2.0 * PI * f;
                    w / ((w_n * w_n - om * om).powi(2) + (2.0 * zeta * w_n * om).powi(2))
                })
                .sum();
            let exact = PI / (4.0 * zeta * w_n.powi(3)) / (2.0 * PI);
            assert!(
                (integral / exact - 1.0).abs() < 1e-3,
                "zeta {zeta}: {integral} vs {exact} with {} points",
                grid.len()
            );
            assert!(grid.len() < 2000, "{}", grid.len());
        }
    }

    #[test]
    fn warped_resonance_sits_where_newmark_puts_it() {
        // Average-acceleration Newmark has period elongation ~ (w dt)^2 / 12 (docs/physics.md
        // section 4); the exact warp atan(w dt / 2) / (pi dt) agrees with it up to
        // (1/80 - 1/144) (w dt)^4 relative (next terms of the two series).
        let (w, dt) = (2.0 * PI * 15.12, 0.004);
        let f = warped_resonance(w, 0.02, dt).center_hz;
        let elongation = (w * dt).powi(2) / 12.0;
        let expected = 15.12 / (1.0 + elongation);
        assert!((f / expected - 1.0).abs() < 0.01 * (w * dt).powi(4), "{f}");
    }
}
