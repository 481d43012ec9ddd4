//! Road profile configuration: the `[road] profile = { kind = ... }` table of a scenario.
//!
//! Plain data with serde derive; every field documents its default. `validate` checks
//! everything once and names the offending field by its scenario path.

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

use super::track::TrackClass;
use crate::base::schema as bounds;
use crate::error::{require_positive, Error, Result};

/// Reference spatial frequency of ISO 8608, cycle/m.
pub const N0_CYCLES_M: f64 = 0.1;

/// Default lower band limit of the synthesized spectrum, cycle/m (100 m wavelength).
pub const DEFAULT_N1_CYCLES_M: f64 = 0.01;

/// Default upper band limit of the synthesized spectrum, cycle/m (0.25 m wavelength).
pub const DEFAULT_N2_CYCLES_M: f64 = 4.0;

/// Default spacing of the synthesized samples, m (Nyquist 10 cycle/m > `n2` = 4).
pub const DEFAULT_SAMPLE_SPACING_M: f64 = 0.05;

/// Largest explicit `G_d(n0)` accepted, m^3: twice the upper limit of class H.
pub const MAX_GD_N0_M3: f64 = 1.048576;

/// Tyre contact-patch length of the moving-average filter of Harris, OBrien & Gonzalez
/// (2007), m. Not applied unless `tyre_patch_filter_m` is set.
pub const TYRE_PATCH_LENGTH_M: f64 = 0.24;

/// ISO 8608 roughness class.
///
/// Implementations disagree on the value of `G_d(n0)` that stands for a class: some take
/// the arithmetic midpoint of the class limits (VBI-2D), others the upper limit. This crate
/// uses the geometric mean of the class limits (the limits are at half and double the
/// value), and says so in the description of the road stored with each run.
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize, JsonSchema,
)]
pub enum IsoClass {
    A,
    B,
    C,
    D,
    E,
    F,
    G,
    H,
}

impl IsoClass {
    /// All classes, best to worst.
    pub const ALL: [IsoClass; 8] = [
        IsoClass::A,
        IsoClass::B,
        IsoClass::C,
        IsoClass::D,
        IsoClass::E,
        IsoClass::F,
        IsoClass::G,
        IsoClass::H,
    ];

    /// The class's `G_d(n0)` in units of 1e-6 m^3: 16 * 4^(index), A = 16 ... H = 262 144.
    pub fn gd_n0_micro_m3(self) -> u32 {
        16 << (2 * self as u32)
    }

    /// Geometric mean of the class limits of `G_d(n0)`, m^3 (A 16e-6, B 64e-6, C 256e-6,
    /// D 1024e-6, E 4096e-6, F 16384e-6, G 65536e-6, H 262144e-6), at n0 = 0.1 cycle/m.
    pub fn gd_n0_m3(self) -> f64 {
        f64::from(self.gd_n0_micro_m3()) * 1e-6
    }

    /// The class letter.
    pub fn letter(self) -> char {
        match self {
            IsoClass::A => 'A',
            IsoClass::B => 'B',
            IsoClass::C => 'C',
            IsoClass::D => 'D',
            IsoClass::E => 'E',
            IsoClass::F => 'F',
            IsoClass::G => 'G',
            IsoClass::H => 'H',
        }
    }
}

/// Declares [`RoadFeature`] and [`RoadProfileSpec`] with the deterministic shapes written
/// once: each shape is a variant of both (alone on a flat road as a profile, or added on
/// top of a random profile as a feature), with the same fields, docs and TOML keys, and
/// `RoadProfileSpec::as_feature` maps one to the other. Every shape field is an `f64`
/// without default.
macro_rules! road_shapes {
    (
        shapes {
            $( $(#[$shape_doc:meta])* $shape:ident {
                $( $(#[$field_doc:meta])* $field:ident, )+
            } )+
        }
        $(#[$profile_meta:meta])*
        pub enum RoadProfileSpec {
            before { $($before:tt)* }
            after { $($after:tt)* }
        }
    ) => {
        /// A deterministic shape, on its own or added on top of a random profile.
        ///
        /// Shapes are evaluated in closed form (not sampled), so their geometry is exact.
        #[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
        #[serde(remote = "Self", rename_all = "snake_case", deny_unknown_fields)]
        #[schemars(tag = "kind")]
        pub enum RoadFeature {
            $( $(#[$shape_doc])* $shape { $( $(#[$field_doc])* $field: f64, )+ }, )+
        }

        $(#[$profile_meta])*
        pub enum RoadProfileSpec {
            $($before)*
            $( $(#[$shape_doc])* $shape { $( $(#[$field_doc])* $field: f64, )+ }, )+
            $($after)*
        }

        impl RoadProfileSpec {
            /// The deterministic shape of a `step`, `ramp` or `bump` spec.
            pub fn as_feature(&self) -> Option<RoadFeature> {
                match *self {
                    $( RoadProfileSpec::$shape { $($field),+ } => {
                        Some(RoadFeature::$shape { $($field),+ })
                    } )+
                    _ => None,
                }
            }
        }
    };
}

road_shapes! {
    shapes {
        /// Elevation jumps by `height_m` at `position_m` (0 before, `height_m` from it on).
        /// Its slope is a Dirac impulse, reported as 0: a vertical step is a limit case; use
        /// a short `ramp` or `bump` when the contact rate matters. No defaults.
        Step {
            /// Road coordinate of the step, m.
            position_m,
            /// Height of the step, m (negative: a drop).
            height_m,
        }
        /// Linear rise from 0 at `start_m` to `height_m` at `start_m + length_m`, constant
        /// after. No defaults.
        Ramp {
            /// Road coordinate where the ramp starts, m.
            start_m,
            /// Horizontal length of the ramp, m (> 0).
            #[schemars(transform = bounds::positive)]
            length_m,
            /// Height reached at the end of the ramp, m.
            height_m,
        }
        /// Raised-cosine bump `h/2 (1 + cos(2 pi (x - position_m) / length_m))` over
        /// `|x - position_m| < length_m / 2`, zero elsewhere: C1, e.g. an approach-slab fault.
        /// No defaults.
        Bump {
            /// Road coordinate of the bump's centre (its crest), m.
            position_m,
            /// Length of the bump, m (> 0).
            #[schemars(transform = bounds::positive)]
            length_m,
            /// Height of the crest, m (negative: a dip).
            height_m,
        }
        /// A dipped rail joint: a symmetric V, `-depth (1 - 2|x - position| / length)` over
        /// `|x - position_m| < length_m / 2` (the rail ends bent down at a worn joint, the
        /// classic wheel-impact defect). No defaults.
        DippedJoint {
            /// Track coordinate of the joint (the bottom of the V), m.
            position_m,
            /// Length of the dipped zone, m (> 0).
            #[schemars(transform = bounds::positive)]
            length_m,
            /// Depth of the dip at the joint, m (> 0).
            #[schemars(transform = bounds::positive)]
            depth_m,
        }
        /// A local void under the sleepers: the rail sags over it as a raised-cosine dip
        /// `-depth/2 (1 + cos(2 pi (x - position) / length))`, C1. No defaults.
        Void {
            /// Track coordinate of the middle of the void, m.
            position_m,
            /// Length of the unsupported zone, m (> 0).
            #[schemars(transform = bounds::positive)]
            length_m,
            /// Sag at its middle, m (> 0).
            #[schemars(transform = bounds::positive)]
            depth_m,
        }
    }
    /// The road profile of a scenario (`[road] profile = { kind = "iso8608", class = "A" }`).
    ///
    /// Default: `smooth`.
    #[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema, Default)]
    #[serde(remote = "Self", rename_all = "snake_case", deny_unknown_fields)]
    #[schemars(tag = "kind")]
    pub enum RoadProfileSpec {
        before {
            /// A perfectly flat road (elevation 0 everywhere).
            #[default]
            Smooth,
            /// A random ISO 8608 profile, `G_d(n) = G_d(n0) (n / n0)^-2` on `[n1, n2]`, with
            /// `n0` = 0.1 cycle/m, synthesized by inverse FFT (docs/physics.md section 7).
            Iso8608 {
                /// Roughness class "A" .. "H" (geometric mean of the class). No default: give
                /// `class` or `gd_n0_m3`.
                #[serde(default, skip_serializing_if = "Option::is_none")]
                class: Option<IsoClass>,
                /// Explicit `G_d(n0)`, m^3, in (0, 1.048576] (twice the upper limit of
                /// class H); overrides `class`. Default: none.
                #[serde(default, skip_serializing_if = "Option::is_none")]
                #[schemars(transform = bounds::positive, range(max = MAX_GD_N0_M3))]
                gd_n0_m3: Option<f64>,
                /// Lower band limit, cycle/m, below `n2_cycles_m`. Default 0.01 (100 m
                /// wavelength).
                #[serde(default = "default_n1")]
                #[schemars(transform = bounds::positive)]
                n1_cycles_m: f64,
                /// Upper band limit, cycle/m. Default 4.0 (0.25 m wavelength); must not exceed the
                /// Nyquist frequency `0.5 / sample_spacing_m`.
                #[serde(default = "default_n2")]
                #[schemars(transform = bounds::positive)]
                n2_cycles_m: f64,
                /// Length of the tyre-patch moving-average filter, m (Harris, OBrien & Gonzalez
                /// 2007 use 0.24). Default: none (unfiltered).
                #[serde(default, skip_serializing_if = "Option::is_none")]
                #[schemars(transform = bounds::positive)]
                tyre_patch_filter_m: Option<f64>,
                /// Spacing of the synthesized samples, m (> 0). Default 0.05.
                #[serde(default = "default_spacing")]
                #[schemars(transform = bounds::positive)]
                sample_spacing_m: f64,
                /// Deterministic shapes added on top of the random profile (not filtered).
                /// Default: none.
                #[serde(default, skip_serializing_if = "Vec::is_empty")]
                features: Vec<RoadFeature>,
            },
        }
        after {
            /// A railway track's vertical irregularity from a published spectrum (FRA track
            /// classes, German high-speed spectra), synthesized as `iso8608` is.
            Track {
                /// `fra_1` (worst) .. `fra_6` (best), `german_low` or `german_high`
                /// (interference). No default.
                class: TrackClass,
                /// Lower band limit, cycle/m, below `n2_cycles_m`. Default 1/150 (150 m
                /// wavelength).
                #[serde(default = "default_track_n1")]
                #[schemars(transform = bounds::positive)]
                n1_cycles_m: f64,
                /// Upper band limit, cycle/m. Default 1.0 (1 m wavelength).
                #[serde(default = "default_track_n2")]
                #[schemars(transform = bounds::positive)]
                n2_cycles_m: f64,
                /// Spacing of the synthesized samples, m (> 0). Default 0.05.
                #[serde(default = "default_spacing")]
                #[schemars(transform = bounds::positive)]
                sample_spacing_m: f64,
                /// Deterministic defects added on top (dipped joints, voids, ...).
                /// Default: none.
                #[serde(default, skip_serializing_if = "Vec::is_empty")]
                features: Vec<RoadFeature>,
            },
            /// A measured profile from a CSV file with header and columns `x_m,elevation_m`
            /// (x strictly increasing, in the road coordinate). It must cover the simulated range.
            Csv {
                /// Path of the file; relative paths are resolved by the caller (the scenario
                /// loader resolves them against the scenario file's folder). No default.
                #[schemars(regex(pattern = r"\S"))]
                path: String,
            },
        }
    }
}
crate::base::tagged::kind_tagged!(RoadFeature);
crate::base::tagged::kind_tagged!(RoadProfileSpec);

fn default_n1() -> f64 {
    DEFAULT_N1_CYCLES_M
}

fn default_n2() -> f64 {
    DEFAULT_N2_CYCLES_M
}

/// Default band of a track spectrum, cycle/m: 1-150 m wavelengths.
pub const DEFAULT_TRACK_N1_CYCLES_M: f64 = 1.0 / 150.0;
pub const DEFAULT_TRACK_N2_CYCLES_M: f64 = 1.0;

fn default_track_n1() -> f64 {
    DEFAULT_TRACK_N1_CYCLES_M
}

fn default_track_n2() -> f64 {
    DEFAULT_TRACK_N2_CYCLES_M
}

fn default_spacing() -> f64 {
    DEFAULT_SAMPLE_SPACING_M
}

impl RoadProfileSpec {
    /// An ISO 8608 profile of `class` with all defaults.
    pub fn iso8608(class: IsoClass) -> Self {
        RoadProfileSpec::Iso8608 {
            class: Some(class),
            gd_n0_m3: None,
            n1_cycles_m: DEFAULT_N1_CYCLES_M,
            n2_cycles_m: DEFAULT_N2_CYCLES_M,
            tyre_patch_filter_m: None,
            sample_spacing_m: DEFAULT_SAMPLE_SPACING_M,
            features: Vec::new(),
        }
    }

    /// Checks every value; errors name the field as `{field_path}.{field}`, e.g.
    /// `road.profile.n1_cycles_m`.
    pub fn validate(&self, field_path: &str) -> Result<()> {
        match self {
            RoadProfileSpec::Smooth => Ok(()),
            RoadProfileSpec::Iso8608 {
                class,
                gd_n0_m3,
                n1_cycles_m,
                n2_cycles_m,
                tyre_patch_filter_m,
                sample_spacing_m,
                features,
            } => {
                match (class, gd_n0_m3) {
                    (_, Some(gd)) => {
                        require_positive(&format!("{field_path}.gd_n0_m3"), *gd)?;
                        if *gd > MAX_GD_N0_M3 {
                            return Err(Error::invalid(
                                format!("{field_path}.gd_n0_m3"),
                                crate::error::num(*gd),
                                format!(
                                    "is beyond any road: at most {MAX_GD_N0_M3} m^3 (ISO 8608 \
                                     class H is {} m^3)",
                                    IsoClass::H.gd_n0_m3()
                                ),
                            ));
                        }
                    }
                    (Some(_), None) => {}
                    (None, None) => {
                        return Err(Error::invalid(
                            format!("{field_path}.class"),
                            "(missing)",
                            "is required unless gd_n0_m3 is given",
                        ))
                    }
                }
                validate_band(field_path, *n1_cycles_m, *n2_cycles_m, *sample_spacing_m)?;
                if let Some(a) = tyre_patch_filter_m {
                    require_positive(&format!("{field_path}.tyre_patch_filter_m"), *a)?;
                }
                for (i, f) in features.iter().enumerate() {
                    f.validate(&format!("{field_path}.features.{i}"))?;
                }
                Ok(())
            }
            RoadProfileSpec::Track {
                n1_cycles_m,
                n2_cycles_m,
                sample_spacing_m,
                features,
                ..
            } => {
                validate_band(field_path, *n1_cycles_m, *n2_cycles_m, *sample_spacing_m)?;
                for (i, f) in features.iter().enumerate() {
                    f.validate(&format!("{field_path}.features.{i}"))?;
                }
                Ok(())
            }
            RoadProfileSpec::Step { .. }
            | RoadProfileSpec::Ramp { .. }
            | RoadProfileSpec::Bump { .. }
            | RoadProfileSpec::DippedJoint { .. }
            | RoadProfileSpec::Void { .. } => match self.as_feature() {
                Some(f) => f.validate(field_path),
                None => Ok(()),
            },
            RoadProfileSpec::Csv { path } => {
                if path.trim().is_empty() {
                    Err(Error::invalid(
                        format!("{field_path}.path"),
                        "\"\"",
                        "must name a CSV file",
                    ))
                } else {
                    Ok(())
                }
            }
        }
    }
}

/// A synthesis band: `0 < n1 < n2 <= 0.5 / dx`.
fn validate_band(
    field_path: &str,
    n1_cycles_m: f64,
    n2_cycles_m: f64,
    spacing_m: f64,
) -> Result<()> {
    let n1 = require_positive(&format!("{field_path}.n1_cycles_m"), n1_cycles_m)?;
    let n2 = require_positive(&format!("{field_path}.n2_cycles_m"), n2_cycles_m)?;
    if n1 >= n2 {
        return Err(Error::invalid(
            format!("{field_path}.n1_cycles_m"),
            n1,
            format!("must be less than n2_cycles_m = {n2}"),
        ));
    }
    let dx = require_positive(&format!("{field_path}.sample_spacing_m"), spacing_m)?;
    let nyquist = 0.5 / dx;
    if n2 > nyquist {
        return Err(Error::invalid(
            format!("{field_path}.n2_cycles_m"),
            n2,
            format!(
                "exceeds the Nyquist frequency 0.5 / sample_spacing_m = {nyquist} \
                 cycle/m; reduce sample_spacing_m = {dx}"
            ),
        ));
    }
    Ok(())
}

/// RMS elevation of an ISO 8608 profile band-limited to `[n1, n2]`, m:
/// `sqrt(G_d(n0) n0^2 (1/n1 - 1/n2))`, the integral of `G_d(n0) (n/n0)^-2` over the band.
pub fn iso8608_band_rms_m(gd_n0_m3: f64, n1_cycles_m: f64, n2_cycles_m: f64) -> f64 {
    (gd_n0_m3 * N0_CYCLES_M * N0_CYCLES_M * (1.0 / n1_cycles_m - 1.0 / n2_cycles_m)).sqrt()
}

/// The one-sided displacement PSD of ISO 8608, `G_d(n0) (n / n0)^-2`, m^3.
pub fn iso8608_psd_m3(gd_n0_m3: f64, n_cycles_m: f64) -> f64 {
    let r = N0_CYCLES_M / n_cycles_m;
    gd_n0_m3 * r * r
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn class_values_are_geometric_means_of_the_class_limits() {
        // ISO 8608 limits of class A are [8e-6, 32e-6) and each class is 4x the previous;
        // the geometric mean of [lo, 4 lo] is 2 lo. Exact in f64 (small integers * 1e-6).
        let mut lower_limit_micro = 8.0_f64;
        for class in IsoClass::ALL {
            let geometric_mean = (lower_limit_micro * 4.0 * lower_limit_micro).sqrt();
            assert_eq!(
                f64::from(class.gd_n0_micro_m3()),
                geometric_mean,
                "{class:?}"
            );
            lower_limit_micro *= 4.0;
        }
        assert_eq!(IsoClass::A.gd_n0_m3(), 16e-6);
        assert_eq!(IsoClass::D.gd_n0_m3(), 1024e-6);
        assert_eq!(IsoClass::H.gd_n0_m3(), 262144e-6);
    }

    #[test]
    fn band_rms_matches_physics_reference() {
        // docs/physics.md section 7 rounds to 0.01 mm, hence the 0.005 mm tolerance.
        let expected_mm = [3.99, 7.99, 15.98, 31.96];
        for (class, mm) in IsoClass::ALL.iter().zip(expected_mm) {
            let rms_mm = 1e3 * iso8608_band_rms_m(class.gd_n0_m3(), 0.01, 4.0);
            assert!((rms_mm - mm).abs() < 0.005, "{class:?}: {rms_mm} mm");
        }
    }

    #[test]
    fn validate_names_the_field() {
        let mut spec = RoadProfileSpec::iso8608(IsoClass::A);
        if let RoadProfileSpec::Iso8608 { n1_cycles_m, .. } = &mut spec {
            *n1_cycles_m = 5.0;
        }
        let err = spec.validate("road.profile").err().map(|e| e.to_string());
        let msg = err.unwrap_or_default();
        assert!(msg.starts_with("road.profile.n1_cycles_m = 5"), "{msg}");
    }

    #[test]
    fn features_evaluate_in_closed_form() {
        let ramp = RoadFeature::Ramp {
            start_m: 1.0,
            length_m: 2.0,
            height_m: 0.04,
        };
        assert_eq!(ramp.evaluate(0.5), (0.0, 0.0));
        assert_eq!(ramp.evaluate(2.0), (0.02, 0.02));
        assert_eq!(ramp.evaluate(9.0), (0.04, 0.0));
        let bump = RoadFeature::Bump {
            position_m: 5.0,
            length_m: 2.0,
            height_m: 0.03,
        };
        assert_eq!(bump.evaluate(5.0), (0.03, 0.0));
        assert_eq!(bump.evaluate(4.0), (0.0, 0.0));
        // Quarter point: h/2 (1 + cos(-pi/2)) = h/2, slope = -h/2 w sin(-pi/2) = h pi / L.
        let (z, s) = bump.evaluate(4.5);
        assert!((z - 0.015).abs() < 1e-15);
        assert!((s - 0.03 * std::f64::consts::PI / 2.0).abs() < 1e-15);
    }
}
