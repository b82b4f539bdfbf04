//! The eigen-structure of one azimuthal mode's transfer matrix
//! M = [[−A, −B], [B, A]] (Stam 2001 appendix E), reduced to size M.
//!
//! The eigenvalues are ±λ with λ² the eigenvalues of (A − B)(A + B). With
//! D = diag(μ), C = diag(w) the matrices are A ± B = D⁻¹(X ± Y)C for the
//! symmetric X = ΩP_same − C⁻¹ and Y = ΩP_opposite, so with
//! K = diag(√(w/μ)) the product is similar to Σ₋Σ₊, Σ± = K(X ± Y)K, two
//! symmetric matrices that are negative definite while Ω < 1. With
//! −Σ₊ = LLᵀ, the product's eigenvalues are those of the symmetric
//! Lᵀ(−Σ₋)L, which nalgebra's symmetric eigen-solver finds reliably (all
//! real and positive, as transport requires); no general eigen-solver is
//! needed.

use nalgebra::{DMatrix, DVector};

/// The eigen-structure of one mode: λ > 0 and the vectors v± of appendix E
/// as columns (the mode grows as e^{λτ} with components (v⁺, v⁻), and
/// decays as e^{−λτ} with (v⁻, v⁺)).
#[derive(Clone, Debug)]
pub struct ModeEigen {
    /// λ₁ … λ_M, > 0, in optical depths⁻¹.
    pub lambda: DVector<f64>,
    /// V⁺, one eigenvector per column.
    pub v_plus: DMatrix<f64>,
    /// V⁻, one eigenvector per column.
    pub v_minus: DMatrix<f64>,
}

/// Solves one mode given Ωₖpₖ on the ordinates (`same`, `opposite` from
/// [`super::phase::mode_kernels`]), the cosines `mu` and weights `w`.
/// Fails (with the reason) only if the scattering operator is not
/// dissipative on this rule, which δ-M moments and Ω < 1 rule out.
pub fn solve_mode(
    same: &[Vec<f64>],
    opposite: &[Vec<f64>],
    mu: &[f64],
    w: &[f64],
) -> Result<ModeEigen, String> {
    let size = mu.len();
    let k: Vec<f64> = (0..size).map(|i| (w[i] / mu[i]).sqrt()).collect();
    // −Σ± = K(C⁻¹ − Ω(P_same ± P_opposite))K.
    let neg_sigma = |sign: f64| {
        DMatrix::from_fn(size, size, |n, m| {
            let diagonal = if n == m { 1.0 / w[n] } else { 0.0 };
            k[n] * (diagonal - same[n][m] - sign * opposite[n][m]) * k[m]
        })
    };
    let n_plus = neg_sigma(1.0);
    let n_minus = neg_sigma(-1.0);
    let l = n_plus
        .clone()
        .cholesky()
        .ok_or("the scattering operator is not dissipative on this quadrature")?
        .unpack();
    let z = l.transpose() * &n_minus * &l;
    let z = (&z + z.transpose()) * 0.5;
    let eigen = z.symmetric_eigen();
    // Eigenvectors of N₋N₊ are N₋Ly; back in the A, B coordinates they are
    // multiplied by H⁻¹ = diag(1/√(μw)).
    let tilde = &n_minus * &l * &eigen.eigenvectors;
    let a_plus_b = DMatrix::from_fn(size, size, |n, m| {
        let diagonal = if n == m { 1.0 } else { 0.0 };
        (w[m] * (same[n][m] + opposite[n][m]) - diagonal) / mu[n]
    });
    let mut e = DMatrix::zeros(size, size);
    for j in 0..size {
        let mut column = DVector::from_fn(size, |i, _| tilde[(i, j)] / (mu[i] * w[i]).sqrt());
        let norm = column.norm();
        if !(norm.is_finite() && norm > 0.0) {
            return Err("an eigenvector vanished".into());
        }
        column /= norm;
        e.set_column(j, &column);
    }
    let lambda = eigen.eigenvalues.map(|alpha| alpha.max(0.0).sqrt());
    if lambda.iter().any(|&l| !(l.is_finite() && l > 0.0)) {
        return Err("an eigenvalue is not positive (albedo too close to 1?)".into());
    }
    // f = −(A + B)e/λ; v± = (e ± f)/2.
    let mut f = -(&a_plus_b * &e);
    for j in 0..size {
        let scale = 1.0 / lambda[j];
        f.column_mut(j).scale_mut(scale);
    }
    Ok(ModeEigen {
        lambda,
        v_plus: (&e + &f) * 0.5,
        v_minus: (&e - &f) * 0.5,
    })
}
