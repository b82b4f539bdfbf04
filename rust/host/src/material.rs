//! Materials as a host gives them: a preset, a material file's text,
//! Blender's Principled BSDF subsurface inputs, or no subsurface; each with
//! an optional base-colour image.

use serde::Deserialize;
use sssbake::Error;
use sssbake::colour::{ColourTexture, Wrap};
use sssbake::image::Image;
use sssbake::materials::{
    AlbedoMapping, MaterialAssignment, Principled, Sidecar, SubsurfaceMethod, preset,
};
use sssbake_profile::Material;
use std::path::Path;
use std::sync::Arc;

/// What a host material is.
#[derive(Clone, Debug)]
pub enum HostMaterialKind {
    /// A preset by the material's `name` (skin1, marble, skin3layer, …).
    Preset,
    /// Principled BSDF inputs, read as Cycles reads them.
    Principled(HostPrincipled),
    /// A material file's TOML text (docs/materials.md, "Materials").
    Toml(String),
    /// Each object's own material in the scene (a scene read from a file),
    /// else the fallback preset.
    Scene,
    /// A sidecar's TOML text naming each object's preset or material file,
    /// relative to the folder the material's `name` gives (none: the
    /// working folder). Objects it does not name take their scene material.
    Sidecar(String),
    /// No subsurface (a Principled BSDF with Subsurface Weight 0, a slot
    /// without a material): its faces are left out of the bake, their
    /// texels empty, and the summary says so.
    NoSubsurface,
}

/// Blender's Principled BSDF subsurface inputs. Every field a host leaves
/// out (reading it from JSON) takes Blender's default.
#[derive(Clone, Copy, Debug, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct HostPrincipled {
    /// Base Color, linear RGB: the colour the surface shows.
    pub base_colour: [f32; 3],
    /// Subsurface Weight; must be positive.
    pub subsurface_weight: f32,
    /// Subsurface Radius per channel (multiplies `scale`).
    pub radius: [f32; 3],
    /// Subsurface Scale, scene units.
    pub scale: f32,
    /// IOR: the specular layer's index over the subsurface.
    pub ior: f32,
    /// Subsurface Anisotropy (Henyey–Greenstein g).
    pub anisotropy: f32,
    /// Subsurface Method.
    #[serde(with = "method_name")]
    pub method: SubsurfaceMethod,
    /// Subsurface IOR (Random Walk (Skin) only).
    pub subsurface_ior: f32,
    /// Specular IOR Level: 0.5 leaves the IOR as it is, 0 removes the
    /// specular layer.
    pub specular_ior_level: f32,
    /// From colour to albedo: Cycles' fit, or the dipole inverted.
    #[serde(with = "albedo_name")]
    pub albedo: AlbedoMapping,
    /// Roughness r in [0, 1] of a rough boundary over the subsurface
    /// (Beckmann RMS slope m = r²; docs/materials.md, "Materials"); 0 is smooth. A
    /// Principled BSDF's Roughness is Cycles' specular layer, not this.
    pub roughness: f32,
}

impl Default for HostPrincipled {
    /// Blender's Principled BSDF defaults, with Subsurface Weight 0.
    fn default() -> Self {
        HostPrincipled {
            base_colour: [0.8; 3],
            subsurface_weight: 0.0,
            radius: [1.0, 0.2, 0.1],
            scale: 0.05,
            ior: 1.5,
            anisotropy: 0.0,
            method: SubsurfaceMethod::RandomWalk,
            subsurface_ior: 1.4,
            specular_ior_level: 0.5,
            albedo: AlbedoMapping::Cycles,
            roughness: 0.0,
        }
    }
}

/// Blender's names of the subsurface methods (`BURLEY`, `RANDOM_WALK`,
/// `RANDOM_WALK_SKIN`).
mod method_name {
    use serde::{Deserialize, Deserializer, de::Error};
    use sssbake::materials::SubsurfaceMethod;

    /// The method of Blender's name.
    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<SubsurfaceMethod, D::Error> {
        let name = String::deserialize(d)?;
        super::subsurface_method(&name).ok_or_else(|| {
            D::Error::custom(format!(
                "subsurface method `{name}` is not BURLEY, RANDOM_WALK or RANDOM_WALK_SKIN"
            ))
        })
    }
}

/// The mappings from colour to albedo by name (`cycles`, `physical`).
mod albedo_name {
    use serde::{Deserialize, Deserializer, de::Error};
    use sssbake::materials::AlbedoMapping;

    /// The mapping of `name`.
    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<AlbedoMapping, D::Error> {
        match String::deserialize(d)?.as_str() {
            "cycles" => Ok(AlbedoMapping::Cycles),
            "physical" => Ok(AlbedoMapping::Physical),
            other => Err(D::Error::custom(format!(
                "albedo mapping `{other}` is not cycles or physical"
            ))),
        }
    }
}

/// The subsurface method of Blender's enum name, or `None`.
pub fn subsurface_method(name: &str) -> Option<SubsurfaceMethod> {
    match name {
        "BURLEY" => Some(SubsurfaceMethod::Burley),
        "RANDOM_WALK" => Some(SubsurfaceMethod::RandomWalk),
        "RANDOM_WALK_SKIN" => Some(SubsurfaceMethod::RandomWalkSkin),
        _ => None,
    }
}

/// A base-colour image: `width` × `height` texels of `channels` floats (3
/// RGB, or 4 RGBA whose alpha is ignored), linear (the host decodes its
/// colour space), rows from v = 0 up (Blender's order). It replaces the
/// base colour where it is sampled; the profile is built for its mean
/// (docs/materials.md, "Colour maps").
#[derive(Clone, Copy, Debug)]
pub struct HostImage<'a> {
    /// The texels.
    pub pixels: &'a [f32],
    /// Texels per row.
    pub width: usize,
    /// Rows.
    pub height: usize,
    /// 3 or 4.
    pub channels: usize,
    /// The UV set it reads: 0 the mesh's `uvs`, k ≥ 1 its texture UV set k.
    pub uv_set: usize,
    /// What it does outside [0, 1].
    pub wrap: Wrap,
    /// The nearest texel (Blender's Closest) rather than bilinear.
    pub nearest: bool,
    /// Its name for reports.
    pub name: Option<&'a str>,
}

/// A material as a host gives it.
#[derive(Clone, Debug)]
pub struct HostMaterial<'a> {
    /// What it is.
    pub kind: HostMaterialKind,
    /// The preset's name, the material's name for reports, or the
    /// sidecar's folder.
    pub name: Option<&'a str>,
    /// Its Base Color image, if any.
    pub image: Option<HostImage<'a>>,
}

impl HostMaterial<'_> {
    /// The library's material assignment for this material in a scene of
    /// `mm_per_unit`.
    pub fn assignment(&self, mm_per_unit: f64) -> Result<MaterialAssignment, Error> {
        let name_or = |default: &str| self.name.unwrap_or(default).to_string();
        let everywhere =
            |material: Material, source: &str| Ok(MaterialAssignment::everywhere(material, source));
        match &self.kind {
            HostMaterialKind::Preset => {
                let name = self
                    .name
                    .ok_or_else(|| Error::field("material", "preset name is null"))?;
                everywhere(preset(name)?, "preset")
            }
            HostMaterialKind::Toml(toml) => {
                let name = name_or("material");
                let parsed = Material::from_toml(toml, &name, &name)?;
                everywhere(parsed, "material TOML")
            }
            HostMaterialKind::Principled(inputs) => {
                let principled = Principled {
                    name: name_or("Principled BSDF"),
                    base_colour: inputs.base_colour,
                    subsurface_weight: inputs.subsurface_weight,
                    radius: inputs.radius,
                    scale_mm: f64::from(inputs.scale) * mm_per_unit,
                    method: inputs.method,
                    ior: inputs.ior,
                    specular_ior_level: inputs.specular_ior_level,
                    subsurface_ior: inputs.subsurface_ior,
                    anisotropy: inputs.anisotropy,
                    roughness: inputs.roughness,
                    albedo: inputs.albedo,
                };
                MaterialAssignment::principled(principled, "Principled BSDF")
            }
            HostMaterialKind::Scene => Ok(MaterialAssignment::default()),
            HostMaterialKind::NoSubsurface => Err(Error::input(format!(
                "material `{}` has no subsurface; there is nothing to bake with it",
                name_or("material")
            ))),
            HostMaterialKind::Sidecar(toml) => {
                let folder = name_or(".");
                let sidecar = Sidecar::parse(toml, Path::new("sidecar"), Path::new(&folder))?;
                Ok(MaterialAssignment {
                    sidecar: Some(sidecar),
                    ..MaterialAssignment::default()
                })
            }
        }
    }

    /// The base-colour texture this material gives, or `None`; `object` and
    /// its `uv_set_count` UV sets name and bound what it may read.
    pub fn texture(
        &self,
        object: &str,
        uv_set_count: usize,
    ) -> Result<Option<ColourTexture>, Error> {
        let Some(image) = &self.image else {
            return Ok(None);
        };
        let material_name = self.name.unwrap_or("material");
        let image_name = image.name.unwrap_or("Base Color image");
        let at = |what: String| {
            Error::field(
                "image",
                format!(
                    "object `{object}`, material `{material_name}`, image `{image_name}`: {what}"
                ),
            )
        };
        let (w, h, c) = (image.width, image.height, image.channels);
        if w == 0 || h == 0 {
            return Err(at(format!("its size is {w} × {h}; both must be positive")));
        }
        if c != 3 && c != 4 {
            return Err(at(format!(
                "{c} channels; it must have 3 (RGB) or 4 (RGBA)"
            )));
        }
        let len = w
            .checked_mul(h)
            .and_then(|n| n.checked_mul(c))
            .ok_or_else(|| at(format!("{w} × {h} × {c} floats is too many")))?;
        let pixels = image.pixels;
        if pixels.len() != len {
            return Err(at(format!(
                "it holds {} floats; {w} × {h} × {c} are {len}",
                pixels.len()
            )));
        }
        if let Some(bad) = pixels.iter().position(|v| !v.is_finite()) {
            let texel = bad / c;
            return Err(at(format!(
                "texel ({}, {}) from the bottom left is {}; colours must be finite",
                texel % w,
                texel / w,
                pixels[bad]
            )));
        }
        let uv_set = image.uv_set;
        if uv_set >= uv_set_count.max(1) {
            return Err(at(format!(
                "it reads UV set {uv_set} but the mesh has {uv_set_count} (0 is `uvs`, then `texture_uvs`)"
            )));
        }
        // The host's rows run up from v = 0; an Image's rows run down.
        let texels = (0..h)
            .rev()
            .flat_map(|y| (0..w).map(move |x| (y * w + x) * c))
            .map(|i| [pixels[i], pixels[i + 1], pixels[i + 2]])
            .collect();
        let built = Image::new(w, h, texels).map_err(|e| at(e.to_string()))?;
        Ok(Some(ColourTexture {
            material: material_name.to_string(),
            input: "Base Color".into(),
            file: image_name.to_string(),
            image: Ok(Arc::new(built)),
            colour_space: "linear (decoded by the host)".into(),
            uv_set,
            uv_set_name: format!("UV set {uv_set}"),
            transform: None,
            wrap: [image.wrap; 2],
            nearest: image.nearest,
            scale: [1.0; 3],
            bias: [0.0; 3],
        }))
    }
}
