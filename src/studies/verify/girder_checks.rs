//! Continuous girders against the exact continuous-beam solution (`analytic::
//! continuous_beam`) and the three-moment equation: frequencies of every model, the
//! influence line of the pier moment, and a force crossing two spans.

use std::f64::consts::PI;

use super::harness::{moving_force_history_at, MovingForceCase};
use super::CheckRow;
use crate::error::Result;
use crate::physics::bridge::{
    BeamProperties, BridgeModel, Girder, LumpedStiffness, ModelSpec, PointQuantity, Support,
};
use crate::studies::analytic::{Condition, ContinuousBeam};

const EI_N_M2: f64 = 5.629e10;
const MASS_KG_M: f64 = 12_000.0;

/// A girder of the paper's section.
pub(super) fn girder(spans: &[f64], supports: &[Support], overhangs_m: [f64; 2]) -> BeamProperties {
    BeamProperties {
        girder: Girder {
            spans_m: spans.to_vec(),
            supports: supports.to_vec(),
            overhang_left_m: overhangs_m[0],
            overhang_right_m: overhangs_m[1],
        },
        ..BeamProperties::paper_default()
    }
}

/// The same beam for the analytic module: pieces and their conditions.
fn exact(beam: &BeamProperties) -> ContinuousBeam {
    let g = &beam.girder;
    let condition = |s: &Support| match *s {
        Support::Pinned | Support::Roller => Condition::Pinned,
        Support::Fixed => Condition::Clamped,
        Support::Elastic {
            vertical_n_m,
            rotational_n_m_rad,
        } => Condition::Springs {
            vertical_n_m,
            rotational_n_m_rad,
        },
    };
    let mut pieces = Vec::new();
    let mut conditions = Vec::new();
    if g.overhang_left_m > 0.0 {
        pieces.push(g.overhang_left_m);
        conditions.push(Condition::Free);
    }
    conditions.extend(g.supports.iter().map(condition));
    pieces.extend(&g.spans_m);
    if g.overhang_right_m > 0.0 {
        pieces.push(g.overhang_right_m);
        conditions.push(Condition::Free);
    }
    ContinuousBeam {
        pieces_m: pieces,
        conditions,
        flexural_rigidity_n_m2: beam.flexural_rigidity_n_m2,
        mass_per_length_kg_m: beam.mass_per_length_kg_m,
    }
}

/// The girders of the frequency rows.
fn cases() -> Vec<(&'static str, BeamProperties)> {
    use Support::*;
    let bearing = Elastic {
        vertical_n_m: 5e8,
        rotational_n_m_rad: 0.0,
    };
    vec![
        (
            "two spans 30+30",
            girder(&[30.0, 30.0], &[Pinned, Roller, Roller], [0.0; 2]),
        ),
        (
            "three spans 24+30+24",
            girder(
                &[24.0, 30.0, 24.0],
                &[Pinned, Roller, Roller, Roller],
                [0.0; 2],
            ),
        ),
        (
            "clamped-clamped 30",
            girder(&[30.0], &[Fixed, Fixed], [0.0; 2]),
        ),
        ("cantilever 15", girder(&[], &[Fixed], [0.0, 15.0])),
        (
            "30 on elastic bearings 5e8 N/m",
            girder(&[30.0], &[bearing, bearing], [0.0; 2]),
        ),
        (
            "two spans 25+25, overhangs 5 and 3",
            girder(&[25.0, 25.0], &[Pinned, Roller, Roller], [5.0, 3.0]),
        ),
    ]
}

/// Frequencies of FE, lumped and modal models on continuous girders against the exact
/// frequency determinant.
pub fn girder_frequencies() -> Result<Vec<CheckRow>> {
    let mut rows = Vec::new();
    for (name, beam) in cases() {
        let reference = exact(&beam).modes(3)?;
        let length = beam.length_m();
        // About 40 elements or 20 masses per 30 m, the scale of the default models.
        let elements = (length / 30.0 * 40.0).round() as usize;
        let masses = (length / 30.0 * 20.0).round() as usize;
        let specs = [
            ModelSpec::FiniteElement { elements },
            ModelSpec::LumpedMass {
                nodes: masses,
                stiffness: LumpedStiffness::Auto,
            },
            ModelSpec::Modal {
                modes: 10,
                elements: Some(elements),
            },
        ];
        for spec in specs {
            let model = BridgeModel::build(&beam, &spec, 0.0)?;
            let h = match spec {
                ModelSpec::LumpedMass { nodes, .. } => length / nodes as f64,
                _ => length / elements as f64,
            };
            let g = &beam.girder;
            let end_masses = g.overhang_left_m > 0.0
                || g.overhang_right_m > 0.0
                || g.supports.iter().any(|s| !s.rigid_vertical());
            for (n, mode) in reference.iter().enumerate() {
                let exact_hz = mode.omega_rad_s / (2.0 * PI);
                let beta_h = (mode.omega_rad_s * (MASS_KG_M / EI_N_M2).sqrt()).sqrt() * h;
                // Hermite elements with consistent mass err from above below the Rayleigh
                // quotient bound (beta h)^4 / 720 (beta the mode's wavenumber; the
                // simple span's (n pi h / L)^4 / 720). Lumped masses between rigid
                // supports err from below at about twice that size on a simple span,
                // (beta h)^4 / 1440 x 2 with the unequal spacing of the spans: (beta h)^4 /
                // 240 bounds them. A mass at a free tip or on a spring carries half a
                // spacing of girder at the end of its piece, which shifts the mass
                // distribution by O(h): the error falls only as (beta h)^2 there, and
                // (beta h)^2 / 6 bounds it (measured: a cantilever of 10 masses errs by
                // 0.46 % on f1, 1.6 % on f2). Plus 1e-9 for the eigen-solution's round-off.
                let tolerance = match spec {
                    ModelSpec::LumpedMass { .. } if end_masses => beta_h.powi(2) / 6.0,
                    ModelSpec::LumpedMass { .. } => beta_h.powi(4) / 240.0 + 1e-9,
                    _ => beta_h.powi(4) / 720.0 + 1e-9,
                };
                rows.push(CheckRow::relative(
                    "girder_frequencies",
                    format!("f{} {name} {}", n + 1, spec.label()),
                    "exact determinant (Hz)",
                    exact_hz,
                    model.frequency_hz(n + 1),
                    tolerance,
                ));
            }
        }
    }
    Ok(rows)
}

/// The pier moment of two equal spans under a unit load in span one (Clapeyron, the
/// three-moment equation: `M = -a (L^2 - a^2) / (4 L^2)`), and the load-point deflection
/// `23 P L^3 / (1536 EI)`, on FE and lumped models. With the load at a node the Hermite
/// statics are exact, so FE is held to 1e-9; the lumped model reads the moment through its
/// condensation transform, exact too for loads at its masses.
pub fn girder_statics() -> Result<Vec<CheckRow>> {
    use Support::*;
    let l = 30.0;
    let beam = girder(&[l, l], &[Pinned, Roller, Roller], [0.0; 2]);
    let mut rows = Vec::new();
    for spec in [
        ModelSpec::FiniteElement { elements: 40 },
        ModelSpec::LumpedMass {
            nodes: 39,
            stiffness: LumpedStiffness::Auto,
        },
    ] {
        let model = BridgeModel::build(&beam, &spec, 0.0)?;
        let k = model.stiffness.to_dense();
        let chol = k.cholesky().ok_or_else(|| crate::Error::Factorization {
            what: "girder stiffness".into(),
            reason: "not positive definite".into(),
        })?;
        for a in [7.5, 15.0, 22.5] {
            let load = model.point_load_vector(a, -1.0);
            let u = chol.solve(&load);
            let moment = model.read(l, PointQuantity::Moment, &u);
            rows.push(CheckRow::relative(
                "girder_statics",
                format!("pier moment, unit load at {a} m, {}", spec.label()),
                "three-moment equation (N m)",
                -a * (l * l - a * a) / (4.0 * l * l),
                moment,
                1e-9,
            ));
            if a == 15.0 {
                rows.push(CheckRow::relative(
                    "girder_statics",
                    format!("deflection under a unit load at 15 m, {}", spec.label()),
                    "23 P L^3 / (1536 EI) (m)",
                    23.0 * l.powi(3) / (1536.0 * EI_N_M2),
                    -model.read(a, PointQuantity::Deflection, &u),
                    1e-9,
                ));
            }
        }
    }
    Ok(rows)
}

/// A constant force crossing two equal spans: FE (Newmark, dt = 1 ms) against the series
/// of the first 20 exact continuous-beam modes, at midspan of each span.
pub fn girder_moving_force() -> Result<Vec<CheckRow>> {
    use Support::*;
    let beam = girder(&[30.0, 30.0], &[Pinned, Roller, Roller], [0.0; 2]);
    let continuous = exact(&beam);
    let modes = continuous.modes(20)?;
    let force_n = 200_000.0;
    let mut rows = Vec::new();
    for speed in [15.0, 30.0] {
        let case = MovingForceCase {
            beam: beam.clone(),
            spec: ModelSpec::FiniteElement { elements: 80 },
            damping_ratio: 0.0,
            force_n,
            speed_m_s: speed,
            dt_s: 1e-3,
            free_time_s: 0.5,
        };
        for probe in [15.0, 45.0] {
            let (times, numerical) = moving_force_history_at(&case, probe)?;
            let zeta = vec![0.0; modes.len()];
            let reference =
                continuous.moving_force_deflection(&modes, &zeta, force_n, speed, probe, &times)?;
            let peak = reference.iter().fold(0.0f64, |a, &b| a.max(b.abs()));
            let peak_num = numerical.iter().fold(0.0f64, |a, &b| a.max(b.abs()));
            let rms = (numerical
                .iter()
                .zip(&reference)
                .map(|(a, b)| (a - b).powi(2))
                .sum::<f64>()
                / times.len() as f64)
                .sqrt();
            // As the simple span's moving-force rows: the time step's phase error on mode
            // 1 ((w dt)^2 / 12 per radian) and the force's jumps between time steps leave
            // < 1e-3 of the peak; 20 modes truncate the static part by < 1e-4 (terms
            // fall as 1 / n^4). Measured: 5e-4 at most on the peaks and the histories.
            let what = format!("x={probe} v={speed}");
            rows.push(CheckRow::relative(
                "girder_moving_force",
                format!("peak {what}"),
                "exact modes, 20 (m)",
                peak,
                peak_num,
                1e-3,
            ));
            rows.push(CheckRow::with_error(
                "girder_moving_force",
                format!("history rms {what}"),
                "exact modes, 20 (rms / peak)",
                0.0,
                rms,
                rms / peak,
                1e-3,
            ));
        }
    }
    Ok(rows)
}
