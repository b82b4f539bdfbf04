//! An object ready to integrate: its layout and the light entering it, as
//! the integrators read them (lit by [`crate::pipeline::prepare`]).

use crate::control::{Cancelled, Control};
use crate::error::Error;
use crate::irradiance::emitters::Emitter;
use crate::irradiance::entry::EntryTransmittance;
use crate::irradiance::incidence::{IncidentHarmonics, incident_harmonics};
use crate::irradiance::{IrradianceSettings, Receivers};
use crate::layout::Layout;
use crate::rays::RayScene;
use crate::surface::curvature::{mean_curvature, mean_curvatures};
use crate::surface::dilation::{MAX_REACH, SeamAwareDilation, seam_aware_dilation};
use crate::surface::opposite::{Opposite, opposites};
use crate::surface::turk::{place_points, relax};
use crate::transport::octree::shape::TreeShape;
use crate::transport::rim_light::RimSights;
use crate::transport::sources::{OwnSource, Sources, Targets};
use crate::walk::Enclosure;
use glam::Vec3;
use std::borrow::Cow;
use std::sync::{Arc, Mutex, OnceLock};

/// An object ready to integrate: its layout and the light entering it.
pub struct Prepared {
    pub(crate) layout: Arc<Layout>,
    /// Transmitted irradiance per surfel, W/m² (before the colour split);
    /// empty when the bake needs no light.
    pub irradiance: Vec<[f32; 3]>,
    /// The base colour per surfel relative to the nominal colour the
    /// profile is built for (ones without a map).
    pub colour: Arc<[[f32; 3]]>,
    pub(crate) colour_split: f32,
    pub(crate) dilation: OnceLock<SeamAwareDilation>,
    /// The face behind each texel within the reach last sought (mm), found
    /// on first use and shared with the same object under other light
    /// ([`Prepared::relit`]).
    pub(crate) opposites: Arc<Mutex<Option<Behind>>>,
    pub(crate) seconds: f64,
    /// The lights and scene kept for splitting the light by incidence,
    /// when the material has an oblique kernel and scene lights light it.
    pub(crate) lights: Option<SceneLighting>,
    /// The light split by incidence, made on first use.
    pub(crate) incidence: OnceLock<Vec<IncidentHarmonics>>,
    /// The mean curvature at every surfel at the scale it was last asked
    /// for (mm), shared with the same object under other light.
    pub(crate) curvature: Arc<Mutex<Option<Curvature>>>,
    /// The light entering raised where the surface within reach ends,
    /// found by the last profile method that integrated, for its
    /// scattering and settings.
    pub(crate) raised: Mutex<Option<Arc<Raised>>>,
    /// The octree's shape over the texels, made on first use and shared
    /// with the same object under other light: it depends on where the
    /// texels lie, not on their light.
    pub(crate) texel_tree: Arc<OnceLock<TreeShape>>,
}

/// The mean curvature at every surfel (1/mm) and the scale it was seen at
/// (mm).
pub(crate) type Curvature = (f32, Arc<Vec<f32>>);

/// The face behind every surfel ([`opposites`]) and the reach (mm) it was
/// sought within.
pub(crate) type Behind = (f32, Arc<Vec<Option<Opposite>>>);

/// How much the light at each surfel is raised where the surface within
/// the profile's reach ends ([`crate::transport::local_slab`]): by the
/// square root of the gain where it enters and again where it leaves, so
/// the pair weight stays symmetric (light's reciprocity) and under uniform
/// light a texel returns what the plane or the slab returns.
#[derive(Clone, Debug)]
pub struct Raised {
    /// The scattering and integrator it was found by
    /// ([`crate::pipeline`]'s key).
    pub(crate) key: String,
    /// The scattering alone it was found for, which the ball's gains
    /// depend on.
    pub(crate) scattering: String,
    /// Per surfel and channel, √gain, in [1, 2].
    pub halves: Vec<[f32; 3]>,
    /// Per surfel and channel, the part of the gain a ball as curved as
    /// the surface there asked for ([`crate::transport::ball_gain`]), in
    /// [1, 4].
    pub ball: Arc<Vec<[f32; 3]>>,
    /// Surfels raised by more than 1% in some channel.
    pub count: usize,
    /// Surfels on parts thin enough in some channel to gather with their
    /// own slab's profile there ([`crate::transport::slab_profiles`]).
    pub by_slab_profile: usize,
    /// For each of those surfels, in order, where the light its slab
    /// would carry past the part's rim comes in through the rim
    /// ([`crate::transport::rim_light`]).
    pub rim: RimSights,
    /// Texels apart, along u and along v, at which the sums under a unit
    /// light were taken and fitted between; 1 where they were summed at
    /// every texel.
    pub stride: u32,
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
pub(crate) struct SceneLighting {
    pub(crate) mesh: u32,
    pub(crate) rays: RayScene,
    pub(crate) emitters: Vec<Emitter>,
    pub(crate) entry: EntryTransmittance,
    pub(crate) settings: IrradianceSettings,
}

/// The layout's fields read straight through a prepared object.
impl std::ops::Deref for Prepared {
    type Target = Layout;

    fn deref(&self) -> &Layout {
        &self.layout
    }
}

/// Some texels of a prepared object as targets ([`Prepared::listed`]).
pub struct Listed<'a> {
    position: Vec<Vec3>,
    normal: Vec<Vec3>,
    piece: Vec<u32>,
    part: Vec<u32>,
    listed: &'a [usize],
}

impl Listed<'_> {
    /// The targets, in the order listed.
    pub fn targets(&self) -> Targets<'_> {
        Targets {
            position: &self.position,
            normal: &self.normal,
            own: OwnSource::Listed(self.listed),
            piece: &self.piece,
            part: &self.part,
        }
    }
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
            part: &self.surfels.part,
        }
    }

    /// The texels `listed` alone as targets of a gather, each its own
    /// source (its light is its own texel's).
    pub fn listed<'a>(&self, listed: &'a [usize]) -> Listed<'a> {
        fn copy<T: Copy>(list: &[T], listed: &[usize]) -> Vec<T> {
            listed.iter().map(|&i| list[i]).collect()
        }
        let surfels = &self.surfels;
        Listed {
            position: copy(&surfels.position, listed),
            normal: copy(&surfels.normal, listed),
            // No pieces: every target gathers from every piece.
            piece: if surfels.piece.is_empty() {
                Vec::new()
            } else {
                copy(&surfels.piece, listed)
            },
            part: if surfels.part.is_empty() {
                Vec::new()
            } else {
                copy(&surfels.part, listed)
            },
            listed,
        }
    }

    /// Empty texels near a chart and the covered texels they copy, as far
    /// as texture-space blurs reach, with which lie beyond open edges (made
    /// on first use).
    pub fn dilation(&self) -> &SeamAwareDilation {
        self.dilation
            .get_or_init(|| seam_aware_dilation(&self.mesh, &self.uvs, &self.surfels, MAX_REACH))
    }

    /// The face behind each surfel, where the object ends along its
    /// inward normal within `reach` mm (found on first use, and again
    /// only for a longer reach). Faces farther than `reach` found for a
    /// longer reach asked before stay listed: a reader weighs a thickness
    /// only against slabs that end at its own reach.
    pub fn opposites(&self, reach: f32) -> Arc<Vec<Option<Opposite>>> {
        let mut kept = self.opposites.lock().unwrap_or_else(|e| e.into_inner());
        if let Some((within, found)) = kept.as_ref()
            && *within >= reach
        {
            return Arc::clone(found);
        }
        let enclosure = Enclosure::new(&self.mesh, &self.uvs);
        let found = Arc::new(opposites(&enclosure, &self.surfels, reach));
        *kept = Some((reach, Arc::clone(&found)));
        found
    }

    /// The mean curvature at every surfel, 1/mm, seen at `scale` mm
    /// ([`mean_curvature`]), found once for the last scale asked or kept
    /// by [`Self::mean_curvatures`].
    pub fn mean_curvature(&self, scale: f32) -> Arc<Vec<f32>> {
        let mut kept = self.curvature.lock().unwrap_or_else(|e| e.into_inner());
        if let Some((at, curvature)) = kept.as_ref()
            && *at == scale
        {
            return Arc::clone(curvature);
        }
        let curvature = Arc::new(mean_curvature(&self.surfels, scale));
        *kept = Some((scale, Arc::clone(&curvature)));
        curvature
    }

    /// The mean curvature at every surfel, 1/mm, seen at each of `scales`
    /// mm, found together ([`mean_curvatures`]). The longest scale's is
    /// kept for [`Self::mean_curvature`]: it is the one thin parts read,
    /// the longest half-light radius (a second pass over every texel at
    /// 4096², 2.7 s on the head).
    pub fn mean_curvatures(&self, scales: [f32; 3]) -> Vec<[f32; 3]> {
        let found = mean_curvatures(&self.surfels, scales);
        let longest = (0..3).fold(0, |l, c| if scales[c] > scales[l] { c } else { l });
        let kept = found.iter().map(|h| h[longest]).collect();
        *self.curvature.lock().unwrap_or_else(|e| e.into_inner()) =
            Some((scales[longest], Arc::new(kept)));
        found
    }

    /// True when some texel has a face behind it nearer than `reach` mm.
    pub fn has_thin_parts(&self, reach: f32) -> bool {
        self.opposites(reach)
            .iter()
            .flatten()
            .any(|o| o.thickness <= reach)
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
        self.relit(irradiance, Arc::clone(&self.colour))
    }

    /// The same object under a unit irradiance everywhere, colour 1 and no
    /// lights to split by incidence: integrated, it gives each texel its
    /// sum of the kernel's weights over the surface, which the corrected
    /// model sets beside a plane's ([`crate::transport::local_slab`]).
    pub fn uniformly_lit(&self) -> Prepared {
        let n = self.surfels.len();
        self.relit(vec![[1.0; 3]; n], vec![[1.0; 3]; n].into())
    }

    /// The same layout, faces behind and dilation under `irradiance` and
    /// `colour` (one per surfel), with no lights to split by incidence.
    fn relit(&self, irradiance: Vec<[f32; 3]>, colour: Arc<[[f32; 3]]>) -> Prepared {
        Prepared {
            layout: Arc::clone(&self.layout),
            irradiance,
            colour,
            colour_split: self.colour_split,
            dilation: self.dilation.clone(),
            opposites: Arc::clone(&self.opposites),
            seconds: 0.0,
            lights: None,
            incidence: OnceLock::new(),
            curvature: Arc::clone(&self.curvature),
            raised: Mutex::new(None),
            texel_tree: Arc::clone(&self.texel_tree),
        }
    }

    /// The irradiance per surfel with the colour applied before scattering.
    pub fn entering(&self) -> Vec<[f32; 3]> {
        (0..self.irradiance.len())
            .map(|s| self.entering_at(s))
            .collect()
    }

    /// [`Self::entering`] at surfel `s` alone, for a reader of a few
    /// surfels (the error estimate's) that need not hold a whole map.
    #[inline]
    pub fn entering_at(&self, s: usize) -> [f32; 3] {
        let (e, c) = (self.irradiance[s], self.colour[s]);
        // A colour of 1 (no colour map) leaves the light as it is, without
        // a power per channel.
        [0, 1, 2].map(|k| {
            if c[k] == 1.0 {
                e[k]
            } else {
                e[k] * c[k].powf(self.colour_split)
            }
        })
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
            for (h, colour) in split.iter_mut().zip(self.colour.iter()) {
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
    pub fn texel_sources(&self) -> Sources<'_> {
        Sources {
            position: Cow::Borrowed(&self.surfels.position),
            normal: Cow::Borrowed(&self.surfels.normal),
            area: Cow::Borrowed(&self.surfels.area),
            irradiance: self.entering(),
            footprint: Cow::Borrowed(self.texel_footprints()),
            piece: Cow::Borrowed(&self.surfels.piece),
            part: Cow::Borrowed(&self.surfels.part),
        }
    }

    /// The octree's shape over the texels ([`Self::texel_sources`]).
    pub(crate) fn texel_tree(&self) -> &TreeShape {
        self.texel_tree
            .get_or_init(|| TreeShape::new(&self.texel_sources()))
    }

    /// `count` relaxed Turk points as sources, each carrying the texels of
    /// its Voronoi cell.
    pub fn point_sources(
        &self,
        count: usize,
        seed: u64,
        control: &Control,
    ) -> Result<Sources<'static>, Error> {
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
}
