//! Vehicle presets per traffic class, and the builder that scales a class preset to the
//! gross weight, axle spacings and axle load shares the traffic generator draws.
//!
//! # Presets (scenario: `kind = "rigid_truck"` or `"articulated"`, `preset = <class>`)
//!
//! | class | kind | bodies: mass (kg), pitch inertia (kg m^2), CG behind front axle (m) | axle spacing (m) | axle mass (kg) | k_susp (kN/m) | k_tyre (kN/m) | static loads (kN) | modes (Hz) | source |
//! |---|---|---|---|---|---|---|---|---|---|
//! | `car` | rigid_truck | 1 230, 1 900, 1.10 | 2.60 | 90/80 | 50/45 | 400/400 | 7.8/5.9 | 1.27, 1.43, 11.3, 11.9 | estimate (1) |
//! | `truck_2axle` | rigid_truck | 17 735, 1.47e5, 2.135 | 4.27 | 1 500/1 000 | 2 470/4 230 | 3 740/4 600 | 101.7/96.8 | 1.62, 2.31, 10.4, 15.1 | docs/physics.md 6 `two_axle_truck` |
//! | `truck_3axle` | rigid_truck | 23 400, 1.9e5, 3.75 | 4.50, 1.35 | 600/1 000/1 000 | 800/1 500/1 500 | 2 000/3 500/3 500 | 68.1/97.5/89.5 | 1.29, 1.72, 10.9, 11.3, 11.3 | estimate (2) |
//! | `truck_4axle` | rigid_truck | 28 600, 2.4e5, 3.50 | 1.90, 3.30, 1.35 | 600/600/1 100/1 100 | 800/800/1 500/1 500 | 2 000/2 000/3 500/3 500 | 76.6/66.9/91.6/78.9 | 1.36, 1.80, 10.7, 10.8, 10.9, 10.9 | estimate (2) |
//! | `artic_5axle` | articulated | tractor 4 500, 4 604, 0.54; trailer 31 450, 16 302, 7.64; fifth wheel 2.89 | 3.24, 5.43, 1.20, 1.21 | 700/1 100/750/750/750 | 400/1 000/750/750/750 | 1 750/3 500 x4 | 54.3/105.8/78.8/77.5/76.2 | 1.42, 1.60, 4.96, 8.85, 10.5, 12.0, 12.0, 12.1 | VBI-2D `Vehicle_2A3` (docs/sensors.md 4) on the Auxerre spacings; CGs, fifth wheel: estimates (3) |
//!
//! Damping: `car` 3.0/2.4 kN s/m suspension (about 25 % of critical on the body), 0.2 kN
//! s/m tyres (estimates); `truck_2axle` as docs/physics.md; the other trucks 0.01 s x k_susp
//! (the `truck_2axle` ratio) and 10 kN s/m per axle's tyres (VBI-2D).
//!
//! (1) A 1 400 kg family car, 57 % of its weight on the front axle, two 200 kN/m tyres
//! per axle, tuned into the usual passenger-car ride (1-1.5 Hz) and wheel-hop (10-12 Hz)
//! ranges. (2) GVW 26 t (3 axles) and 32 t (4 axles), the usual European limits; steer
//! axles 600 kg on 2 x 1 000 kN/m tyres, drive axles with VBI-2D's twin-tyre 3 500 kN/m;
//! spacings typical of steer + tandem and twin-steer + tandem chassis. (3) VBI-2D's
//! geometry (tractor CG 0.5 m behind the steer axle of 3.0 m wheelbase, fifth wheel
//! 0.35 m ahead of the drive axle, trailer CG at 0.68 of kingpin to tridem centre)
//! moved onto these spacings.
//!
//! Modes on a rigid road; `tests/suite/multi_axle.rs` pins them. Body bounce/pitch lie in
//! 1-4 Hz (docs/sensors.md section 4) except the light tractor's pitch on its stiff drive axle
//! (4.96 Hz); axle hop lies in 10-20 Hz except `artic_5axle`'s steer axle (8.85 Hz):
//! VBI-2D's soft steer suspension on a 700 kg axle gives that.
//! Tandem/tridem axles have independent springs (no load-equalising bogie), so their
//! static loads differ by the body's static pitch.
//!
//! # Scaling to the traffic generator's draw (`vehicle_for_traffic`)
//!
//! Axle masses and tyres are the preset's (hardware does not change with payload; a
//! tyre's stiffness barely depends on its load). Each suspension keeps the preset's
//! static deflection, so its stiffness scales with the body load it carries, as an air
//! suspension's does: body frequencies stay near the preset's. The body points above the
//! axles must lie on one line per body (the trailer's through the kingpin), so the wanted
//! deflections (preset suspension deflection + new tyre compression) are fitted by least
//! squares (exact for a 2-axle body) and each suspension is sized to carry its body load
//! over the fitted deflection left after its tyre's. Bodies are then placed where their
//! equilibrium needs them: body mass = sum of suspension loads, CG at their centroid (the
//! lever rule). That position being rigid (hinge respected) and every force balancing, it
//! is the static solution of the new model: `set_static_loads_from_gravity` returns
//! exactly `gross_weight_n * share`. Dampers keep the preset's values: shock absorbers
//! are hardware like the axles and tyres, and scaling them with the load-levelled springs
//! would leave an empty truck's axle hop nearly undamped (a 6 t `truck_2axle`'s front
//! suspension carries 2.7 kN of body over a 1 500 kg axle; its hop damping ratio fell
//! from 0.19 to 0.03 and its dynamic tyre force reached 0.7 x static on a class A road).
//! An empty body is then more damped than a loaded one, as on the road. Pitch inertias with
//! mass times length squared (same radius of gyration per unit body length); the fifth
//! wheel keeps its fraction of the tractor wheelbase. An articulated tractor's body scales
//! with its axles' load so the kingpin keeps its share of it (positive for any draw); the
//! trailer takes the rest of the sprung weight. A draw whose loads within one body differ
//! so much that a suspension would keep less than half its preset deflection is refused
//! (named field), rather than given a near-rigid spring.

use nalgebra::DVector;

use super::articulated::ArticulatedParams;
use super::dynamics::{VehicleDynamics, GRAVITY_M_S2};
use super::models::{AxleParams, BodyParams, RigidTruckParams};
use super::truck_spec::{axle_offsets, ArticulatedSpec, RigidTruckSpec};
use crate::error::{num, require_positive, Error, Result};

/// The traffic classes `vehicle_for_traffic` accepts; each is also a preset name.
pub const TRAFFIC_CLASSES: [&str; 5] = [
    "car",
    "truck_2axle",
    "truck_3axle",
    "truck_4axle",
    "artic_5axle",
];

/// How far the axle load shares may sum away from 1: rounding of shares drawn or read as
/// decimals, not a second weight.
const SHARE_SUM_TOLERANCE: f64 = 1e-6;

/// A vehicle of traffic class `class` (`TRAFFIC_CLASSES`) whose static axle loads on a
/// level road are `gross_weight_n * axle_load_share[j]`, with axles `axle_spacing_m`
/// apart. The class preset is scaled as the module documentation explains; the model is
/// named `<kind>/<class>` ("rigid_truck/truck_3axle", "articulated/artic_5axle").
/// Errors name `<field_prefix>.class`, `.gross_weight_n`, `.axle_spacing_m[.i]` or
/// `.axle_load_share[.i]`. The shares must sum to 1 within 1e-6 and are used as given.
pub fn vehicle_for_traffic(
    class: &str,
    gross_weight_n: f64,
    axle_spacing_m: &[f64],
    axle_load_share: &[f64],
    field_prefix: &str,
) -> Result<VehicleDynamics> {
    let f = |name: &str| format!("{field_prefix}.{name}");
    let preset = ClassPreset::of(class, &f("class"))?;
    let n = preset.axle_count();
    require_positive(&f("gross_weight_n"), gross_weight_n)?;
    let offsets_m = axle_offsets(Some(axle_spacing_m.to_vec()), &f("axle_spacing_m"), n..=n)?;
    let loads_n = target_loads(gross_weight_n, axle_load_share, n, &f("axle_load_share"))?;
    let mut vehicle = match preset {
        ClassPreset::Rigid(kind, p) => {
            scale_rigid(&p, &offsets_m, &loads_n, &f("axle_load_share"))?
                .build(&format!("{kind}/{class}"))?
        }
        ClassPreset::Articulated(kind, p) => {
            scale_articulated(&p, &offsets_m, &loads_n, &f("axle_load_share"))?
                .build(&format!("{kind}/{class}"))?
        }
    };
    vehicle
        .parameters
        .push(("gross_weight_n".into(), gross_weight_n));
    for (j, share) in axle_load_share.iter().enumerate() {
        vehicle
            .parameters
            .push((format!("axle_{}_load_share", j + 1), *share));
    }
    Ok(vehicle)
}

/// A class's preset parameters, with its scenario kind.
enum ClassPreset {
    Rigid(&'static str, RigidTruckParams),
    Articulated(&'static str, ArticulatedParams),
}

impl ClassPreset {
    fn of(class: &str, field: &str) -> Result<ClassPreset> {
        // Presets are constants: failing to build one is a bug, reported, not hidden.
        if let Some(spec) = RigidTruckSpec::preset(class) {
            return Ok(ClassPreset::Rigid("rigid_truck", spec.params(field)?));
        }
        if let Some(spec) = ArticulatedSpec::preset(class) {
            return Ok(ClassPreset::Articulated("articulated", spec.params(field)?));
        }
        Err(Error::invalid(
            field,
            format!("\"{class}\""),
            format!(
                "is not a traffic class; known: {}",
                TRAFFIC_CLASSES.join(", ")
            ),
        ))
    }

    fn axle_count(&self) -> usize {
        match self {
            ClassPreset::Rigid(_, p) => p.axles.len(),
            ClassPreset::Articulated(_, p) => p.axles.len(),
        }
    }
}

/// `gross_weight_n * share`, after checking the shares.
fn target_loads(gross_weight_n: f64, shares: &[f64], n: usize, field: &str) -> Result<Vec<f64>> {
    if shares.len() != n {
        return Err(Error::invalid(
            field,
            format!("{shares:?}"),
            format!("must have {n} entries, one per axle"),
        ));
    }
    for (i, &s) in shares.iter().enumerate() {
        require_positive(&format!("{field}.{i}"), s)?;
    }
    let sum: f64 = shares.iter().sum();
    if (sum - 1.0).abs() > SHARE_SUM_TOLERANCE {
        return Err(Error::invalid(
            field,
            format!("{shares:?}"),
            format!("must sum to 1 (sum {})", num(sum)),
        ));
    }
    Ok(shares.iter().map(|s| gross_weight_n * s).collect())
}

/// Suspension force of each axle: its load minus its own weight, which must stay positive.
fn body_loads(loads_n: &[f64], axles: &[AxleParams], field: &str) -> Result<Vec<f64>> {
    loads_n
        .iter()
        .zip(axles)
        .enumerate()
        .map(|(i, (&load, a))| {
            let own_n = a.mass_kg * GRAVITY_M_S2;
            if load > own_n {
                Ok(load - own_n)
            } else {
                Err(Error::invalid(
                    format!("{field}.{i}"),
                    num(load / loads_n.iter().sum::<f64>()),
                    format!(
                        "gives axle {} a load of {} N, not above its own weight {} N",
                        i + 1,
                        num(load),
                        num(own_n)
                    ),
                ))
            }
        })
        .collect()
}

/// The preset's static suspension deflection per axle (m): body load / stiffness.
fn suspension_deflections_m(preset: &VehicleDynamics, axles: &[AxleParams]) -> Vec<f64> {
    preset
        .axles
        .iter()
        .zip(axles)
        .map(|(contact, a)| {
            (contact.static_load_n - a.mass_kg * GRAVITY_M_S2) / a.suspension_stiffness_n_m
        })
        .collect()
}

/// Least-squares line `a + b (x - x0)` through `(x, y)`; with `start` given, only the
/// slope is fitted (the line must pass through `(x0, start)`).
fn fit_line(x0_m: f64, start: Option<f64>, x_m: &[f64], y: &[f64]) -> (f64, f64) {
    let n = x_m.len() as f64;
    let dx: Vec<f64> = x_m.iter().map(|x| x - x0_m).collect();
    match start {
        Some(a) => {
            let rise: Vec<f64> = y.iter().map(|v| v - a).collect();
            (a, dot(&dx, &rise) / dot(&dx, &dx))
        }
        None => {
            let (mx, my) = (dx.iter().sum::<f64>() / n, y.iter().sum::<f64>() / n);
            let sxy: f64 = dx.iter().zip(y).map(|(x, v)| (x - mx) * (v - my)).sum();
            let sxx: f64 = dx.iter().map(|x| (x - mx).powi(2)).sum();
            let b = sxy / sxx;
            (my - b * mx, b)
        }
    }
}

/// The smallest suspension deflection accepted, as a fraction of the preset's: below
/// it the draw asks one body to carry axle loads a rigid body on linear springs cannot
/// match without near-rigid or near-slack springs.
const MIN_DEFLECTION_FRACTION: f64 = 0.5;

/// New axles carrying `loads_n` whose body points lie at `deflection_m` (static, downward):
/// tyres unchanged, each suspension sized to carry its body load over what is left.
/// Dampers keep the preset's values (hardware; see the module documentation).
fn scaled_axles(
    preset: &[AxleParams],
    wanted_suspension_m: &[f64],
    deflection_m: &[f64],
    loads_n: &[f64],
    field: &str,
) -> Result<Vec<AxleParams>> {
    let body_n = body_loads(loads_n, preset, field)?;
    (0..preset.len())
        .map(|j| {
            let a = &preset[j];
            let suspension_m = deflection_m[j] - loads_n[j] / a.tyre_stiffness_n_m;
            if suspension_m.is_nan()
                || suspension_m < MIN_DEFLECTION_FRACTION * wanted_suspension_m[j]
            {
                return Err(Error::invalid(
                    format!("{field}.{j}"),
                    num(loads_n[j] / loads_n.iter().sum::<f64>()),
                    format!(
                        "differs too much from the other axles of its body: its suspension \
                         would deflect {} m statically against {} m in the preset",
                        num(suspension_m),
                        num(wanted_suspension_m[j])
                    ),
                ));
            }
            let ks = body_n[j] / suspension_m;
            Ok(AxleParams {
                suspension_stiffness_n_m: ks,
                ..*a
            })
        })
        .collect()
}

/// A body carrying `weight_n` with its CG at `cg_m`, its inertia scaled from `preset` by
/// mass and by `length_ratio` squared.
fn scaled_body(preset: &BodyParams, weight_n: f64, cg_m: f64, length_ratio: f64) -> BodyParams {
    let mass_kg = weight_n / GRAVITY_M_S2;
    BodyParams {
        mass_kg,
        pitch_inertia_kg_m2: preset.pitch_inertia_kg_m2 * mass_kg / preset.mass_kg
            * length_ratio.powi(2),
        cg_behind_front_m: cg_m,
    }
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    DVector::from_column_slice(a).dot(&DVector::from_column_slice(b))
}

/// Wanted static deflection of the body point above each axle: the preset's suspension
/// deflection plus the new tyre compression.
fn wanted_deflections_m(suspension_m: &[f64], axles: &[AxleParams], loads_n: &[f64]) -> Vec<f64> {
    (0..axles.len())
        .map(|j| suspension_m[j] + loads_n[j] / axles[j].tyre_stiffness_n_m)
        .collect()
}

fn scale_rigid(
    p: &RigidTruckParams,
    offsets_m: &[f64],
    loads_n: &[f64],
    field: &str,
) -> Result<RigidTruckParams> {
    let suspension_m = suspension_deflections_m(&p.build("preset")?, &p.axles);
    let wanted = wanted_deflections_m(&suspension_m, &p.axles, loads_n);
    let (a, b) = fit_line(0.0, None, offsets_m, &wanted);
    let deflection_m: Vec<f64> = offsets_m.iter().map(|x| a + b * x).collect();
    let axles = scaled_axles(&p.axles, &suspension_m, &deflection_m, loads_n, field)?;
    let body_n = body_loads(loads_n, &p.axles, field)?;
    let weight_n: f64 = body_n.iter().sum();
    let cg_m = dot(&body_n, offsets_m) / weight_n;
    let last = offsets_m.len() - 1;
    let length_ratio = offsets_m[last] / p.axle_offsets_m[last];
    Ok(RigidTruckParams {
        body: scaled_body(&p.body, weight_n, cg_m, length_ratio),
        axle_offsets_m: offsets_m.to_vec(),
        axles,
    })
}

fn scale_articulated(
    p: &ArticulatedParams,
    offsets_m: &[f64],
    loads_n: &[f64],
    field: &str,
) -> Result<ArticulatedParams> {
    let preset = p.build("preset")?;
    let suspension_m = suspension_deflections_m(&preset, &p.axles);
    let wanted = wanted_deflections_m(&suspension_m, &p.axles, loads_n);
    let n_tc = p.tractor_axle_count;
    let x_preset = &p.axle_offsets_m;
    // The fifth wheel keeps its place as a fraction of the tractor wheelbase.
    let tractor_ratio = offsets_m[n_tc - 1] / x_preset[n_tc - 1];
    let kingpin_m = p.fifth_wheel_behind_front_m * tractor_ratio;
    let (a, b) = fit_line(0.0, None, &offsets_m[..n_tc], &wanted[..n_tc]);
    let kingpin_deflection_m = a + b * kingpin_m;
    let (_, b_tr) = fit_line(
        kingpin_m,
        Some(kingpin_deflection_m),
        &offsets_m[n_tc..],
        &wanted[n_tc..],
    );
    let deflection_m: Vec<f64> = offsets_m
        .iter()
        .enumerate()
        .map(|(j, &x)| match p.body_of_axle(j) {
            0 => a + b * x,
            _ => kingpin_deflection_m + b_tr * (x - kingpin_m),
        })
        .collect();
    let axles = scaled_axles(&p.axles, &suspension_m, &deflection_m, loads_n, field)?;

    let body_n = body_loads(loads_n, &p.axles, field)?;
    let preset_loads_n: Vec<f64> = preset.axles.iter().map(|a| a.static_load_n).collect();
    let preset_body_n = body_loads(&preset_loads_n, &p.axles, field)?;
    let tractor_axles_n: f64 = body_n[..n_tc].iter().sum();
    let preset_tractor_axles_n: f64 = preset_body_n[..n_tc].iter().sum();
    let tractor_n = p.tractor.mass_kg * GRAVITY_M_S2 * tractor_axles_n / preset_tractor_axles_n;
    let kingpin_n = tractor_axles_n - tractor_n;
    // Tractor: axle reactions up, kingpin reaction down; trailer: kingpin and its axles up.
    let tractor_cg_m =
        (dot(&body_n[..n_tc], &offsets_m[..n_tc]) - kingpin_n * kingpin_m) / tractor_n;
    let trailer_n = kingpin_n + body_n[n_tc..].iter().sum::<f64>();
    let trailer_cg_m =
        (kingpin_n * kingpin_m + dot(&body_n[n_tc..], &offsets_m[n_tc..])) / trailer_n;
    let last = offsets_m.len() - 1;
    let trailer_ratio =
        (offsets_m[last] - kingpin_m) / (x_preset[last] - p.fifth_wheel_behind_front_m);
    Ok(ArticulatedParams {
        tractor: scaled_body(&p.tractor, tractor_n, tractor_cg_m, tractor_ratio),
        trailer: scaled_body(&p.trailer, trailer_n, trailer_cg_m, trailer_ratio),
        fifth_wheel_behind_front_m: kingpin_m,
        tractor_axle_count: n_tc,
        axle_offsets_m: offsets_m.to_vec(),
        axles,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn spacing_and_shares(v: &VehicleDynamics) -> (Vec<f64>, Vec<f64>) {
        let spacing = v
            .axles
            .windows(2)
            .map(|w| w[1].offset_m - w[0].offset_m)
            .collect();
        let shares = v
            .axles
            .iter()
            .map(|a| a.static_load_n / v.gross_weight_n())
            .collect();
        (spacing, shares)
    }

    fn preset_model(class: &str) -> VehicleDynamics {
        match ClassPreset::of(class, "c").unwrap() {
            ClassPreset::Rigid(_, p) => p.build(class).unwrap(),
            ClassPreset::Articulated(_, p) => p.build(class).unwrap(),
        }
    }

    #[test]
    fn scaling_a_preset_to_its_own_loads_gives_the_preset_back() {
        // The scaling is the identity on the preset's own draw: every spring, damper,
        // mass and CG is recovered to rounding (1e-9 relative; the chain has a few
        // solves with condition numbers ~1e3).
        for class in TRAFFIC_CLASSES {
            let preset = preset_model(class);
            let (spacing, shares) = spacing_and_shares(&preset);
            let v = vehicle_for_traffic(class, preset.gross_weight_n(), &spacing, &shares, "t")
                .unwrap();
            for (a, b) in [
                (&v.mass, &preset.mass),
                (&v.stiffness, &preset.stiffness),
                (&v.damping, &preset.damping),
            ] {
                assert!((a - b).amax() <= 1e-9 * b.amax(), "{class}\n{a}\n{b}");
            }
            for (a, b) in v.axles.iter().zip(&preset.axles) {
                let kt = (a.tyre_stiffness_n_m - b.tyre_stiffness_n_m).abs();
                assert!(kt <= 1e-9 * b.tyre_stiffness_n_m, "{class}");
            }
        }
    }
}
