//! The interface every reflectance profile offers, whatever model made it.

use crate::Rgb;
use crate::numerics::roots::radius_where;

/// A radially symmetric diffusion profile per RGB channel.
///
/// `reflectance(r)` is the flux leaving the lit face per unit area at
/// distance `r` (mm) from where a unit flux entered, in 1/mm²; the total
/// ∫ 2πr R(r) dr is the diffuse reflectance. `transmittance` is the same
/// at the opposite face of a slab.
pub trait Profile: Send + Sync {
    /// The model's name as the command line spells it.
    fn model(&self) -> &'static str;

    /// R(r) in 1/mm² at radius `r_mm`.
    fn reflectance(&self, r_mm: f64) -> Rgb;

    /// T(r) in 1/mm² at radius `r_mm`; zero for semi-infinite media.
    fn transmittance(&self, _r_mm: f64) -> Rgb {
        [0.0; 3]
    }

    /// Total diffuse reflectance ∫ 2πr R(r) dr (dimensionless).
    fn total_reflectance(&self) -> Rgb;

    /// Total diffuse transmittance ∫ 2πr T(r) dr (dimensionless).
    fn total_transmittance(&self) -> Rgb {
        [0.0; 3]
    }

    /// Light thin layers return without scattering (bounced off their
    /// faces): a delta at r = 0, not part of R(r) nor of the total.
    fn ballistic_reflectance(&self) -> Rgb {
        [0.0; 3]
    }

    /// Light crossing thin layers without scattering: a delta at r = 0, not
    /// part of T(r) nor of the total transmittance.
    fn ballistic_transmittance(&self) -> Rgb {
        [0.0; 3]
    }

    /// Reflectance inside radius `r_mm`: ∫_0^r 2πs R(s) ds.
    fn enclosed_reflectance(&self, r_mm: f64) -> Rgb;

    /// A radius (mm) typical of the profile's spread, per channel; where
    /// searches start.
    fn length_scale(&self) -> Rgb;

    /// The 2-D Fourier transform R̂(k) = ∫ R(x) e^{−ik·x} d²x at angular
    /// frequency `k` (rad/mm), where the model knows it in closed form;
    /// R̂(0) is the total reflectance. Convolutions with the profile (blurs
    /// in texture space, layer combination) are products of it.
    fn reflectance_spectrum(&self, _k: f64) -> Option<Rgb> {
        None
    }

    /// Draws a radius (mm) in [0, `r_max`] from channel `channel`'s density
    /// ∝ 2πr R(r), from one uniform number `xi` and monotone in it piece
    /// by piece (so a stratified `xi` gives stratified radii), where the
    /// model can do so exactly; `None` sends callers to a tabulated inverse
    /// CDF.
    fn sample_radius(&self, _channel: usize, _xi: f64, _r_max: f64) -> Option<f64> {
        None
    }

    /// The radius d_max (mm) holding all but a fraction `epsilon` of the
    /// reflectance (Mikkelsen eq. 40 generalised), per channel.
    fn d_max(&self, epsilon: f64) -> Rgb {
        let scale = self.length_scale();
        let whole = self.enclosed_reflectance(f64::INFINITY);
        crate::rgb_map(|c| {
            if whole[c] <= 0.0 || !whole[c].is_finite() {
                return 0.0;
            }
            let target = (1.0 - epsilon.clamp(0.0, 1.0)) * whole[c];
            radius_where(|r| self.enclosed_reflectance(r)[c], target, scale[c])
        })
    }
}

/// Sixty radii (mm), evenly spaced in ln r, from a twentieth of the
/// profile's typical radius to its largest d_max keeping all but `epsilon`
/// of the reflectance: where a table or plot of the profile samples it.
pub fn default_radii(profile: &dyn Profile, epsilon: f64) -> Vec<f64> {
    let scale = profile
        .length_scale()
        .into_iter()
        .fold(f64::INFINITY, f64::min);
    let reach = profile.d_max(epsilon).into_iter().fold(0.0, f64::max);
    let lo = (scale / 20.0).max(1e-9);
    let hi = reach.max(lo * 10.0);
    let n = 60;
    (0..n)
        .map(|i| lo * (hi / lo).powf(i as f64 / (n - 1) as f64))
        .collect()
}
