//! The sampled road profile that vehicles roll over.

use rand_chacha::ChaCha8Rng;

use super::csv;
use super::curve::HermiteCurve;
use super::iso8608::{self, IsoBand};
use super::spec::{iso8608_band_rms_m, RoadFeature, RoadProfileSpec, DEFAULT_SAMPLE_SPACING_M};
use crate::error::{require_finite, Error, Result};

/// Field path used when `build` validates a spec (the scenario loader validates earlier
/// with the same path).
const SPEC_PATH: &str = "road.profile";

/// Most samples of a profile (memory guard): 20 million, 1 000 km at 0.05 m.
const MAX_SAMPLES: f64 = 2e7;

/// A road elevation profile `r(x)` over `[x_start_m, x_end_m]`.
///
/// `x` is the road coordinate in metres along the direction of travel: the bridge occupies
/// `[0, L]`, the approach is at negative x, the exit beyond L; one continuous profile
/// covers all of it. Elevation is positive upwards.
///
/// Representation: a cubic Hermite curve through samples (uniform for synthesized
/// profiles, so evaluation is O(1)), plus deterministic shapes evaluated in closed form.
/// Synthesized profiles carry the exact slope of their harmonic sum at each sample, so the
/// interpolated elevation is accurate to O(dx^4) and `slope` is the exact derivative of
/// `elevation_m` (consistent contact rate `v dr/dx`).
///
/// Outside its range the profile is clamped: held at its end value with zero slope. Build
/// it over the whole range the simulation visits (`x_range_m` tells the range); it is
/// never silently zero.
#[derive(Debug, Clone)]
pub struct RoadProfile {
    base: HermiteCurve,
    features: Vec<RoadFeature>,
    /// The base knots are samples worth writing out (synthesized or measured); otherwise
    /// the base is flat and `to_csv` samples the shapes on a 0.05 m grid.
    sampled: bool,
    band_rms_m: Option<f64>,
    description: String,
    /// `to_csv`, written once: every run and every burst of the estimate puts it in its
    /// manifest, and a sampled kilometre is tens of thousands of formatted rows.
    csv: std::sync::OnceLock<std::sync::Arc<str>>,
}

impl RoadProfile {
    /// Builds the profile of `spec` over `[x_start_m, x_end_m]`.
    ///
    /// Validates `spec` (errors name `road.profile.<field>`). Random profiles draw from
    /// `rng` only, so the profile is a pure function of (spec, range, seed); deterministic
    /// variants draw nothing. A synthesized profile may extend past `x_end_m` by less
    /// than one sample spacing; a CSV profile keeps the file's range, which must cover
    /// `[x_start_m, x_end_m]`.
    pub fn build(
        spec: &RoadProfileSpec,
        x_start_m: f64,
        x_end_m: f64,
        rng: &mut ChaCha8Rng,
    ) -> Result<RoadProfile> {
        spec.validate(SPEC_PATH)?;
        require_finite("x_start_m", x_start_m)?;
        require_finite("x_end_m", x_end_m)?;
        if x_end_m <= x_start_m {
            return Err(Error::invalid(
                "x_end_m",
                x_end_m,
                format!("must be greater than x_start_m = {x_start_m}"),
            ));
        }
        // Millimetres: the ends are sums like -(approach + wheelbase + 5) whose shortest
        // decimal can carry binary noise (-448.61999999999995).
        let range = format!("over [{x_start_m:.3}, {x_end_m:.3}] m");
        match spec {
            RoadProfileSpec::Smooth => Ok(Self::flat(
                x_start_m,
                x_end_m,
                Vec::new(),
                format!("smooth road (elevation 0) {range}"),
            )),
            RoadProfileSpec::Step { .. }
            | RoadProfileSpec::Ramp { .. }
            | RoadProfileSpec::Bump { .. }
            | RoadProfileSpec::DippedJoint { .. }
            | RoadProfileSpec::Void { .. } => {
                let features: Vec<RoadFeature> = spec.as_feature().into_iter().collect();
                let text = features
                    .iter()
                    .map(RoadFeature::describe)
                    .collect::<Vec<_>>()
                    .join("; ");
                Ok(Self::flat(
                    x_start_m,
                    x_end_m,
                    features,
                    format!("{text} on a flat road {range}"),
                ))
            }
            RoadProfileSpec::Csv { path } => {
                let profile = Self::from_csv_file(path)?;
                let (lo, hi) = profile.x_range_m();
                if lo > x_start_m || hi < x_end_m {
                    return Err(Error::File {
                        path: path.clone(),
                        reason: format!(
                            "the profile covers [{lo}, {hi}] m but the simulation needs \
                             [{x_start_m}, {x_end_m}] m"
                        ),
                    });
                }
                Ok(profile)
            }
            RoadProfileSpec::Track {
                class,
                n1_cycles_m,
                n2_cycles_m,
                sample_spacing_m,
                features,
            } => {
                let band = IsoBand {
                    gd_n0_m3: 0.0,
                    track: Some(*class),
                    n1_cycles_m: *n1_cycles_m,
                    n2_cycles_m: *n2_cycles_m,
                    spacing_m: *sample_spacing_m,
                    tyre_patch_m: None,
                };
                let rms_m = class.band_variance_m2(*n1_cycles_m, *n2_cycles_m).sqrt();
                let mut text = format!(
                    "track irregularity, {}, wavelengths {:.3}-{:.3} m, band RMS {:.2} mm, \
                     inverse-FFT synthesis at {} m spacing {range}",
                    class.label(),
                    1.0 / n2_cycles_m,
                    1.0 / n1_cycles_m,
                    1e3 * rms_m,
                    band.spacing_m
                );
                for f in features {
                    text += &format!("; plus {}", f.describe());
                }
                Ok(RoadProfile {
                    base: Self::synthesize(&band, x_start_m, x_end_m, rng)?,
                    features: features.clone(),
                    sampled: true,
                    band_rms_m: Some(rms_m),
                    description: text,
                    csv: Default::default(),
                })
            }
            RoadProfileSpec::Iso8608 {
                class,
                gd_n0_m3,
                n1_cycles_m,
                n2_cycles_m,
                tyre_patch_filter_m,
                sample_spacing_m,
                features,
            } => {
                let (gd, source) = match (gd_n0_m3, class) {
                    (Some(gd), Some(c)) => (
                        *gd,
                        format!(
                            "ISO 8608 explicit G_d(n0) = {gd:e} m^3 (overrides class {})",
                            c.letter()
                        ),
                    ),
                    (Some(gd), None) => (*gd, format!("ISO 8608 explicit G_d(n0) = {gd:e} m^3")),
                    (None, Some(c)) => (
                        c.gd_n0_m3(),
                        format!(
                            "ISO 8608 class {}, G_d(n0) = {}e-6 m^3 (geometric mean of class)",
                            c.letter(),
                            c.gd_n0_micro_m3()
                        ),
                    ),
                    // validate() rejects a spec with neither.
                    (None, None) => {
                        return Err(Error::invalid(
                            format!("{SPEC_PATH}.class"),
                            "(missing)",
                            "is required unless gd_n0_m3 is given",
                        ))
                    }
                };
                let band = IsoBand {
                    gd_n0_m3: gd,
                    track: None,
                    n1_cycles_m: *n1_cycles_m,
                    n2_cycles_m: *n2_cycles_m,
                    spacing_m: *sample_spacing_m,
                    tyre_patch_m: *tyre_patch_filter_m,
                };
                let rms_m = iso8608_band_rms_m(gd, band.n1_cycles_m, band.n2_cycles_m);
                let mut text = format!(
                    "{source}, n0 = 0.1 cycle/m, n in [{}, {}] cycle/m, band RMS {:.2} mm, \
                     inverse-FFT synthesis at {} m spacing {range}",
                    band.n1_cycles_m,
                    band.n2_cycles_m,
                    1e3 * rms_m,
                    band.spacing_m
                );
                if let Some(a) = band.tyre_patch_m {
                    text += &format!("; tyre-patch moving average {a} m");
                }
                for f in features {
                    text += &format!("; plus {}", f.describe());
                }
                let profile = Self::synthesize(&band, x_start_m, x_end_m, rng)?;
                Ok(RoadProfile {
                    base: profile,
                    features: features.clone(),
                    sampled: true,
                    band_rms_m: Some(rms_m),
                    description: text,
                    csv: Default::default(),
                })
            }
        }
    }

    fn flat(x_start_m: f64, x_end_m: f64, features: Vec<RoadFeature>, text: String) -> Self {
        RoadProfile {
            base: HermiteCurve::through(vec![x_start_m, x_end_m], vec![0.0, 0.0]),
            features,
            sampled: false,
            band_rms_m: None,
            description: text,
            csv: Default::default(),
        }
    }

    fn synthesize(
        band: &IsoBand,
        x_start_m: f64,
        x_end_m: f64,
        rng: &mut ChaCha8Rng,
    ) -> Result<HermiteCurve> {
        let intervals = ((x_end_m - x_start_m) / band.spacing_m - 1e-9)
            .ceil()
            .max(1.0);
        if intervals.is_nan() || intervals >= MAX_SAMPLES {
            return Err(Error::invalid(
                format!("{SPEC_PATH}.sample_spacing_m"),
                band.spacing_m,
                format!(
                    "gives {intervals} samples over [{x_start_m}, {x_end_m}] m, more than \
                     {MAX_SAMPLES}"
                ),
            ));
        }
        let n_samples = intervals as usize + 1;
        let nfft = iso8608::fft_len(n_samples, band)?;
        let (z, slope) = iso8608::synthesize(band, nfft, n_samples, rng);
        Ok(HermiteCurve::uniform(x_start_m, band.spacing_m, z, slope))
    }

    /// A measured profile from CSV text (`x_m,elevation_m` with header); `source` names it
    /// in errors and in `describe`.
    pub fn from_csv_str(text: &str, source: &str) -> Result<RoadProfile> {
        Ok(Self::measured(csv::parse(text, source)?, source))
    }

    /// A measured profile from the CSV file at `path`.
    pub fn from_csv_file(path: &str) -> Result<RoadProfile> {
        Ok(Self::measured(csv::read(path)?, path))
    }

    fn measured(parsed: csv::CsvProfile, source: &str) -> RoadProfile {
        let n = parsed.x_m.len();
        let base = HermiteCurve::through(parsed.x_m, parsed.elevation_m);
        let description = format!(
            "measured profile from {source}: {n} points over [{}, {}] m, cubic Hermite \
             interpolation",
            base.x_start_m(),
            base.x_end_m()
        );
        RoadProfile {
            base,
            features: Vec::new(),
            sampled: true,
            band_rms_m: None,
            description,
            csv: Default::default(),
        }
    }

    /// The range `[x_start_m, x_end_m]` over which the profile is defined.
    pub fn x_range_m(&self) -> (f64, f64) {
        (self.base.x_start_m(), self.base.x_end_m())
    }

    /// Whether `x_m` lies within the defined range (outside it the profile is clamped).
    pub fn contains(&self, x_m: f64) -> bool {
        x_m >= self.base.x_start_m() && x_m <= self.base.x_end_m()
    }

    /// Elevation (m) and slope dr/dx at `x_m`; clamped outside the range (end value, zero
    /// slope).
    #[inline]
    pub fn elevation_and_slope(&self, x_m: f64) -> (f64, f64) {
        let (lo, hi) = self.x_range_m();
        let xc = x_m.clamp(lo, hi);
        // A flat base is zero everywhere: no knot search under every wheel every step.
        let (mut z, mut s) = match self.sampled {
            true => self.base.evaluate(xc),
            false => (0.0, 0.0),
        };
        for f in &self.features {
            let (fz, fs) = f.evaluate(xc);
            z += fz;
            s += fs;
        }
        if xc != x_m {
            s = 0.0;
        }
        (z, s)
    }

    /// Elevation at `x_m`, m (clamped outside the range).
    pub fn elevation_m(&self, x_m: f64) -> f64 {
        self.elevation_and_slope(x_m).0
    }

    /// Slope dr/dx at `x_m` (dimensionless; 0 outside the range), the exact derivative of
    /// `elevation_m` except at a `step`, whose Dirac impulse is left out.
    pub fn slope(&self, x_m: f64) -> f64 {
        self.elevation_and_slope(x_m).1
    }

    /// The profile's sample points `(x_m, elevation_m)`: the synthesized or measured
    /// samples (shapes added), or, for a flat base, a uniform grid of at most 0.05 m; a
    /// flat base with no shape is its two ends (the line through them is the road).
    pub fn sample_points(&self) -> Box<dyn Iterator<Item = (f64, f64)> + '_> {
        if !self.sampled && self.features.is_empty() {
            let (lo, hi) = self.x_range_m();
            return Box::new([(lo, 0.0), (hi, 0.0)].into_iter());
        }
        if self.sampled {
            Box::new(self.base.knots().map(|(x, z)| {
                (
                    x,
                    z + self.features.iter().map(|f| f.evaluate(x).0).sum::<f64>(),
                )
            }))
        } else {
            let (lo, hi) = self.x_range_m();
            let intervals = ((hi - lo) / DEFAULT_SAMPLE_SPACING_M - 1e-9)
                .ceil()
                .max(1.0) as usize;
            let dx = (hi - lo) / intervals as f64;
            Box::new((0..=intervals).map(move |i| {
                let x = if i == intervals {
                    hi
                } else {
                    lo + i as f64 * dx
                };
                (x, self.elevation_m(x))
            }))
        }
    }

    /// Number of sample points of `sample_points` / rows of `to_csv`.
    pub fn sample_count(&self) -> usize {
        if self.sampled {
            self.base.len()
        } else {
            self.sample_points().count()
        }
    }

    /// The profile as CSV (`x_m,elevation_m` with header), e.g. for the MCAP attachment.
    /// Reading it back with `from_csv_str` gives the same elevation at every sample.
    pub fn to_csv(&self) -> std::sync::Arc<str> {
        (self.csv)
            .get_or_init(|| csv::write(self.sample_points()).into())
            .clone()
    }

    /// Target band RMS `sqrt(G_d(n0) n0^2 (1/n1 - 1/n2))` of an ISO 8608 profile, m
    /// (before any tyre-patch filter and shapes); `None` for other kinds.
    pub fn band_rms_m(&self) -> Option<f64> {
        self.band_rms_m
    }

    /// One line saying what this profile is, including the class value used, e.g.
    /// `ISO 8608 class A, G_d(n0) = 16e-6 m^3 (geometric mean of class), ...`.
    pub fn describe(&self) -> &str {
        &self.description
    }
}
