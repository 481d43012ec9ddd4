//! Splitting a parent's relative weighing error among its parts so that each part's error
//! has a prescribed standard deviation and the parts add up exactly to the parent.
//!
//! Children `k = 1..m` carry weight shares `w_k` (static load / parent load, `sum w = 1`)
//! and relative errors `e_k`; the parent's relative error is `e_P = sum w_k e_k`, so the
//! measured loads add up exactly. We want `Var(e_k) = s_k^2` and `Var(e_P) = s_P^2`, i.e. a
//! children covariance `S` with `diag(S) = s^2` and `w' S w = s_P^2`. Two one-parameter
//! families cover every case met by COST 323 vehicles:
//!
//! - **common + independent** (`s_P^2 >= sum (w_k s_k)^2`, the parent varies at least as
//!   much as with independent children): `e_k = c x_0 + sqrt(s_k^2 - c^2) z_k` with
//!   `x_0, z_k ~ N(0, 1)`; `w' S w = c^2 + sum w_k^2 (s_k^2 - c^2)`, hence
//!   `c^2 = (s_P^2 - sum w_k^2 s_k^2) / (1 - sum w_k^2)`.
//! - **balanced** (`s_P^2 < sum (w_k s_k)^2`, the children must compensate each other): a
//!   mixture of independent children (correlation `I`) and the most compensating
//!   correlation we construct, `R_min`, the correlation of `P z` with `P = I - u u'`,
//!   `u = a / |a|`, `a_k = w_k s_k` (the projection that removes the direction the parent
//!   sees). `e_k = s_k (sqrt(1 - theta) z_k + sqrt(theta) y_k)`, `y = diag(P)^(-1/2) P z'`;
//!   `w' S w = (1 - theta) a'a + theta a' R_min a` is linear in `theta`, solved exactly.
//!   For two children `R_min` is perfect anti-correlation, `a' R_min a = (a_1 - a_2)^2`, the
//!   smallest parent variance any correlation allows.
//!
//! The draw is conditional on a parent error `e_P` drawn first (by the caller, one level up):
//! draw `e' ~ N(0, S)` from the family, then `e = e' + S w (e_P - w'e') / (w' S w)`
//! (conditioning by kriging: the result has the law of `e | w'e = e_P`, and `w'e = e_P`
//! holds exactly). When the family cannot reach `s_P` (one child dominates so much that even
//! full compensation leaves the parent too noisy, or `c^2` would exceed a child's variance)
//! the parameter is clamped: the sum stays exact and the children's variances move, as
//! [`ErrorSplit::child_sigma`] reports.

use rand::RngExt;
use rand_chacha::ChaCha8Rng;
use rand_distr::StandardNormal;

/// Below this, `1 - u_k^2` means child k alone makes the parent (its siblings weigh 0).
const DOMINANT_EPS: f64 = 1e-12;

/// Correlation family of the children (module doc).
#[derive(Debug, Clone, PartialEq)]
enum Family {
    /// One child: it is the parent.
    Single,
    /// `e_k = c x_0 + sqrt(s_k^2 - c^2) z_k`.
    Common { common_var: f64 },
    /// `e_k = s_k (sqrt(1 - theta) z_k + sqrt(theta) y_k)`.
    Balanced { theta: f64, u: Vec<f64> },
}

/// A planned split of one parent's error among its children (module doc).
#[derive(Debug, Clone, PartialEq)]
pub struct ErrorSplit {
    weights: Vec<f64>,
    sigmas: Vec<f64>,
    family: Family,
    /// `S w`: covariance of each child with the parent.
    cov_with_parent: Vec<f64>,
    /// `w' S w`: the parent variance the family produces.
    parent_var: f64,
}

impl ErrorSplit {
    /// Plans children of static loads `loads` (their shares become the weights; all zero
    /// means equal shares), child target sigmas `child_sigmas` and parent target sigma
    /// `parent_sigma` (relative errors, e.g. 0.035).
    ///
    /// # Panics
    /// If `loads` is empty or its length differs from `child_sigmas` (a caller bug).
    pub fn plan(loads: &[f64], child_sigmas: &[f64], parent_sigma: f64) -> Self {
        assert!(!loads.is_empty(), "a split needs at least one child");
        assert_eq!(loads.len(), child_sigmas.len(), "one sigma per child");
        let weights = shares(loads);
        if weights.len() == 1 {
            return Self::single(parent_sigma);
        }
        let sigmas = child_sigmas.to_vec();
        let target_var = parent_sigma * parent_sigma;
        let a: Vec<f64> = weights.iter().zip(&sigmas).map(|(w, s)| w * s).collect();
        let independent_var: f64 = a.iter().map(|x| x * x).sum();
        let family = if target_var >= independent_var {
            common_family(&weights, &sigmas, target_var, independent_var)
        } else {
            balanced_family(&a, target_var, independent_var)
        };
        let cov = covariance(&family, &sigmas);
        let cov_with_parent: Vec<f64> = cov
            .iter()
            .map(|row| row.iter().zip(&weights).map(|(c, w)| c * w).sum())
            .collect();
        let parent_var = cov_with_parent
            .iter()
            .zip(&weights)
            .map(|(c, w)| c * w)
            .sum();
        Self {
            weights,
            sigmas,
            family,
            cov_with_parent,
            parent_var,
        }
    }

    fn single(parent_sigma: f64) -> Self {
        Self {
            weights: vec![1.0],
            sigmas: vec![parent_sigma],
            family: Family::Single,
            cov_with_parent: vec![parent_sigma * parent_sigma],
            parent_var: parent_sigma * parent_sigma,
        }
    }

    /// Number of children.
    pub fn child_count(&self) -> usize {
        self.sigmas.len()
    }

    /// Children covariance `S` of the planned family (before conditioning), row-major.
    pub fn covariance(&self) -> Vec<Vec<f64>> {
        covariance(&self.family, &self.sigmas)
    }

    /// Standard deviation of the parent error the family produces, `sqrt(w' S w)`; equal
    /// to the target parent sigma when the plan is exact.
    pub fn family_parent_sigma(&self) -> f64 {
        self.parent_var.sqrt()
    }

    /// Standard deviation of child `k` after conditioning on a parent error of standard
    /// deviation `parent_sigma`: `Var = S_kk + (S w)_k^2 (s_P^2 - V) / V^2`, `V = w' S w`;
    /// `S_kk` (the target) whenever the family reaches `V = s_P^2`.
    pub fn child_sigma(&self, k: usize, parent_sigma: f64) -> f64 {
        if self.parent_var <= 0.0 {
            return parent_sigma;
        }
        let c = self.cov_with_parent[k];
        let s_kk = match self.family {
            Family::Single => self.parent_var,
            _ => self.sigmas[k] * self.sigmas[k],
        };
        let v = self.parent_var;
        (s_kk + c * c * (parent_sigma * parent_sigma - v) / (v * v))
            .max(0.0)
            .sqrt()
    }

    /// Children errors given the parent's drawn error `parent_error`, appended to `out`.
    /// Draws `m + 1` (common) or `2 m` (balanced) standard normals from `rng`, none for a
    /// single child.
    pub fn draw(&self, parent_error: f64, rng: &mut ChaCha8Rng, out: &mut Vec<f64>) {
        let start = out.len();
        match &self.family {
            Family::Single => {
                out.push(parent_error);
                return;
            }
            Family::Common { common_var } => draw_common(*common_var, &self.sigmas, rng, out),
            Family::Balanced { theta, u } => draw_balanced(*theta, u, &self.sigmas, rng, out),
        }
        let children = &mut out[start..];
        let unconditioned: f64 = children.iter().zip(&self.weights).map(|(e, w)| e * w).sum();
        if self.parent_var > 0.0 {
            let gain = (parent_error - unconditioned) / self.parent_var;
            for (e, c) in children.iter_mut().zip(&self.cov_with_parent) {
                *e += c * gain;
            }
        } else {
            // All sigmas zero: the children can only repeat the parent.
            children.iter_mut().for_each(|e| *e = parent_error);
        }
    }
}

/// Load shares summing to 1; equal shares when the loads sum to nothing.
fn shares(loads: &[f64]) -> Vec<f64> {
    let total: f64 = loads.iter().sum();
    if total > 0.0 && total.is_finite() {
        loads.iter().map(|l| l / total).collect()
    } else {
        vec![1.0 / loads.len() as f64; loads.len()]
    }
}

/// `c^2` solved from the parent variance, clamped to `[0, min s_k^2]` (module doc).
fn common_family(weights: &[f64], sigmas: &[f64], target_var: f64, independent_var: f64) -> Family {
    let w2: f64 = weights.iter().map(|w| w * w).sum();
    let max_common = sigmas.iter().map(|s| s * s).fold(f64::INFINITY, f64::min);
    let common_var = if 1.0 - w2 > DOMINANT_EPS {
        ((target_var - independent_var) / (1.0 - w2)).clamp(0.0, max_common)
    } else {
        max_common
    };
    Family::Common { common_var }
}

/// `theta` solved from the parent variance, clamped to `[0, 1]` (module doc).
fn balanced_family(a: &[f64], target_var: f64, independent_var: f64) -> Family {
    let norm = independent_var.sqrt();
    let u: Vec<f64> = a.iter().map(|x| x / norm).collect();
    let r_min = min_correlation(&u);
    let compensated_var: f64 = quadratic_form(&r_min, a);
    let theta = if independent_var > compensated_var {
        ((independent_var - target_var) / (independent_var - compensated_var)).clamp(0.0, 1.0)
    } else {
        0.0
    };
    Family::Balanced { theta, u }
}

/// Correlation of `P z`, `P = I - u u'`; a child with `1 - u_k^2 ~ 0` (it alone makes the
/// parent) is left uncorrelated, as [`draw_balanced`] draws it.
fn min_correlation(u: &[f64]) -> Vec<Vec<f64>> {
    let m = u.len();
    let mut r = vec![vec![0.0; m]; m];
    for j in 0..m {
        for k in 0..m {
            let (pj, pk) = (1.0 - u[j] * u[j], 1.0 - u[k] * u[k]);
            r[j][k] = if j == k {
                1.0
            } else if pj < DOMINANT_EPS || pk < DOMINANT_EPS {
                0.0
            } else {
                -u[j] * u[k] / (pj * pk).sqrt()
            };
        }
    }
    r
}

fn quadratic_form(matrix: &[Vec<f64>], x: &[f64]) -> f64 {
    matrix
        .iter()
        .zip(x)
        .map(|(row, xj)| xj * row.iter().zip(x).map(|(m, xk)| m * xk).sum::<f64>())
        .sum()
}

fn covariance(family: &Family, sigmas: &[f64]) -> Vec<Vec<f64>> {
    let m = sigmas.len();
    match family {
        Family::Single => vec![vec![sigmas[0] * sigmas[0]]],
        Family::Common { common_var } => (0..m)
            .map(|j| {
                (0..m)
                    .map(|k| {
                        if j == k {
                            sigmas[j] * sigmas[j]
                        } else {
                            *common_var
                        }
                    })
                    .collect()
            })
            .collect(),
        Family::Balanced { theta, u } => {
            let r_min = min_correlation(u);
            (0..m)
                .map(|j| {
                    (0..m)
                        .map(|k| {
                            let identity = if j == k { 1.0 } else { 0.0 };
                            let r = (1.0 - theta) * identity + theta * r_min[j][k];
                            sigmas[j] * sigmas[k] * r
                        })
                        .collect()
                })
                .collect()
        }
    }
}

fn draw_common(common_var: f64, sigmas: &[f64], rng: &mut ChaCha8Rng, out: &mut Vec<f64>) {
    let x0: f64 = rng.sample(StandardNormal);
    let common = common_var.sqrt() * x0;
    for s in sigmas {
        let z: f64 = rng.sample(StandardNormal);
        out.push(common + (s * s - common_var).max(0.0).sqrt() * z);
    }
}

fn draw_balanced(theta: f64, u: &[f64], sigmas: &[f64], rng: &mut ChaCha8Rng, out: &mut Vec<f64>) {
    let m = u.len();
    let z: Vec<f64> = (0..m).map(|_| rng.sample(StandardNormal)).collect();
    let z2: Vec<f64> = (0..m).map(|_| rng.sample(StandardNormal)).collect();
    let along_u: f64 = u.iter().zip(&z2).map(|(a, b)| a * b).sum();
    for k in 0..m {
        let p_kk = 1.0 - u[k] * u[k];
        let y = if p_kk < DOMINANT_EPS {
            z2[k]
        } else {
            (z2[k] - u[k] * along_u) / p_kk.sqrt()
        };
        out.push(sigmas[k] * ((1.0 - theta).sqrt() * z[k] + theta.sqrt() * y));
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::SeedableRng;

    fn parent_var_of(split: &ErrorSplit, loads: &[f64]) -> f64 {
        let w = shares(loads);
        quadratic_form(&split.covariance(), &w)
    }

    #[test]
    fn common_family_reaches_the_targets() {
        // Tridem of equal axles, B+(7): axle of group 7 %, group 5 % (sigma = delta / 2).
        // Independent axles would give 7 / sqrt(3) = 4.04 % < 5 %: common part needed,
        // c^2 = (25 - 49 / 3) / (2 / 3) = 13 (%^2), a hand figure.
        let loads = [80e3, 80e3, 80e3];
        let split = ErrorSplit::plan(&loads, &[0.07; 3], 0.05);
        let cov = split.covariance();
        assert!((cov[0][1] - 13e-4).abs() < 1e-15, "{}", cov[0][1]);
        assert!((cov[1][1] - 49e-4).abs() < 1e-15);
        assert!((parent_var_of(&split, &loads) - 25e-4).abs() < 1e-15);
    }

    #[test]
    fn two_children_compensate_exactly_when_needed() {
        // 2-axle truck 1/3 : 2/3, class A(5): axles 4 %, gross 2.5 %. Independent axles give
        // (16 / 9 + 64 / 9) = 8.9 %^2 > 6.25 %^2: anti-correlation rho solves
        // 6.25 = 16 (1/9 + 4/9 + 2 (2/9) rho) -> rho = -0.371, a hand figure.
        let loads = [50e3, 100e3];
        let split = ErrorSplit::plan(&loads, &[0.04, 0.04], 0.025);
        let cov = split.covariance();
        let rho = cov[0][1] / (cov[0][0].sqrt() * cov[1][1].sqrt());
        let rho_hand = (6.25 / 16.0 - 5.0 / 9.0) / (4.0 / 9.0);
        assert!((rho - rho_hand).abs() < 1e-12, "rho {rho} vs {rho_hand}");
        assert!((split.family_parent_sigma() - 0.025).abs() < 1e-15);
    }

    #[test]
    fn balanced_family_handles_three_children() {
        // Weights 0.2/0.3/0.5 with large child sigmas against a small parent sigma.
        let loads = [2.0, 3.0, 5.0];
        let sig = [0.05, 0.06, 0.07];
        let split = ErrorSplit::plan(&loads, &sig, 0.02);
        let cov = split.covariance();
        for k in 0..3 {
            assert!((cov[k][k].sqrt() - sig[k]).abs() < 1e-15);
        }
        assert!((parent_var_of(&split, &loads).sqrt() - 0.02).abs() < 1e-12);
        assert!(matches!(split.family, Family::Balanced { .. }));
    }

    #[test]
    fn infeasible_split_keeps_the_sum_and_reports_the_moved_sigma() {
        // 0.95 / 0.05 pair, children 1 %, parent 0.1 %: even full anti-correlation leaves
        // the parent at (0.95 - 0.05) % = 0.9 %.
        let loads = [95.0, 5.0];
        let split = ErrorSplit::plan(&loads, &[0.01, 0.01], 0.001);
        assert!((split.family_parent_sigma() - 0.009).abs() < 1e-12);
        assert!(split.child_sigma(0, 0.001) < 0.01);
        let mut rng = ChaCha8Rng::seed_from_u64(5);
        let mut out = Vec::new();
        split.draw(0.0007, &mut rng, &mut out);
        let sum = 0.95 * out[0] + 0.05 * out[1];
        assert!((sum - 0.0007).abs() < 1e-15, "{sum}");
    }

    #[test]
    fn conditional_draws_have_the_planned_sigmas() {
        // Sample check of the conditioning formula: parent drawn N(0, s_P^2), children drawn
        // given it. 40 000 draws: standard error of a sample sigma is sigma / sqrt(2 n)
        // = 0.35 %; 2 % is ~6 standard errors.
        let loads = [30.0, 70.0];
        let split = ErrorSplit::plan(&loads, &[0.055, 0.055], 0.035);
        let mut rng = ChaCha8Rng::seed_from_u64(11);
        let n = 40_000;
        let mut sum_sq = [0.0; 2];
        let mut out = Vec::with_capacity(2);
        for _ in 0..n {
            let z: f64 = rng.sample(StandardNormal);
            out.clear();
            split.draw(0.035 * z, &mut rng, &mut out);
            assert!((0.3 * out[0] + 0.7 * out[1] - 0.035 * z).abs() < 1e-15);
            sum_sq[0] += out[0] * out[0];
            sum_sq[1] += out[1] * out[1];
        }
        for s in sum_sq {
            let sigma = (s / n as f64).sqrt();
            assert!((sigma / 0.055 - 1.0).abs() < 0.02, "sigma {sigma}");
        }
    }

    #[test]
    fn one_child_is_the_parent() {
        let split = ErrorSplit::plan(&[10.0], &[0.07], 0.05);
        let mut rng = ChaCha8Rng::seed_from_u64(1);
        let mut out = Vec::new();
        split.draw(0.012, &mut rng, &mut out);
        assert_eq!(out, vec![0.012]);
        assert_eq!(split.child_sigma(0, 0.05), 0.05);
    }
}
