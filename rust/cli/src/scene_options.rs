//! The options every command that bakes shares: the scene, the objects,
//! the material, the map size, the light, and turning them into the
//! library's inputs.

use crate::Failure;
use crate::material_choice;
use crate::material_map::MaterialMap;
use sssbake::irradiance::entry::Boundary;
use sssbake::irradiance::environment::EnvironmentMap;
use sssbake::pipeline::{BakeSettings, Lighting};
use sssbake::scene::LightKind;
use sssbake::{MaterialHint, Scene};
use sssbake_io::{ReadOptions, read_image, read_scene};
use sssbake_profile::Material;
use sssbake_profile::appearance::channel_mean_free_paths;
use sssbake_profile::model::{Model, build_profile};
use sssbake_profile::profile::Profile;
use std::path::{Path, PathBuf};

/// Options shared by the baking commands.
#[derive(clap::Args, Clone, Debug)]
pub struct SceneOptions {
    /// The scene: .gltf, .glb, .usd, .usda, .usdc or .usdz.
    pub input: PathBuf,
    /// An object to bake (repeat for more) [default: every object].
    #[arg(long = "object", value_name = "NAME")]
    pub objects: Vec<String>,
    /// A material preset for every object the sidecar does not name
    /// [default: the object's own material in the file, else skin1].
    #[arg(long, conflicts_with = "material")]
    pub preset: Option<String>,
    /// A TOML material file.
    #[arg(long)]
    pub material: Option<PathBuf>,
    /// A TOML sidecar mapping objects to presets or material files; objects
    /// it does not name take --preset or --material.
    #[arg(long, value_name = "FILE")]
    pub materials: Option<PathBuf>,
    /// The profile model [default: chosen for the material].
    #[arg(long)]
    pub model: Option<Model>,
    /// Texels per side of each map.
    #[arg(long, default_value_t = 1024)]
    pub resolution: u32,
    /// The texture-coordinate set to bake into.
    #[arg(long, default_value_t = 0)]
    pub uv_set: usize,
    /// Millimetres per scene unit, overriding the file's units.
    #[arg(long)]
    pub unit_scale: Option<f64>,
    /// An image (.exr linear, .png sRGB) in the object's UV layout to use
    /// as the transmitted irradiance instead of the scene's lights.
    #[arg(long, value_name = "IMAGE")]
    pub irradiance: Option<PathBuf>,
    /// An equirectangular image (.exr) for the scene's environment light.
    #[arg(long, value_name = "IMAGE")]
    pub environment: Option<PathBuf>,
    /// A base colour image (.exr linear, .png sRGB) in the object's UVs,
    /// applied as C^α before scattering and C^(1−α) after.
    #[arg(long = "base-color", value_name = "IMAGE")]
    pub base_color: Option<PathBuf>,
    /// α of the colour split (Mikkelsen §3.5): 0 colours after scattering
    /// only, 1 before only.
    #[arg(long, default_value_t = 0.5)]
    pub colour_split: f32,
    /// Samples per soft light and for the environment, per texel.
    #[arg(long, default_value_t = 16)]
    pub light_samples: u32,
    /// RMS slope of a rough surface (Donner & Jensen 2005 §2.4) [default: smooth].
    #[arg(long)]
    pub roughness: Option<f64>,
    /// Random seed for sample points and Monte Carlo.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Worker threads [default: every core].
    #[arg(long)]
    pub threads: Option<usize>,
}

/// One object's material, its profile and the settings that follow from it.
pub struct Assigned {
    /// The material.
    pub material: Material,
    /// Where it came from: the sidecar, the command line, the asset (with
    /// the inputs read), or the default.
    pub source: String,
    /// Its profile.
    pub profile: Box<dyn Profile>,
    /// The bake settings (the material's index and mean free path set).
    pub settings: BakeSettings,
}

/// Everything a bake needs, read and checked.
pub struct Loaded {
    /// The scene.
    pub scene: Scene,
    /// The names of the objects to bake, each with its material.
    pub objects: Vec<(String, Assigned)>,
    /// Where the light comes from.
    pub lighting: Lighting,
}

impl SceneOptions {
    /// Checks the options, reads the scene, material and images.
    pub fn load(&self) -> Result<Loaded, Failure> {
        if !(1..=16384).contains(&self.resolution) {
            return Err(Failure::Input(format!(
                "--resolution: {} must be between 1 and 16384",
                self.resolution
            )));
        }
        if let Some(s) = self.unit_scale.filter(|s| !(s.is_finite() && *s > 0.0)) {
            return Err(Failure::Input(format!(
                "--unit-scale: {s} must be a positive number of millimetres"
            )));
        }
        if let Some(m) = self.roughness.filter(|m| !(m.is_finite() && *m > 0.0)) {
            return Err(Failure::Input(format!("--roughness: {m} must be positive")));
        }
        if !(0.0..=1.0).contains(&self.colour_split) {
            return Err(Failure::Input(format!(
                "--colour-split: {} must be between 0 and 1",
                self.colour_split
            )));
        }
        if let Some(threads) = self.threads {
            // Only the first call sets the pool; later ones keep it.
            let _ = rayon::ThreadPoolBuilder::new()
                .num_threads(threads.max(1))
                .build_global();
        }
        let explicit = match (&self.preset, &self.material) {
            (None, None) => None,
            (preset, file) => Some(material_choice::load(preset.as_deref(), file.as_deref())?),
        };
        let default_material = material_choice::load(Some("skin1"), None)?;
        let options = ReadOptions {
            uv_set: self.uv_set,
            unit_scale: self.unit_scale,
        };
        let scene = read_scene(&self.input, &options).map_err(|e| Failure::Input(e.to_string()))?;
        let names: Vec<String> = scene
            .select(&self.objects)
            .map_err(Failure::Input)?
            .iter()
            .map(|o| o.mesh.name.clone())
            .collect();
        if names.is_empty() {
            return Err(Failure::Input(format!(
                "{}: has no object to bake",
                self.input.display()
            )));
        }
        let all: Vec<String> = scene.objects.iter().map(|o| o.mesh.name.clone()).collect();
        let map = match &self.materials {
            Some(path) => Some(MaterialMap::read(path, &all)?),
            None => None,
        };
        let lighting = self.lighting(&scene)?;
        let base_colour = match &self.base_color {
            Some(path) => Some(read_image(path).map_err(|e| Failure::Input(e.to_string()))?),
            None => None,
        };
        let base = BakeSettings {
            resolution: self.resolution,
            irradiance: sssbake::irradiance::IrradianceSettings {
                samples: self.light_samples.max(1),
                shadows: true,
            },
            boundary: self
                .roughness
                .map_or(Boundary::Smooth, |roughness| Boundary::Rough { roughness }),
            base_colour,
            colour_split: self.colour_split,
            ..BakeSettings::default()
        };
        let mut objects = Vec::new();
        for name in names {
            let hint = scene
                .objects
                .iter()
                .find(|o| o.mesh.name == name)
                .and_then(|o| o.material.as_ref());
            let (material, source) = self.material_for(
                &name,
                map.as_ref(),
                explicit.as_ref(),
                hint,
                &default_material,
            )?;
            let model = self.model.unwrap_or_else(|| Model::default_for(&material));
            let profile = build_profile(&material, model, 6)
                .map_err(|e| Failure::Input(format!("object `{name}`: {e}")))?;
            let settings = BakeSettings {
                eta: material.entry_index(),
                mean_free_path_mm: material.finest_mean_free_path_mm(),
                ..base.clone()
            };
            objects.push((
                name,
                Assigned {
                    material,
                    source,
                    profile,
                    settings,
                },
            ));
        }
        Ok(Loaded {
            scene,
            objects,
            lighting,
        })
    }

    /// The object's material: the sidecar's entry, else --preset or
    /// --material, else the asset's own material, else skin1.
    fn material_for(
        &self,
        name: &str,
        map: Option<&MaterialMap>,
        explicit: Option<&Material>,
        hint: Option<&MaterialHint>,
        default: &Material,
    ) -> Result<(Material, String), Failure> {
        if let Some((material, path)) = map.and_then(|m| m.for_object(name).map(|x| (x, &m.path))) {
            return Ok((material.clone(), format!("sidecar {}", path.display())));
        }
        if let Some(material) = explicit {
            let flag = if self.preset.is_some() {
                "--preset"
            } else {
                "--material"
            };
            return Ok((material.clone(), flag.to_string()));
        }
        let Some(hint) = hint else {
            return Ok((
                default.clone(),
                "default (the asset gives no material)".into(),
            ));
        };
        let (appearance, from) = hint.appearance(channel_mean_free_paths(default));
        let material = appearance.to_material().map_err(|e| {
            Failure::Input(format!(
                "{}: object `{name}`, material `{}`: {e}",
                self.input.display(),
                hint.name
            ))
        })?;
        let source = match from {
            Some(inputs) => format!("asset: {inputs}"),
            None => format!(
                "asset: base colour, with {}'s scattering distance",
                default.name
            ),
        };
        Ok((material, source))
    }

    fn lighting(&self, scene: &Scene) -> Result<Lighting, Failure> {
        if let Some(path) = &self.irradiance {
            let image = read_image(path).map_err(|e| Failure::Input(e.to_string()))?;
            return Ok(Lighting::Irradiance(image));
        }
        // The environment image: named on the command line, or by the
        // scene's environment light, relative to the scene file.
        let named = scene.lights.iter().find_map(|l| match &l.kind {
            LightKind::Environment { texture: Some(t) } => Some(t.clone()),
            _ => None,
        });
        let path = match (&self.environment, named) {
            (Some(p), _) => Some(p.clone()),
            (None, Some(t)) => Some(relative_to(&self.input, &t)),
            (None, None) => None,
        };
        let Some(path) = path else {
            return Ok(Lighting::SceneLights);
        };
        let image = read_image(&path).map_err(|e| Failure::Input(e.to_string()))?;
        let environment = EnvironmentMap::new(image.width, image.height, image.texels)
            .map_err(|e| Failure::Input(format!("{}: {e}", path.display())))?;
        Ok(Lighting::SceneLightsWith { environment })
    }
}

fn relative_to(scene: &Path, file: &str) -> PathBuf {
    let path = Path::new(file);
    if path.is_absolute() {
        return path.to_path_buf();
    }
    scene.parent().unwrap_or(Path::new(".")).join(path)
}
