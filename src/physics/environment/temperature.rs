//! Air temperature series: a daily sinusoid with Ornstein-Uhlenbeck noise, a measured CSV
//! record, or a constant. Streamed at O(1) work per call for non-decreasing times.

use std::path::Path;

use rand::RngExt;
use rand_chacha::ChaCha8Rng;
use rand_distr::StandardNormal;
use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

use super::csv_series::TemperatureTable;
use crate::error::{require_finite, require_non_negative, require_positive, Error, Result};

/// Seconds in a day: the period of the daily cycle.
pub const DAY_S: f64 = 86_400.0;

/// Air temperature of the scenario (`environment.temperature`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(remote = "Self", rename_all = "snake_case", deny_unknown_fields)]
#[schemars(tag = "kind")]
pub enum TemperatureSpec {
    /// The same temperature all the time (the default, 20 degC).
    Constant {
        /// Air temperature (degC).
        value_c: f64,
    },
    /// A daily cosine with its maximum at `peak_hour`, plus optional red noise.
    Daily(DailySpec),
    /// A measured record, linearly interpolated.
    Csv {
        /// File with the header `time_s,temperature_c`, relative to the scenario file.
        /// `time_s` is simulation time (0 = `start_time`); the end values hold outside.
        #[schemars(regex(pattern = r"\S"))]
        path: String,
    },
}
crate::base::tagged::kind_tagged!(TemperatureSpec);

impl Default for TemperatureSpec {
    fn default() -> Self {
        TemperatureSpec::Constant {
            value_c: DEFAULT_AIR_C,
        }
    }
}

/// Default constant air temperature (degC); equal to the stiffness law's default reference
/// temperature, so a scenario without temperatures keeps the bridge's EI exactly.
pub const DEFAULT_AIR_C: f64 = 20.0;

/// Daily cycle `mean_c + amplitude_c cos(2 pi (hour - peak_hour) / 24) + noise`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct DailySpec {
    /// Daily mean (degC).
    pub mean_c: f64,
    /// Half the peak-to-trough swing (degC), >= 0.
    #[schemars(range(min = 0))]
    pub amplitude_c: f64,
    /// Hour of the maximum, in [0, 24) (default 15: air peaks mid-afternoon).
    #[serde(default = "default_peak_hour")]
    #[schemars(range(min = 0), transform = crate::base::schema::below(24.0))]
    pub peak_hour: f64,
    /// Standard deviation of the stationary noise (degC), >= 0 (default 0: none).
    #[serde(default)]
    #[schemars(range(min = 0))]
    pub noise_sd_c: f64,
    /// Correlation time of the noise (s), > 0 (default 3600: weather fronts and clouds
    /// vary over hours, not seconds).
    #[serde(default = "default_noise_correlation_s")]
    #[schemars(transform = crate::base::schema::positive)]
    pub noise_correlation_s: f64,
}

fn default_peak_hour() -> f64 {
    15.0
}
fn default_noise_correlation_s() -> f64 {
    3600.0
}

impl TemperatureSpec {
    /// Checks the fields; `path` is the scenario path (`environment.temperature`).
    pub fn validate(&self, path: &str) -> Result<()> {
        match self {
            TemperatureSpec::Constant { value_c } => {
                require_finite(&format!("{path}.value_c"), *value_c)?;
            }
            TemperatureSpec::Daily(daily) => daily.validate(path)?,
            TemperatureSpec::Csv { path: file } => {
                if file.trim().is_empty() {
                    return Err(Error::invalid(
                        format!("{path}.path"),
                        "\"\"",
                        "must name a CSV file",
                    ));
                }
            }
        }
        Ok(())
    }
}

impl DailySpec {
    fn validate(&self, path: &str) -> Result<()> {
        require_finite(&format!("{path}.mean_c"), self.mean_c)?;
        require_non_negative(&format!("{path}.amplitude_c"), self.amplitude_c)?;
        if !(self.peak_hour.is_finite() && (0.0..24.0).contains(&self.peak_hour)) {
            return Err(Error::invalid(
                format!("{path}.peak_hour"),
                self.peak_hour,
                "must be in [0, 24)",
            ));
        }
        require_non_negative(&format!("{path}.noise_sd_c"), self.noise_sd_c)?;
        require_positive(
            &format!("{path}.noise_correlation_s"),
            self.noise_correlation_s,
        )?;
        Ok(())
    }

    /// The noise-free cycle at `time_of_day_s` seconds after midnight (degC).
    pub fn deterministic_c(&self, time_of_day_s: f64) -> f64 {
        let phase = std::f64::consts::TAU * (time_of_day_s - 3600.0 * self.peak_hour) / DAY_S;
        self.mean_c + self.amplitude_c * phase.cos()
    }
}

/// Ornstein-Uhlenbeck process with stationary standard deviation `sd_c` and correlation
/// time `tau_s`, advanced by its exact transition: for a step h,
/// `x' = rho x + sd sqrt(1 - rho^2) z`, `rho = exp(-h / tau)` (Gillespie 1996, Phys. Rev. E
/// 54, 2084, eq. 1.3), so its statistics do not depend on the step size.
#[derive(Debug, Clone)]
pub struct OrnsteinUhlenbeck {
    sd_c: f64,
    tau_s: f64,
    value_c: f64,
    last_t_s: f64,
    rng: ChaCha8Rng,
}

impl OrnsteinUhlenbeck {
    /// Starts at `t_s` with a draw from the stationary law N(0, sd^2), so the series has
    /// no start-up transient.
    pub fn new(sd_c: f64, tau_s: f64, t_s: f64, mut rng: ChaCha8Rng) -> Self {
        let z: f64 = if sd_c > 0.0 {
            rng.sample(StandardNormal)
        } else {
            0.0
        };
        Self {
            sd_c,
            tau_s,
            value_c: sd_c * z,
            last_t_s: t_s,
            rng,
        }
    }

    /// The value at `t_s`; a time at or before the last one returns the last value and
    /// draws nothing, so repeated calls at one instant agree.
    pub fn at(&mut self, t_s: f64) -> f64 {
        let step_s = t_s - self.last_t_s;
        if step_s > 0.0 && self.sd_c > 0.0 {
            let rho = (-step_s / self.tau_s).exp();
            // 1 - rho^2 by expm1 keeps the innovation accurate for steps << tau.
            let innovation_sd = self.sd_c * (-(-2.0 * step_s / self.tau_s).exp_m1()).sqrt();
            let z: f64 = self.rng.sample(StandardNormal);
            self.value_c = rho * self.value_c + innovation_sd * z;
        }
        self.last_t_s = self.last_t_s.max(t_s);
        self.value_c
    }
}

/// A streaming air temperature source built from a [`TemperatureSpec`].
#[derive(Debug, Clone)]
pub struct AirTemperature {
    source: Source,
}

#[derive(Debug, Clone)]
enum Source {
    Constant(f64),
    // Boxed: the noise generator's state dwarfs the other variants.
    Daily(Box<DailySource>),
    Table(TemperatureTable),
}

#[derive(Debug, Clone)]
struct DailySource {
    spec: DailySpec,
    start_time_of_day_s: f64,
    noise: OrnsteinUhlenbeck,
}

impl AirTemperature {
    /// Builds the source. `start_time_of_day_s` is the clock time of t = 0 in seconds after
    /// midnight (from the scenario's `start_time`), which places the daily peak;
    /// `scenario_dir` resolves a relative CSV path; `rng` feeds the noise (use
    /// `child_rng(seed, "environment/temperature")`). Validates `spec` first.
    pub fn new(
        spec: &TemperatureSpec,
        start_time_of_day_s: f64,
        scenario_dir: &Path,
        rng: ChaCha8Rng,
    ) -> Result<Self> {
        spec.validate("environment.temperature")?;
        require_finite("start_time_of_day_s", start_time_of_day_s)?;
        let source = match spec {
            TemperatureSpec::Constant { value_c } => Source::Constant(*value_c),
            TemperatureSpec::Daily(daily) => Source::Daily(Box::new(DailySource {
                spec: daily.clone(),
                start_time_of_day_s,
                noise: OrnsteinUhlenbeck::new(
                    daily.noise_sd_c,
                    daily.noise_correlation_s,
                    0.0,
                    rng,
                ),
            })),
            TemperatureSpec::Csv { path } => {
                Source::Table(TemperatureTable::load(&scenario_dir.join(path))?)
            }
        };
        Ok(Self { source })
    }

    /// A constant source (tests, defaults).
    pub fn constant(value_c: f64) -> Self {
        Self {
            source: Source::Constant(value_c),
        }
    }

    /// A source reading a parsed table.
    pub fn from_table(table: TemperatureTable) -> Self {
        Self {
            source: Source::Table(table),
        }
    }

    /// Air temperature at simulation time `t_s` (degC). O(1) amortized for non-decreasing
    /// times; an earlier time is answered too (the table searches, the noise holds).
    pub fn air_c(&mut self, t_s: f64) -> f64 {
        match &mut self.source {
            Source::Constant(value_c) => *value_c,
            Source::Daily(daily) => {
                daily.spec.deterministic_c(daily.start_time_of_day_s + t_s) + daily.noise.at(t_s)
            }
            Source::Table(table) => table.at(t_s),
        }
    }

    /// Structure temperature at t = 0 that starts a first-order lag `lag_s` on its
    /// periodic steady state: for the daily cycle the noise-free response
    /// `mean + A / sqrt(1 + (w tau)^2) cos(phase - atan(w tau))`, otherwise the air
    /// temperature at t = 0. Avoids a start-up transient of several `lag_s`.
    pub fn settled_structure_c(&mut self, lag_s: f64) -> f64 {
        match &self.source {
            Source::Daily(daily) => daily.settled_structure_c(lag_s),
            _ => self.air_c(0.0),
        }
    }
}

impl DailySource {
    /// Periodic response of `tau dT/dt = a(t) - T` to the noise-free cosine at t = 0: the
    /// cosine attenuated by `1 / sqrt(1 + (w tau)^2)` and delayed by `atan(w tau)`.
    fn settled_structure_c(&self, lag_s: f64) -> f64 {
        let w_tau = std::f64::consts::TAU / DAY_S * lag_s;
        let phase = std::f64::consts::TAU
            * (self.start_time_of_day_s - 3600.0 * self.spec.peak_hour)
            / DAY_S;
        let attenuation = 1.0 / (1.0 + w_tau * w_tau).sqrt();
        self.spec.mean_c + self.spec.amplitude_c * attenuation * (phase - w_tau.atan()).cos()
    }
}
