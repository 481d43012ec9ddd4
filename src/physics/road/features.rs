//! The deterministic shapes' closed forms: their checks, elevation and slope, and the
//! one-line description stored with a run.

use super::spec::RoadFeature;
use crate::error::{require_finite, require_positive, Result};

impl RoadFeature {
    /// Checks that all values are finite and lengths positive.
    pub fn validate(&self, field_path: &str) -> Result<()> {
        match *self {
            RoadFeature::Step {
                position_m,
                height_m,
            } => {
                require_finite(&format!("{field_path}.position_m"), position_m)?;
                require_finite(&format!("{field_path}.height_m"), height_m)?;
            }
            RoadFeature::Ramp {
                start_m,
                length_m,
                height_m,
            } => {
                require_finite(&format!("{field_path}.start_m"), start_m)?;
                require_positive(&format!("{field_path}.length_m"), length_m)?;
                require_finite(&format!("{field_path}.height_m"), height_m)?;
            }
            RoadFeature::Bump {
                position_m,
                length_m,
                height_m,
            } => {
                require_finite(&format!("{field_path}.position_m"), position_m)?;
                require_positive(&format!("{field_path}.length_m"), length_m)?;
                require_finite(&format!("{field_path}.height_m"), height_m)?;
            }
            RoadFeature::DippedJoint {
                position_m,
                length_m,
                depth_m,
            }
            | RoadFeature::Void {
                position_m,
                length_m,
                depth_m,
            } => {
                require_finite(&format!("{field_path}.position_m"), position_m)?;
                require_positive(&format!("{field_path}.length_m"), length_m)?;
                require_positive(&format!("{field_path}.depth_m"), depth_m)?;
            }
        }
        Ok(())
    }

    /// Elevation (m) and slope (dr/dx) of the shape at `x_m`.
    pub fn evaluate(&self, x_m: f64) -> (f64, f64) {
        match *self {
            RoadFeature::Step {
                position_m,
                height_m,
            } => {
                if x_m >= position_m {
                    (height_m, 0.0)
                } else {
                    (0.0, 0.0)
                }
            }
            RoadFeature::Ramp {
                start_m,
                length_m,
                height_m,
            } => {
                if x_m <= start_m {
                    (0.0, 0.0)
                } else if x_m >= start_m + length_m {
                    (height_m, 0.0)
                } else {
                    let grade = height_m / length_m;
                    (grade * (x_m - start_m), grade)
                }
            }
            RoadFeature::Bump {
                position_m,
                length_m,
                height_m,
            } => {
                let u = x_m - position_m;
                if u.abs() >= 0.5 * length_m {
                    (0.0, 0.0)
                } else {
                    let w = 2.0 * std::f64::consts::PI / length_m;
                    let (s, c) = (w * u).sin_cos();
                    (0.5 * height_m * (1.0 + c), -0.5 * height_m * w * s)
                }
            }
            RoadFeature::DippedJoint {
                position_m,
                length_m,
                depth_m,
            } => {
                let u = x_m - position_m;
                let half = 0.5 * length_m;
                if u.abs() >= half {
                    (0.0, 0.0)
                } else {
                    (
                        -depth_m * (1.0 - u.abs() / half),
                        depth_m / half * u.signum(),
                    )
                }
            }
            RoadFeature::Void {
                position_m,
                length_m,
                depth_m,
            } => RoadFeature::Bump {
                position_m,
                length_m,
                height_m: -depth_m,
            }
            .evaluate(x_m),
        }
    }

    /// One-line description, e.g. `step of 0.02 m at x = 0 m`.
    pub fn describe(&self) -> String {
        match *self {
            RoadFeature::Step {
                position_m,
                height_m,
            } => format!("step of {height_m} m at x = {position_m} m"),
            RoadFeature::Ramp {
                start_m,
                length_m,
                height_m,
            } => format!(
                "ramp of {height_m} m over [{start_m}, {}] m",
                start_m + length_m
            ),
            RoadFeature::Bump {
                position_m,
                length_m,
                height_m,
            } => format!(
                "cosine bump of {height_m} m, {length_m} m long, centred at x = {position_m} m"
            ),
            RoadFeature::DippedJoint {
                position_m,
                length_m,
                depth_m,
            } => format!("dipped joint {depth_m} m deep over {length_m} m at x = {position_m} m"),
            RoadFeature::Void {
                position_m,
                length_m,
                depth_m,
            } => format!("void: {depth_m} m sag over {length_m} m centred at x = {position_m} m"),
        }
    }
}
