//! Time integration: Newmark-beta, the linear algebra behind it, and the coupled
//! vehicle-bridge step.

mod band;
mod coupled;
mod direct;
mod linear;
mod newmark;

pub use coupled::{ContactLaw, CoupledSolver, CoupledVehicle};
pub use direct::DirectSolver;
pub use linear::{to_csc, Factor, Operator, SmallLu, Storage};
pub use newmark::{Newmark, NewmarkCoefficients, NewmarkParams, SolveMode, State};
