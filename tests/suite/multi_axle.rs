//! Multi-axle vehicles: rigid trucks on 2-4 axles, the tractor +
//! semi-trailer hinged at the fifth wheel, the traffic-class presets and their scaling to
//! a traffic draw. Every figure is checked against an independent computation: statics by
//! the lever rule on each body, matrices rebuilt here from docs/physics.md's formula,
//! eigenvalues of the hinged model against a penalty-spring two-body model, axle hop
//! against the decoupled `sqrt((k_s + k_t) / m)`.

use nalgebra::{DMatrix, DVector, SymmetricEigen};

use bridgetwin::physics::solver::vehicle_natural_frequencies_hz;
use bridgetwin::physics::vehicle::{
    rigid_body_on_axles, vehicle_for_traffic, ArticulatedParams, ArticulatedSpec, HalfCarSpec,
    RigidTruckSpec, VehicleDynamics, VehicleModelSpec, GRAVITY_M_S2, RIGID_TRUCK_PRESETS,
    TRAFFIC_CLASSES,
};

const PATH: &str = "vehicles.3.model";

fn from_toml(text: &str) -> bridgetwin::Result<VehicleDynamics> {
    let spec: VehicleModelSpec = toml::from_str(text).expect("valid TOML");
    spec.build(PATH)
}

fn kind_of(class: &str) -> &'static str {
    if class.starts_with("artic") {
        "articulated"
    } else {
        "rigid_truck"
    }
}

fn preset(class: &str) -> VehicleDynamics {
    from_toml(&format!(
        "kind = \"{}\"\npreset = \"{class}\"",
        kind_of(class)
    ))
    .unwrap()
}

fn artic_params() -> ArticulatedParams {
    ArticulatedSpec::preset("artic_5axle")
        .unwrap()
        .params(PATH)
        .unwrap()
}

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}

/// Frequencies (Hz, ascending) of K x = w^2 M x for a diagonal M, computed here by the
/// symmetric scaling M^-1/2 K M^-1/2 (independent of the library's Cholesky path).
fn frequencies_diagonal_mass_hz(k: &DMatrix<f64>, m: &DMatrix<f64>) -> Vec<f64> {
    let s = DVector::from_iterator(m.nrows(), (0..m.nrows()).map(|i| 1.0 / m[(i, i)].sqrt()));
    let a = DMatrix::from_fn(k.nrows(), k.ncols(), |i, j| s[i] * k[(i, j)] * s[j]);
    let mut w2: Vec<f64> = SymmetricEigen::new(a).eigenvalues.iter().copied().collect();
    w2.sort_by(f64::total_cmp);
    w2.iter()
        .map(|l| l.max(0.0).sqrt() / (2.0 * std::f64::consts::PI))
        .collect()
}

// ---------------------------------------------------------------------------------------
// Statics
// ---------------------------------------------------------------------------------------

/// Axle loads of a rigid body on n series springs (suspension + tyre), solved here by
/// hand: body loads P_j = -ke_j (y + d_j theta + c_j), c_j = m_j g / kt_j (the axle's own
/// weight pre-compresses its tyre), with sum P = W_body and sum P d = 0, a 2x2 system.
/// For two axles this is the plain lever rule whatever the springs.
fn elastic_lever_rule_loads_n(spec: &RigidTruckSpec) -> Vec<f64> {
    let p = spec.params(PATH).unwrap();
    let weight_n = p.body.mass_kg * GRAVITY_M_S2;
    let (mut a, mut b, mut c, mut r0, mut r1) = (0.0, 0.0, 0.0, -weight_n, 0.0);
    for (ax, &x) in p.axles.iter().zip(&p.axle_offsets_m) {
        let ke = 1.0 / (1.0 / ax.suspension_stiffness_n_m + 1.0 / ax.tyre_stiffness_n_m);
        let d = p.body.cg_behind_front_m - x;
        let pre = ax.mass_kg * GRAVITY_M_S2 / ax.tyre_stiffness_n_m;
        a += ke;
        b += ke * d;
        c += ke * d * d;
        r0 -= ke * pre;
        r1 += -ke * d * pre;
    }
    let det = a * c - b * b;
    let (y, theta) = ((r0 * c - b * r1) / det, (a * r1 - b * r0) / det);
    p.axles
        .iter()
        .zip(&p.axle_offsets_m)
        .map(|(ax, &x)| {
            let ke = 1.0 / (1.0 / ax.suspension_stiffness_n_m + 1.0 / ax.tyre_stiffness_n_m);
            let pre = ax.mass_kg * GRAVITY_M_S2 / ax.tyre_stiffness_n_m;
            let body_n = -ke * (y + (p.body.cg_behind_front_m - x) * theta + pre);
            body_n + ax.mass_kg * GRAVITY_M_S2
        })
        .collect()
}

#[test]
fn rigid_presets_static_loads_sum_to_the_weight_and_follow_the_lever_rule() {
    // 1e-9 relative: the library's 6x6 LU solve and the 2x2 Cramer solve here both lose
    // at most cond ~1e4 x 1e-16.
    for name in RIGID_TRUCK_PRESETS {
        let spec = RigidTruckSpec::preset(name).unwrap();
        let p = spec.params(PATH).unwrap();
        let v = preset(name);
        let weight_n =
            (p.body.mass_kg + p.axles.iter().map(|a| a.mass_kg).sum::<f64>()) * GRAVITY_M_S2;
        assert!(rel(v.gross_weight_n(), weight_n) < 1e-9, "{name}");
        for (a, want) in v.axles.iter().zip(elastic_lever_rule_loads_n(&spec)) {
            assert!(rel(a.static_load_n, want) < 1e-9, "{name}: {a:?} {want}");
        }
        if p.axles.len() == 2 {
            // Closed form: front body load W (L - x_cg) / L.
            let l = p.axle_offsets_m[1];
            let front = p.body.mass_kg * GRAVITY_M_S2 * (l - p.body.cg_behind_front_m) / l
                + p.axles[0].mass_kg * GRAVITY_M_S2;
            assert!(rel(v.axles[0].static_load_n, front) < 1e-9, "{name}");
        }
    }
}

/// Each body of an articulated vehicle in equilibrium: the trailer about the kingpin, the
/// tractor about its front axle with the kingpin force on it (lever rule). Returns the
/// kingpin force (N).
fn assert_articulated_lever_rule(p: &ArticulatedParams, v: &VehicleDynamics, tol: f64) -> f64 {
    let g = GRAVITY_M_S2;
    let body_n: Vec<f64> = v
        .axles
        .iter()
        .zip(&p.axles)
        .map(|(c, a)| c.static_load_n - a.mass_kg * g)
        .collect();
    let x = &p.axle_offsets_m;
    let n_tc = p.tractor_axle_count;
    let xk = p.fifth_wheel_behind_front_m;
    let trailer_n = p.trailer.mass_kg * g;
    let kingpin_n = trailer_n - body_n[n_tc..].iter().sum::<f64>();
    let trailer_moment: f64 = (n_tc..x.len()).map(|j| body_n[j] * (x[j] - xk)).sum();
    let want = trailer_n * (p.trailer.cg_behind_front_m - xk);
    assert!(rel(trailer_moment, want) < tol, "{trailer_moment} {want}");
    let tractor_n = p.tractor.mass_kg * g;
    let tractor_sum: f64 = body_n[..n_tc].iter().sum();
    assert!(rel(tractor_sum, tractor_n + kingpin_n) < tol);
    let tractor_moment: f64 = (0..n_tc).map(|j| body_n[j] * x[j]).sum();
    let want = tractor_n * p.tractor.cg_behind_front_m + kingpin_n * xk;
    assert!(rel(tractor_moment, want) < tol, "{tractor_moment} {want}");
    kingpin_n
}

#[test]
fn articulated_static_loads_sum_to_the_weight_and_split_by_the_lever_rule() {
    let p = artic_params();
    let v = preset("artic_5axle");
    let weight_n = (4_500.0 + 31_450.0 + 4_050.0) * GRAVITY_M_S2;
    assert!(rel(v.gross_weight_n(), weight_n) < 1e-9);
    let kingpin_n = assert_articulated_lever_rule(&p, &v, 1e-9);
    // About a quarter of the trailer rests on the fifth wheel (VBI-2D geometry: 0.32).
    let share = kingpin_n / (31_450.0 * GRAVITY_M_S2);
    assert!((0.25..0.40).contains(&share), "{share}");
    // The statically indeterminate tridem split agrees with the penalty model, whose
    // hinge stretches by F / k_pen: 1e-6 relative at k_pen = 1e12 N/m.
    let (k, _, gravity) = penalty_model(&p, 1e12);
    let y = k.lu().solve(&gravity).unwrap();
    for (j, a) in v.axles.iter().enumerate() {
        let dof = penalty_axle_dof(&p, j);
        let load = -p.axles[j].tyre_stiffness_n_m * y[dof];
        assert!(rel(load, a.static_load_n) < 1e-6, "axle {j}: {load} {a:?}");
    }
}

// ---------------------------------------------------------------------------------------
// The hinge
// ---------------------------------------------------------------------------------------

/// An independent model of the tractor-trailer: each body built alone by
/// `rigid_body_on_axles`, side by side, tyres on, the hinge a spring of `k_pen` between
/// the kingpin points. DOFs: tractor (y, theta, its axles), trailer (y, theta, its
/// axles). Returns (K with tyres and penalty, diagonal M, gravity forces).
fn penalty_model(p: &ArticulatedParams, k_pen: f64) -> (DMatrix<f64>, DMatrix<f64>, DVector<f64>) {
    let n_tc = p.tractor_axle_count;
    let tractor = rigid_body_on_axles(
        "tractor",
        p.tractor.mass_kg,
        p.tractor.pitch_inertia_kg_m2,
        p.tractor.cg_behind_front_m,
        &p.axle_offsets_m[..n_tc],
        &p.axles[..n_tc],
    )
    .unwrap();
    let trailer = rigid_body_on_axles(
        "trailer",
        p.trailer.mass_kg,
        p.trailer.pitch_inertia_kg_m2,
        p.trailer.cg_behind_front_m,
        &p.axle_offsets_m[n_tc..],
        &p.axles[n_tc..],
    )
    .unwrap();
    let (a, n) = (tractor.n_dof(), tractor.n_dof() + trailer.n_dof());
    let mut k = DMatrix::zeros(n, n);
    let mut m = DMatrix::zeros(n, n);
    k.view_mut((0, 0), (a, a))
        .copy_from(&tractor.stiffness_with_tyres());
    k.view_mut((a, a), (n - a, n - a))
        .copy_from(&trailer.stiffness_with_tyres());
    m.view_mut((0, 0), (a, a)).copy_from(&tractor.mass);
    m.view_mut((a, a), (n - a, n - a)).copy_from(&trailer.mass);
    let mut hinge = DVector::zeros(n);
    hinge[0] = 1.0;
    hinge[1] = p.tractor.cg_behind_front_m - p.fifth_wheel_behind_front_m;
    hinge[a] = -1.0;
    hinge[a + 1] = -(p.trailer.cg_behind_front_m - p.fifth_wheel_behind_front_m);
    k += &hinge * hinge.transpose() * k_pen;
    // Gravity: bodies on their bounce DOFs, axles on theirs; M is diagonal.
    let mut gravity = DVector::zeros(n);
    for i in [0, a] {
        gravity[i] = -m[(i, i)] * GRAVITY_M_S2;
    }
    for j in 0..p.axles.len() {
        let dof = penalty_axle_dof(p, j);
        gravity[dof] = -m[(dof, dof)] * GRAVITY_M_S2;
    }
    (k, m, gravity)
}

fn penalty_axle_dof(p: &ArticulatedParams, axle: usize) -> usize {
    let n_tc = p.tractor_axle_count;
    if axle < n_tc {
        2 + axle
    } else {
        2 + n_tc + 2 + (axle - n_tc)
    }
}

#[test]
fn articulated_eigenvalues_equal_the_penalty_hinged_two_body_model() {
    // The penalty model converges to the hinged one as k / k_pen: with k_pen = 1e12 N/m
    // against suspension springs <= 3.5e6 N/m the eigenvalues agree to ~1e-6; its extra
    // hinge mode (~3e3 Hz) is dropped. Tolerance 1e-4 on eigenvalues (w^2).
    let p = artic_params();
    let hinged = vehicle_natural_frequencies_hz(&preset("artic_5axle")).unwrap();
    let (k, m, _) = penalty_model(&p, 1e12);
    let penalty = frequencies_diagonal_mass_hz(&k, &m);
    assert_eq!(penalty.len(), hinged.len() + 1);
    assert!(penalty[hinged.len()] > 100.0 * hinged[hinged.len() - 1]);
    for (h, q) in hinged.iter().zip(&penalty) {
        assert!(rel(h * h, q * q) < 1e-4, "{hinged:?}\n{penalty:?}");
    }
}

#[test]
fn articulated_zero_energy_modes_are_exactly_the_three_rigid_motions() {
    // Without tyres the suspended system has three zero-energy motions, all rigid with
    // the axles following the body above them: whole-vehicle bounce, whole-vehicle pitch
    // (both bodies turning together), and the trailer turning about the kingpin with the
    // tractor still. K must annihilate each (1e-12 of ||K|| ||q||: rounding) and have rank
    // 5 (the next eigenvalue far from zero), so the hinge admits nothing else.
    let p = artic_params();
    let v = preset("artic_5axle");
    let n = v.n_dof();
    let x = &p.axle_offsets_m;
    let xk = p.fifth_wheel_behind_front_m;
    let n_tc = p.tractor_axle_count;
    let mut bounce = DVector::from_element(n, 1.0);
    bounce[1] = 0.0;
    bounce[2] = 0.0;
    // Pitch nose-up by 1 rad about the front axle: a point x behind it moves -x.
    let mut pitch = DVector::zeros(n);
    pitch[0] = -p.tractor.cg_behind_front_m;
    pitch[1] = 1.0;
    pitch[2] = 1.0;
    let mut trailer_turn = DVector::zeros(n);
    trailer_turn[2] = 1.0;
    for j in 0..x.len() {
        pitch[3 + j] = -x[j];
        if j >= n_tc {
            trailer_turn[3 + j] = -(x[j] - xk);
        }
    }
    let k_norm = v.stiffness.norm();
    for q in [&bounce, &pitch, &trailer_turn] {
        assert!(
            (&v.stiffness * q).norm() <= 1e-12 * k_norm * q.norm(),
            "{q}"
        );
    }
    let eig = SymmetricEigen::new(v.stiffness.clone()).eigenvalues;
    let mut l: Vec<f64> = eig.iter().map(|e| e.abs()).collect();
    l.sort_by(f64::total_cmp);
    assert!(l[2] < 1e-12 * l[n - 1] && l[3] > 1e-4 * l[n - 1], "{l:?}");

    // The mass matrix carries the trailer's bounce through the hinge: the rigid motions'
    // kinetic energies are those of the whole vehicle (1e-12: a few products).
    let axle_mass: f64 = p.axles.iter().map(|a| a.mass_kg).sum();
    let total = p.tractor.mass_kg + p.trailer.mass_kg + axle_mass;
    assert!(rel(bounce.dot(&(&v.mass * &bounce)), total) < 1e-12);
    let pitch_inertia = p.tractor.pitch_inertia_kg_m2
        + p.trailer.pitch_inertia_kg_m2
        + p.tractor.mass_kg * p.tractor.cg_behind_front_m.powi(2)
        + p.trailer.mass_kg * p.trailer.cg_behind_front_m.powi(2)
        + p.axles
            .iter()
            .zip(x)
            .map(|(a, x)| a.mass_kg * x * x)
            .sum::<f64>();
    assert!(rel(pitch.dot(&(&v.mass * &pitch)), pitch_inertia) < 1e-12);
}

// ---------------------------------------------------------------------------------------
// Frequencies
// ---------------------------------------------------------------------------------------

/// docs/physics.md section 6's K and M for a rigid body on n axles, written out entry by
/// entry here, tyres included.
fn rigid_matrices_by_hand(spec: &RigidTruckSpec) -> (DMatrix<f64>, DMatrix<f64>) {
    let p = spec.params(PATH).unwrap();
    let n = p.axles.len();
    let mut k = DMatrix::zeros(n + 2, n + 2);
    let mut m = DMatrix::zeros(n + 2, n + 2);
    m[(0, 0)] = p.body.mass_kg;
    m[(1, 1)] = p.body.pitch_inertia_kg_m2;
    for (j, (a, &x)) in p.axles.iter().zip(&p.axle_offsets_m).enumerate() {
        let (ks, d) = (a.suspension_stiffness_n_m, p.body.cg_behind_front_m - x);
        k[(0, 0)] += ks;
        k[(0, 1)] += ks * d;
        k[(1, 0)] += ks * d;
        k[(1, 1)] += ks * d * d;
        k[(0, 2 + j)] = -ks;
        k[(2 + j, 0)] = -ks;
        k[(1, 2 + j)] = -ks * d;
        k[(2 + j, 1)] = -ks * d;
        k[(2 + j, 2 + j)] = ks + a.tyre_stiffness_n_m;
        m[(2 + j, 2 + j)] = a.mass_kg;
    }
    (k, m)
}

/// Sorted decoupled axle-hop estimates sqrt((k_s + k_t) / m) / 2 pi (body held still).
fn decoupled_hop_hz(axles: &[bridgetwin::physics::vehicle::AxleParams]) -> Vec<f64> {
    let mut f: Vec<f64> = axles
        .iter()
        .map(|a| {
            ((a.suspension_stiffness_n_m + a.tyre_stiffness_n_m) / a.mass_kg).sqrt()
                / (2.0 * std::f64::consts::PI)
        })
        .collect();
    f.sort_by(f64::total_cmp);
    f
}

/// The presets' modes (Hz), pinned to 0.5 % (they are the table in `classes.rs`).
const PRESET_MODES_HZ: [(&str, &[f64]); 5] = [
    ("car", &[1.27, 1.43, 11.26, 11.88]),
    ("truck_2axle", &[1.62, 2.31, 10.35, 15.11]),
    ("truck_3axle", &[1.293, 1.717, 10.904, 11.256, 11.310]),
    (
        "truck_4axle",
        &[1.356, 1.796, 10.731, 10.794, 10.874, 10.907],
    ),
    (
        "artic_5axle",
        &[1.42, 1.60, 4.96, 8.85, 10.48, 11.98, 11.98, 12.11],
    ),
];

#[test]
fn preset_frequencies_are_plausible_and_match_independent_computations() {
    for (class, pinned) in PRESET_MODES_HZ {
        let v = preset(class);
        let f = vehicle_natural_frequencies_hz(&v).unwrap();
        let (axles, body_dofs) = match RigidTruckSpec::preset(class) {
            Some(spec) => {
                // Matrices rebuilt by hand, eigenvalues by another route: 1e-9.
                let (k, m) = rigid_matrices_by_hand(&spec);
                for (a, b) in f.iter().zip(frequencies_diagonal_mass_hz(&k, &m)) {
                    assert!(rel(*a, b) < 1e-9, "{class}: {f:?}");
                }
                (spec.params(PATH).unwrap().axles, 2)
            }
            None => (artic_params().axles, 3),
        };
        // Body modes: 1-4 Hz bounce and pitch (docs/sensors.md section 4); the light
        // tractor's pitch on its stiff drive axle is the exception, ~5 Hz.
        for (i, fb) in f[..body_dofs].iter().enumerate() {
            let band = if i == 2 { 4.0..6.0 } else { 1.0..4.0 };
            assert!(band.contains(fb), "{class}: body mode {i} {f:?}");
        }
        // Axle hop: within 3 % of the decoupled estimate (the body, 10-50 times heavier,
        // barely moves at hop frequencies), and in 8.5-20 Hz (10-20 Hz in docs/sensors.md;
        // VBI-2D's soft steer axle hops at 8.8 Hz).
        for (got, est) in f[body_dofs..].iter().zip(decoupled_hop_hz(&axles)) {
            assert!(rel(*got, est) < 0.03, "{class}: {got} vs {est}");
            assert!((8.5..20.0).contains(got), "{class}: {f:?}");
        }
        assert_eq!(pinned.len(), f.len(), "{class}");
        for (got, want) in f.iter().zip(pinned.iter()) {
            assert!(rel(*got, *want) < 0.005, "{class}: {f:?}");
        }
    }
}

#[test]
fn truck_2axle_is_the_two_axle_truck_half_car() {
    let rigid = preset("truck_2axle");
    let half = VehicleModelSpec::HalfCar(HalfCarSpec::preset("two_axle_truck").unwrap())
        .build(PATH)
        .unwrap();
    assert_eq!(rigid.stiffness, half.stiffness);
    assert_eq!(rigid.mass, half.mass);
    assert_eq!(rigid.damping, half.damping);
    assert_eq!(rigid.axles, half.axles);
    assert_eq!(rigid.name, "rigid_truck/truck_2axle");
}

// ---------------------------------------------------------------------------------------
// Scaling to a traffic draw
// ---------------------------------------------------------------------------------------

/// Draws like the traffic generator's (docs/sensors.md section 4: Auxerre spacings and
/// weights, 2-axle front/rear 1/3 : 2/3): (class, gross weight N, spacings, shares).
fn draws() -> Vec<(&'static str, f64, Vec<f64>, Vec<f64>)> {
    let t = 1_000.0 * GRAVITY_M_S2;
    vec![
        ("car", 1.55 * t, vec![2.75], vec![0.55, 0.45]),
        (
            "truck_2axle",
            14.0 * t,
            vec![5.53],
            vec![1.0 / 3.0, 2.0 / 3.0],
        ),
        ("truck_2axle", 9.0 * t, vec![5.02], vec![0.45, 0.55]),
        (
            "truck_3axle",
            22.0 * t,
            vec![4.9, 1.3],
            vec![0.3, 0.35, 0.35],
        ),
        (
            "truck_4axle",
            29.0 * t,
            vec![2.0, 3.8, 1.3],
            vec![0.22, 0.22, 0.28, 0.28],
        ),
        (
            "artic_5axle",
            41.2 * t,
            vec![3.24, 5.43, 1.20, 1.21],
            vec![0.15, 0.25, 0.2, 0.2, 0.2],
        ),
        (
            "artic_5axle",
            29.6 * t,
            vec![3.6, 6.1, 1.31, 1.31],
            vec![0.21, 0.33, 0.16, 0.15, 0.15],
        ),
    ]
}

#[test]
fn traffic_vehicles_carry_exactly_the_drawn_axle_loads() {
    // The scaled model's static solution is constructed exactly (classes.rs), so the
    // computed loads match gross * share to rounding: 1e-9 relative.
    for (class, gross_n, spacing, shares) in draws() {
        let v = vehicle_for_traffic(class, gross_n, &spacing, &shares, "traffic.7").unwrap();
        assert_eq!(v.name, format!("{}/{class}", kind_of(class)));
        assert!(rel(v.gross_weight_n(), gross_n) < 1e-9, "{class}");
        let mut offset = 0.0;
        for (j, a) in v.axles.iter().enumerate() {
            assert!(
                rel(a.static_load_n, gross_n * shares[j]) < 1e-9,
                "{class} {j}: {a:?}"
            );
            assert!((a.offset_m - offset).abs() < 1e-12);
            offset += spacing.get(j).copied().unwrap_or(0.0);
        }
        // Frequencies stay plausible: body bounce 1-4 Hz, every body mode below 6 Hz,
        // axle hop 8-20 Hz.
        let f = vehicle_natural_frequencies_hz(&v).unwrap();
        let body_dofs = v.n_dof() - v.axles.len();
        assert!((1.0..4.0).contains(&f[0]), "{class}: {f:?}");
        assert!(f[..body_dofs].iter().all(|&x| x < 6.0), "{class}: {f:?}");
        assert!(
            f[body_dofs..].iter().all(|&x| (8.0..20.0).contains(&x)),
            "{class}: {f:?}"
        );
    }
}

/// (undamped frequency Hz, damping ratio) of each underdamped mode of the vehicle on a
/// rigid road, by frequency: zeta = -Re(lambda) / |lambda| of each complex pair.
fn modal_damping_ratios(v: &VehicleDynamics) -> Vec<(f64, f64)> {
    let mut modes: Vec<(f64, f64)> = v
        .rigid_road_eigenvalues()
        .unwrap()
        .iter()
        .filter(|l| l.im > 0.0)
        .map(|l| (l.norm() / (2.0 * std::f64::consts::PI), -l.re / l.norm()))
        .collect();
    modes.sort_by(|x, y| x.0.total_cmp(&y.0));
    modes
}

fn parameter(v: &VehicleDynamics, name: &str) -> f64 {
    v.parameters
        .iter()
        .find(|(n, _)| n == name)
        .unwrap_or_else(|| panic!("{} has no parameter {name}", v.name))
        .1
}

#[test]
fn an_empty_truck_keeps_its_dampers_and_its_axles_stay_damped() {
    // Dampers are hardware: an empty truck has the same shock absorbers as a loaded one
    // (classes.rs). Scaling them with the load-levelled springs, as an earlier version
    // did, left a 6 t truck_2axle's front axle hop almost undamped (its suspension
    // carries 2.7 kN of body over a 1 500 kg axle) and put dynamic tyre forces of 0.7 x
    // static on a class A road. Check: a light and a heavy draw keep the preset's
    // dampers exactly, and every axle-hop mode of the light draw keeps at least 60 % of
    // the preset's smallest hop damping ratio (0.187): with scaled dampers the 6 t
    // truck's front axle kept 0.033, now 0.196.
    let t = 1_000.0 * GRAVITY_M_S2;
    let preset = preset("truck_2axle");
    let hop_zeta = |v: &VehicleDynamics| -> Vec<f64> {
        let modes = modal_damping_ratios(v);
        modes[modes.len() - v.axles.len()..]
            .iter()
            .map(|m| m.1)
            .collect()
    };
    let preset_min = hop_zeta(&preset).into_iter().fold(f64::INFINITY, f64::min);
    for gross_t in [6.0, 22.0] {
        let v = vehicle_for_traffic("truck_2axle", gross_t * t, &[5.0], &[0.3, 0.7], "t").unwrap();
        for j in 1..=2 {
            for part in ["suspension", "tyre"] {
                let name = format!("axle_{j}_{part}_damping_n_s_m");
                assert_eq!(parameter(&v, &name), parameter(&preset, &name), "{name}");
            }
        }
        let zeta = hop_zeta(&v);
        println!("{gross_t} t: hop damping ratios {zeta:?}, preset's smallest {preset_min:.4}");
        if gross_t < 10.0 {
            assert!(
                zeta.iter().all(|&z| z >= 0.6 * preset_min),
                "{zeta:?} against {preset_min}"
            );
        }
    }
}

#[test]
fn traffic_articulated_bodies_balance_by_the_lever_rule() {
    // Rebuild the scaled tractor-trailer from its truth parameters and check each body's
    // equilibrium independently (1e-9), and that the kingpin carries a positive load.
    for (class, gross_n, spacing, shares) in draws() {
        if kind_of(class) != "articulated" {
            continue;
        }
        let v = vehicle_for_traffic(class, gross_n, &spacing, &shares, "t").unwrap();
        let get = |name: &str| {
            v.parameters
                .iter()
                .find(|(n, _)| n == name)
                .map(|(_, x)| *x)
                .unwrap()
        };
        let body = |prefix: &str| bridgetwin::physics::vehicle::BodyParams {
            mass_kg: get(&format!("{prefix}_body_mass_kg")),
            pitch_inertia_kg_m2: get(&format!("{prefix}_pitch_inertia_kg_m2")),
            cg_behind_front_m: get(&format!("{prefix}_cg_behind_front_m")),
        };
        let axles = (1..=5)
            .map(|i| bridgetwin::physics::vehicle::AxleParams {
                mass_kg: get(&format!("axle_{i}_mass_kg")),
                suspension_stiffness_n_m: get(&format!("axle_{i}_suspension_stiffness_n_m")),
                suspension_damping_n_s_m: get(&format!("axle_{i}_suspension_damping_n_s_m")),
                tyre_stiffness_n_m: get(&format!("axle_{i}_tyre_stiffness_n_m")),
                tyre_damping_n_s_m: get(&format!("axle_{i}_tyre_damping_n_s_m")),
            })
            .collect();
        let p = ArticulatedParams {
            tractor: body("tractor"),
            trailer: body("trailer"),
            fifth_wheel_behind_front_m: get("fifth_wheel_behind_front_m"),
            tractor_axle_count: 2,
            axle_offsets_m: v.axles.iter().map(|a| a.offset_m).collect(),
            axles,
        };
        let rebuilt = p.build("check").unwrap();
        assert!((&rebuilt.stiffness - &v.stiffness).amax() <= 1e-9 * v.stiffness.amax());
        assert!(assert_articulated_lever_rule(&p, &v, 1e-9) > 0.0);
    }
}

/// (class, gross weight N, spacings, shares, the field the error must name).
type BadDraw<'a> = (&'a str, f64, &'a [f64], &'a [f64], &'a str);

#[test]
fn bad_traffic_draws_name_the_field() {
    let t = 1_000.0 * GRAVITY_M_S2;
    let s5 = [3.24, 5.43, 1.2, 1.21];
    let q5 = [0.15, 0.25, 0.2, 0.2, 0.2];
    let cases: [BadDraw; 8] = [
        ("bus", 10.0 * t, &[5.0], &[0.5, 0.5], "lane.1.class"),
        ("artic_5axle", -1.0, &s5, &q5, "lane.1.gross_weight_n"),
        (
            "artic_5axle",
            40.0 * t,
            &s5[..3],
            &q5,
            "lane.1.axle_spacing_m",
        ),
        (
            "artic_5axle",
            40.0 * t,
            &[3.2, 5.4, 0.0, 1.2],
            &q5,
            "lane.1.axle_spacing_m.2",
        ),
        (
            "artic_5axle",
            40.0 * t,
            &s5,
            &q5[..4],
            "lane.1.axle_load_share",
        ),
        (
            "artic_5axle",
            40.0 * t,
            &s5,
            &[0.2, 0.25, 0.2, 0.2, 0.2],
            "lane.1.axle_load_share",
        ),
        (
            "artic_5axle",
            40.0 * t,
            &s5,
            &[0.35, 0.25, 0.2, 0.2, -0.0],
            "lane.1.axle_load_share.4",
        ),
        // 0.5 % of 10 t is 49 N, below the 80 kg axle's own weight.
        (
            "car",
            10.0 * t,
            &[2.6],
            &[0.995, 0.005],
            "lane.1.axle_load_share.1",
        ),
    ];
    for (class, gross_n, spacing, shares, field) in cases {
        let msg = vehicle_for_traffic(class, gross_n, spacing, shares, "lane.1")
            .unwrap_err()
            .to_string();
        assert!(msg.starts_with(&format!("{field} = ")), "{msg}");
    }
}

// ---------------------------------------------------------------------------------------
// Scenario syntax
// ---------------------------------------------------------------------------------------

#[test]
fn presets_parse_with_overrides_and_round_trip() {
    let v = from_toml(
        r#"kind = "rigid_truck"
preset = "truck_3axle"
body_mass_kg = 15000
axle_spacing_m = [5.0, 1.4]
tyre_damping_n_s_m = [0, 0, 0]"#,
    )
    .unwrap();
    assert_eq!(v.name, "rigid_truck/truck_3axle");
    assert_eq!(v.mass[(0, 0)], 15_000.0);
    assert_eq!(v.axles[2].offset_m, 6.4);
    assert!(v.axles.iter().all(|a| a.tyre_damping_n_s_m == 0.0));
    assert_eq!(v.axles[0].tyre_stiffness_n_m, 2.0e6); // from the preset

    let v = from_toml(
        r#"kind = "articulated"
preset = "artic_5axle"
trailer_body_mass_kg = 12000.0
fifth_wheel_behind_front_m = 2.7"#,
    )
    .unwrap();
    assert_eq!(v.name, "articulated/artic_5axle");
    let weight = (4_500.0 + 12_000.0 + 4_050.0) * GRAVITY_M_S2;
    assert!(rel(v.gross_weight_n(), weight) < 1e-9);
    assert_eq!(
        v.dof_names[..3],
        ["tractor_bounce", "tractor_pitch", "trailer_pitch"]
    );

    // A rigid truck written out in full, without a preset; CG defaults to mid-wheelbase.
    let v = from_toml(
        r#"kind = "rigid_truck"
body_mass_kg = 10000.0
pitch_inertia_kg_m2 = 50000.0
axle_spacing_m = [5.0]
axle_mass_kg = [900.0, 900.0]
suspension_stiffness_n_m = [6e6, 6e6]
suspension_damping_n_s_m = [1e4, 1e4]
tyre_stiffness_n_m = [1.75e6, 1.75e6]
tyre_damping_n_s_m = [0.0, 0.0]"#,
    )
    .unwrap();
    assert_eq!(v.name, "rigid_truck");
    assert!(rel(v.axles[0].static_load_n, v.axles[1].static_load_n) < 1e-12);

    for class in TRAFFIC_CLASSES {
        let spec: VehicleModelSpec = toml::from_str(&format!(
            "kind = \"{}\"\npreset = \"{class}\"",
            kind_of(class)
        ))
        .unwrap();
        let full = match &spec {
            VehicleModelSpec::RigidTruck(_) => {
                VehicleModelSpec::RigidTruck(RigidTruckSpec::preset(class).unwrap())
            }
            _ => VehicleModelSpec::Articulated(ArticulatedSpec::preset(class).unwrap()),
        };
        let text = toml::to_string(&full).unwrap();
        let back: VehicleModelSpec = toml::from_str(&text).unwrap();
        assert_eq!(back, full, "{text}");
        assert_eq!(
            back.build(PATH).unwrap().stiffness,
            spec.build(PATH).unwrap().stiffness
        );
    }
}

#[test]
fn bad_multi_axle_inputs_name_the_field() {
    let cases = [
        ("kind = \"rigid_truck\"\npreset = \"bus\"", "preset"),
        ("kind = \"articulated\"\npreset = \"truck_3axle\"", "preset"),
        (
            "kind = \"rigid_truck\"\npreset = \"truck_3axle\"\naxle_spacing_m = [4.0, 1.3, 1.3]",
            "axle_mass_kg",
        ),
        (
            "kind = \"rigid_truck\"\npreset = \"truck_3axle\"\naxle_spacing_m = [4.0, 1.3, 1.3, 1.3]",
            "axle_spacing_m",
        ),
        (
            "kind = \"rigid_truck\"\npreset = \"truck_3axle\"\naxle_spacing_m = [4.0, -1.3]",
            "axle_spacing_m.1",
        ),
        (
            "kind = \"rigid_truck\"\npreset = \"truck_3axle\"\nsuspension_stiffness_n_m = [1e6, 0, 1e6]",
            "suspension_stiffness_n_m.1",
        ),
        (
            "kind = \"rigid_truck\"\npreset = \"car\"\ntyre_damping_n_s_m = [100, -1]",
            "tyre_damping_n_s_m.1",
        ),
        (
            "kind = \"rigid_truck\"\npreset = \"car\"\ncg_behind_front_m = 3.0",
            "cg_behind_front_m",
        ),
        (
            "kind = \"rigid_truck\"\naxle_spacing_m = [3.0]",
            "body_mass_kg",
        ),
        (
            "kind = \"articulated\"\npreset = \"artic_5axle\"\ntractor_axle_count = 5",
            "tractor_axle_count",
        ),
        (
            "kind = \"articulated\"\npreset = \"artic_5axle\"\nfifth_wheel_behind_front_m = 9.0",
            "fifth_wheel_behind_front_m",
        ),
        (
            "kind = \"articulated\"\npreset = \"artic_5axle\"\ntrailer_cg_behind_front_m = 2.0",
            "trailer_cg_behind_front_m",
        ),
        (
            "kind = \"articulated\"\npreset = \"artic_5axle\"\ntractor_body_mass_kg = nan",
            "tractor_body_mass_kg",
        ),
        (
            "kind = \"articulated\"\npreset = \"artic_5axle\"\naxle_mass_kg = [700, 1100, 750, 750]",
            "axle_mass_kg",
        ),
    ];
    for (text, field) in cases {
        let msg = from_toml(text).unwrap_err().to_string();
        assert!(
            msg.starts_with(&format!("{PATH}.{field} = ")),
            "{text}\n{msg}"
        );
    }
    let unknown: Result<VehicleModelSpec, _> =
        toml::from_str("kind = \"articulated\"\npreset = \"artic_5axle\"\nbody_mass_kg = 1.0");
    assert!(unknown.unwrap_err().to_string().contains("body_mass_kg"));
}

/// Per-vehicle variation (`VehicleDynamics::varied`, applied to generated traffic) equals
/// rebuilding the vehicle from its parameters with every spring times `f` and every
/// damper times `g`, static loads included: the rebuild solves gravity on the scaled
/// springs, so equal static loads show the drawn axle loads stay the truth.
#[test]
fn varying_springs_and_dampers_keeps_the_static_axle_loads() {
    let (f, g) = (1.17, 0.86);
    let scale = |axles: &mut [bridgetwin::physics::vehicle::AxleParams]| {
        for a in axles {
            a.suspension_stiffness_n_m *= f;
            a.tyre_stiffness_n_m *= f;
            a.suspension_damping_n_s_m *= g;
            a.tyre_damping_n_s_m *= g;
        }
    };
    let mut rigid = RigidTruckSpec::preset("truck_3axle")
        .unwrap()
        .params(PATH)
        .unwrap();
    let rigid_varied = rigid.build("x").unwrap().varied(f, g);
    scale(&mut rigid.axles);
    let mut artic = artic_params();
    let artic_varied = artic.build("x").unwrap().varied(f, g);
    scale(&mut artic.axles);
    for (varied, rebuilt) in [
        (rigid_varied, rigid.build("x").unwrap()),
        (artic_varied, artic.build("x").unwrap()),
    ] {
        let close = |a: &DMatrix<f64>, b: &DMatrix<f64>| (a - b).norm() <= 1e-12 * b.norm();
        assert!(close(&varied.stiffness, &rebuilt.stiffness));
        assert!(close(&varied.damping, &rebuilt.damping));
        for (a, b) in varied.axles.iter().zip(&rebuilt.axles) {
            assert!(rel(a.static_load_n, b.static_load_n) < 1e-9);
            assert!(rel(a.tyre_stiffness_n_m, b.tyre_stiffness_n_m) < 1e-12);
            assert!(rel(a.tyre_damping_n_s_m, b.tyre_damping_n_s_m) < 1e-12);
        }
    }
}
