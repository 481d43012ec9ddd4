//! Trains (`physics::vehicle::train*`): the HSLM-A axle layouts against EN 1991-2 Annex E
//! as encoded in an independent code, every HSLM axle carrying P in the vehicle models,
//! the articulated rake's load path, the Manchester benchmark vehicle's modes against
//! estimates written out by hand, and the coupled solver's split of a train into cars
//! against the direct solver that assembles and factorizes the whole system each step.

use bridgetwin::physics::bridge::{
    BeamProperties, BridgeModel, ModelSpec, PointQuantity, SparseVec,
};
use bridgetwin::physics::road::{IsoClass, LevelRoad, RoadProfile, RoadProfileSpec, RoadSurface};
use bridgetwin::physics::solver::{
    vehicle_natural_frequencies_hz, ContactLaw, CoupledSolver, CoupledVehicle, DirectSolver,
    NewmarkCoefficients, NewmarkParams, SolveMode, Storage,
};
use bridgetwin::physics::vehicle::{
    car_preset, train_preset, Representation, VehicleDynamics, GRAVITY_M_S2, HSLM_A,
};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

fn train(name: &str, representation: Representation) -> VehicleDynamics {
    train_preset(name).unwrap().build(representation).unwrap()
}

#[test]
fn hslm_a_axles_are_those_of_annex_e() {
    // First-to-last axle distance of A1..A10 from the axle files of the UPM CALDINTAV code
    // (a01-a10.def), an independent encoding of EN 1991-2 Figure E.8 and Table E.4; and
    // the first axles of A1 from the same file.
    let span_m = [
        397.525, 398.525, 397.525, 394.525, 389.525, 382.525, 397.525, 387.525, 375.525, 388.525,
    ];
    for (i, &(n, _, _, _)) in HSLM_A.iter().enumerate() {
        let t = train(&format!("hslm_a{}", i + 1), Representation::MovingForces);
        assert_eq!(t.axles.len(), 2 * (n + 3) + 8, "A{}", i + 1);
        assert!(
            (t.wheelbase_m() - span_m[i]).abs() < 1e-9,
            "A{}: {}",
            i + 1,
            t.wheelbase_m()
        );
    }
    let a1: Vec<f64> = train("hslm_a1", Representation::MovingForces)
        .axles
        .iter()
        .map(|a| a.offset_m)
        .collect();
    let want = [
        0.0, 3.0, 14.0, 17.0, 20.525, 22.525, 35.7625, 37.7625, 53.7625, 55.7625,
    ];
    for (got, want) in a1.iter().zip(want) {
        assert!((got - want).abs() < 1e-9, "{a1:?}");
    }
    // The rear mirrors the front.
    let last = a1[a1.len() - 1];
    for (front, rear) in a1.iter().zip(a1.iter().rev()) {
        assert!((front - (last - rear)).abs() < 1e-9);
    }
}

#[test]
fn every_hslm_axle_carries_p_as_moving_force_and_as_vehicle() {
    // The articulated rake is statically determinate (each body on two pivots, each bogie
    // on two wheelsets), so the body masses chosen for P give P exactly, to round-off.
    for (i, &(_, _, _, p_kn)) in HSLM_A.iter().enumerate() {
        let name = format!("hslm_a{}", i + 1);
        for r in [Representation::MovingForces, Representation::Vehicles] {
            for a in &train(&name, r).axles {
                assert!(
                    (a.static_load_n / (p_kn * 1e3) - 1.0).abs() < 1e-9,
                    "{name} {r:?}: {}",
                    a.static_load_n
                );
            }
        }
    }
    // The vehicle model of A1 couples its whole articulated rake: one Jacobs bogie's
    // bounce couples the two bodies resting on it.
    let a1 = train("hslm_a1", Representation::Vehicles);
    assert_eq!(a1.axles.len(), 50);
    assert_eq!(
        a1.n_dof(),
        2 * 22 + 2 * 25 + 50,
        "bodies, bogies, wheelsets"
    );
}

#[test]
fn en1991_type4_is_the_annex_d_train_with_17_t_on_every_axle() {
    // Independent construction from the Annex D figure as a list of vehicles, each by the
    // distances between its coupler ends and its axles (the pacril transcription's form):
    // power car, end trailer, eight intermediate trailers, end trailer, power car.
    let power = [3.5, 3.0, 11.0, 3.0, 1.65];
    let end_a = [1.65, 3.0, 15.7, 1.5];
    let middle = [1.5, 15.7, 1.5];
    let end_c = [1.5, 15.7, 3.0, 1.65];
    let rear = [1.65, 3.0, 11.0, 3.0, 3.5];
    let mut vehicles: Vec<&[f64]> = vec![&power, &end_a];
    vehicles.extend(std::iter::repeat_n(&middle[..], 8));
    vehicles.extend([&end_c[..], &rear[..]]);
    let mut want = Vec::new();
    let mut coupler = 0.0;
    for gaps in vehicles {
        let mut x = coupler;
        for (k, g) in gaps.iter().enumerate() {
            x += g;
            if k + 1 < gaps.len() {
                want.push(x);
            }
        }
        coupler = x;
    }
    // The trailers' articulation points are Jacobs bogies: the axle on each side of one
    // belongs to the two trailers, one listed with each.
    let want: Vec<f64> = want.iter().map(|x| x - want[0]).collect();
    assert_eq!(want.len(), 30);
    for r in [Representation::MovingForces, Representation::Vehicles] {
        let t = train("en1991_type4", r);
        let got: Vec<f64> = t.axles.iter().map(|a| a.offset_m).collect();
        assert_eq!(got.len(), want.len(), "{r:?}");
        for (g, w) in got.iter().zip(&want) {
            assert!((g - w).abs() < 1e-9, "{r:?}: {got:?}");
        }
        for a in &t.axles {
            let tonnes = a.static_load_n / GRAVITY_M_S2 / 1e3;
            assert!((tonnes / 17.0 - 1.0).abs() < 1e-9, "{r:?}: {tonnes} t");
        }
    }
    // As vehicles: one articulated rake of ten bodies on eleven bogies between the power
    // cars (each with its own body and two bogies).
    let t = train("en1991_type4", Representation::Vehicles);
    assert_eq!(t.n_dof(), 2 * 12 + 2 * 15 + 30, "bodies, bogies, wheelsets");
}

#[test]
fn en1991_freight_trains_are_their_annex_d_axles_as_moving_forces_only() {
    // Written out from the Annex D definitions (locomotive axle gaps; a bogie wagon by its
    // end-to-bogie-centre a, bogie spacing b and wheelbase c: axles at a - c/2, a + c/2,
    // a + b - c/2, a + b + c/2 of a 2a + b wagon).
    let loco = [1.4, 3.6, 5.8, 12.7, 14.9, 17.1];
    for (name, tonnes, a, b, c) in [
        ("en1991_type7", 22.5, 2.5, 12.8, 1.8),
        ("en1991_type11", 25.0, 2.5, 13.0, 2.0),
    ] {
        let mut want: Vec<(f64, f64)> = loco.iter().map(|&x| (x, 22.5)).collect();
        for w in 0..10 {
            let start = 18.5 + w as f64 * (2.0 * a + b);
            for x in [a - c / 2.0, a + c / 2.0, a + b - c / 2.0, a + b + c / 2.0] {
                want.push((start + x, tonnes));
            }
        }
        let t = train(name, Representation::MovingForces);
        assert_eq!(t.axles.len(), 46, "{name}");
        assert_eq!(t.n_dof(), 0, "{name}: moving forces");
        for (axle, (x, w_t)) in t.axles.iter().zip(&want) {
            assert!(
                (axle.offset_m - (x - 1.4)).abs() < 1e-9,
                "{name}: {}",
                axle.offset_m
            );
            let got_t = axle.static_load_n / GRAVITY_M_S2 / 1e3;
            assert!((got_t - w_t).abs() < 1e-9, "{name}: {got_t} t");
        }
        // No vehicle model: asked for one, the train says why.
        let err = train_preset(name)
            .unwrap()
            .build(Representation::Vehicles)
            .unwrap_err()
            .to_string();
        assert!(err.contains("moving_forces") && err.contains(name), "{err}");
    }
}

#[test]
fn ice3_cars_carry_their_weight_by_the_lever_rule() {
    // A conventional car with its centre midway: each wheelset a quarter of the body, half
    // a bogie and itself (Goicolea 2014's masses).
    let t = train("ice3", Representation::Vehicles);
    assert_eq!(t.axles.len(), 32);
    let end = car_preset("ice3_end_car").unwrap();
    let expected =
        (end.body_mass_kg / 4.0 + end.bogie_mass_kg / 2.0 + end.wheelset_mass_kg) * GRAVITY_M_S2;
    assert!((t.axles[0].static_load_n / expected - 1.0).abs() < 1e-12);
    let total: f64 = t.axles.iter().map(|a| a.static_load_n).sum();
    let mass = 6.0 * 47_800.0 + 2.0 * 41_200.0 + 8.0 * 2.0 * 3_500.0 + 32.0 * 1_800.0;
    assert!(
        (total / (mass * GRAVITY_M_S2) - 1.0).abs() < 1e-12,
        "{total} vs {}",
        mass * GRAVITY_M_S2
    );
    // Coupled ICE 3 units: 16 cars, 64 axles, the second unit 200.67 m behind the first
    // (8 cars: 2 x 25.835 + 6 x 24.775 m).
    let double = train("ice3_double", Representation::Vehicles);
    assert_eq!(double.axles.len(), 64);
    let unit_m = 2.0 * 25.835 + 6.0 * 24.775;
    assert!((double.axles[32].offset_m - double.axles[0].offset_m - unit_m).abs() < 1e-9);
}

#[test]
fn manchester_vehicle_modes_match_hand_estimates() {
    // No published natural frequencies of the benchmark's vertical model were found;
    // these are estimates written out by hand from its parameters. Body bounce: the
    // secondary in series with the primaries and contacts of a bogie, two bogies; pitch:
    // the same springs at the pivots' lever 9.5 m about the body inertia. Bogie bounce: the
    // bogie frame on its two primaries with the body held still (the secondary adds to
    // it). The coupled modes differ from these by the neighbours' participation: 5 %.
    let car = car_preset("manchester_benchmark").unwrap();
    let dynamics = train("manchester_benchmark", Representation::Vehicles);
    let hz = vehicle_natural_frequencies_hz(&dynamics).unwrap();
    let two_pi = 2.0 * std::f64::consts::PI;
    let contact = dynamics.axles[0].tyre_stiffness_n_m;
    let per_bogie = 1.0
        / (1.0 / car.secondary.stiffness_n_m
            + 1.0 / (2.0 * car.primary.stiffness_n_m)
            + 1.0 / (2.0 * contact));
    let bounce = (2.0 * per_bogie / car.body_mass_kg).sqrt() / two_pi;
    let pitch = (2.0 * per_bogie * 9.5 * 9.5 / car.body_pitch_inertia_kg_m2).sqrt() / two_pi;
    let bogie = ((2.0 * car.primary.stiffness_n_m + car.secondary.stiffness_n_m)
        / car.bogie_mass_kg)
        .sqrt()
        / two_pi;
    let near = |f: f64| hz.iter().any(|&h| (h / f - 1.0).abs() < 0.05);
    for (what, f) in [
        ("bounce", bounce),
        ("pitch", pitch),
        ("bogie bounce", bogie),
    ] {
        assert!(near(f), "{what} {f:.3} Hz not within 5 % of {hz:?}");
    }
    // Body modes near 1 Hz, as a passenger coach's ride.
    assert!(
        (0.6..1.6).contains(&bounce) && (0.6..1.6).contains(&pitch),
        "{bounce} {pitch}"
    );
}

/// An ISO 8608 class A profile over `[from_m, to_m]` (seed 19).
fn class_a_road(from_m: f64, to_m: f64) -> RoadProfile {
    let mut rng = ChaCha8Rng::seed_from_u64(19);
    RoadProfile::build(
        &RoadProfileSpec::iso8608(IsoClass::A),
        from_m,
        to_m,
        &mut rng,
    )
    .unwrap()
}

/// The paper's bridge in 16 finite elements, 2 % damping.
fn paper_bridge() -> BridgeModel {
    let beam = BeamProperties::paper_default();
    BridgeModel::build(&beam, &ModelSpec::FiniteElement { elements: 16 }, 0.02).unwrap()
}

/// The coupled (low-rank) solver with sparse storage and full contact.
fn low_rank_solver<'a>(
    model: &'a BridgeModel,
    road: &'a dyn RoadSurface,
    coef: NewmarkCoefficients,
) -> CoupledSolver<'a> {
    let mode = SolveMode::Prefactored(Storage::Sparse);
    CoupledSolver::new(model, road, coef, mode, ContactLaw::Full).unwrap()
}

/// Runs a train across the paper's bridge with both solvers and returns the largest
/// differences of midspan deflection and wheel force relative to their peaks, and the
/// number of blocks the coupled solver split the train into.
fn split_vs_direct(name: &str) -> (f64, f64, usize) {
    let model = paper_bridge();
    let road = class_a_road(-100.0, 200.0);
    let coef = NewmarkCoefficients::new(2e-3, NewmarkParams::default()).unwrap();
    let (start, speed) = (-10.0, 40.0);
    let dynamics = train(name, Representation::Vehicles);
    let mut split = low_rank_solver(&model, &road, coef);
    split.add_vehicle(CoupledVehicle::new(1, dynamics.clone(), speed, start, 0));
    let mut direct = DirectSolver::new(&model, &road, coef).unwrap();
    direct.add_vehicle(CoupledVehicle::new(1, dynamics.clone(), speed, start, 0));
    let mut op = SparseVec::default();
    let (mut du, mut u_peak, mut df, mut f_peak) = (0.0f64, 0.0f64, 0.0f64, 0.0f64);
    let steps = ((30.0 + dynamics.wheelbase_m() - start) / speed / coef.dt_s) as usize;
    for _ in 0..steps {
        split.advance().unwrap();
        direct.advance().unwrap();
        let a = split.bridge_response(15.0, PointQuantity::Deflection, 0, &mut op);
        let b = direct.bridge_response(15.0, PointQuantity::Deflection, 0, &mut op);
        du = du.max((a - b).abs());
        u_peak = u_peak.max(a.abs());
        for (fa, fb) in split.vehicles[0]
            .contact_force_n
            .iter()
            .zip(&direct.vehicles[0].contact_force_n)
        {
            df = df.max((fa - fb).abs());
            f_peak = f_peak.max(fa.abs());
        }
    }
    assert!(u_peak > 1e-3, "the train must load the bridge: {u_peak}");
    (du / u_peak, df / f_peak, split.vehicles[0].block_count())
}

#[test]
fn a_train_split_into_its_cars_matches_the_direct_solver() {
    // Same Newmark, same linear contact law; the coupled solver solves each car apart and
    // the wheel forces in independent groups, the direct solver factorizes the whole
    // system: only round-off may differ (condition numbers ~1e8 with the Hertz springs).
    let (du, df, blocks) = split_vs_direct("ice3");
    assert_eq!(blocks, 8, "eight cars, no spring between them");
    assert!(du < 1e-8 && df < 1e-8, "deflection {du:e}, force {df:e}");
}

#[test]
fn an_articulated_rake_is_one_block_and_matches_the_direct_solver() {
    let (du, df, blocks) = split_vs_direct("hslm_a9");
    assert_eq!(blocks, 3, "power car, articulated rake, power car");
    assert!(du < 1e-8 && df < 1e-8, "deflection {du:e}, force {df:e}");
}

/// Runs `name` across the paper's bridge on `road` twice, skipping the step of the cars
/// at rest on the approach and not, and returns the largest difference of any bridge DOF
/// or tyre force between the two (bits, as f64 differences) and the block-steps skipped.
fn resting_skip_vs_full_step(
    dynamics: &VehicleDynamics,
    road: &dyn RoadSurface,
    law: ContactLaw,
) -> (f64, u64) {
    let model = paper_bridge();
    let coef = NewmarkCoefficients::new(2e-3, NewmarkParams::default()).unwrap();
    let mode = SolveMode::Prefactored(Storage::Sparse);
    let (start, speed) = (-10.0, 60.0);
    let mut runs: Vec<CoupledSolver> = [true, false]
        .into_iter()
        .map(|skip| {
            let mut solver = CoupledSolver::new(&model, road, coef, mode, law).unwrap();
            solver.rest_skip = skip;
            solver.add_vehicle(CoupledVehicle::new(1, dynamics.clone(), speed, start, 0));
            solver
        })
        .collect();
    let steps = ((30.0 + dynamics.wheelbase_m() - start) / speed / coef.dt_s) as usize;
    let mut worst = 0.0f64;
    for _ in 0..steps {
        for solver in &mut runs {
            solver.advance().unwrap();
        }
        let (a, b) = (&runs[0], &runs[1]);
        let bridge = (a.bridge.state.u.iter()).zip(b.bridge.state.u.iter());
        let tyres = (a.vehicles[0].contact_force_n.iter()).zip(&b.vehicles[0].contact_force_n);
        let (sa, sb) = (&a.vehicles[0].state, &b.vehicles[0].state);
        let vehicle =
            (sa.u.iter().chain(&sa.v).chain(&sa.a)).zip(sb.u.iter().chain(&sb.v).chain(&sb.a));
        for (x, y) in bridge.chain(tyres).chain(vehicle) {
            assert_eq!(x.to_bits(), y.to_bits(), "{x:e} against {y:e}");
            worst = worst.max((x - y).abs());
        }
    }
    assert_eq!(
        runs[1].resting_block_steps, 0,
        "the full step skips nothing"
    );
    (worst, runs[0].resting_block_steps)
}

#[test]
fn cars_at_rest_on_a_level_approach_skip_their_step_and_change_no_bit() {
    // On a level road the cars behind the span stay exactly at rest until a tyre reaches
    // it: skipping them must give the same bits as stepping them (asserted every step).
    let ice3 = train("ice3", Representation::Vehicles);
    let (_, skipped) = resting_skip_vs_full_step(&ice3, &LevelRoad, ContactLaw::Full);
    // ICE 3: eight cars, 200 m; most of them wait on the approach for seconds.
    assert!(
        skipped > 2000,
        "the waiting cars must be skipped: {skipped}"
    );
    // On an irregular track every tyre is excited from the first step: nothing rests.
    let rough = class_a_road(-300.0, 300.0);
    let (_, skipped) = resting_skip_vs_full_step(&ice3, &rough, ContactLaw::Unilateral);
    assert_eq!(skipped, 0);
    // Unilateral contact with a wheel that carries no static load (it lifts off at once,
    // its force pinned at -F_static): its car moves from the first step and must not be
    // skipped; the other seven cars still are.
    let mut unloaded = ice3.clone();
    unloaded.axles[5].static_load_n = -1000.0;
    let (_, skipped) = resting_skip_vs_full_step(&unloaded, &LevelRoad, ContactLaw::Unilateral);
    assert!(skipped > 1000, "the other cars still rest: {skipped}");
}

/// Two trains 60 s apart over a 30 m span, triggered records 2 s before and after each.
const TRIGGERED_RUN: &str = r#"
seed = 3
duration_s = 90.0
[bridge]
span_m = 30.0
flexural_rigidity_n_m2 = 5.629e10
mass_per_length_kg_m = 12000.0
model = { kind = "finite_element", elements = 20 }
[solver]
dt_s = 0.001
contact = "unilateral"
[road]
profile = { kind = "track", class = "german_low" }
approach_m = 40.0
exit_m = 20.0
[output]
trigger = { pre_s = 2.0, post_s = 2.0 }
[[vehicles]]
id = 7
model = { kind = "train", preset = "ice3" }
speed_m_s = 40.0
[[vehicles]]
id = 8
model = { kind = "train", cars = [{ preset = "manchester_benchmark", count = 3 }] }
speed_m_s = 30.0
entry_time_s = 60.0
[[sensors]]
id = "A1"
kind = "accelerometer"
position_m = 15.0
rate_hz = 100.0
"#;

#[test]
fn triggered_records_keep_only_the_passages_and_report_each_train() {
    use bridgetwin::record::Record;
    let records = crate::common::records_of(TRIGGERED_RUN);
    // Train 7 (first to last wheelset 200.67 - 2 x 3.51 = 193.65 m): front axle on the
    // bridge at 40 / 40 = 1 s, last axle off at 1 + (30 + 193.65) / 40 = 6.59 s; train 8
    // (3 x 25 - 2 x 1.72 = 71.56 m) from 60 + 40 / 30 = 61.33 s to 61.33 + 101.56 / 30 =
    // 64.72 s. Windows 2 s either side: [0, 8.59] and [59.33, 66.72] s.
    let windows = [(0.0, 8.592), (59.332, 66.719)];
    let inside = |t: f64| windows.iter().any(|&(a, b)| t >= a - 1e-3 && t <= b + 1e-3);
    let mut samples = 0;
    for r in &records {
        if let Record::Sensor { t_ns, .. } | Record::AxleLoads { t_ns, .. } = r {
            let t = *t_ns as f64 * 1e-9;
            assert!(inside(t), "a sampled record at {t} s, outside the windows");
            samples += 1;
        }
    }
    // 100 Hz and the axle loads at 200 Hz over the 16 s of windows.
    assert!(samples > 4000, "{samples}");
    let events: Vec<String> = records
        .iter()
        .filter_map(|r| match r {
            Record::Event { text, .. } => Some(text.clone()),
            _ => None,
        })
        .collect();
    let containing =
        |needle: &str| -> Vec<&String> { events.iter().filter(|e| e.contains(needle)).collect() };
    let opened = containing("triggered record");
    assert_eq!(opened.len(), 2, "{events:?}");
    assert!(
        opened[0].contains("of 2") && opened[1].contains("vehicle 8 (train)"),
        "{opened:?}"
    );
    let left = containing("leaves the bridge");
    assert_eq!(left.len(), 2, "{events:?}");
    assert!(
        left[0].starts_with("vehicle 7 leaves the bridge (train/ice3, 32 wheelsets, 144 km/h)")
            && left[0].contains("smallest wheel load 0.")
            && left[0].contains("no wheel lifted off"),
        "{}",
        left[0]
    );
}

#[test]
fn over_three_sleepers_each_axle_is_three_loads_of_a_quarter_a_half_and_a_quarter() {
    // HSLM-A1 as moving forces over the 15 m span with the load spread over sleepers
    // 0.6 m apart, against Fryba's closed form summed over three loads per axle (P/4 at
    // a behind, P/2 at, P/4 at a ahead of the wheel), within 2e-3 of the peak (measured
    // 1.15e-3: the 40-element model and the 0.5 ms step; 2e-3 is 1.7 times that). The
    // control: the same run against the point loads (1.48e-2 off) must miss that same
    // tolerance, so the spread is what the test sees.
    use bridgetwin::studies::analytic::{MovingLoadTrain, SimplySupportedBeam};
    use bridgetwin::studies::hslm::StudyBridge;
    let bridge = StudyBridge::short_span();
    let model = BridgeModel::build(
        &bridge.beam,
        &ModelSpec::FiniteElement { elements: 40 },
        0.0,
    )
    .unwrap();
    let road = bridgetwin::physics::road::LevelRoad;
    let coef = NewmarkCoefficients::new(5e-4, NewmarkParams::default()).unwrap();
    let a = 0.6;
    let forces = train("hslm_a1", Representation::MovingForces);
    let v = 200.0 / 3.6;
    let mut solver = low_rank_solver(&model, &road, coef);
    solver.sleeper_spacing_m = Some(a);
    // The front wheel starts a before the span so that its leading quarter enters at 0.
    solver.add_vehicle(CoupledVehicle::new(1, forces.clone(), v, -a, 0));
    let spread = MovingLoadTrain {
        loads: forces
            .axles
            .iter()
            .flat_map(|x| {
                let p = x.static_load_n;
                [
                    (x.offset_m, 0.25 * p),
                    (x.offset_m + a, 0.5 * p),
                    (x.offset_m + 2.0 * a, 0.25 * p),
                ]
            })
            .collect(),
    };
    let point = MovingLoadTrain {
        loads: forces
            .axles
            .iter()
            .map(|x| (x.offset_m + a, x.static_load_n))
            .collect(),
    };
    let beam = SimplySupportedBeam::new(
        15.0,
        bridge.beam.flexural_rigidity_n_m2,
        bridge.beam.mass_per_length_kg_m,
    )
    .unwrap();
    let none = bridgetwin::studies::analytic::ModalDamping::None;
    let reference =
        bridgetwin::studies::analytic::MovingForceSolution::for_train(beam, &spread, v, none, 100)
            .unwrap();
    let unspread =
        bridgetwin::studies::analytic::MovingForceSolution::for_train(beam, &point, v, none, 100)
            .unwrap();
    let mut op = SparseVec::default();
    let (mut err, mut err_point, mut peak) = (0.0f64, 0.0f64, 0.0f64);
    let steps = ((15.0 + forces.wheelbase_m() + 2.0 * a) / v / coef.dt_s) as usize;
    for _ in 0..steps {
        solver.advance().unwrap();
        let t = solver.time_s();
        let u = -solver.bridge_response(7.5, PointQuantity::Deflection, 0, &mut op);
        err = err.max((u - reference.deflection_m(7.5, t)).abs());
        err_point = err_point.max((u - unspread.deflection_m(7.5, t)).abs());
        peak = peak.max(u.abs());
    }
    println!(
        "spread vs three loads per axle {:.2e}, vs point loads {:.2e} of the peak",
        err / peak,
        err_point / peak
    );
    assert!(
        err / peak < 2e-3,
        "spread vs three loads per axle: {:e}",
        err / peak
    );
    assert!(
        err_point / peak > 2e-3,
        "point loads would pass too: {:e}",
        err_point / peak
    );
}
