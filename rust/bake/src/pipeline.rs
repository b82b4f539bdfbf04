//! One object's bake below the plan: its light (the irradiance entering every
//! texel, [`prepare`]) and the integration of the exitance by any
//! [`Integrator`], with the light raised where the surface within reach ends
//! or bulges.

use crate::control::Control;
use crate::error::Error;
use crate::fitted_map::{Carrier, MapFit, first_step, fitted_map, probe_count};
use crate::irradiance::bounce::interreflected;
use crate::irradiance::emitters::Emitter;
use crate::irradiance::entry::EntryTransmittance;
use crate::irradiance::{IrradianceSettings, Receivers, transmitted_irradiance};
use crate::layout::Layout;
use crate::mesh::Mesh;
use crate::prepared::{Prepared, Raised, SceneLighting};
use crate::rays::RayScene;
use crate::request::{BakeRequest, Lighting};
use crate::scattering::Scattering;
use crate::scene::{LightKind, Scene};
use crate::surface::opposite::Opposite;
use crate::surface::texels::TexelSurfels;
use crate::transport::integrator::{Integrated, Integrator, Summer};
use crate::transport::local_slab::{LocalSlab, MAX_GAIN, RAISED};
use crate::transport::rim_light::RimSights;
use crate::transport::slab_profiles::thin_tolerance;
use crate::transport::verify::pick;
use crate::walk::Boundary;
use sssbake_profile::material::Material;
use std::collections::HashMap;
use std::sync::{Arc, Mutex, OnceLock};
use std::time::Instant;

/// What tells one raised light from another on the same object: the
/// material with all its coefficients, the model and the reach, and the
/// integrator with its settings (each finds the gains with its own error,
/// which the error estimate measures).
fn raise_key(scattering: &Scattering, integrator: &dyn Integrator) -> String {
    format!("{} {integrator:?}", scattering_key(scattering))
}

/// What tells one scattering from another on the same object: the
/// material with all its coefficients, the model and the reach.
fn scattering_key(scattering: &Scattering) -> String {
    format!(
        "{:?} {} {}",
        scattering.material,
        scattering.model.name(),
        scattering.kernel.d_max.to_bits()
    )
}

/// The most the gains from the fitted sums may miss those from the sums
/// themselves (relative RMS over the probed texels); above it the stride
/// halves. The head in its own skin at 1024² misses by 0.97% at 4 texels
/// apart and its map moves by 0.08%; the ear at 256² misses by 1.6% at 4
/// and 0.8% at 2, and is baked at 2.
const FIT_TOLERANCE: f64 = 0.01;

/// The shares of an integration's progress ([`Control::part`]) that the
/// sums under a unit light (with the gains they give) fill, and that end
/// with the map; the thin parts' own map fills the rest. From where the
/// time went on the head in skin1 at 4096²: about 35 s, 25 s and 10 s.
const RAISING_SHARE: f64 = 0.5;
const MAP_END: f64 = 0.85;

/// The sums under a unit light summed directly at some texels, and at
/// the texels behind them ([`Prepared::probed_sums`]).
struct Probed {
    probes: Vec<usize>,
    /// Per probed texel, the texel behind it within reach, if any.
    behind: Vec<Option<usize>>,
    summed: HashMap<usize, [f32; 3]>,
}

impl Probed {
    /// How far the gains from `fitted` sums under a unit light miss those
    /// from the sums themselves at the probed texels: the relative RMS of
    /// their ratio's departure from 1.
    fn gains_missed(
        &self,
        slab: &LocalSlab,
        opposites: &[Option<Opposite>],
        fitted: &[[f32; 3]],
        across: bool,
    ) -> f64 {
        let (mut squares, mut count) = (0.0f64, 0usize);
        for (&i, behind) in self.probes.iter().zip(&self.behind) {
            let (shares, _) = slab.shares_at(opposites[i]);
            let j = behind.unwrap_or(i);
            let (Some(&here), Some(&there)) = (self.summed.get(&i), self.summed.get(&j)) else {
                continue;
            };
            let exact = slab.gain(&shares, (here, there), across);
            let got = slab.gain(&shares, (fitted[i], fitted[j]), across);
            for c in 0..3 {
                squares += (got[c] / exact[c] - 1.0).powi(2);
                count += 1;
            }
        }
        (squares / count.max(1) as f64).sqrt()
    }
}

/// The most texels apart the sums under a unit light are taken: the
/// head's map in its own skin at 1024² moved by 0.08% (relative RMSE; the
/// 99.9th percentile 0.3% of the map's peak) from its sums at every texel
/// at 4 apart; in skin1 at 2048² by 0.01% from 4 apart at 6.
const MOST_UNIFORM_STRIDE: u32 = 8;

/// Every how many texels the sums under a unit light are taken: twice the
/// radius holding half the profile's light in its narrowest channel, in
/// texels, so the fit between them follows how the sums fall toward a
/// rim; 1 (every texel) for a profile about a texel wide.
pub fn uniform_stride(scattering: &Scattering, surfels: &TexelSurfels) -> u32 {
    first_step(half_light_texels(scattering, surfels)).min(MOST_UNIFORM_STRIDE)
}

/// The radius holding half the profile's light in its narrowest channel,
/// in mean texels; `None` for a profile or a layout without one.
pub fn half_light_texels(scattering: &Scattering, surfels: &TexelSurfels) -> Option<f64> {
    let texel = surfels.mean_side();
    let half = scattering
        .profile
        .d_max(0.5)
        .into_iter()
        .filter(|r| *r > 0.0)
        .fold(f64::INFINITY, f64::min);
    (texel > 0.0 && half.is_finite()).then(|| half / texel)
}

/// Lights object `index` of `scene` laid out as `layout`: the irradiance
/// entering each texel through the surface of `scattering`'s material (its
/// entry index and roughness, or its Stam top layer), by the request's
/// lighting. `lit` false leaves the light out (outputs that need none).
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
                let mut irradiance = transmitted_irradiance(
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
                let leaving = leaving_share(scattering, &colour);
                let bounced = interreflected(
                    &layout,
                    kept.mesh,
                    &kept.rays,
                    &kept.entry,
                    &irradiance,
                    &leaving,
                    request.bounces,
                    control,
                )?;
                for (e, b) in irradiance.iter_mut().zip(&bounced) {
                    *e = [0, 1, 2].map(|c| e[c] + b[c]);
                }
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
        colour: colour.into(),
        colour_split: request.colour_split.clamp(0.0, 1.0),
        dilation: OnceLock::new(),
        opposites: Default::default(),
        seconds: start.elapsed().as_secs_f64(),
        lights,
        incidence: OnceLock::new(),
        curvature: Default::default(),
        raised: Mutex::new(None),
        texel_tree: Default::default(),
    })
}

/// Per surfel, how much of the light entering it leaves as diffuse light
/// towards the rest of the scene: the material's diffuse albedo
/// ([`Scattering::diffuse_albedo`]) times the base colour there.
fn leaving_share(scattering: &Scattering, colour: &[[f32; 3]]) -> Vec<[f32; 3]> {
    let share = scattering.diffuse_albedo().map(|a| a as f32);
    colour
        .iter()
        .map(|k| [0, 1, 2].map(|c| (share[c] * k[c].max(0.0)).min(1.0)))
        .collect()
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
    /// How the map was carried from a lattice of texels, when the
    /// integrator sums at chosen texels.
    pub fit: Option<MapFit>,
    /// How the thin parts' map by their own slab's profile was carried
    /// from a lattice of their texels, where it was.
    pub thin_fit: Option<MapFit>,
    /// The light entering as raised where the surface within the
    /// profile's reach ends ([`crate::transport::local_slab`]), when it was.
    pub raised: Option<Arc<Raised>>,
    /// Per channel, the share of the raised light kept where it would have
    /// left more power than entered; `None` where all of it was.
    pub kept: Option<[f32; 3]>,
}

/// Whether light leaves `material` through an index-matched boundary: its
/// top layer's index is 1, as the walk reads it.
fn index_matched(material: &Material) -> bool {
    material
        .layers()
        .and_then(<[_]>::first)
        .is_some_and(|top| Boundary::of_index(top.ior) == Boundary::IndexMatched)
}

impl Prepared {
    /// The power of a map over the surface, per channel: Σ value × texel
    /// area (W/m² × mm², for a map in W/m²).
    pub fn power(&self, values: &[[f32; 3]]) -> [f64; 3] {
        let mut power = [0.0; 3];
        for (v, &a) in values.iter().zip(&self.surfels.area) {
            for c in 0..3 {
                power[c] += f64::from(v[c]) * f64::from(a);
            }
        }
        power
    }

    /// Scales `exitance` down per channel where it leaves more power than
    /// enters, and says by how much: raising the light where the surface
    /// ends holds a plane's total under uniform light, but under light far
    /// from uniform on a part much smaller than the reach it may not.
    ///
    /// Not behind an index-matched boundary (`scattering`'s top layer of
    /// index 1, Cycles' Principled materials). The map is light's radiance
    /// along the normal × π (the walk turned round, Cycles' bake), not the
    /// flux leaving. Behind a dielectric, light trapped by the boundary
    /// leaves nearly as from a Lambertian surface and that power bounds the
    /// map: the walk's red map on a 100 mm ball of long reach carries 0.987
    /// of the power entering. An index-matched boundary lets light leave
    /// with the medium's own angular spread, peaked along the normal: on a
    /// backlit 3 mm slab of Blender's skin the walk's red map carries 1.075
    /// of it, and scaling the bake to 1 left the slab's middle 5% under the
    /// walk.
    fn make_no_energy(
        &self,
        scattering: &Scattering,
        exitance: &mut [[f32; 3]],
    ) -> Option<[f32; 3]> {
        if index_matched(&scattering.material) {
            return None;
        }
        let (leaving, entering) = (self.power(exitance), self.power(&self.entering()));
        let kept = [0, 1, 2].map(|c| {
            let (out, into) = (leaving[c], entering[c]);
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
        let scattered_by = scattering_key(scattering);
        let mut known_ball = None;
        if let Some(raised) = self
            .raised
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .as_ref()
        {
            if raised.key == key {
                return Ok(Arc::clone(raised));
            }
            // The ball's gains need no integrator: another's serve.
            if raised.scattering == scattered_by {
                known_ball = Some(Arc::clone(&raised.ball));
            }
        }
        let (uniform, stride) = self.uniform_sums(integrator, scattering, slab, control)?;
        let summed_across = integrator.carries().across;
        let (gains, _) = slab.gains(&self.opposites(slab.reach()), &uniform, summed_across);
        // Small convex parts return more than the slab; the two gains
        // answer different shortfalls (surface missing within reach, light
        // that meets the surface sooner) and multiply, within the cap.
        let ball = known_ball.unwrap_or_else(|| {
            Arc::new(match slab.ball_scales() {
                Some(scales) => {
                    slab.ball_gains(&self.mean_curvatures(scales), &self.opposites(slab.reach()))
                }
                None => vec![[1.0; 3]; self.surfels.len()],
            })
        });
        let gains: Vec<[f32; 3]> = gains
            .iter()
            .zip(ball.iter())
            .map(|(g, b)| [0, 1, 2].map(|c| (g[c] * b[c]).min(MAX_GAIN as f32)))
            .collect();
        let mut halves: Vec<[f32; 3]> = gains.iter().map(|g| g.map(f32::sqrt)).collect();
        // Thin parts' gains by their own slab's profile, where they take it.
        let (mut by_slab_profile, mut rim) = (0, RimSights::default());
        if let Some(profiles) = scattering.slab_profiles() {
            let thin = profiles.thin_texels(self, None);
            let epsilon = integrator.thin_epsilon();
            rim = profiles.gains(self, &thin, &mut halves, &ball, epsilon, stride, control)?;
            by_slab_profile = thin.texels().len();
        }
        let count = halves
            .iter()
            .filter(|h| h.iter().any(|&h| f64::from(h * h) > RAISED))
            .count();
        let raised = Arc::new(Raised {
            key,
            scattering: scattered_by,
            halves,
            ball,
            count,
            by_slab_profile,
            rim,
            stride,
        });
        *self.raised.lock().unwrap_or_else(|e| e.into_inner()) = Some(Arc::clone(&raised));
        Ok(raised)
    }

    /// Each surfel's sum of the kernel's weights over the surface: the
    /// integrator's sums under a unit light. They change over the profile's
    /// spread, not from texel to texel, so where the integrator can sum at
    /// some texels alone ([`Integrator::summer`]) they are summed on a
    /// lattice of [`uniform_stride`] texels and carried bilinearly between
    /// ([`Carrier::whole`]; from finer lattices where a texel lacks four
    /// corners on its surface, down to its own sum). Where the gains from
    /// the fit miss those from direct sums at random texels by more than
    /// [`FIT_TOLERANCE`], the cells whose corners' sums differ steeply are
    /// carried finer ([`Carrier::with_steep_cells`]); where they still
    /// miss, the stride is halved (rounding up), down to every texel. The error
    /// estimate measures them against exact sums at its texels, as it
    /// measures the map. With the sums, the stride they were taken at.
    fn uniform_sums(
        &self,
        integrator: &dyn Integrator,
        scattering: &Scattering,
        slab: &LocalSlab,
        control: &Control,
    ) -> Result<(Vec<[f32; 3]>, u32), Error> {
        let lit = self.uniformly_lit();
        let mut stride = uniform_stride(scattering, &self.surfels);
        if stride > 1
            && let Some(summer) = integrator.summer(&lit, scattering)
        {
            let probed = self.probed_sums(&*summer, slab, control)?;
            let across = integrator.carries().across;
            let all: Vec<usize> = (0..self.surfels.len()).collect();
            let mut carrier = Carrier::whole(&lit, &*summer);
            let mut steep_cells = false;
            while stride > 1 {
                let fitted = carrier.at(&all, stride, control)?;
                if probed.gains_missed(slab, &self.opposites(slab.reach()), &fitted, across)
                    <= FIT_TOLERANCE
                {
                    return Ok((fitted, stride));
                }
                // A miss is mostly a few cells where the sums change
                // abruptly: those are carried finer before the whole
                // lattice is.
                if !steep_cells {
                    steep_cells = true;
                    carrier = carrier.with_steep_cells();
                    continue;
                }
                // Halved, rounding up: 3 texels apart tries 2 before every
                // texel (skin1 on the head at 1024²: 1.2% missed at 3,
                // 0.8% at 2).
                stride = stride.div_ceil(2);
            }
            return Ok((carrier.at(&all, 1, control)?, 1));
        }
        Ok((integrator.integrate(&lit, scattering, control)?.exitance, 1))
    }

    /// The sums under a unit light at [`probe_count`] texels, drawn at
    /// random, each with the texel behind it, summed directly by `summer`:
    /// what a fit of them is checked against, at every stride it tries.
    fn probed_sums(
        &self,
        summer: &dyn Summer,
        slab: &LocalSlab,
        control: &Control,
    ) -> Result<Probed, Error> {
        let texels = self.surfels.len();
        let probes = pick(texels, probe_count(texels), 0x756e_6974);
        let (behind, asked) = slab.behind(&self.opposites(slab.reach()), &probes);
        let direct = summer.at(&asked, control)?;
        Ok(Probed {
            probes,
            behind,
            summed: asked.into_iter().zip(direct).collect(),
        })
    }

    /// The exitance of the texels on thin parts, in each channel where the
    /// part is thin, by their own slab's profile
    /// ([`crate::transport::slab_profiles`]), gathered through the octree
    /// at `integrator`'s ε for them under `raised_light`, the light
    /// entering raised as `raised` has it (with those texels' gains by the
    /// slab), and carried from the `lattice` (its first step, and the
    /// map's tolerance) where the fit holds. With that fit.
    #[allow(clippy::too_many_arguments)]
    fn thin_by_their_slab(
        &self,
        scattering: &Scattering,
        integrator: &dyn Integrator,
        raised: &Raised,
        raised_light: &Prepared,
        lattice: (u32, f64),
        integrated: &mut Integrated,
        control: &Control,
    ) -> Result<Option<MapFit>, Error> {
        let Some(profiles) = scattering.slab_profiles() else {
            return Ok(None);
        };
        let thin = profiles.thin_texels(self, None);
        let epsilon = integrator.thin_epsilon();
        let halves = &raised.halves;
        // The map's tolerance is its relative RMSE: the thin channels'
        // fit may miss by as much over the square root of their share of
        // the map's Σ M² (the map as it stands standing in for theirs),
        // within a bound.
        let (step, tolerance) = lattice;
        let share = profiles.share_of_map(&thin, &integrated.exitance);
        let lattice = Some((step, thin_tolerance(tolerance, share)));
        let (lit, fit) = profiles.lit(
            raised_light,
            halves,
            &raised.rim,
            &thin,
            epsilon,
            lattice,
            control,
        )?;
        for (t, m) in thin.texels().iter().zip(lit) {
            let old = &mut integrated.exitance[t.texel];
            *old = [0, 1, 2].map(|c| m[c].unwrap_or(old[c]));
        }
        Ok(fit)
    }

    /// Integrates with `integrator` under `scattering` and applies the
    /// colour after scattering. Where the integrator sums at chosen texels,
    /// the map is carried from a lattice of them within a share of
    /// `tolerance` (relative RMSE; [`crate::fitted_map`]).
    pub fn integrate(
        &self,
        scattering: &Scattering,
        integrator: &dyn Integrator,
        tolerance: f64,
        control: &Control,
    ) -> Result<Integration, Error> {
        if self.irradiance.len() != self.surfels.len() {
            return Err(Error::input(
                "the object was prepared without light; nothing to scatter",
            ));
        }
        let start = Instant::now();
        // Every profile method bakes the corrected model; the walk is light.
        let carries = integrator.carries();
        let slab = scattering.local_slab().filter(|_| carries.profile);
        let summed_across = carries.across;
        // The light entering is raised where the surface within reach ends
        // (not for an oblique kernel, which reads the light split by
        // incidence).
        let raised = control.part(0.0, RAISING_SHARE, "sums under a unit light", || match slab
            .filter(|_| scattering.oblique.is_none())
        {
            Some(slab) => self.raise(slab, integrator, scattering, control).map(Some),
            None => Ok(None),
        })?;
        let raised_light = raised.as_ref().map(|r| self.raised_by(&r.halves));
        let lit = raised_light.as_ref().unwrap_or(self);
        let step = first_step(half_light_texels(scattering, &self.surfels));
        // Without raised light no thin parts' map follows the map.
        let map_end = if raised.is_some() { MAP_END } else { 1.0 };
        let (mut integrated, fit) = control.part(RAISING_SHARE, map_end, "the map", || {
            Ok::<_, Error>(match integrator.summer(lit, scattering) {
                Some(summer) => {
                    let (exitance, fit) =
                        fitted_map(lit, &*summer, &scattering.kernel, step, tolerance, control)?;
                    let integrated = Integrated {
                        exitance,
                        sources: self.surfels.len(),
                        walk: None,
                    };
                    (integrated, Some(fit))
                }
                None => (integrator.integrate(lit, scattering, control)?, None),
            })
        })?;
        if let Some(slab) = slab {
            integrated.exitance = slab.correct_all(
                &self.opposites(slab.reach()),
                &integrated.exitance,
                summed_across,
            );
        }
        let (mut kept, mut thin_fit) = (None, None);
        if let Some(raised) = &raised {
            raised.leaving(&mut integrated.exitance);
            // Thin parts' map from the lattice the map began at.
            let lattice = (step, tolerance);
            let raised_light = raised_light.as_ref().unwrap_or(self);
            thin_fit = control.part(MAP_END, 1.0, "thin parts' map", || {
                self.thin_by_their_slab(
                    scattering,
                    integrator,
                    raised,
                    raised_light,
                    lattice,
                    &mut integrated,
                    control,
                )
            })?;
            kept = self.make_no_energy(scattering, &mut integrated.exitance);
        }
        for (i, m) in integrated.exitance.iter_mut().enumerate() {
            *m = self.after_scattering(i, *m);
        }
        Ok(Integration {
            exitance: integrated.exitance,
            seconds: start.elapsed().as_secs_f64(),
            sources: integrated.sources,
            walk: integrated.walk,
            fit,
            thin_fit,
            raised,
            kept,
        })
    }
}
