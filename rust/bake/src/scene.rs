//! A scene as the bake sees it: objects with their meshes and material
//! hints, and lights, all in millimetres.

use crate::mesh::Mesh;
use glam::{Vec2, Vec3};

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
}

/// What an asset's material says about translucency and colour.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct MaterialHint {
    /// Material name.
    pub name: String,
    /// Base colour factor, linear RGBA.
    pub base_color: [f32; 4],
    /// The base colour texture's image URI or name, if any.
    pub base_color_texture: Option<String>,
    /// Index of refraction, if the asset gives one.
    pub ior: Option<f32>,
    /// Volume: attenuation distance (mm) and colour, when the asset has one.
    pub volume: Option<Volume>,
    /// Diffuse transmission factor and colour, when the asset has one.
    pub diffuse_transmission: Option<([f32; 3], f32)>,
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
        self.volume.is_some()
            || self
                .diffuse_transmission
                .is_some_and(|(_, factor)| factor > 0.0)
    }
}

/// A light source in world space.
#[derive(Clone, Debug, PartialEq)]
pub struct Light {
    /// Name for reports.
    pub name: String,
    /// What kind of light.
    pub kind: LightKind,
    /// Linear RGB colour.
    pub color: [f32; 3],
    /// Intensity in the source format's unit (glTF: lux for directional
    /// lights, candela for point and spot lights).
    pub intensity: f32,
    /// Position, mm.
    pub position: Vec3,
    /// Direction the light points, unit.
    pub direction: Vec3,
}

/// Kinds of light.
#[derive(Clone, Debug, PartialEq)]
pub enum LightKind {
    /// Parallel light from infinitely far.
    Directional,
    /// Light from a point.
    Point,
    /// A light with a surface (USD rect and disk lights).
    Area,
    /// Light from every direction (USD dome lights).
    Environment,
    /// A point light limited to a cone (angles in radians).
    Spot {
        /// Full intensity inside this angle from the axis.
        inner_cone: f32,
        /// No light beyond this angle.
        outer_cone: f32,
    },
}

impl Scene {
    /// The objects named `names` (all when empty), or the first name that
    /// matches nothing.
    pub fn select<'a>(&'a self, names: &[String]) -> Result<Vec<&'a SceneObject>, String> {
        if names.is_empty() {
            return Ok(self.objects.iter().collect());
        }
        names
            .iter()
            .map(|name| {
                self.objects
                    .iter()
                    .find(|o| &o.mesh.name == name)
                    .ok_or_else(|| {
                        let known: Vec<&str> =
                            self.objects.iter().map(|o| o.mesh.name.as_str()).collect();
                        format!(
                            "{}: no object named `{name}` (objects: {})",
                            self.source,
                            known.join(", ")
                        )
                    })
            })
            .collect()
    }

    /// Total triangles in the scene.
    pub fn triangle_count(&self) -> usize {
        self.objects.iter().map(|o| o.mesh.triangles.len()).sum()
    }
}
