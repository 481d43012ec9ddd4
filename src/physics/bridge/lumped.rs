//! Lumped-mass model: masses along the girder, stiffness by the flexibility method (the
//! paper's route: closed-form unit-load deflections, by the force method on a continuous
//! girder) or by static condensation of a Hermite mesh with a node at every mass (the
//! general route: sections, stiffness regions, elastic supports).

use nalgebra::{DMatrix, DVector};

use super::beam::BeamProperties;
use super::girder::{PieceKind, Support};
use super::mesh::HermiteMesh;
use crate::error::{Error, Result};

/// Deflection (downward, m per N of downward load) at `x` under a unit load at `a` on a
/// uniform simple span of length `span_m` (docs/physics.md section 2; e.g. Gere &
/// Timoshenko, Mechanics of Materials, table G-2).
fn simple_span_deflection(span_m: f64, ei_n_m2: f64, x_m: f64, a_m: f64) -> f64 {
    let l = span_m;
    let ei = ei_n_m2;
    let b = l - a_m;
    if x_m <= a_m {
        b * x_m * (l * l - b * b - x_m * x_m) / (6.0 * ei * l)
    } else {
        a_m * (l - x_m) * (2.0 * l * x_m - x_m * x_m - a_m * a_m) / (6.0 * ei * l)
    }
}

/// Deflection at `x` under a unit load at `a` on a uniform simply supported beam (its one
/// span), downward per downward newton.
pub fn unit_load_deflection_m_per_n(beam: &BeamProperties, x_m: f64, a_m: f64) -> f64 {
    simple_span_deflection(beam.length_m(), beam.flexural_rigidity_n_m2, x_m, a_m)
}

/// Abscissae of the N interior masses of one span: spacing L / (N + 1).
pub fn mass_positions_m(span_m: f64, n_masses: usize) -> Vec<f64> {
    (1..=n_masses)
        .map(|i| span_m * i as f64 / (n_masses + 1) as f64)
        .collect()
}

/// Where the lumped masses sit and what each weighs.
#[derive(Debug, Clone, PartialEq)]
pub struct MassLayout {
    pub positions_m: Vec<f64>,
    pub masses_kg: Vec<f64>,
}

/// The masses of a lumped model with `n_masses` distributed along the girder: each span
/// and overhang gets a share in proportion to its length (at least one), equally spaced
/// inside a span, out to the tip on an overhang; an elastic support, whose w is free, gets
/// one more. Each mass is the girder's mass over its tributary length (half-way to the
/// neighbouring masses or rigid supports; a rigid support takes the rest). On a uniform
/// simple span this is the paper's model: N equal masses m L / (N + 1).
pub fn mass_layout(beam: &BeamProperties, n_masses: usize) -> Result<MassLayout> {
    let girder = &beam.girder;
    if girder.is_simple_span() && beam.sections.is_empty() {
        let span = beam.length_m();
        return Ok(MassLayout {
            positions_m: mass_positions_m(span, n_masses),
            masses_kg: vec![beam.mass_per_length_kg_m * span / (n_masses + 1) as f64; n_masses],
        });
    }
    let pieces = girder.pieces();
    if n_masses < pieces.len() {
        return Err(Error::invalid(
            "bridge.model.nodes",
            n_masses,
            format!(
                "needs at least one mass per span and overhang: {}",
                pieces.len()
            ),
        ));
    }
    let length = beam.length_m();
    let mut counts: Vec<usize> = pieces
        .iter()
        .map(|p| ((p.length_m() / length * n_masses as f64).round() as usize).max(1))
        .collect();
    // Round-off of the shares: take from or give to the longest pieces.
    while counts.iter().sum::<usize>() != n_masses {
        let over = counts.iter().sum::<usize>() > n_masses;
        let pick = (0..pieces.len())
            .filter(|&i| !over || counts[i] > 1)
            .max_by(|&a, &b| {
                let per = |i: usize| pieces[i].length_m() / counts[i] as f64;
                per(a).total_cmp(&per(b)).then(b.cmp(&a))
            })
            .unwrap_or(0);
        if over {
            counts[pick] -= 1;
        } else {
            counts[pick] += 1;
        }
    }
    let mut positions = Vec::with_capacity(n_masses + girder.supports.len());
    for (piece, &k) in pieces.iter().zip(&counts) {
        let l = piece.length_m();
        match piece.kind {
            PieceKind::Span(_) => {
                positions.extend((1..=k).map(|i| piece.start_m + l * i as f64 / (k + 1) as f64))
            }
            PieceKind::OverhangLeft => {
                positions.extend((1..=k).map(|i| piece.end_m - l * i as f64 / k as f64))
            }
            PieceKind::OverhangRight => {
                positions.extend((1..=k).map(|i| piece.start_m + l * i as f64 / k as f64))
            }
        }
    }
    let supports: Vec<(f64, Support)> = girder
        .support_positions_m()
        .into_iter()
        .zip(girder.supports.iter().copied())
        .collect();
    positions.extend(
        supports
            .iter()
            .filter(|(_, s)| !s.rigid_vertical())
            .map(|&(x, _)| x),
    );
    positions.sort_by(f64::total_cmp);
    let mut anchors: Vec<(f64, bool)> = positions.iter().map(|&x| (x, true)).collect();
    anchors.extend(
        supports
            .iter()
            .filter(|(_, s)| s.rigid_vertical())
            .map(|&(x, _)| (x, false)),
    );
    anchors.sort_by(|a, b| a.0.total_cmp(&b.0));
    let masses = anchors
        .iter()
        .enumerate()
        .filter(|(_, (_, is_mass))| *is_mass)
        .map(|(j, &(x, _))| {
            let lo = j.checked_sub(1).map_or(x, |p| 0.5 * (anchors[p].0 + x));
            let hi = anchors.get(j + 1).map_or(x, |n| 0.5 * (x + n.0));
            beam.mass_between_kg(lo, hi)
        })
        .collect();
    Ok(MassLayout {
        positions_m: positions,
        masses_kg: masses,
    })
}

/// Whether the closed-form flexibility (force method) applies: a uniform girder of one
/// or more spans on rigid supports, clamped only at an end without an overhang.
pub fn force_method_applies(beam: &BeamProperties) -> bool {
    let g = &beam.girder;
    let n = g.spans_m.len();
    let fixed_ok = g.supports.iter().enumerate().all(|(i, s)| match s {
        Support::Pinned | Support::Roller => true,
        Support::Fixed => {
            (i == 0 && g.overhang_left_m == 0.0) || (i == n && g.overhang_right_m == 0.0)
        }
        Support::Elastic { .. } => false,
    });
    n >= 1 && beam.is_uniform() && fixed_ok
}

/// Unit-load deflections of a continuous girder by the force method.
///
/// The primary structure is the chain of simple spans; the redundants are the support
/// moments M_i (sagging positive). Slope continuity at each interior support is
/// Clapeyron's three-moment equation,
/// `c_i M_(i-1) + 2 (c_i + c_(i+1)) M_i + c_(i+1) M_(i+1) = theta_a(i+1) - theta_b(i)`,
/// with `c = l / (6 EI)` and `theta_a`, `theta_b` the end slopes the load gives its
/// simple span; a clamped end adds `theta = 0` there, and an overhang fixes its support's
/// moment to the cantilever moment of the load on it. The deflection is then each span's
/// simple-beam deflection plus that of its end moments; an overhang rotates with its
/// support and bends as a cantilever (docs/physics.md section 2).
pub struct ForceMethod {
    supports_m: Vec<f64>,
    spans_m: Vec<f64>,
    ei_n_m2: f64,
    fixed: [bool; 2],
    /// LU of the moment equations (they do not depend on the load).
    lu: nalgebra::linalg::LU<f64, nalgebra::Dyn, nalgebra::Dyn>,
}

/// Where a point lies: in span `j` at local `xi`, or on an overhang at distance `d` from
/// its support (0 left, 1 right).
#[derive(Debug, Clone, Copy)]
enum Place {
    Span(usize, f64),
    Overhang(usize, f64),
}

impl ForceMethod {
    /// The moment equations of `beam`'s girder; `None` where the method does not apply.
    pub fn new(beam: &BeamProperties) -> Option<Self> {
        if !force_method_applies(beam) {
            return None;
        }
        let g = &beam.girder;
        let n = g.spans_m.len();
        let ei = beam.flexural_rigidity_n_m2;
        let c = |j: usize| g.spans_m[j] / (6.0 * ei);
        let fixed = [
            g.supports[0].rigid_rotation(),
            g.supports[n].rigid_rotation(),
        ];
        let mut a = DMatrix::zeros(n + 1, n + 1);
        for i in 0..=n {
            let interior = i > 0 && i < n;
            if interior {
                a[(i, i - 1)] = c(i - 1);
                a[(i, i)] = 2.0 * (c(i - 1) + c(i));
                a[(i, i + 1)] = c(i);
            } else if i == 0 && fixed[0] {
                a[(0, 0)] = 2.0 * c(0);
                a[(0, 1)] = c(0);
            } else if i == n && fixed[1] {
                a[(n, n - 1)] = c(n - 1);
                a[(n, n)] = 2.0 * c(n - 1);
            } else {
                a[(i, i)] = 1.0;
            }
        }
        Some(ForceMethod {
            supports_m: g.support_positions_m(),
            spans_m: g.spans_m.clone(),
            ei_n_m2: ei,
            fixed,
            lu: a.lu(),
        })
    }

    fn place(&self, x_m: f64) -> Place {
        let n = self.spans_m.len();
        if x_m < self.supports_m[0] {
            return Place::Overhang(0, self.supports_m[0] - x_m);
        }
        if x_m > self.supports_m[n] {
            return Place::Overhang(1, x_m - self.supports_m[n]);
        }
        let j = self.supports_m[1..n]
            .partition_point(|&s| s < x_m)
            .min(n - 1);
        Place::Span(j, x_m - self.supports_m[j])
    }

    /// End slopes (theta_a, theta_b) of simple span `j` under a downward unit load at `xi`.
    fn load_slopes(&self, j: usize, xi: f64) -> (f64, f64) {
        let l = self.spans_m[j];
        let b = l - xi;
        let k = xi * b / (6.0 * self.ei_n_m2 * l);
        (-k * (l + b), k * (l + xi))
    }

    /// The support moments (N m, sagging positive) under a downward unit load at `a_m`.
    pub fn support_moments(&self, a_m: f64) -> DVector<f64> {
        let n = self.spans_m.len();
        let mut rhs = DVector::zeros(n + 1);
        match self.place(a_m) {
            Place::Span(j, xi) => {
                let (theta_a, theta_b) = self.load_slopes(j, xi);
                // Equation j (the span's left support) and j + 1 (its right support).
                if j > 0 || self.fixed[0] {
                    rhs[j] += theta_a;
                }
                if j + 1 < n || self.fixed[1] {
                    rhs[j + 1] -= theta_b;
                }
            }
            Place::Overhang(side, d) => rhs[side * n] = -d,
        }
        self.lu.solve(&rhs).unwrap_or(rhs)
    }

    /// Downward deflection at `x_m` per downward newton at `a_m`.
    pub fn deflection_m_per_n(&self, x_m: f64, a_m: f64) -> f64 {
        self.deflection_with_moments(x_m, a_m, &self.support_moments(a_m))
    }

    /// [`Self::deflection_m_per_n`] with the support moments of the load at `a_m` given
    /// (they depend on the load only: one solve per column of a flexibility matrix).
    fn deflection_with_moments(&self, x_m: f64, a_m: f64, m: &DVector<f64>) -> f64 {
        let ei = self.ei_n_m2;
        let load = self.place(a_m);
        let n = self.spans_m.len();
        // Upward w, then negated.
        let w = match self.place(x_m) {
            Place::Span(j, xi) => {
                let l = self.spans_m[j];
                let t = xi / l;
                let u = 1.0 - t;
                let from_moments =
                    l * l / (6.0 * ei) * (m[j] * (u * u * u - u) + m[j + 1] * (t * t * t - t));
                let from_load = match load {
                    Place::Span(k, a) if k == j => -simple_span_deflection(l, ei, xi, a),
                    _ => 0.0,
                };
                from_moments + from_load
            }
            Place::Overhang(side, c) => {
                let (span, sign) = if side == 0 { (0, -1.0) } else { (n - 1, 1.0) };
                let l = self.spans_m[span];
                let (mut theta_a, mut theta_b) = (
                    -l / (6.0 * ei) * (2.0 * m[0] + m[1]),
                    l / (6.0 * ei) * (m[n - 1] + 2.0 * m[n]),
                );
                if let Place::Span(k, a) = load {
                    let (ta, tb) = self.load_slopes(k, a);
                    if k == 0 {
                        theta_a += ta;
                    }
                    if k == n - 1 {
                        theta_b += tb;
                    }
                }
                let theta = if side == 0 { theta_a } else { theta_b };
                let cantilever = match load {
                    Place::Overhang(s, d) if s == side => {
                        let (near, far) = if c <= d { (c, d) } else { (d, c) };
                        -near * near * (3.0 * far - near) / (6.0 * ei)
                    }
                    _ => 0.0,
                };
                sign * theta * c + cantilever
            }
        };
        -w
    }
}

/// The flexibility matrix F (m/N) of masses at `positions_m`: F_ij = deflection at x_i
/// under a unit load at x_j, by the force method.
pub fn flexibility_matrix(beam: &BeamProperties, positions_m: &[f64]) -> Result<DMatrix<f64>> {
    let n = positions_m.len();
    if beam.girder.is_simple_span() {
        return Ok(DMatrix::from_fn(n, n, |i, j| {
            unit_load_deflection_m_per_n(beam, positions_m[i], positions_m[j])
        }));
    }
    let method = ForceMethod::new(beam).ok_or_else(|| {
        Error::invalid(
            "bridge.model.stiffness",
            "flexibility",
            "the closed-form flexibility needs a uniform girder on rigid supports (clamped \
             only at an end without an overhang); use \"condensation\"",
        )
    })?;
    let mut f = DMatrix::zeros(n, n);
    for (j, &a) in positions_m.iter().enumerate() {
        let moments = method.support_moments(a);
        for (i, &x) in positions_m.iter().enumerate() {
            f[(i, j)] = method.deflection_with_moments(x, a, &moments);
        }
    }
    Ok(f)
}

/// K = F^-1 by Cholesky (F is symmetric positive definite). Only for uniform girders on
/// rigid supports.
pub fn stiffness_by_flexibility(
    beam: &BeamProperties,
    positions_m: &[f64],
) -> Result<DMatrix<f64>> {
    if !beam.is_uniform() {
        return Err(Error::invalid(
            "bridge.stiffness_regions",
            beam.stiffness_regions.len(),
            "closed-form flexibility needs a uniform beam; use the condensation route",
        ));
    }
    let f = flexibility_matrix(beam, positions_m)?;
    let chol = f.cholesky().ok_or_else(|| Error::Factorization {
        what: "flexibility matrix".into(),
        reason: "not positive definite".into(),
    })?;
    let k = chol.inverse();
    // Symmetrize the round-off so that later Cholesky factorizations see an exact mirror.
    Ok((&k + k.transpose()) * 0.5)
}

/// The Hermite mesh with nodes at the girder's ends, supports, section edges and at
/// every mass.
pub fn condensation_mesh(beam: &BeamProperties, positions_m: &[f64]) -> HermiteMesh {
    let length = beam.length_m();
    let mut nodes = vec![0.0];
    nodes.extend(positions_m.iter().copied());
    nodes.push(length);
    if !(beam.girder.is_simple_span() && beam.sections.is_empty()) {
        nodes.extend(beam.girder.support_positions_m());
        nodes.extend(beam.sections.iter().flat_map(|s| [s.start_m, s.end_m]));
        nodes.sort_by(f64::total_cmp);
        nodes.dedup_by(|a, b| (*a - *b).abs() <= 1e-9 * length);
    }
    HermiteMesh::new(beam, nodes)
}

/// The w equations of `mesh` at `positions_m` (the lumped model's DOFs), in order.
pub fn mass_dofs(mesh: &HermiteMesh, positions_m: &[f64]) -> Vec<usize> {
    positions_m
        .iter()
        .filter_map(|&x| {
            let node = mesh
                .node_x_m
                .partition_point(|&n| n < x - 1e-9 * mesh.node_x_m[mesh.node_x_m.len() - 1]);
            mesh.dof.get(node).and_then(|d| d[0])
        })
        .collect()
}

/// Static condensation of a Hermite model onto the equations `kept`.
///
/// `K_c = K_kk - K_kr K_rr^-1 K_rk` (r: every other equation); also returns `T`
/// (n_full x n_kept) such that the full DOF vector of a state loaded only at the kept
/// equations is `T u`: it maps point operators of the mesh onto the condensed DOFs
/// (`h_c = T^T h`).
pub struct Condensation {
    pub stiffness: DMatrix<f64>,
    pub transform: DMatrix<f64>,
}

/// Condenses `mesh` onto the equations `kept`.
pub fn condense(mesh: &HermiteMesh, kept: &[usize]) -> Result<Condensation> {
    let k = mesh.stiffness();
    let mut is_kept = vec![false; mesh.n_dof];
    for &d in kept {
        is_kept[d] = true;
    }
    let rest: Vec<usize> = (0..mesh.n_dof).filter(|&d| !is_kept[d]).collect();
    let k_tt = k.select_rows(&rest).select_columns(&rest);
    let k_tw = k.select_rows(&rest).select_columns(kept);
    let k_ww = k.select_rows(kept).select_columns(kept);
    let chol = k_tt.cholesky().ok_or_else(|| Error::Factorization {
        what: "condensed-out stiffness block".into(),
        reason: "not positive definite".into(),
    })?;
    // theta = -K_tt^-1 K_tw w
    let theta_from_w = -chol.solve(&k_tw);
    let stiffness = &k_ww + k_tw.transpose() * &theta_from_w;
    let mut transform = DMatrix::zeros(mesh.n_dof, kept.len());
    for (col, &dof) in kept.iter().enumerate() {
        transform[(dof, col)] = 1.0;
    }
    for (row, &dof) in rest.iter().enumerate() {
        transform.row_mut(dof).copy_from(&theta_from_w.row(row));
    }
    let stiffness = (&stiffness + stiffness.transpose()) * 0.5;
    Ok(Condensation {
        stiffness,
        transform,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn flexibility_is_symmetric_and_matches_midspan_formula() {
        let beam = BeamProperties::paper_default();
        // P L^3 / 48 EI at midspan for a load at midspan.
        let l = beam.length_m();
        let d = unit_load_deflection_m_per_n(&beam, l / 2.0, l / 2.0);
        let expected = l.powi(3) / (48.0 * beam.flexural_rigidity_n_m2);
        assert!((d - expected).abs() < 1e-12 * expected);
        // Maxwell reciprocity.
        let a = unit_load_deflection_m_per_n(&beam, 7.0, 19.0);
        let b = unit_load_deflection_m_per_n(&beam, 19.0, 7.0);
        assert!((a - b).abs() < 1e-12 * a.abs());
    }

    #[test]
    fn flexibility_and_condensation_give_the_same_stiffness() {
        // Both routes are exact for a uniform beam (Hermite cubics are the exact static
        // solution between nodal loads), so only round-off separates them: 1e-9 relative
        // (the condition number of K grows as N^4: ~1e8 at N = 100).
        let beam = BeamProperties::paper_default();
        for n in [7, 20, 50, 100] {
            let x = mass_positions_m(beam.length_m(), n);
            let kf = stiffness_by_flexibility(&beam, &x).unwrap();
            let mesh = condensation_mesh(&beam, &x);
            let kc = condense(&mesh, &mass_dofs(&mesh, &x)).unwrap().stiffness;
            let rel = (&kf - &kc).norm() / kc.norm();
            assert!(rel < 1e-9, "n = {n}: relative difference {rel:e}");
        }
    }
}
