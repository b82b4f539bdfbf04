//! A scene as the bake sees it: objects with their meshes and material
//! hints, and lights, all in millimetres.

use crate::mesh::Mesh;
use glam::{Vec2, Vec3};
use sssbake_profile::Appearance;

/// Everything read from one input file.
#[derive(Clone, Debug, Default)]
pub struct Scene {
    /// The file it came from, for messages.
    pub source: String,
    /// Millimetres per scene unit applied when reading (1000 for metres).
    pub millimetres_per_unit: f64,
    /// The bakeable objects.
    pub objects: Vec<SceneObject>,
    /// The lights.
    pub lights: Vec<Light>,
    /// Things read but not used, with counts, for the plan to report.
    pub notes: Vec<String>,
}

/// One object: a mesh in world space and what its material says.
#[derive(Clone, Debug, Default)]
pub struct SceneObject {
    /// The mesh (its name is the object's name).
    pub mesh: Mesh,
    /// Every UV set the object has, by index; the mesh carries the chosen one.
    pub uv_sets: Vec<Vec<Vec2>>,
    /// The material's hints, from the first primitive that has a material.
    pub material: Option<MaterialHint>,
    /// Where the object came from in its file, so writers can find it
    /// again: the glTF node index.
    pub node: Option<usize>,
    /// ... or the USD mesh prim's path.
    pub prim: Option<String>,
    /// The texture its material's colour reads, when one drives it
    /// (docs/materials.md, "Colour maps").
    pub colour_texture: Option<crate::colour::ColourTexture>,
    /// From the file's coordinates in the object's own frame (the glTF
    /// node's) to the scene's, in mm; identity where positions are read in
    /// world space already.
    pub local_to_world: glam::Mat4,
}

/// What an asset's material says about translucency and colour.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct MaterialHint {
    /// Material name.
    pub name: String,
    /// Base colour factor, linear RGBA.
    pub base_color: [f32; 4],
    /// Index of refraction, if the asset gives one.
    pub ior: Option<f32>,
    /// Volume: attenuation distance (mm) and colour, when the asset has one.
    pub volume: Option<Volume>,
    /// Diffuse transmission factor and colour, when the asset has one.
    pub diffuse_transmission: Option<([f32; 3], f32)>,
    /// What the shader says about light under the surface, when it gives a
    /// scattering distance (docs/materials.md, "Materials from the asset").
    pub subsurface: Option<Subsurface>,
}

/// A shader's subsurface description, in the terms every format shares.
#[derive(Clone, Debug, PartialEq)]
pub struct Subsurface {
    /// The colour the surface shows under uniform light, linear RGB.
    pub colour: [f64; 3],
    /// Mean free path 1/σt per channel, mm.
    pub mean_free_path_mm: [f64; 3],
    /// Henyey–Greenstein mean cosine g.
    pub anisotropy: f64,
    /// Which inputs it came from, for reports.
    pub from: String,
}

/// A participating medium's attenuation as glTF describes it.
#[derive(Clone, Debug, PartialEq)]
pub struct Volume {
    /// Distance at which light falls to the attenuation colour, mm.
    pub attenuation_distance_mm: f32,
    /// Colour left after that distance.
    pub attenuation_color: [f32; 3],
    /// Thickness factor, mm (a hint for thin geometry).
    pub thickness_mm: f32,
}

impl MaterialHint {
    /// True when the material asks for light to pass under the surface.
    pub fn is_translucent(&self) -> bool {
        self.subsurface.is_some()
            || self.volume.is_some()
            || self
                .diffuse_transmission
                .is_some_and(|(_, factor)| factor > 0.0)
    }

    /// The material as a shader describes it, and the inputs it came from;
    /// `None` for a material that gives only a colour (UsdPreviewSurface, a
    /// glTF base colour), which takes `fallback_mfp_mm`, the scattering
    /// distance of a fallback material, per channel.
    pub fn appearance(&self, fallback_mfp_mm: [f64; 3]) -> (Appearance, Option<String>) {
        let ior = f64::from(self.ior.unwrap_or(DEFAULT_IOR));
        let (colour, mean_free_path_mm, anisotropy, from) = match &self.subsurface {
            Some(s) => (
                s.colour,
                s.mean_free_path_mm,
                s.anisotropy,
                Some(s.from.clone()),
            ),
            None => (
                [0, 1, 2].map(|c| f64::from(self.base_color[c])),
                fallback_mfp_mm,
                0.0,
                None,
            ),
        };
        let appearance = Appearance {
            name: self.name.clone(),
            colour,
            mean_free_path_mm,
            ior,
            anisotropy,
        };
        (appearance, from)
    }
}

/// Index of refraction when a material states none: glTF's default, and
/// UsdPreviewSurface's.
pub const DEFAULT_IOR: f32 = 1.5;

/// A light source in world space, in radiometric units.
///
/// Readers convert each format's units once (docs/lights.md, "Lights and units"):
/// glTF lux and candela as Blender's glTF exporter writes them (a sun's
/// lux is its W/m²; a point's candela is 683 lm/W · W/(4π sr)), USD
/// intensity × 2^exposure as UsdLux defines it, Blender's own units as
/// Cycles reads them.
#[derive(Clone, Debug, PartialEq)]
pub struct Light {
    /// Name for reports.
    pub name: String,
    /// What kind of light, with its shape.
    pub kind: LightKind,
    /// Linear RGB colour (multiplies the intensity).
    pub color: [f32; 3],
    /// Strength in the unit [`LightKind`] gives for the kind.
    pub intensity: f32,
    /// Position, mm.
    pub position: Vec3,
    /// Direction the light points (its −Z axis), unit.
    pub direction: Vec3,
    /// The light's local X axis, unit: orients rectangles and is a
    /// cylinder's axis.
    pub tangent: Vec3,
    /// False for a light whose light no object blocks (Blender's
    /// `use_shadow` off).
    pub casts_shadow: bool,
}

/// Kinds of light, with the unit of [`Light::intensity`] for each.
#[derive(Clone, Debug, PartialEq)]
pub enum LightKind {
    /// Parallel light from far away; intensity is the irradiance on a
    /// surface facing it, W/m². `angle` is the sun's angular diameter,
    /// radians (0: a hard shadow).
    Directional {
        /// Angular diameter, radians.
        angle: f32,
    },
    /// Light from a point or a sphere of `radius_mm`; intensity is the
    /// radiant intensity, W/sr.
    Point {
        /// Sphere radius, mm (0 for a point).
        radius_mm: f32,
    },
    /// A point light limited to a cone; intensity in W/sr on its axis.
    Spot {
        /// Sphere radius, mm.
        radius_mm: f32,
        /// Full intensity inside this angle from the axis, radians.
        inner_cone: f32,
        /// No light beyond this angle, radians.
        outer_cone: f32,
        /// How the light fades between the two cones.
        falloff: ConeFalloff,
    },
    /// A rectangle emitting from its front face; intensity is radiance,
    /// W/(m²·sr).
    Rectangle {
        /// Extent along the light's X axis, mm.
        width_mm: f32,
        /// Extent along its Y axis, mm.
        height_mm: f32,
        /// Angle of the cone the emission fills, radians (π: a Lambertian
        /// emitter; Cycles' area `spread`).
        spread: f32,
    },
    /// A disk emitting from its front face; intensity is radiance,
    /// W/(m²·sr).
    Disk {
        /// Radius, mm.
        radius_mm: f32,
        /// As for a rectangle.
        spread: f32,
    },
    /// A cylinder along the light's X axis emitting from its side (not its
    /// caps); intensity is radiance, W/(m²·sr).
    Cylinder {
        /// Length along the axis, mm.
        length_mm: f32,
        /// Radius, mm.
        radius_mm: f32,
    },
    /// A line along the light's X axis (a cylinder of no radius); intensity
    /// is the radiant intensity of each metre of it seen broadside,
    /// W/(sr·m), falling with the sine of the angle from the axis.
    Line {
        /// Length, mm.
        length_mm: f32,
    },
    /// Light from every direction; intensity is radiance, W/(m²·sr),
    /// multiplied by the equirectangular image when there is one.
    Environment {
        /// The image file, as the asset names it.
        texture: Option<String>,
    },
}

/// How a spot fades from its inner cone (full light) to its outer cone
/// (none), each format by its own definition.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ConeFalloff {
    /// Cycles: a smooth step (3t² − 2t³) in t, the cosine's share of the
    /// way from the outer cone to the inner one.
    Cycles,
    /// glTF `KHR_lights_punctual`: t², the same t squared.
    Gltf,
    /// UsdLux `ShapingAPI`: one minus a smooth step in the angle itself,
    /// from the inner cone to the outer one.
    UsdLux,
}

impl ConeFalloff {
    /// The share of the axis's light at `angle` (radians) from the axis of a
    /// spot whose light fades from `inner` to `outer` (radians).
    pub fn at(self, angle: f32, inner: f32, outer: f32) -> f32 {
        if angle >= outer {
            return 0.0;
        }
        if angle <= inner {
            return 1.0;
        }
        let smooth = |t: f32| {
            let t = t.clamp(0.0, 1.0);
            t * t * (3.0 - 2.0 * t)
        };
        match self {
            ConeFalloff::Cycles | ConeFalloff::Gltf => {
                let (cos, cos_inner, cos_outer) = (angle.cos(), inner.cos(), outer.cos());
                let t = ((cos - cos_outer) / (cos_inner - cos_outer).max(1e-9)).clamp(0.0, 1.0);
                if self == ConeFalloff::Cycles {
                    smooth(t)
                } else {
                    t * t
                }
            }
            ConeFalloff::UsdLux => 1.0 - smooth((angle - inner) / (outer - inner).max(1e-9)),
        }
    }
}

/// The inner and outer cone (radians from the axis) of a spot of
/// `half_angle` (radians) whose edge fades over `blend` of the cone, as
/// Cycles fades Blender's spots: full light inside the inner cone, a smooth
/// step in cos θ over the last `blend` × (1 − cos half_angle).
pub fn spot_cone(half_angle: f32, blend: f32) -> (f32, f32) {
    let outer = half_angle.clamp(0.0, std::f32::consts::PI);
    let inner = (outer.cos() + blend.clamp(0.0, 1.0) * (1.0 - outer.cos()))
        .clamp(-1.0, 1.0)
        .acos();
    (inner, outer)
}

impl LightKind {
    /// The kind's name in reports.
    pub fn name(&self) -> &'static str {
        match self {
            LightKind::Directional { .. } => "directional",
            LightKind::Point { .. } => "point",
            LightKind::Spot { .. } => "spot",
            LightKind::Rectangle { .. } => "rectangle",
            LightKind::Disk { .. } => "disk",
            LightKind::Cylinder { .. } => "cylinder",
            LightKind::Line { .. } => "line",
            LightKind::Environment { .. } => "environment",
        }
    }
}

impl Scene {
    /// The indices of the objects named `names` (all when empty), or an
    /// error naming the first name that matches nothing.
    pub fn select(&self, names: &[String]) -> Result<Vec<usize>, crate::Error> {
        if names.is_empty() {
            return Ok((0..self.objects.len()).collect());
        }
        names
            .iter()
            .map(|name| {
                self.objects
                    .iter()
                    .position(|o| &o.mesh.name == name)
                    .ok_or_else(|| {
                        let known: Vec<&str> =
                            self.objects.iter().map(|o| o.mesh.name.as_str()).collect();
                        crate::Error::input(format!(
                            "no object named `{name}` (objects: {})",
                            known.join(", ")
                        ))
                        .in_file(self.source.clone())
                    })
            })
            .collect()
    }

    /// Total triangles in the scene.
    pub fn triangle_count(&self) -> usize {
        self.objects.iter().map(|o| o.mesh.triangles.len()).sum()
    }
}

/// One row of a format's light table (docs/lights.md, "Lights and units"): what a
/// file says, what the bake makes of it, and the irradiance it gives at a
/// point of a plane. Each reader keeps its table beside its code, and a
/// test checks docs/lights.md shows the same rows.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct LightRow {
    /// The light as the format states it.
    pub source: &'static str,
    /// The bake's light.
    pub read_as: &'static str,
    /// Irradiance at a point of a plane, before the entry Fresnel.
    pub irradiance: &'static str,
}

/// `rows` as a Markdown table under `header` (three column titles).
pub fn light_table_markdown(header: [&str; 3], rows: &[LightRow]) -> String {
    let mut out = format!(
        "| {} | {} | {} |\n|---|---|---|\n",
        header[0], header[1], header[2]
    );
    for row in rows {
        out.push_str(&format!(
            "| {} | {} | {} |\n",
            row.source, row.read_as, row.irradiance
        ));
    }
    out
}
