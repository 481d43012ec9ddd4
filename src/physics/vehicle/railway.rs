//! A railway car in the pitch plane: the car body (bounce, pitch) on two bogies (bounce,
//! pitch) through the secondary suspension, each bogie on two wheelsets through the
//! primary suspension, each wheelset on the rail through a linearised Hertz contact
//! spring. Ten DOFs; the solver sees it as any other linear vehicle (the contact spring is
//! the "tyre"), so trains need no solver change.
//!
//! Levers are signed as in `rigid_body_on_axles`: positive ahead of the body's centre. A
//! spring between a point of one body at lever `d` and another DOF stretches by
//! `z + d theta - z_other`, so each spring adds `k B B^T` with that `B`.

use nalgebra::{DMatrix, DVector};

use super::dynamics::{Axle, VehicleDynamics, GRAVITY_M_S2};
use crate::error::Result;

/// One suspension stage: stiffness and damping of the springs at one point, summed over
/// the track's two sides (N/m, N s/m).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Suspension {
    pub stiffness_n_m: f64,
    pub damping_n_s_m: f64,
}

/// A symmetric railway car (conventional: its own two bogies).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RailwayCarParams {
    /// Car body mass (kg) and pitch inertia about its centre (kg m^2).
    pub body_mass_kg: f64,
    pub body_pitch_inertia_kg_m2: f64,
    /// Half the distance between the bogie pivots (m).
    pub bogie_half_spacing_m: f64,
    /// Bogie frame mass (kg) and pitch inertia (kg m^2).
    pub bogie_mass_kg: f64,
    pub bogie_pitch_inertia_kg_m2: f64,
    /// Half the bogie wheelbase (m).
    pub wheelbase_half_m: f64,
    /// Wheelset mass (kg).
    pub wheelset_mass_kg: f64,
    /// Per bogie (both sides).
    pub secondary: Suspension,
    /// Per wheelset (both sides).
    pub primary: Suspension,
    /// Linearised Hertz contact stiffness per wheelset, both wheels (N/m).
    pub contact_stiffness_n_m: f64,
}

/// DOF order: body bounce, body pitch, front bogie bounce and pitch, rear bogie bounce and
/// pitch, wheelsets 1-4 from the front.
const DOF_NAMES: [&str; 10] = [
    "body_bounce",
    "body_pitch",
    "bogie_1_bounce",
    "bogie_1_pitch",
    "bogie_2_bounce",
    "bogie_2_pitch",
    "wheelset_1",
    "wheelset_2",
    "wheelset_3",
    "wheelset_4",
];

impl RailwayCarParams {
    /// Wheelset positions behind the front wheelset (m): 0, 2 lt, 2 lc, 2 lc + 2 lt.
    pub fn wheelset_offsets_m(&self) -> [f64; 4] {
        let (lc, lt) = (self.bogie_half_spacing_m, self.wheelbase_half_m);
        [0.0, 2.0 * lt, 2.0 * lc, 2.0 * lc + 2.0 * lt]
    }

    /// The car's matrices and contacts, static wheel loads from gravity.
    pub fn build(&self, name: &str) -> Result<VehicleDynamics> {
        let n = DOF_NAMES.len();
        let mut mass = DMatrix::zeros(n, n);
        for (d, m) in [
            self.body_mass_kg,
            self.body_pitch_inertia_kg_m2,
            self.bogie_mass_kg,
            self.bogie_pitch_inertia_kg_m2,
            self.bogie_mass_kg,
            self.bogie_pitch_inertia_kg_m2,
        ]
        .into_iter()
        .chain([self.wheelset_mass_kg; 4])
        .enumerate()
        {
            mass[(d, d)] = m;
        }
        let mut stiffness = DMatrix::zeros(n, n);
        let mut damping = DMatrix::zeros(n, n);
        let mut spring = |from: (usize, usize, f64), to: usize, s: Suspension| {
            // (bounce DOF, pitch DOF, lever) of the upper body, the lower DOF.
            let mut b = DVector::zeros(n);
            b[from.0] = 1.0;
            b[from.1] = from.2;
            b[to] = -1.0;
            let bbt = &b * b.transpose();
            stiffness += &bbt * s.stiffness_n_m;
            damping += &bbt * s.damping_n_s_m;
        };
        let (lc, lt) = (self.bogie_half_spacing_m, self.wheelbase_half_m);
        for (bogie, lever) in [(0usize, lc), (1, -lc)] {
            let bounce = 2 + 2 * bogie;
            spring((0, 1, lever), bounce, self.secondary);
            for (w, l) in [(0usize, lt), (1, -lt)] {
                spring((bounce, bounce + 1, l), 6 + 2 * bogie + w, self.primary);
            }
        }
        let axles = self
            .wheelset_offsets_m()
            .iter()
            .enumerate()
            .map(|(w, &offset)| Axle {
                offset_m: offset,
                dof: Some(6 + w),
                tyre_stiffness_n_m: self.contact_stiffness_n_m,
                tyre_damping_n_s_m: 0.0,
                static_load_n: 0.0,
            })
            .collect();
        let mut car = VehicleDynamics {
            name: name.to_string(),
            mass: mass.clone(),
            damping,
            stiffness,
            axles,
            parameters: self.parameters(),
            dof_names: DOF_NAMES.iter().map(|s| s.to_string()).collect(),
        };
        // Gravity on the bounce DOFs only (a pitch DOF carries no weight).
        let gravity = DVector::from_fn(n, |d, _| match d {
            1 | 3 | 5 => 0.0,
            _ => -mass[(d, d)] * GRAVITY_M_S2,
        });
        car.set_static_loads_from_gravity(&gravity)?;
        Ok(car)
    }

    fn parameters(&self) -> Vec<(String, f64)> {
        [
            ("body_mass_kg", self.body_mass_kg),
            ("body_pitch_inertia_kg_m2", self.body_pitch_inertia_kg_m2),
            ("bogie_half_spacing_m", self.bogie_half_spacing_m),
            ("bogie_mass_kg", self.bogie_mass_kg),
            ("bogie_pitch_inertia_kg_m2", self.bogie_pitch_inertia_kg_m2),
            ("wheelbase_half_m", self.wheelbase_half_m),
            ("wheelset_mass_kg", self.wheelset_mass_kg),
            ("secondary_stiffness_n_m", self.secondary.stiffness_n_m),
            ("secondary_damping_n_s_m", self.secondary.damping_n_s_m),
            ("primary_stiffness_n_m", self.primary.stiffness_n_m),
            ("primary_damping_n_s_m", self.primary.damping_n_s_m),
            ("contact_stiffness_n_m", self.contact_stiffness_n_m),
        ]
        .into_iter()
        .map(|(k, v)| (k.to_string(), v))
        .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Values of the order of a passenger coach (not a published vehicle: the checks are
    /// against hand-derived matrices and statics, which hold for any values).
    fn coach() -> RailwayCarParams {
        RailwayCarParams {
            body_mass_kg: 40_000.0,
            body_pitch_inertia_kg_m2: 2.0e6,
            bogie_half_spacing_m: 9.0,
            bogie_mass_kg: 3_000.0,
            bogie_pitch_inertia_kg_m2: 3_000.0,
            wheelbase_half_m: 1.25,
            wheelset_mass_kg: 1_800.0,
            secondary: Suspension {
                stiffness_n_m: 6.0e5,
                damping_n_s_m: 2.0e4,
            },
            primary: Suspension {
                stiffness_n_m: 2.4e6,
                damping_n_s_m: 3.0e4,
            },
            contact_stiffness_n_m: 1.4e9,
        }
    }

    #[test]
    fn the_stiffness_is_the_hand_derived_one() {
        // Written out from the free-body diagrams, not from the B vectors: the body sees
        // 2 ks in bounce and 2 ks lc^2 in pitch; a bogie ks + 2 kp in bounce, 2 kp lt^2 in
        // pitch; each coupling with the opposite sign and its lever.
        let p = coach();
        let k = p.build("coach").unwrap().stiffness;
        let (ks, kp) = (p.secondary.stiffness_n_m, p.primary.stiffness_n_m);
        let (lc, lt) = (p.bogie_half_spacing_m, p.wheelbase_half_m);
        let mut h = DMatrix::<f64>::zeros(10, 10);
        h[(0, 0)] = 2.0 * ks;
        h[(1, 1)] = 2.0 * ks * lc * lc;
        for (i, l) in [(2usize, lc), (4, -lc)] {
            h[(0, i)] = -ks;
            h[(1, i)] = -ks * l;
            h[(i, i)] = ks + 2.0 * kp;
            h[(i + 1, i + 1)] = 2.0 * kp * lt * lt;
            let w = 6 + (i - 2);
            for (j, m) in [(w, lt), (w + 1, -lt)] {
                h[(i, j)] = -kp;
                h[(i + 1, j)] = -kp * m;
                h[(j, j)] = kp;
            }
        }
        let h = h.clone() + h.transpose() - DMatrix::from_diagonal(&h.diagonal());
        assert!(
            (&k - &h).abs().max() <= 1e-9 * h.abs().max(),
            "{k}\nvs\n{h}"
        );
    }

    #[test]
    fn static_wheel_loads_follow_the_lever_rule() {
        // Symmetric car: each wheelset carries a quarter of the body, half a bogie and
        // itself.
        let p = coach();
        let car = p.build("coach").unwrap();
        let expected =
            (p.body_mass_kg / 4.0 + p.bogie_mass_kg / 2.0 + p.wheelset_mass_kg) * GRAVITY_M_S2;
        for a in &car.axles {
            assert!(
                (a.static_load_n / expected - 1.0).abs() < 1e-12,
                "{}",
                a.static_load_n
            );
        }
        assert_eq!(p.wheelset_offsets_m(), [0.0, 2.5, 18.0, 20.5]);
    }

    #[test]
    fn on_a_rigid_level_track_the_car_rests_and_its_modes_are_the_expected_ones() {
        let p = coach();
        let car = p.build("coach").unwrap();
        // A uniform rise of the rail lifts every DOF by it and pitches nothing.
        let y = car.equilibrium_on_road(&[0.01; 4]);
        for (d, &v) in y.iter().enumerate() {
            let want = if matches!(d, 1 | 3 | 5) { 0.0 } else { 0.01 };
            assert!((v - want).abs() < 1e-12, "DOF {d}: {v}");
        }
        // Body bounce on the secondary, the primaries and contacts in series (per bogie):
        // the stiff levels below it barely move, so f ~ sqrt(2 k_eq / M) / 2 pi within a
        // few percent (the bogies' mass adds a little).
        let series = 1.0
            / (1.0 / p.secondary.stiffness_n_m
                + 1.0 / (2.0 * p.primary.stiffness_n_m)
                + 1.0 / (2.0 * p.contact_stiffness_n_m));
        let bounce_hz = (2.0 * series / p.body_mass_kg).sqrt() / (2.0 * std::f64::consts::PI);
        let mut hz: Vec<f64> = car
            .rigid_road_eigenvalues()
            .unwrap()
            .iter()
            .filter(|l| l.im > 0.0)
            .map(|l| l.norm() / (2.0 * std::f64::consts::PI))
            .collect();
        hz.sort_by(f64::total_cmp);
        assert_eq!(hz.len(), 10, "{hz:?}");
        assert!(
            (hz[0] / bounce_hz - 1.0).abs() < 0.05,
            "{} vs {bounce_hz}",
            hz[0]
        );
    }
}
