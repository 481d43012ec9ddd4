//! Points of a vehicle where an instrument can ride: an axle's unsprung mass, or a point of
//! the body. Each is a linear combination of the vehicle's DOFs (upward positive), so that
//! a sensor there reads `sum c_i y_i` and its derivatives with no further model.

use super::VehicleDynamics;

/// Where on a vehicle a point sits.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum MountPoint {
    /// The unsprung mass of axle `index` (0 = front).
    Axle { index: usize },
    /// The body, `offset_m` behind the front axle.
    Body { offset_m: f64 },
}

/// Why a vehicle has no such point.
#[derive(Debug, Clone, PartialEq)]
pub enum MountError {
    /// The vehicle has fewer axles.
    NoSuchAxle { axles: usize },
    /// The axle is a moving force (no DOF moves there).
    RigidAxle,
    /// The body is not one rigid body in bounce and pitch (moving forces, tractor and
    /// trailer).
    NoSingleBody,
    /// The point is off the body: further than [`BODY_OVERHANG_M`] beyond an outer axle.
    OffBody { from_m: f64, to_m: f64 },
}

/// How far beyond its outer axles a vehicle's body is taken to reach, m. A rigid body in
/// bounce and pitch is a model of the vehicle, not of the road 20 m behind it: a point
/// further out is a typing error. Road vehicles' overhangs stay below this (a city bus's
/// front overhang is about 2.7 m, a rigid truck's rear one about 3 m), so no real mount
/// is refused.
pub const BODY_OVERHANG_M: f64 = 3.5;

impl VehicleDynamics {
    /// The DOF combination `[(dof, coefficient)]` whose value is the vertical motion of
    /// `point` (upward positive, from static equilibrium).
    pub fn mount_point(&self, point: MountPoint) -> Result<Vec<(usize, f64)>, MountError> {
        match point {
            MountPoint::Axle { index } => {
                let axle = self.axles.get(index).ok_or(MountError::NoSuchAxle {
                    axles: self.axles.len(),
                })?;
                axle.dof
                    .map(|d| vec![(d, 1.0)])
                    .ok_or(MountError::RigidAxle)
            }
            MountPoint::Body { offset_m } => self.body_point(offset_m),
        }
    }

    /// A body point `offset_m` behind the front axle: a rigid body in bounce `y_B` and
    /// pitch `theta` moves `y_B + (cg - offset) theta` there (models.rs, the lever `d`);
    /// a quarter car's or sprung mass's body is one DOF.
    fn body_point(&self, offset_m: f64) -> Result<Vec<(usize, f64)>, MountError> {
        let (from_m, to_m) = (-BODY_OVERHANG_M, self.wheelbase_m() + BODY_OVERHANG_M);
        if !(from_m..=to_m).contains(&offset_m) {
            return Err(MountError::OffBody { from_m, to_m });
        }
        let names: Vec<&str> = self.dof_names.iter().map(String::as_str).collect();
        match names.as_slice() {
            ["body_bounce", "body_pitch", ..] => {
                let cg = self
                    .parameters
                    .iter()
                    .find(|(name, _)| name == "cg_behind_front_m")
                    .map(|&(_, v)| v)
                    .ok_or(MountError::NoSingleBody)?;
                Ok(vec![(0, 1.0), (1, cg - offset_m)])
            }
            ["body", "axle"] | ["mass"] => Ok(vec![(0, 1.0)]),
            _ => Err(MountError::NoSingleBody),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::physics::vehicle::{rigid_body_on_axles, sprung_mass, AxleParams};

    fn axle() -> AxleParams {
        AxleParams {
            mass_kg: 500.0,
            suspension_stiffness_n_m: 1e6,
            suspension_damping_n_s_m: 1e4,
            tyre_stiffness_n_m: 2e6,
            tyre_damping_n_s_m: 0.0,
        }
    }

    #[test]
    fn a_body_point_follows_bounce_and_pitch_with_its_lever() {
        let v = rigid_body_on_axles("t", 1e4, 5e4, 2.0, &[0.0, 5.0], &[axle(), axle()]).unwrap();
        // Above the front axle the lever is cg - 0 = 2 m; above the rear, 2 - 5 = -3 m: the
        // same levers the suspension springs use, so a pitch-only motion stretches the
        // front spring by 2 theta.
        assert_eq!(
            v.mount_point(MountPoint::Body { offset_m: 0.0 }),
            Ok(vec![(0, 1.0), (1, 2.0)])
        );
        assert_eq!(
            v.mount_point(MountPoint::Body { offset_m: 5.0 }),
            Ok(vec![(0, 1.0), (1, -3.0)])
        );
        // The suspension of axle j acts on (body point above it) - (axle j): its row in
        // K is k_j * [-1, -lever, +1 at the axle], so the lever read off K must be ours.
        for (j, offset_m) in [(0usize, 0.0), (1, 5.0)] {
            let lever = v.mount_point(MountPoint::Body { offset_m }).unwrap()[1].1;
            assert_eq!(v.stiffness[(2 + j, 1)], -1e6 * lever, "axle {j}");
        }
        assert_eq!(
            v.mount_point(MountPoint::Axle { index: 1 }),
            Ok(vec![(3, 1.0)])
        );
        assert_eq!(
            v.mount_point(MountPoint::Axle { index: 2 }),
            Err(MountError::NoSuchAxle { axles: 2 })
        );
    }

    #[test]
    fn moving_forces_have_no_point_to_mount_on() {
        let v = VehicleDynamics::moving_forces(&[1e5, 1e5], &[0.0, 4.0]);
        assert_eq!(
            v.mount_point(MountPoint::Axle { index: 0 }),
            Err(MountError::RigidAxle)
        );
        assert_eq!(
            v.mount_point(MountPoint::Body { offset_m: 1.0 }),
            Err(MountError::NoSingleBody)
        );
        let m = sprung_mass(1220.0, 5e5, 0.0);
        assert_eq!(
            m.mount_point(MountPoint::Body { offset_m: 0.0 }),
            Ok(vec![(0, 1.0)])
        );
    }
}
