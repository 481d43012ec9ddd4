//! Measurement: what turns the true response into what an installation records. Sensor
//! channels (anti-alias filter, resampling, measurement chains), DAQ node clocks and
//! faults, weigh-in-motion stations. Uses physics for nothing but plain numbers.

pub mod daq;
pub mod sensor;
pub mod vehicle;
pub mod wim;
