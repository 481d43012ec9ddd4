//! How temperature scales the modulus: the bilinear E(T) seen on the Z24 bridge.

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

use crate::error::{require_finite, Error, Result};

/// Temperatures outside this range are held at its ends, so the validated factor stays
/// positive whatever a record or the noise produces (degC).
pub const LAW_RANGE_C: (f64, f64) = (-60.0, 70.0);

/// `E(T) / E_ref`, continuous and piecewise linear with a knee (`environment.stiffness`).
///
/// Z24 (Peeters & De Roeck 2001, Earthq. Eng. Struct. Dyn. 30, 149) shows frequencies
/// nearly flat with a small negative slope above 0 degC and rising steeply below, as the
/// asphalt and the soil at the abutments stiffen. Since f ~ sqrt(E), a relative change of
/// E changes f by about half as much. The default slopes are estimates of that shape, not
/// values fitted to Z24.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct TemperatureStiffnessLaw {
    /// Temperature where E = E_ref, the bridge section's EI (degC) (default 20: the
    /// default constant air temperature, so an unset environment leaves EI unchanged).
    #[serde(default = "default_reference_c")]
    pub reference_c: f64,
    /// Temperature of the knee (degC) (default 0: water in asphalt and soil freezes).
    #[serde(default)]
    pub knee_c: f64,
    /// d(E/E_ref)/dT above the knee, per degC (default -0.0015: -0.15 %/degC on E,
    /// about -0.075 %/degC on f).
    #[serde(default = "default_slope_above_per_c")]
    pub slope_above_knee_per_c: f64,
    /// d(E/E_ref)/dT below the knee, per degC (default -0.03: E rises 3 % per degC of
    /// cooling, about 1.5 % on f).
    #[serde(default = "default_slope_below_per_c")]
    pub slope_below_knee_per_c: f64,
}

fn default_reference_c() -> f64 {
    20.0
}
fn default_slope_above_per_c() -> f64 {
    -0.0015
}
fn default_slope_below_per_c() -> f64 {
    -0.03
}

impl Default for TemperatureStiffnessLaw {
    fn default() -> Self {
        Self {
            reference_c: default_reference_c(),
            knee_c: 0.0,
            slope_above_knee_per_c: default_slope_above_per_c(),
            slope_below_knee_per_c: default_slope_below_per_c(),
        }
    }
}

impl TemperatureStiffnessLaw {
    /// Checks the fields and that the factor stays positive over [`LAW_RANGE_C`] (being
    /// piecewise linear, checking the range ends suffices); `path` is
    /// `environment.stiffness`.
    pub fn validate(&self, path: &str) -> Result<()> {
        require_finite(&format!("{path}.reference_c"), self.reference_c)?;
        require_finite(&format!("{path}.knee_c"), self.knee_c)?;
        require_finite(
            &format!("{path}.slope_above_knee_per_c"),
            self.slope_above_knee_per_c,
        )?;
        require_finite(
            &format!("{path}.slope_below_knee_per_c"),
            self.slope_below_knee_per_c,
        )?;
        let (cold_c, hot_c) = LAW_RANGE_C;
        for (field, slope, at_c) in [
            (
                "slope_below_knee_per_c",
                self.slope_below_knee_per_c,
                cold_c,
            ),
            ("slope_above_knee_per_c", self.slope_above_knee_per_c, hot_c),
        ] {
            let factor = self.factor(at_c);
            if factor <= 0.0 {
                return Err(Error::invalid(
                    format!("{path}.{field}"),
                    slope,
                    format!("gives E/E_ref = {factor} <= 0 at {at_c} degC"),
                ));
            }
        }
        Ok(())
    }

    /// E(T) / E_ref at structure temperature `temperature_c`.
    pub fn factor(&self, temperature_c: f64) -> f64 {
        let (cold_c, hot_c) = LAW_RANGE_C;
        let t_c = temperature_c.clamp(cold_c, hot_c);
        1.0 + self.offset(t_c) - self.offset(self.reference_c)
    }

    /// Integral of the slope from the knee to `t_c`.
    fn offset(&self, t_c: f64) -> f64 {
        let slope = if t_c >= self.knee_c {
            self.slope_above_knee_per_c
        } else {
            self.slope_below_knee_per_c
        };
        slope * (t_c - self.knee_c)
    }
}
