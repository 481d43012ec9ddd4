//! The run manifest: what the run will emit, described for its outputs before the first
//! record (see [`crate::record::RunManifest`]).

use crate::error::Result;
use crate::measurement::wim::WimModelSpec;
use crate::record::{
    AxleDetectorInfo, BridgeSummary, DaqClockInfo, GirderSummary, GnssInfo,
    InstrumentedVehicleInfo, PreviewInfo, RoadSummary, RunInfo, RunManifest, SensorChannelInfo,
    StreamRates, VehicleMountInfo, WimStationInfo,
};
use crate::scenario::{Resolved, ResolvedSensor, SensorKind};

use super::Prepared;

/// The manifest of the run `resolved` on the model and road of `prepared`.
pub fn manifest(resolved: &Resolved, prepared: &Prepared) -> Result<RunManifest> {
    let s = &resolved.scenario;
    let model = &prepared.model;
    let (natural_frequencies_hz, damping_ratios) = model.modal_summary(10);
    let sensors = resolved
        .sensors
        .iter()
        .map(|sensor| sensor_info(resolved, sensor))
        .collect();
    Ok(RunManifest {
        run: RunInfo {
            seed: s.seed,
            start_time: s.start_time.clone(),
            start_time_ns: resolved.start_time_ns,
            scenario_toml: s.to_toml(),
            source_toml: resolved.source_toml.clone(),
            git_revision: resolved.git_revision.clone(),
        },
        bridge: BridgeSummary {
            model: s.bridge.model.label(),
            natural_frequencies_hz,
            damping_ratios,
            damping_ratio: s.bridge.damping_ratio,
            rayleigh_a0_per_s: model.rayleigh.a0_per_s,
            rayleigh_a1_s: model.rayleigh.a1_s,
            flexural_rigidity_n_m2: s.bridge.flexural_rigidity_n_m2,
            mass_per_length_kg_m: s.bridge.mass_per_length_kg_m,
            length_m: s.bridge.length_m(),
            layout: girder_summary(&s.bridge.girder()),
            shape_position_m: model.shape_positions_m().to_vec(),
            temperatures_c: prepared
                .condition
                .as_ref()
                .map(|c| (c.state.temperature_structure_c, c.state.temperature_air_c)),
        },
        road: RoadSummary {
            description: prepared.road.describe().to_string(),
            csv: prepared.road.to_csv(),
        },
        sensors,
        wim_stations: s
            .wim_stations
            .iter()
            .map(|w| WimStationInfo {
                id: w.id.clone(),
                position_m: w.position_m,
                model: wim_model_label(&w.model),
            })
            .collect(),
        gnss: s
            .gnss
            .iter()
            .map(|g| GnssInfo {
                id: g.id.clone(),
                vehicle_id: g.vehicle,
                rate_hz: g.rate_hz,
                position_noise_m: g.position_noise_m,
                correlation_s: g.correlation_s,
                speed_noise_m_s: g.speed_noise_m_s,
            })
            .collect(),
        axle_detectors: s
            .axle_detectors
            .iter()
            .map(|d| AxleDetectorInfo {
                id: d.id.clone(),
                position_m: d.position_m,
                lane: d.lane,
                jitter_s: d.jitter_s,
                miss_probability: d.miss_probability,
            })
            .collect(),
        instrumented_vehicles: resolved
            .instrumented_vehicles
            .iter()
            .filter_map(|&id| resolved.vehicles.iter().find(|v| v.id == id))
            .map(|v| InstrumentedVehicleInfo {
                vehicle_id: v.id,
                model: v.dynamics.name.clone(),
                dof_names: v.dynamics.dof_names.clone(),
                axles: v.dynamics.axles.len(),
            })
            .collect(),
        rates: StreamRates {
            axle_load_rate_hz: s.output.axle_load_rate_hz,
            bridge_state_rate_hz: s.output.bridge_state_rate_hz,
        },
        layout: s.output.layout,
        block_samples: s.output.block_samples,
        scene: resolved.scene,
    })
}

/// One sensor's channel description, with its chain as realised.
fn sensor_info(resolved: &Resolved, sensor: &ResolvedSensor) -> SensorChannelInfo {
    let spec = &sensor.spec;
    let noise_density_per_sqrt_hz = match sensor.resolved_chain() {
        Some(chain) => chain.chain_parameters().noise_density,
        None => sensor.noise_density,
    };
    let chain = match &sensor.chain {
        Some(chain) => chain.parameters().to_vec(),
        None => Vec::new(),
    };
    let clock = sensor.node.zip(sensor.clock.as_ref()).map(|(i, clock)| {
        let node = &resolved.scenario.daq_nodes[i];
        DaqClockInfo {
            node_id: node.id.clone(),
            drift_ppm: node.clock.drift_ppm,
            offset_s: node.clock.offset_s,
            true_rate_hz: clock.true_rate_hz(),
        }
    });
    SensorChannelInfo {
        id: spec.id.clone(),
        kind: spec.kind,
        rate: sensor.rate,
        rate_hz: spec.rate_hz,
        position_m: sensor.position_m,
        vehicle: sensor.mount.as_ref().map(|m| VehicleMountInfo {
            vehicle_id: m.vehicle_id,
            mount: m.label.clone(),
        }),
        model: sensor.model_name().to_string(),
        noise_density_per_sqrt_hz,
        chain,
        clock,
        gauge_depth_m: (spec.kind == SensorKind::Strain).then_some(sensor.gauge_depth_m),
        has_faults: spec.faults.as_ref().is_some_and(|f| !f.is_empty()),
        preview: sensor.preview_factor.map(|factor| PreviewInfo {
            factor,
            rate_hz: spec.rate_hz / factor as f64,
        }),
    }
}

/// A station model as one short label.
fn wim_model_label(model: &WimModelSpec) -> String {
    match model {
        WimModelSpec::Ideal => "ideal (dynamic tyre force at the strip)".into(),
        WimModelSpec::Cost323 { class, .. } => format!("cost323 {class}"),
        WimModelSpec::Physics { noise_rel, .. } => {
            format!("physics (dynamic tyre force x (1 + N(0, {noise_rel})))")
        }
    }
}

/// The layout for the run's metadata, when the girder is not one simple span.
fn girder_summary(girder: &crate::physics::bridge::Girder) -> Option<GirderSummary> {
    (!girder.is_simple_span()).then(|| GirderSummary {
        spans_m: girder.spans_m.clone(),
        support_position_m: girder.support_positions_m(),
        supports: girder
            .supports
            .iter()
            .map(|s| s.name().to_string())
            .collect(),
    })
}
