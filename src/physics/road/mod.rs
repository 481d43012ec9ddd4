//! Road profiles: ISO 8608 random roughness, railway track irregularity spectra (FRA
//! classes, German high-speed), deterministic shapes (step, ramp, bump, dipped joint, void),
//! measured profiles from CSV, the optional tyre-patch filter, and the [`RoadSurface`] the
//! tyres roll on (a built profile or a closed-form surface).
//!
//! [`RoadProfileSpec`] is the scenario's configuration; [`RoadProfile::build`] turns it into
//! a profile over the road range the simulation visits (approach, bridge and exit in one
//! continuous profile), evaluated in O(1) by [`RoadProfile::elevation_m`] and
//! [`RoadProfile::slope`]. The synthesis and its verification follow docs/physics.md section 7.

mod csv;
mod curve;
mod features;
mod iso8608;
mod profile;
mod spec;
mod surface;
mod track;

pub use profile::RoadProfile;
pub use spec::{
    iso8608_band_rms_m, iso8608_psd_m3, IsoClass, RoadFeature, RoadProfileSpec,
    DEFAULT_N1_CYCLES_M, DEFAULT_N2_CYCLES_M, DEFAULT_SAMPLE_SPACING_M, DEFAULT_TRACK_N1_CYCLES_M,
    DEFAULT_TRACK_N2_CYCLES_M, N0_CYCLES_M, TYRE_PATCH_LENGTH_M,
};
pub use surface::{ConstantRoad, LevelRoad, RoadSurface, SineRoad};
pub use track::TrackClass;
