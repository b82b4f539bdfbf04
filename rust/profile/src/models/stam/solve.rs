//! The boundary-value problem of one azimuthal mode (Stam 2001 §3.2,
//! eq. 15) with the scaled exponentials of Stamnes & Conklin: the growing
//! solutions are referred to the bottom of the layer, so every exponential
//! in the system is e^{−λτ} ≤ 1 and a thick layer cannot overflow.

use super::boundary::ModeBoundary;
use super::eigen::ModeEigen;
use nalgebra::DMatrix;

/// Radiance leaving one mode, per unit irradiance on each outside ordinate.
pub struct ModeSolution {
    /// Radiance reflected into air (E×E: outside ordinate × incidence).
    pub reflected: DMatrix<f64>,
    /// Radiance transmitted into the air below (E×E).
    pub transmitted: DMatrix<f64>,
}

/// Solves one mode of a layer of (scaled) optical depth `depth` for the
/// incident radiances `incident` (E×E, a column per incidence) given the
/// mode's eigen-structure and boundary operators.
pub fn solve_mode(
    eigen: &ModeEigen,
    boundary: &ModeBoundary,
    depth: f64,
    incident: &DMatrix<f64>,
) -> Result<ModeSolution, String> {
    let r = &boundary.reflect_inside;
    let inside = solve_between(eigen, r, r, depth, &(&boundary.transmit_in * incident))?;
    Ok(ModeSolution {
        reflected: &boundary.reflect_outside * incident
            + &boundary.transmit_out * &inside.up_at_top,
        transmitted: &boundary.transmit_out * &inside.down_at_bottom,
    })
}

/// The radiance just inside both faces, per source column.
pub struct InsideRadiance {
    /// Upwelling radiance just under the top face (M×columns).
    pub up_at_top: DMatrix<f64>,
    /// Downwelling radiance just over the bottom face (M×columns).
    pub down_at_bottom: DMatrix<f64>,
}

/// Solves one mode between a top face that reflects the upwelling
/// radiance by `top` (M×M) and a bottom face that reflects the
/// downwelling radiance by `bottom`, for the downwelling radiances
/// `source` (M×columns) entering just under the top face: Stam's eq. 15
/// with each face's own operator (0 for a face in optical contact).
pub fn solve_between(
    eigen: &ModeEigen,
    top: &DMatrix<f64>,
    bottom: &DMatrix<f64>,
    depth: f64,
    source: &DMatrix<f64>,
) -> Result<InsideRadiance, String> {
    let m = eigen.lambda.len();
    let (vp, vm) = (&eigen.v_plus, &eigen.v_minus);
    // E(−τb): diagonal decay across the layer; 0 for a semi-infinite one.
    let decay = DMatrix::from_fn(m, m, |i, j| {
        if i == j {
            let x = eigen.lambda[i] * depth;
            if x.is_finite() { (-x).exp() } else { 0.0 }
        } else {
            0.0
        }
    });
    let mut system = DMatrix::zeros(2 * m, 2 * m);
    // Top: u⁻(0) − R_top u⁺(0) = source.
    system
        .view_mut((0, 0), (m, m))
        .copy_from(&((vm - top * vp) * &decay));
    system.view_mut((0, m), (m, m)).copy_from(&(vp - top * vm));
    // Bottom: u⁺(τ) − R_bottom u⁻(τ) = 0.
    system
        .view_mut((m, 0), (m, m))
        .copy_from(&(vp - bottom * vm));
    system
        .view_mut((m, m), (m, m))
        .copy_from(&((vm - bottom * vp) * &decay));
    let columns = source.ncols();
    let mut rhs = DMatrix::zeros(2 * m, columns);
    rhs.view_mut((0, 0), (m, columns)).copy_from(source);
    let solution = system
        .lu()
        .solve(&rhs)
        .ok_or("the boundary system is singular")?;
    let grow = solution.rows(0, m); // ũ₀⁺
    let fall = solution.rows(m, m); // u₀⁻
    Ok(InsideRadiance {
        up_at_top: vp * &decay * grow + vm * fall,
        down_at_bottom: vm * grow + vp * &decay * fall,
    })
}
