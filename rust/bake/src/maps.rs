//! The baked maps: per-texel values turned into images in the layout,
//! dilated across the charts' margins.
//!
//! | output | value per texel |
//! |---|---|
//! | `subsurface` | M, the radiant exitance (W/m²) after the colour split |
//! | `irradiance` | E_t, the irradiance transmitted through the surface (W/m²) |
//! | `diffuse` | M·ρt(0)/π: the diffuse radiance leaving towards the normal through the exit Fresnel, or a rough surface's ρdt(0) (W/(m²·sr)) |
//! | `thickness` | distance through the object along the inward normal (mm; 0 where a ray leaves it) |
//! | `stretch` | surface length of one texel along u (red) and v (green), mm |
//! | `area` | surface area the texel stands for, mm² |

use crate::image::Image;
use crate::prepared::Prepared;
use crate::rays::RayScene;
use crate::surface::dilation::seam_aware_offsets;
use crate::surface::texels::TexelSurfels;
use crate::transport::thin::inward_thickness;
use serde::{Deserialize, Serialize};
use sssbake_profile::boundary::surface::Surface;

/// A map sssbake can write.
#[derive(
    Clone,
    Copy,
    Debug,
    PartialEq,
    Eq,
    Hash,
    PartialOrd,
    Ord,
    Serialize,
    Deserialize,
    strum::Display,
    strum::EnumString,
    strum::IntoStaticStr,
    strum::VariantArray,
    strum::VariantNames,
    strum::EnumMessage,
)]
#[serde(rename_all = "lowercase")]
#[strum(serialize_all = "lowercase")]
pub enum Output {
    /// Radiant exitance.
    Subsurface,
    /// Transmitted irradiance.
    Irradiance,
    /// Diffuse radiance through the exit Fresnel.
    Diffuse,
    /// Thickness along the inward normal.
    Thickness,
    /// Texel size on the surface along u and v.
    Stretch,
    /// Texel area.
    Area,
}

impl Output {
    /// Every output, in the order of the C ABI's numbers.
    pub const ALL: [Output; 6] = [
        Output::Subsurface,
        Output::Irradiance,
        Output::Diffuse,
        Output::Thickness,
        Output::Stretch,
        Output::Area,
    ];

    /// The outputs a bake writes when none are named.
    pub const DEFAULT: [Output; 3] = [Output::Subsurface, Output::Irradiance, Output::Diffuse];

    /// The name in file names and on the command line.
    pub fn name(self) -> &'static str {
        self.into()
    }

    /// True for maps that are colours (also written as sRGB PNG).
    pub fn is_colour(self) -> bool {
        matches!(
            self,
            Output::Subsurface | Output::Irradiance | Output::Diffuse
        )
    }

    /// True for maps that need the light scattered under the surface.
    pub fn needs_scattering(self) -> bool {
        matches!(self, Output::Subsurface | Output::Diffuse)
    }

    /// True for maps that need the light entering the surface.
    pub fn needs_light(self) -> bool {
        self.needs_scattering() || self == Output::Irradiance
    }
}

/// Empty texels within `margin` texels of a chart and the covered texels
/// they copy: across the seam where the chart edge is one, else the
/// nearest (so filtering and mip-mapping never read black).
pub fn margin_fill(prepared: &Prepared, margin: u32) -> Vec<(u32, u32)> {
    seam_aware_offsets(&prepared.mesh, &prepared.uvs, &prepared.surfels, margin)
}

/// The map `output` of `prepared` as an image, rows top to bottom, with
/// the empty texels of `fill` (from [`margin_fill`]) filled. `exitance` is
/// the integration's result (zero where there is none); `surface` the
/// material's, whose π L(0)/M ([`Surface::exit_at_normal`]: the radiance
/// leaving along the normal per unit of the exitance that left, ρdt(0)/ρ̄dt
/// under a boundary) turns the exitance into the `diffuse` map.
pub fn render(
    prepared: &Prepared,
    exitance: &[[f32; 3]],
    surface: &Surface,
    output: Output,
    fill: &[(u32, u32)],
) -> Image {
    let surfels = &prepared.surfels;
    let values: Vec<[f32; 3]> = match output {
        Output::Subsurface => exitance.to_vec(),
        Output::Irradiance => prepared.irradiance.clone(),
        Output::Diffuse => {
            let exit = surface
                .exit_at_normal()
                .map(|t| t as f32 * std::f32::consts::FRAC_1_PI);
            exitance
                .iter()
                .map(|m| std::array::from_fn(|c| m[c] * exit[c]))
                .collect()
        }
        Output::Thickness => thickness(prepared),
        Output::Stretch => surfels.stretch.iter().map(|s| [s.x, s.y, 0.0]).collect(),
        Output::Area => surfels.area.iter().map(|&a| [a; 3]).collect(),
    };
    in_layout(surfels, &values, fill)
}

/// Per-surfel `values` as an image of the layout, rows top to bottom, with
/// the empty texels of `fill` filled and the rest black.
pub fn in_layout(surfels: &TexelSurfels, values: &[[f32; 3]], fill: &[(u32, u32)]) -> Image {
    let n = surfels.resolution as usize;
    let mut grid = vec![[0.0f32; 3]; n * n];
    for (&t, &value) in surfels.texel.iter().zip(values) {
        grid[t as usize] = value;
    }
    for &(to, from) in fill {
        grid[to as usize] = grid[from as usize];
    }
    // Texel row y runs up with v; image rows run down.
    let texels = (0..n)
        .rev()
        .flat_map(|y| grid[y * n..(y + 1) * n].iter().copied())
        .collect();
    Image {
        width: n,
        height: n,
        texels,
    }
}

/// Distance along the inward normal to where the object ends, mm.
fn thickness(prepared: &Prepared) -> Vec<[f32; 3]> {
    use rayon::prelude::*;
    let rays = RayScene::new(&[&prepared.mesh]);
    let surfels = &prepared.surfels;
    (0..surfels.len())
        .into_par_iter()
        .map(|s| [inward_thickness(&rays, surfels, s, f32::MAX).unwrap_or(0.0); 3])
        .collect()
}
