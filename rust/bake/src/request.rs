//! What a caller asks of a bake: one struct with one `Default` and one
//! `validate`, whichever door it came through (the CLI, the C ABI, a
//! Python pipeline).

use crate::error::Error;
use crate::image::Image;
use crate::irradiance::environment::EnvironmentMap;
use crate::limits::Limits;
use crate::maps::Output;
use crate::materials::MaterialAssignment;
use crate::scattering::D_MAX_EPSILON;
use crate::transport::Method;
use crate::transport::integrator::IntegratorSettings;
use serde::{Deserialize, Serialize};
use sssbake_profile::boundary::rough::MAX_ROUGHNESS;
use sssbake_profile::model::Model;
use std::sync::Arc;

/// What light reaches the object.
#[derive(Clone, Debug, Default)]
pub enum Lighting {
    /// The scene's lights, with the images environment lights name.
    #[default]
    SceneLights,
    /// The scene's lights; `environment` replaces every environment
    /// light's texture (already read from its file).
    SceneLightsWith {
        /// The equirectangular image (shared: the plan copies the request).
        environment: Arc<EnvironmentMap>,
    },
    /// A texture in the object's own UV layout is the transmitted
    /// irradiance (a lightmap from any renderer); lights are ignored.
    Irradiance(Arc<Image>),
}

/// The largest map side, texels.
pub const MAX_RESOLUTION: u32 = 16384;

/// What to do with an object's own UVs.
#[derive(
    Clone,
    Copy,
    Debug,
    Default,
    PartialEq,
    Eq,
    Serialize,
    Deserialize,
    strum::Display,
    strum::EnumString,
    strum::VariantNames,
    strum::EnumMessage,
    strum::VariantArray,
    strum::IntoStaticStr,
)]
#[serde(rename_all = "lowercase")]
#[strum(serialize_all = "lowercase")]
pub enum UvPolicy {
    /// Keep usable UVs; unwrap missing or unusable ones with xatlas.
    #[default]
    Auto,
    /// Unwrap every object, even where its UVs are usable.
    Unwrap,
    /// Bake into the object's UVs as they are, even where they overlap or
    /// stretch (with a warning); for hosts that show the maps through UVs
    /// of their own, such as Blender's. An object without UVs is refused.
    Keep,
}

/// The relative RMSE against the exact sum `auto` holds each object to
/// unless asked otherwise.
pub const DEFAULT_TOLERANCE: f64 = 0.01;

/// A bake as asked for.
///
/// Start from [`BakeRequest::default`] and change what differs; [`crate::plan()`]
/// validates it, so a door never restates a default or a check.
///
/// ```
/// let mut request = sssbake::BakeRequest { resolution: 0, ..Default::default() };
/// let error = request.validate().unwrap_err();
/// assert!(error.to_string().contains("resolution"), "{error}");
///
/// request.resolution = 256;
/// assert!(request.validate().is_ok());
/// ```
#[derive(Clone, Debug)]
pub struct BakeRequest {
    /// Objects to bake by name; every object when empty.
    pub objects: Vec<String>,
    /// Which material each object bakes with.
    pub materials: MaterialAssignment,
    /// The profile model; `None` lets each material choose its own.
    pub model: Option<Model>,
    /// Texels per side of each map, 1 to [`MAX_RESOLUTION`].
    pub resolution: u32,
    /// Keep, unwrap or trust the objects' UVs.
    pub uvs: UvPolicy,
    /// Texels filled beyond each chart's edge (across seams where the edge
    /// is one), and the padding between the charts of an unwrap.
    pub margin: u32,
    /// The maps to make; the plan leaves out every stage they do not need.
    pub outputs: Vec<Output>,
    /// The integrator, or `auto` to let the plan choose.
    pub method: Method,
    /// Every integrator's settings.
    pub integrators: IntegratorSettings,
    /// Relative RMSE against the exact sum that `auto` holds each object
    /// to: it checks its estimate and moves to a more exact method above it.
    pub tolerance: f64,
    /// Texels at which every bake is checked against light itself (a
    /// volumetric random walk through the mesh); 0 turns the check off.
    pub light_check: u32,
    /// Share of the reflectance left outside d_max, in (0, 1).
    pub d_max_epsilon: f64,
    /// Where the light comes from.
    pub lighting: Lighting,
    /// Samples per soft light and for the environment, per texel.
    pub light_samples: u32,
    /// Bounces of the light each object sends onto itself across air
    /// (an eye socket, a fold), up to
    /// [`MOST_BOUNCES`](crate::irradiance::bounce::MOST_BOUNCES); 0 leaves
    /// it out, as a bake of the direct light alone.
    pub bounces: u32,
    /// RMS facet slope of every material's surface (Donner & Jensen 2005
    /// §2.4), in [0, 1] (0 smooth); `None` keeps each material's own
    /// ([`Material::roughness`](sssbake_profile::Material::roughness)).
    pub roughness: Option<f64>,
    /// A base colour map in the objects' UVs, applied as C^α before
    /// scattering and C^(1−α) after (Mikkelsen §3.5). Shared, so that the
    /// plan's copy of the request does not copy the image.
    pub base_colour: Option<Arc<Image>>,
    /// α of the colour split, in [0, 1].
    pub colour_split: f32,
    /// The memory and work the bake may take; the plan refuses more.
    pub limits: Limits,
}

impl Default for BakeRequest {
    fn default() -> Self {
        BakeRequest {
            objects: Vec::new(),
            materials: MaterialAssignment::default(),
            model: None,
            resolution: 1024,
            uvs: UvPolicy::Auto,
            margin: 8,
            outputs: Output::DEFAULT.to_vec(),
            method: Method::Auto,
            integrators: IntegratorSettings::default(),
            tolerance: DEFAULT_TOLERANCE,
            light_check: crate::transport::light_check::DEFAULT_TEXELS,
            d_max_epsilon: D_MAX_EPSILON,
            lighting: Lighting::SceneLights,
            light_samples: 16,
            bounces: crate::irradiance::bounce::DEFAULT_BOUNCES,
            roughness: None,
            base_colour: None,
            colour_split: 0.5,
            limits: Limits::default(),
        }
    }
}

impl BakeRequest {
    /// Refuses a request no bake can run, naming the field; sorts and
    /// deduplicates the outputs.
    pub fn validate(&mut self) -> Result<(), Error> {
        if !(1..=MAX_RESOLUTION).contains(&self.resolution) {
            return Err(Error::field(
                "resolution",
                format!("{} must be between 1 and {MAX_RESOLUTION}", self.resolution),
            ));
        }
        if self.margin > self.resolution {
            return Err(Error::field(
                "margin",
                format!(
                    "{} texels is more than the map's side ({})",
                    self.margin, self.resolution
                ),
            ));
        }
        self.outputs.sort();
        self.outputs.dedup();
        if self.outputs.is_empty() {
            return Err(Error::field("outputs", "name at least one map"));
        }
        if self.light_samples == 0 {
            return Err(Error::field("light_samples", "must be at least 1"));
        }
        if self.bounces > crate::irradiance::bounce::MOST_BOUNCES {
            return Err(Error::field(
                "bounces",
                format!(
                    "{} is more than {}",
                    self.bounces,
                    crate::irradiance::bounce::MOST_BOUNCES
                ),
            ));
        }
        if !(self.d_max_epsilon > 0.0 && self.d_max_epsilon < 1.0) {
            return Err(Error::field(
                "d_max_epsilon",
                format!("{} must be between 0 and 1", self.d_max_epsilon),
            ));
        }
        if let Some(m) = self
            .roughness
            .filter(|m| !(0.0..=MAX_ROUGHNESS).contains(m))
        {
            return Err(Error::field(
                "roughness",
                format!("{m} must be an RMS facet slope between 0 (smooth) and {MAX_ROUGHNESS}"),
            ));
        }
        if !(self.tolerance.is_finite() && self.tolerance > 0.0) {
            return Err(Error::field(
                "tolerance",
                format!(
                    "{} must be a positive relative error (0.01 is 1%)",
                    self.tolerance
                ),
            ));
        }
        let most = crate::transport::light_check::MOST_TEXELS;
        if self.light_check > most {
            return Err(Error::field(
                "light_check",
                format!("{} texels is more than {most}", self.light_check),
            ));
        }
        if !(0.0..=1.0).contains(&self.colour_split) {
            return Err(Error::field(
                "colour_split",
                format!("{} must be between 0 and 1", self.colour_split),
            ));
        }
        if self.limits.max_memory_bytes == 0 {
            return Err(Error::field("max_memory", "must be a positive size"));
        }
        // `inf` lifts the limit; NaN and 0 are refused.
        if self.limits.max_evaluations.partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater) {
            return Err(Error::field(
                "max_evaluations",
                format!("{} must be positive", self.limits.max_evaluations),
            ));
        }
        self.integrators.validate()
    }

    /// True when any output needs the light scattered.
    pub fn scatters(&self) -> bool {
        self.outputs.iter().any(|o| o.needs_scattering())
    }

    /// True when any output needs the light entering the surface.
    pub fn lights(&self) -> bool {
        self.outputs.iter().any(|o| o.needs_light())
    }
}
