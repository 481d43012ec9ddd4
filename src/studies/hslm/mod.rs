//! `bridgetwin study hslm`: the EN 1991-2 6.4.6 dynamic analysis with the ten HSLM-A
//! trains, on a short span at risk of resonance and on the paper's bridge.
//!
//! For every train and speed (from 100 km/h to 1.2 x a 350 km/h line speed in 5 km/h
//! steps) a Hermite FE model of the span carries the train, as moving forces and as
//! vehicle models (articulated rakes on Eurostar bogies, every axle at P); the peaks are
//! the deck acceleration with the modes up to `max(30 Hz, 1.5 n0, n3)` (the FE
//! acceleration projected on them), the midspan deflection and the midspan moment, whose
//! ratio to the static moment of the same train on the same mesh is `1 + phi'_dyn`. The
//! envelope over the trains is set against the acceleration limits and the resonance
//! speeds `v = n0 D / i`, the dynamic factors against Phi2 / Phi3, the simulated peaks
//! against the closed-form DER and LIR envelopes of mode 1, and the vehicle models against
//! the moving forces (what the interaction takes off at resonance).

mod eurocode;
mod passage;
mod report;

use std::path::Path;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Mutex;
use std::time::Instant;

use crate::error::Result;
use crate::physics::bridge::{BeamProperties, BridgeModel, ModelSpec};
use crate::physics::vehicle::{train_preset, Representation, VehicleDynamics, HSLM_A};
use crate::studies::analytic::resonance::{
    der_acceleration_m_s2, lir_acceleration_m_s2, ResonanceSpan,
};

pub use eurocode::{
    cutoff_frequency_hz, frequency_band_hz, phi2, phi3, DeckType, LIMIT_BALLASTED_M_S2,
    LIMIT_DIRECT_FASTENING_M_S2,
};
pub use passage::{Deck, Peaks};

/// Line speed of the study (km/h): the checks run to 1.2 times it.
pub const LINE_SPEED_KM_H: f64 = 350.0;

/// Hermite elements per span of the study's models (0.75 m on the short span).
const ELEMENTS: usize = 20;

/// Time step (s): 22 steps per period of a 45 Hz third mode.
const DT_S: f64 = 1e-3;

/// A bridge of the study.
#[derive(Debug, Clone)]
pub struct StudyBridge {
    pub name: &'static str,
    pub beam: BeamProperties,
    pub deck: DeckType,
}

impl StudyBridge {
    /// A 15 m simply supported prestressed-concrete span of 15 t/m with n0 = 5.0 Hz:
    /// below Figure 6.10's lower limit (80 / L = 5.3 Hz), so a dynamic analysis is needed,
    /// and its second resonances `n0 D / 2` (163-243 km/h) lie inside the speed range.
    pub fn short_span() -> Self {
        let (length, mass) = (15.0, 15_000.0);
        // n0 = (pi / (2 L^2)) sqrt(EI / m)  =>  EI = m (2 L^2 n0 / pi)^2.
        let ei = mass * (2.0 * length * length * 5.0 / std::f64::consts::PI).powi(2);
        StudyBridge {
            name: "short_15m",
            beam: BeamProperties::simply_supported(length, ei, mass),
            deck: DeckType::PrestressedConcrete,
        }
    }

    /// The paper's 30 m bridge (f1 = 3.78 Hz) as a reinforced-concrete railway deck.
    pub fn paper() -> Self {
        StudyBridge {
            name: "paper_30m",
            beam: BeamProperties::paper_default(),
            deck: DeckType::ReinforcedConcrete,
        }
    }

    pub fn length_m(&self) -> f64 {
        self.beam.length_m()
    }

    pub fn damping_ratio(&self) -> f64 {
        self.deck.damping_ratio(self.length_m())
    }
}

/// One (bridge, train, representation, speed) passage.
#[derive(Debug, Clone, Copy)]
pub struct Row {
    pub bridge: usize,
    /// HSLM-A number, 1-10.
    pub train: usize,
    pub vehicles: bool,
    pub speed_km_h: f64,
    pub peaks: Peaks,
    /// The static midspan moment peak of the train (N m).
    pub static_moment_n_m: f64,
    /// Mode-1 closed forms at this speed (m/s^2).
    pub der_m_s2: f64,
    pub lir_m_s2: f64,
}

impl Row {
    /// `1 + phi'_dyn`: the dynamic midspan moment over the static.
    pub fn moment_factor(&self) -> f64 {
        self.peaks.moment_n_m / self.static_moment_n_m
    }
}

/// Everything the report needs.
pub struct HslmReport {
    pub bridges: Vec<StudyBridge>,
    /// Per bridge: the model's first frequencies (Hz), the kept modes and the cut-off.
    pub frequencies_hz: Vec<Vec<f64>>,
    pub kept_modes: Vec<usize>,
    pub cutoff_hz: Vec<f64>,
    pub rows: Vec<Row>,
    pub speeds_km_h: Vec<f64>,
    pub trains: Vec<usize>,
    /// Wall time of the moving-force grid and of the vehicle-model grid (s).
    pub moving_force_s: f64,
    pub vehicles_s: f64,
    pub quick: bool,
}

/// The grid: every train at every speed; `quick` keeps three trains at every fifth speed.
fn grid(quick: bool) -> (Vec<usize>, Vec<f64>) {
    let top = 1.2 * LINE_SPEED_KM_H;
    let step = if quick { 25.0 } else { 5.0 };
    let speeds = (0..)
        .map(|i| 100.0 + step * i as f64)
        .take_while(|&v| v <= top + 1e-9)
        .collect();
    let trains = if quick {
        vec![1, 4, 9]
    } else {
        (1..=10).collect()
    };
    (trains, speeds)
}

/// Runs the study into `out`.
pub fn run(out: &Path, quick: bool, progress: &mut dyn FnMut(&str)) -> Result<HslmReport> {
    let bridges = vec![StudyBridge::short_span(), StudyBridge::paper()];
    let (trains, speeds) = grid(quick);
    let mut decks = Vec::new();
    for b in &bridges {
        let spec = ModelSpec::FiniteElement { elements: ELEMENTS };
        let model = BridgeModel::build(&b.beam, &spec, b.damping_ratio())?;
        let f = model.modal_summary(3).0;
        decks.push(Deck::new(model, cutoff_frequency_hz(f[0], f[2]), DT_S)?);
    }
    let mut rows = Vec::new();
    let mut seconds = [0.0; 2];
    for (slot, vehicles) in [(0, false), (1, true)] {
        let t0 = Instant::now();
        // The quick grid runs the vehicle models of the first train only.
        let modelled = match (quick, vehicles) {
            (true, true) => &trains[..1],
            _ => &trains[..],
        };
        let cases: Vec<(usize, usize)> = (0..bridges.len())
            .flat_map(|b| modelled.iter().map(move |&t| (b, t)))
            .collect();
        progress(&format!(
            "{} passages with {}",
            cases.len() * speeds.len(),
            if vehicles {
                "vehicle models"
            } else {
                "moving forces"
            }
        ));
        rows.extend(run_cases(&cases, &decks, &bridges, &speeds, vehicles)?);
        seconds[slot] = t0.elapsed().as_secs_f64();
        progress(&format!("  done in {:.1} s", seconds[slot]));
    }
    rows.sort_by(|a, b| {
        (a.bridge, a.train, a.vehicles)
            .cmp(&(b.bridge, b.train, b.vehicles))
            .then(a.speed_km_h.total_cmp(&b.speed_km_h))
    });
    let report = HslmReport {
        frequencies_hz: decks.iter().map(|d| d.frequencies_hz.clone()).collect(),
        kept_modes: decks.iter().map(|d| d.kept_modes).collect(),
        cutoff_hz: decks.iter().map(|d| d.cutoff_hz).collect(),
        bridges,
        rows,
        speeds_km_h: speeds,
        trains,
        moving_force_s: seconds[0],
        vehicles_s: seconds[1],
        quick,
    };
    report::write_outputs(out, &report)?;
    Ok(report)
}

/// The (bridge, train) cases at every speed, on every core.
fn run_cases(
    cases: &[(usize, usize)],
    decks: &[Deck],
    bridges: &[StudyBridge],
    speeds: &[f64],
    vehicles: bool,
) -> Result<Vec<Row>> {
    let next = AtomicUsize::new(0);
    let done: Mutex<Vec<Result<Vec<Row>>>> = Mutex::new(Vec::new());
    let workers = std::thread::available_parallelism().map_or(1, |n| n.get());
    std::thread::scope(|scope| {
        for _ in 0..workers.min(cases.len()) {
            scope.spawn(|| {
                while let Some(&(b, t)) = cases.get(next.fetch_add(1, Ordering::Relaxed)) {
                    let result = run_case(&decks[b], &bridges[b], b, t, speeds, vehicles);
                    done.lock().unwrap_or_else(|e| e.into_inner()).push(result);
                }
            });
        }
    });
    let mut rows = Vec::new();
    for result in done.into_inner().unwrap_or_else(|e| e.into_inner()) {
        rows.extend(result?);
    }
    Ok(rows)
}

/// One train on one bridge at every speed.
fn run_case(
    deck: &Deck,
    bridge: &StudyBridge,
    b: usize,
    train: usize,
    speeds: &[f64],
    vehicles: bool,
) -> Result<Vec<Row>> {
    let preset = train_preset(&format!("hslm_a{train}")).expect("HSLM presets exist");
    let representation = match vehicles {
        true => Representation::Vehicles,
        false => Representation::MovingForces,
    };
    let dynamics = preset.build(representation)?;
    let static_moment_n_m = static_midspan_moment_n_m(&bridge.beam, &dynamics)?;
    let loads = axle_loads(&dynamics);
    let span = ResonanceSpan {
        length_m: bridge.length_m(),
        mass_per_length_kg_m: bridge.beam.mass_per_length_kg_m,
        f1_hz: deck.frequencies_hz[0],
        zeta: bridge.damping_ratio(),
    };
    speeds
        .iter()
        .map(|&speed_km_h| {
            let v = speed_km_h / 3.6;
            Ok(Row {
                bridge: b,
                train,
                vehicles,
                speed_km_h,
                peaks: deck.passage(&dynamics, v)?,
                static_moment_n_m,
                der_m_s2: der_acceleration_m_s2(&span, &loads, v),
                lir_m_s2: lir_acceleration_m_s2(&span, &loads, v),
            })
        })
        .collect()
}

/// `(x behind the first axle, load)` of every axle.
pub fn axle_loads(train: &VehicleDynamics) -> Vec<(f64, f64)> {
    train
        .axles
        .iter()
        .map(|a| (a.offset_m, a.static_load_n))
        .collect()
}

/// The largest static midspan moment of the train's axle loads on the study's mesh.
fn static_midspan_moment_n_m(beam: &BeamProperties, train: &VehicleDynamics) -> Result<f64> {
    let mid = 0.5 * beam.length_m();
    crate::studies::continuous::static_peaks(beam, train, (mid, mid), ELEMENTS).map(|p| p.0)
}

/// The HSLM-A parameters (N, D, d, P) of train `number`.
pub fn hslm_parameters(number: usize) -> (usize, f64, f64, f64) {
    HSLM_A[number - 1]
}
