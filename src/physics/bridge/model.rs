//! `BridgeModel`: one discretized bridge (lumped mass, Hermite FE or modal) behind one
//! interface: matrices, modes, Rayleigh damping, and point operators that turn a force at
//! any x into a load vector and read displacement, slope and moment back at any x.

use nalgebra::{DMatrix, DVector};
use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

use super::beam::BeamProperties;
use super::lumped::{condensation_mesh, condense, stiffness_by_flexibility};
use super::mesh::{HermiteMesh, PointQuantity};
use super::modes::{generalized_modes, Rayleigh};
use super::sparse::SparseVec;
use crate::error::{Error, Result};

/// Most masses, elements or modes a bridge model may have: beyond it the dense solves of
/// the lumped and modal models take minutes per run.
pub const MAX_MODEL_SIZE: usize = 5000;

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
        /// Number of equal elements, 1 to 5000.
        #[schemars(range(min = 1, max = MAX_MODEL_SIZE))]
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
        #[schemars(range(min = 2))]
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
    /// Validates counts; `path` is the scenario path of the spec.
    pub fn validate(&self, path: &str) -> Result<()> {
        let (field, value, min) = match self {
            ModelSpec::LumpedMass { nodes, .. } => ("nodes", *nodes, 1),
            ModelSpec::FiniteElement { elements } => ("elements", *elements, 1),
            ModelSpec::Modal { modes, elements } => {
                if let Some(e) = elements {
                    if *e < 2 * modes {
                        return Err(Error::invalid(
                            format!("{path}.elements"),
                            e,
                            format!("must be at least 2 x modes = {}", 2 * modes),
                        ));
                    }
                }
                ("modes", *modes, 1)
            }
        };
        if value < min || value > MAX_MODEL_SIZE {
            return Err(Error::invalid(
                format!("{path}.{field}"),
                value,
                format!("must be between 1 and {MAX_MODEL_SIZE}"),
            ));
        }
        Ok(())
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
enum Reduction {
    /// The model DOFs are the mesh DOFs (finite elements).
    Identity,
    /// Mesh DOFs = T * model DOFs (condensation for lumped mass, mode shapes for modal).
    Dense(DMatrix<f64>),
}

/// A discretized bridge, ready for time integration.
#[derive(Debug, Clone)]
pub struct BridgeModel {
    pub beam: BeamProperties,
    pub spec: ModelSpec,
    pub mass: DMatrix<f64>,
    pub stiffness: DMatrix<f64>,
    pub damping: DMatrix<f64>,
    pub rayleigh: Rayleigh,
    /// The damping ratio Rayleigh damping is fitted to on modes 1 and 2.
    pub damping_ratio: f64,
    /// Natural circular frequencies of this model, ascending (rad/s).
    pub omega_rad_s: Vec<f64>,
    /// True when the mass matrix is diagonal (lumped, modal).
    pub diagonal_mass: bool,
    mesh: HermiteMesh,
    reduction: Reduction,
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
        let (mesh, mass, stiffness, reduction, diagonal_mass) = match spec {
            ModelSpec::LumpedMass { nodes, stiffness } => lumped(beam, *nodes, *stiffness)?,
            ModelSpec::FiniteElement { elements } => {
                let mesh = HermiteMesh::simply_supported(beam, *elements);
                let (m, k) = (mesh.consistent_mass(), mesh.stiffness());
                (mesh, m, k, Reduction::Identity, false)
            }
            ModelSpec::Modal { modes, elements } => modal(beam, *modes, *elements)?,
        };
        let modes = generalized_modes(&stiffness, &mass)?;
        let omega: Vec<f64> = modes.omega_rad_s.iter().copied().collect();
        // A single-DOF model has one mode: fit on it alone (a0 and a1 split the ratio).
        let w2 = omega.get(1).copied().unwrap_or(omega[0]);
        let rayleigh = Rayleigh::fit(damping_ratio, omega[0], w2);
        let damping = &mass * rayleigh.a0_per_s + &stiffness * rayleigh.a1_s;
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
        })
    }

    /// Number of DOFs of the model.
    pub fn n_dof(&self) -> usize {
        self.mass.nrows()
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

    /// Span (m).
    pub fn span_m(&self) -> f64 {
        self.beam.span_m
    }

    /// True when `x_m` lies on the bridge.
    pub fn on_span(&self, x_m: f64) -> bool {
        (0.0..=self.beam.span_m).contains(&x_m)
    }

    /// Weights of `quantity` at `x_m` over the model DOFs; empty off the span.
    ///
    /// For `Deflection` this is both the read-back `w(x) = h . u` and the consistent load
    /// vector `h P` of a force P at x (the two are transposes of each other, which keeps
    /// the coupled system's work balance exact).
    pub fn point_operator(&self, x_m: f64, quantity: PointQuantity, out: &mut SparseVec) {
        out.clear();
        if !self.on_span(x_m) {
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

    /// Consistent load vector of a distributed load q(x) (N/m, upward positive), by
    /// 4-point Gauss quadrature on each mesh element (exact for cubic x cubic loads).
    pub fn distributed_load(&self, q_n_m: impl Fn(f64) -> f64) -> DVector<f64> {
        const GAUSS: [(f64, f64); 4] = [
            (-0.861_136_311_594_052_6, 0.347_854_845_137_453_85),
            (-0.339_981_043_584_856_3, 0.652_145_154_862_546_2),
            (0.339_981_043_584_856_3, 0.652_145_154_862_546_2),
            (0.861_136_311_594_052_6, 0.347_854_845_137_453_85),
        ];
        let mut load = DVector::zeros(self.n_dof());
        let mut op = SparseVec::with_capacity(self.n_dof());
        for pair in self.mesh.node_x_m.windows(2) {
            let (a, b) = (pair[0], pair[1]);
            let half = 0.5 * (b - a);
            for (s, weight) in GAUSS {
                let x = a + half * (1.0 + s);
                self.point_operator(x, PointQuantity::Deflection, &mut op);
                op.add_scaled_to(weight * half * q_n_m(x), &mut load);
            }
        }
        load
    }

    /// Positions where `/truth/bridge` reports the deflected shape (mesh nodes, supports included).
    pub fn shape_positions_m(&self) -> &[f64] {
        &self.mesh.node_x_m
    }
}

type Built = (HermiteMesh, DMatrix<f64>, DMatrix<f64>, Reduction, bool);

fn lumped(beam: &BeamProperties, nodes: usize, route: LumpedStiffness) -> Result<Built> {
    let mesh = condensation_mesh(beam, nodes);
    let condensation = condense(&mesh)?;
    let use_flexibility = match route {
        LumpedStiffness::Auto => beam.is_uniform(),
        LumpedStiffness::Flexibility => true,
        LumpedStiffness::Condensation => false,
    };
    let stiffness = if use_flexibility {
        stiffness_by_flexibility(beam, nodes)?
    } else {
        condensation.stiffness
    };
    let node_mass_kg = beam.mass_per_length_kg_m * beam.span_m / (nodes + 1) as f64;
    let mass = DMatrix::from_diagonal_element(nodes, nodes, node_mass_kg);
    Ok((
        mesh,
        mass,
        stiffness,
        Reduction::Dense(condensation.transform),
        true,
    ))
}

fn modal(beam: &BeamProperties, modes: usize, elements: Option<usize>) -> Result<Built> {
    let elements = elements.unwrap_or((4 * modes).max(40));
    let mesh = HermiteMesh::simply_supported(beam, elements);
    let (m_fe, k_fe) = (mesh.consistent_mass(), mesh.stiffness());
    let fe_modes = generalized_modes(&k_fe, &m_fe)?;
    let kept = modes.min(fe_modes.omega_rad_s.len());
    let shapes = fe_modes.shapes.columns(0, kept).into_owned();
    let omega2 =
        DVector::from_iterator(kept, fe_modes.omega_rad_s.iter().take(kept).map(|w| w * w));
    Ok((
        mesh,
        DMatrix::identity(kept, kept),
        DMatrix::from_diagonal(&omega2),
        Reduction::Dense(shapes),
        true,
    ))
}
