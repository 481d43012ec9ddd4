//! What the tyres roll on: the [`RoadSurface`] the coupled solver reads, its implementation
//! for a built [`RoadProfile`], and the closed-form surfaces that checks and tests drive on.

use super::RoadProfile;

/// The road surface the tyres roll on (elevation upward positive, m).
pub trait RoadSurface {
    fn elevation_m(&self, x_m: f64) -> f64;
    /// dr/dx (m/m).
    fn slope(&self, x_m: f64) -> f64;
    /// Both at once (a profile finds its interval once).
    fn elevation_and_slope(&self, x_m: f64) -> (f64, f64) {
        (self.elevation_m(x_m), self.slope(x_m))
    }
}

impl RoadSurface for RoadProfile {
    fn elevation_m(&self, x_m: f64) -> f64 {
        RoadProfile::elevation_m(self, x_m)
    }
    fn slope(&self, x_m: f64) -> f64 {
        RoadProfile::slope(self, x_m)
    }
    fn elevation_and_slope(&self, x_m: f64) -> (f64, f64) {
        RoadProfile::elevation_and_slope(self, x_m)
    }
}

/// A level road: `r(x) = 0`.
#[derive(Debug, Clone, Copy, Default)]
pub struct LevelRoad;

impl RoadSurface for LevelRoad {
    fn elevation_m(&self, _x_m: f64) -> f64 {
        0.0
    }
    fn slope(&self, _x_m: f64) -> f64 {
        0.0
    }
}

/// A level road raised (or lowered) everywhere: `r(x) = elevation_m`.
#[derive(Debug, Clone, Copy, Default)]
pub struct ConstantRoad {
    pub elevation_m: f64,
}

impl RoadSurface for ConstantRoad {
    fn elevation_m(&self, _x_m: f64) -> f64 {
        self.elevation_m
    }
    fn slope(&self, _x_m: f64) -> f64 {
        0.0
    }
}

/// A sinusoidal road `r(x) = A sin(k x)`, with its exact slope `A k cos(k x)`.
#[derive(Debug, Clone, Copy)]
pub struct SineRoad {
    pub amplitude_m: f64,
    pub wavenumber_rad_m: f64,
}

impl RoadSurface for SineRoad {
    fn elevation_m(&self, x_m: f64) -> f64 {
        self.amplitude_m * (self.wavenumber_rad_m * x_m).sin()
    }
    fn slope(&self, x_m: f64) -> f64 {
        self.amplitude_m * self.wavenumber_rad_m * (self.wavenumber_rad_m * x_m).cos()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::physics::road::RoadProfileSpec;
    use rand::SeedableRng;
    use rand_chacha::ChaCha8Rng;

    #[test]
    fn a_profile_is_seen_as_it_evaluates() {
        let spec = RoadProfileSpec::Bump {
            position_m: 2.0,
            length_m: 1.0,
            height_m: 0.01,
        };
        let mut rng = ChaCha8Rng::seed_from_u64(0);
        let profile = RoadProfile::build(&spec, 0.0, 5.0, &mut rng).unwrap();
        let surface: &dyn RoadSurface = &profile;
        for x in [0.0, 1.7, 2.4, 2.5, 4.0] {
            assert_eq!(surface.elevation_m(x), profile.elevation_m(x));
            assert_eq!(surface.slope(x), profile.slope(x));
        }
    }

    #[test]
    fn the_sine_slope_is_the_derivative() {
        let road = SineRoad {
            amplitude_m: 0.005,
            wavenumber_rad_m: 0.7,
        };
        // Central difference, h = 1e-4 m: truncation A k^3 h^2 / 6 ~ 3e-12, round-off
        // ~ 1e-16 * A / h ~ 5e-15: the slope (~3.5e-3) agrees to 1e-10.
        let h = 1e-4;
        for x in [-3.0, 0.0, 1.1, 8.0] {
            let fd = (road.elevation_m(x + h) - road.elevation_m(x - h)) / (2.0 * h);
            assert!((fd - road.slope(x)).abs() < 1e-10, "x = {x}");
        }
        let raised = ConstantRoad { elevation_m: 0.05 };
        assert_eq!((raised.elevation_m(7.0), raised.slope(7.0)), (0.05, 0.0));
        assert_eq!(
            (LevelRoad.elevation_m(7.0), LevelRoad.slope(7.0)),
            (0.0, 0.0)
        );
    }
}
