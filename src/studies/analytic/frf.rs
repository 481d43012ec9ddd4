//! Steady-state response of a linear MDOF system to a harmonic base (road) input.
//!
//! For `M y'' + C y' + K y = B_k r + B_c r'` with `r(t) = R sin(w t)`, the steady state is
//! `y_j(t) = |Y_j| sin(w t + phi_j)` with the complex amplitude
//!
//! `Y = (K - w^2 M + i w C)^-1 (B_k + i w B_c) R`
//!
//! (Clough & Penzien, Dynamics of Structures, section 12-7: substitute `r = Im(R e^(iwt))`
//! and `y = Im(Y e^(iwt))`). Used to verify vehicle models on sinusoidal roads.

use nalgebra::{Complex, DMatrix, DVector};

use crate::error::{require_finite, Error, Result};

/// Steady-state harmonic response, one entry per degree of freedom.
#[derive(Debug, Clone, PartialEq)]
pub struct HarmonicResponse {
    /// Input circular frequency w, rad/s.
    pub omega_rad_s: f64,
    /// Complex amplitude `Y_j`: `y_j(t) = Im(Y_j e^(i w t))`.
    pub complex_amplitude: DVector<Complex<f64>>,
}

impl HarmonicResponse {
    /// Amplitude `|Y_j|` per DOF (units of `y`).
    pub fn amplitudes(&self) -> DVector<f64> {
        self.complex_amplitude.map(|c| c.norm())
    }

    /// Phase `phi_j = arg(Y_j)` per DOF, rad, in `(-pi, pi]`: `y_j = |Y_j| sin(w t + phi_j)`,
    /// so a response lagging the input has a negative phase.
    pub fn phases_rad(&self) -> DVector<f64> {
        self.complex_amplitude.map(|c| c.arg())
    }

    /// Response of DOF `j` at time `t_s`.
    pub fn value_at(&self, j: usize, t_s: f64) -> f64 {
        self.complex_amplitude.get(j).map_or(0.0, |c| {
            (c * Complex::from_polar(1.0, self.omega_rad_s * t_s)).im
        })
    }
}

/// Complex amplitude of the steady-state response of `M y'' + C y' + K y = B_k r + B_c r'`
/// to `r = amplitude sin(omega t)`; see the module docs. Errors on mismatched dimensions,
/// non-finite input or a singular dynamic stiffness (undamped resonance).
pub fn harmonic_response(
    mass: &DMatrix<f64>,
    damping: &DMatrix<f64>,
    stiffness: &DMatrix<f64>,
    b_stiffness: &DVector<f64>,
    b_damping: &DVector<f64>,
    omega_rad_s: f64,
    amplitude: f64,
) -> Result<HarmonicResponse> {
    let n = mass.nrows();
    for (name, m) in [
        ("mass", mass),
        ("damping", damping),
        ("stiffness", stiffness),
    ] {
        if m.shape() != (n, n) {
            return Err(Error::invalid(
                format!("{name}.shape"),
                format!("{:?}", m.shape()),
                format!("must be ({n}, {n})"),
            ));
        }
        if m.iter().any(|v| !v.is_finite()) {
            return Err(Error::invalid(name, "matrix", "has non-finite entries"));
        }
    }
    for (name, b) in [("b_stiffness", b_stiffness), ("b_damping", b_damping)] {
        if b.len() != n {
            return Err(Error::invalid(
                format!("{name}.len()"),
                b.len(),
                format!("must be {n}"),
            ));
        }
    }
    require_finite("omega_rad_s", omega_rad_s)?;
    require_finite("amplitude", amplitude)?;
    let w = omega_rad_s;
    let dynamic = DMatrix::from_fn(n, n, |i, j| {
        Complex::new(
            stiffness[(i, j)] - w * w * mass[(i, j)],
            w * damping[(i, j)],
        )
    });
    let rhs = DVector::from_fn(n, |i, _| {
        Complex::new(b_stiffness[i] * amplitude, w * b_damping[i] * amplitude)
    });
    let solution = dynamic
        .lu()
        .solve(&rhs)
        .ok_or_else(|| Error::Factorization {
            what: "dynamic stiffness K - w^2 M + i w C".into(),
            reason: format!("singular at omega = {w} rad/s (undamped resonance?)"),
        })?;
    if solution
        .iter()
        .any(|c| !c.re.is_finite() || !c.im.is_finite())
    {
        return Err(Error::Factorization {
            what: "dynamic stiffness K - w^2 M + i w C".into(),
            reason: format!("numerically singular at omega = {w} rad/s"),
        });
    }
    Ok(HarmonicResponse {
        omega_rad_s: w,
        complex_amplitude: solution,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn residual_of_a_two_dof_system_vanishes() {
        // Quarter car: body over axle, tyre to the road (stiffness and damping).
        let mass = DMatrix::from_row_slice(2, 2, &[400.0, 0.0, 0.0, 40.0]);
        let k = DMatrix::from_row_slice(2, 2, &[2.0e4, -2.0e4, -2.0e4, 2.0e4 + 2.0e5]);
        let c = DMatrix::from_row_slice(2, 2, &[1.5e3, -1.5e3, -1.5e3, 1.5e3 + 100.0]);
        let bk = DVector::from_vec(vec![0.0, 2.0e5]);
        let bc = DVector::from_vec(vec![0.0, 100.0]);
        let w = 30.0;
        let resp = harmonic_response(&mass, &c, &k, &bk, &bc, w, 0.01).unwrap();
        // Time-domain residual at a few instants: M y'' + C y' + K y - B_k r - B_c r' = 0.
        for &t in &[0.0, 0.1, 0.37] {
            let y = DVector::from_fn(2, |j, _| resp.value_at(j, t));
            let yd = DVector::from_fn(2, |j, _| {
                (resp.complex_amplitude[j] * Complex::new(0.0, w) * Complex::from_polar(1.0, w * t))
                    .im
            });
            let ydd = -y.clone() * (w * w);
            let r = 0.01 * (w * t).sin();
            let rd = 0.01 * w * (w * t).cos();
            let res = &mass * ydd + &c * yd + &k * y - &bk * r - &bc * rd;
            assert!(res.norm() < 1e-9, "{res}");
        }
    }

    #[test]
    fn undamped_resonance_is_an_error() {
        let m = DMatrix::from_element(1, 1, 1.0);
        let c = DMatrix::zeros(1, 1);
        let k = DMatrix::from_element(1, 1, 4.0);
        let b = DVector::from_element(1, 4.0);
        let z = DVector::zeros(1);
        assert!(harmonic_response(&m, &c, &k, &b, &z, 2.0, 1.0).is_err());
        assert!(harmonic_response(&m, &c, &k, &b, &z, 1.0, 1.0).is_ok());
    }
}
