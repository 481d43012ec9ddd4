//! Time integration: Newmark-beta, the linear algebra behind it, the coupled
//! vehicle-bridge step, and stepping it with the divergence check.

mod coupled;
mod coupled_vehicle;
mod direct;
mod linear;
mod newmark;
mod stepping;
mod vehicle_modes;

pub use coupled::{ContactLaw, CoupledSolver, CoupledVehicle};
pub use direct::DirectSolver;
pub use linear::{to_csc, Factor, Operator, SmallLu, Storage};
pub use newmark::{Newmark, NewmarkCoefficients, NewmarkParams, SolveMode, State};
pub use stepping::{check_state, divergence_hint, Stepper, RUNAWAY_CHECK_STRIDE};
pub use vehicle_modes::vehicle_natural_frequencies_hz;
