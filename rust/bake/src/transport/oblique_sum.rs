//! The exact discrete sum with an oblique kernel
//! ([`sssbake_profile::models::empirical::kernel`]): M(x) = Σ_j A_j Σ_nodes
//! [E_j,n m₀,n(r) + Σ_k m_k,n(r) (C_jk,n cos kβ + S_jk,n sin kβ)], β the
//! azimuth of x − x_j on source j's tangent plane in its frame and
//! (E, C, S) the source's light split by incidence
//! ([`crate::irradiance::incidence`]): cos k(β − α) expanded, so each
//! light's own azimuth α is kept however many lights there are.
//!
//! A source's own texel gets the light leaving within the disc of its
//! area (the harmonics integrate to zero over it); a source closer than
//! twice its footprint is read as the mean over a 4 × 4 grid of its
//! footprint, since the kernel is steep on the scale of a texel there.
//! The sum is clamped at zero per target: a truncated series can dip
//! below zero behind an entry point, never over a lit neighbourhood.

use super::sources::{Grid, Sources, Targets};
use super::through_medium::path_length;
use crate::control::{Cancelled, Control, parallel_fill};
use crate::irradiance::incidence::{COMPONENTS, IncidentHarmonics, frame};
use glam::{Vec2, Vec3};
use sssbake_profile::models::empirical::kernel::ObliqueKernel;
use sssbake_profile::models::empirical::oblique::HARMONICS_KEPT;

/// Sub-points per side of a near source's footprint.
const NEAR_GRID: usize = 4;

/// One source's light at one incidence node.
#[derive(Clone, Copy)]
struct NodeLight {
    node: usize,
    light: [[f32; 3]; COMPONENTS],
}

/// What each lit source carries, in grid order.
struct Lit {
    position: Vec<Vec3>,
    normal: Vec<Vec3>,
    frame: Vec<(Vec3, Vec3)>,
    area: Vec<f32>,
    footprint: Vec<[Vec3; 2]>,
    /// Index of each source in the caller's [`Sources`].
    index: Vec<usize>,
    /// Each source's run in `nodes`.
    runs: Vec<std::ops::Range<usize>>,
    nodes: Vec<NodeLight>,
}

/// Radiant exitance (W/m²) at each target by the exact sum over `sources`
/// within `reach` mm, under `kernel`; `incidence` splits each source's
/// light by incidence (`None`: all of it at normal incidence);
/// `azimuthal_mean` drops the harmonics (each light's azimuthal mean at
/// its own incidence, for comparisons).
pub fn integrate(
    kernel: &ObliqueKernel,
    reach: f32,
    sources: &Sources,
    incidence: Option<&[IncidentHarmonics]>,
    targets: Targets,
    azimuthal_mean: bool,
    control: &Control,
) -> Result<Vec<[f32; 3]>, Cancelled> {
    let lit = lit_sources(sources, incidence);
    let cell = (0.25 * reach).max(1e-3);
    let grid = Grid::new(&lit.position, cell);
    let harmonics = if azimuthal_mean { 1 } else { HARMONICS_KEPT };
    let mut out = vec![[0.0f32; 3]; targets.position.len()];
    parallel_fill(&mut out, 64, control, |i| {
        let p = targets.position[i];
        let n = targets.normal[i];
        let own = targets.own.of(i);
        let target = targets.at(i);
        let mut sum = [0.0f64; 3];
        grid.for_each_run(p, reach, |run| {
            for &g in &grid.order[run] {
                let j = g as usize;
                let straight = p - lit.position[j];
                let distance = straight.length();
                if distance > reach || !sources.joins(lit.index[j], &target) {
                    continue;
                }
                // Across a concave crease the light goes round through the
                // medium: the offset is read at the length of that path.
                let path = path_length(lit.position[j], lit.normal[j], p, n, distance);
                if path > reach {
                    continue;
                }
                let d = if path > distance {
                    straight * (path / distance)
                } else {
                    straight
                };
                let part = if own == Some(lit.index[j]) {
                    own_light(kernel, &lit, j)
                } else {
                    pair(kernel, &lit, j, d, harmonics)
                };
                for c in 0..3 {
                    sum[c] += part[c];
                }
            }
        });
        sum.map(super::stored_exitance)
    })?;
    Ok(out)
}

/// The sources with light, each with its nodes.
fn lit_sources(sources: &Sources, incidence: Option<&[IncidentHarmonics]>) -> Lit {
    let mut lit = Lit {
        position: Vec::new(),
        normal: Vec::new(),
        frame: Vec::new(),
        area: Vec::new(),
        footprint: Vec::new(),
        index: Vec::new(),
        runs: Vec::new(),
        nodes: Vec::new(),
    };
    let incidence = incidence.filter(|h| h.len() == sources.len());
    for j in 0..sources.len() {
        let area = sources.area[j];
        if !(area > 0.0 && area.is_finite()) {
            continue;
        }
        let start = lit.nodes.len();
        match incidence {
            Some(h) => {
                for (node, light) in h[j].iter().enumerate() {
                    if light.iter().flatten().any(|&v| v != 0.0) {
                        lit.nodes.push(NodeLight {
                            node,
                            light: *light,
                        });
                    }
                }
            }
            None => {
                let e = sources.irradiance[j];
                if e.iter().any(|&v| v != 0.0) {
                    let mut light = [[0.0; 3]; COMPONENTS];
                    light[0] = e;
                    lit.nodes.push(NodeLight { node: 0, light });
                }
            }
        }
        if lit.nodes.len() == start {
            continue;
        }
        let n = sources.normal[j];
        lit.position.push(sources.position[j]);
        lit.normal.push(n);
        lit.frame.push(frame(n));
        lit.area.push(area);
        lit.footprint
            .push(sources.footprint.get(j).copied().unwrap_or([Vec3::ZERO; 2]));
        lit.index.push(j);
        lit.runs.push(start..lit.nodes.len());
    }
    lit
}

/// A source's light at its own texel: what leaves within the disc of its
/// area.
fn own_light(kernel: &ObliqueKernel, lit: &Lit, j: usize) -> [f64; 3] {
    let radius = (lit.area[j] as f64 / std::f64::consts::PI).sqrt();
    let mut out = [0.0; 3];
    for node in &lit.nodes[lit.runs[j].clone()] {
        for (c, o) in out.iter_mut().enumerate() {
            *o += node.light[0][c] as f64 * kernel.enclosed(node.node, c, radius);
        }
    }
    out
}

/// Source `j`'s light at offset `d` (target − source), with the first
/// `harmonics` harmonics; near sources averaged over their footprint.
fn pair(kernel: &ObliqueKernel, lit: &Lit, j: usize, d: Vec3, harmonics: usize) -> [f64; 3] {
    let [e0, e1] = lit.footprint[j];
    let size2 = e0.length_squared().max(e1.length_squared());
    let area = lit.area[j] as f64;
    if size2 > 0.0 && d.length_squared() < 4.0 * size2 {
        let mut out = [0.0; 3];
        let share = area / (NEAR_GRID * NEAR_GRID) as f64;
        for a in 0..NEAR_GRID {
            for b in 0..NEAR_GRID {
                let f = |i: usize| (i as f32 + 0.5) / NEAR_GRID as f32 - 0.5;
                let at = d - (e0 * f(a) + e1 * f(b));
                let v = point(kernel, lit, j, at, harmonics);
                for c in 0..3 {
                    out[c] += share * v[c];
                }
            }
        }
        out
    } else {
        point(kernel, lit, j, d, harmonics).map(|v| v * area)
    }
}

/// The kernel of source `j`'s light (per unit area) at offset `d`.
fn point(kernel: &ObliqueKernel, lit: &Lit, j: usize, d: Vec3, harmonics: usize) -> [f64; 3] {
    let nodes = lit.nodes[lit.runs[j].clone()]
        .iter()
        .map(|n| (n.node, &n.light));
    light_at(kernel, nodes, lit.normal[j], lit.frame[j], d, harmonics)
}

/// The kernel per unit area of light entering at a point of unit normal
/// `n` and tangent frame `frame` ([`frame`]), split by incidence into
/// `nodes` (node, components), read at offset `d` (exit − entry) with the
/// first `harmonics` harmonics.
pub(crate) fn light_at<'a>(
    kernel: &ObliqueKernel,
    nodes: impl Iterator<Item = (usize, &'a [[f32; 3]; COMPONENTS])> + Clone,
    n: Vec3,
    frame: (Vec3, Vec3),
    d: Vec3,
    harmonics: usize,
) -> [f64; 3] {
    let r = d.length() as f64;
    let (u, v) = frame;
    let along = d - n * d.dot(n);
    let direction = Vec2::new(along.dot(u), along.dot(v));
    // Straight above the entry point there is no azimuth: the harmonics,
    // whose sum over a circle is zero, have no direction to lean to.
    let (unit, harmonics) = match direction.try_normalize() {
        Some(unit) => (unit.as_dvec2(), harmonics),
        None => (Vec2::X.as_dvec2(), 1),
    };
    // cos kβ, sin kβ by powers of e^{iβ}.
    let mut turns = [(1.0f64, 0.0f64); HARMONICS_KEPT];
    for k in 1..HARMONICS_KEPT {
        let (c, s) = turns[k - 1];
        turns[k] = (c * unit.x - s * unit.y, c * unit.y + s * unit.x);
    }
    let mut out = [0.0; 3];
    for (c, o) in out.iter_mut().enumerate() {
        let Some(b) = kernel.annulus(c, r) else {
            continue;
        };
        for (node, light) in nodes.clone() {
            let m = kernel.harmonics_in(node, c, b);
            let mut v = m[0] * light[0][c] as f64;
            for (k, &(cos_k, sin_k)) in turns.iter().enumerate().take(harmonics).skip(1) {
                let (cw, sw) = (light[2 * k - 1][c], light[2 * k][c]);
                v += m[k] * (cw as f64 * cos_k + sw as f64 * sin_k);
            }
            *o += v;
        }
    }
    out
}
