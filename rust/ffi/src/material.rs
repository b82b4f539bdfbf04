//! Materials as a host gives them: a preset, a material file's text, or
//! Blender's Principled BSDF subsurface inputs, with an optional
//! base-colour image.

use crate::errors::{Failure, slice, text};
use sssbake::colour::Wrap;
use sssbake::materials::{AlbedoMapping, SubsurfaceMethod};
use sssbake_host::{HostImage, HostMaterial, HostMaterialKind, HostPrincipled};
use std::ffi::c_char;

/// A preset by `name` (skin1, marble, skin3layer, …).
pub const SSSBAKE_MATERIAL_PRESET: u32 = 0;
/// Principled BSDF inputs: base colour, subsurface weight, radius, scale,
/// method, IORs and anisotropy, read as Cycles reads them.
pub const SSSBAKE_MATERIAL_PRINCIPLED: u32 = 1;
/// A material file's TOML text in `toml` (docs/materials.md, "Materials").
pub const SSSBAKE_MATERIAL_TOML: u32 = 2;
/// Each object's own material in the scene (a scene read from a file),
/// else the fallback preset.
pub const SSSBAKE_MATERIAL_SCENE: u32 = 3;
/// A sidecar's TOML text in `toml` naming each object's preset or material
/// file; `name` is the folder those files are relative to (null: the
/// working folder). Objects it does not name take their scene material.
pub const SSSBAKE_MATERIAL_SIDECAR: u32 = 4;
/// No subsurface (a Principled BSDF with Subsurface Weight 0, a slot
/// without a material): the faces of this material are left out of the
/// bake, their texels empty (alpha 0), and the summary says so.
pub const SSSBAKE_MATERIAL_NONE: u32 = 5;

/// Image Texture extension: the image tiles.
pub const SSSBAKE_EXTENSION_REPEAT: u32 = 0;
/// The edge texel repeats (Blender's Extend).
pub const SSSBAKE_EXTENSION_EXTEND: u32 = 1;
/// Black outside the image (Blender's Clip).
pub const SSSBAKE_EXTENSION_CLIP: u32 = 2;
/// The image tiles mirrored (Blender's Mirror).
pub const SSSBAKE_EXTENSION_MIRROR: u32 = 3;

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
    /// The Base Color image, or null: `image_width` × `image_height`
    /// texels of `image_channels` floats (3 RGB, or 4 RGBA whose alpha is
    /// ignored), linear (the host decodes its colour space), rows from
    /// v = 0 up (Blender's order). It replaces `base_colour` where it is
    /// sampled; the profile is built for its mean (docs/materials.md, "Colour maps").
    pub image_pixels: *const f32,
    /// Texels per row.
    pub image_width: u32,
    /// Rows.
    pub image_height: u32,
    /// 3 or 4.
    pub image_channels: u32,
    /// The UV set the image reads: 0 the mesh's `uvs`, k ≥ 1 its texture
    /// UV set k ([`SssbakeMesh::texture_uvs`](crate::SssbakeMesh)).
    pub image_uv_set: u32,
    /// One of the `SSSBAKE_EXTENSION_*` wraps outside [0, 1].
    pub image_extension: u32,
    /// Nonzero: the nearest texel (Blender's Closest); 0: bilinear.
    pub image_nearest: u32,
    /// The image's name for reports (UTF-8), or null.
    pub image_name: *const c_char,
    /// Roughness r in [0, 1] of a rough boundary over the subsurface, whose
    /// Beckmann RMS slope is m = r² (Donner & Jensen 2005 §2.4; docs/materials.md,
    /// "Materials"); 0, the default, is smooth (Principled kind; a TOML
    /// material gives its own `roughness`). A Principled BSDF's Roughness
    /// is Cycles' specular layer, not this boundary: the add-on passes 0.
    pub roughness: f32,
}

impl Default for SssbakeMaterial {
    /// A preset with no name, no image, Blender's Principled defaults for
    /// the rest: a host fills what its kind uses.
    fn default() -> Self {
        SssbakeMaterial {
            kind: SSSBAKE_MATERIAL_PRESET,
            name: std::ptr::null(),
            toml: std::ptr::null(),
            base_colour: [0.8; 3],
            subsurface_weight: 0.0,
            radius: [1.0, 0.2, 0.1],
            scale: 0.05,
            ior: 1.5,
            anisotropy: 0.0,
            subsurface_method: SSSBAKE_SUBSURFACE_RANDOM_WALK,
            subsurface_ior: 1.4,
            specular_ior_level: 0.5,
            albedo_mapping: SSSBAKE_ALBEDO_CYCLES,
            image_pixels: std::ptr::null(),
            image_width: 0,
            image_height: 0,
            image_channels: 0,
            image_uv_set: 0,
            image_extension: SSSBAKE_EXTENSION_REPEAT,
            image_nearest: 0,
            image_name: std::ptr::null(),
            roughness: 0.0,
        }
    }
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

/// The library's view of a host's material: its strings and image read.
///
/// # Safety
/// The strings are null or NUL-terminated; `image_pixels` is null or holds
/// the floats the material states.
pub(crate) unsafe fn host_material<'a>(
    material: &'a SssbakeMaterial,
) -> Result<HostMaterial<'a>, Failure> {
    let optional = |pointer: *const c_char, what: &str| -> Result<Option<&'a str>, Failure> {
        if pointer.is_null() {
            Ok(None)
        } else {
            // SAFETY: forwarded from the caller.
            Ok(Some(unsafe { text(pointer, what) }?))
        }
    };
    let name = optional(material.name, "material name")?;
    let toml = |what: &str| -> Result<String, Failure> {
        // SAFETY: forwarded from the caller.
        Ok(unsafe { text(material.toml, what) }?.to_string())
    };
    let kind = match material.kind {
        SSSBAKE_MATERIAL_PRESET => {
            if name.is_none() {
                return Err(Failure::argument("preset name is null"));
            }
            HostMaterialKind::Preset
        }
        SSSBAKE_MATERIAL_TOML => HostMaterialKind::Toml(toml("material TOML")?),
        SSSBAKE_MATERIAL_PRINCIPLED => HostMaterialKind::Principled(HostPrincipled {
            base_colour: material.base_colour,
            subsurface_weight: material.subsurface_weight,
            radius: material.radius,
            scale: material.scale,
            ior: material.ior,
            anisotropy: material.anisotropy,
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
            subsurface_ior: material.subsurface_ior,
            specular_ior_level: material.specular_ior_level,
            albedo: match material.albedo_mapping {
                SSSBAKE_ALBEDO_CYCLES => AlbedoMapping::Cycles,
                SSSBAKE_ALBEDO_PHYSICAL => AlbedoMapping::Physical,
                other => {
                    return Err(Failure::argument(format!(
                        "albedo mapping {other} is not one of SSSBAKE_ALBEDO_*"
                    )));
                }
            },
            roughness: material.roughness,
        }),
        SSSBAKE_MATERIAL_SCENE => HostMaterialKind::Scene,
        SSSBAKE_MATERIAL_NONE => HostMaterialKind::NoSubsurface,
        SSSBAKE_MATERIAL_SIDECAR => HostMaterialKind::Sidecar(toml("sidecar TOML")?),
        other => {
            return Err(Failure::argument(format!(
                "material kind {other} is not one of SSSBAKE_MATERIAL_*"
            )));
        }
    };
    let image = if material.image_pixels.is_null() {
        None
    } else {
        let (w, h, c) = (
            material.image_width as usize,
            material.image_height as usize,
            material.image_channels as usize,
        );
        // The library checks the size; an impossible one reads nothing.
        let len = w.checked_mul(h).and_then(|n| n.checked_mul(c));
        let pixels = match len {
            // SAFETY: forwarded from the caller.
            Some(len) if c == 3 || c == 4 => {
                unsafe { slice(material.image_pixels, len, "image pixels") }?
            }
            _ => &[],
        };
        Some(HostImage {
            pixels,
            width: w,
            height: h,
            channels: c,
            uv_set: material.image_uv_set as usize,
            wrap: match material.image_extension {
                SSSBAKE_EXTENSION_REPEAT => Wrap::Repeat,
                SSSBAKE_EXTENSION_EXTEND => Wrap::Clamp,
                SSSBAKE_EXTENSION_CLIP => Wrap::Black,
                SSSBAKE_EXTENSION_MIRROR => Wrap::Mirror,
                other => {
                    return Err(Failure::argument(format!(
                        "material `{}`: image extension {other} is not one of SSSBAKE_EXTENSION_*",
                        name.unwrap_or("material")
                    )));
                }
            },
            nearest: material.image_nearest != 0,
            name: optional(material.image_name, "image name")?,
        })
    };
    Ok(HostMaterial { kind, name, image })
}
