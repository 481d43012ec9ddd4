//! Closed-form envelopes of the first-mode response of a simply supported span under a
//! train of moving loads: the residual-vibration method (LIR, "ligne d'influence
//! residuelle") and the dynamic envelope of resonance (DER), both of ERRI D214 (1999),
//! used in the Spanish IAPF and behind EN 1991-2 Annex E's train signatures. Formulas as
//! implemented in the UPM CALDINTAV code (functions `LIR` and `DER`); the LIR single-load
//! factor is also derived here (see [`lir_acceleration_m_s2`]), which checks it.
//!
//! Loads are `(x_m, force_n)`: positions behind the first axle and downward forces.

use std::f64::consts::PI;

/// The span: simply supported, uniform, mode 1 only.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ResonanceSpan {
    pub length_m: f64,
    pub mass_per_length_kg_m: f64,
    /// First natural frequency (Hz).
    pub f1_hz: f64,
    /// Damping ratio of mode 1.
    pub zeta: f64,
}

/// Residual-vibration envelope of the midspan acceleration (m/s^2) at speed `v`.
///
/// One load P crossing the span at `v` leaves mode 1 (modal mass mL/2, force
/// `P sin(pi v t / L)`) vibrating freely; solving the undamped forced phase in closed form
/// and taking `(q, q'/w)` at exit gives the residual acceleration amplitude
/// `(2 P / (m L)) 2K / (1 - K^2) |cos(pi / (2K))|`, `K = v / (2 f1 L) = lambda / (2L)`:
/// the LIR factor `A(K)` below at zeta = 0 (`sqrt(2 + 2 cos(pi/K)) = 2 |cos(pi/(2K))|`).
/// The loads' residual vibrations add with phase `2 pi delta_i` and decay
/// `exp(-2 pi zeta delta_i)`, `delta_i = (x_k - x_i) / lambda`; the envelope is the largest
/// sum over the train's first k loads.
pub fn lir_acceleration_m_s2(span: &ResonanceSpan, loads: &[(f64, f64)], speed_m_s: f64) -> f64 {
    let lambda = speed_m_s / span.f1_hz;
    let k = lambda / (2.0 * span.length_m);
    let z = span.zeta;
    let a = k / (1.0 - k * k)
        * ((-2.0 * z * PI / k).exp() + 1.0 + 2.0 * (PI / k).cos() * (-z * PI / k).exp())
            .max(0.0)
            .sqrt();
    let a = if (k - 1.0).abs() < 1e-9 {
        // K = 1: 0/0; the limit of the undamped factor is pi/2 (l'Hopital).
        PI / 2.0
    } else {
        a.abs()
    };
    let g = (0..loads.len())
        .map(|last| {
            let x_k = loads[last].0;
            let (mut re, mut im) = (0.0, 0.0);
            for &(x_i, p) in &loads[..=last] {
                let delta = (x_k - x_i) / lambda;
                let decay = (-2.0 * PI * z * delta).exp();
                re += p * decay * (2.0 * PI * delta).cos();
                im += p * decay * (2.0 * PI * delta).sin();
            }
            re.hypot(im)
        })
        .fold(0.0, f64::max);
    2.0 / (span.mass_per_length_kg_m * span.length_m) * a * g
}

/// Dynamic envelope of resonance of the midspan acceleration (m/s^2) at speed `v`:
/// `a = 4 / (pi m) A(L / lambda) G(lambda)` with `A(r) = |cos(pi r) / ((2r)^2 - 1)|` and the
/// train signature `G(lambda) = max_i (1 - exp(-2 pi zeta x_i / lambda)) / (zeta x_i)
/// |sum_{k <= i} P_k exp(2 pi i x_k / lambda)|` (x from the first axle).
pub fn der_acceleration_m_s2(span: &ResonanceSpan, loads: &[(f64, f64)], speed_m_s: f64) -> f64 {
    let lambda = speed_m_s / span.f1_hz;
    let r = span.length_m / lambda;
    let a = if (2.0 * r - 1.0).abs() < 1e-9 {
        PI / 4.0 // the 0/0 limit at L = lambda / 2
    } else {
        ((PI * r).cos() / (4.0 * r * r - 1.0)).abs()
    };
    let z = span.zeta;
    let x0 = loads.first().map_or(0.0, |l| l.0);
    let (mut re, mut im, mut g) = (0.0f64, 0.0f64, 0.0f64);
    for &(x, p) in loads {
        let x = x - x0;
        re += p * (2.0 * PI * x / lambda).cos();
        im += p * (2.0 * PI * x / lambda).sin();
        let weight = if x == 0.0 || z == 0.0 {
            2.0 * PI / lambda
        } else {
            (1.0 - (-2.0 * PI * z * x / lambda).exp()) / (z * x)
        };
        g = g.max(weight * re.hypot(im));
    }
    4.0 / (PI * span.mass_per_length_kg_m) * a * g
}

/// The speeds (m/s) at which loads repeating every `spacing_m` resonate with mode 1:
/// `v_i = f1 spacing / i`, i = 1, 2, ... within `[lo, hi]`.
pub fn resonance_speeds_m_s(f1_hz: f64, spacing_m: f64, lo: f64, hi: f64) -> Vec<(usize, f64)> {
    (1..=20)
        .map(|i| (i, f1_hz * spacing_m / i as f64))
        .filter(|&(_, v)| (lo..=hi).contains(&v))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn one_load_leaves_the_residual_vibration_of_the_closed_form() {
        // Undamped, one load: A(K) = 2K/(1-K^2)|cos(pi/(2K))| (derived above), at a speed
        // away from cancellation.
        let span = ResonanceSpan {
            length_m: 20.0,
            mass_per_length_kg_m: 10_000.0,
            f1_hz: 5.0,
            zeta: 0.0,
        };
        let v = 60.0;
        let k = v / (2.0 * 5.0 * 20.0);
        let want =
            2.0 * 1e5 / (1e4 * 20.0) * 2.0 * k / (1.0 - k * k) * (PI / (2.0 * k)).cos().abs();
        let got = lir_acceleration_m_s2(&span, &[(0.0, 1e5)], v);
        assert!((got / want - 1.0).abs() < 1e-12, "{got} vs {want}");
    }

    #[test]
    fn regular_loads_grow_at_resonance_and_cancel_between() {
        // 20 loads every 20 m on a 15 m span: at v = f1 d the residuals add in phase.
        let span = ResonanceSpan {
            length_m: 15.0,
            mass_per_length_kg_m: 15_000.0,
            f1_hz: 5.0,
            zeta: 0.01,
        };
        let loads: Vec<(f64, f64)> = (0..20).map(|i| (20.0 * i as f64, 2e5)).collect();
        let at = |v| lir_acceleration_m_s2(&span, &loads, v);
        let resonance = at(100.0);
        // In phase, 20 damped residuals add to ~12 P; 10 % off, the partial sums of phasors
        // turning by 0.2 pi stay below ~3 P.
        assert!(resonance > 3.0 * at(90.0) && resonance > 3.0 * at(110.0));
        let der = |v| der_acceleration_m_s2(&span, &loads, v);
        assert!(der(100.0) > 3.0 * der(90.0));
    }
}
