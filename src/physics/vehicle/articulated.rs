//! Tractor + semi-trailer in the pitch plane: two rigid bodies (bounce, pitch) joined by a
//! hinge at the fifth wheel, one unsprung mass per axle (docs/sensors.md section 4).
//!
//! The hinge makes the kingpin point move vertically with the fifth-wheel point of the
//! tractor while both bodies pitch freely. The constraint is eliminated rather than
//! penalised: the trailer's bounce is not a DOF but follows from the tractor's bounce and
//! pitch and the trailer's pitch, `u = T q`, and the matrices are `T^T M_full T` etc.
//! (the standard reduction for a linear holonomic constraint). A stiff penalty spring would
//! add a spurious very high mode that forces a tiny time step; the reduction is exact and
//! has one DOF fewer.

use nalgebra::{DMatrix, DVector};

use super::dynamics::{VehicleDynamics, GRAVITY_M_S2};
use super::models::{axle_parameters, tyre_contacts, AxleParams, BodyParams};
use crate::error::{Error, Result};

/// Index of the first axle DOF in the reduced coordinates
/// (tractor bounce, tractor pitch, trailer pitch, axles...).
const FIRST_AXLE_DOF: usize = 3;

/// Full (unconstrained) coordinates: tractor bounce, tractor pitch, trailer bounce,
/// trailer pitch, axles.
const FIRST_AXLE_FULL: usize = 4;

/// A tractor + semi-trailer. Axles `0..tractor_axle_count` carry the tractor, the rest
/// the trailer; the trailer's front rests on the fifth wheel.
#[derive(Debug, Clone, PartialEq)]
pub struct ArticulatedParams {
    pub tractor: BodyParams,
    pub trailer: BodyParams,
    /// Fifth-wheel (kingpin) position behind the front axle (m).
    pub fifth_wheel_behind_front_m: f64,
    /// Number of tractor axles (>= 2); the remaining axles (>= 1) are the trailer's.
    pub tractor_axle_count: usize,
    /// Distances behind the front axle (m), ascending, the first 0.
    pub axle_offsets_m: Vec<f64>,
    /// One entry per axle, front first.
    pub axles: Vec<AxleParams>,
}

impl ArticulatedParams {
    /// The reduced model (DOFs: tractor bounce, tractor pitch, trailer pitch, axles), with
    /// static axle loads from gravity.
    pub fn build(&self, name: &str) -> Result<VehicleDynamics> {
        self.check_layout()?;
        let t = self.hinge_transformation();
        let full = self.full_matrices();
        let reduce = |a: &DMatrix<f64>| t.transpose() * a * &t;
        let mut vehicle = VehicleDynamics {
            name: name.to_string(),
            mass: reduce(&full.mass),
            damping: reduce(&full.damping),
            stiffness: reduce(&full.stiffness),
            axles: tyre_contacts(&self.axle_offsets_m, &self.axles, FIRST_AXLE_DOF),
            parameters: self.parameters(),
            dof_names: self.dof_names(),
        };
        // Generalized gravity forces: the virtual work of the full gravity vector.
        let gravity = t.transpose() * &full.gravity_n;
        vehicle.set_static_loads_from_gravity(&gravity)?;
        Ok(vehicle)
    }

    /// The body an axle belongs to: 0 tractor, 1 trailer.
    pub fn body_of_axle(&self, axle: usize) -> usize {
        usize::from(axle >= self.tractor_axle_count)
    }

    /// Signed lever of the kingpin on body `body` (positive ahead of its CG), the `d` of
    /// `rigid_body_on_axles`.
    fn kingpin_lever_m(&self, body: &BodyParams) -> f64 {
        body.cg_behind_front_m - self.fifth_wheel_behind_front_m
    }

    /// Structural checks the builder cannot do without (the scenario layer validates the
    /// values and names the fields).
    fn check_layout(&self) -> Result<()> {
        let n = self.axles.len();
        if self.axle_offsets_m.len() != n {
            return Err(Error::invalid(
                "axle_offsets_m",
                format!("{:?}", self.axle_offsets_m),
                format!("must have {n} entries, one per axle"),
            ));
        }
        if self.tractor_axle_count < 2 || self.tractor_axle_count >= n {
            return Err(Error::invalid(
                "tractor_axle_count",
                self.tractor_axle_count,
                format!("must leave the tractor >= 2 and the trailer >= 1 of the {n} axles"),
            ));
        }
        Ok(())
    }

    /// `u = T q`: the trailer CG moves with the kingpin on the tractor plus its own pitch,
    /// `y2 = y1 + d_k1 theta1 - d_k2 theta2` (d_k = kingpin lever on each body), so the
    /// kingpin has the same vertical displacement on both bodies for every q.
    fn hinge_transformation(&self) -> DMatrix<f64> {
        let n = self.axles.len();
        let mut t = DMatrix::zeros(FIRST_AXLE_FULL + n, FIRST_AXLE_DOF + n);
        t[(0, 0)] = 1.0;
        t[(1, 1)] = 1.0;
        t[(2, 0)] = 1.0;
        t[(2, 1)] = self.kingpin_lever_m(&self.tractor);
        t[(2, 2)] = -self.kingpin_lever_m(&self.trailer);
        t[(3, 2)] = 1.0;
        for j in 0..n {
            t[(FIRST_AXLE_FULL + j, FIRST_AXLE_DOF + j)] = 1.0;
        }
        t
    }

    /// Matrices of the two free bodies on their axles, as `rigid_body_on_axles` builds
    /// each, side by side.
    fn full_matrices(&self) -> FullMatrices {
        let n = self.axles.len();
        let dofs = FIRST_AXLE_FULL + n;
        let mut m = FullMatrices {
            mass: DMatrix::zeros(dofs, dofs),
            damping: DMatrix::zeros(dofs, dofs),
            stiffness: DMatrix::zeros(dofs, dofs),
            gravity_n: DVector::zeros(dofs),
        };
        for (b, body) in [self.tractor, self.trailer].iter().enumerate() {
            m.mass[(2 * b, 2 * b)] = body.mass_kg;
            m.mass[(2 * b + 1, 2 * b + 1)] = body.pitch_inertia_kg_m2;
            m.gravity_n[2 * b] = -body.mass_kg * GRAVITY_M_S2;
        }
        for (j, (axle, &offset)) in self.axles.iter().zip(&self.axle_offsets_m).enumerate() {
            let b = self.body_of_axle(j);
            let body = if b == 0 { &self.tractor } else { &self.trailer };
            let dof = FIRST_AXLE_FULL + j;
            m.mass[(dof, dof)] = axle.mass_kg;
            m.gravity_n[dof] = -axle.mass_kg * GRAVITY_M_S2;
            // Suspension between the body point above the axle and the axle.
            let mut s = DVector::zeros(dofs);
            s[2 * b] = 1.0;
            s[2 * b + 1] = body.cg_behind_front_m - offset;
            s[dof] = -1.0;
            let sst = &s * s.transpose();
            m.stiffness += &sst * axle.suspension_stiffness_n_m;
            m.damping += &sst * axle.suspension_damping_n_s_m;
        }
        m
    }

    fn parameters(&self) -> Vec<(String, f64)> {
        let mut p = vec![
            ("tractor_body_mass_kg".to_string(), self.tractor.mass_kg),
            (
                "tractor_pitch_inertia_kg_m2".to_string(),
                self.tractor.pitch_inertia_kg_m2,
            ),
            (
                "tractor_cg_behind_front_m".to_string(),
                self.tractor.cg_behind_front_m,
            ),
            ("trailer_body_mass_kg".to_string(), self.trailer.mass_kg),
            (
                "trailer_pitch_inertia_kg_m2".to_string(),
                self.trailer.pitch_inertia_kg_m2,
            ),
            (
                "trailer_cg_behind_front_m".to_string(),
                self.trailer.cg_behind_front_m,
            ),
            (
                "fifth_wheel_behind_front_m".to_string(),
                self.fifth_wheel_behind_front_m,
            ),
            (
                "tractor_axle_count".to_string(),
                self.tractor_axle_count as f64,
            ),
        ];
        for (j, (a, &offset)) in self.axles.iter().zip(&self.axle_offsets_m).enumerate() {
            p.extend(axle_parameters(j + 1, offset, a));
        }
        p
    }

    fn dof_names(&self) -> Vec<String> {
        let mut names: Vec<String> = ["tractor_bounce", "tractor_pitch", "trailer_pitch"]
            .iter()
            .map(|s| s.to_string())
            .collect();
        names.extend((1..=self.axles.len()).map(|i| format!("axle_{i}")));
        names
    }
}

/// The unconstrained two-body system, coordinates (y1, theta1, y2, theta2, axles).
struct FullMatrices {
    mass: DMatrix<f64>,
    damping: DMatrix<f64>,
    stiffness: DMatrix<f64>,
    gravity_n: DVector<f64>,
}

#[cfg(test)]
mod tests {
    use super::*;

    fn axle(mass_kg: f64) -> AxleParams {
        AxleParams {
            mass_kg,
            suspension_stiffness_n_m: 1.0e6,
            suspension_damping_n_s_m: 1.0e4,
            tyre_stiffness_n_m: 3.0e6,
            tyre_damping_n_s_m: 1.0e3,
        }
    }

    fn simple() -> ArticulatedParams {
        ArticulatedParams {
            tractor: BodyParams {
                mass_kg: 5_000.0,
                pitch_inertia_kg_m2: 6_000.0,
                cg_behind_front_m: 1.0,
            },
            trailer: BodyParams {
                mass_kg: 20_000.0,
                pitch_inertia_kg_m2: 1.0e5,
                cg_behind_front_m: 7.0,
            },
            fifth_wheel_behind_front_m: 3.0,
            tractor_axle_count: 2,
            axle_offsets_m: vec![0.0, 3.5, 10.0],
            axles: vec![axle(600.0), axle(1_000.0), axle(800.0)],
        }
    }

    #[test]
    fn hinge_transformation_keeps_the_kingpin_together() {
        // For any reduced q, the kingpin's displacement computed on the tractor
        // (y1 + d_k1 theta1) equals the one on the trailer (y2 + d_k2 theta2).
        let p = simple();
        let t = p.hinge_transformation();
        let q = DVector::from_vec(vec![0.3, -0.7, 1.9, 0.0, 0.0, 0.0]);
        let u = &t * q;
        let on_tractor = u[0] + p.kingpin_lever_m(&p.tractor) * u[1];
        let on_trailer = u[2] + p.kingpin_lever_m(&p.trailer) * u[3];
        assert!(
            (on_tractor - on_trailer).abs() < 1e-14,
            "{on_tractor} {on_trailer}"
        );
    }

    #[test]
    fn reduced_matrices_are_symmetric_and_static_loads_sum_to_the_weight() {
        let v = simple().build("articulated").unwrap();
        for m in [&v.mass, &v.stiffness, &v.damping] {
            assert!((m - m.transpose()).amax() <= 1e-12 * m.amax());
        }
        // Single-body statics with three supports (2 tractor axles + hinge) and a
        // 1-axle trailer: trailer about the kingpin, 20000 * (7 - 3) = P3 * (10 - 3).
        let weight = (5_000.0 + 20_000.0 + 2_400.0) * GRAVITY_M_S2;
        assert!((v.gross_weight_n() - weight).abs() < 1e-10 * weight);
        let p3 = 20_000.0 * GRAVITY_M_S2 * 4.0 / 7.0 + 800.0 * GRAVITY_M_S2;
        assert!((v.axles[2].static_load_n - p3).abs() < 1e-10 * p3);
    }

    #[test]
    fn layouts_without_a_trailer_axle_are_refused() {
        let mut p = simple();
        p.tractor_axle_count = 3;
        let msg = p.build("a").unwrap_err().to_string();
        assert!(msg.starts_with("tractor_axle_count = 3"), "{msg}");
        p.tractor_axle_count = 2;
        p.axle_offsets_m.pop();
        let msg = p.build("a").unwrap_err().to_string();
        assert!(msg.starts_with("axle_offsets_m"), "{msg}");
    }
}
