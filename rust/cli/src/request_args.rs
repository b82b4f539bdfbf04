//! The options `bake`, `plan` and `report` share, turned into the scene
//! and the library's [`BakeRequest`]. Every default comes from the library.

use clap::builder::{PossibleValuesParser, TypedValueParser};
use sssbake::request::MAX_RESOLUTION;
use sssbake::transport::integrator::IntegratorSettings;
use sssbake::{BakeRequest, Error, Method, Output, Scene, UvPolicy};
use sssbake_io::BakeOptions;
use sssbake_profile::model::Model;
use std::path::PathBuf;
use std::sync::LazyLock;
use strum::VariantNames;

static DEFAULTS: LazyLock<BakeRequest> = LazyLock::new(BakeRequest::default);
static INTEGRATORS: LazyLock<IntegratorSettings> = LazyLock::new(IntegratorSettings::default);

/// A parser accepting the names `names` and parsing them as `T`.
pub fn named<T>(names: &'static [&'static str]) -> impl TypedValueParser<Value = T>
where
    T: std::str::FromStr + Clone + Send + Sync + 'static,
    T::Err: std::error::Error + Send + Sync + 'static,
{
    PossibleValuesParser::new(names).try_map(|name| name.parse::<T>())
}

/// Options shared by the commands that bake.
#[derive(clap::Args, Clone, Debug)]
pub struct RequestArgs {
    /// The scene: .gltf, .glb, .usd, .usda, .usdc or .usdz.
    pub input: PathBuf,
    /// An object to bake (repeat for more) [default: every object].
    #[arg(long = "object", value_name = "NAME")]
    pub objects: Vec<String>,
    /// A material preset for every object the sidecar does not name
    /// [default: the object's own material in the file, else skin1].
    #[arg(long, conflicts_with = "material")]
    pub preset: Option<String>,
    /// A TOML material file for every object the sidecar does not name.
    #[arg(long)]
    pub material: Option<PathBuf>,
    /// A TOML sidecar mapping objects to presets or material files.
    #[arg(long, value_name = "FILE")]
    pub materials: Option<PathBuf>,
    /// The profile model [default: chosen for the material].
    #[arg(long, value_parser = named::<Model>(Model::VARIANTS))]
    pub model: Option<Model>,
    /// Texels per side of each map (1 to 16384).
    #[arg(long, default_value_t = DEFAULTS.resolution,
          value_parser = clap::value_parser!(u32).range(1..=i64::from(MAX_RESOLUTION)))]
    pub resolution: u32,
    /// The texture-coordinate set to bake into.
    #[arg(long, default_value_t = 0)]
    pub uv_set: usize,
    /// Unwrap every object with xatlas, even where its UVs are usable.
    #[arg(long, conflicts_with = "keep_uvs")]
    pub unwrap: bool,
    /// Bake into the objects' UVs as they are, even where they overlap.
    #[arg(long)]
    pub keep_uvs: bool,
    /// Texels filled beyond each chart's edge, and between the charts of
    /// an unwrap.
    #[arg(long, default_value_t = DEFAULTS.margin)]
    pub margin: u32,
    /// The maps to make, comma-separated.
    #[arg(long, value_delimiter = ',', default_values_t = DEFAULTS.outputs.clone(),
          value_parser = named::<Output>(Output::VARIANTS))]
    pub outputs: Vec<Output>,
    /// The integrator.
    #[arg(long, default_value_t = DEFAULTS.method, value_parser = named::<Method>(Method::VARIANTS))]
    pub method: Method,
    /// Octree: the solid angle (sr) below which a node is taken whole.
    #[arg(long, default_value_t = INTEGRATORS.octree.epsilon)]
    pub octree_epsilon: f32,
    /// Texture: Gaussians in the fit (and in a `gaussians` model).
    #[arg(long, default_value_t = INTEGRATORS.texture.gaussians)]
    pub gaussians: usize,
    /// Importance: probes per texel.
    #[arg(long, default_value_t = INTEGRATORS.importance.samples)]
    pub samples: u32,
    /// Walk: walks per texel and channel (`--method walk`).
    #[arg(long, default_value_t = INTEGRATORS.walk.samples)]
    pub walk_samples: u32,
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
    #[arg(long, default_value_t = DEFAULTS.colour_split)]
    pub colour_split: f32,
    /// Samples per soft light and for the environment, per texel.
    #[arg(long, default_value_t = DEFAULTS.light_samples)]
    pub light_samples: u32,
    /// RMS facet slope of every material's surface, in [0, 1] (Donner &
    /// Jensen 2005 §2.4) [default: each material's own `roughness`].
    #[arg(long)]
    pub roughness: Option<f64>,
    /// Relative RMSE against the exact sum that `--method auto` holds each
    /// object to: it estimates its error and moves to a more exact method
    /// above it (0.01 is 1%).
    #[arg(long, default_value_t = DEFAULTS.tolerance)]
    pub tolerance: f64,
    /// Texels at which the bake is checked against light itself: a
    /// volumetric random walk through the mesh, reported beside the error
    /// against the exact sum (0 turns the check off).
    #[arg(long, value_name = "TEXELS", default_value_t = DEFAULTS.light_check)]
    pub light_check: u32,
    /// Seed of the Monte Carlo of importance sampling and of the walk.
    #[arg(long, default_value_t = INTEGRATORS.importance.seed)]
    pub seed: u64,
    /// Memory a bake may hold (16G, 512M, binary units); the plan refuses
    /// a bake estimated to need more [default: 16G].
    #[arg(long, value_name = "SIZE")]
    pub max_memory: Option<String>,
    /// Shadow rays, kernel evaluations and probes a bake may take; the plan
    /// refuses more [default: 3e10, about an hour of the exact sum on two
    /// cores].
    #[arg(long, value_name = "COUNT")]
    pub max_evaluations: Option<f64>,
    /// Worker threads [default: every core].
    #[arg(long)]
    pub threads: Option<usize>,
}

impl RequestArgs {
    /// Reads the scene, the materials and the images, and makes the request.
    pub fn load(&self) -> Result<(Scene, BakeRequest), Error> {
        if let Some(s) = self.unit_scale.filter(|s| !(s.is_finite() && *s > 0.0)) {
            return Err(Error::field(
                "--unit-scale",
                format!("{s} must be a positive number of millimetres"),
            ));
        }
        if let Some(threads) = self.threads {
            // Only the first call sets the pool; later ones keep it.
            let _ = rayon::ThreadPoolBuilder::new()
                .num_threads(threads.max(1))
                .build_global();
        }
        self.options().load(&self.input)
    }

    /// These flags as the library's [`BakeOptions`] (the flags' defaults
    /// are the library's own, so every option is given).
    fn options(&self) -> BakeOptions {
        BakeOptions {
            objects: Some(self.objects.clone()),
            preset: self.preset.clone(),
            material: self.material.clone(),
            materials: self.materials.clone(),
            model: self.model.map(|m| m.to_string()),
            resolution: Some(self.resolution),
            uv_set: Some(self.uv_set),
            uvs: Some(if self.unwrap {
                UvPolicy::Unwrap
            } else if self.keep_uvs {
                UvPolicy::Keep
            } else {
                UvPolicy::Auto
            }),
            margin: Some(self.margin),
            outputs: Some(self.outputs.iter().map(|o| o.to_string()).collect()),
            method: Some(self.method.to_string()),
            octree_epsilon: Some(self.octree_epsilon),
            gaussians: Some(self.gaussians),
            samples: Some(self.samples),
            walk_samples: Some(self.walk_samples),
            seed: Some(self.seed),
            unit_scale: self.unit_scale,
            irradiance: self.irradiance.clone(),
            environment: self.environment.clone(),
            base_color: self.base_color.clone(),
            colour_split: Some(self.colour_split),
            light_samples: Some(self.light_samples),
            roughness: self.roughness,
            tolerance: Some(self.tolerance),
            light_check: Some(self.light_check),
            max_memory: self.max_memory.clone(),
            max_evaluations: self.max_evaluations,
            half: None,
            exposure: None,
        }
    }
}
