//! The matrices the models are kept in and the algebra on them that is not a time step:
//! symmetric storage (dense, band, diagonal), the band kernels the solver runs every step,
//! and the lowest eigenpairs of a banded pencil without a dense eigenproblem. Used by the
//! bridge models and the solver; it uses nothing else of physics.

mod band;
mod band_eigen;
mod sym;

pub use band::{half_bandwidth, BandCholesky, BandMatrix, SymBand};
pub use band_eigen::{count_below, lowest_eigenpairs, BandLdl, EigenError};
pub use sym::SymMatrix;

#[cfg(test)]
mod band_eigen_tests;
