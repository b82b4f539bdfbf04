//! Sums of 2-D Gaussians: d'Eon & Luebke's measured skin, and a fit of any
//! profile minimising Mikkelsen's r-weighted squared error.

use crate::profile::Profile;
use crate::{Rgb, rgb_map};
use std::f64::consts::PI;

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
/// nor loses energy in Gaussians wider than the sampled range.
pub fn fit_gaussians(profile: &dyn Profile, count: usize) -> GaussianFit {
    let count = count.clamp(1, 16);
    let reach = profile.d_max(1e-5);
    use rayon::prelude::*;
    let fits: Vec<(Vec<(f64, f64)>, f64)> = (0..3)
        .into_par_iter()
        .map(|c| {
            fit_channel(
                |r| profile.reflectance(r)[c],
                profile.total_reflectance()[c],
                reach[c],
                count,
            )
        })
        .collect();
    GaussianFit {
        gaussians: SumOfGaussians {
            terms: [0, 1, 2].map(|c| fits[c].0.clone()),
        },
        error: rgb_map(|c| fits[c].1),
    }
}

fn fit_channel(
    profile: impl Fn(f64) -> f64,
    total: f64,
    reach: f64,
    count: usize,
) -> (Vec<(f64, f64)>, f64) {
    if !(reach > 0.0 && reach.is_finite() && total > 0.0) {
        return (vec![], 0.0);
    }
    // Quadrature of ∫ r f² dr = ∫ r² f² d(ln r) on a log grid up to the reach.
    let samples = 400;
    let r_lo = reach * 1e-5;
    let h = (reach / r_lo).ln() / (samples - 1) as f64;
    let radii: Vec<f64> = (0..samples).map(|i| r_lo * (i as f64 * h).exp()).collect();
    let mut target: Vec<f64> = radii.iter().map(|&r| profile(r)).collect();
    let mut quad: Vec<f64> = radii.iter().map(|r| r * r * h).collect();
    let norm: f64 = target.iter().zip(&quad).map(|(t, q)| q * t * t).sum();
    if !(norm > 0.0 && norm.is_finite()) {
        return (vec![], 0.0);
    }
    // One more row: Σw = total, weighted so a 1% miss costs the whole norm.
    target.push(total);
    quad.push(1e4 * norm / (total * total));

    let (v_lo, v_hi) = ((10.0 * r_lo).powi(2), (reach / 3.0).powi(2));
    let (x_min, x_max) = ((r_lo * r_lo).ln(), (reach * reach).ln());
    let system = System {
        radii: &radii,
        target: &target,
        quad: &quad,
    };

    // Start from variances spread geometrically over the profile's range.
    let mut x: Vec<f64> = (0..count)
        .map(|k| {
            let t = if count == 1 {
                0.5
            } else {
                k as f64 / (count - 1) as f64
            };
            v_lo.ln() + t * (v_hi.ln() - v_lo.ln())
        })
        .collect();
    // A pattern search moves one variance at a time, so only that
    // Gaussian's column and its row of the normal equations are recomputed
    // for a trial; the rest are kept.
    let mut normal = Normal::new(&system, &x);
    let mut best = normal.fit(&system).0;
    let mut step = 1.0;
    while step > 1e-3 {
        let mut improved = false;
        for (k, x_k) in x.iter_mut().enumerate() {
            for direction in [1.0, -1.0] {
                let moved = (*x_k + direction * step).clamp(x_min, x_max);
                let kept = normal.replace(&system, k, moved);
                let value = normal.fit(&system).0;
                if value < best {
                    best = value;
                    *x_k = moved;
                    improved = true;
                    break;
                }
                normal.restore(k, kept);
            }
        }
        if !improved {
            step *= 0.5;
        }
    }
    let (error, weights) = normal.fit(&system);
    let mut terms: Vec<(f64, f64)> = weights
        .into_iter()
        .zip(x.iter().map(|lv| lv.exp()))
        .collect();
    terms.sort_by(|a, b| a.1.total_cmp(&b.1));
    (terms, (error / norm).sqrt())
}

/// The least-squares problem of a fit: the profile's samples at `radii`
/// (then the total), weighed by `quad`.
struct System<'a> {
    radii: &'a [f64],
    target: &'a [f64],
    quad: &'a [f64],
}

impl System<'_> {
    /// The Gaussian of ln-variance `log_var` at each sample radius, then 1
    /// (its share of the total).
    fn column(&self, log_var: f64) -> Vec<f64> {
        let v = log_var.exp();
        self.radii
            .iter()
            .map(|&r| gaussian(v, r))
            .chain([1.0])
            .collect()
    }

    /// Σ_s q_s a_s b_s.
    fn dot(&self, a: &[f64], b: &[f64]) -> f64 {
        (0..self.target.len())
            .map(|s| self.quad[s] * a[s] * b[s])
            .sum()
    }
}

/// The columns of a set of Gaussians and their normal equations.
struct Normal {
    columns: Vec<Vec<f64>>,
    gram: Vec<Vec<f64>>,
    rhs: Vec<f64>,
}

/// What [`Normal::replace`] displaced, for [`Normal::restore`].
struct Kept {
    column: Vec<f64>,
    row: Vec<f64>,
    rhs: f64,
}

impl Normal {
    fn new(system: &System, log_vars: &[f64]) -> Self {
        let columns: Vec<Vec<f64>> = log_vars.iter().map(|&lv| system.column(lv)).collect();
        let gram = columns
            .iter()
            .map(|a| columns.iter().map(|b| system.dot(a, b)).collect())
            .collect();
        let rhs = columns
            .iter()
            .map(|a| system.dot(a, system.target))
            .collect();
        Normal { columns, gram, rhs }
    }

    /// Moves Gaussian `k` to ln-variance `log_var`.
    fn replace(&mut self, system: &System, k: usize, log_var: f64) -> Kept {
        let column = std::mem::replace(&mut self.columns[k], system.column(log_var));
        let row: Vec<f64> = self.gram[k].clone();
        for j in 0..self.columns.len() {
            let g = system.dot(&self.columns[k], &self.columns[j]);
            self.gram[k][j] = g;
            self.gram[j][k] = g;
        }
        let rhs = std::mem::replace(
            &mut self.rhs[k],
            system.dot(&self.columns[k], system.target),
        );
        Kept { column, row, rhs }
    }

    /// Undoes the [`Normal::replace`] of Gaussian `k`.
    fn restore(&mut self, k: usize, kept: Kept) {
        self.columns[k] = kept.column;
        for (j, &g) in kept.row.iter().enumerate() {
            self.gram[k][j] = g;
            self.gram[j][k] = g;
        }
        self.rhs[k] = kept.rhs;
    }

    /// The non-negative weights and the squared error they leave over the
    /// profile's samples (the total's row is a constraint, not error).
    fn fit(&self, system: &System) -> (f64, Vec<f64>) {
        let weights = non_negative_least_squares(&self.gram, &self.rhs);
        let samples = system.radii.len();
        let error = (0..samples)
            .map(|i| {
                let fit: f64 = self
                    .columns
                    .iter()
                    .zip(&weights)
                    .map(|(col, w)| w * col[i])
                    .sum();
                system.quad[i] * (system.target[i] - fit).powi(2)
            })
            .sum();
        (error, weights)
    }
}

/// Minimises Σ q_i (t_i − Σ_k w_k a_ki)² over w ≥ 0, given its normal
/// equations (`gram` = AᵀQA, `rhs` = AᵀQt), dropping the most negative
/// weight until none is negative.
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
