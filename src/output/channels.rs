//! The channels of a run and its metadata records, registered from the run manifest
//! alone: units, rates, positions, the realised chain values and the clocks become
//! channel metadata; the run, the scenario and the model become metadata records; the
//! scenario as written and the road profile become attachments.

use std::collections::BTreeMap;
use std::io::{Seek, Write};

use super::blocks::{OpenBlock, Stream};
use super::proto::foxglove::{Log, SceneUpdate};
use super::proto::v1::{
    AccelerationSample, AxleDetection, AxleDetectionTruth, AxleLoads, BridgeState,
    DisplacementSample, FaultInterval, GnssFix, ReactionSample, RotationSample, SampleBlock,
    SensorTruth, SensorTruthBlock, StrainSample, TemperatureSample, VehicleState, VehicleTruth,
    WimRecord,
};
use super::scene::SCENE_FRAME;
use super::{metadata, ChannelId, McapSink, Topics};
use crate::error::Result;
use crate::record::{
    GirderSummary, Layout, PreviewInfo, RunManifest, SensorChannelInfo, SensorKind,
};

/// The channels of one sensor.
pub(super) struct SensorChannels {
    pub kind: SensorKind,
    pub id: String,
    pub measured: ChannelId,
    pub truth: ChannelId,
    /// Block layout only: the truth samples waiting to fill the next block.
    pub block: Option<OpenBlock>,
    /// Block layout only: the measured samples waiting to fill the next block.
    pub measured_block: Option<OpenBlock>,
    /// The preview's (measured, truth) channels, if the run writes a preview.
    pub preview: Option<(ChannelId, ChannelId)>,
}

impl SensorChannels {
    /// The open blocks (none in the sample layout).
    pub fn open_blocks(&mut self) -> impl Iterator<Item = &mut OpenBlock> {
        self.block.iter_mut().chain(self.measured_block.iter_mut())
    }
}

/// Every channel of a run.
pub(super) struct Channels {
    pub sensors: Vec<SensorChannels>,
    pub axle_loads: ChannelId,
    pub bridge: ChannelId,
    pub vehicles: ChannelId,
    /// Per station: (id, channel, model label as written in its records).
    pub wim: Vec<(String, ChannelId, String)>,
    pub events: ChannelId,
    /// `/truth/faults`, registered when some sensor has faults configured.
    pub faults: Option<ChannelId>,
    /// `/scene`, registered when the run writes the 3D scene.
    pub scene: Option<ChannelId>,
    /// Per GNSS receiver, manifest order.
    pub gnss: Vec<ChannelId>,
    /// Per axle detector, manifest order: (id, channel).
    pub axle_detectors: Vec<(String, ChannelId)>,
    /// `/truth/axle_detections`, registered when the run has axle detectors.
    pub axle_detections: Option<ChannelId>,
    /// Per instrumented vehicle: (vehicle id, `/truth/vehicle_state/<id>`).
    pub vehicle_states: Vec<(u32, ChannelId)>,
}

/// Writes the run's metadata records and attachments, then registers every channel.
pub(super) fn register<W: Write + Seek>(
    sink: &mut McapSink<W>,
    manifest: &RunManifest,
) -> Result<Channels> {
    write_metadata(sink, manifest)?;
    let sensors = manifest
        .sensors
        .iter()
        .map(|s| sensor_channels(sink, manifest, s))
        .collect::<Result<Vec<_>>>()?;
    let axle_rate = format!("{}", manifest.rates.axle_load_rate_hz);
    let axle_loads = sink.add_channel::<AxleLoads>(
        Topics::AXLE_LOADS,
        metadata([
            ("unit", "N"),
            ("sample_rate_hz", axle_rate.as_str()),
            ("sign", "force on the road positive"),
        ]),
    )?;
    let bridge_rate = format!("{}", manifest.rates.bridge_state_rate_hz);
    let bridge = sink.add_channel::<BridgeState>(
        Topics::BRIDGE,
        metadata([
            ("unit", "m"),
            ("sample_rate_hz", bridge_rate.as_str()),
            ("sign", "deflection downward positive"),
        ]),
    )?;
    let vehicles = sink.add_channel::<VehicleTruth>(
        Topics::VEHICLES,
        metadata([("content", "one record per vehicle")]),
    )?;
    let mut wim = Vec::new();
    for w in &manifest.wim_stations {
        let position = format!("{}", w.position_m);
        let ch = sink.add_channel::<WimRecord>(
            &Topics::wim(&w.id)?,
            metadata([
                ("position_m", position.as_str()),
                ("station_model", w.model.as_str()),
            ]),
        )?;
        wim.push((w.id.clone(), ch, w.model.clone()));
    }
    let events = sink.add_channel::<Log>(Topics::EVENTS, BTreeMap::new())?;
    let faults = match manifest.has_faults() {
        true => Some(sink.add_channel::<FaultInterval>(
            Topics::FAULTS,
            metadata([("content", "one record per fault interval, at its start")]),
        )?),
        false => None,
    };
    let scene = match &manifest.scene {
        Some(info) => {
            let rate = format!("{}", info.rate_hz);
            let factor = format!("{}", info.exaggeration);
            let peak = format!("{}", info.expected_peak_m);
            Some(sink.add_channel::<SceneUpdate>(
                Topics::SCENE,
                metadata([
                    ("sample_rate_hz", rate.as_str()),
                    ("frame_id", SCENE_FRAME),
                    (
                        "axes",
                        "x along the bridge from the left support, y across (lane 0 on +y), \
                         z up; m",
                    ),
                    ("exaggeration", factor.as_str()),
                    ("expected_peak_m", peak.as_str()),
                    (
                        "content",
                        "the whole scene each message: the deck following the deflected \
                         shape of /truth/bridge drawn exaggeration times larger, the supports, \
                         the vehicles as boxes with a wheel pair at each axle of \
                         /truth/axle_loads, the sensors and WIM strips",
                    ),
                ]),
            )?)
        }
        None => None,
    };
    let instruments = instrument_channels(sink, manifest)?;
    Ok(Channels {
        sensors,
        axle_loads,
        bridge,
        vehicles,
        wim,
        events,
        faults,
        scene,
        gnss: instruments.0,
        axle_detectors: instruments.1,
        axle_detections: instruments.2,
        vehicle_states: instruments.3,
    })
}

/// The channels of what sees the vehicles.
type InstrumentChannels = (
    Vec<ChannelId>,
    Vec<(String, ChannelId)>,
    Option<ChannelId>,
    Vec<(u32, ChannelId)>,
);

/// Registers the GNSS receivers, the axle detectors (and their truth) and the
/// instrumented vehicles' state channels.
fn instrument_channels<W: Write + Seek>(
    sink: &mut McapSink<W>,
    manifest: &RunManifest,
) -> Result<InstrumentChannels> {
    let mut gnss = Vec::new();
    for g in &manifest.gnss {
        let values = [
            format!("{}", g.rate_hz),
            format!("{}", g.position_noise_m),
            format!("{}", g.correlation_s),
            format!("{}", g.speed_noise_m_s),
        ];
        gnss.push(sink.add_channel::<GnssFix>(
            &Topics::gnss(g.vehicle_id, &g.id)?,
            metadata([
                ("unit", "m, m/s"),
                ("sample_rate_hz", values[0].as_str()),
                ("position_noise_m", values[1].as_str()),
                ("position_correlation_s", values[2].as_str()),
                ("speed_noise_m_s", values[3].as_str()),
                (
                    "content",
                    "position of the front axle on the road axis (the bridge's x) and speed, \
                     with the receiver's error; the truth is on /truth/vehicle_state",
                ),
            ]),
        )?);
    }
    let mut detectors = Vec::new();
    for d in &manifest.axle_detectors {
        let values = [
            format!("{}", d.position_m),
            d.lane.map_or("all".to_string(), |l| l.to_string()),
            format!("{}", d.jitter_s),
            format!("{}", d.miss_probability),
        ];
        let ch = sink.add_channel::<AxleDetection>(
            &Topics::axle_detector(&d.id)?,
            metadata([
                ("position_m", values[0].as_str()),
                ("lane", values[1].as_str()),
                ("jitter_s", values[2].as_str()),
                ("miss_probability", values[3].as_str()),
                (
                    "content",
                    "one message per axle detected: detected_time is the detector's time of the \
                     crossing (true instant plus jitter); timestamp = log time = the first \
                     solver instant after it",
                ),
            ]),
        )?;
        detectors.push((d.id.clone(), ch));
    }
    let detections = match manifest.axle_detectors.is_empty() {
        true => None,
        false => Some(sink.add_channel::<AxleDetectionTruth>(
            Topics::AXLE_DETECTIONS,
            metadata([(
                "content",
                "every axle crossing of every detector: crossing_time is the true instant, \
                 detected and detected_time what the detector made of it",
            )]),
        )?),
    };
    let rate = format!("{}", manifest.rates.axle_load_rate_hz);
    let mut states = Vec::new();
    for v in &manifest.instrumented_vehicles {
        let names = v.dof_names.join(",");
        let axles = v.axles.to_string();
        let ch = sink.add_channel::<VehicleState>(
            &Topics::vehicle_state(v.vehicle_id),
            metadata([
                ("sample_rate_hz", rate.as_str()),
                ("model", v.model.as_str()),
                ("dof_names", names.as_str()),
                ("axles", axles.as_str()),
                (
                    "sign",
                    "vehicle DOFs upward positive; deck deflection and acceleration downward \
                     positive; elevations upward positive",
                ),
            ]),
        )?;
        states.push((v.vehicle_id, ch));
    }
    Ok((gnss, detectors, detections, states))
}

/// The metadata records `bridgetwin`, `scenario`, `bridge_model` and the attachments
/// `scenario.toml` (as the user wrote it) and `road_profile.csv`.
fn write_metadata<W: Write + Seek>(sink: &mut McapSink<W>, manifest: &RunManifest) -> Result<()> {
    let run = &manifest.run;
    sink.write_metadata(
        "bridgetwin",
        BTreeMap::from([
            ("version".to_string(), env!("CARGO_PKG_VERSION").to_string()),
            ("git_revision".to_string(), run.git_revision.clone()),
            ("seed".to_string(), run.seed.to_string()),
            ("start_time".to_string(), run.start_time.clone()),
        ]),
    )?;
    sink.write_metadata(
        "scenario",
        BTreeMap::from([("toml".to_string(), run.scenario_toml.clone())]),
    )?;
    let b = &manifest.bridge;
    let freqs: Vec<String> = b
        .natural_frequencies_hz
        .iter()
        .map(|f| format!("{f:.6}"))
        .collect();
    sink.write_metadata(
        "bridge_model",
        BTreeMap::from([
            ("model".to_string(), b.model.clone()),
            ("natural_frequencies_hz".to_string(), freqs.join(",")),
            ("damping_ratio".to_string(), b.damping_ratio.to_string()),
            (
                "rayleigh_a0_per_s".to_string(),
                b.rayleigh_a0_per_s.to_string(),
            ),
            ("rayleigh_a1_s".to_string(), b.rayleigh_a1_s.to_string()),
            (
                "flexural_rigidity_n_m2".to_string(),
                b.flexural_rigidity_n_m2.to_string(),
            ),
            (
                "mass_per_length_kg_m".to_string(),
                b.mass_per_length_kg_m.to_string(),
            ),
            ("span_m".to_string(), b.length_m.to_string()),
            ("road".to_string(), manifest.road.description.clone()),
        ])
        .into_iter()
        .chain(girder_metadata(b.layout.as_ref()))
        .collect(),
    )?;
    let start = run.start_time_ns;
    sink.attach(
        "scenario.toml",
        "application/toml",
        run.source_toml.as_bytes(),
        start,
    )?;
    sink.attach(
        "road_profile.csv",
        "text/csv",
        manifest.road.csv.as_bytes(),
        start,
    )
}

/// The channel metadata of one sensor: what a user needs to interpret its samples.
fn sensor_metadata(manifest: &RunManifest, sensor: &SensorChannelInfo) -> BTreeMap<String, String> {
    let rate = format!("{}", sensor.rate_hz);
    let position = format!("{}", sensor.position_m);
    let density = format!("{}", sensor.noise_density_per_sqrt_hz);
    let layout_name = match manifest.layout {
        Layout::Sample => "sample".to_string(),
        Layout::Block => format!("block of {} samples", manifest.block_samples),
    };
    let mut meta = metadata([
        ("unit", sensor.kind.unit()),
        ("sample_rate_hz", rate.as_str()),
        ("position_m", position.as_str()),
        ("sensor_model", sensor.model.as_str()),
        ("noise_density_per_sqrt_hz", density.as_str()),
        ("sign", sensor.kind.sign()),
        ("layout", layout_name.as_str()),
    ]);
    for (name, value) in &sensor.chain {
        meta.insert(format!("chain.{name}"), format!("{value}"));
    }
    if let Some(clock) = &sensor.clock {
        meta.insert("daq_node".into(), clock.node_id.clone());
        meta.insert("nominal_sample_rate_hz".into(), rate.clone());
        meta.insert(
            "true_sample_rate_hz".into(),
            format!("{}", clock.true_rate_hz),
        );
        meta.insert("clock_drift_ppm".into(), format!("{}", clock.drift_ppm));
        meta.insert("clock_offset_s".into(), format!("{}", clock.offset_s));
        meta.insert(
            "timestamps".into(),
            "measured: node clock; truth: true time (node_timestamp holds the node's)".into(),
        );
    }
    if let Some(depth) = sensor.gauge_depth_m {
        meta.insert("gauge_depth_m".into(), format!("{depth}"));
    }
    meta
}

/// Registers the measured and truth channels of one sensor in the run's layout.
fn sensor_channels<W: Write + Seek>(
    sink: &mut McapSink<W>,
    manifest: &RunManifest,
    sensor: &SensorChannelInfo,
) -> Result<SensorChannels> {
    let layout = manifest.layout;
    let mut meta = sensor_metadata(manifest, sensor);
    let topic = match &sensor.vehicle {
        Some(v) => {
            meta.insert("vehicle_id".into(), v.vehicle_id.to_string());
            meta.insert("mount".into(), v.mount.clone());
            meta.insert(
                "sign".into(),
                "downward positive (as the bridge's accelerometers)".into(),
            );
            Topics::vehicle_sensor(sensor.kind, v.vehicle_id, &sensor.id)?
        }
        None => Topics::sensor(sensor.kind, &sensor.id)?,
    };
    let measured = match (layout, sensor.kind) {
        (Layout::Block, _) => sink.add_channel::<SampleBlock>(&topic, meta.clone())?,
        (_, SensorKind::Accelerometer) => {
            sink.add_channel::<AccelerationSample>(&topic, meta.clone())?
        }
        (_, SensorKind::Strain) => sink.add_channel::<StrainSample>(&topic, meta.clone())?,
        (_, SensorKind::Displacement) => {
            sink.add_channel::<DisplacementSample>(&topic, meta.clone())?
        }
        (_, SensorKind::Inclinometer) => {
            sink.add_channel::<RotationSample>(&topic, meta.clone())?
        }
        (_, SensorKind::LoadCell) => sink.add_channel::<ReactionSample>(&topic, meta.clone())?,
        (_, SensorKind::Thermometer) => {
            sink.add_channel::<TemperatureSample>(&topic, meta.clone())?
        }
    };
    meta.insert(
        "sensor_model".into(),
        "truth (noise-free, unfiltered, true time)".into(),
    );
    let truth_topic = Topics::truth_sensor(&sensor.id)?;
    let truth = match layout {
        Layout::Sample => sink.add_channel::<SensorTruth>(&truth_topic, meta)?,
        Layout::Block => sink.add_channel::<SensorTruthBlock>(&truth_topic, meta)?,
    };
    let preview = match &sensor.preview {
        Some(p) => Some(preview_channels(sink, sensor, p)?),
        None => None,
    };
    let blocked = layout == Layout::Block;
    let block = |stream| OpenBlock::new(stream, sensor.rate, manifest.block_samples);
    Ok(SensorChannels {
        kind: sensor.kind,
        id: sensor.id.clone(),
        measured,
        truth,
        block: blocked.then(|| block(Stream::Truth)),
        measured_block: blocked.then(|| block(Stream::Measured)),
        preview,
    })
}

/// Registers a sensor's preview channels: the measured and the true stream decimated,
/// each in the sensor's per-sample message type.
fn preview_channels<W: Write + Seek>(
    sink: &mut McapSink<W>,
    sensor: &SensorChannelInfo,
    preview: &PreviewInfo,
) -> Result<(ChannelId, ChannelId)> {
    let rate = format!("{}", preview.rate_hz);
    let factor = format!("{}", preview.factor);
    let position = format!("{}", sensor.position_m);
    let mut meta = metadata([
        ("unit", sensor.kind.unit()),
        ("sample_rate_hz", rate.as_str()),
        ("decimation_factor", factor.as_str()),
        ("position_m", position.as_str()),
        ("sensor_model", sensor.model.as_str()),
        (
            "content",
            "preview for viewers: the measured stream decimated with an anti-alias filter \
             (pass band to 0.4 x sample_rate_hz, 60 dB from 0.5 x); analyses read the \
             full-rate topic",
        ),
        ("sign", sensor.kind.sign()),
    ]);
    let measured_topic = Topics::preview(Topics::segment(sensor.kind), &sensor.id)?;
    let truth_topic = Topics::preview_truth(&sensor.id)?;
    let add = |sink: &mut McapSink<W>, topic: &str, meta| match sensor.kind {
        SensorKind::Accelerometer => sink.add_channel::<AccelerationSample>(topic, meta),
        SensorKind::Strain => sink.add_channel::<StrainSample>(topic, meta),
        SensorKind::Displacement => sink.add_channel::<DisplacementSample>(topic, meta),
        SensorKind::Inclinometer => sink.add_channel::<RotationSample>(topic, meta),
        SensorKind::LoadCell => sink.add_channel::<ReactionSample>(topic, meta),
        SensorKind::Thermometer => sink.add_channel::<TemperatureSample>(topic, meta),
    };
    let mut measured_meta = meta.clone();
    if let Some(clock) = &sensor.clock {
        // The preview keeps the measured stream's instants, so its stamps are the node's.
        measured_meta.insert("daq_node".into(), clock.node_id.clone());
        measured_meta.insert(
            "timestamps".into(),
            "node clock (as the measured topic); the truth preview is in true time".into(),
        );
    }
    let measured = add(sink, &measured_topic, measured_meta)?;
    meta.insert(
        "content".into(),
        "preview for viewers: the truth of the measured quantity, decimated as the measured \
         preview (true time)"
            .into(),
    );
    let truth = add(sink, &truth_topic, meta)?;
    Ok((measured, truth))
}

/// `spans_m`, `support_position_m` and `supports` (comma-separated) of a continuous
/// girder; nothing for one simple span, whose `span_m` says it all. (`span_m` is then the
/// girder's whole length.)
fn girder_metadata(layout: Option<&GirderSummary>) -> Vec<(String, String)> {
    let list = |v: &[f64]| {
        v.iter()
            .map(|x| x.to_string())
            .collect::<Vec<_>>()
            .join(",")
    };
    layout.map_or_else(Vec::new, |g| {
        vec![
            ("spans_m".to_string(), list(&g.spans_m)),
            (
                "support_position_m".to_string(),
                list(&g.support_position_m),
            ),
            ("supports".to_string(), g.supports.join(",")),
        ]
    })
}
