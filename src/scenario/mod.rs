//! Scenario: TOML -> validated `Scenario`. Every field is checked once, here, and errors
//! name the field path (`sensors.2.rate_hz = 5000 ...`).

mod instruments;
mod parse_error;
mod resolve;
#[cfg(test)]
mod resolve_tests;
mod resolved;
mod scene;
pub mod schema;
mod sensor_spec;
mod sensors;

use std::path::Path;

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

use crate::base::schema as bounds;
use crate::base::tagged;
use crate::error::{Error, Result};
use crate::physics::bridge::{
    BeamProperties, Girder, ModelSpec, Section, StiffnessRegion, Support,
};
use crate::physics::road::RoadProfileSpec;
use crate::physics::solver::{ContactLaw, NewmarkParams};
use crate::physics::vehicle::VehicleModelSpec;
pub use crate::record::{Layout, SensorKind};

pub use instruments::{AxleDetectorSpec, GnssSpec, VehicleMountSpec};
use parse_error::toml_error;
use resolve::unique_segment;
pub use resolve::{
    F1_RANGE_HZ, MAX_DURATION_S, MAX_ROAD_M, MAX_SPAN_M, MAX_SPEED_M_S, MAX_STEPS,
    MAX_TRAIN_SPEED_M_S,
};
pub use resolved::{
    Resolved, ResolvedSensor, ResolvedVehicle, MIN_STEPS_PER_MODE_PERIOD,
    MIN_STEPS_PER_SENSOR_PERIOD,
};
pub use scene::{
    exaggeration_for, DEFAULT_SCENE_RATE_HZ, SCENE_FALLBACK_WEIGHT_N, SCENE_PEAK_FRACTION_OF_SPAN,
};
pub use sensor_spec::{default_noise_density, Fibre, SensorSpec};
pub use sensors::sensor_streams;

/// The embedded default scenario (`bridgetwin scenario show`).
pub const DEFAULT_SCENARIO_TOML: &str = include_str!("default.toml");

/// A run, as written in a scenario file.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
// Generated traffic has no last vehicle to end the run: `resolve` requires `duration_s`.
#[schemars(extend("dependencies" = { "traffic": ["duration_s"] }))]
pub struct Scenario {
    /// Run seed; every random component derives its own stream from it (default 42).
    #[serde(default = "default_seed")]
    pub seed: u64,
    /// Wall-clock time of t = 0, RFC 3339 (default 2026-01-01T00:00:00Z).
    #[serde(default = "default_start_time")]
    #[schemars(extend("format" = "date-time"))]
    pub start_time: String,
    /// Simulated time (s), at most 30 days; default: until the last vehicle has left the
    /// bridge + 3 s.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(transform = bounds::positive, range(max = resolve::MAX_DURATION_S))]
    pub duration_s: Option<f64>,
    /// The girder: spans, supports, sections, damping and its discretization.
    pub bridge: BridgeSection,
    /// Time step and integrator.
    #[serde(default)]
    pub solver: SolverSection,
    /// Road profile, approach and exit.
    #[serde(default)]
    pub road: RoadSection,
    /// Vehicles listed one by one, each with its model, speed and entry time.
    #[serde(default)]
    pub vehicles: Vec<VehicleEntry>,
    /// Bridge sensors: accelerometers, strain gauges, displacement transducers.
    #[serde(default)]
    pub sensors: Vec<SensorSpec>,
    /// Weigh-in-motion strips on the approach.
    #[serde(default)]
    pub wim_stations: Vec<WimStationSpec>,
    /// GNSS receivers on vehicles: position along the road and speed, with their noise.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub gnss: Vec<instruments::GnssSpec>,
    /// Road axle detectors (tape switches): the time each axle crosses them, with timing
    /// jitter and missed axles.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub axle_detectors: Vec<instruments::AxleDetectorSpec>,
    /// Generated traffic (lanes, flows, class mix): vehicles arrive during the run, next to
    /// the `[[vehicles]]` listed; needs `duration_s`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub traffic: Option<crate::physics::traffic::TrafficSpec>,
    /// Band-limited random loads on the bridge (wind, micro-tremor), their level set by the
    /// RMS acceleration they cause; none by default.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub ambient: Option<crate::physics::excitation::AmbientSpec>,
    /// DAQ nodes whose clocks stamp their sensors' samples (`sensors.N.daq_node`).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub daq_nodes: Vec<crate::measurement::daq::DaqNodeSpec>,
    /// Air temperature, its lag into the structure and E(T); with it the bridge model is
    /// rebuilt as the stiffness drifts. None by default: EI stays the scenario's.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub environment: Option<crate::physics::environment::EnvironmentSpec>,
    /// Damaged regions: EI loss with an onset time and a growth law.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub damage: Vec<crate::physics::environment::DamageSpec>,
    /// Changes of the supports' condition: bearing degradation, scour, settlement, each
    /// with an onset time and a growth law.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub support_condition: Vec<crate::physics::environment::SupportConditionSpec>,
    /// Message layout, truth-stream rates and file splitting.
    #[serde(default)]
    pub output: OutputSection,
}

fn default_seed() -> u64 {
    42
}
fn default_start_time() -> String {
    "2026-01-01T00:00:00Z".into()
}

/// The bridge.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
#[schemars(transform = bounds::exactly_one_key(&["span_m", "spans_m"]))]
pub struct BridgeSection {
    /// One simply supported span (m), at most 10 km; or give `spans_m` instead.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(transform = bounds::positive, range(max = resolve::MAX_SPAN_M))]
    pub span_m: Option<f64>,
    /// Span lengths of a continuous girder, left to right (m, each at most 10 km); or give
    /// `span_m` for one span. May be empty for a cantilever (one fixed support and an
    /// overhang).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(transform = bounds::positive_items)]
    pub spans_m: Option<Vec<f64>>,
    /// The support at each span end, left to right: `"pinned"`, `"roller"`, `"fixed"` or
    /// `{ elastic = { vertical_n_m = .., rotational_n_m_rad = .. } }` (default: pinned at
    /// the first, rollers at the others).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub supports: Option<Vec<Support>>,
    /// Free overhang beyond the first support (m, default 0); x = 0 is its tip.
    #[serde(default, skip_serializing_if = "is_zero")]
    #[schemars(range(min = 0))]
    pub overhang_left_m: f64,
    /// Free overhang beyond the last support (m, default 0).
    #[serde(default, skip_serializing_if = "is_zero")]
    #[schemars(range(min = 0))]
    pub overhang_right_m: f64,
    /// Flexural rigidity EI of the reference section (N m^2).
    #[schemars(transform = bounds::positive)]
    pub flexural_rigidity_n_m2: f64,
    /// Mass per unit length of the reference section (kg/m).
    #[schemars(transform = bounds::positive)]
    pub mass_per_length_kg_m: f64,
    /// Segments with their own EI and mass, constant or linearly varying (haunches over
    /// piers), in m from the girder's left end (default none).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub sections: Vec<Section>,
    /// Rayleigh damping ratio on modes 1 and 2, in [0, 1) (default 0.02).
    #[serde(default = "default_damping")]
    #[schemars(range(min = 0), transform = bounds::below(1.0))]
    pub damping_ratio: f64,
    /// Discretization (default finite elements, 30 elements).
    #[serde(default = "default_model")]
    pub model: ModelSpec,
    /// EI factors over regions (default none).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub stiffness_regions: Vec<StiffnessRegion>,
}

fn default_damping() -> f64 {
    0.02
}
fn default_model() -> ModelSpec {
    ModelSpec::FiniteElement { elements: 30 }
}

fn is_zero(x: &f64) -> bool {
    *x == 0.0
}

impl BridgeSection {
    /// The span lengths, from `spans_m` or the single `span_m`.
    pub fn spans(&self) -> Vec<f64> {
        match &self.spans_m {
            Some(spans) => spans.clone(),
            None => self.span_m.into_iter().collect(),
        }
    }

    /// The girder's layout (supports by default pinned, then rollers).
    pub fn girder(&self) -> Girder {
        let spans = self.spans();
        let supports = self.supports.clone().unwrap_or_else(|| {
            (0..=spans.len())
                .map(|i| {
                    if i == 0 {
                        Support::Pinned
                    } else {
                        Support::Roller
                    }
                })
                .collect()
        });
        Girder {
            spans_m: spans,
            supports,
            overhang_left_m: self.overhang_left_m,
            overhang_right_m: self.overhang_right_m,
        }
    }

    /// Total length of the girder, overhangs included (m).
    pub fn length_m(&self) -> f64 {
        self.girder().length_m()
    }

    /// The physical beam.
    pub fn beam(&self) -> BeamProperties {
        BeamProperties {
            girder: self.girder(),
            flexural_rigidity_n_m2: self.flexural_rigidity_n_m2,
            mass_per_length_kg_m: self.mass_per_length_kg_m,
            sections: self.sections.clone(),
            stiffness_regions: self.stiffness_regions.clone(),
        }
    }
}

/// Time integration.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct SolverSection {
    /// Time step (s), a whole number of nanoseconds in (0, 0.1] (default 0.001).
    #[serde(default = "default_dt")]
    #[schemars(transform = bounds::positive, range(max = 0.1))]
    pub dt_s: f64,
    /// Newmark gamma and beta (default average acceleration).
    #[serde(default)]
    pub newmark: NewmarkParams,
    /// Tyre contact law (default `full`, as the paper; `unilateral` allows lift-off).
    #[serde(default)]
    pub contact: ContactLaw,
}

fn default_dt() -> f64 {
    0.001
}

impl Default for SolverSection {
    fn default() -> Self {
        SolverSection {
            dt_s: default_dt(),
            newmark: NewmarkParams::default(),
            contact: ContactLaw::Full,
        }
    }
}

/// The road: one continuous profile over approach, bridge and exit.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct RoadSection {
    /// Profile (default smooth).
    #[serde(default)]
    pub profile: RoadProfileSpec,
    /// Approach length before the bridge where vehicles start (m, default 100), at most
    /// 100 km.
    #[serde(default = "default_approach")]
    #[schemars(transform = bounds::positive, range(max = resolve::MAX_ROAD_M))]
    pub approach_m: f64,
    /// Road after the bridge before vehicles are dropped (m, default 30), at most 100 km.
    #[serde(default = "default_exit")]
    #[schemars(range(min = 0, max = resolve::MAX_ROAD_M))]
    pub exit_m: f64,
    /// Sleeper spacing of a ballasted railway track (m, 0.3 to 1.0): each wheel load then
    /// reaches the deck over three sleepers, a quarter at x - a, half at x, a quarter at
    /// x + a (EN 1991-2 6.3.6.1), and the wheel rides on the same weighted deflection.
    /// Default: none (each tyre acts at its contact point).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(range(min = 0.3, max = 1.0))]
    pub sleeper_spacing_m: Option<f64>,
}

fn default_approach() -> f64 {
    100.0
}
fn default_exit() -> f64 {
    30.0
}

impl Default for RoadSection {
    fn default() -> Self {
        RoadSection {
            profile: RoadProfileSpec::default(),
            approach_m: default_approach(),
            exit_m: default_exit(),
            sleeper_spacing_m: None,
        }
    }
}

/// One vehicle with its entry time.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
// A train may run faster than a road vehicle (the loader's MAX_TRAIN_SPEED_M_S vs
// MAX_SPEED_M_S).
#[schemars(extend(
    "if" = { "properties": { "model": {
        "description": "A train (kind = \"train\") may run at up to 150 m/s.",
        "properties": { "kind": { "const": "train" } }
    } } },
    "then" = { "properties": { "speed_m_s": { "maximum": 150.0 } } },
    "else" = { "properties": { "speed_m_s": { "maximum": 100.0 } } }
))]
pub struct VehicleEntry {
    /// Vehicle id in the truth streams (default: 1-based index).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub id: Option<u32>,
    /// The vehicle model, chosen by `kind`.
    pub model: VehicleModelSpec,
    /// Speed (m/s, > 0; at most 100 for a road vehicle, 150 for a train).
    #[schemars(transform = bounds::positive, range(max = resolve::MAX_TRAIN_SPEED_M_S))]
    pub speed_m_s: f64,
    /// Time at which the front axle is at the start of the approach (s, default 0), at
    /// most 30 days.
    #[serde(default)]
    #[schemars(range(min = 0, max = resolve::MAX_DURATION_S))]
    pub entry_time_s: f64,
    /// Lane number for the records (default 1).
    #[serde(default = "default_lane")]
    pub lane: u32,
    /// 1 (default): towards +x, entering at the left support; -1: the opposite
    /// direction, entering at the right support after its own approach.
    #[serde(default = "default_direction", skip_serializing_if = "is_forward")]
    #[schemars(extend("enum" = [1, -1], "default" = 1))]
    pub direction: i8,
}

fn default_direction() -> i8 {
    1
}

fn is_forward(direction: &i8) -> bool {
    *direction == 1
}

fn default_lane() -> u32 {
    1
}

/// A weigh-in-motion strip on the road.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct WimStationSpec {
    /// Station name in the topics (`/wim/<id>`): letters, digits, `_` and `-`; unique.
    #[schemars(regex(pattern = bounds::TOPIC_SEGMENT))]
    pub id: String,
    /// Strip position on the road axis (m), on the approach: in (-approach_m, 0).
    #[schemars(range(min = -resolve::MAX_ROAD_M), transform = bounds::below(0.0))]
    pub position_m: f64,
    /// What the station reports: `{ kind = "ideal" }` (default: the dynamic tyre force
    /// at the strip), `{ kind = "cost323", class = "B+(7)" }`, `{ kind = "physics",
    /// noise_rel = 0.02 }`.
    #[serde(default)]
    pub model: crate::measurement::wim::WimModelSpec,
    /// Thresholds of the off-scale and low-speed flags.
    #[serde(default)]
    pub limits: crate::measurement::wim::WimLimits,
}

/// Output options.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct OutputSection {
    /// `sample` (default) or `block`.
    #[serde(default = "default_layout")]
    pub layout: Layout,
    /// Samples per block message, 1 to 100 000 (default 50).
    #[serde(default = "default_block")]
    #[schemars(range(min = 1, max = 100_000))]
    pub block_samples: usize,
    /// Rate of `/truth/axle_loads` (Hz, must divide the solver rate, at least one message
    /// in 30 days; default 200).
    #[serde(default = "default_axle_rate")]
    #[schemars(range(min = 1.0 / resolve::MAX_DURATION_S))]
    pub axle_load_rate_hz: f64,
    /// Rate of the deflected shape on `/truth/bridge` (Hz, must divide the solver rate, at
    /// least one message in 30 days; default 20).
    #[serde(default = "default_bridge_rate")]
    #[schemars(range(min = 1.0 / resolve::MAX_DURATION_S))]
    pub bridge_state_rate_hz: f64,
    /// Starts a new file every this much simulated time (s, >= 1): `--out day.mcap` writes
    /// `day-0000.mcap`, `day-0001.mcap`, ... each a complete MCAP with every channel, as a
    /// monitoring system keeps hourly files. Memory then stays flat however long the run
    /// (one file's index grows with its size). Default: one file.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(range(min = 1))]
    pub split_every_s: Option<f64>,
    /// Closes the file's current chunk every this much simulated time (s, > 0; default
    /// 60), so that a run killed midway leaves a file readable up to a recent flush. It
    /// follows simulated time, never the wall clock: the bytes never depend on the
    /// machine's speed. At least 0.001 s, at most 30 days.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(range(min = 0.001, max = resolve::MAX_DURATION_S))]
    pub flush_every_s: Option<f64>,
    /// Rate of the per-sample preview channels (`/preview/...`, Hz; 0: none): each sensor's
    /// measured and true stream decimated by a whole factor with the anti-alias filter,
    /// one sample per message, so that a viewer's plot panel draws every run as time
    /// series (it cannot draw the samples inside a block message against time). The
    /// factor is the sensor rate over this, rounded (at least 1); the actual rate is in
    /// the channel metadata. Default: 25 with the block layout, none with the sample
    /// layout (its messages already are per sample). At most 1e6.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(range(min = 0, max = 1e6))]
    pub preview_rate_hz: Option<f64>,
    /// Rate of the 3D scene on `/scene` (`foxglove.SceneUpdate`, Hz; 0: none): the deck
    /// following the deflected shape (exaggerated, the factor in the scene), the supports,
    /// the vehicles with their axles and the sensors. Every n-th deflected shape gets an
    /// update, n the shape rate over this, rounded (at least 1); the actual rate is in the
    /// channel metadata. Default 10. At most 1e6.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(range(min = 0, max = 1e6))]
    pub scene_rate_hz: Option<f64>,
    /// Triggered records, as railway monitoring keeps them: the sampled streams (sensors,
    /// previews, axle loads, the deflected shape, vehicle states, GNSS) are written only
    /// from `pre_s` before each vehicle's first axle enters the bridge to `post_s` after
    /// its last leaves (overlapping windows merge); events, vehicle and WIM records
    /// always. A day of trains then writes only the passages. Needs every vehicle listed
    /// (no `[traffic]`). Default: none (everything is written).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub trigger: Option<TriggerSpec>,
}

/// `output.trigger`: the window around each passage.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct TriggerSpec {
    /// Kept before the first axle enters the bridge (s, 0 to 3600; default 10).
    #[serde(default = "default_trigger_s")]
    #[schemars(range(min = 0, max = 3600))]
    pub pre_s: f64,
    /// Kept after the last axle leaves it (s, 0 to 3600; default 10).
    #[serde(default = "default_trigger_s")]
    #[schemars(range(min = 0, max = 3600))]
    pub post_s: f64,
}

fn default_trigger_s() -> f64 {
    10.0
}

/// Default of `output.preview_rate_hz` in the block layout: the pass band reaches 10 Hz
/// (the first modes of road bridges, 1-10 Hz) at about a tenth of a 100-200 Hz
/// channel's messages.
pub const DEFAULT_PREVIEW_RATE_HZ: f64 = 25.0;

/// Default of `output.flush_every_s`: a killed run loses at most the last simulated
/// minute (or the last 1 MiB chunk, whichever is less), and one chunk boundary a minute
/// costs a negligible index entry.
pub const DEFAULT_FLUSH_EVERY_S: f64 = 60.0;

fn default_layout() -> Layout {
    Layout::Sample
}
fn default_block() -> usize {
    50
}
fn default_axle_rate() -> f64 {
    200.0
}
fn default_bridge_rate() -> f64 {
    20.0
}

impl Default for OutputSection {
    fn default() -> Self {
        OutputSection {
            layout: default_layout(),
            block_samples: default_block(),
            axle_load_rate_hz: default_axle_rate(),
            bridge_state_rate_hz: default_bridge_rate(),
            split_every_s: None,
            flush_every_s: None,
            preview_rate_hz: None,
            scene_rate_hz: None,
            trigger: None,
        }
    }
}

impl Scenario {
    /// Parses TOML; `source` names the file in errors. Relative paths inside (the road
    /// CSV) are kept as written: see [`Scenario::from_file`].
    pub fn from_toml(text: &str, source: &str) -> Result<Scenario> {
        if text.trim().is_empty() {
            return Err(Error::File {
                path: source.to_string(),
                reason: "is empty: a scenario needs at least a [bridge] table \
                         (`bridgetwin scenario show` prints a complete one)"
                    .into(),
            });
        }
        let document =
            toml::Deserializer::parse(text).map_err(|e| toml_error(source, "", &e, None))?;
        serde_path_to_error::deserialize(document).map_err(|e| {
            // The text is valid TOML here (only its content is wrong): its tables give the
            // ids of the listed items the path runs through.
            let table = toml::from_str::<toml::Table>(text).ok();
            toml_error(source, &tagged::dotted(e.path()), e.inner(), table.as_ref())
        })
    }

    /// Reads and parses a scenario file, and resolves the relative paths in it (the road
    /// CSV) against the file's folder, so that a scenario runs the same from any working
    /// directory. Returns the scenario and the file's text. Errors name the file: it
    /// cannot be read, is not UTF-8 (with the offset of the first bad byte), or is not a
    /// valid scenario.
    pub fn from_file(path: &Path) -> Result<(Scenario, String)> {
        let label = path.display().to_string();
        let fail = |reason: String| Error::File {
            path: label.clone(),
            reason,
        };
        let bytes =
            std::fs::read(path).map_err(|e| fail(format!("cannot read the scenario: {e}")))?;
        let text = String::from_utf8(bytes).map_err(|e| {
            let at = e.utf8_error().valid_up_to();
            fail(format!(
                "is not UTF-8 text (byte 0x{:02x} at offset {at}): a scenario is a TOML file",
                e.as_bytes()[at]
            ))
        })?;
        let mut scenario = Scenario::from_toml(&text, &label)?;
        if let Some(dir) = path.parent() {
            scenario.resolve_relative_paths(dir);
        }
        Ok((scenario, text))
    }

    /// Joins relative file paths in the scenario (the road and temperature CSVs) to `base_dir`.
    pub fn resolve_relative_paths(&mut self, base_dir: &Path) {
        let join = |path: &mut String| {
            if Path::new(path.as_str()).is_relative() && !base_dir.as_os_str().is_empty() {
                *path = base_dir.join(path.as_str()).to_string_lossy().into_owned();
            }
        };
        if let RoadProfileSpec::Csv { path } = &mut self.road.profile {
            join(path);
        }
        if let Some(crate::physics::environment::TemperatureSpec::Csv { path }) =
            self.environment.as_mut().map(|e| &mut e.temperature)
        {
            join(path);
        }
    }

    /// The embedded default.
    pub fn default_scenario() -> Scenario {
        // The embedded file is tested to parse; a failure here is a build defect.
        Scenario::from_toml(DEFAULT_SCENARIO_TOML, "<default scenario>")
            .expect("embedded default scenario parses")
    }

    /// The resolved scenario as TOML (stored in the output).
    pub fn to_toml(&self) -> String {
        toml::to_string(self).unwrap_or_default()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn from_file_resolves_the_road_csv_against_the_scenario_folder() {
        let dir = tempfile::tempdir().unwrap();
        let text = DEFAULT_SCENARIO_TOML.replace(
            r#"profile = { kind = "iso8608", class = "A" }"#,
            r#"profile = { kind = "csv", path = "road.csv" }"#,
        );
        let file = dir.path().join("s.toml");
        std::fs::write(&file, &text).unwrap();
        let (s, read) = Scenario::from_file(&file).unwrap();
        assert_eq!(read, text);
        let expected = dir.path().join("road.csv").to_string_lossy().into_owned();
        assert_eq!(s.road.profile, RoadProfileSpec::Csv { path: expected });

        // Absolute paths stay as written; a bare file name has no folder to join.
        let mut s = Scenario::default_scenario();
        s.road.profile = RoadProfileSpec::Csv {
            path: "/abs/road.csv".into(),
        };
        s.resolve_relative_paths(dir.path());
        assert_eq!(
            s.road.profile,
            RoadProfileSpec::Csv {
                path: "/abs/road.csv".into()
            }
        );
        s.road.profile = RoadProfileSpec::Csv {
            path: "road.csv".into(),
        };
        s.resolve_relative_paths(Path::new(""));
        assert_eq!(
            s.road.profile,
            RoadProfileSpec::Csv {
                path: "road.csv".into()
            }
        );
    }

    #[test]
    fn from_file_names_the_file() {
        let dir = tempfile::tempdir().unwrap();
        let missing = dir.path().join("nope.toml");
        let msg = Scenario::from_file(&missing).unwrap_err().to_string();
        assert!(msg.contains("nope.toml: cannot read the scenario"), "{msg}");
        let garbage = dir.path().join("g.toml");
        std::fs::write(&garbage, b"seed = 1\n\xff\xfe").unwrap();
        let msg = Scenario::from_file(&garbage).unwrap_err().to_string();
        assert!(
            msg.contains("g.toml: is not UTF-8 text (byte 0xff at offset 9)"),
            "{msg}"
        );
    }
}
