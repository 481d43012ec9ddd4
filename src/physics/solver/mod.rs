//! Time integration: Newmark-beta, the linear algebra behind it, and the coupled
//! vehicle-bridge step.

mod band;
mod coupled;
mod direct;
mod linear;
mod newmark;
mod vehicle_modes;

pub use coupled::{ContactLaw, CoupledSolver, CoupledVehicle, LevelRoad, RoadSurface};
pub use direct::DirectSolver;
pub use linear::{to_csc, Factor, Operator, SmallLu, Storage};
pub use newmark::{Newmark, NewmarkCoefficients, NewmarkParams, SolveMode, State};
pub use vehicle_modes::vehicle_natural_frequencies_hz;
