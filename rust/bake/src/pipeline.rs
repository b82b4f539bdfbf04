//! One object from scene to exitance: layout, texels, irradiance, then any
//! integrator. [`prepare`] does what every method shares, so a report can
//! run many integrators on one preparation.

use crate::control::{Cancelled, Control};
use crate::dilation::seam_aware_offsets;
use crate::image::Image;
use crate::irradiance::emitters::Emitter;
use crate::irradiance::entry::{Boundary, EntryTransmittance};
use crate::irradiance::environment::EnvironmentMap;
use crate::irradiance::{IrradianceSettings, Receivers, transmitted_irradiance};
use crate::mesh::Mesh;
use crate::rays::RayScene;
use crate::scene::{LightKind, Scene};
use crate::texels::{TexelSurfels, rasterize, uv_jacobian};
use crate::transport::choice::{Choice, choose};
use crate::transport::clusters::cluster;
use crate::transport::kernel::Kernel;
use crate::transport::sources::{Sources, Targets};
use crate::transport::{Method, MethodSettings, brute, importance, octree, texture_space};
use crate::turk::{place_points, point_count, relax};
use crate::uv_analysis::analyse_uvs;
use glam::{Vec2, Vec3};
use sssbake_profile::gaussians::fit_gaussians;
use sssbake_profile::profile::Profile;
use std::time::Instant;

/// Why a bake stopped.
#[derive(Debug, thiserror::Error)]
pub enum BakeError {
    /// The caller cancelled.
    #[error("cancelled")]
    Cancelled(#[from] Cancelled),
    /// The inputs cannot be baked; the message names the object and why.
    #[error("{0}")]
    Input(String),
}

/// What light reaches the object.
#[derive(Clone, Debug, Default)]
pub enum Lighting {
    /// The scene's lights, with the images environment lights name.
    #[default]
    SceneLights,
    /// The scene's lights; `environment` replaces every environment
    /// light's texture (already read from its file).
    SceneLightsWith {
        /// The equirectangular image.
        environment: EnvironmentMap,
    },
    /// A texture in the object's own UV layout is the transmitted
    /// irradiance (a lightmap from any renderer); lights are ignored.
    Irradiance(Image),
}

/// Settings shared by every method.
#[derive(Clone, Debug)]
pub struct BakeSettings {
    /// Texels per side.
    pub resolution: u32,
    /// Texels between charts when unwrapping.
    pub padding: u32,
    /// Unwrap even when the UVs are usable.
    pub force_unwrap: bool,
    /// Never unwrap: bake into the object's UVs even where they overlap or
    /// stretch (reported in [`Prepared::uv_warning`]), and fail only when
    /// it has none; for callers that show the maps through UVs of their
    /// own, such as Blender's.
    pub keep_uvs: bool,
    /// Light sampling.
    pub irradiance: IrradianceSettings,
    /// The boundary light enters through.
    pub boundary: Boundary,
    /// Material index of refraction (inside over outside).
    pub eta: f64,
    /// Base colour map applied as C^α before scattering and C^(1−α)
    /// after (Mikkelsen §3.5).
    pub base_colour: Option<Image>,
    /// α of the colour split, in [0, 1] (½ by default).
    pub colour_split: f32,
    /// The material's mean free path, mm (Turk point spacing).
    pub mean_free_path_mm: f64,
}

impl Default for BakeSettings {
    fn default() -> Self {
        BakeSettings {
            resolution: 1024,
            padding: 4,
            force_unwrap: false,
            keep_uvs: false,
            irradiance: IrradianceSettings::default(),
            boundary: Boundary::Smooth,
            eta: 1.3,
            base_colour: None,
            colour_split: 0.5,
            mean_free_path_mm: 1.0,
        }
    }
}

/// An object ready to integrate.
pub struct Prepared {
    /// The mesh with the UVs the bake uses.
    pub mesh: Mesh,
    /// Those UVs.
    pub uvs: Vec<Vec2>,
    /// True when the UVs came from unwrapping.
    pub unwrapped: bool,
    /// For an unwrapped mesh, the scene mesh's vertex each vertex copies;
    /// empty otherwise.
    pub source_vertex: Vec<u32>,
    /// What is wrong with UVs kept although they overlap or stretch.
    pub uv_warning: Option<String>,
    /// The texels.
    pub surfels: TexelSurfels,
    /// Transmitted irradiance per surfel, W/m² (before the colour split).
    pub irradiance: Vec<[f32; 3]>,
    /// The base colour per surfel (ones without a map).
    pub colour: Vec<[f32; 3]>,
    /// Empty texels and the texels they copy, for blurs and lookups.
    pub dilation: Vec<(u32, u32)>,
    settings: BakeSettings,
    seconds: f64,
}

/// Lays out `object` of `scene`, finds its texels and lights them.
pub fn prepare(
    scene: &Scene,
    object: &str,
    lighting: Lighting,
    settings: &BakeSettings,
    control: &Control,
) -> Result<Prepared, BakeError> {
    let start = Instant::now();
    let index = scene
        .objects
        .iter()
        .position(|o| o.mesh.name == object)
        .ok_or_else(|| BakeError::Input(format!("{}: no object named `{object}`", scene.source)))?;
    let original = &scene.objects[index].mesh;
    let report = analyse_uvs(original, None, settings.resolution);
    let keep = settings.keep_uvs && original.uvs.is_some();
    if settings.keep_uvs && !keep {
        return Err(BakeError::Input(format!(
            "{}: object `{object}`: has no UVs to bake into",
            scene.source
        )));
    }
    let unwrapped = !keep && (settings.force_unwrap || !report.usable());
    let uv_warning = report
        .problems()
        .filter(|_| keep && !report.usable())
        .map(|problems| format!("baked into its UVs as they are: {problems}"));
    if unwrapped && matches!(lighting, Lighting::Irradiance(_)) {
        return Err(BakeError::Input(format!(
            "{}: object `{object}`: an irradiance image needs the object's own UVs, but they are not usable ({})",
            scene.source,
            report.verdict()
        )));
    }
    let (mesh, source_vertex) = if unwrapped {
        crate::unwrap::unwrap_with_sources(original, settings.resolution, settings.padding)
            .map_err(|e| BakeError::Input(format!("{}: {e}", scene.source)))?
    } else {
        (original.clone(), Vec::new())
    };
    control.check()?;
    let uvs = mesh.uvs.clone().unwrap_or_default();
    let surfels = rasterize(&mesh, &uvs, settings.resolution);
    if surfels.is_empty() {
        return Err(BakeError::Input(format!(
            "{}: object `{object}`: covers no texel at {}²",
            scene.source, settings.resolution
        )));
    }
    let n = settings.resolution as f32;
    let texel_uv = |s: usize| {
        let t = surfels.texel[s];
        Vec2::new(
            ((t % settings.resolution) as f32 + 0.5) / n,
            ((t / settings.resolution) as f32 + 0.5) / n,
        )
    };
    let colour: Vec<[f32; 3]> = match &settings.base_colour {
        Some(map) => (0..surfels.len())
            .map(|s| map.sample(texel_uv(s)))
            .collect(),
        None => vec![[1.0; 3]; surfels.len()],
    };
    let irradiance = match &lighting {
        Lighting::Irradiance(image) => (0..surfels.len())
            .map(|s| image.sample(texel_uv(s)))
            .collect(),
        Lighting::SceneLights | Lighting::SceneLightsWith { .. } => {
            let environment = match &lighting {
                Lighting::SceneLightsWith { environment } => Some(environment),
                _ => None,
            };
            // Every object casts shadows; this one with the UVs it bakes into.
            let meshes: Vec<&Mesh> = scene
                .objects
                .iter()
                .enumerate()
                .map(|(i, o)| if i == index { &mesh } else { &o.mesh })
                .collect();
            let emitters: Vec<Emitter> = scene
                .lights
                .iter()
                .map(|light| {
                    let map = matches!(light.kind, LightKind::Environment { .. })
                        .then(|| environment.cloned())
                        .flatten();
                    Emitter::new(light, map)
                })
                .collect();
            transmitted_irradiance(
                Receivers {
                    mesh: index as u32,
                    position: &surfels.position,
                    normal: &surfels.normal,
                    triangle: &surfels.triangle,
                },
                &emitters,
                &RayScene::new(&meshes),
                &EntryTransmittance::new(settings.eta, settings.boundary),
                &settings.irradiance,
                control,
            )?
        }
    };
    let dilation = seam_aware_offsets(&mesh, &uvs, &surfels, texture_space::MAX_REACH);
    Ok(Prepared {
        mesh,
        uvs,
        unwrapped,
        source_vertex,
        uv_warning,
        surfels,
        irradiance,
        colour,
        dilation,
        settings: settings.clone(),
        seconds: start.elapsed().as_secs_f64(),
    })
}

/// The outcome of one integration.
#[derive(Clone, Debug)]
pub struct Integration {
    /// Radiant exitance per surfel, W/m² (after the colour split).
    pub exitance: Vec<[f32; 3]>,
    /// The method that ran, and why.
    pub choice: Choice,
    /// Seconds spent integrating (not preparing).
    pub seconds: f64,
    /// Sources the 3-D methods gathered from (texels or Turk points).
    pub sources: usize,
}

impl Prepared {
    /// Seconds spent preparing.
    pub fn seconds(&self) -> f64 {
        self.seconds
    }

    /// The irradiance per surfel with the colour applied before scattering.
    fn entering(&self) -> Vec<[f32; 3]> {
        let alpha = self.settings.colour_split.clamp(0.0, 1.0);
        self.irradiance
            .iter()
            .zip(&self.colour)
            .map(|(e, c)| [0, 1, 2].map(|k| e[k] * c[k].powf(alpha)))
            .collect()
    }

    /// The texels as sources of light.
    pub fn texel_sources(&self) -> Sources {
        let n = self.surfels.resolution as f32;
        let footprint = self
            .surfels
            .triangle
            .iter()
            .map(|&t| {
                uv_jacobian(&self.mesh, &self.uvs, t as usize)
                    .map_or([Vec3::ZERO; 2], |(du, dv)| {
                        [du.as_vec3() / n, dv.as_vec3() / n]
                    })
            })
            .collect();
        Sources {
            position: self.surfels.position.clone(),
            normal: self.surfels.normal.clone(),
            area: self.surfels.area.clone(),
            irradiance: self.entering(),
            footprint,
        }
    }

    /// Turk points as sources: `multiplier` points per disk of one mean
    /// free path, relaxed, each carrying the texels of its Voronoi cell.
    pub fn point_sources(
        &self,
        multiplier: f64,
        seed: u64,
        control: &Control,
    ) -> Result<Sources, BakeError> {
        let count = point_count(
            self.mesh.area(),
            self.settings.mean_free_path_mm,
            multiplier,
        );
        let (mut points, mut weights) = place_points(&self.mesh, count, seed);
        relax(&self.mesh, &mut points, &mut weights, 10);
        control.check()?;
        let spacing = (self.mesh.area() / points.position.len().max(1) as f64).sqrt() as f32;
        Ok(cluster(&self.texel_sources(), &points.position, spacing))
    }

    /// The irradiance entering (after the colour split) as a dilated N × N
    /// texture, row-major with y growing with v.
    pub fn entering_texture(&self) -> Vec<[f32; 3]> {
        let n = self.surfels.resolution as usize;
        let mut image = vec![[0.0f32; 3]; n * n];
        for (s, e) in self.entering().into_iter().enumerate() {
            image[self.surfels.texel[s] as usize] = e;
        }
        for &(to, from) in &self.dilation {
            image[to as usize] = image[from as usize];
        }
        image
    }

    /// Which method `method` means here (auto chooses).
    pub fn choose(&self, method: Method, kernel: &Kernel) -> Choice {
        if method != Method::Auto {
            return Choice {
                method,
                reason: "asked for".to_string(),
            };
        }
        let texels = self.surfels.len();
        let mean_area = self.surfels.total_area() / texels.max(1) as f64;
        choose(texels, mean_area, kernel.d_max as f64, kernel.transmits())
    }

    /// Integrates with `method` and applies the colour after scattering.
    pub fn integrate(
        &self,
        profile: &dyn Profile,
        kernel: &Kernel,
        method: Method,
        settings: &MethodSettings,
        control: &Control,
    ) -> Result<Integration, BakeError> {
        let choice = self.choose(method, kernel);
        let start = Instant::now();
        let targets = Targets {
            position: &self.surfels.position,
            normal: &self.surfels.normal,
        };
        let (mut exitance, sources) = match choice.method {
            Method::Auto | Method::Brute => {
                let sources = self.texel_sources();
                (
                    brute::integrate(kernel, &sources, targets, control)?,
                    sources.len(),
                )
            }
            Method::Octree => {
                // Turk points do not crowd, and their weight sums scatter by
                // several percent with their spacing: capping them would
                // darken flat ground to catch folds the texels catch.
                let sources =
                    self.point_sources(settings.point_multiplier, settings.seed, control)?;
                let m =
                    octree::integrate(kernel, &sources, targets, settings.octree_epsilon, control)?;
                (m, sources.len())
            }
            Method::Texture => {
                let fit = fit_gaussians(profile, settings.gaussians);
                let m = texture_space::integrate(
                    &fit.gaussians,
                    &self.surfels,
                    &self.entering(),
                    &self.dilation,
                    control,
                )?;
                (m, 0)
            }
            Method::Importance => {
                let probes = RayScene::new(&[&self.mesh]);
                let texture = self.entering_texture();
                let surface = importance::Surface {
                    mesh: &self.mesh,
                    uvs: &self.uvs,
                    probes: &probes,
                    irradiance: &texture,
                    resolution: self.surfels.resolution,
                };
                let m = importance::integrate(
                    kernel,
                    profile,
                    &surface,
                    &self.surfels.position,
                    &self.surfels.normal,
                    settings.samples,
                    settings.seed,
                    control,
                )?;
                (m, 0)
            }
        };
        let alpha = self.settings.colour_split.clamp(0.0, 1.0);
        for (m, c) in exitance.iter_mut().zip(&self.colour) {
            for k in 0..3 {
                m[k] *= c[k].powf(1.0 - alpha);
            }
        }
        Ok(Integration {
            exitance,
            choice,
            seconds: start.elapsed().as_secs_f64(),
            sources,
        })
    }
}
