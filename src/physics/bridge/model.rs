//! `BridgeModel`: one discretized bridge (lumped mass, Hermite FE or modal) behind one
//! interface: matrices, modes, Rayleigh damping, and point operators that turn a force at
//! any x into a load vector and read displacement, slope and moment back at any x.

use nalgebra::{DMatrix, DVector};
use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

use super::beam::{BeamProperties, GAUSS_4};
use super::lumped::{
    condensation_mesh, condense, force_method_applies, mass_dofs, mass_layout,
    stiffness_by_flexibility,
};
use super::mesh::{HermiteMesh, PointQuantity};
use super::modes::{EigenRoute, Modes, Rayleigh, Wanted};
use super::sparse::SparseVec;
use crate::base::units::bytes_text;
use crate::error::{Error, Result};
use crate::physics::linalg::{SymBand, SymMatrix};

/// Modes every model computes when it is built: the Rayleigh fit needs two, the run's
/// metadata and `/truth/bridge` report ten.
pub const REPORTED_MODES: usize = 10;

/// Most masses or modes a bridge model may have: the lumped model's stiffness is dense
/// (O(n^2) memory, O(n^3) to build) and a modal model's shapes grow as modes x mesh.
pub const MAX_MODEL_SIZE: usize = 5000;

/// Most elements of a finite-element mesh (of a finite-element or modal model): the band
/// keeps memory and step cost O(n), so round-off sets the limit. The stiffness's condition
/// number grows as about 26 N^4 (4e18 at 20 000 elements), and at 30 000 the band Cholesky
/// met a non-positive pivot. Meshes past about 1000 elements already lose f1 digits to it
/// (docs/performance.md, "Big models").
pub const MAX_ELEMENTS: usize = 20_000;

/// Memory a model may need to be built and run (bytes, 2 GiB): a model whose
/// [`ModelSpec::memory_estimate_bytes`] exceeds it is refused before anything is built,
/// so that a sweep of one job per core stays within a 24 GiB machine with room to spare.
pub const MAX_MODEL_MEMORY_BYTES: u64 = 2 << 30;

/// Which discretization to build.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(remote = "Self", rename_all = "snake_case", deny_unknown_fields)]
#[schemars(tag = "kind")]
pub enum ModelSpec {
    /// N equal lumped masses (the paper's flexibility method).
    LumpedMass {
        /// Number of interior masses N, 1 to 5000.
        #[schemars(range(min = 1, max = MAX_MODEL_SIZE))]
        nodes: usize,
        /// How K is obtained (default `flexibility` for a uniform beam, else `condensation`).
        #[serde(default)]
        stiffness: LumpedStiffness,
    },
    /// Hermite cubic elements with consistent mass.
    FiniteElement {
        /// Number of equal elements, 1 to 20000.
        #[schemars(range(min = 1, max = MAX_ELEMENTS))]
        elements: usize,
    },
    /// The first `modes` modes of a fine finite-element model.
    Modal {
        /// Modes kept, 1 to 5000.
        #[schemars(range(min = 1, max = MAX_MODEL_SIZE))]
        modes: usize,
        /// Elements of the underlying FE model, at least 2 x modes (default 4 x modes, at
        /// least 40).
        #[serde(default)]
        #[schemars(range(min = 2, max = MAX_ELEMENTS))]
        elements: Option<usize>,
    },
}
crate::base::tagged::kind_tagged!(ModelSpec);

/// Route to the lumped-mass stiffness.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum LumpedStiffness {
    /// Closed-form flexibility when the beam is uniform, condensation otherwise.
    #[default]
    Auto,
    /// `K = F^-1` with closed-form unit-load deflections (uniform beams only).
    Flexibility,
    /// Static condensation of a Hermite mesh with nodes at the masses.
    Condensation,
}

impl ModelSpec {
    /// Validates counts and the memory the model needs; `path` is the scenario path of
    /// the spec.
    pub fn validate(&self, path: &str) -> Result<()> {
        let (field, value, max) = match self {
            ModelSpec::LumpedMass { nodes, .. } => ("nodes", *nodes, MAX_MODEL_SIZE),
            ModelSpec::FiniteElement { elements } => ("elements", *elements, MAX_ELEMENTS),
            ModelSpec::Modal { modes, elements } => {
                if let Some(e) = elements {
                    if *e < 2 * modes || *e > MAX_ELEMENTS {
                        return Err(Error::invalid(
                            format!("{path}.elements"),
                            e,
                            format!(
                                "must be at least 2 x modes = {} and at most {MAX_ELEMENTS}",
                                2 * modes
                            ),
                        ));
                    }
                }
                ("modes", *modes, MAX_MODEL_SIZE)
            }
        };
        if value < 1 || value > max {
            return Err(Error::invalid(
                format!("{path}.{field}"),
                value,
                format!("must be between 1 and {max}"),
            ));
        }
        let bytes = self.memory_estimate_bytes();
        if bytes > MAX_MODEL_MEMORY_BYTES {
            return Err(Error::invalid(
                format!("{path}.{field}"),
                value,
                format!(
                    "needs about {} to build and run (estimate), above the limit of {}: \
                     use a smaller model",
                    bytes_text(bytes),
                    bytes_text(MAX_MODEL_MEMORY_BYTES)
                ),
            ));
        }
        Ok(())
    }

    /// Peak memory the model takes to build and to set up its solver (bytes), counted
    /// from the matrices each route holds at once (docs/physics.md section 3; measured
    /// peaks in the build table of docs/performance.md lie within a factor of two of it):
    /// - finite elements: about 80 band-sized vectors of the mesh's DOFs (K, M, C, K_eff,
    ///   their product and factor forms, the eigen-solution's copies), plus the columns
    ///   of K_eff^-1 the coupled step keeps for meshes of at most 1024 DOFs;
    /// - modal: the finite-element mesh's share plus the shapes, twice (the eigenvectors
    ///   and the model's copy);
    /// - lumped mass: about 14 dense n x n matrices (flexibility, its factor and inverse,
    ///   the condensation's blocks and transform, C, K_eff and its factor).
    pub fn memory_estimate_bytes(&self) -> u64 {
        const F64: u64 = 8;
        let fe = |elements: usize| {
            let dofs = 2 * elements as u64;
            let inverse_columns = if dofs <= 1024 { dofs * dofs } else { 0 };
            (80 * dofs + inverse_columns) * F64
        };
        match self {
            ModelSpec::FiniteElement { elements } => fe(*elements),
            ModelSpec::Modal { modes, elements } => {
                let elements = elements.unwrap_or((4 * modes).max(40));
                fe(elements) + 2 * (2 * elements as u64) * *modes as u64 * F64
            }
            ModelSpec::LumpedMass { nodes, .. } => {
                let n = *nodes as u64;
                14 * n * n * F64 + fe(*nodes + 1)
            }
        }
    }

    /// Short label for tables ("lumped_mass n=100").
    pub fn label(&self) -> String {
        match self {
            ModelSpec::LumpedMass { nodes, .. } => format!("lumped_mass n={nodes}"),
            ModelSpec::FiniteElement { elements } => format!("finite_element n={elements}"),
            ModelSpec::Modal { modes, .. } => format!("modal m={modes}"),
        }
    }
}

/// How model DOFs relate to the Hermite mesh's DOFs.
#[derive(Debug, Clone)]
pub(super) enum Reduction {
    /// The model DOFs are the mesh DOFs (finite elements).
    Identity,
    /// Mesh DOFs = T * model DOFs (condensation for lumped mass, mode shapes for modal).
    Dense(DMatrix<f64>),
}

/// A discretized bridge, ready for time integration. Its matrices are kept in the storage
/// their structure deserves (finite elements: band, O(n) memory; lumped mass: dense
/// stiffness and diagonal mass; modal: diagonal).
#[derive(Debug, Clone)]
pub struct BridgeModel {
    pub beam: BeamProperties,
    pub spec: ModelSpec,
    pub mass: SymMatrix,
    pub stiffness: SymMatrix,
    pub damping: SymMatrix,
    pub rayleigh: Rayleigh,
    /// The damping ratio Rayleigh damping is fitted to on modes 1 and 2.
    pub damping_ratio: f64,
    /// The lowest natural circular frequencies of this model, ascending (rad/s):
    /// [`REPORTED_MODES`] of them, or every mode of a model with fewer DOFs (and every
    /// kept mode of a modal model). [`BridgeModel::modes`] computes more when needed.
    pub omega_rad_s: Vec<f64>,
    /// True when the mass matrix is diagonal (lumped, modal).
    pub diagonal_mass: bool,
    mesh: HermiteMesh,
    pub(super) reduction: Reduction,
    eigen_route: EigenRoute,
}

impl BridgeModel {
    /// Builds the model; `damping_ratio` is fitted on modes 1 and 2.
    pub fn build(beam: &BeamProperties, spec: &ModelSpec, damping_ratio: f64) -> Result<Self> {
        beam.validate("bridge")?;
        spec.validate("bridge.model")?;
        if !(damping_ratio.is_finite() && (0.0..1.0).contains(&damping_ratio)) {
            return Err(Error::invalid(
                "bridge.damping_ratio",
                damping_ratio,
                "must be in [0, 1)",
            ));
        }
        let built = match spec {
            ModelSpec::LumpedMass { nodes, stiffness } => lumped(beam, *nodes, *stiffness)?,
            ModelSpec::FiniteElement { elements } => {
                let mesh = HermiteMesh::on_girder(beam, *elements);
                Built {
                    mass: SymMatrix::Band(mesh.consistent_mass_band()),
                    stiffness: SymMatrix::Band(mesh.stiffness_band()),
                    reduction: Reduction::Identity,
                    diagonal_mass: false,
                    eigen_route: EigenRoute::OwnBand,
                    mesh,
                }
            }
            ModelSpec::Modal { modes, elements } => modal(beam, *modes, *elements)?,
        };
        let Built {
            mesh,
            mass,
            stiffness,
            reduction,
            diagonal_mass,
            eigen_route,
        } = built;
        let reported = eigen_route.lowest(
            &stiffness,
            &mass,
            Wanted::Lowest(REPORTED_MODES.min(mass.n())),
        )?;
        let omega: Vec<f64> = match &eigen_route {
            // A modal model's frequencies are its diagonal: keep them all.
            EigenRoute::Diagonal => stiffness.diagonal().iter().map(|w2| w2.sqrt()).collect(),
            _ => reported.omega_rad_s.iter().copied().collect(),
        };
        // A single-DOF model has one mode: fit on it alone (a0 and a1 split the ratio).
        let w2 = omega.get(1).copied().unwrap_or(omega[0]);
        let rayleigh = Rayleigh::fit(damping_ratio, omega[0], w2);
        let damping = SymMatrix::linear_combination(&[
            (rayleigh.a0_per_s, &mass),
            (rayleigh.a1_s, &stiffness),
        ]);
        Ok(BridgeModel {
            beam: beam.clone(),
            spec: spec.clone(),
            mass,
            stiffness,
            damping,
            rayleigh,
            damping_ratio,
            omega_rad_s: omega,
            diagonal_mass,
            mesh,
            reduction,
            eigen_route,
        })
    }

    /// The lowest modes of the model, mass-normalized over the model DOFs: from the band
    /// of its finite-element mesh (or, for a lumped model, of its condensation mesh) by
    /// Sturm bisection and inverse iteration, densely only where that is cheaper (small
    /// models); see [`super::modes`].
    pub fn modes(&self, wanted: Wanted) -> Result<Modes> {
        self.eigen_route.lowest(&self.stiffness, &self.mass, wanted)
    }

    /// True for a modal model (its DOFs are modal coordinates of a finite-element mesh,
    /// whose elements carry their own distributed mass).
    pub fn is_modal(&self) -> bool {
        matches!(self.spec, ModelSpec::Modal { .. })
    }

    /// Number of DOFs of the model.
    pub fn n_dof(&self) -> usize {
        self.mass.n()
    }

    /// Natural frequency of mode `n` (1-based), Hz.
    pub fn frequency_hz(&self, n: usize) -> f64 {
        self.omega_rad_s[n - 1] / (2.0 * std::f64::consts::PI)
    }

    /// Natural frequencies (Hz) and Rayleigh damping ratios of the lowest `n` modes (fewer
    /// when the model has fewer).
    pub fn modal_summary(&self, n: usize) -> (Vec<f64>, Vec<f64>) {
        let n = self.omega_rad_s.len().min(n);
        let frequencies = (1..=n).map(|k| self.frequency_hz(k)).collect();
        let ratios = self.omega_rad_s[..n]
            .iter()
            .map(|&w| self.rayleigh.ratio_at(w))
            .collect();
        (frequencies, ratios)
    }

    /// Length of the girder, overhangs included (m).
    pub fn length_m(&self) -> f64 {
        self.beam.length_m()
    }

    /// True when `x_m` lies on the girder.
    #[inline]
    pub fn on_girder(&self, x_m: f64) -> bool {
        (0.0..=self.beam.length_m()).contains(&x_m)
    }

    /// Weights of `quantity` at `x_m` over the model DOFs; empty off the girder.
    ///
    /// For `Deflection` this is both the read-back `w(x) = h . u` and the consistent load
    /// vector `h P` of a force P at x (the two are transposes of each other, which keeps
    /// the coupled system's work balance exact).
    #[inline]
    pub fn point_operator(&self, x_m: f64, quantity: PointQuantity, out: &mut SparseVec) {
        out.clear();
        if !self.on_girder(x_m) {
            return;
        }
        match &self.reduction {
            Reduction::Identity => self.mesh.point_operator(x_m, quantity, out),
            Reduction::Dense(t) => {
                let mut mesh_weights = [(0usize, 0.0f64); 4];
                let mut count = 0;
                self.mesh.for_each_weight(x_m, quantity, |dof, w| {
                    mesh_weights[count] = (dof, w);
                    count += 1;
                });
                for j in 0..t.ncols() {
                    let v: f64 = mesh_weights[..count]
                        .iter()
                        .map(|&(dof, w)| w * t[(dof, j)])
                        .sum();
                    out.push(j, v);
                }
            }
        }
    }

    /// The operator `sum_k weights[k].1 * (mesh DOF weights[k].0)` over the model DOFs,
    /// into `out`; constrained mesh DOFs (`None`) carry nothing.
    pub(super) fn operator_from_mesh(&self, weights: &[(Option<usize>, f64)], out: &mut SparseVec) {
        out.clear();
        match &self.reduction {
            Reduction::Identity => {
                for &(dof, w) in weights {
                    if let Some(dof) = dof {
                        out.push(dof, w);
                    }
                }
            }
            Reduction::Dense(t) => {
                for j in 0..t.ncols() {
                    let v: f64 = weights
                        .iter()
                        .filter_map(|&(dof, w)| dof.map(|dof| w * t[(dof, j)]))
                        .sum();
                    out.push(j, v);
                }
            }
        }
    }

    /// `[deflection, slope]` operators at `x_m`: the two [`BridgeModel::point_operator`]
    /// calls, the element located once on a finite-element model (a wheel needs both).
    #[inline]
    pub fn wheel_operators(&self, x_m: f64, [deflection, slope]: [&mut SparseVec; 2]) {
        match (&self.reduction, self.on_girder(x_m)) {
            (Reduction::Identity, true) => self.mesh.wheel_operators(x_m, [deflection, slope]),
            _ => {
                self.point_operator(x_m, PointQuantity::Deflection, deflection);
                self.point_operator(x_m, PointQuantity::Slope, slope);
            }
        }
    }

    /// [`BridgeModel::point_operator`] at each of `xs_m`.
    pub fn point_operators(&self, xs_m: &[f64], quantity: PointQuantity) -> Vec<SparseVec> {
        xs_m.iter()
            .map(|&x| {
                let mut op = SparseVec::default();
                self.point_operator(x, quantity, &mut op);
                op
            })
            .collect()
    }

    /// Convenience: the value of `quantity` at `x_m` for a state vector.
    pub fn read(&self, x_m: f64, quantity: PointQuantity, state: &DVector<f64>) -> f64 {
        let mut op = SparseVec::with_capacity(self.n_dof());
        self.point_operator(x_m, quantity, &mut op);
        op.dot(state)
    }

    /// Consistent load vector of a point force `force_n` (upward positive) at `x_m`.
    pub fn point_load_vector(&self, x_m: f64, force_n: f64) -> DVector<f64> {
        let mut op = SparseVec::with_capacity(self.n_dof());
        self.point_operator(x_m, PointQuantity::Deflection, &mut op);
        let mut load = DVector::zeros(self.n_dof());
        op.add_scaled_to(force_n, &mut load);
        load
    }

    /// Consistent load vector of a distributed load q(x) (N/m, upward positive), by
    /// 4-point Gauss quadrature on each mesh element (exact for cubic x cubic loads).
    pub fn distributed_load(&self, q_n_m: impl Fn(f64) -> f64) -> DVector<f64> {
        let mut load = DVector::zeros(self.n_dof());
        let mut op = SparseVec::with_capacity(self.n_dof());
        for pair in self.mesh.node_x_m.windows(2) {
            let (a, b) = (pair[0], pair[1]);
            let half = 0.5 * (b - a);
            for (s, weight) in GAUSS_4 {
                let x = a + half * (1.0 + s);
                self.point_operator(x, PointQuantity::Deflection, &mut op);
                op.add_scaled_to(weight * half * q_n_m(x), &mut load);
            }
        }
        load
    }

    /// The Hermite mesh the model's DOFs map onto.
    pub(super) fn mesh(&self) -> &HermiteMesh {
        &self.mesh
    }

    /// Positions where `/truth/bridge` reports the deflected shape (mesh nodes, supports
    /// included).
    pub fn shape_positions_m(&self) -> &[f64] {
        &self.mesh.node_x_m
    }
}

/// What the three discretizations build.
struct Built {
    mesh: HermiteMesh,
    mass: SymMatrix,
    stiffness: SymMatrix,
    reduction: Reduction,
    diagonal_mass: bool,
    eigen_route: EigenRoute,
}

fn lumped(beam: &BeamProperties, nodes: usize, route: LumpedStiffness) -> Result<Built> {
    let layout = mass_layout(beam, nodes)?;
    let mesh = condensation_mesh(beam, &layout.positions_m);
    let model_dofs = mass_dofs(&mesh, &layout.positions_m);
    let condensation = condense(&mesh, &model_dofs)?;
    let use_flexibility = match route {
        LumpedStiffness::Auto => force_method_applies(beam),
        LumpedStiffness::Flexibility => true,
        LumpedStiffness::Condensation => false,
    };
    let stiffness = if use_flexibility {
        stiffness_by_flexibility(beam, &layout.positions_m)?
    } else {
        condensation.stiffness
    };
    // The modes come from the condensation mesh with the masses on its translations:
    // its other equations are massless, so its finite eigenpairs are those of the
    // condensed stiffness (the same K as the flexibility route up to round-off), while its
    // band keeps the eigen-solution O(n).
    let mut mesh_mass = SymBand::zeros(mesh.n_dof, 0);
    for (&dof, &m) in model_dofs.iter().zip(&layout.masses_kg) {
        mesh_mass.add(dof, dof, m);
    }
    Ok(Built {
        eigen_route: EigenRoute::CondensationMesh {
            stiffness: mesh.stiffness_band(),
            mass: mesh_mass,
            model_dofs,
        },
        mesh,
        mass: SymMatrix::Diagonal(DVector::from_vec(layout.masses_kg)),
        stiffness: SymMatrix::Dense(stiffness),
        reduction: Reduction::Dense(condensation.transform),
        diagonal_mass: true,
    })
}

fn modal(beam: &BeamProperties, modes: usize, elements: Option<usize>) -> Result<Built> {
    let elements = elements.unwrap_or((4 * modes).max(40));
    let mesh = HermiteMesh::on_girder(beam, elements);
    let (k_fe, m_fe) = (
        SymMatrix::Band(mesh.stiffness_band()),
        SymMatrix::Band(mesh.consistent_mass_band()),
    );
    let wanted = Wanted::Lowest(modes.min(k_fe.n()));
    let fe_modes = EigenRoute::OwnBand.lowest(&k_fe, &m_fe, wanted)?;
    let kept = fe_modes.omega_rad_s.len();
    let omega2 = fe_modes.omega_rad_s.map(|w| w * w);
    Ok(Built {
        mesh,
        mass: SymMatrix::Diagonal(DVector::from_element(kept, 1.0)),
        stiffness: SymMatrix::Diagonal(omega2),
        reduction: Reduction::Dense(fe_modes.shapes),
        diagonal_mass: true,
        eigen_route: EigenRoute::Diagonal,
    })
}
