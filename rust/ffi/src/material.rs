//! Materials as a host gives them: a preset, a material file's text, or
//! Blender's Principled BSDF subsurface inputs.

use crate::errors::{Failure, text};
use sssbake_profile::presets;
use sssbake_profile::{Appearance, Material};
use std::ffi::c_char;

/// A preset by `name` (skin1, marble, skin3layer, …).
pub const SSSBAKE_MATERIAL_PRESET: u32 = 0;
/// Principled BSDF inputs: base colour, subsurface weight, radius, scale,
/// IOR and anisotropy.
pub const SSSBAKE_MATERIAL_PRINCIPLED: u32 = 1;
/// A material file's TOML text in `toml` (README, "Materials").
pub const SSSBAKE_MATERIAL_TOML: u32 = 2;

/// A material. Fields a kind does not use are ignored.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct SssbakeMaterial {
    /// One of the `SSSBAKE_MATERIAL_*` kinds.
    pub kind: u32,
    /// The preset's name, or the material's name for reports.
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
    /// Subsurface IOR.
    pub ior: f32,
    /// Subsurface Anisotropy (Henyey–Greenstein g).
    pub anisotropy: f32,
}

/// The library's material for a host material in a scene of `mm_per_unit`.
/// Principled inputs become a colour and a mean free path Radius × Scale
/// (README, "Materials from the asset").
///
/// # Safety
/// The strings are null or NUL-terminated.
pub(crate) unsafe fn material_from_host(
    material: &SssbakeMaterial,
    mm_per_unit: f64,
) -> Result<Material, Failure> {
    match material.kind {
        SSSBAKE_MATERIAL_PRESET => {
            // SAFETY: forwarded from the caller.
            let name = unsafe { text(material.name, "preset name") }?;
            presets::named(name).map_err(Failure::input)
        }
        SSSBAKE_MATERIAL_TOML => {
            // SAFETY: forwarded from the caller.
            let toml = unsafe { text(material.toml, "material TOML") }?;
            let name = if material.name.is_null() {
                "material"
            } else {
                // SAFETY: forwarded from the caller.
                unsafe { text(material.name, "material name") }?
            };
            Material::from_toml(toml, name, name).map_err(|e| Failure::input(e.to_string()))
        }
        SSSBAKE_MATERIAL_PRINCIPLED => {
            let name = if material.name.is_null() {
                "Principled BSDF".to_string()
            } else {
                // SAFETY: forwarded from the caller.
                unsafe { text(material.name, "material name") }?.to_string()
            };
            if material.subsurface_weight.is_nan() || material.subsurface_weight <= 0.0 {
                return Err(Failure::input(format!(
                    "material `{name}`: Subsurface Weight is {}; there is no subsurface scattering to bake",
                    material.subsurface_weight
                )));
            }
            let scale_mm = f64::from(material.scale) * mm_per_unit;
            let appearance = Appearance {
                name: name.clone(),
                colour: material.base_colour.map(f64::from),
                mean_free_path_mm: material.radius.map(|r| f64::from(r) * scale_mm),
                ior: f64::from(material.ior),
                anisotropy: f64::from(material.anisotropy),
            };
            appearance
                .to_material()
                .map_err(|e| Failure::input(format!("material `{name}`: {e}")))
        }
        other => Err(Failure::argument(format!(
            "material kind {other} is not one of SSSBAKE_MATERIAL_*"
        ))),
    }
}
