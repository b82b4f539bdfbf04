//! Scalar optical coefficients of one homogeneous medium in one channel, and
//! the diffusion quantities derived from them.

/// Absorption and reduced scattering of a medium, both in 1/mm.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Medium {
    /// Absorption coefficient σa, 1/mm.
    pub sigma_a: f64,
    /// Reduced scattering coefficient σs' = σs(1 − g), 1/mm.
    pub sigma_s_reduced: f64,
}

impl Medium {
    /// Reduced extinction σt' = σa + σs', 1/mm.
    pub fn sigma_t_reduced(&self) -> f64 {
        self.sigma_a + self.sigma_s_reduced
    }

    /// Reduced albedo α' = σs'/σt' (0 for a medium that does not interact).
    pub fn albedo_reduced(&self) -> f64 {
        let t = self.sigma_t_reduced();
        if t > 0.0 {
            (self.sigma_s_reduced / t).clamp(0.0, 1.0)
        } else {
            0.0
        }
    }

    /// Effective transport coefficient σtr = √(3 σa σt'), 1/mm.
    pub fn sigma_tr(&self) -> f64 {
        (3.0 * self.sigma_a * self.sigma_t_reduced()).sqrt()
    }

    /// Diffusion coefficient D = 1/(3σt'), mm.
    pub fn diffusion(&self) -> f64 {
        1.0 / (3.0 * self.sigma_t_reduced())
    }

    /// Transport mean free path ℓ = 1/σt', mm: the depth of the dipole's real source.
    pub fn mean_free_path(&self) -> f64 {
        1.0 / self.sigma_t_reduced()
    }
}
