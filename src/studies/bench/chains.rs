//! What realistic measurement chains cost: the same run with 16 accelerometers as `ideal`
//! sensors and as `mems_lownoise` sensors (bias, gain error, white + 1/f noise, 20-bit
//! ADC) on two DAQ nodes with drifting, jittered, resynchronised clocks and bursty packet
//! loss on every channel. Both end to end into an in-memory MCAP, the writer on a second
//! thread as `simulate` does (shared with the criterion bench `benches/sensor_chains.rs`).

use std::hint::black_box;

use serde::Serialize;

use super::end_to_end::write_mcap;
use super::timing::median_wall_s;
use crate::app::run::WriterThread;
use crate::error::Result;
use crate::scenario::{Resolved, Scenario};
use crate::sim::{prepare, Prepared};

/// Accelerometers in the comparison (the issue's 16-channel case).
pub const CHANNELS: usize = 16;
/// Simulated time of each run (s).
pub const DURATION_S: f64 = 60.0;

/// The 16-channel run: ambient excitation and one truck on the paper's bridge, 100 Hz
/// accelerometers, `realistic` choosing the chains, clocks and faults.
pub fn scenario(realistic: bool) -> Result<(Resolved, Prepared)> {
    let mut text = format!(
        "seed = 5\nduration_s = {DURATION_S}\n{}",
        r#"
[bridge]
span_m = 30.0
flexural_rigidity_n_m2 = 5.629e10
mass_per_length_kg_m = 12000.0
damping_ratio = 0.02
model = { kind = "finite_element", elements = 50 }
[ambient]
target_rms_m_s2 = 0.005
[[vehicles]]
id = 1
model = { kind = "half_car", preset = "two_axle_truck" }
speed_m_s = 20.0
entry_time_s = 20.0
[[daq_nodes]]
id = "west"
clock = { drift_ppm = 20.0, jitter_rms_s = 1e-5, resync_interval_s = 10.0, resync_residual_rms_s = 5e-5 }
[[daq_nodes]]
id = "east"
clock = { drift_ppm = -30.0, jitter_rms_s = 1e-5, resync_interval_s = 10.0, resync_residual_rms_s = 5e-5 }
"#
    );
    for i in 0..CHANNELS {
        let x = 30.0 * (i + 1) as f64 / (CHANNELS + 1) as f64;
        let extra = match realistic {
            false => "preset = \"ideal\"".to_string(),
            true => format!(
                "preset = \"mems_lownoise\"\ndaq_node = \"{}\"\nfaults = {{ loss = {{ kind = \
                 \"bursty\", probability = 0.01, mean_burst_samples = 10 }}, spikes = {{ \
                 rate_per_hour = 60.0, amplitude = 0.1 }} }}",
                if x < 15.0 { "west" } else { "east" }
            ),
        };
        text.push_str(&format!(
            "[[sensors]]\nid = \"A{i}\"\nkind = \"accelerometer\"\nposition_m = {x}\n\
             rate_hz = 100.0\n{extra}\n"
        ));
    }
    let resolved = Scenario::from_toml(&text, "bench chains")?.resolve()?;
    let prepared = prepare(&resolved)?;
    Ok((resolved, prepared))
}

/// The two runs' median wall times and their ratio.
#[derive(Debug, Clone, Serialize)]
pub struct ChainCost {
    pub channels: usize,
    pub simulated_s: f64,
    pub ideal_s: f64,
    pub realistic_s: f64,
    /// realistic_s / ideal_s (target: at most 1.5).
    pub ratio: f64,
    pub repetitions: usize,
}

/// Measures both runs, `repetitions` times each after a warm-up run of each.
pub fn measure(repetitions: usize) -> Result<ChainCost> {
    let ideal = scenario(false)?;
    let realistic = scenario(true)?;
    // Errors cannot appear in the timed calls: each run is done once here first.
    write_mcap(&ideal.0, &ideal.1, None, WriterThread::Background)?;
    write_mcap(&realistic.0, &realistic.1, None, WriterThread::Background)?;
    let run = |case: &(Resolved, Prepared)| {
        black_box(write_mcap(&case.0, &case.1, None, WriterThread::Background).ok());
    };
    let ideal_s = median_wall_s(repetitions, || run(&ideal));
    let realistic_s = median_wall_s(repetitions, || run(&realistic));
    Ok(ChainCost {
        channels: CHANNELS,
        simulated_s: DURATION_S,
        ideal_s,
        realistic_s,
        ratio: realistic_s / ideal_s,
        repetitions: repetitions.max(1),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_realistic_run_has_its_chains_clocks_and_faults_and_the_ideal_one_none() {
        let (ideal, _) = scenario(false).unwrap();
        let (real, _) = scenario(true).unwrap();
        assert_eq!(ideal.sensors.len(), CHANNELS);
        assert!(ideal
            .sensors
            .iter()
            .all(|s| s.node.is_none() && s.spec.faults.is_none()));
        assert!(real.sensors.iter().all(|s| s.node.is_some()
            && s.model_name() == "mems_lownoise"
            && s.spec.faults.is_some()));
    }
}
