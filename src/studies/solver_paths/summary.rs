//! `summary.md` of the solver-paths study: the reference and its check, the error tables,
//! what the numbers say, and the recommended default path and size.

use std::fmt::Write as _;

use super::metrics::PathErrors;
use super::recommend::{recommended, smallest_adequate_size, Candidate, MOMENT_TARGET};
use super::{SolverPath, SolverPathsReport, REFERENCE_TOLERANCE};
use crate::studies::dlc::DlcSetup;

/// The whole summary.
pub fn markdown(r: &SolverPathsReport) -> String {
    let mut md = String::from("# Solver paths against a converged reference\n\n");
    let _ = writeln!(
        md,
        "The paper's case: {} m bridge, EI {:.4e} N m^2, {} kg/m, Rayleigh {} % on modes 1 \
         and 2; the `two_axle_truck` half car at {} m/s from {} m before the bridge until {} s \
         after the rear axle leaves; smooth road and ISO 8608 class A (realisation 0 of the \
         DLC study's stream, seed {}); bilateral contact (`solver.contact = \"full\"`), \
         `CoupledSolver` (bridge factorized once, low-rank contact coupling), dt = {} ms.\n",
        r.case.beam.length_m(),
        r.case.beam.flexural_rigidity_n_m2,
        r.case.beam.mass_per_length_kg_m,
        100.0 * r.case.damping_ratio,
        r.case.speed_m_s,
        r.case.approach_m,
        r.case.free_time_s,
        r.case.seed,
        1e3 * r.case.dt_s
    );
    md.push_str(METRICS_TEXT);
    reference_section(&mut md, r);
    for spatial in [false, true] {
        error_tables(&mut md, r, spatial);
    }
    findings(&mut md, r);
    recommendation(&mut md, r);
    md.push_str(
        "\nFiles: `solver_paths.csv` (every point, both error sets), `reference.csv`, \
         `errors_vs_dof.svg`, `spatial_errors_vs_dof.svg`, `histories.svg`.\n",
    );
    md
}

const METRICS_TEXT: &str = "Metrics, each over the whole run on the 1 ms grid: midspan \
deflection max |u - u_ref| / max |u_ref|; midspan acceleration low-passed to 50 Hz \
(zero-phase, raised-cosine 45-55 Hz) as max-norm and RMS relative to the reference's; tyre \
forces max |F - F_ref| / F_static over both axles while on the span; midspan bending moment \
(the strain gauge) max-norm relative to its peak; and the peak-only errors the bench \
reports. `us/step` is this study's loop time per step over the whole run, approach included \
(per-step costs with both axles on the span: `bridgetwin bench`).\n\n";

fn reference_section(md: &mut String, r: &SolverPathsReport) {
    md.push_str("## Reference and its convergence check\n\n");
    md.push_str(
        "Reference: Hermite FE, 400 elements, dt = 0.25 ms. Check: 200 elements at 0.5 ms \
         (half of each). Time-step floor: 400 elements at the paths' dt = 1 ms, against the \
         reference (the time-step error alone).\n\n",
    );
    md.push_str("| road | metric | check change | tolerance | time-step floor | check / floor |\n|---|---|---|---|---|---|\n");
    for (surface, reference) in &r.references {
        for (name, get) in HISTORY_METRICS {
            let (c, f) = (get(&reference.check), get(&reference.time_step_floor));
            let _ = writeln!(
                md,
                "| {surface} | {name} | {c:.2e} | {:.0e} | {f:.2e} | {:.2} |",
                get(&REFERENCE_TOLERANCE),
                c / f
            );
        }
        let _ = writeln!(
            md,
            "| {surface} | **converged** | **{}** | | | |",
            if reference.converged() { "yes" } else { "NO" }
        );
    }
    md.push_str(
        "\nConverged means: every change within its tolerance, and the change at most 0.35 \
         of the floor (Newmark's dt^2 error predicts 0.2 when space is converged). The \
         reference's own error is then about a third of the change, a fifteenth of the floor. \
         The midspan moment is not part of the check: its errors below sit at a few 1e-4 from \
         the smallest size on, the level of the time-step floor's.\n\n",
    );
}

type Metric = (&'static str, fn(&PathErrors) -> f64);

const HISTORY_METRICS: [Metric; 3] = [
    ("deflection", |e| e.deflection),
    ("acceleration RMS", |e| e.acceleration_rms),
    ("force / static", |e| e.force),
];

fn error_tables(md: &mut String, r: &SolverPathsReport, spatial: bool) {
    if spatial {
        md.push_str("## Spatial error alone (against FE 400 elements at the same dt = 1 ms)\n\n");
    } else {
        md.push_str("## Errors against the converged reference\n\n");
    }
    for (surface, reference) in &r.references {
        let _ = writeln!(md, "Road {surface}:\n");
        md.push_str("| path | size | DOF | deflection | accel max | accel RMS | force / static | moment | peak defl | peak force | us/step |\n|---|---|---|---|---|---|---|---|---|---|---|\n");
        for p in r.points.iter().filter(|p| &p.surface == surface) {
            let e = if spatial { &p.spatial } else { &p.errors };
            let _ = writeln!(
                md,
                "| {} | {} {} | {} | {} | {:.1} |",
                p.path.name(),
                p.size,
                p.path.size_name(),
                p.dof,
                metrics_row(e),
                p.us_per_step
            );
        }
        let _ = writeln!(
            md,
            "| time-step floor | | | {} | |\n",
            metrics_row(&reference.time_step_floor)
        );
    }
}

fn metrics_row(e: &PathErrors) -> String {
    [
        e.deflection,
        e.acceleration_max,
        e.acceleration_rms,
        e.force,
        e.moment,
        e.peak_deflection,
        e.peak_force,
    ]
    .iter()
    .map(|v| format!("{v:.2e}"))
    .collect::<Vec<_>>()
    .join(" | ")
}

fn findings(md: &mut String, r: &SolverPathsReport) {
    md.push_str("## What the numbers say\n\n");
    md.push_str(
        "- **The time step dominates at dt = 1 ms.** Smallest size whose spatial error is \
         within the time-step floor (deflection, acceleration RMS, forces; both roads):",
    );
    for path in SolverPath::ALL {
        let size = smallest_adequate_size(r, path, f64::INFINITY);
        let _ = write!(
            md,
            " {} {};",
            path.name(),
            size.map_or("none of the sizes".into(), |s| format!(
                "{s} {}",
                path.size_name()
            ))
        );
    }
    md.push_str(
        " past that, refining changes the error against the reference by nothing that \
         matters: the remaining error is Newmark's at 1 ms (halve dt to cut it by 4).\n",
    );
    modal_forces(md, r);
    moments(md, r);
    element_passing(md, r);
    md.push('\n');
}

/// Whether the modal path's tyre forces suffer from the modes it drops, with numbers.
fn modal_forces(md: &mut String, r: &SolverPathsReport) {
    md.push_str(
        "- **Modal path and contact forces** (truncation error of the tyre forces over \
         static, against FE 400 at the same dt):",
    );
    let mut worst = 0.0f64;
    let mut roads = Vec::new();
    for (surface, reference) in &r.references {
        let mut pts: Vec<_> = r
            .points
            .iter()
            .filter(|p| p.path == SolverPath::Modal && &p.surface == surface)
            .collect();
        pts.sort_by_key(|p| p.size);
        let list: Vec<String> = pts
            .iter()
            .map(|p| format!("{} modes {:.1e}", p.size, p.spatial.force))
            .collect();
        worst = pts.iter().fold(worst, |w, p| w.max(p.spatial.force));
        roads.push(format!(
            "road {surface}: {} (time-step floor {:.1e})",
            list.join(", "),
            reference.time_step_floor.force
        ));
    }
    let _ = write!(md, " {}.", roads.join("; "));
    let first = smallest_force_adequate_modes(r);
    let _ = writeln!(
        md,
        " {} Even the fewest modes err by at most {:.1e} of the static axle load: the tyre \
         is {:.0}x softer than the bridge under a wheel at midspan (48 EI / L^3 against kt \
         of the front axle), so the force sees the bridge as nearly rigid and a truncation \
         error of the deflection under the wheel reaches it reduced by about that factor. \
         The higher modes the wheel point needs are not worth a static correction here.",
        match first {
            Some(m) => format!(
                "From {m} modes on, the dropped modes cost the forces less than the time \
                 step does on both roads: the modal path is not inaccurate for the contact \
                 forces in this case."
            ),
            None => "No modal size tested gets the force error under the time-step floor \
                     on both roads."
                .into(),
        },
        worst,
        ratio_bridge_to_tyre_stiffness(r)
    );
}

/// Smallest modal size whose force error is within the floor on every road.
fn smallest_force_adequate_modes(r: &SolverPathsReport) -> Option<usize> {
    let mut sizes: Vec<usize> = r
        .points
        .iter()
        .filter(|p| p.path == SolverPath::Modal)
        .map(|p| p.size)
        .collect();
    sizes.sort_unstable();
    sizes.into_iter().find(|&m| {
        r.references.iter().all(|(surface, reference)| {
            r.point(SolverPath::Modal, m, surface)
                .is_some_and(|p| p.spatial.force <= reference.time_step_floor.force)
        })
    })
}

fn ratio_bridge_to_tyre_stiffness(r: &SolverPathsReport) -> f64 {
    let b = &r.case.beam;
    let bridge = 48.0 * b.flexural_rigidity_n_m2 / b.length_m().powi(3);
    let tyre = DlcSetup::truck()
        .ok()
        .and_then(|t| t.axles.first().map(|a| a.tyre_stiffness_n_m))
        .unwrap_or(f64::NAN);
    bridge / tyre
}

/// The moment's errors on every path.
fn moments(md: &mut String, r: &SolverPathsReport) {
    md.push_str(
        "- **The midspan moment (strain) is right from the smallest size on, on every path**: \
         the gauge recovers it from the equilibrium of the element it sits in, with the \
         static part a lumped or modal model leaves out added (docs/physics.md section 3.1), \
         where interpolating the element's curvature converged only as 1/n (1.7 % at 20 \
         elements). Road A, max-norm over the peak:",
    );
    let surface = r.references.last().map_or("A".to_string(), |s| s.0.clone());
    for path in SolverPath::ALL {
        let pts: Vec<String> = r
            .points
            .iter()
            .filter(|p| p.path == path && p.surface == surface)
            .map(|p| format!("{} {:.1e}", p.size, p.errors.moment))
            .collect();
        let _ = write!(
            md,
            " {} ({}) {};",
            path.name(),
            path.size_name(),
            pts.join(", ")
        );
    }
    md.push_str(" the other metrics converge as 1/n^2 to 1/n^4 to the time-step floor.\n");
}

/// Where a full-order path's acceleration error rises with refinement: a wheel crossing
/// elements (or mass spacings) of length h at speed v loads the bridge at v / h, which
/// can land on a bridge frequency.
fn element_passing(md: &mut String, r: &SolverPathsReport) {
    let b = &r.case.beam;
    let f1_hz = std::f64::consts::PI / (2.0 * b.length_m() * b.length_m())
        * (b.flexural_rigidity_n_m2 / b.mass_per_length_kg_m).sqrt();
    let mut notes = Vec::new();
    for (surface, _) in &r.references {
        for path in [SolverPath::LumpedLowRank, SolverPath::FeBanded] {
            let mut pts: Vec<_> = r
                .points
                .iter()
                .filter(|p| p.path == path && &p.surface == surface)
                .collect();
            pts.sort_by_key(|p| p.size);
            for w in pts.windows(2) {
                let (a, c) = (w[0].spatial.acceleration_rms, w[1].spatial.acceleration_rms);
                if c > a {
                    let spacings = w[1].size + usize::from(path == SolverPath::LumpedLowRank);
                    let passing_hz = r.case.speed_m_s * spacings as f64 / b.length_m();
                    let k = (passing_hz / f1_hz).sqrt().round().max(1.0);
                    notes.push(format!(
                        "{} {} on road {surface}: v/h = {passing_hz:.1} Hz next to f{k} = \
                         {:.1} Hz, acceleration RMS {c:.1e} against {a:.1e} at {}",
                        path.name(),
                        w[1].size,
                        k * k * f1_hz,
                        w[0].size
                    ));
                }
            }
        }
    }
    if !notes.is_empty() {
        let _ = writeln!(
            md,
            "- **Acceleration errors need not fall monotonically with n**: a wheel crossing \
             elements of length h at speed v loads the bridge at v/h, and near a bridge \
             frequency that excites the mode spuriously: {}. Far below the time-step floor.",
            notes.join("; ")
        );
    }
}

fn recommendation(md: &mut String, r: &SolverPathsReport) {
    md.push_str("## Recommended default\n\n");
    let _ = writeln!(
        md,
        "Targets: spatial error within the dt = 1 ms floor for deflection, acceleration and \
         forces on both roads, and midspan moment within {:.0} %. Each path at the smallest \
         size meeting them, timed on the default scenario (physics and sensor chains, \
         records dropped; median of repetitions):\n",
        100.0 * MOMENT_TARGET
    );
    md.push_str("| path | size | default scenario, ms | real-time factor |\n|---|---|---|---|\n");
    for c in &r.candidates {
        let _ = writeln!(
            md,
            "| {} | {} {} | {:.1} | {:.0}x |",
            c.path.name(),
            c.size,
            c.path.size_name(),
            c.scenario_physics_ms,
            1e3 * c.scenario_simulated_s / c.scenario_physics_ms
        );
    }
    for path in SolverPath::ALL {
        if !r.candidates.iter().any(|c| c.path == path) {
            let _ = writeln!(
                md,
                "| {} | no size tested meets the targets | | |",
                path.name()
            );
        }
    }
    let Some(best) = recommended(&r.candidates) else {
        md.push_str("\nNo path meets the targets at the sizes tested: refine or halve dt.\n");
        return;
    };
    let _ = writeln!(
        md,
        "\n**Recommended: `{}` with {} {} at dt = 1 ms** ({}): the cheapest way to the \
         targets where the cost is paid, the whole run. {}",
        best.path.name(),
        best.size,
        best.path.size_name(),
        scenario_toml(best.path, best.size),
        why(r, best.path)
    );
    scenario_default_line(md, r, best);
}

fn scenario_toml(path: SolverPath, size: usize) -> String {
    match path {
        SolverPath::LumpedLowRank => {
            format!("`model = {{ kind = \"lumped_mass\", nodes = {size} }}`")
        }
        SolverPath::FeBanded => {
            format!("`model = {{ kind = \"finite_element\", elements = {size} }}`")
        }
        SolverPath::Modal => format!("`model = {{ kind = \"modal\", modes = {size} }}`"),
    }
}

/// The reasons behind the pick, with the study's numbers.
fn why(r: &SolverPathsReport, best: SolverPath) -> String {
    let (wins, total) = fe_at_least_as_accurate(r);
    let mut text = format!(
        "Hermite FE is at least as accurate as the lumped model at the same node count in \
         {wins} of {total} comparisons (sizes x roads x deflection, acceleration, force, \
         moment; spatial errors). "
    );
    text.push_str(
        "The solve is not the whole cost: sensor reads and the deflected shape go through \
         the point operators, 4 entries per point for FE but dense over the masses for the \
         lumped model (its reduction maps a point onto every mass) and over the modes for \
         the modal one; the modal path needs many modes for the moment, and the lumped \
         step is O(n^2) (dense K = F^-1) where FE's is O(n) (banded Cholesky).",
    );
    if best != SolverPath::FeBanded {
        text.push_str(" In this run, though, the timings favoured the path above.");
    }
    text
}

/// (FE spatial error <= lumped spatial error, comparisons) at equal size.
fn fe_at_least_as_accurate(r: &SolverPathsReport) -> (usize, usize) {
    let metrics: [fn(&PathErrors) -> f64; 4] = [
        |e| e.deflection,
        |e| e.acceleration_rms,
        |e| e.force,
        |e| e.moment,
    ];
    let (mut wins, mut total) = (0, 0);
    for lumped in r
        .points
        .iter()
        .filter(|p| p.path == SolverPath::LumpedLowRank)
    {
        if let Some(fe) = r.point(SolverPath::FeBanded, lumped.size, &lumped.surface) {
            for m in metrics {
                total += 1;
                wins += usize::from(m(&fe.spatial) <= m(&lumped.spatial));
            }
        }
    }
    (wins, total)
}

/// How the default scenario's model (FE 30) compares, when it was run.
fn scenario_default_line(md: &mut String, r: &SolverPathsReport, best: &Candidate) {
    let points: Vec<_> = r
        .references
        .iter()
        .filter_map(|(s, _)| r.point(SolverPath::FeBanded, 30, s))
        .collect();
    if points.is_empty() || (best.path == SolverPath::FeBanded && best.size == 30) {
        return;
    }
    let at_floor = r.references.iter().all(|(surface, reference)| {
        r.point(SolverPath::FeBanded, 30, surface).is_some_and(|p| {
            let (e, f) = (&p.spatial, &reference.time_step_floor);
            e.deflection <= f.deflection
                && e.acceleration_rms <= f.acceleration_rms
                && e.force <= f.force
        })
    });
    let worst_moment = points.iter().map(|p| p.errors.moment).fold(0.0, f64::max);
    let _ = writeln!(
        md,
        "\nThe scenario's current default, 30 elements, is {} the floor for deflection, \
         acceleration and forces, and its midspan moment errs by up to {:.1} %.",
        if at_floor { "within" } else { "not within" },
        100.0 * worst_moment,
    );
}
