//! A scene built up by a host: meshes, lights and a world, or read from a
//! glTF or USD file (then its meshes are the file's).

use crate::lights::{HostLight, light_from_host};
use crate::mesh::{HostMesh, object_from_host};
use glam::Vec3;
use sssbake::{Error, Light, LightKind, Scene};
use std::collections::HashMap;
use std::path::PathBuf;

/// A scene a host builds, or one read from a file.
#[derive(Clone, Debug)]
pub struct HostScene {
    /// The library's scene (lengths in mm).
    pub scene: Scene,
    /// The file it was read from, kept so a bake into a folder can write
    /// the file's glTF copy or USD layer; `None` for a host's scene.
    pub file: Option<SceneFile>,
    /// Per object of a host's scene, the material index of each of its
    /// mesh's triangles (in the mesh's order); absent: all 0.
    pub face_materials: HashMap<String, Vec<u32>>,
}

/// Where a scene read from a file came from.
#[derive(Clone, Debug)]
pub struct SceneFile {
    /// The glTF or USD file.
    pub path: PathBuf,
    /// The texture-coordinate set it was read with.
    pub uv_set: usize,
}

impl HostScene {
    /// An empty scene whose units are `millimetres_per_unit` mm.
    pub fn new(millimetres_per_unit: f64) -> Result<Self, Error> {
        if !(millimetres_per_unit.is_finite() && millimetres_per_unit > 0.0) {
            return Err(Error::field(
                "millimetres_per_unit",
                format!("millimetres per unit is {millimetres_per_unit}; it must be positive"),
            ));
        }
        Ok(HostScene {
            scene: Scene {
                source: "host scene".into(),
                millimetres_per_unit,
                ..Scene::default()
            },
            file: None,
            face_materials: HashMap::new(),
        })
    }

    /// The scene read from `file` (with its texture-coordinate set
    /// `uv_set`).
    pub fn from_file(scene: Scene, file: PathBuf, uv_set: usize) -> Self {
        HostScene {
            scene,
            file: Some(SceneFile { path: file, uv_set }),
            face_materials: HashMap::new(),
        }
    }

    /// Adds a mesh as an object of its name (see [`HostMesh`]); refused in
    /// a scene read from a file, and for a name the scene has already.
    pub fn add_mesh(&mut self, mesh: &HostMesh) -> Result<(), Error> {
        if let Some(file) = &self.file {
            // The glTF copy or USD layer a folder bake writes follows the
            // file's objects; a mesh the file lacks would have no place there.
            return Err(Error::field(
                "mesh",
                format!(
                    "the scene was read from {}; meshes are added to a host's scene",
                    file.path.display()
                ),
            ));
        }
        let (object, face_materials) = object_from_host(mesh, self.scene.millimetres_per_unit)?;
        if self
            .scene
            .objects
            .iter()
            .any(|o| o.mesh.name == object.mesh.name)
        {
            return Err(Error::field(
                "mesh",
                format!(
                    "object `{}`: the scene has one of that name already",
                    object.mesh.name
                ),
            ));
        }
        if let Some(face_materials) = face_materials {
            self.face_materials
                .insert(object.mesh.name.clone(), face_materials);
        }
        self.scene.objects.push(object);
        Ok(())
    }

    /// Adds a light in Blender's terms (see [`HostLight`]).
    pub fn add_light(&mut self, light: &HostLight) -> Result<(), Error> {
        let converted = light_from_host(light, self.scene.millimetres_per_unit)?;
        self.scene.lights.push(converted);
        Ok(())
    }

    /// Sets a uniform world: `colour` (linear) × `strength`, a radiance in
    /// W/(m²·sr) as Blender's Background shader gives it; black or 0
    /// removes it.
    pub fn set_world(&mut self, colour: [f32; 3], strength: f32) -> Result<(), Error> {
        if !(strength.is_finite() && strength >= 0.0)
            || colour.iter().any(|c| !c.is_finite() || *c < 0.0)
        {
            return Err(Error::field(
                "world",
                format!(
                    "world colour {colour:?} × strength {strength}: both must be finite and non-negative"
                ),
            ));
        }
        self.scene
            .lights
            .retain(|l| !matches!(l.kind, LightKind::Environment { .. }));
        if strength > 0.0 && colour.iter().any(|&c| c > 0.0) {
            self.scene.lights.push(Light {
                name: "World".into(),
                kind: LightKind::Environment { texture: None },
                color: colour,
                intensity: strength,
                position: Vec3::ZERO,
                direction: Vec3::NEG_Z,
                tangent: Vec3::X,
                casts_shadow: true,
            });
        }
        Ok(())
    }
}
