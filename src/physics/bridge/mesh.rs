//! A Hermite beam mesh: nodes, elements, supports and the map from node DOFs to
//! equation numbers. Both the finite-element model and the lumped-mass model (through
//! static condensation) are built on it, which is what lets non-uniform EI and more
//! supports enter without a rewrite.

use nalgebra::DMatrix;

use super::beam::BeamProperties;
use super::girder::Support;
use super::hermite::{
    element_consistent_mass, element_stiffness, shape, shape_dx, shape_dxx, ShapeValues,
};
use super::sparse::SparseVec;
use crate::physics::linalg::SymBand;

/// One beam element between nodes `i` and `i + 1`.
#[derive(Debug, Clone)]
pub struct Element {
    pub length_m: f64,
    pub ei_n_m2: f64,
    pub mass_per_length_kg_m: f64,
}

/// Nodes along the girder with (w, theta) DOFs; w is fixed at rigid supports, theta too
/// at fixed ones, and elastic supports put their springs on the diagonal.
#[derive(Debug, Clone)]
pub struct HermiteMesh {
    /// Node abscissae, strictly increasing, first 0 and last the girder's length (m).
    pub node_x_m: Vec<f64>,
    pub elements: Vec<Element>,
    /// Equation number of (w, theta) at each node; `None` where constrained.
    pub dof: Vec<[Option<usize>; 2]>,
    pub n_dof: usize,
    /// Support springs: (equation, stiffness in N/m or N m/rad).
    pub springs: Vec<(usize, f64)>,
}

/// Which quantity a point operator interpolates.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PointQuantity {
    /// w(x): also the consistent load vector of a unit force.
    Deflection,
    /// dw/dx(x).
    Slope,
    /// EI w''(x): the bending moment (sagging positive).
    Moment,
}

impl HermiteMesh {
    /// A mesh with the given node abscissae and the girder's supports (which must be
    /// nodes). EI and mass per element are the means over the element.
    pub fn new(beam: &BeamProperties, node_x_m: Vec<f64>) -> Self {
        let elements = node_x_m
            .windows(2)
            .map(|pair| Element {
                length_m: pair[1] - pair[0],
                ei_n_m2: beam.mean_ei_n_m2(pair[0], pair[1]),
                mass_per_length_kg_m: beam.mean_mass_kg_m(pair[0], pair[1]),
            })
            .collect();
        let tolerance_m = 1e-9 * beam.length_m();
        let supports: Vec<(f64, Support)> = beam
            .girder
            .support_positions_m()
            .into_iter()
            .zip(beam.girder.supports.iter().copied())
            .collect();
        let mut n_dof = 0;
        let mut springs = Vec::new();
        let mut next = |free: bool| {
            free.then(|| {
                n_dof += 1;
                n_dof - 1
            })
        };
        let mut dof = Vec::with_capacity(node_x_m.len());
        for &x in &node_x_m {
            let support = supports
                .iter()
                .find(|(s, _)| (s - x).abs() < tolerance_m)
                .map(|&(_, kind)| kind);
            let w = next(!support.is_some_and(|s| s.rigid_vertical()));
            let theta = next(!support.is_some_and(|s| s.rigid_rotation()));
            let (kv, kr) = support.map_or((0.0, 0.0), |s| s.springs());
            for (equation, k) in [(w, kv), (theta, kr)] {
                if let (Some(e), true) = (equation, k > 0.0) {
                    springs.push((e, k));
                }
            }
            dof.push([w, theta]);
        }
        HermiteMesh {
            node_x_m,
            elements,
            dof,
            n_dof,
            springs,
        }
    }

    /// The girder with about `n_elements` elements: a node at every end, support and
    /// section edge, each piece between them divided into equal elements in proportion to
    /// its length (at least one each). A single span without sections gets exactly
    /// `n_elements` equal elements.
    pub fn on_girder(beam: &BeamProperties, n_elements: usize) -> Self {
        Self::new(beam, girder_nodes(beam, n_elements))
    }

    /// Elements the mesh of [`Self::on_girder`] needs at least: one per piece between key
    /// points (ends, supports, section edges).
    pub fn min_elements(beam: &BeamProperties) -> usize {
        key_points_m(beam).len() - 1
    }

    /// Equation numbers of the element's four DOFs.
    #[inline]
    pub(super) fn element_dofs(&self, e: usize) -> [Option<usize>; 4] {
        let (a, b) = (self.dof[e], self.dof[e + 1]);
        [a[0], a[1], b[0], b[1]]
    }

    /// Assembles element matrices into the band of the free DOFs (each node's DOFs are
    /// numbered next to each other, so an element spans at most four consecutive
    /// equations: half-bandwidth 3), trimmed to the band its nonzeros need.
    fn assemble(
        &self,
        element_matrix: impl Fn(&Element) -> super::hermite::ElementMatrix,
    ) -> SymBand {
        let mut global = SymBand::zeros(self.n_dof, 3);
        for (e, element) in self.elements.iter().enumerate() {
            let local = element_matrix(element);
            let dofs = self.element_dofs(e);
            for (r, gr) in dofs.iter().enumerate() {
                let Some(gr) = gr else { continue };
                for (c, gc) in dofs.iter().enumerate() {
                    match gc {
                        // The lower triangle only: add() stands for both entries.
                        Some(gc) if gc <= gr => global.add(*gr, *gc, local[(r, c)]),
                        _ => {}
                    }
                }
            }
        }
        global.trimmed()
    }

    /// Global stiffness over the free DOFs, banded, support springs included.
    pub fn stiffness_band(&self) -> SymBand {
        let mut k = self.assemble(|e| element_stiffness(e.ei_n_m2, e.length_m));
        for &(equation, stiffness) in &self.springs {
            k.add(equation, equation, stiffness);
        }
        k
    }

    /// Global consistent mass over the free DOFs, banded.
    pub fn consistent_mass_band(&self) -> SymBand {
        self.assemble(|e| element_consistent_mass(e.mass_per_length_kg_m, e.length_m))
    }

    /// Global stiffness over the free DOFs, dense (for static condensation).
    pub fn stiffness(&self) -> DMatrix<f64> {
        self.stiffness_band().to_dense()
    }

    /// Global consistent mass over the free DOFs, dense.
    pub fn consistent_mass(&self) -> DMatrix<f64> {
        self.consistent_mass_band().to_dense()
    }

    /// The element containing `x_m` (clamped to the girder) and the local coordinate.
    #[inline]
    pub fn locate(&self, x_m: f64) -> (usize, f64) {
        let last = self.elements.len() - 1;
        // partition_point: number of nodes <= x; the element starts at the node before.
        let e = self
            .node_x_m
            .partition_point(|&node| node <= x_m)
            .saturating_sub(1)
            .min(last);
        let xi = ((x_m - self.node_x_m[e]) / self.elements[e].length_m).clamp(0.0, 1.0);
        (e, xi)
    }

    /// Fills `out` with the weights of `quantity` at `x_m` over the free DOFs.
    #[inline]
    pub fn point_operator(&self, x_m: f64, quantity: PointQuantity, out: &mut SparseVec) {
        out.clear();
        self.for_each_weight(x_m, quantity, |dof, w| out.push(dof, w));
    }

    /// `[deflection, slope]` operators at `x_m` (as two [`Self::point_operator`] calls,
    /// locating the element once: every wheel on the span needs both, every step).
    #[inline]
    pub fn wheel_operators(&self, x_m: f64, [deflection, slope]: [&mut SparseVec; 2]) {
        let (e, xi) = self.locate(x_m);
        let length_m = self.elements[e].length_m;
        let (w, dw) = (shape(xi, length_m), shape_dx(xi, length_m));
        deflection.clear();
        slope.clear();
        for (k, dof) in self.element_dofs(e).iter().enumerate() {
            if let Some(d) = *dof {
                deflection.push(d, w[k]);
                slope.push(d, dw[k]);
            }
        }
    }

    /// Calls `f(dof, weight)` for the (at most four) free DOFs that carry `quantity` at `x_m`.
    #[inline]
    pub fn for_each_weight(
        &self,
        x_m: f64,
        quantity: PointQuantity,
        mut f: impl FnMut(usize, f64),
    ) {
        let (e, xi) = self.locate(x_m);
        let element = &self.elements[e];
        let values: ShapeValues = match quantity {
            PointQuantity::Deflection => shape(xi, element.length_m),
            PointQuantity::Slope => shape_dx(xi, element.length_m),
            PointQuantity::Moment => shape_dxx(xi, element.length_m) * element.ei_n_m2,
        };
        for (k, dof) in self.element_dofs(e).iter().enumerate() {
            if let Some(d) = dof {
                f(*d, values[k]);
            }
        }
    }

    /// Indices of the translational (w) and rotational (theta) free DOFs.
    pub fn split_dofs(&self) -> (Vec<usize>, Vec<usize>) {
        let w = self.dof.iter().filter_map(|d| d[0]).collect();
        let theta = self.dof.iter().filter_map(|d| d[1]).collect();
        (w, theta)
    }
}

/// Ends, supports and section edges, ascending and distinct.
fn key_points_m(beam: &BeamProperties) -> Vec<f64> {
    let length = beam.length_m();
    let mut points: Vec<f64> = [0.0, length]
        .into_iter()
        .chain(beam.girder.support_positions_m())
        .chain(beam.sections.iter().flat_map(|s| [s.start_m, s.end_m]))
        .collect();
    points.sort_by(f64::total_cmp);
    points.dedup_by(|a, b| (*a - *b).abs() <= 1e-9 * length);
    points
}

/// Node abscissae of [`HermiteMesh::on_girder`]: `n_elements` shared among the pieces by
/// largest remainder of their length share, at least one each.
fn girder_nodes(beam: &BeamProperties, n_elements: usize) -> Vec<f64> {
    let keys = key_points_m(beam);
    let length = beam.length_m();
    let pieces = keys.len() - 1;
    let total = n_elements.max(pieces);
    let shares: Vec<f64> = keys
        .windows(2)
        .map(|w| (w[1] - w[0]) / length * total as f64)
        .collect();
    let mut counts: Vec<usize> = shares.iter().map(|s| (s.floor() as usize).max(1)).collect();
    let mut order: Vec<usize> = (0..pieces).collect();
    order.sort_by(|&a, &b| {
        let rest = |i: usize| shares[i] - counts[i] as f64;
        rest(b).total_cmp(&rest(a)).then(a.cmp(&b))
    });
    let missing = total.saturating_sub(counts.iter().sum());
    for &i in order.iter().cycle().take(missing) {
        counts[i] += 1;
    }
    let mut nodes = vec![keys[0]];
    for (w, &n) in keys.windows(2).zip(&counts) {
        let (start, piece) = (w[0], w[1] - w[0]);
        nodes.extend((1..n).map(|i| start + piece * i as f64 / n as f64));
        nodes.push(w[1]);
    }
    nodes
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn locate_finds_element_and_local_coordinate() {
        let beam = BeamProperties::paper_default();
        let mesh = HermiteMesh::on_girder(&beam, 10);
        assert_eq!(mesh.locate(0.0), (0, 0.0));
        let (e, xi) = mesh.locate(4.5);
        assert_eq!(e, 1);
        assert!((xi - 0.5).abs() < 1e-12);
        assert_eq!(mesh.locate(30.0), (9, 1.0));
        assert_eq!(mesh.n_dof, 2 * 10);
    }
}
