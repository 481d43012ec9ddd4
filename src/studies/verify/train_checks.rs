//! Trains on a simply supported span: an HSLM train of moving forces against the
//! superposition of Fryba's closed form axle by axle; the resonance speed `v = n0 D`
//! and its peak acceleration against the residual-vibration (LIR) and DER envelopes;
//! the vehicle models' static loads against the lever rule and the Manchester vehicle's
//! modes against hand estimates.

use crate::error::Result;
use crate::physics::bridge::{BridgeModel, ModelSpec};
use crate::physics::solver::vehicle_natural_frequencies_hz;
use crate::physics::vehicle::{car_preset, train_preset, Representation, HSLM_A};
use crate::studies::analytic::resonance::{
    der_acceleration_m_s2, lir_acceleration_m_s2, ResonanceSpan,
};
use crate::studies::analytic::{ModalDamping, MovingForceSolution, MovingLoadTrain};
use crate::studies::hslm::{axle_loads, Deck, StudyBridge};

use super::CheckRow;

/// The study's short span (n0 = 5 Hz, 1.35 % damping), 20 Hermite elements.
fn short_span_deck(damping: f64) -> Result<(StudyBridge, Deck)> {
    let bridge = StudyBridge::short_span();
    let model = BridgeModel::build(
        &bridge.beam,
        &ModelSpec::FiniteElement { elements: 20 },
        damping,
    )?;
    Ok((bridge, Deck::new(model, 45.0, 1e-3)?))
}

/// HSLM-A1 as moving forces against Fryba's series summed over its 50 axles.
pub fn train_moving_forces() -> Result<Vec<CheckRow>> {
    let bridge = StudyBridge::short_span();
    let train = train_preset("hslm_a1")
        .expect("preset")
        .build(Representation::MovingForces)?;
    let loads = MovingLoadTrain {
        loads: train
            .axles
            .iter()
            .map(|a| (a.offset_m, a.static_load_n))
            .collect(),
    };
    let ab = crate::studies::analytic::SimplySupportedBeam::new(
        bridge.length_m(),
        bridge.beam.flexural_rigidity_n_m2,
        bridge.beam.mass_per_length_kg_m,
    )?;
    let mut rows = Vec::new();
    for speed_km_h in [200.0, 300.0] {
        let v: f64 = speed_km_h / 3.6;
        let case = super::MovingForceCase {
            beam: bridge.beam.clone(),
            spec: ModelSpec::FiniteElement { elements: 20 },
            damping_ratio: 0.0,
            force_n: 0.0,
            speed_m_s: v,
            dt_s: 5e-4,
            free_time_s: 0.5,
        };
        let (times, numerical) = super::train_history(&case, &train)?;
        let reference = MovingForceSolution::for_train(ab, &loads, v, ModalDamping::None, 100)?;
        let mid = 0.5 * bridge.length_m();
        let exact: Vec<f64> = times
            .iter()
            .map(|&t| reference.deflection_m(mid, t))
            .collect();
        let (peak_ref, peak_num, rms) = super::history_errors(&numerical, &exact);
        // Undamped, 5.6-8.6 s of passage: Newmark's period error (w1 dt)^2 / 12 = 2e-5
        // accumulates to 0.02-0.03 rad of phase on mode 1 over 28-43 cycles, which the
        // free vibration left by 50 loads carries (a fraction of the peak, more near
        // resonance); 20 elements leave < 1e-4 on the static part. Peak 2e-3, history RMS
        // 3e-3 of the peak (measured: 4-6e-4 and 1e-3).
        let what = format!("HSLM-A1 at {speed_km_h} km/h");
        rows.push(CheckRow::relative(
            "train",
            format!("moving forces, midspan peak, {what}"),
            "Fryba x 50 axles, 100 modes (m)",
            peak_ref,
            peak_num,
            2e-3,
        ));
        rows.push(CheckRow::with_error(
            "train",
            format!("moving forces, history rms, {what}"),
            "Fryba x 50 axles (rms / peak)",
            0.0,
            rms,
            rms / peak_ref,
            3e-3,
        ));
    }
    Ok(rows)
}

/// The resonance of HSLM-A1 (D = 18 m) on the short span: where the peak acceleration
/// falls against `n0 D`, and its height against LIR and DER.
pub fn train_resonance() -> Result<Vec<CheckRow>> {
    let zeta = StudyBridge::short_span().damping_ratio();
    let (bridge, deck) = short_span_deck(zeta)?;
    let train = train_preset("hslm_a1")
        .expect("preset")
        .build(Representation::MovingForces)?;
    let f1 = deck.frequencies_hz[0];
    let coach_m = HSLM_A[0].1;
    let v_res = f1 * coach_m;
    // 1 km/h steps over +-4 % of the resonance.
    let mut best = (0.0, 0.0);
    let lo = (3.6 * v_res * 0.96).floor();
    for i in 0..=((3.6 * v_res * 0.08).ceil() as usize) {
        let v = (lo + i as f64) / 3.6;
        let a = deck.passage(&train, v)?.acceleration_m_s2;
        if a > best.1 {
            best = (v, a);
        }
    }
    let span = ResonanceSpan {
        length_m: bridge.length_m(),
        mass_per_length_kg_m: bridge.beam.mass_per_length_kg_m,
        f1_hz: f1,
        zeta,
    };
    let loads = axle_loads(&train);
    let lir = lir_acceleration_m_s2(&span, &loads, best.0);
    let der = der_acceleration_m_s2(&span, &loads, best.0);
    Ok(vec![
        // The peak of a sweep in 1 km/h steps lies within half a step (0.15 %) of the
        // true one; damping of 1.35 % moves a resonance by zeta^2 / 2 (1e-4): 0.5 %.
        CheckRow::relative(
            "train",
            "resonance speed of HSLM-A1 (D = 18 m), 1 km/h sweep".into(),
            "v = n0 D (m/s)",
            v_res,
            best.0,
            5e-3,
        ),
        // LIR and DER keep mode 1 and the residual vibration between loads; the
        // simulation adds modes 2-3 (mode 2 has a node at midspan) and the forced
        // response while loads are on the span, each a fraction of a percent at a
        // resonance of mode 1: 2 % for LIR; DER's envelope weights the train signature
        // differently (its own approximation of the build-up): 5 %.
        CheckRow::relative(
            "train",
            "peak acceleration at resonance, HSLM-A1".into(),
            "LIR, mode 1 (m/s^2)",
            lir,
            best.1,
            2e-2,
        ),
        CheckRow::relative(
            "train",
            "peak acceleration at resonance, HSLM-A1".into(),
            "DER, mode 1 (m/s^2)",
            der,
            best.1,
            5e-2,
        ),
    ])
}

/// Static loads and modes of the railway vehicle models.
pub fn train_vehicles() -> Result<Vec<CheckRow>> {
    let mut rows = Vec::new();
    for (i, &(_, _, _, p_kn)) in HSLM_A.iter().enumerate() {
        let train = train_preset(&format!("hslm_a{}", i + 1))
            .expect("preset")
            .build(Representation::Vehicles)?;
        let worst = train
            .axles
            .iter()
            .map(|a| (a.static_load_n / (p_kn * 1e3) - 1.0).abs())
            .fold(0.0, f64::max);
        // Statically determinate: exact to round-off.
        rows.push(CheckRow::with_error(
            "train",
            format!("HSLM-A{} vehicle model, every axle's static load", i + 1),
            "P of Table E.4 (largest relative error)",
            p_kn * 1e3,
            p_kn * 1e3 * (1.0 + worst),
            worst,
            1e-9,
        ));
    }
    let car = car_preset("manchester_benchmark").expect("preset");
    let dynamics = train_preset("manchester_benchmark")
        .expect("preset")
        .build(Representation::Vehicles)?;
    let hz = vehicle_natural_frequencies_hz(&dynamics)?;
    let contact = dynamics.axles[0].tyre_stiffness_n_m;
    let per_bogie = 1.0
        / (1.0 / car.secondary.stiffness_n_m
            + 1.0 / (2.0 * car.primary.stiffness_n_m)
            + 1.0 / (2.0 * contact));
    let two_pi = 2.0 * std::f64::consts::PI;
    let half_spacing = 0.5 * car.bogie_spacing_m;
    for (what, estimate) in [
        (
            "body bounce",
            (2.0 * per_bogie / car.body_mass_kg).sqrt() / two_pi,
        ),
        (
            "body pitch",
            (2.0 * per_bogie * half_spacing * half_spacing / car.body_pitch_inertia_kg_m2).sqrt()
                / two_pi,
        ),
    ] {
        let nearest = hz
            .iter()
            .copied()
            .min_by(|a, b| (a - estimate).abs().total_cmp(&(b - estimate).abs()))
            .unwrap_or(f64::NAN);
        // The estimate holds the bogies still; their participation moves the coupled
        // mode by a few percent: 5 %.
        rows.push(CheckRow::relative(
            "train",
            format!("Manchester benchmark vehicle, {what}"),
            "series springs written out by hand (Hz)",
            estimate,
            nearest,
            5e-2,
        ));
    }
    Ok(rows)
}
