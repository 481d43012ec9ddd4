//! Bridge models: the beam, its discretizations (lumped mass by flexibility, Hermite
//! finite elements, modal), modes, Rayleigh damping and point operators.

mod beam;
mod gauge;
mod girder;
mod hermite;
mod lumped;
mod mesh;
mod model;
mod modes;
mod reactions;
mod settlement;
mod sparse;

pub use beam::{BeamProperties, Section, StiffnessRegion, Varying};
pub use gauge::{fixed_end_moment_m, GaugeFactors, GaugeState, MomentGauge};
pub use girder::{Girder, Piece, PieceKind, Support, MAX_SPANS};
pub use hermite::{element_consistent_mass, element_stiffness};
pub use lumped::{
    condensation_mesh, condense, flexibility_matrix, force_method_applies, mass_dofs, mass_layout,
    mass_positions_m, stiffness_by_flexibility, unit_load_deflection_m_per_n, ForceMethod,
    MassLayout,
};
pub use mesh::{HermiteMesh, PointQuantity};
pub use model::{BridgeModel, LumpedStiffness, ModelSpec, MAX_ELEMENTS, REPORTED_MODES};
pub use modes::{generalized_modes, Modes, Rayleigh, Wanted, DENSE_EIGEN_MAX_DOF};
pub use reactions::{ReactionOperator, ReactionState};
pub use settlement::SettlementField;
pub use sparse::SparseVec;

#[cfg(test)]
mod girder_tests;
#[cfg(test)]
mod tests;
