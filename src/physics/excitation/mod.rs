//! Ambient excitation: band-limited random loads on the bridge.
//!
//! - `ambient`: the `[ambient]` spec and the calibrated force field written into the
//!   solver's external load each step.
//! - `bandpass`: the Butterworth band-pass (bilinear transform, second-order sections).
//! - `calibrate`: the stationary response variance from the model's modes, which sets the
//!   force level for a target RMS acceleration without a trial simulation.

mod ambient;
mod bandpass;
mod calibrate;

pub use ambient::{AmbientField, AmbientSpec, AMBIENT_STREAM};
pub use bandpass::{BandPass, Biquad, FilterBank, EDGE_ORDER, SECTIONS};
pub use calibrate::ResponseModel;
