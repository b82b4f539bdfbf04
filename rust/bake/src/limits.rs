//! What a bake may use, checked when it is planned: the memory it will
//! hold and the work it will do are estimated from the scene and the
//! request before anything proportional to them is allocated, and a
//! request over a limit is refused with what drives it, rather than found
//! out by running out of memory or by hanging.
//!
//! The limits are fixed numbers, not a share of this machine's memory, so
//! a farm's machines all accept or all refuse the same request.

use crate::error::Error;
use crate::maps::Output;
use crate::mesh::Mesh;
use crate::request::UvPolicy;
use crate::transport::integrator::{Integrator, Work};
use crate::transport::octree::shape::BYTES_PER_TEXEL as TREE_SHAPE_BYTES_PER_TEXEL;
use serde::Serialize;

/// The default memory limit, bytes (16 GiB).
pub const DEFAULT_MAX_MEMORY_BYTES: u64 = 16 << 30;

/// The default work limit: kernel evaluations, shadow rays and probes
/// together. The exact sum, the costliest per evaluation, runs about 7·10⁷
/// pairs a second on two cores (the marble at 512², 1.5·10⁸ pairs, in about
/// 2 s), so 3·10¹⁰ is about seven minutes of it.
pub const DEFAULT_MAX_EVALUATIONS: f64 = 3e10;

/// Memory a bake holds besides its texels, bytes: the scene, the profile
/// tables, the threads' stacks.
const BASE_BYTES: u64 = 16 << 20;

/// Bytes per texel of the map's full square, covered or not: the texel
/// index and one RGBA f32 image per map.
fn bytes_per_map_texel(outputs: usize) -> u64 {
    4 + 16 * outputs as u64
}

/// Bytes per covered texel while an object's bake runs, besides its
/// layout: its irradiance, colour and exitance, the integrator's tables
/// and the transient buffers of rasterising and writing. With the layout's
/// 80, 360 in all, rounded up from the 200 to 245 measured beyond the maps
/// (peak resident memory of `sssbake bake` on the bundled examples with
/// each method, 512² to 2048²) and from the head's peak at 512², which
/// varies from run to run (146 to 163 MB, where 220 here planned 147 MB;
/// 155 MB in six runs by `/usr/bin/time`); `tests/test_limits.py` checks
/// the estimate stays above the measured peak and within 2.5× it. The
/// octree's shape, held from the first gathering to the end of the
/// object's bake, is counted apart ([`TREE_SHAPE_BYTES_PER_TEXEL`]). The
/// carried map's reach of N per texel (4 bytes, held with the map) came
/// after those measures and is added to them.
const BYTES_PER_TEXEL: u64 = 284;

/// Bytes per covered texel of an object's layout, which the plan holds for
/// every object until the bake ends.
const LAYOUT_BYTES_PER_TEXEL: u64 = 80;

/// Bytes per covered texel of the light split by incidence that an oblique
/// kernel reads ([`crate::irradiance::incidence`]), held while the object
/// bakes, and the exact sum's copy of it: every node a texel's light may
/// fall in (an area light or the environment reaches them all), each with
/// its index, and the source's position, normal, frame, area, footprint,
/// index and run (100 bytes).
const INCIDENCE_BYTES_PER_TEXEL: usize = {
    use crate::irradiance::incidence::{COMPONENTS, IncidentHarmonics, NODES};
    std::mem::size_of::<IncidentHarmonics>()
        + NODES * std::mem::size_of::<(usize, [[f32; 3]; COMPONENTS])>()
        + 100
};

/// Texels `mesh` will cover in maps of `resolution`² texels, estimated
/// before its layout is made: its UV area, or the whole square where it
/// may be unwrapped (no UVs, or UVs that overlap or cover almost nothing).
pub fn estimated_texels(mesh: &Mesh, resolution: u32, policy: UvPolicy) -> f64 {
    let square = f64::from(resolution).powi(2);
    let Some(uvs) = mesh.uvs.as_ref().filter(|_| policy != UvPolicy::Unwrap) else {
        return square;
    };
    let area: f64 = mesh
        .triangles
        .iter()
        .map(|t| {
            let [a, b, c] = t.map(|i| uvs[i as usize].as_dvec2());
            0.5 * (b - a).perp_dot(c - a).abs()
        })
        .filter(|a| a.is_finite())
        .sum();
    let may_unwrap = policy == UvPolicy::Auto && !(0.01..=1.0).contains(&area);
    if may_unwrap {
        square
    } else {
        area.min(1.0) * square
    }
}

/// What a bake may use; a request over either is refused when planned.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Limits {
    /// Peak memory, bytes.
    pub max_memory_bytes: u64,
    /// Kernel evaluations, shadow rays and probes, all objects together.
    pub max_evaluations: f64,
}

impl Default for Limits {
    fn default() -> Self {
        Limits {
            max_memory_bytes: DEFAULT_MAX_MEMORY_BYTES,
            max_evaluations: DEFAULT_MAX_EVALUATIONS,
        }
    }
}

/// The second, uniform integration's copy of a texel's light and colour
/// (12 bytes each), the face behind it (12) and its sums (12).
const UNIFORM_PASS_BYTES_PER_TEXEL: usize = 48;

/// One object's share of a bake, as the plan estimates it.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct ObjectCost {
    /// Texels covered (estimated from the UV area before the layout).
    pub texels: f64,
    /// Peak memory while this object bakes, bytes, besides the layouts.
    pub memory_bytes: f64,
    /// Memory of its layout, held until the bake ends, bytes.
    pub layout_bytes: f64,
    /// Rays of its lighting: shadow rays, and the rays that gather the
    /// light the object sends onto itself.
    pub rays: f64,
    /// Kernel evaluations (or probes) of its scattering.
    pub evaluations: f64,
    /// Walk events of its check against light (all channels).
    pub light_check: f64,
    /// Steps finding the surface's curvature, where the corrected model
    /// raises small convex parts (all channels).
    pub curvature: f64,
    /// Kernel evaluations of the thin parts' own slab profiles, at most:
    /// under a unit light and under the light, as if every texel were on a
    /// thin part ([`crate::transport::slab_profiles`]).
    pub thin_parts: f64,
}

impl ObjectCost {
    /// The memory of an object of `texels` covered texels in maps of
    /// `resolution`² texels with `outputs` maps.
    pub fn memory(texels: f64, resolution: u32, outputs: &[Output]) -> ObjectCost {
        let square = f64::from(resolution).powi(2);
        ObjectCost {
            texels,
            memory_bytes: square * bytes_per_map_texel(outputs.len()) as f64
                + texels * (BYTES_PER_TEXEL + TREE_SHAPE_BYTES_PER_TEXEL as u64) as f64,
            layout_bytes: texels * LAYOUT_BYTES_PER_TEXEL as f64,
            ..ObjectCost::default()
        }
    }

    /// This cost with the lighting and scattering work of `integrator`
    /// (none when nothing scatters) over `work`: at most `rays_per_texel`
    /// shadow rays each, and the integrator's own evaluations.
    pub fn with_work(
        mut self,
        integrator: Option<&dyn Integrator>,
        work: &Work,
        rays_per_texel: f64,
    ) -> ObjectCost {
        self.rays = self.texels * rays_per_texel;
        self.evaluations = integrator.map_or(0.0, |i| i.evaluations(work));
        self
    }
}

impl ObjectCost {
    /// This cost when the corrected model raises the sums where the
    /// surface within reach ends (`raises`, for an integrator of the
    /// profile): the integrator runs a second time under a unit light, on
    /// a copy of the light, colour and faces behind, and holds its sums.
    /// A bound: an integrator that sums at some texels alone runs that
    /// pass at one texel in up to 16, a sixteenth of the evaluations
    /// counted here.
    pub fn with_uniform_pass(
        mut self,
        raises: bool,
        integrator: Option<&dyn Integrator>,
    ) -> ObjectCost {
        if raises && integrator.is_some_and(|i| i.carries().profile) {
            self.evaluations *= 2.0;
            self.memory_bytes += self.texels * UNIFORM_PASS_BYTES_PER_TEXEL as f64;
        }
        self
    }

    /// This cost when an oblique kernel reads the light split by incidence
    /// (`split`): its light samples are traced a second time, the split is
    /// held per texel, and each pair or probe of an integrator that takes
    /// the oblique kernel reads every component of a node
    /// ([`crate::irradiance::incidence::COMPONENTS`]) instead of one value,
    /// with what the integrator holds for it over maps of `resolution`².
    pub fn with_incidence_split(
        mut self,
        split: bool,
        integrator: Option<&dyn Integrator>,
        resolution: u32,
    ) -> ObjectCost {
        if split {
            self.rays *= 2.0;
            self.memory_bytes += self.texels * INCIDENCE_BYTES_PER_TEXEL as f64;
            if let Some(integrator) = integrator {
                if integrator.carries().oblique {
                    self.evaluations *= crate::irradiance::incidence::COMPONENTS as f64;
                }
                self.memory_bytes += integrator.extra_memory_bytes(resolution, split);
            }
        }
        self
    }
}

/// A bake's estimated cost, all objects together.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct Cost {
    /// Peak memory, bytes: every layout, and the largest object's bake.
    pub memory_bytes: f64,
    /// Shadow rays, kernel evaluations and probes, walk events, the
    /// curvature's steps and the thin parts' gathers.
    pub evaluations: f64,
}

impl Cost {
    /// The cost of baking `objects` one after another.
    pub fn of(objects: &[ObjectCost]) -> Cost {
        let layouts: f64 = objects.iter().map(|o| o.layout_bytes).sum();
        let largest = objects.iter().map(|o| o.memory_bytes).fold(0.0, f64::max);
        Cost {
            memory_bytes: BASE_BYTES as f64 + layouts + largest,
            evaluations: objects
                .iter()
                .map(|o| o.rays + o.evaluations + o.light_check + o.curvature + o.thin_parts)
                .sum(),
        }
    }

    /// Refuses a cost over `limits`, naming `what` drives it (the request's
    /// resolution, the objects, the method) and how to go on; the limit is
    /// named by its field, which each front door puts in its own terms
    /// ([`Error::naming_limit`]).
    pub fn check(&self, limits: &Limits, what: &str) -> Result<(), Error> {
        if self.memory_bytes > limits.max_memory_bytes as f64 {
            return Err(Error::field(
                "max_memory",
                format!(
                    "the bake would hold about {} ({what}), over the limit of {}: lower the \
                     resolution, bake fewer objects at once, or raise the limit",
                    bytes_text(self.memory_bytes),
                    bytes_text(limits.max_memory_bytes as f64)
                ),
            ));
        }
        if self.evaluations > limits.max_evaluations {
            return Err(Error::field(
                "max_evaluations",
                format!(
                    "the bake would take about {:.1e} kernel evaluations, shadow rays and probes \
                     ({what}), over the limit of {:.1e}: lower the resolution or the samples, \
                     choose a faster method, or raise the limit",
                    self.evaluations, limits.max_evaluations
                ),
            ));
        }
        Ok(())
    }
}

/// `bytes` in the largest binary unit that keeps it at least 1.
pub fn bytes_text(bytes: f64) -> String {
    const UNITS: [&str; 5] = ["B", "KiB", "MiB", "GiB", "TiB"];
    let mut value = bytes;
    let mut unit = 0;
    while value >= 1024.0 && unit + 1 < UNITS.len() {
        value /= 1024.0;
        unit += 1;
    }
    format!("{value:.1} {}", UNITS[unit])
}

/// `bytes` as [`parse_bytes`] reads it back: in the largest binary unit
/// that divides it (`16G`, `512M`), else in bytes.
pub fn size_text(bytes: u64) -> String {
    for (shift, unit) in [(40, "T"), (30, "G"), (20, "M"), (10, "K")] {
        if bytes > 0 && bytes.is_multiple_of(1u64 << shift) {
            return format!("{}{unit}", bytes >> shift);
        }
    }
    bytes.to_string()
}

/// Reads a size such as `16G`, `512MiB`, `2.5 GB` or `1000000` (bytes);
/// the units are binary (K = 1024).
pub fn parse_bytes(text: &str) -> Result<u64, String> {
    let trimmed = text.trim();
    let split = trimmed
        .find(|c: char| c.is_ascii_alphabetic())
        .unwrap_or(trimmed.len());
    let (number, unit) = trimmed.split_at(split);
    let value: f64 = number
        .trim()
        .parse()
        .map_err(|_| format!("`{text}` is not a size such as 16G, 512M or 1000000"))?;
    let unit = unit.trim();
    let shift = match unit.to_ascii_uppercase().as_str() {
        "" | "B" => 0,
        "K" | "KB" | "KIB" => 10,
        "M" | "MB" | "MIB" => 20,
        "G" | "GB" | "GIB" => 30,
        "T" | "TB" | "TIB" => 40,
        _ => {
            return Err(format!(
                "`{unit}` in `{text}` is not a unit: use K, M, G or T"
            ));
        }
    };
    let bytes = value * (1u64 << shift) as f64;
    if !(bytes.is_finite() && bytes >= 1.0 && bytes < u64::MAX as f64) {
        return Err(format!("`{text}` must be a positive size"));
    }
    Ok(bytes as u64)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sizes_read_in_binary_units() {
        assert_eq!(parse_bytes("16G"), Ok(16 << 30));
        assert_eq!(parse_bytes("512 MiB"), Ok(512 << 20));
        assert_eq!(parse_bytes("1.5k"), Ok(1536));
        assert_eq!(parse_bytes("1000"), Ok(1000));
        for bad in ["", "G", "-1G", "0", "NaN", "1e300T", "12 parsecs"] {
            assert!(parse_bytes(bad).is_err(), "{bad}");
        }
    }

    #[test]
    fn the_largest_object_and_every_layout_count() {
        let outputs = [Output::Subsurface];
        let small = ObjectCost::memory(1e3, 64, &outputs);
        let large = ObjectCost::memory(1e6, 1024, &outputs);
        let both = Cost::of(&[small, large]);
        let large_alone = Cost::of(&[large]);
        assert_eq!(
            both.memory_bytes - large_alone.memory_bytes,
            small.layout_bytes
        );
    }

    #[test]
    fn a_cost_over_a_limit_is_refused_naming_the_limit() {
        let cost = Cost {
            memory_bytes: 2e9,
            evaluations: 1e3,
        };
        let tight = Limits {
            max_memory_bytes: 1 << 30,
            max_evaluations: 1e12,
        };
        let message = cost.check(&tight, "object `Head`").unwrap_err().to_string();
        assert!(
            message.starts_with("max_memory: ") && message.contains("1.9 GiB"),
            "{message}"
        );
        assert!(message.ends_with("or raise the limit"), "{message}");
        let at_a_door = cost
            .check(&tight, "")
            .unwrap_err()
            .naming_limit(|field| format!("--{}", field.replace('_', "-")))
            .to_string();
        assert!(
            at_a_door.ends_with("or raise the limit (--max-memory)"),
            "{at_a_door}"
        );
        assert!(cost.check(&Limits::default(), "").is_ok());
        let slow = Limits {
            max_memory_bytes: 1 << 40,
            max_evaluations: 1e2,
        };
        let message = cost.check(&slow, "brute").unwrap_err().to_string();
        assert!(message.starts_with("max_evaluations: "), "{message}");
    }
}
