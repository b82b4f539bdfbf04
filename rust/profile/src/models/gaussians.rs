//! Sums of 2-D Gaussians: d'Eon & Luebke's measured skin, and a fit of any
//! profile minimising Mikkelsen's r-weighted squared error.

use crate::profile::Profile;
use crate::{Rgb, rgb_map};
use std::f64::consts::PI;
use std::rc::Rc;

/// Per channel, a list of (weight, variance in mm²) terms
/// R(r) = Σ w·e^{−r²/2v}/(2πv).
#[derive(Clone, Debug, PartialEq)]
pub struct SumOfGaussians {
    /// Terms per channel.
    pub terms: [Vec<(f64, f64)>; 3],
}

/// d'Eon & Luebke 2007's six-Gaussian skin (Mikkelsen table 4): variances in
/// mm² and red, green, blue weights. Each channel's weights sum to 1, so the
/// profile carries no colour of its own.
pub const DEON_SKIN: [(f64, Rgb); 6] = [
    (0.0064, [0.233, 0.455, 0.649]),
    (0.0484, [0.1, 0.336, 0.344]),
    (0.187, [0.118, 0.198, 0.0]),
    (0.567, [0.113, 0.007, 0.007]),
    (1.99, [0.358, 0.004, 0.0]),
    (7.41, [0.078, 0.0, 0.0]),
];

impl SumOfGaussians {
    /// d'Eon & Luebke's skin.
    pub fn deon_skin() -> Self {
        Self {
            terms: [0, 1, 2].map(|c| DEON_SKIN.iter().map(|(v, w)| (w[c], *v)).collect()),
        }
    }
}

/// The normalised 2-D Gaussian e^{−r²/2v}/(2πv), 1/mm².
pub fn gaussian(variance: f64, r: f64) -> f64 {
    (-r * r / (2.0 * variance)).exp() / (2.0 * PI * variance)
}

impl Profile for SumOfGaussians {
    fn model(&self) -> &'static str {
        "gaussians"
    }

    fn reflectance(&self, r: f64) -> Rgb {
        rgb_map(|c| self.terms[c].iter().map(|&(w, v)| w * gaussian(v, r)).sum())
    }

    fn total_reflectance(&self) -> Rgb {
        rgb_map(|c| self.terms[c].iter().map(|&(w, _)| w).sum())
    }

    /// Each Gaussian transforms to w·e^{−k²v/2}.
    fn reflectance_spectrum(&self, k: f64) -> Option<Rgb> {
        Some(rgb_map(|c| {
            self.terms[c]
                .iter()
                .map(|&(w, v)| w * (-0.5 * k * k * v).exp())
                .sum()
        }))
    }

    fn enclosed_reflectance(&self, r: f64) -> Rgb {
        rgb_map(|c| {
            self.terms[c]
                .iter()
                .map(|&(w, v)| -w * (-r * r / (2.0 * v)).exp_m1())
                .sum()
        })
    }

    fn length_scale(&self) -> Rgb {
        rgb_map(|c| {
            let total: f64 = self.terms[c].iter().map(|t| t.0).sum();
            let mean_var: f64 =
                self.terms[c].iter().map(|&(w, v)| w * v).sum::<f64>() / total.max(1e-300);
            mean_var.sqrt().max(1e-9)
        })
    }
}

/// A fitted sum of Gaussians and how far it is from the profile.
#[derive(Clone, Debug)]
pub struct GaussianFit {
    /// The fit.
    pub gaussians: SumOfGaussians,
    /// Relative r-weighted RMS error per channel:
    /// √(∫ r (R − fit)² dr / ∫ r R² dr).
    pub error: Rgb,
}

/// Fits `count` Gaussians per channel to `profile`: non-negative weights by
/// least squares for given variances, variances by pattern search in ln v
/// within the profile's reach. The weights also honour the profile's total
/// reflectance (a stiff penalty on Σw − R_total), so the fit neither gains
/// nor loses energy in Gaussians wider than the sampled range. Channels
/// whose samples are the same (a grey material) are fitted once.
pub fn fit_gaussians(profile: &dyn Profile, count: usize) -> GaussianFit {
    let count = count.clamp(1, 16);
    let reach = profile.d_max(1e-5);
    let total = profile.total_reflectance();
    let problems: Vec<Option<Problem>> = (0..3)
        .map(|c| Problem::sample(|r| profile.reflectance(r)[c], total[c], reach[c]))
        .collect();
    // Each channel fitted once unless an earlier one posed the same problem.
    let first_alike: Vec<usize> = (0..3)
        .map(|c| (0..c).find(|&e| problems[e] == problems[c]).unwrap_or(c))
        .collect();
    use rayon::prelude::*;
    let fits: Vec<Option<ChannelFit>> = (0..3)
        .into_par_iter()
        .map(|c| {
            (first_alike[c] == c).then(|| match &problems[c] {
                Some(problem) => problem.fit(count),
                None => (vec![], 0.0),
            })
        })
        .collect();
    let fit_of = |c: usize| fits[first_alike[c]].clone().unwrap_or_default();
    GaussianFit {
        gaussians: SumOfGaussians {
            terms: [0, 1, 2].map(|c| fit_of(c).0),
        },
        error: rgb_map(|c| fit_of(c).1),
    }
}

/// One channel's fit: its (weight, variance in mm²) terms sorted by
/// variance, and its relative r-weighted RMS error.
type ChannelFit = (Vec<(f64, f64)>, f64);

/// One channel's fitting problem: the profile sampled on a log grid up to
/// its reach, the quadrature weights of ∫ r f² dr = ∫ r² f² d(ln r) there,
/// and one more row asking Σw = total, weighted so a 1% miss costs the
/// whole norm.
#[derive(Debug, PartialEq)]
struct Problem {
    radii: Vec<f64>,
    /// The samples, then the total reflectance.
    target: Vec<f64>,
    /// The quadrature weights, then the total's weight.
    quad: Vec<f64>,
    /// ∫ r f² dr.
    norm: f64,
    r_lo: f64,
    reach: f64,
}

/// Radii in a channel's fitting grid.
const FIT_SAMPLES: usize = 400;

impl Problem {
    /// Samples `profile` up to `reach`; None when there is nothing to fit.
    fn sample(profile: impl Fn(f64) -> f64, total: f64, reach: f64) -> Option<Self> {
        if !(reach > 0.0 && reach.is_finite() && total > 0.0) {
            return None;
        }
        let r_lo = reach * 1e-5;
        let h = (reach / r_lo).ln() / (FIT_SAMPLES - 1) as f64;
        let radii: Vec<f64> = (0..FIT_SAMPLES)
            .map(|i| r_lo * (i as f64 * h).exp())
            .collect();
        let mut target: Vec<f64> = radii.iter().map(|&r| profile(r)).collect();
        let mut quad: Vec<f64> = radii.iter().map(|r| r * r * h).collect();
        let norm: f64 = target.iter().zip(&quad).map(|(t, q)| q * t * t).sum();
        if !(norm > 0.0 && norm.is_finite()) {
            return None;
        }
        target.push(total);
        quad.push(1e4 * norm / (total * total));
        Some(Self {
            radii,
            target,
            quad,
            norm,
            r_lo,
            reach,
        })
    }

    /// The Gaussian of variance e^`log_var` at every radius, then 1 (its
    /// weight's share of the total).
    fn column(&self, log_var: f64) -> Vec<f64> {
        self.radii
            .iter()
            .map(|&r| gaussian(log_var.exp(), r))
            .chain([1.0])
            .collect()
    }

    /// Σ q a b over every row.
    fn product(&self, a: &[f64], b: &[f64]) -> f64 {
        (0..self.target.len())
            .map(|s| self.quad[s] * a[s] * b[s])
            .sum()
    }

    /// The weighted squared error of the weights' sum over the samples.
    fn error(&self, columns: &[Rc<Vec<f64>>], weights: &[f64]) -> f64 {
        (0..FIT_SAMPLES)
            .map(|i| {
                let fit: f64 = columns.iter().zip(weights).map(|(col, w)| w * col[i]).sum();
                self.quad[i] * (self.target[i] - fit).powi(2)
            })
            .sum()
    }

    /// The fit of `count` Gaussians, sorted by variance, and its relative
    /// r-weighted RMS error.
    fn fit(&self, count: usize) -> ChannelFit {
        let (r_lo, reach) = (self.r_lo, self.reach);
        let (v_lo, v_hi) = ((10.0 * r_lo).powi(2), (reach / 3.0).powi(2));
        let (x_min, x_max) = ((r_lo * r_lo).ln(), (reach * reach).ln());
        // Start from variances spread geometrically over the profile's range.
        let x: Vec<f64> = (0..count)
            .map(|k| {
                let t = if count == 1 {
                    0.5
                } else {
                    k as f64 / (count - 1) as f64
                };
                v_lo.ln() + t * (v_hi.ln() - v_lo.ln())
            })
            .collect();
        let mut state = State::new(self, x);
        let mut best = state.evaluate(self).0;
        let mut step = 1.0;
        while step > 1e-3 {
            let mut improved = false;
            for k in 0..count {
                for direction in [1.0, -1.0] {
                    let moved = (state.x[k] + direction * step).clamp(x_min, x_max);
                    let trial = state.moved(self, k, moved);
                    let value = trial.evaluate(self).0;
                    if value < best {
                        best = value;
                        state = trial;
                        improved = true;
                        break;
                    }
                }
            }
            if !improved {
                step *= 0.5;
            }
        }
        let (error, weights) = state.evaluate(self);
        let mut terms: Vec<(f64, f64)> = weights
            .into_iter()
            .zip(state.x.iter().map(|lv| lv.exp()))
            .collect();
        terms.sort_by(|a, b| a.1.total_cmp(&b.1));
        (terms, (error / self.norm).sqrt())
    }
}

/// The log variances being searched, with their columns and normal
/// equations kept up to date: a pattern search moves one variance at a
/// time, so a trial recomputes one column and one row of the Gram matrix.
#[derive(Clone)]
struct State {
    x: Vec<f64>,
    /// Shared with the states a trial came from, so a trial copies only
    /// what it changes.
    columns: Vec<Rc<Vec<f64>>>,
    /// gram[i][j] = Σ q a_i a_j.
    gram: Vec<Vec<f64>>,
    /// rhs[i] = Σ q a_i t.
    rhs: Vec<f64>,
}

impl State {
    fn new(problem: &Problem, x: Vec<f64>) -> Self {
        let columns: Vec<Rc<Vec<f64>>> = x.iter().map(|&lv| Rc::new(problem.column(lv))).collect();
        let gram = columns
            .iter()
            .map(|a| columns.iter().map(|b| problem.product(a, b)).collect())
            .collect();
        let rhs = columns
            .iter()
            .map(|a| problem.product(a, &problem.target))
            .collect();
        Self {
            x,
            columns,
            gram,
            rhs,
        }
    }

    /// This state with variance `k` moved to e^`log_var`.
    fn moved(&self, problem: &Problem, k: usize, log_var: f64) -> Self {
        let mut next = self.clone();
        next.x[k] = log_var;
        next.columns[k] = Rc::new(problem.column(log_var));
        for j in 0..next.x.len() {
            next.gram[k][j] = problem.product(&next.columns[k], &next.columns[j]);
            next.gram[j][k] = problem.product(&next.columns[j], &next.columns[k]);
        }
        next.rhs[k] = problem.product(&next.columns[k], &problem.target);
        next
    }

    /// The squared error of the best non-negative weights, and the weights.
    fn evaluate(&self, problem: &Problem) -> (f64, Vec<f64>) {
        let weights = non_negative_least_squares(&self.gram, &self.rhs);
        (problem.error(&self.columns, &weights), weights)
    }
}

/// Minimises Σ q_i (t_i − Σ_k w_k a_ki)² over w ≥ 0 by the normal equations
/// (`gram`, `rhs`), dropping the most negative weight until none is negative.
fn non_negative_least_squares(gram: &[Vec<f64>], rhs: &[f64]) -> Vec<f64> {
    let n = rhs.len();
    let mut active: Vec<usize> = (0..n).collect();
    loop {
        let sub_gram = active
            .iter()
            .map(|&i| active.iter().map(|&j| gram[i][j]).collect())
            .collect();
        let sub_rhs = active.iter().map(|&i| rhs[i]).collect();
        let solution = solve_symmetric(sub_gram, sub_rhs);
        let mut weights = vec![0.0; n];
        for (a, &i) in active.iter().enumerate() {
            weights[i] = solution[a];
        }
        match active
            .iter()
            .enumerate()
            .filter(|(a, _)| solution[*a] < 0.0 || solution[*a].is_nan())
            .min_by(|x, y| solution[x.0].total_cmp(&solution[y.0]))
        {
            None => return weights,
            Some((a, _)) => {
                active.remove(a);
                if active.is_empty() {
                    return vec![0.0; n];
                }
            }
        }
    }
}

/// Solves a small symmetric positive semi-definite system by Gaussian
/// elimination with partial pivoting and a tiny ridge for near-singular sets.
fn solve_symmetric(mut a: Vec<Vec<f64>>, mut b: Vec<f64>) -> Vec<f64> {
    let n = b.len();
    let scale = (0..n).map(|i| a[i][i]).fold(0.0f64, f64::max).max(1e-300);
    for (i, row) in a.iter_mut().enumerate() {
        row[i] += 1e-12 * scale;
    }
    for col in 0..n {
        let pivot = (col..n)
            .max_by(|&x, &y| a[x][col].abs().total_cmp(&a[y][col].abs()))
            .unwrap_or(col);
        a.swap(col, pivot);
        b.swap(col, pivot);
        let p = a[col][col];
        if p.abs() < 1e-300 {
            continue;
        }
        for row in col + 1..n {
            let f = a[row][col] / p;
            let (upper, lower) = a.split_at_mut(row);
            for (x, p) in lower[0][col..].iter_mut().zip(&upper[col][col..]) {
                *x -= f * p;
            }
            b[row] -= f * b[col];
        }
    }
    let mut x = vec![0.0; n];
    for row in (0..n).rev() {
        let s: f64 = (row + 1..n).map(|k| a[row][k] * x[k]).sum();
        x[row] = if a[row][row].abs() > 1e-300 {
            (b[row] - s) / a[row][row]
        } else {
            0.0
        };
    }
    x
}
