//! Piecewise cubic Hermite curve through knots with given values and slopes.
//!
//! The slope returned is the exact derivative of the interpolated elevation, so the contact
//! rate `v dr/dx` is consistent with the elevation the tyre sees. On a uniform grid the
//! knot is found in O(1); otherwise by binary search.

/// Knot positions: a uniform grid (nothing stored) or a list.
#[derive(Debug, Clone)]
enum Knots {
    Uniform {
        x0_m: f64,
        dx_m: f64,
        inv_dx: f64,
    },
    /// Strictly increasing; `inv_dx` is set when they are uniform to 1e-9 of their mean
    /// spacing, for O(1) lookup.
    Listed {
        x_m: Vec<f64>,
        inv_dx: Option<f64>,
    },
}

/// Knots (at least 2) with values `z` and slopes `slope`.
#[derive(Debug, Clone)]
pub(crate) struct HermiteCurve {
    knots: Knots,
    z_m: Vec<f64>,
    slope: Vec<f64>,
}

impl HermiteCurve {
    /// A curve on the uniform grid `x0 + i dx`, i = 0 .. z_m.len().
    pub fn uniform(x0_m: f64, dx_m: f64, z_m: Vec<f64>, slope: Vec<f64>) -> Self {
        HermiteCurve {
            knots: Knots::Uniform {
                x0_m,
                dx_m,
                inv_dx: 1.0 / dx_m,
            },
            z_m,
            slope,
        }
    }

    /// A curve through arbitrary strictly increasing knots, with slopes estimated by the
    /// three-point finite difference (exact for quadratics; one-sided at the ends).
    pub fn through(x_m: Vec<f64>, z_m: Vec<f64>) -> Self {
        let n = x_m.len();
        let mut slope = vec![0.0; n];
        if n >= 2 {
            slope[0] = (z_m[1] - z_m[0]) / (x_m[1] - x_m[0]);
            slope[n - 1] = (z_m[n - 1] - z_m[n - 2]) / (x_m[n - 1] - x_m[n - 2]);
        }
        for i in 1..n.saturating_sub(1) {
            let (h0, h1) = (x_m[i] - x_m[i - 1], x_m[i + 1] - x_m[i]);
            let (d0, d1) = ((z_m[i] - z_m[i - 1]) / h0, (z_m[i + 1] - z_m[i]) / h1);
            slope[i] = (h1 * d0 + h0 * d1) / (h0 + h1);
        }
        let inv_dx = if n >= 2 {
            let dx = (x_m[n - 1] - x_m[0]) / (n - 1) as f64;
            let uniform = x_m
                .iter()
                .enumerate()
                .all(|(i, &x)| (x - (x_m[0] + i as f64 * dx)).abs() <= 1e-9 * dx);
            uniform.then_some(1.0 / dx)
        } else {
            None
        };
        HermiteCurve {
            knots: Knots::Listed { x_m, inv_dx },
            z_m,
            slope,
        }
    }

    /// Position of knot `i`.
    fn x(&self, i: usize) -> f64 {
        match &self.knots {
            Knots::Uniform { x0_m, dx_m, .. } => x0_m + i as f64 * dx_m,
            Knots::Listed { x_m, .. } => x_m[i],
        }
    }

    pub fn x_start_m(&self) -> f64 {
        self.x(0)
    }

    pub fn x_end_m(&self) -> f64 {
        self.x(self.z_m.len() - 1)
    }

    pub fn knots(&self) -> impl Iterator<Item = (f64, f64)> + '_ {
        self.z_m.iter().enumerate().map(|(i, &z)| (self.x(i), z))
    }

    pub fn len(&self) -> usize {
        self.z_m.len()
    }

    /// Index `i` of the interval `[x_i, x_{i+1}]` holding `x` (clamped to the ends).
    fn interval(&self, x_m: f64) -> usize {
        let last = self.z_m.len() - 2;
        let (x0, inv_dx) = match &self.knots {
            Knots::Uniform { x0_m, inv_dx, .. } => (*x0_m, *inv_dx),
            Knots::Listed {
                x_m,
                inv_dx: Some(inv_dx),
            } => (x_m[0], *inv_dx),
            Knots::Listed {
                x_m: xs,
                inv_dx: None,
            } => {
                return xs
                    .partition_point(|&xk| xk <= x_m)
                    .saturating_sub(1)
                    .min(last)
            }
        };
        // `as usize` saturates (negative and NaN give 0); rounding may put x one interval
        // off, so nudge.
        let mut i = (((x_m - x0) * inv_dx).floor().max(0.0) as usize).min(last);
        if i > 0 && x_m < self.x(i) {
            i -= 1;
        } else if i < last && x_m >= self.x(i + 1) {
            i += 1;
        }
        i
    }

    /// Elevation and slope at `x`, which must lie within the knots (callers clamp).
    pub fn evaluate(&self, x_m: f64) -> (f64, f64) {
        let i = self.interval(x_m);
        let x_i = self.x(i);
        let h = self.x(i + 1) - x_i;
        let t = (x_m - x_i) / h;
        let (z0, z1) = (self.z_m[i], self.z_m[i + 1]);
        let (m0, m1) = (h * self.slope[i], h * self.slope[i + 1]);
        let t2 = t * t;
        let t3 = t2 * t;
        let z = (2.0 * t3 - 3.0 * t2 + 1.0) * z0
            + (t3 - 2.0 * t2 + t) * m0
            + (-2.0 * t3 + 3.0 * t2) * z1
            + (t3 - t2) * m1;
        let dz_dt = (6.0 * t2 - 6.0 * t) * (z0 - z1)
            + (3.0 * t2 - 4.0 * t + 1.0) * m0
            + (3.0 * t2 - 2.0 * t) * m1;
        (z, dz_dt / h)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reproduces_cubics_exactly_with_exact_slopes() {
        // Hermite interpolation is exact for cubics given exact knot slopes; 1e-12 is
        // rounding only.
        let f = |x: f64| 0.3 * x * x * x - x * x + 2.0 * x - 1.0;
        let df = |x: f64| 0.9 * x * x - 2.0 * x + 2.0;
        let xs: Vec<f64> = (0..11).map(|i| -1.0 + 0.3 * i as f64).collect();
        let curve = HermiteCurve::uniform(
            -1.0,
            0.3,
            xs.iter().map(|&x| f(x)).collect(),
            xs.iter().map(|&x| df(x)).collect(),
        );
        for j in 0..=300 {
            let x = -1.0 + 3.0 * j as f64 / 300.0;
            let (z, s) = curve.evaluate(x);
            assert!((z - f(x)).abs() < 1e-12, "x {x}");
            assert!((s - df(x)).abs() < 1e-12, "x {x}");
        }
    }

    #[test]
    fn nonuniform_knots_reproduce_quadratics() {
        // Three-point slopes are exact for quadratics at interior knots; the one-sided end
        // slopes are not, so test the interior intervals only. 1e-12: rounding.
        let f = |x: f64| 2.0 * x * x - 3.0 * x + 0.5;
        let xs = vec![0.0, 0.1, 0.35, 0.4, 1.0, 1.7, 2.0];
        let curve = HermiteCurve::through(xs.clone(), xs.iter().map(|&x| f(x)).collect());
        assert!(matches!(curve.knots, Knots::Listed { inv_dx: None, .. }));
        for j in 0..=100 {
            let x = 0.1 + 1.6 * j as f64 / 100.0;
            let (z, s) = curve.evaluate(x);
            assert!((z - f(x)).abs() < 1e-12, "x {x}");
            assert!((s - (4.0 * x - 3.0)).abs() < 1e-12, "x {x}");
        }
    }
}
