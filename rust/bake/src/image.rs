//! Plain float images handed in by callers (a lightmap to use as the
//! irradiance, a base colour map, an environment) and read by UV.

use glam::Vec2;

/// A linear RGB image, rows top to bottom as files store them: row 0 is
/// v = 1 in sssbake's v-up convention.
#[derive(Clone, Debug, PartialEq)]
pub struct Image {
    /// Columns.
    pub width: usize,
    /// Rows.
    pub height: usize,
    /// Row-major texels.
    pub texels: Vec<[f32; 3]>,
}

impl Image {
    /// Checks the size; non-finite and negative texels become zero.
    pub fn new(width: usize, height: usize, texels: Vec<[f32; 3]>) -> Result<Self, crate::Error> {
        if width == 0 || height == 0 || texels.len() != width * height {
            return Err(crate::Error::input(format!(
                "an image of {width}×{height} needs {} texels, has {}",
                width * height,
                texels.len()
            )));
        }
        let texels = texels
            .into_iter()
            .map(|c| c.map(|v| if v.is_finite() { v.max(0.0) } else { 0.0 }))
            .collect();
        Ok(Image {
            width,
            height,
            texels,
        })
    }

    /// Bilinear lookup at `uv` (v up), repeating outside [0, 1]² as glTF's
    /// default sampler does.
    pub fn sample(&self, uv: Vec2) -> [f32; 3] {
        let x = uv.x.rem_euclid(1.0) * self.width as f32 - 0.5;
        let y = (1.0 - uv.y).rem_euclid(1.0) * self.height as f32 - 0.5;
        let (x0, y0) = (x.floor(), y.floor());
        let (fx, fy) = (x - x0, y - y0);
        let wrap = |v: f32, n: usize| (v as i64).rem_euclid(n as i64) as usize;
        let at = |dx: f32, dy: f32| {
            self.texels[wrap(y0 + dy, self.height) * self.width + wrap(x0 + dx, self.width)]
        };
        let (a, b, c, d) = (at(0.0, 0.0), at(1.0, 0.0), at(0.0, 1.0), at(1.0, 1.0));
        [0, 1, 2].map(|k| {
            (a[k] * (1.0 - fx) + b[k] * fx) * (1.0 - fy) + (c[k] * (1.0 - fx) + d[k] * fx) * fy
        })
    }
}
