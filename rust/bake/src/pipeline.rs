//! The stages of one object's bake below the plan: its layout (UVs and
//! texels, made while planning), its light (the irradiance entering every
//! texel), and the integration of the exitance by any [`Integrator`].

use crate::control::{Cancelled, Control};
use crate::error::{Error, InputError};
use crate::image::Image;
use crate::irradiance::emitters::Emitter;
use crate::irradiance::entry::EntryTransmittance;
use crate::irradiance::environment::EnvironmentMap;
use crate::irradiance::incidence::{IncidentHarmonics, incident_harmonics};
use crate::irradiance::{IrradianceSettings, Receivers, transmitted_irradiance};
use crate::mesh::Mesh;
use crate::rays::RayScene;
use crate::request::{BakeRequest, UvPolicy};
use crate::scattering::Scattering;
use crate::scene::{LightKind, Scene};
use crate::surface::dilation::{SeamAwareDilation, seam_aware_dilation};
use crate::surface::opposite::{Opposite, opposites};
use crate::surface::texels::{TexelSurfels, rasterize, uv_jacobian};
use crate::surface::turk::{place_points, relax};
use crate::surface::uv_analysis::analyse_uvs;
use crate::transport::Method;
use crate::transport::integrator::Integrator;
use crate::transport::local_slab::LocalSlab;
use crate::transport::sources::{OwnSource, Sources, Targets};
use crate::transport::texture_space;
use crate::walk::Enclosure;
use glam::{Vec2, Vec3};
use std::sync::{Arc, Mutex, OnceLock};
use std::time::Instant;

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

/// Where an object's texels are: the mesh with the UVs the bake uses and
/// the texels they cover. Made by the plan, shared by every stage after.
#[derive(Clone, Debug)]
pub struct Layout {
    /// The mesh with the UVs the bake uses.
    pub mesh: Mesh,
    /// Those UVs.
    pub uvs: Vec<Vec2>,
    /// True when the UVs came from unwrapping.
    pub unwrapped: bool,
    /// For an unwrapped mesh, the scene mesh's vertex each vertex copies;
    /// empty otherwise.
    pub source_vertex: Vec<u32>,
    /// The texels.
    pub surfels: TexelSurfels,
    /// The base colour per surfel relative to the nominal colour the
    /// profile is built for, C/m (crate::colour); empty: the same colour
    /// everywhere. Set by the plan.
    pub relative_colour: Vec<[f32; 3]>,
}

/// The layout's verdict on an object's own UVs, and what it did.
#[derive(Clone, Debug, PartialEq)]
pub struct UvDecision {
    /// The UV analysis in words.
    pub verdict: String,
    /// Whether the object is unwrapped.
    pub unwrap: bool,
    /// Why (or why not).
    pub reason: String,
    /// What is wrong with UVs kept although they overlap or stretch.
    pub warning: Option<String>,
}

impl Layout {
    /// Decides whether object `index` of `scene` keeps its UVs, unwraps if
    /// not, and finds the texels its layout covers.
    pub fn new(
        scene: &Scene,
        index: usize,
        request: &BakeRequest,
    ) -> Result<(Layout, UvDecision), Error> {
        let original = &scene.objects[index].mesh;
        let object_error = |message: String| {
            Error::Input(InputError {
                file: Some(scene.source.clone()),
                object: Some(original.name.clone()),
                field: None,
                message,
            })
        };
        let resolution = request.resolution;
        let report = analyse_uvs(original, None, resolution);
        let verdict = report.verdict();
        let has_uvs = original.uvs.is_some();
        let (unwrap, reason, warning) = match request.uvs {
            UvPolicy::Keep if !has_uvs => {
                return Err(object_error("has no UVs to bake into".into()));
            }
            UvPolicy::Keep => (
                false,
                "its own UVs, as asked".to_string(),
                report
                    .problems()
                    .filter(|_| !report.usable())
                    .map(|problems| format!("baked into its UVs as they are: {problems}")),
            ),
            UvPolicy::Unwrap => (true, "unwrapping was asked for".to_string(), None),
            UvPolicy::Auto if report.usable() => {
                (false, "its own UVs are usable".to_string(), None)
            }
            UvPolicy::Auto => (true, format!("its UVs are not usable ({verdict})"), None),
        };
        if unwrap && matches!(request.lighting, Lighting::Irradiance(_)) {
            return Err(object_error(format!(
                "an irradiance image needs the object's own UVs, but {reason}"
            )));
        }
        let (mesh, source_vertex) = if unwrap {
            crate::surface::unwrap::unwrap_with_sources(original, resolution, request.margin)
                .map_err(|e| Error::from(e).in_file(scene.source.clone()))?
        } else {
            (original.clone(), Vec::new())
        };
        let uvs = mesh.uvs.clone().unwrap_or_default();
        let surfels = rasterize(&mesh, &uvs, resolution);
        if surfels.is_empty() {
            return Err(object_error(format!("covers no texel at {resolution}²")));
        }
        let layout = Layout {
            mesh,
            uvs,
            unwrapped: unwrap,
            source_vertex,
            surfels,
            relative_colour: Vec::new(),
        };
        let decision = UvDecision {
            verdict,
            unwrap,
            reason,
            warning,
        };
        Ok((layout, decision))
    }

    /// The centre of surfel `s`'s texel in UV space.
    pub(crate) fn texel_uv(&self, s: usize) -> Vec2 {
        let n = self.surfels.resolution;
        let t = self.surfels.texel[s];
        Vec2::new(
            ((t % n) as f32 + 0.5) / n as f32,
            ((t / n) as f32 + 0.5) / n as f32,
        )
    }
}

/// An object ready to integrate: its layout and the light entering it.
pub struct Prepared {
    layout: Arc<Layout>,
    /// Transmitted irradiance per surfel, W/m² (before the colour split);
    /// empty when the bake needs no light.
    pub irradiance: Vec<[f32; 3]>,
    /// The base colour per surfel relative to the nominal colour the
    /// profile is built for (ones without a map).
    pub colour: Vec<[f32; 3]>,
    colour_split: f32,
    dilation: OnceLock<SeamAwareDilation>,
    /// The face behind each texel, found on first use.
    opposites: OnceLock<Vec<Option<Opposite>>>,
    seconds: f64,
    /// The lights and scene kept for splitting the light by incidence,
    /// when the material has an oblique kernel and scene lights light it.
    lights: Option<SceneLighting>,
    /// The light split by incidence, made on first use.
    incidence: OnceLock<Vec<IncidentHarmonics>>,
    /// The light entering raised where the surface within reach ends,
    /// found by the last profile method that integrated, for its
    /// scattering and settings.
    raised: Mutex<Option<Arc<Raised>>>,
}

/// How much the light at each surfel is raised where the surface within
/// the profile's reach ends ([`crate::transport::local_slab`]): by the
/// square root of the gain where it enters and again where it leaves, so
/// the pair weight stays symmetric (light's reciprocity) and under uniform
/// light a texel returns what the plane or the slab returns.
#[derive(Clone, Debug)]
pub struct Raised {
    /// The scattering and integrator it was found by ([`raise_key`]).
    key: String,
    /// Per surfel and channel, √gain, in [1, 2].
    pub halves: Vec<[f32; 3]>,
    /// Surfels raised by more than 1% in some channel.
    pub count: usize,
}

/// What tells one raised light from another on the same object: the
/// material with all its coefficients, the model and the reach, and the
/// integrator with its settings (each finds the gains with its own error,
/// which the error estimate measures).
fn raise_key(scattering: &Scattering, integrator: &dyn Integrator) -> String {
    format!(
        "{:?} {} {} {integrator:?}",
        scattering.material,
        scattering.model.name(),
        scattering.kernel.d_max.to_bits()
    )
}

impl Raised {
    /// The sums `exitance` (one per surfel) raised where the light leaves.
    pub fn leaving(&self, exitance: &mut [[f32; 3]]) {
        for (m, h) in exitance.iter_mut().zip(&self.halves) {
            *m = [0, 1, 2].map(|c| m[c] * h[c]);
        }
    }
}

/// What the irradiance was gathered from, kept for
/// [`Prepared::incidence`].
struct SceneLighting {
    mesh: u32,
    rays: RayScene,
    emitters: Vec<Emitter>,
    entry: EntryTransmittance,
    settings: IrradianceSettings,
}

/// The layout's fields read straight through a prepared object.
impl std::ops::Deref for Prepared {
    type Target = Layout;

    fn deref(&self) -> &Layout {
        &self.layout
    }
}

/// Lights object `index` of `scene` laid out as `layout`: the irradiance
/// entering each texel through the surface of `scattering`'s material (its
/// entry index and roughness, or its Stam top layer), by the request's lighting. `lit` false leaves the light out (outputs that need
/// none).
pub fn prepare(
    scene: &Scene,
    index: usize,
    layout: Arc<Layout>,
    request: &BakeRequest,
    scattering: &Scattering,
    lit: bool,
    control: &Control,
) -> Result<Prepared, Error> {
    let start = Instant::now();
    let count = layout.surfels.len();
    let colour: Vec<[f32; 3]> = if layout.relative_colour.len() == count {
        layout.relative_colour.clone()
    } else {
        vec![[1.0; 3]; count]
    };
    let mut lights = None;
    let irradiance = if !lit {
        Vec::new()
    } else {
        match &request.lighting {
            Lighting::Irradiance(image) => (0..count)
                .map(|s| image.sample(layout.texel_uv(s)))
                .collect(),
            Lighting::SceneLights | Lighting::SceneLightsWith { .. } => {
                let environment = match &request.lighting {
                    Lighting::SceneLightsWith { environment } => Some(environment),
                    _ => None,
                };
                // Every object casts shadows; this one with the UVs it bakes into.
                let meshes: Vec<&Mesh> = scene
                    .objects
                    .iter()
                    .enumerate()
                    .map(|(i, o)| if i == index { &layout.mesh } else { &o.mesh })
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
                let surfels = &layout.surfels;
                let kept = SceneLighting {
                    mesh: index as u32,
                    rays: RayScene::new(&meshes),
                    emitters,
                    entry: EntryTransmittance::of_surface(&scattering.surface),
                    settings: IrradianceSettings {
                        samples: request.light_samples,
                        shadows: true,
                    },
                };
                let irradiance = transmitted_irradiance(
                    Receivers {
                        mesh: kept.mesh,
                        position: &surfels.position,
                        normal: &surfels.normal,
                        triangle: &surfels.triangle,
                    },
                    &kept.emitters,
                    &kept.rays,
                    &kept.entry,
                    &kept.settings,
                    control,
                )?;
                if scattering.oblique.is_some() {
                    lights = Some(kept);
                }
                irradiance
            }
        }
    };
    Ok(Prepared {
        layout,
        irradiance,
        colour,
        colour_split: request.colour_split.clamp(0.0, 1.0),
        dilation: OnceLock::new(),
        opposites: OnceLock::new(),
        seconds: start.elapsed().as_secs_f64(),
        lights,
        incidence: OnceLock::new(),
        raised: Mutex::new(None),
    })
}

/// The outcome of one integration.
#[derive(Clone, Debug)]
pub struct Integration {
    /// Radiant exitance per surfel, W/m² (after the colour split).
    pub exitance: Vec<[f32; 3]>,
    /// Seconds spent integrating (not preparing).
    pub seconds: f64,
    /// Sources the 3-D methods gathered from (texels or Turk points).
    pub sources: usize,
    /// The walk's noise and dropped weight, when the walk integrated.
    pub walk: Option<crate::transport::walk::WalkNoise>,
    /// The light entering as raised where the surface within the
    /// profile's reach ends ([`crate::transport::local_slab`]), when it was.
    pub raised: Option<Arc<Raised>>,
    /// Per channel, the share of the raised light kept where it would have
    /// left more power than entered; `None` where all of it was.
    pub kept: Option<[f32; 3]>,
}

impl Prepared {
    /// Seconds spent lighting.
    pub fn seconds(&self) -> f64 {
        self.seconds
    }

    /// The layout this object was prepared on.
    pub fn layout(&self) -> &Arc<Layout> {
        &self.layout
    }

    /// The texels as targets of the integration.
    pub fn targets(&self) -> Targets<'_> {
        Targets {
            position: &self.surfels.position,
            normal: &self.surfels.normal,
            own: OwnSource::None,
            piece: &self.surfels.piece,
        }
    }

    /// Empty texels near a chart and the covered texels they copy, as far
    /// as texture-space blurs reach, with which lie beyond open edges (made
    /// on first use).
    pub fn dilation(&self) -> &SeamAwareDilation {
        self.dilation.get_or_init(|| {
            seam_aware_dilation(
                &self.mesh,
                &self.uvs,
                &self.surfels,
                texture_space::MAX_REACH,
            )
        })
    }

    /// The face behind each surfel, where the object ends along its
    /// inward normal (found on first use).
    pub fn opposites(&self) -> &[Option<Opposite>] {
        self.opposites
            .get_or_init(|| opposites(&Enclosure::new(&self.mesh, &self.uvs), &self.surfels))
    }

    /// True when some texel has a face behind it nearer than `reach` mm.
    pub fn has_thin_parts(&self, reach: f32) -> bool {
        self.opposites()
            .iter()
            .flatten()
            .any(|o| o.thickness <= reach)
    }

    /// Scales `exitance` down per channel where it leaves more power than
    /// enters, and says by how much: raising the light where the surface
    /// ends holds a plane's total under uniform light, but under light far
    /// from uniform on a part much smaller than the reach it may not.
    fn make_no_energy(&self, exitance: &mut [[f32; 3]]) -> Option<[f32; 3]> {
        let area = &self.surfels.area;
        let power = |values: &[[f32; 3]], c: usize| -> f64 {
            values
                .iter()
                .zip(area)
                .map(|(v, &a)| f64::from(v[c]) * f64::from(a))
                .sum()
        };
        let entering = self.entering();
        let kept = [0, 1, 2].map(|c| {
            let (out, into) = (power(exitance, c), power(&entering, c));
            if out > into && out > 0.0 {
                (into / out) as f32
            } else {
                1.0
            }
        });
        if kept == [1.0; 3] {
            return None;
        }
        for m in exitance.iter_mut() {
            *m = [0, 1, 2].map(|c| m[c] * kept[c]);
        }
        Some(kept)
    }

    /// How much the light entering each surfel is raised where the surface
    /// within the profile's reach ends ([`LocalSlab::gains`]): found by
    /// `integrator` under a unit light, once per scattering and
    /// integrator.
    fn raise(
        &self,
        slab: &LocalSlab,
        integrator: &dyn Integrator,
        scattering: &Scattering,
        control: &Control,
    ) -> Result<Arc<Raised>, Error> {
        let key = raise_key(scattering, integrator);
        if let Some(raised) = self
            .raised
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .as_ref()
            .filter(|r| r.key == key)
        {
            return Ok(Arc::clone(raised));
        }
        let uniform = integrator.integrate(&self.uniformly_lit(), scattering, control)?;
        let summed_across = integrator.method() != Method::Texture;
        let (gains, count) = slab.gains(self.opposites(), &uniform.exitance, summed_across);
        let raised = Arc::new(Raised {
            key,
            halves: gains.iter().map(|g| g.map(f32::sqrt)).collect(),
            count,
        });
        *self.raised.lock().unwrap_or_else(|e| e.into_inner()) = Some(Arc::clone(&raised));
        Ok(raised)
    }

    /// The same object with the light entering each surfel scaled by
    /// `gains` (one per surfel), and no lights to split by incidence.
    pub fn raised_by(&self, gains: &[[f32; 3]]) -> Prepared {
        let irradiance = self
            .irradiance
            .iter()
            .zip(gains)
            .map(|(e, g)| [0, 1, 2].map(|c| e[c] * g[c]))
            .collect();
        self.relit(irradiance, self.colour.clone())
    }

    /// The same object under a unit irradiance everywhere, colour 1 and no
    /// lights to split by incidence: integrated, it gives each texel its
    /// sum of the kernel's weights over the surface, which the corrected
    /// model sets beside a plane's ([`crate::transport::local_slab`]).
    pub fn uniformly_lit(&self) -> Prepared {
        let n = self.surfels.len();
        self.relit(vec![[1.0; 3]; n], vec![[1.0; 3]; n])
    }

    /// The same layout, faces behind and dilation under `irradiance` and
    /// `colour` (one per surfel), with no lights to split by incidence.
    fn relit(&self, irradiance: Vec<[f32; 3]>, colour: Vec<[f32; 3]>) -> Prepared {
        let opposites = OnceLock::new();
        let _ = opposites.set(self.opposites().to_vec());
        Prepared {
            layout: Arc::clone(&self.layout),
            irradiance,
            colour,
            colour_split: self.colour_split,
            dilation: self.dilation.clone(),
            opposites,
            seconds: 0.0,
            lights: None,
            incidence: OnceLock::new(),
            raised: Mutex::new(None),
        }
    }

    /// The irradiance per surfel with the colour applied before scattering.
    pub fn entering(&self) -> Vec<[f32; 3]> {
        let alpha = self.colour_split;
        self.irradiance
            .iter()
            .zip(&self.colour)
            .map(|(e, c)| [0, 1, 2].map(|k| e[k] * c[k].powf(alpha)))
            .collect()
    }

    /// Drops what only the scattering reads: the scene's lights and rays
    /// kept for splitting the light by incidence, and the split. After
    /// this, [`Self::incidence`] gives `None`.
    pub fn release_lighting(&mut self) {
        self.lights = None;
        self.incidence = OnceLock::new();
    }

    /// True when the light can be split by incidence for an oblique
    /// kernel ([`Self::incidence`] gives it).
    pub fn splits_by_incidence(&self) -> bool {
        self.lights.is_some() && self.irradiance.len() == self.surfels.len()
    }

    /// The light entering each texel split by incidence (after the colour
    /// split's first part, as [`Self::entering`]), for an oblique kernel;
    /// `None` when the material has none or the light is an irradiance
    /// image (no direction to split by). Gathered on first use, with
    /// the same samples as the irradiance.
    pub fn incidence(&self, control: &Control) -> Result<Option<&[IncidentHarmonics]>, Cancelled> {
        let Some(lights) = self.lights.as_ref().filter(|_| self.splits_by_incidence()) else {
            return Ok(None);
        };
        if self.incidence.get().is_none() {
            let surfels = &self.surfels;
            let mut split = incident_harmonics(
                Receivers {
                    mesh: lights.mesh,
                    position: &surfels.position,
                    normal: &surfels.normal,
                    triangle: &surfels.triangle,
                },
                &lights.emitters,
                &lights.rays,
                &lights.entry,
                &lights.settings,
                control,
            )?;
            let alpha = self.colour_split;
            for (h, colour) in split.iter_mut().zip(&self.colour) {
                let scale = colour.map(|c| c.powf(alpha));
                for v in h.iter_mut().flatten() {
                    for k in 0..3 {
                        v[k] *= scale[k];
                    }
                }
            }
            let _ = self.incidence.set(split);
        }
        Ok(self.incidence.get().map(Vec::as_slice))
    }

    /// The texels as sources of light.
    pub fn texel_sources(&self) -> Sources {
        let n = self.surfels.resolution as f32;
        // Each texel's covered parallelogram, from texel units onto its
        // triangle's plane, scaled to the area it stands for (which adds
        // the shares of every triangle in the texel, at their own scale):
        // a texel's own light then returns exactly R_total where the
        // profile is sharper than the texel, neither more nor less.
        let footprint = self
            .surfels
            .triangle
            .iter()
            .zip(&self.surfels.extent)
            .zip(&self.surfels.area)
            .map(|((&t, extent), &area)| {
                let Some((du, dv)) = uv_jacobian(&self.mesh, &self.uvs, t as usize) else {
                    return [Vec3::ZERO; 2];
                };
                let (du, dv) = (du.as_vec3() / n, dv.as_vec3() / n);
                let edges = extent.map(|e| du * e.x + dv * e.y);
                let spanned = edges[0].cross(edges[1]).length();
                if spanned > 0.0 && area > 0.0 {
                    edges.map(|e| e * (area / spanned).sqrt())
                } else {
                    [Vec3::ZERO; 2]
                }
            })
            .collect();
        Sources {
            position: self.surfels.position.clone(),
            normal: self.surfels.normal.clone(),
            area: self.surfels.area.clone(),
            irradiance: self.entering(),
            footprint,
            piece: self.surfels.piece.clone(),
        }
    }

    /// `count` relaxed Turk points as sources, each carrying the texels of
    /// its Voronoi cell.
    pub fn point_sources(
        &self,
        count: usize,
        seed: u64,
        control: &Control,
    ) -> Result<Sources, Error> {
        let (mut points, mut weights) = place_points(&self.mesh, count, seed);
        relax(&self.mesh, &mut points, &mut weights, 10);
        control.check()?;
        let spacing = (self.mesh.area() / points.position.len().max(1) as f64).sqrt() as f32;
        Ok(crate::transport::clusters::cluster(
            &self.texel_sources(),
            &points.position,
            spacing,
        ))
    }

    /// The irradiance entering (after the colour split) as a dilated N × N
    /// texture, row-major with y growing with v.
    pub fn entering_texture(&self) -> Vec<[f32; 3]> {
        let n = self.surfels.resolution as usize;
        let mut image = vec![[0.0f32; 3]; n * n];
        for (s, e) in self.entering().into_iter().enumerate() {
            image[self.surfels.texel[s] as usize] = e;
        }
        for &(to, from) in &self.dilation().offsets {
            image[to as usize] = image[from as usize];
        }
        image
    }

    /// For each texel of the N × N layout, row-major with y growing with
    /// v, the surfel it holds or copies (the same dilation as
    /// [`Self::entering_texture`]); `u32::MAX` where none.
    pub fn surfel_texture(&self) -> Vec<u32> {
        let n = self.surfels.resolution as usize;
        let mut image = vec![u32::MAX; n * n];
        for (s, &t) in self.surfels.texel.iter().enumerate() {
            image[t as usize] = s as u32;
        }
        for &(to, from) in &self.dilation().offsets {
            image[to as usize] = image[from as usize];
        }
        image
    }

    /// Exitance `m` at texel `i` with the colour split's second part
    /// applied: C^(1 − α).
    pub fn after_scattering(&self, i: usize, m: [f32; 3]) -> [f32; 3] {
        let beta = 1.0 - self.colour_split;
        let c = self.colour[i];
        [0, 1, 2].map(|k| m[k] * c[k].powf(beta))
    }

    /// Integrates with `integrator` under `scattering` and applies the
    /// colour after scattering.
    pub fn integrate(
        &self,
        scattering: &Scattering,
        integrator: &dyn Integrator,
        control: &Control,
    ) -> Result<Integration, Error> {
        if self.irradiance.len() != self.surfels.len() {
            return Err(Error::input(
                "the object was prepared without light; nothing to scatter",
            ));
        }
        let start = Instant::now();
        // Every profile method bakes the corrected model; the walk is light.
        let method = integrator.method();
        let slab = scattering.local_slab().filter(|_| method != Method::Walk);
        let summed_across = method != Method::Texture;
        // The light entering is raised where the surface within reach ends
        // (not for an oblique kernel, which reads the light split by
        // incidence).
        let raised = match slab.filter(|_| scattering.oblique.is_none()) {
            Some(slab) => Some(self.raise(slab, integrator, scattering, control)?),
            None => None,
        };
        let mut integrated = match &raised {
            Some(raised) => {
                integrator.integrate(&self.raised_by(&raised.halves), scattering, control)?
            }
            None => integrator.integrate(self, scattering, control)?,
        };
        if let Some(slab) = slab {
            integrated.exitance =
                slab.correct_all(self.opposites(), &integrated.exitance, summed_across);
        }
        let mut kept = None;
        if let Some(raised) = &raised {
            raised.leaving(&mut integrated.exitance);
            kept = self.make_no_energy(&mut integrated.exitance);
        }
        for (i, m) in integrated.exitance.iter_mut().enumerate() {
            *m = self.after_scattering(i, *m);
        }
        Ok(Integration {
            exitance: integrated.exitance,
            seconds: start.elapsed().as_secs_f64(),
            sources: integrated.sources,
            walk: integrated.walk,
            raised,
            kept,
        })
    }
}
