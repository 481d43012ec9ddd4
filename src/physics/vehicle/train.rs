//! Trains: compositions of railway cars (conventional cars, articulated rakes) built as one
//! vehicle, and the preset trains with the sources of their numbers.
//!
//! A train is one `VehicleDynamics` (its axles numbered front to rear along the whole
//! train, so `/truth/axle_loads` names every wheelset); the solver splits it into its
//! independent cars. As moving forces it is the same axles carrying the same static loads
//! with no dynamics.

use super::dynamics::{VehicleDynamics, GRAVITY_M_S2};
use super::rake::{Bogie, CarBody, Pivot, RakeLayout, Suspension};
use crate::error::{Error, Result};

/// One car with its own two bogies.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CarParams {
    pub body_mass_kg: f64,
    pub body_pitch_inertia_kg_m2: f64,
    /// Distance between the two bogie centres (m).
    pub bogie_spacing_m: f64,
    /// From the front coupler to the front bogie centre, and from the rear bogie centre to
    /// the rear coupler (m).
    pub front_overhang_m: f64,
    pub rear_overhang_m: f64,
    pub bogie_mass_kg: f64,
    pub bogie_pitch_inertia_kg_m2: f64,
    pub wheelbase_m: f64,
    pub wheelset_mass_kg: f64,
    /// Per wheelset (both axleboxes).
    pub primary: Suspension,
    /// Per bogie (both sides).
    pub secondary: Suspension,
    /// Per wheelset; `None`: the linearised Hertz spring at the wheelset's static load.
    pub contact_stiffness_n_m: Option<f64>,
}

/// A part of a train between two couplers: its rake (positions behind its own first
/// wheelset) and where that wheelset sits.
#[derive(Debug, Clone, PartialEq)]
pub struct TrainUnit {
    pub layout: RakeLayout,
    /// From the front coupler to the first wheelset (m).
    pub nose_m: f64,
    /// Coupler to coupler (m).
    pub length_m: f64,
    /// `None`: Hertz at each wheelset's static load.
    pub contact_stiffness_n_m: Option<f64>,
}

/// How the train loads the track.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Representation {
    /// The full pitch-plane model of every car.
    Vehicles,
    /// Each wheelset's static load as a constant force.
    MovingForces,
}

/// Contact spring the static loads are solved with before the Hertz springs are set from
/// them (N/m): any value gives the same loads; one of the right order keeps the solve well
/// conditioned.
const NOMINAL_CONTACT_N_M: f64 = 2.5e9;

/// Wheel radius the Hertz constant is evaluated at (m): a new high-speed wheel of 0.92 m
/// diameter.
pub const WHEEL_RADIUS_M: f64 = 0.46;

/// Linearised Hertz stiffness of one wheelset (two wheels, N/m) under axle load
/// `axle_load_n`: with the wheel-rail Hertz law `delta = G Q^(2/3)` and the constant
/// `G = 4.57e-8 R^-0.149 m/N^(2/3)` for a worn tread (the form commonly quoted from Zhai's
/// vehicle-track coupled dynamics; not checked here against the text), the tangent
/// stiffness per wheel at its static load Q is `3/2 Q^(1/3) / G`.
pub fn hertz_contact_stiffness_n_m(axle_load_n: f64) -> f64 {
    let g = 4.57e-8 * WHEEL_RADIUS_M.powf(-0.149);
    let wheel_load_n = 0.5 * axle_load_n;
    2.0 * 1.5 * wheel_load_n.cbrt() / g
}

impl CarParams {
    /// The car as a train unit: one body (its centre of gravity midway between the bogies)
    /// on two bogies.
    pub fn unit(&self) -> TrainUnit {
        let half_wb = 0.5 * self.wheelbase_m;
        let bogie = |centre_m| Bogie {
            centre_m,
            wheelbase_m: self.wheelbase_m,
            frame_mass_kg: self.bogie_mass_kg,
            frame_pitch_inertia_kg_m2: self.bogie_pitch_inertia_kg_m2,
            wheelset_mass_kg: self.wheelset_mass_kg,
            primary: self.primary,
            contact_stiffness_n_m: self.contact_stiffness_n_m.unwrap_or(NOMINAL_CONTACT_N_M),
        };
        let pivot = |bogie| Pivot {
            body: 0,
            bogie,
            secondary: self.secondary,
        };
        TrainUnit {
            layout: RakeLayout {
                bodies: vec![CarBody {
                    centre_m: half_wb + 0.5 * self.bogie_spacing_m,
                    mass_kg: self.body_mass_kg,
                    pitch_inertia_kg_m2: self.body_pitch_inertia_kg_m2,
                }],
                bogies: vec![bogie(half_wb), bogie(half_wb + self.bogie_spacing_m)],
                pivots: vec![pivot(0), pivot(1)],
            },
            nose_m: self.front_overhang_m - half_wb,
            length_m: self.front_overhang_m + self.bogie_spacing_m + self.rear_overhang_m,
            contact_stiffness_n_m: self.contact_stiffness_n_m,
        }
    }

    /// The same car turned round (its overhangs swapped): the rear end car of a train.
    pub fn reversed(&self) -> CarParams {
        CarParams {
            front_overhang_m: self.rear_overhang_m,
            rear_overhang_m: self.front_overhang_m,
            ..*self
        }
    }
}

/// A train: units coupled front to rear.
#[derive(Debug, Clone, PartialEq)]
pub struct Train {
    pub name: String,
    pub units: Vec<TrainUnit>,
    /// A train known only by its axles (a load model whose vehicles have no published
    /// suspension): it runs as moving forces only, and `units` is empty.
    pub axles_only: Option<AxleLoads>,
}

/// Axles of a train known only as a load model: positions behind the first axle and
/// static loads, front to rear.
#[derive(Debug, Clone, PartialEq)]
pub struct AxleLoads {
    pub offsets_m: Vec<f64>,
    pub loads_n: Vec<f64>,
    /// Coupler to coupler (m).
    pub length_m: f64,
}

impl Train {
    /// The whole train as one rake, positions behind its first wheelset, with the index
    /// of the unit of every bogie.
    pub fn layout(&self) -> (RakeLayout, Vec<usize>) {
        let mut rake = RakeLayout::default();
        let mut unit_of_bogie = Vec::new();
        let mut coupler_m = -self.units.first().map_or(0.0, |u| u.nose_m);
        for (i, unit) in self.units.iter().enumerate() {
            rake.append(&unit.layout, coupler_m + unit.nose_m);
            unit_of_bogie.extend(std::iter::repeat_n(i, unit.layout.bogies.len()));
            coupler_m += unit.length_m;
        }
        (rake, unit_of_bogie)
    }

    /// Coupler to coupler (m).
    pub fn length_m(&self) -> f64 {
        match &self.axles_only {
            Some(axles) => axles.length_m,
            None => self.units.iter().map(|u| u.length_m).sum(),
        }
    }

    /// The train as the solver sees it. A load model (`axles_only`) has no vehicles: it
    /// is refused as such, naming `representation`.
    pub fn build(&self, representation: Representation) -> Result<VehicleDynamics> {
        self.build_for(representation, "representation")
    }

    /// [`Train::build`], its refusal of vehicles for a load model naming
    /// `representation_field` (the scenario path of the choice).
    pub fn build_for(
        &self,
        representation: Representation,
        representation_field: &str,
    ) -> Result<VehicleDynamics> {
        if let Some(axles) = &self.axles_only {
            if representation == Representation::Vehicles {
                return Err(Error::invalid(
                    representation_field,
                    "\"vehicles\"",
                    format!(
                        "is not available for {}: a load model, axle loads and geometry \
                         only, with no published suspension for its vehicles; use \
                         representation = \"moving_forces\"",
                        self.name
                    ),
                ));
            }
            check_axle_order(&axles.offsets_m, &self.name)?;
            let mut forces = VehicleDynamics::moving_forces(&axles.loads_n, &axles.offsets_m);
            forces.name = format!("{} (moving forces)", self.name);
            forces.parameters = vec![
                ("length_m".to_string(), axles.length_m),
                ("gross_weight_n".to_string(), axles.loads_n.iter().sum()),
            ];
            return Ok(forces);
        }
        let (rake, unit_of_bogie) = self.layout();
        check_axle_order(&rake.wheelset_offsets_m(), &self.name)?;
        let parameters = vec![
            ("cars".to_string(), rake.bodies.len() as f64),
            ("length_m".to_string(), self.length_m()),
        ];
        let mut train = rake.build(&self.name, parameters)?;
        // The static loads do not depend on the contact springs (each body rests on two
        // pivots, each bogie on two wheelsets: statically determinate), so the Hertz
        // springs can be set from them afterwards.
        for (j, axle) in train.axles.iter_mut().enumerate() {
            axle.tyre_stiffness_n_m = self.units[unit_of_bogie[j / 2]]
                .contact_stiffness_n_m
                .unwrap_or_else(|| hertz_contact_stiffness_n_m(axle.static_load_n));
        }
        train
            .parameters
            .push(("gross_weight_n".to_string(), train.gross_weight_n()));
        Ok(match representation {
            Representation::Vehicles => train,
            Representation::MovingForces => {
                let loads: Vec<f64> = train.axles.iter().map(|a| a.static_load_n).collect();
                let offsets: Vec<f64> = train.axles.iter().map(|a| a.offset_m).collect();
                let mut forces = VehicleDynamics::moving_forces(&loads, &offsets);
                forces.name = format!("{} (moving forces)", self.name);
                forces.parameters = train.parameters;
                forces
            }
        })
    }
}

/// Every wheelset behind the one before it (cars whose bogies reach past their couplers
/// would put wheelsets on top of each other's).
fn check_axle_order(offsets_m: &[f64], name: &str) -> Result<()> {
    for (j, pair) in offsets_m.windows(2).enumerate() {
        if pair[1] <= pair[0] {
            return Err(Error::invalid(
                "cars",
                name,
                format!(
                    "puts wheelset {} at {} m, not behind wheelset {} at {} m: a bogie \
                     reaches past its car's coupler (overhang shorter than half the \
                     wheelbase?)",
                    j + 2,
                    crate::error::num(pair[1]),
                    j + 1,
                    crate::error::num(pair[0])
                ),
            ));
        }
    }
    Ok(())
}

/// Body pitch inertia of a slender uniform body of `length_m` (kg m^2): the estimate used
/// where a source gives none.
fn slender_pitch_inertia(mass_kg: f64, length_m: f64) -> f64 {
    mass_kg * length_m * length_m / 12.0
}

/// The ten HSLM-A trains of EN 1991-2 Annex E (Table E.4): (N intermediate coaches,
/// coach length D (m), bogie axle spacing d (m), axle load P (kN)). Cross-checked: the
/// UPM CALDINTAV axle files (a01-a10.def, Goicolea's group) and the table of a Python
/// port of TTB-2D (Cantero 2022) agree on every entry.
pub const HSLM_A: [(usize, f64, f64, f64); 10] = [
    (18, 18.0, 2.0, 170.0),
    (17, 19.0, 3.5, 200.0),
    (16, 20.0, 2.0, 180.0),
    (15, 21.0, 3.0, 190.0),
    (14, 22.0, 2.0, 170.0),
    (13, 23.0, 2.0, 180.0),
    (13, 24.0, 2.0, 190.0),
    (12, 25.0, 2.5, 190.0),
    (11, 26.0, 2.0, 210.0),
    (11, 27.0, 2.0, 210.0),
];

/// HSLM-A power car axles (EN 1991-2 Figure E.8): 0, 3, 14, 17 m; 3.525 m from its last
/// axle to the end coach's first.
const HSLM_POWER_CAR_AXLES_M: [f64; 4] = [0.0, 3.0, 14.0, 17.0];
const HSLM_COUPLING_M: f64 = 3.525;

/// Bogies and suspension of the HSLM vehicle models: the standard defines only axle
/// loads and geometry, so the vehicle models take a high-speed train's bogies: the
/// Eurostar locomotive's for the power cars and the articulated trailers' for the coaches
/// (Domenech 2014, PhD thesis, UPV, as tabulated in TTB-2D's TrainProp files; the trailers'
/// secondary damping, blank there, is taken as the end trailers' 20 kN s/m). Body masses
/// are then set so that every axle carries exactly P.
struct HslmBogies {
    frame_kg: f64,
    frame_pitch_kg_m2: f64,
    wheelset_kg: f64,
    primary: Suspension,
    secondary: Suspension,
}

const HSLM_POWER_BOGIE: HslmBogies = HslmBogies {
    frame_kg: 2_200.0,
    frame_pitch_kg_m2: 1_900.0,
    wheelset_kg: 1_700.0,
    primary: Suspension {
        stiffness_n_m: 2.6e6,
        damping_n_s_m: 1.2e4,
    },
    secondary: Suspension {
        stiffness_n_m: 3.26e6,
        damping_n_s_m: 9.0e4,
    },
};

const HSLM_COACH_BOGIE: HslmBogies = HslmBogies {
    frame_kg: 2_900.0,
    frame_pitch_kg_m2: 2_508.0,
    wheelset_kg: 1_900.0,
    primary: Suspension {
        stiffness_n_m: 2.0e6,
        damping_n_s_m: 1.2e4,
    },
    secondary: Suspension {
        stiffness_n_m: 5.8e5,
        damping_n_s_m: 2.0e4,
    },
};

impl HslmBogies {
    fn bogie(&self, centre_m: f64, wheelbase_m: f64) -> Bogie {
        Bogie {
            centre_m,
            wheelbase_m,
            frame_mass_kg: self.frame_kg,
            frame_pitch_inertia_kg_m2: self.frame_pitch_kg_m2,
            wheelset_mass_kg: self.wheelset_kg,
            primary: self.primary,
            contact_stiffness_n_m: NOMINAL_CONTACT_N_M,
        }
    }

    /// What a bogie weighs with its wheelsets (N).
    fn weight_n(&self) -> f64 {
        (self.frame_kg + 2.0 * self.wheelset_kg) * GRAVITY_M_S2
    }
}

/// HSLM-A`number` (1-10): its axles as moving forces of exactly P, or as vehicles.
pub fn hslm_a(number: usize) -> Train {
    let (n, coach_m, d, p_kn) = HSLM_A[number - 1];
    let p = p_kn * 1e3;
    // The end coach's outer bogie to the first Jacobs bogie: its front axle
    // `D - 1.5 d - 3.525 / 2` behind the outer bogie's rear axle (Figure E.8).
    let end_span_m = coach_m - 0.5 * d - 0.5 * HSLM_COUPLING_M;
    let rake = articulated_rake(n, end_span_m, coach_m, d, p, HSLM_COUPLING_M);
    powered_rake(format!("hslm_a{number}"), p, rake, HSLM_COUPLING_M)
}

/// The articulated high-speed train of EN 1991-2 Annex D, train type 4 (the TGV family):
/// two power cars of four 17 t axles (bogies of 3.0 m wheelbase, 11.0 m between their
/// inner axles) and ten trailers on two outer bogies and nine Jacobs bogies (3.0 m
/// wheelbase, 18.7 m apart; 15.7 m from an outer bogie's inner axle to the first Jacobs
/// bogie's), 17 t on every axle, 1.65 m from each end axle to its coupler: 30 axles.
/// Source: the standard's figure as transcribed in the pacril package
/// (Gunnstein/pacril, `data/eurocode.py`, `Type4`); the standard's own text was not at
/// hand. The 14.0 m power-car bogie spacing and the 18.7 m trailer pitch agree with the
/// AVE axle file of the UPM CALDINTAV code (`trains/ave.def`) and with the Eurostar of
/// TTB-2D. As vehicles it takes the HSLM vehicle models' bogies (the Eurostar's, below)
/// with the bodies' masses set so that every axle carries its 17 t.
pub fn en1991_type4() -> Train {
    const AXLE_LOAD_N: f64 = 17_000.0 * GRAVITY_M_S2;
    const COUPLING_M: f64 = 2.0 * 1.65;
    const WHEELBASE_M: f64 = 3.0;
    const PITCH_M: f64 = 18.7;
    // Outer bogie centre to the first Jacobs bogie's: half a wheelbase, 15.7 m, half.
    let end_span_m = WHEELBASE_M + 15.7;
    let rake = articulated_rake(8, end_span_m, PITCH_M, WHEELBASE_M, AXLE_LOAD_N, COUPLING_M);
    powered_rake("en1991_type4".into(), AXLE_LOAD_N, rake, COUPLING_M)
}

/// Power car, `rake`, power car turned round: the HSLM and TGV-family layout.
fn powered_rake(name: String, p_n: f64, rake: TrainUnit, coupling_m: f64) -> Train {
    let power = power_car(p_n, coupling_m);
    Train {
        name,
        units: vec![
            power.clone(),
            rake,
            TrainUnit {
                layout: mirrored(&power.layout),
                ..power
            },
        ],
        axles_only: None,
    }
}

/// A freight train of EN 1991-2 Annex D as a load model: a six-axle locomotive (axles
/// 1.4, 2.2, 2.2, 6.9, 2.2, 2.2 m apart, 1.4 m to each coupler, 22.5 t) and ten bogie
/// wagons of `axle_t` tonnes per axle, `end_m` from each coupler to the nearer bogie
/// centre, bogie centres `bogies_m` apart, wheelbase `wheelbase_m`. Type 7: 22.5 t,
/// 2.5 / 12.8 / 1.8 m; type 11: 25 t, 2.5 / 13.0 / 2.0 m. Source: the Annex D figures as
/// transcribed in the pacril package (`data/eurocode.py`), with its documented symmetric
/// wagon (the code's rear overhang `a / 2` reads as a slip); the standard's text was not
/// at hand. No published suspension for these vehicles was found, so there is no vehicle
/// model.
pub fn en1991_freight(
    name: &str,
    axle_t: f64,
    end_m: f64,
    bogies_m: f64,
    wheelbase_m: f64,
) -> Train {
    const LOCO_AXLE_T: f64 = 22.5;
    let loco_gaps = [1.4, 2.2, 2.2, 6.9, 2.2, 2.2, 1.4];
    let wagon_gaps = [
        end_m - 0.5 * wheelbase_m,
        wheelbase_m,
        bogies_m - wheelbase_m,
        wheelbase_m,
        end_m - 0.5 * wheelbase_m,
    ];
    let mut vehicles: Vec<(&[f64], f64)> = vec![(&loco_gaps, LOCO_AXLE_T)];
    vehicles.extend(std::iter::repeat_n((&wagon_gaps[..], axle_t), 10));
    let (mut offsets_m, mut loads_n) = (Vec::new(), Vec::new());
    let mut coupler_m = 0.0;
    for (gaps, tonnes) in vehicles {
        let mut x = coupler_m;
        for (k, gap) in gaps.iter().enumerate() {
            x += gap;
            if k + 1 < gaps.len() {
                offsets_m.push(x);
                loads_n.push(tonnes * 1e3 * GRAVITY_M_S2);
            }
        }
        coupler_m = x;
    }
    let first = offsets_m[0];
    Train {
        name: name.to_string(),
        units: Vec::new(),
        axles_only: Some(AxleLoads {
            offsets_m: offsets_m.iter().map(|x| x - first).collect(),
            loads_n,
            length_m: coupler_m,
        }),
    }
}

/// A power car on two bogies of 3 m wheelbase, 14 m apart, each axle carrying P, half a
/// coupling `coupling_m` from each end axle to its coupler.
fn power_car(p_n: f64, coupling_m: f64) -> TrainUnit {
    let g = &HSLM_POWER_BOGIE;
    let [a0, a1, a2, a3] = HSLM_POWER_CAR_AXLES_M;
    let body_weight_n = 4.0 * p_n - 2.0 * g.weight_n();
    let mass = body_weight_n / GRAVITY_M_S2;
    let length_m = a3 - a0 + coupling_m;
    TrainUnit {
        layout: RakeLayout {
            bodies: vec![CarBody {
                centre_m: 0.5 * (a0 + a3),
                mass_kg: mass,
                pitch_inertia_kg_m2: slender_pitch_inertia(mass, length_m),
            }],
            bogies: vec![
                g.bogie(0.5 * (a0 + a1), a1 - a0),
                g.bogie(0.5 * (a2 + a3), a3 - a2),
            ],
            pivots: (0..2)
                .map(|bogie| Pivot {
                    body: 0,
                    bogie,
                    secondary: g.secondary,
                })
                .collect(),
        },
        nose_m: 0.5 * coupling_m,
        length_m,
        contact_stiffness_n_m: None,
    }
}

/// End coach, N intermediate coaches, end coach on N + 3 bogies of wheelbase d: the end
/// coaches' outer bogies, `end_span_m` from the first and last of N + 1 Jacobs bogies D
/// apart, half a coupling `coupling_m` from each end axle to its coupler.
///
/// Every axle carries P: an intermediate body weighs `W = 2P - bogie` (each Jacobs bogie
/// carries two half bodies); an end coach weighs `1.5 W` with its centre a third of its
/// pivot spacing from its outer bogie, which then takes `W` and the Jacobs bogie `W / 2`.
fn articulated_rake(
    n: usize,
    end_span_m: f64,
    coach_m: f64,
    d: f64,
    p_n: f64,
    coupling_m: f64,
) -> TrainUnit {
    let g = &HSLM_COACH_BOGIE;
    let w_n = 2.0 * p_n - g.weight_n();
    let mut centres = vec![0.5 * d];
    centres.extend((0..=n).map(|k| 0.5 * d + end_span_m + k as f64 * coach_m));
    centres.push(centres[n + 1] + end_span_m);
    let bogies: Vec<Bogie> = centres.iter().map(|&c| g.bogie(c, d)).collect();
    let end = |outer: f64, inner: f64| {
        let mass = 1.5 * w_n / GRAVITY_M_S2;
        CarBody {
            centre_m: outer + (inner - outer) / 3.0,
            mass_kg: mass,
            pitch_inertia_kg_m2: slender_pitch_inertia(mass, coach_m),
        }
    };
    let mut bodies = vec![end(centres[0], centres[1])];
    bodies.extend((1..=n).map(|k| {
        let mass = w_n / GRAVITY_M_S2;
        CarBody {
            centre_m: 0.5 * (centres[k] + centres[k + 1]),
            mass_kg: mass,
            pitch_inertia_kg_m2: slender_pitch_inertia(mass, coach_m),
        }
    }));
    bodies.push(end(centres[n + 2], centres[n + 1]));
    let pivots = (0..bodies.len())
        .flat_map(|b| [b, b + 1])
        .enumerate()
        .map(|(i, bogie)| Pivot {
            body: i / 2,
            bogie,
            secondary: g.secondary,
        })
        .collect();
    let last_axle_m = centres[n + 2] + 0.5 * d;
    TrainUnit {
        layout: RakeLayout {
            bodies,
            bogies,
            pivots,
        },
        nose_m: 0.5 * coupling_m,
        length_m: last_axle_m + coupling_m,
        contact_stiffness_n_m: None,
    }
}

/// A unit's rake turned round about its own first and last wheelsets.
fn mirrored(layout: &RakeLayout) -> RakeLayout {
    let last = layout
        .wheelset_offsets_m()
        .last()
        .copied()
        .unwrap_or_default();
    let flip = |x: f64| last - x;
    let nb = layout.bogies.len();
    RakeLayout {
        bodies: layout
            .bodies
            .iter()
            .rev()
            .map(|b| CarBody {
                centre_m: flip(b.centre_m),
                ..*b
            })
            .collect(),
        bogies: layout
            .bogies
            .iter()
            .rev()
            .map(|g| Bogie {
                centre_m: flip(g.centre_m),
                ..*g
            })
            .collect(),
        pivots: layout
            .pivots
            .iter()
            .map(|p| Pivot {
                body: layout.bodies.len() - 1 - p.body,
                bogie: nb - 1 - p.bogie,
                ..*p
            })
            .collect(),
    }
}
