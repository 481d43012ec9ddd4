//! Panels of the instrumented vehicles (drive-by monitoring): the accelerometers riding on
//! each, measured and true, and where its wheels touch the road (the contact-point
//! elevation of `/truth/vehicle_state`, the input a drive-by method reconstructs).

use super::contents::RunContents;
use super::panels::{Plot, Series, XAxis};
use super::plotted_streams;
use crate::output::proto::v1::VehicleState;
use prost::Name;

/// Instrumented vehicles given panels at most (the rest are listed in the notes).
const MAX_VEHICLES: usize = 2;

/// Two plots per instrumented vehicle (its accelerations; its contact points), for the
/// first [`MAX_VEHICLES`] of them.
pub(super) fn vehicle_plots(contents: &RunContents, notes: &mut Vec<String>) -> Vec<Plot> {
    let vehicles: Vec<&str> = contents
        .channels
        .values()
        .filter(|c| c.schema == VehicleState::full_name() && c.messages > 0)
        .filter_map(|c| c.topic.strip_prefix("/truth/vehicle_state/"))
        .collect();
    if vehicles.len() > MAX_VEHICLES {
        notes.push(format!(
            "instrumented vehicles: {MAX_VEHICLES} of {} plotted ({})",
            vehicles.len(),
            vehicles[..MAX_VEHICLES].join(", ")
        ));
    }
    let mut plots = Vec::new();
    for vid in vehicles.into_iter().take(MAX_VEHICLES) {
        if let Some(plot) = acceleration_plot(contents, vid) {
            plots.push(plot);
        }
        plots.push(contact_plot(contents, vid));
    }
    plots
}

/// The vehicle's accelerometers: their preview where the run writes one, else every
/// sample, with the truth.
fn acceleration_plot(contents: &RunContents, vid: &str) -> Option<Plot> {
    let prefix = format!("/vehicles/{vid}/accel/");
    let field = "acceleration_m_s2";
    let mut series = Vec::new();
    for channel in contents.channels.values() {
        let Some(id) = channel.topic.strip_prefix(&prefix) else {
            continue;
        };
        let Some((measured, truth)) = plotted_streams(contents, "accel", id, &channel.topic) else {
            continue;
        };
        series.push(Series::new(
            format!("{measured}.{field}"),
            format!("{id} measured"),
        ));
        if let Some(truth) = truth {
            series.push(Series::new(
                format!("{truth}.{field}"),
                format!("{id} truth"),
            ));
        }
    }
    (!series.is_empty()).then(|| Plot {
        title: format!("Vehicle {vid}: accelerations riding on it, m/s^2 (downward positive)"),
        series,
        x: XAxis::Time,
        y_range: None,
    })
}

/// The elevation of each wheel's contact point and the deck's deflection under it.
fn contact_plot(contents: &RunContents, vid: &str) -> Plot {
    let topic = format!("/truth/vehicle_state/{vid}");
    let axles = contents
        .channels
        .get(&topic)
        .and_then(|c| c.metadata.get("axles"))
        .and_then(|a| a.parse::<usize>().ok())
        .unwrap_or(2);
    let mut series = Vec::new();
    for j in 0..axles {
        series.push(Series::new(
            format!("{topic}.contacts[{j}].contact_elevation_m"),
            format!("axle {} contact elevation", j + 1),
        ));
        series.push(Series::new(
            format!("{topic}.contacts[{j}].bridge_deflection_m.@negative"),
            format!("axle {} deck under it", j + 1),
        ));
    }
    Plot {
        title: format!("Vehicle {vid}: contact points (truth), m (upward positive)"),
        series,
        x: XAxis::Time,
        y_range: None,
    }
}
