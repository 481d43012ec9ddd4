//! Physics: the bridge, the vehicles, the road, the loads that act on them and the
//! integrators that advance them. Nothing here knows a file format, a sensor or the
//! command line; the time loop (`sim`) puts these pieces together.
//!
//! Inside the layer, imports run one way too: `linalg` (matrix storage, band kernels,
//! eigenpairs) uses nothing of the others; `bridge` uses only `linalg`; `road` uses
//! nothing; `vehicle` uses neither the bridge nor the road; `solver` is where bridge,
//! vehicle and road meet; `environment` (temperature, damage) and `excitation` (ambient
//! loads) act on the bridge model; `traffic` draws vehicles.

pub mod bridge;
pub mod environment;
pub mod excitation;
pub mod linalg;
pub mod road;
pub mod solver;
pub mod traffic;
pub mod vehicle;
