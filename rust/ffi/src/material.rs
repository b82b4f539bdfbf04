//! Materials as a host gives them: a preset, a material file's text, or
//! Blender's Principled BSDF subsurface inputs.

use crate::errors::{Failure, text};
use sssbake::materials::{
    AlbedoMapping, MaterialAssignment, Principled, Sidecar, SubsurfaceMethod, preset,
};
use sssbake_profile::Material;
use std::ffi::c_char;
use std::path::Path;

/// A preset by `name` (skin1, marble, skin3layer, …).
pub const SSSBAKE_MATERIAL_PRESET: u32 = 0;
/// Principled BSDF inputs: base colour, subsurface weight, radius, scale,
/// method, IORs and anisotropy, read as Cycles reads them.
pub const SSSBAKE_MATERIAL_PRINCIPLED: u32 = 1;
/// A material file's TOML text in `toml` (README, "Materials").
pub const SSSBAKE_MATERIAL_TOML: u32 = 2;
/// Each object's own material in the scene (a scene read from a file),
/// else the fallback preset.
pub const SSSBAKE_MATERIAL_SCENE: u32 = 3;
/// A sidecar's TOML text in `toml` naming each object's preset or material
/// file; `name` is the folder those files are relative to (null: the
/// working folder). Objects it does not name take their scene material.
pub const SSSBAKE_MATERIAL_SIDECAR: u32 = 4;

/// A material. Fields a kind does not use are ignored.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct SssbakeMaterial {
    /// One of the `SSSBAKE_MATERIAL_*` kinds.
    pub kind: u32,
    /// The preset's name, the material's name for reports, or the
    /// sidecar's folder.
    pub name: *const c_char,
    /// TOML text, NUL-terminated.
    pub toml: *const c_char,
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
    /// One of the `SSSBAKE_SUBSURFACE_*` methods.
    pub subsurface_method: u32,
    /// Subsurface IOR (Random Walk (Skin) only).
    pub subsurface_ior: f32,
    /// Specular IOR Level: 0.5 leaves the IOR as it is, 0 removes the
    /// specular layer.
    pub specular_ior_level: f32,
    /// One of the `SSSBAKE_ALBEDO_*` mappings from colour to albedo.
    pub albedo_mapping: u32,
}

/// Christensen–Burley: mean free path Radius × Scale / 4π.
pub const SSSBAKE_SUBSURFACE_BURLEY: u32 = 0;
/// Random Walk: mean free path Radius × Scale / 4π, index-matched exit.
pub const SSSBAKE_SUBSURFACE_RANDOM_WALK: u32 = 1;
/// Random Walk (Skin): Radius × Scale is the diffusion length; light
/// enters through Subsurface IOR.
pub const SSSBAKE_SUBSURFACE_RANDOM_WALK_SKIN: u32 = 2;
/// Cycles' fit from colour to albedo: the bake looks like Cycles' render.
pub const SSSBAKE_ALBEDO_CYCLES: u32 = 0;
/// The dipole inverted: the uniform-light reflectance is the colour.
pub const SSSBAKE_ALBEDO_PHYSICAL: u32 = 1;

/// The library's material assignment for a host material in a scene of
/// `mm_per_unit`.
///
/// # Safety
/// The strings are null or NUL-terminated.
pub(crate) unsafe fn assignment_from_host(
    material: &SssbakeMaterial,
    mm_per_unit: f64,
) -> Result<MaterialAssignment, Failure> {
    let name_or = |default: &str| -> Result<String, Failure> {
        if material.name.is_null() {
            Ok(default.to_string())
        } else {
            // SAFETY: forwarded from the caller.
            Ok(unsafe { text(material.name, "material name") }?.to_string())
        }
    };
    let everywhere =
        |material: Material, source: &str| Ok(MaterialAssignment::everywhere(material, source));
    match material.kind {
        SSSBAKE_MATERIAL_PRESET => {
            // SAFETY: forwarded from the caller.
            let name = unsafe { text(material.name, "preset name") }?;
            everywhere(preset(name)?, "preset")
        }
        SSSBAKE_MATERIAL_TOML => {
            // SAFETY: forwarded from the caller.
            let toml = unsafe { text(material.toml, "material TOML") }?;
            let name = name_or("material")?;
            let parsed = Material::from_toml(toml, &name, &name).map_err(sssbake::Error::from)?;
            everywhere(parsed, "material TOML")
        }
        SSSBAKE_MATERIAL_PRINCIPLED => {
            let principled = Principled {
                name: name_or("Principled BSDF")?,
                base_colour: material.base_colour,
                subsurface_weight: material.subsurface_weight,
                radius: material.radius,
                scale_mm: f64::from(material.scale) * mm_per_unit,
                method: match material.subsurface_method {
                    SSSBAKE_SUBSURFACE_BURLEY => SubsurfaceMethod::Burley,
                    SSSBAKE_SUBSURFACE_RANDOM_WALK => SubsurfaceMethod::RandomWalk,
                    SSSBAKE_SUBSURFACE_RANDOM_WALK_SKIN => SubsurfaceMethod::RandomWalkSkin,
                    other => {
                        return Err(Failure::argument(format!(
                            "subsurface method {other} is not one of SSSBAKE_SUBSURFACE_*"
                        )));
                    }
                },
                ior: material.ior,
                specular_ior_level: material.specular_ior_level,
                subsurface_ior: material.subsurface_ior,
                anisotropy: material.anisotropy,
                albedo: match material.albedo_mapping {
                    SSSBAKE_ALBEDO_CYCLES => AlbedoMapping::Cycles,
                    SSSBAKE_ALBEDO_PHYSICAL => AlbedoMapping::Physical,
                    other => {
                        return Err(Failure::argument(format!(
                            "albedo mapping {other} is not one of SSSBAKE_ALBEDO_*"
                        )));
                    }
                },
            };
            Ok(MaterialAssignment::principled(
                principled,
                "Principled BSDF",
            )?)
        }
        SSSBAKE_MATERIAL_SCENE => Ok(MaterialAssignment::default()),
        SSSBAKE_MATERIAL_SIDECAR => {
            // SAFETY: forwarded from the caller.
            let toml = unsafe { text(material.toml, "sidecar TOML") }?;
            let folder = name_or(".")?;
            let sidecar = Sidecar::parse(toml, Path::new("sidecar"), Path::new(&folder))?;
            Ok(MaterialAssignment {
                sidecar: Some(sidecar),
                ..MaterialAssignment::default()
            })
        }
        other => Err(Failure::argument(format!(
            "material kind {other} is not one of SSSBAKE_MATERIAL_*"
        ))),
    }
}
