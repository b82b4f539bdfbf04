//! The contour-wise fit of Donner et al. 2009 §4.1: the lobe H (eq. 8)
//! fitted to one simulated hemisphere of exitant radiance.
//!
//! k_s first makes H match the data at the peak (eq. 8). Along the plane of symmetry
//! (the disc's x-axis, where ν = 0 and μ = cosh⁻¹(x/a±), eq. 9) every
//! sample between 10% and 100% of the peak gives one row of the linear
//! system of eq. 10 for k_e and k_c, solved in the least-squares sense on
//! each side of the peak, keeping the smaller value of each. Given those,
//! each sample gives a candidate a± by eq. 11; the candidate with the
//! smallest L2 error over the hemisphere is kept. The tally has no
//! direction bins on a line across the plane of symmetry through an
//! off-centre peak, so b (b⁺ = b⁻, equal by the mirror symmetry of normal
//! incidence) is chosen by the same L2 criterion from a geometric ladder
//! of candidates, and k_e with it (axis samples between the foci have
//! μ = 0 and cannot set k_e, yet it is what narrows the lobe across the
//! plane: near the entry point, light scattered once leaves exactly along
//! the plane, a ridge at φ_o = 0). The loop repeats ten times or until
//! the error changes by less than 1%. The error compares each bin's
//! simulated radiance with the lobe's mean over the bin.
//!
//! Once the shape is fitted, k_s is rescaled so the lobe's exitance
//! ∫ H cos θ_o dω equals the slice's simulated exitance (a departure from
//! the paper: one bright bin then cannot set the profile's energy, and
//! R(r) keeps the simulation's light); [`SliceFit::peak_ratio`] records
//! how far that moves the peak.

use crate::models::empirical::lobe::{FOCUS_RANGE, Lobe, exit_transmittance};
use crate::models::empirical::simulation::Grid;
use std::f64::consts::FRAC_PI_2;

/// The lowest contour level read, as a fraction of the peak (§4.1: 10%)...
const LOWEST_CONTOUR: f64 = 0.1;
/// ...lowered to this where a side of the peak has fewer than two samples
/// above 10% (a lobe narrower than the tally's direction bins).
const LOWEST_CONTOUR_NARROW: f64 = 0.01;
/// Iterations of the fit at most (§4.1).
const ITERATIONS: usize = 10;
/// Candidate values of b on a geometric ladder over [`FOCUS_RANGE`].
const B_LADDER: usize = 40;
/// Candidate values of k_e on a geometric ladder over `K_RANGE` (and 0).
const K_LADDER: usize = 30;
/// The range of k_e candidates.
const K_RANGE: (f64, f64) = (0.05, 200.0);

/// A fitted lobe and how well it follows its hemisphere.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct SliceFit {
    /// The fitted lobe.
    pub lobe: Lobe,
    /// RMS over the hemisphere (solid-angle weighted) of H, averaged over
    /// each direction bin, minus the simulated radiance, 1/(ℓ² sr): the
    /// paper's fit error (§4.3).
    pub rms: f64,
    /// RMS of the simulation's own standard errors over the same bins: the
    /// part of `rms` that is noise in the data, not misfit.
    pub noise_rms: f64,
    /// The simulated radiance at the peak, 1/(ℓ² sr).
    pub peak: f64,
    /// The lobe's radiance at the peak over the simulated one: 1 under
    /// the paper's k_s (§4), other than 1 once k_s keeps the exitance.
    pub peak_ratio: f64,
}

/// A data sample on the unit disc (eq. 5).
#[derive(Clone, Copy)]
struct Sample {
    x: f64,
    y: f64,
    theta: f64,
    weight: f64,
    value: f64,
    /// Four points (x_d, y_d, F_t) splitting the bin into quarters of
    /// equal projected solid angle, where the lobe's bin average is read.
    nodes: [(f64, f64, f64); 4],
}

impl Sample {
    /// The lobe's mean radiance over the bin, as the tally measures it.
    fn mean(&self, lobe: &Lobe) -> f64 {
        0.25 * self
            .nodes
            .iter()
            .map(|&(x, y, ft)| lobe.shape(x, y) * ft)
            .sum::<f64>()
    }
}

/// The quarter points of direction bin (i, k): two θ_o at a quarter and
/// three quarters of its sin²θ_o span, two φ_o at a quarter and three
/// quarters of its φ_o span on the y_d ≥ 0 side (the lobe is mirror
/// symmetric, b⁺ = b⁻).
fn quarter_nodes(grid: &Grid, i: usize, k: usize, eta: f64) -> [(f64, f64, f64); 4] {
    let n = grid.theta_bins as f64;
    let step = grid.phi_step();
    let (phi0, phi1) = if k == 0 {
        (0.0, 0.5 * step)
    } else if k + 1 == grid.phi_bins {
        (std::f64::consts::PI - 0.5 * step, std::f64::consts::PI)
    } else {
        (
            grid.phi_centre(k) - 0.5 * step,
            grid.phi_centre(k) + 0.5 * step,
        )
    };
    let node = |t: f64, f: f64| {
        let theta = ((i as f64 + t) / n).sqrt().min(1.0).asin();
        let phi = phi0 + f * (phi1 - phi0);
        let rho = theta / FRAC_PI_2;
        (
            rho * phi.cos(),
            rho * phi.sin(),
            exit_transmittance(theta.cos(), eta),
        )
    };
    [
        node(0.25, 0.25),
        node(0.25, 0.75),
        node(0.75, 0.25),
        node(0.75, 0.75),
    ]
}

/// Fits the lobe to `values` (radiance per direction bin of `grid`, with
/// standard errors `errors`) for a boundary of relative index `eta`, its
/// exitance kept at `exitance` (1/ℓ²).
pub fn fit_slice(grid: &Grid, values: &[f64], errors: &[f64], eta: f64, exitance: f64) -> SliceFit {
    let samples: Vec<Sample> = (0..grid.theta_bins)
        .flat_map(|i| (0..grid.phi_bins).map(move |k| (i, k)))
        .map(|(i, k)| {
            let theta = grid.theta_centre(i);
            let rho = theta / FRAC_PI_2;
            let phi = grid.phi_centre(k);
            Sample {
                x: rho * phi.cos(),
                y: rho * phi.sin(),
                theta,
                weight: grid.solid_angle(i, k),
                value: values[grid.index(i, k)],
                nodes: quarter_nodes(grid, i, k, eta),
            }
        })
        .collect();
    let total_weight: f64 = samples.iter().map(|s| s.weight).sum();
    let noise_rms = (samples
        .iter()
        .zip(0..)
        .map(|(s, j)| {
            let (i, k) = (j / grid.phi_bins, j % grid.phi_bins);
            s.weight * errors[grid.index(i, k)].powi(2)
        })
        .sum::<f64>()
        / total_weight)
        .sqrt();
    let error = |lobe: &Lobe| {
        let sum: f64 = samples
            .iter()
            .map(|s| s.weight * (s.mean(lobe) - s.value).powi(2))
            .sum();
        (sum / total_weight).sqrt()
    };

    // The axis samples (φ_o = 0 and π) hold the peak and the contours.
    let axis: Vec<Sample> = samples
        .iter()
        .copied()
        .filter(|s| s.y.abs() < 1e-12)
        .collect();
    let Some(peak) = axis
        .iter()
        .copied()
        .filter(|s| s.value > 0.0 && s.value.is_finite())
        .max_by(|a, b| a.value.total_cmp(&b.value))
    else {
        let lobe = Lobe::dark();
        return SliceFit {
            rms: error(&lobe),
            lobe,
            noise_rms,
            peak: 0.0,
            peak_ratio: 1.0,
        };
    };
    let k_s = peak.value / exit_transmittance(peak.theta.cos(), eta).max(1e-12);
    // −log(c_i H(peak)/F_t) per sample, with its offset from the peak.
    let rows_above = |level: f64| -> Vec<(f64, f64)> {
        axis.iter()
            .filter(|s| s.value >= level * peak.value && s.x != peak.x)
            .filter_map(|s| {
                let ft = exit_transmittance(s.theta.cos(), eta);
                (ft > 0.0).then(|| (s.x - peak.x, -(s.value / (ft * k_s)).ln()))
            })
            .collect()
    };
    let mut rows = rows_above(LOWEST_CONTOUR);
    let narrow = [1.0, -1.0]
        .iter()
        .any(|side| rows.iter().filter(|r| r.0 * side > 0.0).count() < 2);
    if narrow {
        rows = rows_above(LOWEST_CONTOUR_NARROW);
    }

    let mut lobe = Lobe {
        peak_x: peak.x,
        a_plus: 0.2,
        a_minus: 0.2,
        b_plus: 0.2,
        b_minus: 0.2,
        k_e: 0.0,
        k_c: 0.0,
        k_s,
    };
    let mut best = f64::INFINITY;
    for _ in 0..ITERATIONS {
        (lobe.k_e, lobe.k_c) = falloffs(&rows, lobe.a_plus, lobe.a_minus);
        for side in [1.0, -1.0] {
            let mut candidates = vec![if side > 0.0 {
                lobe.a_plus
            } else {
                lobe.a_minus
            }];
            if lobe.k_e > 0.0 {
                // Eq. 11: a = x / cosh((−log(c_i H/F_t) − k_c x)/k_e).
                candidates.extend(rows.iter().filter(|r| r.0 * side > 0.0).map(|&(x, rhs)| {
                    let x = x.abs();
                    x / ((rhs - lobe.k_c * x) / lobe.k_e).max(0.0).cosh()
                }));
            }
            let chosen = choose(&candidates, FOCUS_RANGE, |a| {
                let mut trial = lobe;
                if side > 0.0 {
                    trial.a_plus = a;
                } else {
                    trial.a_minus = a;
                }
                error(&trial)
            });
            if side > 0.0 {
                lobe.a_plus = chosen;
            } else {
                lobe.a_minus = chosen;
            }
        }
        // Samples on the plane of symmetry between the foci have μ = 0 and
        // say nothing of k_e; across the plane (b) it is what narrows the
        // lobe, so k_e and b are refined together by the L2 criterion.
        let (lo, hi) = FOCUS_RANGE;
        let mut b_ladder = vec![lobe.b_plus];
        b_ladder.extend(ladder(lo, hi, B_LADDER));
        let mut k_ladder = vec![lobe.k_e, 0.0];
        k_ladder.extend(ladder(K_RANGE.0, K_RANGE.1, K_LADDER));
        for _ in 0..2 {
            let b = choose(&b_ladder, FOCUS_RANGE, |b| {
                error(&Lobe {
                    b_plus: b,
                    b_minus: b,
                    ..lobe
                })
            });
            lobe.b_plus = b;
            lobe.b_minus = b;
            lobe.k_e = choose(&k_ladder, (0.0, K_RANGE.1), |k_e| {
                error(&Lobe { k_e, ..lobe })
            });
        }
        let now = error(&lobe);
        let settled = (best - now).abs() <= 0.01 * best;
        best = best.min(now);
        if settled {
            break;
        }
    }
    let shaped = lobe.exitance(eta);
    if shaped > 0.0 && exitance.is_finite() && exitance >= 0.0 {
        lobe.k_s *= exitance / shaped;
    }
    SliceFit {
        rms: error(&lobe),
        lobe,
        noise_rms,
        peak: peak.value,
        peak_ratio: lobe.k_s / k_s,
    }
}

/// `n` values from `lo` to `hi`, evenly spaced in ln.
fn ladder(lo: f64, hi: f64, n: usize) -> impl Iterator<Item = f64> {
    (0..n).map(move |i| lo * (hi / lo).powf(i as f64 / (n - 1) as f64))
}

/// The candidate (clamped to `range`) with the smallest `error`, the
/// first on ties.
fn choose(candidates: &[f64], range: (f64, f64), error: impl Fn(f64) -> f64) -> f64 {
    let (lo, hi) = range;
    candidates
        .iter()
        .filter(|c| c.is_finite())
        .map(|&c| c.clamp(lo, hi))
        .map(|c| (error(c), c))
        .reduce(|best, next| if next.0 < best.0 { next } else { best })
        .map_or(lo.max(0.2), |(_, c)| c)
}

/// k_e and k_c by eq. 10 on each side of the peak, the smaller of each
/// kept (§4.1), both non-negative so the lobe never grows away from its
/// peak.
fn falloffs(rows: &[(f64, f64)], a_plus: f64, a_minus: f64) -> (f64, f64) {
    let mut k_e = f64::INFINITY;
    let mut k_c = f64::INFINITY;
    for (side, a) in [(1.0, a_plus), (-1.0, a_minus)] {
        let side_rows: Vec<(f64, f64, f64)> = rows
            .iter()
            .filter(|r| r.0 * side > 0.0)
            .map(|&(x, rhs)| ((x.abs() / a).max(1.0).acosh(), x.abs(), rhs))
            .collect();
        if let Some((e, c)) = least_squares(&side_rows) {
            k_e = k_e.min(e.max(0.0));
            k_c = k_c.min(c.max(0.0));
        }
    }
    let clean = |k: f64| if k.is_finite() { k.max(0.0) } else { 0.0 };
    (clean(k_e), clean(k_c))
}

/// Least squares of rhs = k_e μ + k_c χ over rows (μ, χ, rhs); with μ all
/// zero (every sample inside the focal segment) k_e is 0 and k_c alone fits.
fn least_squares(rows: &[(f64, f64, f64)]) -> Option<(f64, f64)> {
    if rows.is_empty() {
        return None;
    }
    let (mut mm, mut mc, mut cc, mut mr, mut cr) = (0.0, 0.0, 0.0, 0.0, 0.0);
    for &(m, c, r) in rows {
        mm += m * m;
        mc += m * c;
        cc += c * c;
        mr += m * r;
        cr += c * r;
    }
    let det = mm * cc - mc * mc;
    if rows.len() >= 2 && det > 1e-12 * (mm * cc).max(1e-300) {
        Some(((mr * cc - cr * mc) / det, (mm * cr - mc * mr) / det))
    } else if cc > 0.0 {
        Some((0.0, cr / cc))
    } else {
        None
    }
}
