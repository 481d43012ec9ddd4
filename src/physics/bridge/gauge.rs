//! The bending moment at a gauge, recovered from the equilibrium of the element it sits
//! in rather than interpolated.
//!
//! Inside a Hermite element the interpolated curvature is linear, while a wheel in the
//! element puts a kink in the true moment diagram: interpolation is then off by up to
//! `P l / 8` (percent of the span's moment with 30 elements). The model's state fixes the
//! element's end displacements; with those held, the element is a beam clamped at both
//! ends under the loads inside it, plus the cubic that the end displacements alone give.
//! So the moment at `x` is the interpolated one plus the fixed-end moment at `x` of every
//! load inside the element: the same as the element's end forces `K_e u_e - f_e` carried
//! along the element by statics (`f_e`, the fixed-end forces, is the consistent load
//! vector). With the nodal displacements of the Hermite model (exact for static loads)
//! the moment is exact for any element size and any position in the element.
//!
//! The element's own distributed inertia and mass-proportional damping, `-m (a + a0 v)`
//! interpolated by the shape functions as the consistent mass does, load it too and enter
//! the same way. The stiffness-proportional part of Rayleigh damping is a viscous stress,
//! not a strain: the gauge reads the elastic moment `EI w''`, as a strain gauge reads
//! strain. At a node the two elements either side give the same moment when the node's
//! rotation equation holds; their mean keeps a mirrored passage the mirror image.
//!
//! A reduced model (lumped masses, modes) does not carry the whole static field of a load
//! in its state: the lumped model's condensed rotations miss the load's own share on them,
//! a modal model misses the modes it dropped. Both respond to a load quasi-statically
//! there (massless DOFs; modes far above the load's content), so the gauge adds the
//! missing static part, `g^T (K_mesh^-1 - T K_model^-1 T^T) h(x) F` per load: the mode
//! acceleration method (Craig and Kurdila, "Fundamentals of Structural Dynamics", 2006,
//! section 14.5), which for the lumped model is its static condensation made exact.

use std::sync::Arc;

use nalgebra::{Cholesky, DMatrix, DVector, Dyn};

use super::beam::GAUSS_4;
use super::hermite::{shape, shape_dxx};
use super::mesh::{HermiteMesh, PointQuantity};
use super::model::{BridgeModel, Reduction};
use super::sparse::SparseVec;
use crate::error::{Error, Result};
use crate::physics::linalg::{BandCholesky, SymMatrix};

/// The sagging moment at local abscissa `x_m` of a beam of length `length_m` clamped at
/// both ends, under a unit upward force at local abscissa `s_m` (N m per N): the
/// fixed-end moments `a b^2 / l^2`, `a^2 b / l^2` and the left reaction
/// `b^2 (3a + b) / l^3` of a point load (Roark's Formulas, table 8.1 case 1c), with the
/// sign of an upward force.
#[inline]
pub fn fixed_end_moment_m(x_m: f64, s_m: f64, length_m: f64) -> f64 {
    let l = length_m;
    let (a, b) = (s_m, l - s_m);
    let reaction = b * b * (3.0 * a + b) / (l * l * l);
    a * b * b / (l * l) - reaction * x_m + (x_m - s_m).max(0.0)
}

/// One element's share of a gauge.
#[derive(Debug, Clone, Default)]
struct Side {
    /// Start of the element and its length (m).
    start_m: f64,
    length_m: f64,
    /// The gauge's local abscissa in the element (m).
    local_m: f64,
    /// `EI w''` of the interpolated field over the model DOFs.
    elastic: SparseVec,
    /// Fixed-end moment of the element's distributed inertia per unit of `a + a0 v`, over
    /// the model DOFs (empty when the model's mass sits on its nodes).
    inertia: SparseVec,
    /// The static moment a reduced model leaves out, per unit load, over the mesh DOFs:
    /// `(K_mesh^-1 - T K_model^-1 T^T) g` (empty for a finite-element model).
    missing_static: Vec<f64>,
}

/// The factors a reduced model's gauges need for the static part it leaves out, built
/// once per model for all its gauges (`None` parts for a finite-element model).
pub struct GaugeFactors {
    mesh: Arc<HermiteMesh>,
    reduced: Option<ReducedStatics>,
}

/// The two static solves of a reduced model.
struct ReducedStatics {
    mesh_stiffness: BandCholesky,
    model_stiffness: ModelSolve,
    transform: DMatrix<f64>,
}

/// `K_model^-1`: diagonal for modes, dense for lumped masses.
enum ModelSolve {
    Diagonal(DVector<f64>),
    Dense(Cholesky<f64, Dyn>),
}

impl GaugeFactors {
    /// The factors of `model` (one band and, for a lumped model, one dense Cholesky).
    pub fn new(model: &BridgeModel) -> Result<Self> {
        let mesh = Arc::new(model.mesh().clone());
        let Reduction::Dense(transform) = &model.reduction else {
            return Ok(GaugeFactors {
                mesh,
                reduced: None,
            });
        };
        let singular = |what: &str| {
            Error::invalid(
                "bridge.model",
                model.spec.label(),
                format!("its {what} stiffness is not positive definite (a moment gauge needs it)"),
            )
        };
        let mesh_stiffness =
            BandCholesky::factor(&mesh.stiffness_band()).map_err(|_| singular("mesh"))?;
        let model_stiffness = match &model.stiffness {
            SymMatrix::Diagonal(d) => ModelSolve::Diagonal(d.clone()),
            other => {
                ModelSolve::Dense(Cholesky::new(other.to_dense()).ok_or_else(|| singular("model"))?)
            }
        };
        Ok(GaugeFactors {
            mesh,
            reduced: Some(ReducedStatics {
                mesh_stiffness,
                model_stiffness,
                transform: transform.clone(),
            }),
        })
    }

    /// `(K_mesh^-1 - T K_model^-1 T^T) g` for mesh weights `g`.
    fn missing_static(&self, g: &[(Option<usize>, f64)]) -> Vec<f64> {
        let Some(r) = &self.reduced else {
            return Vec::new();
        };
        let mut full = vec![0.0; self.mesh.n_dof];
        for &(dof, w) in g {
            if let Some(d) = dof {
                full[d] += w;
            }
        }
        let g_mesh = DVector::from_column_slice(&full);
        r.mesh_stiffness.solve_in_place(&mut full);
        let mut reduced = r.transform.tr_mul(&g_mesh);
        match &r.model_stiffness {
            ModelSolve::Diagonal(k) => reduced.component_div_assign(k),
            ModelSolve::Dense(c) => c.solve_mut(&mut reduced),
        }
        let kept = &r.transform * reduced;
        full.iter_mut().zip(kept.iter()).for_each(|(f, k)| *f -= k);
        full
    }
}

/// The operators of the bending moment at one point of the girder, built once per model.
#[derive(Clone, Default)]
pub struct MomentGauge {
    sides: Vec<Side>,
    /// The model's mass-proportional damping coefficient `a0` (1/s).
    a0_per_s: f64,
    /// The mesh, for a reduced model's missing static part (where a load's shape
    /// functions fall).
    mesh: Option<Arc<HermiteMesh>>,
}

impl std::fmt::Debug for MomentGauge {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("MomentGauge")
            .field("elements", &self.sides.len())
            .field("reduced", &self.mesh.is_some())
            .finish()
    }
}

/// The bridge state a gauge reads: displacement, velocity and acceleration over the
/// model DOFs (upward positive), and the point loads on the girder this step (x m,
/// force N upward positive), every load the solver put on the deck.
pub struct GaugeState<'a> {
    pub u: &'a DVector<f64>,
    pub v: &'a DVector<f64>,
    pub a: &'a DVector<f64>,
    pub loads: &'a [(f64, f64)],
}

impl MomentGauge {
    /// The gauge at `x_m` on `model` (empty off the girder: it then reads zero). Builds
    /// the model's [`GaugeFactors`]: for many gauges on one model build them once and
    /// use [`MomentGauge::with_factors`].
    pub fn new(model: &BridgeModel, x_m: f64) -> Result<Self> {
        Ok(Self::with_factors(model, &GaugeFactors::new(model)?, x_m))
    }

    /// The gauge at `x_m` on `model`, whose factors are `factors`.
    pub fn with_factors(model: &BridgeModel, factors: &GaugeFactors, x_m: f64) -> Self {
        let mut gauge = MomentGauge {
            sides: Vec::new(),
            a0_per_s: model.rayleigh.a0_per_s,
            mesh: factors.reduced.as_ref().map(|_| factors.mesh.clone()),
        };
        if !model.on_girder(x_m) {
            return gauge;
        }
        let mesh = model.mesh();
        let (e, xi) = mesh.locate(x_m);
        let tolerance_m = 1e-9 * model.length_m();
        let mut elements = vec![(e, xi)];
        let at_start_node = (x_m - mesh.node_x_m[e]).abs() <= tolerance_m;
        let at_end_node = (x_m - mesh.node_x_m[e + 1]).abs() <= tolerance_m;
        if at_start_node && e > 0 {
            elements = vec![(e - 1, 1.0), (e, 0.0)];
        } else if at_end_node && e + 1 < mesh.elements.len() {
            elements = vec![(e, 1.0), (e + 1, 0.0)];
        }
        gauge.sides = elements
            .into_iter()
            .map(|(e, xi)| side(model, factors, e, xi))
            .collect();
        gauge
    }

    /// The elastic bending moment (N m, sagging positive) in `state`.
    #[inline]
    pub fn read(&self, state: &GaugeState) -> f64 {
        if self.sides.is_empty() {
            return 0.0;
        }
        let sum: f64 = self
            .sides
            .iter()
            .map(|side| {
                let inertia = match side.inertia.is_empty() {
                    true => 0.0,
                    false => side.inertia.dot(state.a) + self.a0_per_s * side.inertia.dot(state.v),
                };
                let end_m = side.start_m + side.length_m;
                let loads: f64 = state
                    .loads
                    .iter()
                    .filter(|(x, _)| (side.start_m..=end_m).contains(x))
                    .map(|&(x, f)| {
                        f * fixed_end_moment_m(side.local_m, x - side.start_m, side.length_m)
                    })
                    .sum();
                side.elastic.dot(state.u) + inertia + loads + self.static_part(side, state.loads)
            })
            .sum();
        sum / self.sides.len() as f64
    }

    /// The static moment at `side` a reduced model's state leaves out under `loads`.
    #[inline]
    fn static_part(&self, side: &Side, loads: &[(f64, f64)]) -> f64 {
        let Some(mesh) = &self.mesh else {
            return 0.0;
        };
        let mut sum = 0.0;
        for &(x, f) in loads {
            mesh.for_each_weight(x, PointQuantity::Deflection, |dof, w| {
                sum += f * w * side.missing_static[dof];
            });
        }
        sum
    }
}

/// The share of element `e` at local coordinate `xi`.
fn side(model: &BridgeModel, factors: &GaugeFactors, e: usize, xi: f64) -> Side {
    let mesh = model.mesh();
    let element = &mesh.elements[e];
    let l = element.length_m;
    let local_m = xi * l;
    let dofs = mesh.element_dofs(e);
    let curvature = shape_dxx(xi, l) * element.ei_n_m2;
    let mut out = Side {
        start_m: mesh.node_x_m[e],
        length_m: l,
        local_m,
        ..Side::default()
    };
    let on_dofs = |values: &[f64]| -> [(Option<usize>, f64); 4] {
        std::array::from_fn(|k| (dofs[k], values[k]))
    };
    let elastic = on_dofs(curvature.as_slice());
    model.operator_from_mesh(&elastic, &mut out.elastic);
    out.missing_static = factors.missing_static(&elastic);
    // A lumped model's masses are point masses on the mesh nodes: its elements carry no
    // inertia of their own.
    if !model.diagonal_mass || model.is_modal() {
        let weights = inertia_weights(local_m, l, element.mass_per_length_kg_m);
        model.operator_from_mesh(&on_dofs(&weights), &mut out.inertia);
    }
    out
}

/// `-m * integral of fixed_end_moment(x, s) N_k(s) ds` over the element for each of its
/// four shape functions: the fixed-end moment at `x` of the inertia load `-m N(s) . a_e`
/// per unit nodal acceleration. The kernel has a kink at `s = x`, so each side of it is
/// integrated on its own by 4-point Gauss, exact there (a polynomial of degree 6 in s).
fn inertia_weights(x_m: f64, length_m: f64, mass_per_length_kg_m: f64) -> [f64; 4] {
    let mut weights = [0.0; 4];
    for (from, to) in [(0.0, x_m), (x_m, length_m)] {
        let half = 0.5 * (to - from);
        if half <= 0.0 {
            continue;
        }
        for (point, weight) in GAUSS_4 {
            let s = from + half * (1.0 + point);
            let kernel = fixed_end_moment_m(x_m, s, length_m);
            let n = shape(s / length_m, length_m);
            for (w, nk) in weights.iter_mut().zip(n.iter()) {
                *w -= mass_per_length_kg_m * weight * half * kernel * nk;
            }
        }
    }
    weights
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The fixed-end moments of a point load against the closed forms written out: a
    /// central load gives -Pl/8 at the ends and +Pl/8 under it (here for an upward unit
    /// force, so the signs flip), and a load at an end gives nothing.
    #[test]
    fn fixed_end_moment_matches_the_clamped_beam() {
        let l = 2.0;
        assert!((fixed_end_moment_m(0.0, 1.0, l) - l / 8.0).abs() < 1e-15);
        assert!((fixed_end_moment_m(l, 1.0, l) - l / 8.0).abs() < 1e-15);
        assert!((fixed_end_moment_m(1.0, 1.0, l) + l / 8.0).abs() < 1e-15);
        for x in [0.0, 0.3, 1.7, 2.0] {
            assert!(fixed_end_moment_m(x, 0.0, l).abs() < 1e-15);
            assert!(fixed_end_moment_m(x, l, l).abs() < 1e-15);
        }
        // Off-centre load at a = 0.5: M_A = -P a b^2 / l^2 (sagging sign, downward P).
        let (a, b) = (0.5, 1.5);
        assert!((fixed_end_moment_m(0.0, a, l) - a * b * b / (l * l)).abs() < 1e-15);
        assert!((fixed_end_moment_m(l, a, l) - a * a * b / (l * l)).abs() < 1e-15);
    }

    /// A uniform load over the whole clamped element gives `q l^2 / 12` hogging at the
    /// ends and `q l^2 / 24` sagging in the middle: the inertia weights of a uniform unit
    /// acceleration (both nodes translating, no rotation) are that load of `-m`.
    #[test]
    fn inertia_weights_of_a_uniform_acceleration_are_the_clamped_uniform_load() {
        let (l, m) = (1.5, 800.0);
        for (x, expected) in [
            (0.0, -l * l / 12.0),
            (0.5 * l, l * l / 24.0),
            (l, -l * l / 12.0),
        ] {
            let w = inertia_weights(x, l, m);
            // Upward unit acceleration: the inertia load is -m (downward) per unit length.
            let moment = w[0] + w[2];
            assert!(
                (moment - m * expected).abs() < 1e-9 * m * l * l,
                "{x}: {moment}"
            );
        }
    }
}
