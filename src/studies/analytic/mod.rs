//! Independent analytical and semi-analytical reference solutions.
//!
//! These are the yardsticks against which the numerical models (lumped mass, Hermite finite
//! elements, modal reduction, Newmark integration) are verified, so nothing here uses the
//! `bridge` or `solver` modules: every formula is coded afresh from its textbook source,
//! cited at the function that implements it.
//!
//! Sign convention: in this whole module vertical displacements of the beam and of vehicle
//! masses, and forces on the beam, are positive DOWNWARD (a load sags the beam by a
//! positive deflection). Road irregularities are road-surface elevations, positive UPWARD,
//! as road profiles are usually given. Callers using an upward-positive convention negate
//! displacements.
//!
//! - [`beam`]: the simply supported Euler-Bernoulli beam (frequencies, modes, statics) and
//!   modal damping laws.
//! - [`continuous_beam`]: exact modes of a uniform beam over several spans and overhangs
//!   on any supports (the frequency determinant), and the modal series of a moving force.
//! - [`moving_force`]: Fryba's closed-form modal solution for constant forces crossing
//!   the beam (one force or an axle train).
//! - [`sprung_mass`]: a sprung mass crossing the beam, coupled through its suspension,
//!   integrated in modal coordinates with an adaptive Dormand-Prince method ([`dopri45`]),
//!   optionally over a deterministic road profile ([`road_irregularity`]).
//! - [`vehicle_crossing`]: the same for a linear vehicle on several tyres (half car,
//!   multi-axle truck), given by its matrices.
//! - [`crossing`]: what the modal crossings share, with the bound on their mode-truncation
//!   error.
//! - [`stepped_beam`]: exact frequencies of a simply supported beam with piecewise-constant
//!   EI (local damage), by transfer matrices.
//! - [`frf`]: steady-state harmonic response of linear MDOF systems to base excitation.
//! - [`oscillator`]: the exact damped single-degree-of-freedom free response and the
//!   Newmark average-acceleration period elongation.

pub mod beam;
pub mod continuous_beam;
pub mod crossing;
pub mod dopri45;
pub mod frf;
pub mod moving_force;
pub mod moving_mass;
pub mod oscillator;
pub mod resonance;
pub mod road_irregularity;
pub mod sprung_mass;
pub mod stepped_beam;
pub mod vehicle_crossing;

pub use beam::{ModalDamping, SimplySupportedBeam};
pub use continuous_beam::{Condition, ContinuousBeam, ExactMode};
pub use crossing::{midspan_truncation_bound_m, ContactTail, CrossingDefaults, CrossingOptions};
pub use dopri45::{Dopri45, Dopri45Options, Dopri45Stats};
pub use frf::{harmonic_response, HarmonicResponse};
pub use moving_force::{MovingForceSolution, MovingLoadTrain};
pub use oscillator::{
    newmark_average_acceleration_period_ratio, DampedOscillator, OscillatorState,
};
pub use road_irregularity::RoadIrregularity;
pub use sprung_mass::{
    SprungMassOptions, SprungMassProblem, SprungMassSample, SprungMassSolution, SprungMassVehicle,
};
pub use stepped_beam::{Segment, SteppedBeam};
pub use vehicle_crossing::{
    LinearVehicle, Tyre, VehicleCrossingOptions, VehicleCrossingProblem, VehicleCrossingSample,
    VehicleCrossingSolution,
};
