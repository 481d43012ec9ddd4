//! The static effect of support settlements: the girder's shape, moments and reactions
//! when its supports sink by prescribed amounts, superposed on the dynamic response.
//!
//! Settlements grow over hours to years, so their own inertia is nil and their effect is
//! the static solution with the supports displaced: `K_ff u_f = -K_fc d_c` over the mesh
//! (a rigid support's constrained w set to the settlement; an elastic support's spring
//! base moved, which loads its w by `k_v d`). The problem is linear, so one unit field per
//! support, solved once per model, gives any combination. On a statically determinate
//! girder the field is a rigid-body motion (no moment, no reaction); on a continuous one
//! it bends the girder and moves load between the supports.

use super::hermite::{element_stiffness, shape, shape_dx, shape_dxx, ShapeValues};
use super::mesh::{HermiteMesh, PointQuantity};
use super::model::BridgeModel;
use super::reactions::{neighbour_rows, support_nodes};
use crate::error::{Error, Result};
use crate::physics::linalg::BandCholesky;

/// Unit settlement fields of a model's supports.
#[derive(Debug, Clone)]
pub struct SettlementField {
    mesh: HermiteMesh,
    /// Per support: (w, theta) at every mesh node (w upward) under a unit downward
    /// settlement of that support, the others held.
    unit: Vec<Vec<[f64; 2]>>,
    /// Per settling support k, the reaction of every support j (N per m, upward on the
    /// girder): `reactions[k][j]`.
    unit_reactions: Vec<Vec<f64>>,
}

impl SettlementField {
    /// The unit fields of `model`'s supports (one banded solve each).
    pub fn new(model: &BridgeModel) -> Result<Self> {
        let mesh = model.mesh().clone();
        let factor = BandCholesky::factor(&mesh.stiffness_band()).map_err(|row| {
            Error::invalid(
                "bridge.supports",
                format!("(equation {row})"),
                "leave the girder a mechanism: no settlement field",
            )
        })?;
        let nodes = support_nodes(model);
        let springs: Vec<f64> = model
            .beam
            .girder
            .supports
            .iter()
            .map(|s| s.springs().0)
            .collect();
        let rigid: Vec<bool> = model
            .beam
            .girder
            .supports
            .iter()
            .map(|s| s.rigid_vertical())
            .collect();
        let mut unit = Vec::with_capacity(nodes.len());
        let mut unit_reactions = Vec::with_capacity(nodes.len());
        for (k, &node) in nodes.iter().enumerate() {
            let mut rhs = vec![0.0; mesh.n_dof];
            match rigid[k] {
                // w of the node is -1 (upward positive): move K_fc (-1) to the right.
                true => {
                    for (e, w) in neighbour_rows(node) {
                        let Some(element) = mesh.elements.get(e) else {
                            continue;
                        };
                        let ke = element_stiffness(element.ei_n_m2, element.length_m);
                        for row in 0..4 {
                            if let Some(dof) = mesh.dof[e + row / 2][row % 2] {
                                rhs[dof] += ke[(row, w)];
                            }
                        }
                    }
                }
                // The spring's base at -1: it pulls the node down by k_v.
                false => {
                    if let Some(dof) = mesh.dof[node][0] {
                        rhs[dof] -= springs[k];
                    }
                }
            }
            factor.solve_in_place(&mut rhs);
            let values: Vec<[f64; 2]> = (0..mesh.node_x_m.len())
                .map(|n| {
                    let w = match mesh.dof[n][0] {
                        Some(d) => rhs[d],
                        None if n == node => -1.0,
                        None => 0.0,
                    };
                    [w, mesh.dof[n][1].map_or(0.0, |d| rhs[d])]
                })
                .collect();
            let reactions = nodes
                .iter()
                .enumerate()
                .map(|(j, &m)| match rigid[j] {
                    true => rigid_reaction(&mesh, m, &values),
                    false => {
                        let base = if j == k { -1.0 } else { 0.0 };
                        -springs[j] * (values[m][0] - base)
                    }
                })
                .collect();
            unit.push(values);
            unit_reactions.push(reactions);
        }
        Ok(Self {
            mesh,
            unit,
            unit_reactions,
        })
    }

    /// The node values (w upward, theta) for downward settlements `settlement_m`, one per
    /// support.
    pub fn node_values(&self, settlement_m: &[f64]) -> Vec<[f64; 2]> {
        let mut out = vec![[0.0; 2]; self.mesh.node_x_m.len()];
        for (field, &d) in self.unit.iter().zip(settlement_m) {
            if d == 0.0 {
                continue;
            }
            for (o, v) in out.iter_mut().zip(field) {
                o[0] += d * v[0];
                o[1] += d * v[1];
            }
        }
        out
    }

    /// `quantity` at `x_m` of the field with `node_values` (w upward; moment sagging
    /// positive).
    pub fn read(&self, node_values: &[[f64; 2]], x_m: f64, quantity: PointQuantity) -> f64 {
        let (e, xi) = self.mesh.locate(x_m);
        let element = &self.mesh.elements[e];
        let weights: ShapeValues = match quantity {
            PointQuantity::Deflection => shape(xi, element.length_m),
            PointQuantity::Slope => shape_dx(xi, element.length_m),
            PointQuantity::Moment => shape_dxx(xi, element.length_m) * element.ei_n_m2,
        };
        let (a, b) = (node_values[e], node_values[e + 1]);
        weights.dot(&ShapeValues::new(a[0], a[1], b[0], b[1]))
    }

    /// The reactions (N, upward on the girder) the settlements cause at every support.
    pub fn reactions(&self, settlement_m: &[f64], out: &mut [f64]) {
        out.iter_mut().for_each(|r| *r = 0.0);
        for (unit, &d) in self.unit_reactions.iter().zip(settlement_m) {
            for (r, u) in out.iter_mut().zip(unit) {
                *r += d * u;
            }
        }
    }
}

/// The reaction of the rigid support at `node` for full node values: its constrained
/// row of `K u` from the elements either side.
fn rigid_reaction(mesh: &HermiteMesh, node: usize, values: &[[f64; 2]]) -> f64 {
    let mut r = 0.0;
    for (e, w) in neighbour_rows(node) {
        let Some(element) = mesh.elements.get(e) else {
            continue;
        };
        let ke = element_stiffness(element.ei_n_m2, element.length_m);
        for col in 0..4 {
            r += ke[(w, col)] * values[e + col / 2][col % 2];
        }
    }
    r
}
