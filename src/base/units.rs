//! Physical constants shared by every layer.

/// Standard gravity used for all static loads and weights (m/s^2): the rounded 9.81 of
/// the paper and of the WIM and traffic literature it is compared with.
pub const GRAVITY_M_S2: f64 = 9.81;
