//! A Foxglove layout for one run, built from the run file's own channels
//! (`bridgetwin layout RUN.mcap`, `docs/output.md` section 3): the sensors grouped by kind,
//! each measured against its truth (the preview topics of a block-layout run, the sensor
//! topics of a sample-layout run), the axle forces of the first vehicles (or chosen
//! ones), the deflected shape along the bridge with a fixed range from the run's peak,
//! the events, a WIM table per station and the 3D scene.
//!
//! Nothing is re-simulated: [`RunContents`] reads the file once, [`layout`] decides the
//! panels from it alone.

mod contents;
mod panels;
mod vehicles;

use std::path::Path;

use serde_json::{json, Map, Value};

pub use contents::{ChannelInfo, RunContents, VehicleInfo};
pub use panels::{Plot, Series, XAxis, TITLE_KEY};

use super::proto::foxglove::{Log, SceneUpdate};
use super::proto::v1::{AxleLoads, BridgeState, SensorTruth, WimRecord};
use super::scene::SCENE_FRAME;
use super::Topics;
use crate::error::{Error, Result};
use panels::{layout_file, log_panel, split, split_weighted, table_panel, three_d_panel};
use prost::Name;

/// Options of [`layout`]; `Default` gives the values documented per field.
#[derive(Debug, Clone, PartialEq)]
pub struct LayoutOptions {
    /// Vehicles whose axle forces get a panel each. Default: empty, the first
    /// `max_vehicles` to reach the bridge.
    pub vehicles: Vec<u32>,
    /// Axle-force panels when `vehicles` is empty. Default 3.
    pub max_vehicles: usize,
    /// Sensors per kind plotted, spread along the bridge. Default 4.
    pub max_sensors_per_kind: usize,
}

impl Default for LayoutOptions {
    fn default() -> Self {
        LayoutOptions {
            vehicles: Vec::new(),
            max_vehicles: 3,
            max_sensors_per_kind: 4,
        }
    }
}

/// A layout and what the user should know about it (sensors left out, no shape data).
#[derive(Debug, Clone, PartialEq)]
pub struct FoxgloveLayout {
    /// The layout file's content (Foxglove: Layouts, Import from file).
    pub json: Value,
    pub notes: Vec<String>,
}

/// One kind of sensor: its topic segment, the value field of its per-sample messages
/// (the same name in `SensorTruth`), and how it is drawn.
struct Kind {
    segment: &'static str,
    title: &'static str,
    field: &'static str,
    /// Downward-positive quantities are drawn down (negated), as the eye expects.
    drawn_down: bool,
}

/// The kinds of sensor a run can hold, in panel order.
const KINDS: &[Kind] = &[
    Kind {
        segment: "accel",
        title: "Acceleration, m/s^2 (downward positive)",
        field: crate::record::SensorKind::Accelerometer.value_field(),
        drawn_down: false,
    },
    Kind {
        segment: "strain",
        title: "Strain, microstrain (tension positive)",
        field: crate::record::SensorKind::Strain.value_field(),
        drawn_down: false,
    },
    Kind {
        segment: "disp",
        title: "Displacement, m (downward positive, drawn down)",
        field: crate::record::SensorKind::Displacement.value_field(),
        drawn_down: true,
    },
    Kind {
        segment: "tilt",
        title: "Rotation, rad (slope of the downward deflection)",
        field: crate::record::SensorKind::Inclinometer.value_field(),
        drawn_down: false,
    },
    Kind {
        segment: "load",
        title: "Bearing reaction, N (compression positive)",
        field: crate::record::SensorKind::LoadCell.value_field(),
        drawn_down: false,
    },
    Kind {
        segment: "temp",
        title: "Deck temperature, degC",
        field: crate::record::SensorKind::Thermometer.value_field(),
        drawn_down: false,
    },
];

/// Schema of a per-sample sensor message (the sample layout and the preview).
fn is_per_sample(schema: &str) -> bool {
    schema.starts_with("bridgetwin.v1.") && schema.ends_with("Sample") && !schema.ends_with("Block")
}

/// The layout of the run in `path`.
pub fn layout_for_file(path: &Path, options: &LayoutOptions) -> Result<FoxgloveLayout> {
    layout(&RunContents::read(path)?, options).map_err(|e| match e {
        Error::File { reason, .. } => Error::File {
            path: path.display().to_string(),
            reason,
        },
        other => other,
    })
}

/// The layout of a run with `contents`.
pub fn layout(contents: &RunContents, options: &LayoutOptions) -> Result<FoxgloveLayout> {
    let mut notes = Vec::new();
    let mut config = Map::new();
    let mut sensor_ids = Vec::new();
    for kind in KINDS {
        if let Some(plot) = sensor_plot(contents, kind, options.max_sensors_per_kind, &mut notes) {
            let id = format!("Plot!{}", kind.segment);
            config.insert(id.clone(), plot.config());
            sensor_ids.push(json!(id));
        }
    }
    let mut middle = Vec::new();
    for plot in axle_plots(contents, options, &mut notes)? {
        let id = format!("Plot!axles_{}", middle.len());
        config.insert(id.clone(), plot.config());
        middle.push(json!(id));
    }
    for plot in vehicles::vehicle_plots(contents, &mut notes) {
        let id = format!("Plot!vehicle_{}", middle.len());
        config.insert(id.clone(), plot.config());
        middle.push(json!(id));
    }
    let stations: Vec<&ChannelInfo> = contents
        .channels
        .values()
        .filter(|c| c.topic.starts_with("/wim/") && c.schema == WimRecord::full_name())
        .filter(|c| c.messages > 0)
        .collect();
    if let Some(plot) = wim_plot(&stations) {
        config.insert("Plot!wim".into(), plot.config());
        middle.push(json!("Plot!wim"));
    }
    // The 3D view gets twice the height of the other panels of its column.
    let mut right = Vec::new();
    if has_data(contents, Topics::SCENE, &SceneUpdate::full_name()) {
        let span_m = contents.span_m.unwrap_or(30.0);
        let panel = three_d_panel(
            "3D scene (/scene)",
            Topics::SCENE,
            SCENE_FRAME,
            [0.5 * span_m, 0.0, 0.0],
            // The span and a little of the approaches in a panel about as wide as high.
            1.1 * span_m,
        );
        config.insert("3D!scene".into(), panel);
        right.push((json!("3D!scene"), 2.0));
    }
    if let Some(plot) = shape_plot(contents, &mut notes) {
        config.insert("Plot!shape".into(), plot.config());
        right.push((json!("Plot!shape"), 1.0));
    }
    if has_data(contents, Topics::EVENTS, &Log::full_name()) {
        config.insert("RosOut!events".into(), log_panel("Events", Topics::EVENTS));
        right.push((json!("RosOut!events"), 1.0));
    }
    for (i, channel) in stations.iter().enumerate() {
        let id = format!("Table!wim_{i}");
        let title = format!("WIM record, latest ({})", channel.topic);
        config.insert(id.clone(), table_panel(&title, &channel.topic));
        right.push((json!(id), 1.0));
    }
    let mut columns: Vec<Value> = [sensor_ids, middle]
        .iter()
        .filter(|column| !column.is_empty())
        .map(|column| split(column, "column"))
        .collect();
    if !right.is_empty() {
        columns.push(split_weighted(&right, "column"));
    }
    if columns.is_empty() {
        return Err(Error::File {
            path: "run".into(),
            reason: "holds none of the topics a layout shows (sensors, /truth/axle_loads, \
                     /truth/bridge, /events, /wim/..., /scene)"
                .into(),
        });
    }
    Ok(FoxgloveLayout {
        json: layout_file(config, split(&columns, "row")),
        notes,
    })
}

/// Whether `topic` exists with schema `schema` and holds messages.
fn has_data(contents: &RunContents, topic: &str, schema: &str) -> bool {
    contents
        .channels
        .get(topic)
        .is_some_and(|c| c.schema == schema && c.messages > 0)
}

/// The measured and true series of one sensor.
struct SensorSeries {
    id: String,
    position_m: f64,
    measured: String,
    truth: Option<String>,
}

/// The plot of up to `max` sensors of `kind`, spread along the bridge.
fn sensor_plot(
    contents: &RunContents,
    kind: &Kind,
    max: usize,
    notes: &mut Vec<String>,
) -> Option<Plot> {
    let mut sensors = Vec::new();
    let measured_prefix = format!("/sensors/{}/", kind.segment);
    for channel in contents.channels.values() {
        let Some(id) = channel.topic.strip_prefix(&measured_prefix) else {
            continue;
        };
        if id.contains('/') {
            // `/sensors/accel/A1/blocks` of a file with both layouts.
            continue;
        }
        let Some((measured, truth)) = plotted_streams(contents, kind.segment, id, &channel.topic)
        else {
            notes.push(format!(
                "{}: no per-sample stream (block layout without a preview): not plotted; set \
                 [output] preview_rate_hz",
                channel.topic
            ));
            continue;
        };
        let position_m = channel
            .metadata
            .get("position_m")
            .and_then(|p| p.parse().ok())
            .unwrap_or(f64::NAN);
        sensors.push(SensorSeries {
            id: id.to_string(),
            position_m,
            measured,
            truth,
        });
    }
    if sensors.is_empty() {
        return None;
    }
    sensors.sort_by(|a, b| a.position_m.total_cmp(&b.position_m).then(a.id.cmp(&b.id)));
    let total = sensors.len();
    let chosen = spread(total, max.max(1));
    if chosen.len() < total {
        let ids: Vec<&str> = chosen.iter().map(|&i| sensors[i].id.as_str()).collect();
        notes.push(format!(
            "{}: {} of {total} sensors plotted ({}), spread along the bridge",
            kind.segment,
            chosen.len(),
            ids.join(", ")
        ));
    }
    let drawn = |topic: &str| match kind.drawn_down {
        true => format!("{topic}.{}.@negative", kind.field),
        false => format!("{topic}.{}", kind.field),
    };
    let mut series = Vec::new();
    for &i in &chosen {
        let s = &sensors[i];
        series.push(Series::new(
            drawn(&s.measured),
            format!("{} measured", s.id),
        ));
        if let Some(truth) = &s.truth {
            series.push(Series::new(drawn(truth), format!("{} truth", s.id)));
        }
    }
    if kind.drawn_down && has_data(contents, Topics::BRIDGE, &BridgeState::full_name()) {
        series.push(Series::new(
            format!("{}.midspan_deflection_m.@negative", Topics::BRIDGE),
            "midspan (model truth)".into(),
        ));
    }
    let source = match sensors[0].measured.starts_with("/preview/") {
        true => "preview, decimated",
        false => "every sample",
    };
    Some(Plot {
        title: format!("{}: measured and truth ({source})", kind.title),
        series,
        x: XAxis::Time,
        y_range: None,
    })
}

/// The (measured, truth) topics to plot for sensor `id` measured on `topic`: its preview
/// where the run writes one (a block-layout run), else its own per-sample stream with its
/// truth; `None` when neither is a per-sample stream with data.
fn plotted_streams(
    contents: &RunContents,
    segment: &str,
    id: &str,
    topic: &str,
) -> Option<(String, Option<String>)> {
    let usable = |topic: &str| {
        contents
            .channels
            .get(topic)
            .is_some_and(|c| is_per_sample(&c.schema) && c.messages > 0)
    };
    let preview = format!("/preview/{segment}/{id}");
    let preview_truth = format!("/preview/truth/{id}");
    let truth_topic = format!("/truth/sensors/{id}");
    if usable(&preview) {
        Some((preview, usable(&preview_truth).then_some(preview_truth)))
    } else if usable(topic) {
        let truth =
            has_data(contents, &truth_topic, &SensorTruth::full_name()).then_some(truth_topic);
        Some((topic.to_string(), truth))
    } else {
        None
    }
}

/// `count` indices out of `0..total`, evenly spread and including both ends.
fn spread(total: usize, count: usize) -> Vec<usize> {
    if total <= count {
        return (0..total).collect();
    }
    if count == 1 {
        return vec![0];
    }
    let mut out: Vec<usize> = (0..count)
        .map(|k| ((k * (total - 1)) as f64 / (count - 1) as f64).round() as usize)
        .collect();
    out.dedup();
    out
}

/// One panel per vehicle: its axles' tyre forces (static loads listed, hidden), over the
/// time it is near the bridge.
fn axle_plots(
    contents: &RunContents,
    options: &LayoutOptions,
    notes: &mut Vec<String>,
) -> Result<Vec<Plot>> {
    if !has_data(contents, Topics::AXLE_LOADS, &AxleLoads::full_name()) {
        return Ok(Vec::new());
    }
    let chosen: Vec<_> = match options.vehicles.is_empty() {
        false => options
            .vehicles
            .iter()
            .map(|&id| {
                contents
                    .vehicles
                    .iter()
                    .find(|v| v.vehicle_id == id)
                    .copied()
                    .ok_or_else(|| unknown_vehicle(contents, id))
            })
            .collect::<Result<_>>()?,
        true => {
            let mut crossed: Vec<_> = contents
                .vehicles
                .iter()
                .filter(|v| v.entry_ns.is_some())
                .copied()
                .collect();
            crossed.sort_by_key(|v| (v.entry_ns, v.vehicle_id));
            if crossed.len() > options.max_vehicles {
                notes.push(format!(
                    "axle forces of the first {} of {} vehicles that reached the bridge; \
                     choose others with --vehicle ID",
                    options.max_vehicles,
                    crossed.len()
                ));
            }
            crossed.truncate(options.max_vehicles);
            crossed
        }
    };
    let start_ns = contents.first_ns.unwrap_or(0);
    let end_ns = contents.last_ns.unwrap_or(start_ns);
    let seconds = |t: u64| t.saturating_sub(start_ns) as f64 * 1e-9;
    Ok(chosen
        .iter()
        .map(|v| {
            let mut series = Vec::new();
            for axle in 0..v.axles {
                let at = format!(
                    "{}.axles[:]{{vehicle_id=={}}}{{axle_index=={axle}}}",
                    Topics::AXLE_LOADS,
                    v.vehicle_id
                );
                series.push(Series::new(format!("{at}.force_n"), format!("axle {axle}")));
                series.push(Series {
                    enabled: false,
                    ..Series::new(format!("{at}.static_load_n"), format!("axle {axle} static"))
                });
            }
            // Two seconds either side of the crossing: the approach and the exit in view.
            let (entry, exit) = (v.entry_ns.unwrap_or(start_ns), v.exit_ns.unwrap_or(end_ns));
            let lo = (seconds(entry) - 2.0).max(0.0);
            let hi = (seconds(exit) + 2.0).min(seconds(end_ns)).max(lo + 1.0);
            Plot {
                title: format!("Vehicle {}: tyre force per axle, N (truth)", v.vehicle_id),
                series,
                x: XAxis::TimeRange(lo, hi),
                y_range: None,
            }
        })
        .collect())
}

fn unknown_vehicle(contents: &RunContents, id: u32) -> Error {
    let mut ids: Vec<u32> = contents.vehicles.iter().map(|v| v.vehicle_id).collect();
    ids.sort_unstable();
    let listed: Vec<String> = ids.iter().take(12).map(u32::to_string).collect();
    let more = if ids.len() > 12 { ", ..." } else { "" };
    Error::invalid(
        "--vehicle",
        id,
        format!(
            "is not in /truth/vehicles of this run (vehicles: {}{more})",
            listed.join(", ")
        ),
    )
}

/// The gross weight every WIM station measured, one point per vehicle, over the run.
fn wim_plot(stations: &[&ChannelInfo]) -> Option<Plot> {
    if stations.is_empty() {
        return None;
    }
    let series = stations
        .iter()
        .map(|c| {
            Series::new(
                format!("{}.gross_weight_n", c.topic),
                format!("{} gross weight", c.topic.trim_start_matches("/wim/")),
            )
        })
        .collect();
    Some(Plot {
        title: "WIM: measured gross weight per vehicle, N".into(),
        series,
        x: XAxis::Time,
        y_range: None,
    })
}

/// The deflected shape along the bridge (x = node index), drawn down, in a fixed range
/// from the run's peak so that it does not rescale as it moves.
fn shape_plot(contents: &RunContents, notes: &mut Vec<String>) -> Option<Plot> {
    if !has_data(contents, Topics::BRIDGE, &BridgeState::full_name()) {
        return None;
    }
    let peak = contents.peak_deflection_m;
    let y_range = match peak > 0.0 && peak.is_finite() {
        // Room below the peak, and above for the rebound of a vibrating deck.
        true => Some((-1.2 * peak, 0.4 * peak)),
        false => {
            notes.push("/truth/bridge: every shape is zero; the shape plot scales itself".into());
            None
        }
    };
    let span = contents
        .span_m
        .map_or(String::new(), |s| format!(" = 0..{s} m"));
    let last = contents.shape_nodes.saturating_sub(1);
    Some(Plot {
        title: format!(
            "Deflected shape, m (drawn down; x = node 0..{last}{span}; peak {:.2} mm)",
            peak * 1e3
        ),
        series: vec![Series::new(
            format!("{}.deflection_m[:].@negative", Topics::BRIDGE),
            "deflection".into(),
        )],
        x: XAxis::Index,
        y_range,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn spread_keeps_the_ends() {
        assert_eq!(spread(3, 4), [0, 1, 2]);
        assert_eq!(spread(20, 4), [0, 6, 13, 19]);
        assert_eq!(spread(5, 1), [0]);
        assert_eq!(spread(5, 2), [0, 4]);
    }
}
