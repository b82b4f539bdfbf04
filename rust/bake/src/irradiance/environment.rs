//! An equirectangular (latitude–longitude) environment with importance
//! sampling by luminance × sin θ.
//!
//! Row 0 is the zenith (+Y) and the last row the nadir; column x covers
//! φ ∈ [2πx/W, 2π(x+1)/W), with direction (sin θ cos φ, cos θ, −sin θ sin φ),
//! so the image centre is the horizon towards −X: Y up, as glTF scenes are.

use glam::{Vec2, Vec3};
use std::f32::consts::{PI, TAU};

/// Radiance from every direction, W/(m²·sr) per unit of the light's
/// intensity.
#[derive(Clone, Debug)]
pub struct EnvironmentMap {
    width: usize,
    height: usize,
    radiance: Vec<[f32; 3]>,
    /// Cumulative distribution over rows (height + 1 entries).
    rows: Vec<f32>,
    /// Cumulative distribution within each row ((width + 1) per row).
    columns: Vec<f32>,
}

impl EnvironmentMap {
    /// A map from `width` × `height` linear RGB texels, rows top to bottom.
    /// Negative and non-finite texels count as black.
    pub fn new(width: usize, height: usize, radiance: Vec<[f32; 3]>) -> Result<Self, crate::Error> {
        if width == 0 || height == 0 || radiance.len() != width * height {
            return Err(crate::Error::input(format!(
                "an environment image of {width}×{height} needs {} texels, has {}",
                width * height,
                radiance.len()
            )));
        }
        let radiance: Vec<[f32; 3]> = radiance
            .into_iter()
            .map(|c| c.map(|v| if v.is_finite() { v.max(0.0) } else { 0.0 }))
            .collect();
        let mut rows = vec![0.0f32; height + 1];
        let mut columns = vec![0.0f32; (width + 1) * height];
        for y in 0..height {
            let sin_theta = (PI * (y as f32 + 0.5) / height as f32).sin();
            let row = &mut columns[y * (width + 1)..(y + 1) * (width + 1)];
            for x in 0..width {
                let c = radiance[y * width + x];
                let weight = (0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2]) * sin_theta;
                row[x + 1] = row[x] + weight;
            }
            rows[y + 1] = rows[y] + row[width];
        }
        Ok(EnvironmentMap {
            width,
            height,
            radiance,
            rows,
            columns,
        })
    }

    /// A constant environment (one texel).
    pub fn constant() -> Self {
        EnvironmentMap::new(1, 1, vec![[1.0; 3]]).expect("one texel")
    }

    /// True when every direction has the same radiance.
    pub fn is_constant(&self) -> bool {
        self.radiance.iter().all(|c| *c == self.radiance[0])
    }

    /// Radiance arriving from unit direction `w` (nearest texel).
    pub fn radiance(&self, w: Vec3) -> [f32; 3] {
        let (x, y) = self.texel_of(w);
        self.radiance[y * self.width + x]
    }

    fn texel_of(&self, w: Vec3) -> (usize, usize) {
        let theta = w.y.clamp(-1.0, 1.0).acos();
        let phi = (-w.z).atan2(w.x).rem_euclid(TAU);
        let x = ((phi / TAU) * self.width as f32) as usize;
        let y = ((theta / PI) * self.height as f32) as usize;
        (x.min(self.width - 1), y.min(self.height - 1))
    }

    /// Draws a direction with density ∝ luminance × sin θ from `u` ∈ [0,1)²;
    /// `None` for a black map.
    pub fn sample(&self, u: Vec2) -> Option<Vec3> {
        let total = *self.rows.last()?;
        if total <= 0.0 {
            return None;
        }
        let y = search(&self.rows, u.y * total).min(self.height - 1);
        let row = &self.columns[y * (self.width + 1)..(y + 1) * (self.width + 1)];
        let x = search(row, u.x * row[self.width]).min(self.width - 1);
        // Uniform in (φ, θ) within the texel; `pdf` divides by the sin θ of
        // the exact direction, so the two agree everywhere.
        let fx = (u.x * row[self.width] - row[x]) / (row[x + 1] - row[x]).max(f32::MIN_POSITIVE);
        let fy =
            (u.y * total - self.rows[y]) / (self.rows[y + 1] - self.rows[y]).max(f32::MIN_POSITIVE);
        let phi = TAU * (x as f32 + fx.clamp(0.0, 1.0)) / self.width as f32;
        let theta = PI * (y as f32 + fy.clamp(0.0, 1.0)) / self.height as f32;
        Some(Vec3::new(
            theta.sin() * phi.cos(),
            theta.cos(),
            -theta.sin() * phi.sin(),
        ))
    }

    /// The density per steradian with which [`EnvironmentMap::sample`]
    /// draws `w`.
    pub fn pdf(&self, w: Vec3) -> f32 {
        let total = match self.rows.last() {
            Some(&t) if t > 0.0 => t,
            _ => return 0.0,
        };
        let (x, y) = self.texel_of(w);
        let row = &self.columns[y * (self.width + 1)..(y + 1) * (self.width + 1)];
        let p_texel = (row[x + 1] - row[x]) / total;
        let sin_theta = (1.0 - w.y * w.y).max(0.0).sqrt().max(1e-6);
        // A texel spans (2π/W)(π/H) in (φ, θ), i.e. that × sin θ steradians.
        p_texel * (self.width * self.height) as f32 / (2.0 * PI * PI * sin_theta)
    }
}

/// The index i with cdf[i] ≤ value < cdf[i + 1].
fn search(cdf: &[f32], value: f32) -> usize {
    cdf.partition_point(|&c| c <= value).saturating_sub(1)
}
