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
use super::model::BridgeModel;

/// The state of the mesh's DOFs next to the supports, as the model reads it.
pub struct ReactionState<'a> {
    /// Displacement, velocity and acceleration over the model DOFs (upward positive).
    pub u: &'a DVector<f64>,
    pub v: Option<&'a DVector<f64>>,
    pub a: Option<&'a DVector<f64>>,
    /// Point loads on the girder: (x m, force N upward positive).
    pub loads: &'a [(f64, f64)],
}

impl BridgeModel {
    /// The vertical reaction of each support (N, upward positive), in the girder's support
    /// order. Damping enters as the model's Rayleigh `a0 M + a1 K`; the lumped model's
    /// masses sit off the supports, so its reactions carry no inertia of their own.
    /// Exact for finite elements; for a lumped model the field between masses is the
    /// condensation's, which leaves out the local response of a load between two masses
    /// (4e-4 of the load in the equilibrium test), and a modal model's is a truncated
    /// series.
    pub fn support_reactions(&self, state: &ReactionState) -> Vec<f64> {
        let mesh = self.mesh();
        let supports = self.beam.girder.support_positions_m();
        let tolerance = 1e-9 * self.length_m();
        supports
            .iter()
            .zip(&self.beam.girder.supports)
            .map(|(&x, support)| {
                let node = mesh
                    .node_x_m
                    .iter()
                    .position(|&n| (n - x).abs() < tolerance)
                    .expect("supports are mesh nodes");
                if !support.rigid_vertical() {
                    let w = self.mesh_value(node, 0, state.u);
                    return -support.springs().0 * w;
                }
                self.rigid_reaction(mesh, node, state)
            })
            .collect()
    }

    /// `(M a + C v + K u)_s - f_s` at the constrained w of `node`.
    fn rigid_reaction(&self, mesh: &HermiteMesh, node: usize, state: &ReactionState) -> f64 {
        let (a0, a1) = (self.rayleigh.a0_per_s, self.rayleigh.a1_s);
        let consistent = !self.diagonal_mass;
        let mut r = 0.0;
        // The element left of the node (node is its second end: local rows 2, 3) and the
        // one right of it (first end: rows 0, 1); row 0 or 2 is the node's w.
        for (e, row) in [(node.wrapping_sub(1), 2), (node, 0)] {
            let Some(element) = mesh.elements.get(e) else {
                continue;
            };
            let k = element_stiffness(element.ei_n_m2, element.length_m);
            let m = element_consistent_mass(element.mass_per_length_kg_m, element.length_m);
            let nodes = [e, e + 1];
            for col in 0..4 {
                let (n, kind) = (nodes[col / 2], col % 2);
                let u = self.mesh_value(n, kind, state.u);
                let v = state.v.map_or(0.0, |v| self.mesh_value(n, kind, v));
                let a = state.a.map_or(0.0, |a| self.mesh_value(n, kind, a));
                r += k[(row, col)] * (u + a1 * v);
                if consistent {
                    r += m[(row, col)] * (a + a0 * v);
                }
            }
            for &(x, force) in state.loads {
                let (el, xi) = mesh.locate(x);
                if el == e {
                    r -= force * shape(xi, element.length_m)[row];
                }
            }
        }
        r
    }

    /// The mesh DOF `kind` (0: w, 1: theta) of `node` for a state over the model DOFs;
    /// zero where the DOF is constrained.
    fn mesh_value(&self, node: usize, kind: usize, state: &DVector<f64>) -> f64 {
        match self.mesh().dof[node][kind] {
            Some(dof) => self.mesh_dof_value(dof, state),
            None => 0.0,
        }
    }
}
