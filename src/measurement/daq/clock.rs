//! DAQ node clocks: offset, oscillator drift, sampling jitter and resynchronisation. The
//! model is the contract stated in the [module doc](super).

use rand::RngExt;
use rand_chacha::ChaCha8Rng;
use rand_distr::StandardNormal;
use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

use super::draws::{field, require_duration, truncated_standard_normal, MAX_SECONDS, NS_PER_S};
use crate::base::random::fnv1a_64;
use crate::base::schema as bounds;
use crate::error::{num, require_finite, require_non_negative, require_positive, Error, Result};

/// Largest accepted oscillator error: a crystal is +/-20-50 ppm (docs/sensors.md section 2), so
/// 1000 ppm only catches unit mistakes (a fraction or a percentage typed as ppm).
pub const MAX_DRIFT_PPM: f64 = 1000.0;

/// Jitter is truncated at this many standard deviations of the underlying normal.
pub const JITTER_TRUNCATION_SIGMAS: f64 = 3.0;

/// RMS of a standard normal truncated at +/-3: `sqrt(1 - 6 phi(3) / (2 Phi(3) - 1))`, with
/// `phi(3) = 0.0044318484`, `Phi(3) = 0.9986501020` (variance of the doubly truncated
/// normal; Johnson, Kotz, Balakrishnan, *Continuous Univariate Distributions* vol. 1,
/// ch. 13). Dividing by it makes `jitter_rms_s` the RMS of the jitter actually applied.
const TRUNCATED_RMS_PER_SIGMA: f64 = 0.986_578_392_6;

/// `jitter_rms_s` must stay below this fraction of the sample period: then the jitter is at
/// most `3 / 0.98658 * 0.1 = 0.304` periods, two neighbours differ by under 0.61 periods
/// and the true instants stay strictly increasing even with 1000 ppm of drift.
const MAX_JITTER_PER_PERIOD: f64 = 0.1;

/// ChaCha words reserved per resync draw: one 16-word block, so draw `j` starts at word
/// `16 j` of the node stream whatever other draws were made.
const WORDS_PER_RESYNC: u128 = 16;

/// A DAQ node's clock (`[daq_nodes.clock]`). All fields default to 0 / none: a perfect
/// clock.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(default, deny_unknown_fields)]
pub struct ClockSpec {
    /// Node clock minus true time at the run start, s. Default 0.
    pub offset_s: f64,
    /// Oscillator frequency error, ppm, `|drift_ppm| <= 1000`; positive runs fast. Default 0.
    #[schemars(range(min = -MAX_DRIFT_PPM, max = MAX_DRIFT_PPM))]
    pub drift_ppm: f64,
    /// RMS of the white sampling-instant jitter, s (normal truncated at 3 sigma), >= 0
    /// and below a tenth of the sample period. Default 0.
    #[schemars(range(min = 0))]
    pub jitter_rms_s: f64,
    /// True time between resynchronisations, s, > 0. Default none: free-running.
    #[schemars(transform = bounds::positive, range(max = MAX_SECONDS))]
    pub resync_interval_s: Option<f64>,
    /// RMS of the clock error left by each resync, s (e.g. 50e-6 for a wireless network),
    /// >= 0. Default 0; requires `resync_interval_s`.
    #[schemars(range(min = 0))]
    pub resync_residual_rms_s: f64,
}

impl ClockSpec {
    /// Checks the rate-independent fields; `prefix` is the path of the clock table.
    pub fn validate(&self, prefix: &str) -> Result<()> {
        require_finite(&field(prefix, "offset_s"), self.offset_s)?;
        let drift_field = field(prefix, "drift_ppm");
        require_finite(&drift_field, self.drift_ppm)?;
        if self.drift_ppm.abs() > MAX_DRIFT_PPM {
            return Err(Error::invalid(
                drift_field,
                num(self.drift_ppm),
                format!("must be within +/-{MAX_DRIFT_PPM} ppm (crystals are +/-20-50 ppm)"),
            ));
        }
        require_non_negative(&field(prefix, "jitter_rms_s"), self.jitter_rms_s)?;
        let residual_field = field(prefix, "resync_residual_rms_s");
        require_non_negative(&residual_field, self.resync_residual_rms_s)?;
        match self.resync_interval_s {
            Some(interval_s) => {
                require_duration(&field(prefix, "resync_interval_s"), interval_s)?;
            }
            None if self.resync_residual_rms_s > 0.0 => {
                return Err(Error::invalid(
                    residual_field,
                    num(self.resync_residual_rms_s),
                    "has no effect without resync_interval_s",
                ));
            }
            None => {}
        }
        Ok(())
    }

    /// [`ClockSpec::validate`] plus the jitter bound for a channel sampled at `rate_hz`.
    pub fn validate_for_rate(&self, prefix: &str, rate_hz: f64) -> Result<()> {
        self.validate(prefix)?;
        require_positive("rate_hz", rate_hz)?;
        let limit_s = MAX_JITTER_PER_PERIOD / rate_hz;
        if self.jitter_rms_s >= limit_s {
            return Err(Error::invalid(
                field(prefix, "jitter_rms_s"),
                num(self.jitter_rms_s),
                format!(
                    "must be < a tenth of the sample period ({} s at {rate_hz} Hz) so that \
                     sample instants stay increasing",
                    num(limit_s)
                ),
            ));
        }
        Ok(())
    }
}

/// One DAQ node of a scenario's `[[daq_nodes]]` array: sensors naming it share its clock.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct DaqNodeSpec {
    /// Node name, `[A-Za-z0-9_-]+` (it may appear in topic names and stream names).
    #[schemars(regex(pattern = bounds::TOPIC_SEGMENT))]
    pub id: String,
    /// The node's clock; default a perfect clock.
    #[serde(default)]
    pub clock: ClockSpec,
}

impl DaqNodeSpec {
    /// Checks the id and the clock; `prefix` is the node's path, e.g. `daq_nodes.0`.
    pub fn validate(&self, prefix: &str) -> Result<()> {
        let valid_char = |c: char| c.is_ascii_alphanumeric() || c == '_' || c == '-';
        if self.id.is_empty() || !self.id.chars().all(valid_char) {
            return Err(Error::invalid(
                field(prefix, "id"),
                format!("{:?}", self.id),
                "must be a non-empty name of [A-Za-z0-9_-]",
            ));
        }
        self.clock.validate(&field(prefix, "clock"))
    }
}

/// A resynchronisation: at true instant `true_ns` the node's clock error jumps from
/// `error_before_s` to `error_after_s` (the residual). For `/events`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ResyncEvent {
    /// Resync number, 1 for the first (at one interval).
    pub index: u64,
    /// True instant, ns since the run start.
    pub true_ns: u64,
    /// Clock error just before, s.
    pub error_before_s: f64,
    /// Clock error just after (the residual draw), s.
    pub error_after_s: f64,
}

#[derive(Debug, Clone)]
struct Resync {
    interval_s: f64,
    residual_rms_s: f64,
    /// The node stream; draw `j` reads it from word `16 j` on (counter-based).
    stream: ChaCha8Rng,
}

/// The clock error `e(t)` of one node, a deterministic function of the node stream and the
/// true time `t`: every channel of the node holds a copy (same stream) and evaluates the
/// same function without seeing the others. See the [module doc](super).
#[derive(Debug, Clone)]
pub struct ClockError {
    offset_s: f64,
    /// Fractional frequency error, `drift_ppm * 1e-6`.
    drift: f64,
    resync: Option<Resync>,
}

impl ClockError {
    /// The error function of a node with clock `spec`; `rng` is the node's stream (e.g.
    /// `child_rng(seed, "daq/<id>/clock")`), only its key and stream id matter. Errors name
    /// `<field_prefix>.<field>`.
    pub fn new(spec: &ClockSpec, rng: ChaCha8Rng, field_prefix: &str) -> Result<Self> {
        spec.validate(field_prefix)?;
        Ok(Self {
            offset_s: spec.offset_s,
            drift: spec.drift_ppm * 1e-6,
            resync: spec.resync_interval_s.map(|interval_s| Resync {
                interval_s,
                residual_rms_s: spec.resync_residual_rms_s,
                stream: rng,
            }),
        })
    }

    /// Number of resyncs at or before true time `true_s` (0 when free-running).
    pub fn resyncs_before(&self, true_s: f64) -> u64 {
        match &self.resync {
            Some(r) if true_s >= r.interval_s => (true_s / r.interval_s).floor() as u64,
            _ => 0,
        }
    }

    /// `e(t)`, node time minus true time at true time `true_s`, s.
    pub fn error_s(&self, true_s: f64) -> f64 {
        let j = self.resyncs_before(true_s);
        self.segment_start_error_s(j) + self.drift * (true_s - self.segment_start_s(j))
    }

    /// Resync `index >= 1`; `None` for index 0 or a free-running clock.
    pub fn resync_event(&self, index: u64) -> Option<ResyncEvent> {
        let r = self.resync.as_ref()?;
        if index == 0 {
            return None;
        }
        let true_s = index as f64 * r.interval_s;
        let prev = index - 1;
        Some(ResyncEvent {
            index,
            true_ns: (true_s * NS_PER_S).round() as u64,
            error_before_s: self.segment_start_error_s(prev)
                + self.drift * (true_s - self.segment_start_s(prev)),
            error_after_s: self.segment_start_error_s(index),
        })
    }

    /// The resyncs in time order (endless; empty when free-running). Take them while
    /// `true_ns` is within the run.
    pub fn resync_events(&self) -> impl Iterator<Item = ResyncEvent> + '_ {
        (1..).map_while(|j| self.resync_event(j))
    }

    /// Stamp minus the nominal instant `k / fs` on segment `j`: `offset` before the first
    /// resync, else `r_j - drift * j * interval` (module doc), s.
    fn stamp_correction_s(&self, j: u64) -> f64 {
        self.segment_start_error_s(j) - self.drift * self.segment_start_s(j)
    }

    /// True instant where segment `j` starts, s.
    fn segment_start_s(&self, j: u64) -> f64 {
        match &self.resync {
            Some(r) => j as f64 * r.interval_s,
            None => 0.0,
        }
    }

    /// `e` at the start of segment `j`: the offset for 0, the residual draw `r_j` after.
    fn segment_start_error_s(&self, j: u64) -> f64 {
        match &self.resync {
            Some(r) if j > 0 => r.residual_rms_s * residual_draw(&r.stream, j),
            _ => self.offset_s,
        }
    }
}

/// Standard normal number `j` of `stream`, read from its own block so that any channel can
/// compute it in O(1) without the draws before it.
fn residual_draw(stream: &ChaCha8Rng, j: u64) -> f64 {
    let mut rng = stream.clone();
    rng.set_word_pos(u128::from(j) * WORDS_PER_RESYNC);
    rng.sample(StandardNormal)
}

/// One sample of a node clock.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ClockedSample {
    /// Sample number, from 0.
    pub index: u64,
    /// True instant, ns since the run start (float: jitter is sub-nanosecond for fast DAQs).
    pub true_ns: f64,
    /// The node's timestamp, ns since the run start (negative with a negative offset).
    pub stamp_ns: i64,
}

/// The sampling clock of one channel on a node: yields sample `k = 0, 1, 2, ...` with its
/// true instant and the node's stamp, in O(1) from `k` (no accumulated sums).
#[derive(Debug, Clone)]
pub struct NodeClock {
    error: ClockError,
    nominal_rate_hz: f64,
    true_rate_hz: f64,
    nominal_period_ns: f64,
    true_period_ns: f64,
    jitter_sigma_ns: f64,
    jitter_rng: ChaCha8Rng,
    next_index: u64,
    segment: u64,
    correction_ns: i64,
}

impl NodeClock {
    /// A channel sampling at `nominal_rate_hz` on a node with clock `spec`. `rng` is the
    /// node's stream, identical for all its channels (e.g. `child_rng(seed,
    /// "daq/<id>/clock")`): the resync draws come from it by counter, and the jitter from a
    /// sibling ChaCha stream of the same key chosen by the rate, so channels of one node
    /// and rate share their jitter (one sampling clock), channels at other rates do not.
    /// Use [`NodeClock::with_jitter_rng`] for independent jitter. Errors name
    /// `<field_prefix>.<field>` and `rate_hz`.
    pub fn new(
        spec: &ClockSpec,
        nominal_rate_hz: f64,
        rng: ChaCha8Rng,
        field_prefix: &str,
    ) -> Result<Self> {
        spec.validate_for_rate(field_prefix, nominal_rate_hz)?;
        let jitter_rng = jitter_stream(&rng, nominal_rate_hz);
        let error = ClockError::new(spec, rng, field_prefix)?;
        let true_rate_hz = nominal_rate_hz * (1.0 + error.drift);
        let correction_ns = seconds_to_signed_ns(error.stamp_correction_s(0));
        Ok(Self {
            error,
            nominal_rate_hz,
            true_rate_hz,
            nominal_period_ns: NS_PER_S / nominal_rate_hz,
            true_period_ns: NS_PER_S / true_rate_hz,
            jitter_sigma_ns: spec.jitter_rms_s * NS_PER_S / TRUNCATED_RMS_PER_SIGMA,
            jitter_rng,
            next_index: 0,
            segment: 0,
            correction_ns,
        })
    }

    /// Replaces the jitter stream (before the first sample), e.g. with a per-channel one.
    pub fn with_jitter_rng(mut self, rng: ChaCha8Rng) -> Self {
        self.jitter_rng = rng;
        self
    }

    /// The next sample: true instant `k / true_rate + jitter_k` and stamp
    /// `round(k * 1e9 / nominal_rate) + round(c_j * 1e9)` (module doc).
    pub fn next_sample(&mut self) -> ClockedSample {
        let k = self.next_index;
        self.next_index += 1;
        let ideal_ns = k as f64 * self.true_period_ns;
        let segment = self.error.resyncs_before(ideal_ns / NS_PER_S);
        if segment != self.segment {
            self.segment = segment;
            self.correction_ns = seconds_to_signed_ns(self.error.stamp_correction_s(segment));
        }
        ClockedSample {
            index: k,
            true_ns: ideal_ns + self.jitter_ns(),
            stamp_ns: round_product(k, self.nominal_period_ns) + self.correction_ns,
        }
    }

    fn jitter_ns(&mut self) -> f64 {
        if self.jitter_sigma_ns == 0.0 {
            return 0.0;
        }
        let z = truncated_standard_normal(&mut self.jitter_rng, JITTER_TRUNCATION_SIGMAS);
        self.jitter_sigma_ns * z
    }

    /// Rate the node believes it samples at, Hz.
    pub fn nominal_rate_hz(&self) -> f64 {
        self.nominal_rate_hz
    }

    /// Rate it really samples at, `nominal * (1 + drift_ppm * 1e-6)`, Hz.
    pub fn true_rate_hz(&self) -> f64 {
        self.true_rate_hz
    }

    /// The node's clock error function (for resync events and checks).
    pub fn clock_error(&self) -> &ClockError {
        &self.error
    }
}

impl Iterator for NodeClock {
    type Item = ClockedSample;

    /// Endless: always `Some(self.next_sample())`.
    fn next(&mut self) -> Option<ClockedSample> {
        Some(self.next_sample())
    }
}

/// The jitter stream of a channel: same key as the node stream, ChaCha stream id mixed with
/// the rate's bits, so it is independent of the resync draws and of other rates.
fn jitter_stream(node: &ChaCha8Rng, rate_hz: f64) -> ChaCha8Rng {
    let mut tag = [0u8; 14];
    tag[..6].copy_from_slice(b"jitter");
    tag[6..].copy_from_slice(&rate_hz.to_bits().to_le_bytes());
    let mut rng = node.clone();
    rng.set_stream(node.get_stream() ^ fnv1a_64(&tag));
    rng.set_word_pos(0);
    rng
}

/// `round(k * period_ns)` without the rounding error of the float product: the exact
/// product is `hi + lo` (two-product by fused multiply-add; Ogita, Rump, Oishi 2005), so
/// the result is off by at most the error of `period_ns` itself, for `k < 2^53`. Equals
/// `round(k * 1e9 / rate)` whenever the period is a whole number of ns (100, 128, 200 Hz).
fn round_product(k: u64, period_ns: f64) -> i64 {
    let kf = k as f64;
    let hi = kf * period_ns;
    let lo = kf.mul_add(period_ns, -hi);
    let whole = hi.round();
    // `hi - whole` is exact (Sterbenz), so the remainder is resolved in full precision.
    whole as i64 + ((hi - whole) + lo).round() as i64
}

fn seconds_to_signed_ns(seconds: f64) -> i64 {
    (seconds * NS_PER_S).round() as i64
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::SeedableRng;

    fn rng() -> ChaCha8Rng {
        ChaCha8Rng::seed_from_u64(7)
    }

    #[test]
    fn truncated_rms_constant_matches_numerical_integration() {
        // Simpson's rule with 6000 panels on [-3, 3]: error ~ h^4 = 1e-12, far below the 1e-8
        // printed precision of the constant.
        let pdf = |z: f64| (-0.5 * z * z).exp();
        let n = 6000;
        let h = 6.0 / n as f64;
        let (mut mass, mut second) = (0.0, 0.0);
        for i in 0..=n {
            let z = -3.0 + i as f64 * h;
            let w = if i == 0 || i == n {
                1.0
            } else if i % 2 == 1 {
                4.0
            } else {
                2.0
            };
            mass += w * pdf(z);
            second += w * z * z * pdf(z);
        }
        let rms = (second / mass).sqrt();
        assert!((rms - TRUNCATED_RMS_PER_SIGMA).abs() < 1e-8, "{rms}");
    }

    #[test]
    fn round_product_is_exact_where_the_float_product_is_not() {
        // k = 2^52 + 1 times 3 ns is 3 * 2^52 + 3, odd, but doubles above 2^53 are even: the
        // plain float product is off by one, the two-product is exact.
        let k = (1_u64 << 52) + 1;
        let exact = 3 * k as i64;
        assert_ne!((k as f64 * 3.0).round() as i64, exact);
        assert_eq!(round_product(k, 3.0), exact);
        assert_eq!(round_product(0, 5e6), 0);
        assert_eq!(round_product(1 << 40, 5e6), (1_i64 << 40) * 5_000_000);
        assert_eq!(round_product(3_000_000, 1e9 / 3.0), 1_000_000_000_000_000);
    }

    #[test]
    fn drift_beyond_the_limit_names_the_field() {
        let spec = ClockSpec {
            drift_ppm: 1500.0,
            ..ClockSpec::default()
        };
        let e = NodeClock::new(&spec, 100.0, rng(), "daq_nodes.2.clock").unwrap_err();
        assert!(
            e.to_string()
                .starts_with("daq_nodes.2.clock.drift_ppm = 1500 "),
            "{e}"
        );
    }

    #[test]
    fn jitter_of_a_tenth_period_is_rejected() {
        let spec = ClockSpec {
            jitter_rms_s: 1e-3,
            ..ClockSpec::default()
        };
        assert!(NodeClock::new(&spec, 99.0, rng(), "c").is_ok());
        let e = NodeClock::new(&spec, 100.0, rng(), "c").unwrap_err();
        assert!(e.to_string().starts_with("c.jitter_rms_s = 0.001 "), "{e}");
    }

    #[test]
    fn residual_without_interval_and_bad_ids_are_rejected() {
        let spec = ClockSpec {
            resync_residual_rms_s: 5e-5,
            ..ClockSpec::default()
        };
        let e = spec.validate("n.clock").unwrap_err().to_string();
        assert!(
            e.starts_with("n.clock.resync_residual_rms_s = 0.00005 "),
            "{e}"
        );
        let node = DaqNodeSpec {
            id: "bad id".into(),
            clock: ClockSpec::default(),
        };
        let e = node.validate("daq_nodes.1").unwrap_err().to_string();
        assert!(e.starts_with("daq_nodes.1.id = \"bad id\" "), "{e}");
        let interval = ClockSpec {
            resync_interval_s: Some(0.0),
            ..ClockSpec::default()
        };
        let e = interval.validate("n.clock").unwrap_err().to_string();
        assert!(e.starts_with("n.clock.resync_interval_s = 0 "), "{e}");
    }

    #[test]
    fn resync_draws_do_not_depend_on_evaluation_order() {
        let spec = ClockSpec {
            resync_interval_s: Some(10.0),
            resync_residual_rms_s: 1e-4,
            ..ClockSpec::default()
        };
        let a = ClockError::new(&spec, rng(), "c").unwrap();
        let b = ClockError::new(&spec, rng(), "c").unwrap();
        let forward: Vec<f64> = (1..50)
            .map(|j| a.resync_event(j).unwrap().error_after_s)
            .collect();
        let backward: Vec<f64> = (1..50)
            .rev()
            .map(|j| b.resync_event(j).unwrap().error_after_s)
            .collect();
        let reversed: Vec<f64> = backward.into_iter().rev().collect();
        assert_eq!(forward, reversed);
        assert!(forward.windows(2).all(|w| w[0] != w[1]));
    }

    #[test]
    fn clock_spec_parses_from_toml_and_rejects_unknown_keys() {
        let node: DaqNodeSpec =
            toml::from_str("id = \"n1\"\nclock = { drift_ppm = 20.0, resync_interval_s = 60.0 }")
                .unwrap();
        assert_eq!(node.clock.drift_ppm, 20.0);
        assert_eq!(node.clock.resync_interval_s, Some(60.0));
        assert_eq!(node.clock.offset_s, 0.0);
        let bad = toml::from_str::<DaqNodeSpec>("id = \"n1\"\nclock = { drift = 20.0 }");
        assert!(bad.is_err());
    }
}
