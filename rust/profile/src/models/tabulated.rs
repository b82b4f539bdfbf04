//! A profile known by samples on an increasing radius grid.

use crate::profile::Profile;
use crate::{Rgb, rgb_map};
use std::f64::consts::PI;

/// R(r) and T(r) sampled per channel on increasing radii, interpolated
/// linearly in ln r, with exact totals supplied by the model that made it.
#[derive(Clone, Debug)]
pub struct Tabulated {
    model: &'static str,
    radii: Vec<f64>,
    reflectance: Vec<Rgb>,
    transmittance: Vec<Rgb>,
    enclosed: Vec<Rgb>,
    total_reflectance: Rgb,
    total_transmittance: Rgb,
}

impl Tabulated {
    /// A table from radii (mm, increasing, positive), R and T samples
    /// (1/mm²), and the exact totals. Below the first radius R is taken as
    /// flat; beyond the last it is zero.
    pub fn new(
        model: &'static str,
        radii: Vec<f64>,
        reflectance: Vec<Rgb>,
        transmittance: Vec<Rgb>,
        total_reflectance: Rgb,
        total_transmittance: Rgb,
    ) -> Self {
        let enclosed = cumulative(&radii, &reflectance);
        Self {
            model,
            radii,
            reflectance,
            transmittance,
            enclosed,
            total_reflectance,
            total_transmittance,
        }
    }

    /// The sample radii, mm.
    pub fn radii(&self) -> &[f64] {
        &self.radii
    }

    fn interpolate(&self, values: &[Rgb], r: f64) -> Rgb {
        let n = self.radii.len();
        if n == 0 || r.is_nan() || r > self.radii[n - 1] {
            return [0.0; 3];
        }
        if r <= self.radii[0] {
            return values[0];
        }
        let i = self.radii.partition_point(|&x| x <= r).clamp(1, n - 1);
        let (r0, r1) = (self.radii[i - 1], self.radii[i]);
        let t = (r / r0).ln() / (r1 / r0).ln();
        rgb_map(|c| values[i - 1][c] + t * (values[i][c] - values[i - 1][c]))
    }
}

/// ∫_0^{r_i} 2πs f(s) ds at every sample, trapezoidal in ln s, with the
/// disk inside the first radius taken at the first value.
fn cumulative(radii: &[f64], values: &[Rgb]) -> Vec<Rgb> {
    let mut out = Vec::with_capacity(radii.len());
    let Some(&first) = radii.first() else {
        return out;
    };
    let mut acc = rgb_map(|c| PI * first * first * values[0][c]);
    out.push(acc);
    for i in 1..radii.len() {
        let h = (radii[i] / radii[i - 1]).ln();
        for (c, a) in acc.iter_mut().enumerate() {
            let f0 = 2.0 * PI * radii[i - 1] * radii[i - 1] * values[i - 1][c];
            let f1 = 2.0 * PI * radii[i] * radii[i] * values[i][c];
            *a += 0.5 * h * (f0 + f1);
        }
        out.push(acc);
    }
    out
}

impl Profile for Tabulated {
    fn model(&self) -> &'static str {
        self.model
    }

    fn reflectance(&self, r: f64) -> Rgb {
        self.interpolate(&self.reflectance, r)
    }

    fn transmittance(&self, r: f64) -> Rgb {
        self.interpolate(&self.transmittance, r)
    }

    fn total_reflectance(&self) -> Rgb {
        self.total_reflectance
    }

    fn total_transmittance(&self) -> Rgb {
        self.total_transmittance
    }

    fn enclosed_reflectance(&self, r: f64) -> Rgb {
        let n = self.radii.len();
        if n == 0 {
            return [0.0; 3];
        }
        if r >= self.radii[n - 1] {
            return self.enclosed[n - 1];
        }
        if r <= self.radii[0] {
            return rgb_map(|c| PI * r * r * self.reflectance[0][c]);
        }
        let i = self.radii.partition_point(|&x| x <= r).clamp(1, n - 1);
        let (r0, f0) = (self.radii[i - 1], self.reflectance[i - 1]);
        let f = self.reflectance(r);
        let h = (r / r0).ln();
        rgb_map(|c| self.enclosed[i - 1][c] + 0.5 * h * 2.0 * PI * (r0 * r0 * f0[c] + r * r * f[c]))
    }

    fn length_scale(&self) -> Rgb {
        // The radius where r²R(r), the reflectance per unit ln r, peaks.
        rgb_map(|c| {
            let mut best = (0.0, self.radii.first().copied().unwrap_or(1.0));
            for (r, v) in self.radii.iter().zip(&self.reflectance) {
                let w = r * r * v[c];
                if w > best.0 {
                    best = (w, *r);
                }
            }
            best.1
        })
    }
}
