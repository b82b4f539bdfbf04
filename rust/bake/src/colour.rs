//! Colour maps: an object's base colour per texel, from the texture its
//! material names (sampled through the texture's own UV set, transform and
//! wrap) or from a caller's image in the bake's layout, and the nominal
//! colour the profile is built for.
//!
//! The colour counts once (Mikkelsen 2009 §3.5, with the profile built for
//! the nominal colour m rather than for white): the exitance at x_o is
//! (C(x_o)/m)^(1−α) Σ R_m(r) (C(x_i)/m)^α E(x_i), where R_m is the profile
//! of a material of colour m and C the colour map. m is the mean of C over
//! the object's covered texels weighted by their surface area, so a
//! constant texture c bakes exactly what a colour factor c bakes.

use crate::image::Image;
use crate::layout::Layout;
use crate::scene::SceneObject;
use glam::Vec2;
use serde::Serialize;
use std::sync::Arc;

/// What a texture does outside [0, 1] along one axis.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Wrap {
    /// Tiles (glTF REPEAT, USD `repeat`; both formats' default).
    #[default]
    Repeat,
    /// Tiles mirrored every other time (glTF MIRRORED_REPEAT, USD `mirror`).
    Mirror,
    /// Repeats the edge texel (glTF CLAMP_TO_EDGE, USD `clamp`).
    Clamp,
    /// Black outside (USD `black`).
    Black,
}

/// A texture-coordinate transform, in the convention of the format that
/// states it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum UvTransform {
    /// glTF `KHR_texture_transform`, in glTF's UV space (v down):
    /// uv' = offset + R(rotation) · (scale ⊙ uv) with R = [[cos, sin], [−sin, cos]].
    Gltf {
        /// `offset`.
        offset: Vec2,
        /// `rotation`, radians.
        rotation: f32,
        /// `scale`.
        scale: Vec2,
    },
    /// `UsdTransform2d`, in USD's st space (t up): st' = translation +
    /// R(rotation) · (scale ⊙ st), R counter-clockwise.
    Usd {
        /// `inputs:translation`.
        translation: Vec2,
        /// `inputs:rotation`, degrees.
        rotation_degrees: f32,
        /// `inputs:scale`.
        scale: Vec2,
    },
}

impl UvTransform {
    /// The transformed coordinate of `uv` (v up, sssbake's convention),
    /// returned v up.
    pub fn apply(&self, uv: Vec2) -> Vec2 {
        match *self {
            UvTransform::Gltf {
                offset,
                rotation,
                scale,
            } => {
                let p = Vec2::new(uv.x, 1.0 - uv.y) * scale;
                let (s, c) = rotation.sin_cos();
                let q = Vec2::new(c * p.x + s * p.y, -s * p.x + c * p.y) + offset;
                Vec2::new(q.x, 1.0 - q.y)
            }
            UvTransform::Usd {
                translation,
                rotation_degrees,
                scale,
            } => {
                let p = uv * scale;
                let (s, c) = rotation_degrees.to_radians().sin_cos();
                Vec2::new(c * p.x - s * p.y, s * p.x + c * p.y) + translation
            }
        }
    }
}

/// A base-colour texture as a material names it, read and decoded.
#[derive(Clone, Debug, PartialEq)]
pub struct ColourTexture {
    /// The material's name, for messages.
    pub material: String,
    /// The material input or texture slot it drives (`baseColorTexture`,
    /// `diffuseColor`, `subsurface_color`, `Base Color`).
    pub input: String,
    /// The image file (or the name of an embedded image), for reports.
    pub file: String,
    /// The decoded image, linear RGB (its colour space already decoded),
    /// or why it could not be read. Readers keep the error here so that it
    /// stops only a bake that uses the texture.
    pub image: Result<Arc<Image>, String>,
    /// The colour space the texels were decoded from (`sRGB`, `raw`, …).
    pub colour_space: String,
    /// Index into the object's `uv_sets` of the coordinates the texture
    /// reads.
    pub uv_set: usize,
    /// Those coordinates' name in the file (`TEXCOORD_1`, `st`, `UVMap`).
    pub uv_set_name: String,
    /// The coordinate transform, if the material states one.
    pub transform: Option<UvTransform>,
    /// Wrap along u and along v.
    pub wrap: [Wrap; 2],
    /// Nearest-texel lookup instead of bilinear.
    pub nearest: bool,
    /// The colour is texel × scale + bias (glTF: the base colour factor and
    /// 0; USD: UsdUVTexture's `scale` and `bias`).
    pub scale: [f32; 3],
    /// See `scale`.
    pub bias: [f32; 3],
}

impl ColourTexture {
    /// The colour at texture coordinate `uv` (v up, before the transform).
    pub fn colour_at(&self, image: &Image, uv: Vec2) -> [f32; 3] {
        let uv = self.transform.map_or(uv, |t| t.apply(uv));
        let texel = sample(image, uv, self.wrap, self.nearest);
        [0, 1, 2].map(|k| (texel[k] * self.scale[k] + self.bias[k]).max(0.0))
    }
}

/// The texel of `image` at `uv` (v up; row 0 of the image is v = 1),
/// bilinear or nearest, with `wrap` along u and v.
pub fn sample(image: &Image, uv: Vec2, wrap: [Wrap; 2], nearest: bool) -> [f32; 3] {
    let (w, h) = (image.width as i64, image.height as i64);
    let x = uv.x * w as f32 - 0.5;
    let y = (1.0 - uv.y) * h as f32 - 0.5;
    let index = |i: i64, n: i64, wrap: Wrap| -> Option<usize> {
        let i = match wrap {
            Wrap::Repeat => i.rem_euclid(n),
            Wrap::Clamp => i.clamp(0, n - 1),
            Wrap::Mirror => {
                let j = i.rem_euclid(2 * n);
                if j >= n { 2 * n - 1 - j } else { j }
            }
            Wrap::Black if (0..n).contains(&i) => i,
            Wrap::Black => return None,
        };
        Some(i as usize)
    };
    let at = |i: i64, j: i64| match (index(i, w, wrap[0]), index(j, h, wrap[1])) {
        (Some(i), Some(j)) => image.texels[j * image.width + i],
        _ => [0.0; 3],
    };
    if nearest {
        return at(x.round() as i64, y.round() as i64);
    }
    let (x0, y0) = (x.floor(), y.floor());
    let (fx, fy) = (x - x0, y - y0);
    let (i, j) = (x0 as i64, y0 as i64);
    let (a, b, c, d) = (at(i, j), at(i + 1, j), at(i, j + 1), at(i + 1, j + 1));
    [0, 1, 2].map(|k| {
        (a[k] * (1.0 - fx) + b[k] * fx) * (1.0 - fy) + (c[k] * (1.0 - fx) + d[k] * fx) * fy
    })
}

/// Where an object's colour came from and what it is, as the plan and the
/// summary report it.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ColourPlan {
    /// `material` (the colour the material states, one value), `texture`
    /// (the material's base-colour texture), `image` (a caller's image in
    /// the bake's layout: `--base-color`), or `none` (a material given by
    /// coefficients, with no image).
    pub source: String,
    /// The texture's or image's file, when there is one.
    pub file: Option<String>,
    /// The material input the texture drives.
    pub input: Option<String>,
    /// The texture coordinates it reads (`TEXCOORD_1`, `st`, …).
    pub uv_set: Option<String>,
    /// The colour space its texels were decoded from.
    pub colour_space: Option<String>,
    /// The nominal colour m the profile is built for, linear RGB: the
    /// texel-area-weighted mean of the map, or the material's colour; null
    /// for a material given by coefficients (a map then multiplies as it
    /// is).
    pub nominal: Option<[f64; 3]>,
    /// α: the share of the colour applied before scattering.
    pub split: f32,
    /// What else to know (a texture not used, and why).
    pub note: Option<String>,
}

/// An object's colour map in its bake layout.
#[derive(Clone, Debug)]
pub struct ColourMap {
    /// The colour per surfel relative to the nominal colour, C/m (0 where
    /// m is 0); empty when the colour is the same everywhere.
    pub relative: Vec<[f32; 3]>,
    /// The nominal colour, when the material states one or a map gives it.
    pub nominal: Option<[f64; 3]>,
}

/// Samples `texture` at every texel of `layout` of `object`: each texel's
/// point on its triangle, found by the barycentric coordinates of the
/// texel's centre in the layout's UVs, reads the texture's own UV set at
/// the same barycentric coordinates.
pub fn texture_per_texel(
    layout: &Layout,
    object: &SceneObject,
    texture: &ColourTexture,
) -> Result<Vec<[f32; 3]>, String> {
    let image = texture.image.as_ref().map_err(Clone::clone)?;
    let coordinates = object.uv_sets.get(texture.uv_set).ok_or_else(|| {
        format!(
            "the texture reads texture coordinates {} but the object has no such set",
            texture.uv_set_name
        )
    })?;
    let source_vertex = |v: u32| -> usize {
        if layout.unwrapped {
            layout.source_vertex[v as usize] as usize
        } else {
            v as usize
        }
    };
    if let Some(v) = (0..layout.mesh.positions.len() as u32)
        .map(source_vertex)
        .find(|&v| v >= coordinates.len())
    {
        return Err(format!(
            "texture coordinates {} have {} values but the mesh uses vertex {v}",
            texture.uv_set_name,
            coordinates.len()
        ));
    }
    let surfels = &layout.surfels;
    Ok((0..surfels.len())
        .map(|s| {
            let t = layout.mesh.triangles[surfels.triangle[s] as usize];
            let b = barycentric_clamped(layout.texel_uv(s), t.map(|v| layout.uvs[v as usize]));
            let uv = (0..3)
                .map(|k| coordinates[source_vertex(t[k])] * b[k])
                .sum::<Vec2>();
            texture.colour_at(image, uv)
        })
        .collect())
}

/// The barycentric coordinates of `p` in triangle `t`, clamped to the
/// triangle (a texel centre just outside its triangle reads the edge).
fn barycentric_clamped(p: Vec2, t: [Vec2; 3]) -> [f32; 3] {
    let (e1, e2, d) = (t[1] - t[0], t[2] - t[0], p - t[0]);
    let det = e1.perp_dot(e2);
    if det.abs() < f32::MIN_POSITIVE {
        return [1.0 / 3.0; 3];
    }
    let b1 = d.perp_dot(e2) / det;
    let b2 = e1.perp_dot(d) / det;
    let b = [1.0 - b1 - b2, b1, b2].map(|x| x.max(0.0));
    let sum: f32 = b.iter().sum();
    if sum > 0.0 {
        b.map(|x| x / sum)
    } else {
        [1.0 / 3.0; 3]
    }
}

/// The texel-area-weighted mean of `colour` over `layout`'s surfels.
pub fn area_mean(layout: &Layout, colour: &[[f32; 3]]) -> [f64; 3] {
    let mut sum = [0.0f64; 3];
    let mut area = 0.0f64;
    for (c, &a) in colour.iter().zip(&layout.surfels.area) {
        for k in 0..3 {
            sum[k] += f64::from(a) * f64::from(c[k]);
        }
        area += f64::from(a);
    }
    if area > 0.0 {
        sum.map(|s| s / area)
    } else {
        [0.0; 3]
    }
}

/// `colour` relative to `nominal`: C/m per channel, 0 where m is 0 (a
/// channel black everywhere bakes black, whatever the black profile's
/// inversion leaves).
pub fn relative_to(colour: &[[f32; 3]], nominal: [f64; 3]) -> Vec<[f32; 3]> {
    colour
        .iter()
        .map(|c| {
            [0, 1, 2].map(|k| {
                if nominal[k] > 0.0 {
                    (f64::from(c[k]) / nominal[k]) as f32
                } else {
                    0.0
                }
            })
        })
        .collect()
}
