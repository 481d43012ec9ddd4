//! Exact natural frequencies of a simply supported Euler-Bernoulli beam whose flexural
//! rigidity is piecewise constant (a stepped beam: local damage, a thicker middle, ...),
//! with uniform mass, by the transfer-matrix method.
//!
//! In each segment `EI w'''' = m omega^2 w` has the exact solution written with the
//! Krylov functions of `z = beta x`, `beta^4 = m omega^2 / EI`:
//! `S = (cosh z + cos z) / 2`, `T = (sinh z + sin z) / 2`, `U = (cosh z - cos z) / 2`,
//! `V = (sinh z - sin z) / 2` (Pestel and Leckie, *Matrix Methods in Elastomechanics*,
//! 1963; any structural-dynamics text with the transfer-matrix method). They carry the
//! state `(w, w', M = EI w'', Q = EI w''')` across a segment exactly; the state is
//! continuous where EI steps (no point mass, no hinge). At `x = 0`, `w = M = 0`: the state
//! is spanned by the two unknowns `w'(0)` and `Q(0)`, and the frequency is a root of the
//! 2 x 2 determinant of `(w(L), M(L))` over them. No discretization: the value is exact to
//! the root finder's tolerance, so it is an independent reference for the meshes.

use std::f64::consts::PI;

/// One segment of constant EI, in order from the left support.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Segment {
    /// Segment length (m).
    pub length_m: f64,
    /// Flexural rigidity over the segment (N m^2).
    pub flexural_rigidity_n_m2: f64,
}

/// A simply supported beam of uniform mass and piecewise-constant EI.
#[derive(Debug, Clone, PartialEq)]
pub struct SteppedBeam {
    /// Mass per unit length (kg/m).
    pub mass_per_length_kg_m: f64,
    /// The segments from the left support to the right; their lengths sum to the span.
    pub segments: Vec<Segment>,
}

/// State `(w, w', M, Q)` after a segment of length `l` for `beta` (1/m), given the state
/// at its start (sign convention of the Krylov solution above).
fn carry(state: [f64; 4], beta: f64, l: f64, ei: f64) -> [f64; 4] {
    let z = beta * l;
    let (ch, sh, c, s) = (z.cosh(), z.sinh(), z.cos(), z.sin());
    let (fs, ft, fu, fv) = (
        0.5 * (ch + c),
        0.5 * (sh + s),
        0.5 * (ch - c),
        0.5 * (sh - s),
    );
    let [w, th, m, q] = state;
    let (m_ei, q_ei) = (m / ei, q / ei);
    let b = beta;
    [
        w * fs + th * ft / b + m_ei * fu / (b * b) + q_ei * fv / (b * b * b),
        w * b * fv + th * fs + m_ei * ft / b + q_ei * fu / (b * b),
        ei * (w * b * b * fu + th * b * fv + m_ei * fs + q_ei * ft / b),
        ei * (w * b * b * b * ft + th * b * b * fu + m_ei * b * fv + q_ei * fs),
    ]
}

impl SteppedBeam {
    /// Span (m).
    pub fn span_m(&self) -> f64 {
        self.segments.iter().map(|s| s.length_m).sum()
    }

    /// The frequency determinant at circular frequency `omega` (rad/s): zero at a natural
    /// frequency. Columns scaled so that a uniform beam's determinant is
    /// `sin(beta L) sinh(beta L)` up to a positive factor.
    pub fn determinant(&self, omega_rad_s: f64) -> f64 {
        let ei_ref = self.segments[0].flexural_rigidity_n_m2;
        let beta_of = |ei: f64| (self.mass_per_length_kg_m * omega_rad_s.powi(2) / ei).powf(0.25);
        let beta_ref = beta_of(ei_ref);
        // Unit slope, and a shear force scaled to give the same order of deflection.
        let mut a = [0.0, 1.0, 0.0, 0.0];
        let mut b = [0.0, 0.0, 0.0, ei_ref * beta_ref * beta_ref];
        for seg in &self.segments {
            let beta = beta_of(seg.flexural_rigidity_n_m2);
            a = carry(a, beta, seg.length_m, seg.flexural_rigidity_n_m2);
            b = carry(b, beta, seg.length_m, seg.flexural_rigidity_n_m2);
        }
        let m_scale = 1.0 / (ei_ref * beta_ref);
        a[0] * b[2] * m_scale - b[0] * a[2] * m_scale
    }

    /// Natural frequency of mode `n` (1-based) in Hz, bracketed on a grid that resolves
    /// each mode of the uniform beam with the smallest EI and refined by bisection to
    /// `1e-14` relative.
    pub fn frequency_hz(&self, n: usize) -> f64 {
        assert!(n >= 1, "modes are numbered from 1");
        let span = self.span_m();
        let m = self.mass_per_length_kg_m;
        let ei_bounds = self
            .segments
            .iter()
            .map(|s| s.flexural_rigidity_n_m2)
            .fold((f64::INFINITY, 0.0f64), |(lo, hi), e| {
                (lo.min(e), hi.max(e))
            });
        // Mode n lies between the uniform beams of the smallest and the largest EI
        // (Rayleigh's principle: lowering EI anywhere lowers every frequency).
        let omega_uniform = |ei: f64, k: usize| (k as f64 * PI / span).powi(2) * (ei / m).sqrt();
        let lo = 0.5 * omega_uniform(ei_bounds.0, 1);
        let hi = omega_uniform(ei_bounds.1, n + 1);
        let steps = 400 * (n + 1);
        let mut found = 0;
        let mut w_prev = lo;
        let mut d_prev = self.determinant(lo);
        for i in 1..=steps {
            let w = lo + (hi - lo) * i as f64 / steps as f64;
            let d = self.determinant(w);
            if d == 0.0 || d.signum() != d_prev.signum() {
                found += 1;
                if found == n {
                    return self.bisect(w_prev, w, d_prev) / (2.0 * PI);
                }
            }
            (w_prev, d_prev) = (w, d);
        }
        panic!("mode {n} not bracketed in [{lo}, {hi}] rad/s");
    }

    fn bisect(&self, mut lo: f64, mut hi: f64, d_lo: f64) -> f64 {
        let sign_lo = d_lo.signum();
        while hi - lo > 1e-14 * hi {
            let mid = 0.5 * (lo + hi);
            let d = self.determinant(mid);
            if d == 0.0 {
                return mid;
            }
            if d.signum() == sign_lo {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        0.5 * (lo + hi)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn uniform(parts: usize) -> SteppedBeam {
        SteppedBeam {
            mass_per_length_kg_m: 9_000.0,
            segments: vec![
                Segment {
                    length_m: 30.0 / parts as f64,
                    flexural_rigidity_n_m2: 2.5e10,
                };
                parts
            ],
        }
    }

    #[test]
    fn a_uniform_beam_cut_anywhere_has_the_closed_form_frequencies() {
        // f_n = (n pi / L)^2 sqrt(EI / m) / (2 pi), however the beam is cut in segments.
        for parts in [1, 3, 7] {
            let beam = uniform(parts);
            for n in 1..=4 {
                let exact =
                    (n as f64 * PI / 30.0).powi(2) * (2.5e10f64 / 9_000.0).sqrt() / (2.0 * PI);
                let f = beam.frequency_hz(n);
                // The determinant sums terms of size cosh(beta L) ~ cosh(n pi) that cancel at
                // the root: round-off moves the root by up to about eps cosh(n pi) relative
                // (3e-11 at n = 4; 2.3e-12 measured, the cancellation being partial).
                let tol = f64::EPSILON * (n as f64 * PI).cosh();
                assert!(
                    (f / exact - 1.0).abs() < tol,
                    "{parts} parts, mode {n}: {f} vs {exact}"
                );
            }
        }
    }

    #[test]
    fn a_symmetric_step_keeps_the_even_modes_when_it_sits_at_their_node() {
        // Mode 2 of a simply supported beam has zero curvature at midspan: a short softer
        // piece centred there barely moves it, while mode 1 (largest curvature there) falls.
        let soft = |len: f64| SteppedBeam {
            mass_per_length_kg_m: 9_000.0,
            segments: vec![
                Segment {
                    length_m: 15.0 - len / 2.0,
                    flexural_rigidity_n_m2: 2.5e10,
                },
                Segment {
                    length_m: len,
                    flexural_rigidity_n_m2: 1.5e10,
                },
                Segment {
                    length_m: 15.0 - len / 2.0,
                    flexural_rigidity_n_m2: 2.5e10,
                },
            ],
        };
        let (u, s) = (uniform(1), soft(0.3));
        let drop1 = 1.0 - s.frequency_hz(1) / u.frequency_hz(1);
        let drop2 = 1.0 - s.frequency_hz(2) / u.frequency_hz(2);
        assert!(drop1 > 1e-3, "mode 1 falls: {drop1}");
        assert!((0.0..1e-5).contains(&drop2), "mode 2 barely moves: {drop2}");
    }

    #[test]
    fn a_beam_softer_everywhere_scales_as_the_square_root_of_ei() {
        let beam = uniform(2);
        let mut soft = beam.clone();
        for s in &mut soft.segments {
            s.flexural_rigidity_n_m2 *= 0.64;
        }
        let ratio = soft.frequency_hz(1) / beam.frequency_hz(1);
        assert!((ratio - 0.8).abs() < 1e-12, "{ratio}");
    }
}
