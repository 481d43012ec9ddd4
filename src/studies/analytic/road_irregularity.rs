//! Deterministic road irregularities for the sprung-mass reference: an elevation profile
//! `r(x)` (m, positive UPWARD) with its slope, given as closures.

use std::fmt;

use crate::error::{Error, Result};

type ProfileFn = Box<dyn Fn(f64) -> f64 + Send + Sync>;

/// A deterministic road irregularity: elevation `r(x)` (m, positive UPWARD), its slope
/// `dr/dx`, and the positions where the slope jumps (the integration restarts there).
/// Defined along the whole road, on and off the beam.
pub struct RoadIrregularity {
    elevation: ProfileFn,
    slope: ProfileFn,
    kinks_m: Vec<f64>,
    description: String,
}

impl fmt::Debug for RoadIrregularity {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("RoadIrregularity")
            .field("description", &self.description)
            .field("kinks_m", &self.kinks_m)
            .finish()
    }
}

impl RoadIrregularity {
    /// A profile from closures for the elevation `r(x)` and its slope, and the sorted
    /// positions of slope discontinuities.
    pub fn new(
        elevation: impl Fn(f64) -> f64 + Send + Sync + 'static,
        slope: impl Fn(f64) -> f64 + Send + Sync + 'static,
        kinks_m: Vec<f64>,
        description: impl Into<String>,
    ) -> Self {
        Self {
            elevation: Box::new(elevation),
            slope: Box::new(slope),
            kinks_m,
            description: description.into(),
        }
    }

    /// A linear ramp: elevation 0 for `x <= start_m`, rising linearly to `height_m` at
    /// `end_m`, and `height_m` beyond (a step smoothed over `end_m - start_m`).
    /// The reference case uses `linear_ramp(5.0, 10.0, 0.010)`: +10 mm over x = 5..10 m.
    pub fn linear_ramp(start_m: f64, end_m: f64, height_m: f64) -> Result<Self> {
        if !(start_m.is_finite() && end_m.is_finite() && end_m > start_m) {
            return Err(Error::invalid(
                "ramp.end_m",
                end_m,
                format!("must be finite and > start_m = {start_m}"),
            ));
        }
        if !height_m.is_finite() {
            return Err(Error::invalid("ramp.height_m", height_m, "must be finite"));
        }
        let grade = height_m / (end_m - start_m);
        Ok(Self::new(
            move |x| {
                if x <= start_m {
                    0.0
                } else if x >= end_m {
                    height_m
                } else {
                    grade * (x - start_m)
                }
            },
            move |x| {
                if x > start_m && x < end_m {
                    grade
                } else {
                    0.0
                }
            },
            vec![start_m, end_m],
            format!("linear ramp of {height_m} m over x = {start_m}..{end_m} m"),
        ))
    }

    /// A raised-cosine bump `h/2 (1 + cos(2 pi (x - position_m) / length_m))` over
    /// `|x - position_m| < length_m / 2`, zero elsewhere. Its slope is continuous (no
    /// kinks): the bump of the road module's `bump` shape, written here from the formula.
    pub fn cosine_bump(position_m: f64, length_m: f64, height_m: f64) -> Result<Self> {
        if !(length_m.is_finite() && length_m > 0.0) {
            return Err(Error::invalid(
                "bump.length_m",
                length_m,
                "must be finite and > 0",
            ));
        }
        if !(position_m.is_finite() && height_m.is_finite()) {
            return Err(Error::invalid(
                "bump.position_m",
                format!("{position_m} (height_m {height_m})"),
                "position and height must be finite",
            ));
        }
        let k = 2.0 * std::f64::consts::PI / length_m;
        let half = 0.5 * length_m;
        Ok(Self::new(
            move |x| {
                let u = x - position_m;
                if u.abs() < half {
                    0.5 * height_m * (1.0 + (k * u).cos())
                } else {
                    0.0
                }
            },
            move |x| {
                let u = x - position_m;
                if u.abs() < half {
                    -0.5 * height_m * k * (k * u).sin()
                } else {
                    0.0
                }
            },
            Vec::new(),
            format!(
                "cosine bump of {height_m} m, {length_m} m long, centred at x = {position_m} m"
            ),
        ))
    }

    /// Elevation at `x_m`, m (positive upward).
    pub fn elevation_m(&self, x_m: f64) -> f64 {
        (self.elevation)(x_m)
    }

    /// Slope `dr/dx` at `x_m`.
    pub fn slope(&self, x_m: f64) -> f64 {
        (self.slope)(x_m)
    }

    /// Positions of slope discontinuities, m.
    pub fn kinks_m(&self) -> &[f64] {
        &self.kinks_m
    }

    /// What the profile is (for reports).
    pub fn description(&self) -> &str {
        &self.description
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Crest `h` at the centre, zero at and beyond the ends, and the slope is the
    /// derivative of the elevation (central differences, error ~ (k dx)^2 / 6).
    #[test]
    fn cosine_bump_shape_and_slope() {
        let bump = RoadIrregularity::cosine_bump(6.0, 3.0, 0.010).unwrap();
        assert!((bump.elevation_m(6.0) - 0.010).abs() < 1e-15);
        for x in [4.5, 7.5, 0.0, 20.0] {
            assert_eq!(bump.elevation_m(x), 0.0, "x {x}");
            assert_eq!(bump.slope(x), 0.0, "x {x}");
        }
        let dx = 1e-5;
        for x in [4.7, 5.3, 6.2, 7.1] {
            let fd = (bump.elevation_m(x + dx) - bump.elevation_m(x - dx)) / (2.0 * dx);
            assert!(
                (fd - bump.slope(x)).abs() < 1e-9,
                "x {x}: {fd} vs {}",
                bump.slope(x)
            );
        }
        assert!(bump.kinks_m().is_empty());
        assert!(RoadIrregularity::cosine_bump(6.0, 0.0, 0.01).is_err());
    }
}
