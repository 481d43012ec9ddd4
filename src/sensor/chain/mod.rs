//! Measurement-chain stages and sensor presets (SENSORS.md section 2).
