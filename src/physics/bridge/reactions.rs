//! Support reactions: the forces the supports exert on the girder (upward positive).
//!
//! A rigid support's reaction is what its constrained equation would carry,
//! `r = (M a + C v + K u)_s - f_s` over the full mesh DOFs (the constrained ones at zero),
//! summed from the elements either side of it; the load a wheel puts straight on the
//! constrained DOF (`f_s`, from the shape functions of the element it stands on) goes to
//! the support. An elastic support's reaction is its spring force, `-k_v w`.

use nalgebra::DVector;

use super::hermite::{element_consistent_mass, element_stiffness, shape};
use super::mesh::HermiteMesh;
use super::model::{BridgeModel, Reduction};
use super::sparse::SparseVec;

/// The state of the mesh's DOFs next to the supports, as the model reads it.
pub struct ReactionState<'a> {
    /// Displacement, velocity and acceleration over the model DOFs (upward positive).
    pub u: &'a DVector<f64>,
    pub v: Option<&'a DVector<f64>>,
    pub a: Option<&'a DVector<f64>>,
    /// Point loads on the girder: (x m, force N upward positive).
    pub loads: &'a [(f64, f64)],
}

/// How one support's reaction is read from the state.
#[derive(Debug, Clone)]
enum SupportRow {
    /// A rigid vertical support at mesh node `node`: `r = k.(u + a1 v) + m.(a + a0 v)`
    /// minus the wheel loads on the elements either side, distributed by their shape
    /// functions onto the node's w.
    Rigid {
        node: usize,
        stiffness: SparseVec,
        mass: SparseVec,
    },
    /// An elastic support: its spring force `-k_v w`.
    Spring { deflection: SparseVec, k_n_m: f64 },
}

/// The support reactions of a model as operators over its DOFs, built once (per model
/// build) so that reading them every time step costs a few dot products and no
/// allocation.
#[derive(Debug, Clone)]
pub struct ReactionOperator {
    rows: Vec<SupportRow>,
    /// Rayleigh coefficients of the model's damping (`C = a0 M + a1 K`).
    a0_per_s: f64,
    a1_s: f64,
    mesh: HermiteMesh,
}

impl ReactionOperator {
    /// The operator of `model`'s supports, in the girder's order.
    pub fn new(model: &BridgeModel) -> Self {
        let mesh = model.mesh();
        let rows = support_nodes(model)
            .into_iter()
            .zip(&model.beam.girder.supports)
            .map(|(node, support)| match support.rigid_vertical() {
                false => {
                    let mut deflection = SparseVec::default();
                    model.push_mesh_dof(mesh.dof[node][0], 1.0, &mut deflection);
                    SupportRow::Spring {
                        deflection,
                        k_n_m: support.springs().0,
                    }
                }
                true => rigid_row(model, node),
            })
            .collect();
        Self {
            rows,
            a0_per_s: model.rayleigh.a0_per_s,
            a1_s: model.rayleigh.a1_s,
            mesh: mesh.clone(),
        }
    }

    /// Number of supports.
    pub fn len(&self) -> usize {
        self.rows.len()
    }

    /// True for a girder without supports (never built: a girder has at least two).
    pub fn is_empty(&self) -> bool {
        self.rows.is_empty()
    }

    /// The reactions (N, upward positive) into `out` (one per support).
    pub fn reactions(&self, state: &ReactionState, out: &mut [f64]) {
        for (row, r) in self.rows.iter().zip(out.iter_mut()) {
            *r = match row {
                SupportRow::Spring { deflection, k_n_m } => -k_n_m * deflection.dot(state.u),
                SupportRow::Rigid {
                    node,
                    stiffness,
                    mass,
                } => {
                    let dot =
                        |op: &SparseVec, x: Option<&DVector<f64>>| x.map_or(0.0, |x| op.dot(x));
                    let v_k = dot(stiffness, state.v);
                    let v_m = dot(mass, state.v);
                    stiffness.dot(state.u)
                        + self.a1_s * v_k
                        + dot(mass, state.a)
                        + self.a0_per_s * v_m
                        - self.direct_load(*node, state.loads)
                }
            };
        }
    }

    /// The share of the point loads that the shape functions of the elements either side
    /// of `node` put on its (constrained) w.
    fn direct_load(&self, node: usize, loads: &[(f64, f64)]) -> f64 {
        let mut f = 0.0;
        for &(x, force) in loads {
            let (e, xi) = self.mesh.locate(x);
            let row = match e {
                e if e + 1 == node => 2,
                e if e == node => 0,
                _ => continue,
            };
            f += force * shape(xi, self.mesh.elements[e].length_m)[row];
        }
        f
    }
}

/// The mesh node of each support of `model`, in the girder's order.
pub(super) fn support_nodes(model: &BridgeModel) -> Vec<usize> {
    let mesh = model.mesh();
    let tolerance = 1e-9 * model.length_m();
    model
        .beam
        .girder
        .support_positions_m()
        .iter()
        .map(|&x| {
            mesh.node_x_m
                .iter()
                .position(|&n| (n - x).abs() < tolerance)
                .expect("supports are mesh nodes")
        })
        .collect()
}

/// The elements either side of `node` with the local row of its w in each: the one left
/// of it (node is its second end: row 2) and the one right of it (first end: row 0). At
/// the girder's ends one index is out of range; callers skip it.
pub(super) fn neighbour_rows(node: usize) -> [(usize, usize); 2] {
    [(node.wrapping_sub(1), 2), (node, 0)]
}

/// The stiffness and mass rows of the constrained w of `node` over the model DOFs, from
/// the element left of the node (node is its second end: local row 2) and the one right
/// of it (first end: row 0).
fn rigid_row(model: &BridgeModel, node: usize) -> SupportRow {
    let mesh = model.mesh();
    let mut stiffness = SparseVec::default();
    let mut mass = SparseVec::default();
    for (e, row) in neighbour_rows(node) {
        let Some(element) = mesh.elements.get(e) else {
            continue;
        };
        let k = element_stiffness(element.ei_n_m2, element.length_m);
        let m = element_consistent_mass(element.mass_per_length_kg_m, element.length_m);
        for col in 0..4 {
            let dof = mesh.dof[e + col / 2][col % 2];
            model.push_mesh_dof(dof, k[(row, col)], &mut stiffness);
            // The lumped model's masses sit off the supports: no inertia of its own.
            if !model.diagonal_mass {
                model.push_mesh_dof(dof, m[(row, col)], &mut mass);
            }
        }
    }
    SupportRow::Rigid {
        node,
        stiffness,
        mass,
    }
}

impl BridgeModel {
    /// The vertical reaction of each support (N, upward positive), in the girder's support
    /// order. Damping enters as the model's Rayleigh `a0 M + a1 K`; the lumped model's
    /// masses sit off the supports, so its reactions carry no inertia of their own.
    /// Exact for finite elements; for a lumped model the field between masses is the
    /// condensation's, which leaves out the local response of a load between two masses
    /// (4e-4 of the load in the equilibrium test), and a modal model's is a truncated
    /// series. For every step of a run build a [`ReactionOperator`] once instead.
    pub fn support_reactions(&self, state: &ReactionState) -> Vec<f64> {
        let op = ReactionOperator::new(self);
        let mut out = vec![0.0; op.len()];
        op.reactions(state, &mut out);
        out
    }

    /// Appends `weight` times mesh DOF `dof` (a model DOF, or a row of the reduction)
    /// to `out`; nothing for a constrained DOF.
    pub(super) fn push_mesh_dof(&self, dof: Option<usize>, weight: f64, out: &mut SparseVec) {
        let Some(dof) = dof else {
            return;
        };
        match &self.reduction {
            Reduction::Identity => out.push(dof, weight),
            Reduction::Dense(t) => {
                for (j, value) in t.row(dof).iter().enumerate() {
                    out.push(j, weight * value);
                }
            }
        }
    }
}
