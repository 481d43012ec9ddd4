//! Strip physics: the WIM sensor reads the dynamic tyre force, not the static load.
//!
//! A WIM strip (piezo-polymer, piezo-quartz, bending plate or load cell) is 50-70 mm long
//! in the direction of travel, shorter than a tyre footprint (~200 mm). It senses the force
//! the tyre applies while rolling over it for a few milliseconds (7 ms at 90 km/h), and the
//! system converts the signal into a load: a piezo strip integrates it in time and scales by
//! the speed (`F = v / w * integral of signal`, so a speed error enters the load too), a
//! bending plate or load cell reads the force directly. Either way what is weighed is the
//! instantaneous dynamic tyre force, which oscillates about the static load with body bounce
//! (1-4 Hz) and axle hop (10-20 Hz) excited by the road profile; its coefficient of
//! variation (dynamic load coefficient, 5-15 % on ordinary roads) is what limits a single
//! strip's accuracy and why multiple-sensor WIM averages several strips. Calibration
//! factors drift with temperature (piezo-polymer) and wear.
//!
//! The model takes the dynamic tyre force from the vehicle-bridge simulation at the time
//! each axle crosses the strip and multiplies it by `1 + N(0, noise_rel)` per axle, one
//! independent draw per axle, front to rear: `noise_rel` lumps the sensor noise, the
//! footprint averaging and the calibration scatter (including a piezo strip's share of the
//! speed error). The COST 323 class of such a station is not set: it emerges from the
//! vehicles' dynamics and the road.

use rand::RngExt;
use rand_chacha::ChaCha8Rng;
use rand_distr::StandardNormal;

/// Relative errors of the strip's readings of `axle_count` axles, appended to `out`: one
/// `noise_rel * z`, `z ~ N(0, 1)` per axle, front to rear.
pub(crate) fn strip_errors(
    axle_count: usize,
    noise_rel: f64,
    rng: &mut ChaCha8Rng,
    out: &mut Vec<f64>,
) {
    for _ in 0..axle_count {
        let z: f64 = rng.sample(StandardNormal);
        out.push(noise_rel * z);
    }
}
