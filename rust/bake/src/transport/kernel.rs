//! The profile as the integrators use it: R(r) and T(r) averaged over the
//! patch a sample stands for, from tables of the enclosed reflectance and
//! transmittance, cut at d_max.
//!
//! A sample of area A stands for the disk of that area around it: its
//! weight is the profile's mean over that disk, not R at its centre, which
//! keeps the discrete sum equal to the integral when the profile is sharp
//! against the sample spacing (a sample's weight for itself is then
//! exactly the reflectance within its own disk).

use super::through_medium::longer_path;
use sssbake_profile::profile::Profile;
use std::sync::OnceLock;

/// Table entries per channel; radii grow quadratically so the sharp
/// centre of a profile is resolved as finely as its tail.
const ENTRIES: usize = 4096;

/// A profile tabulated for integration.
#[derive(Clone, Debug)]
pub struct Kernel {
    /// The radius beyond which nothing is gathered, mm.
    pub d_max: f32,
    /// ∫_0^r 2πs R(s) ds at r = d_max (k/(ENTRIES−1))², per channel.
    reflectance: Vec<[f32; 3]>,
    /// The same for T; empty when the profile transmits nothing.
    transmittance: Vec<[f32; 3]>,
    /// R at the same radii, for densities.
    density: Vec<[f32; 3]>,
    /// T at the same radii; empty when the profile transmits nothing.
    transmit_density: Vec<[f32; 3]>,
}

/// The most a kernel's tables hold, bytes: four tables of
/// [`ENTRIES`] entries.
pub const MOST_BYTES: usize = 4 * ENTRIES * std::mem::size_of::<[f32; 3]>();

/// The blend of reflection and transmission for two normals (Mikkelsen
/// §3.1, from Donner & Jensen 2005): t = (1 − n_i·n_o)/2.
pub fn transmission_share(n_in: glam::Vec3, n_out: glam::Vec3) -> f32 {
    (0.5 * (1.0 - n_in.dot(n_out))).clamp(0.0, 1.0)
}

/// Where a point of entry sits from a point of exit.
#[derive(Clone, Copy, Debug)]
pub struct Separation {
    /// Straight distance, mm: what R is read at.
    pub distance: f32,
    /// Distance across the exit normal, mm: what T is read at, since T(r)
    /// is a function of the offset along the far face, not of the
    /// distance through the slab.
    pub across: f32,
    /// Share of transmission, (1 − n_i·n_o)/2, or 0 when the profile
    /// transmits nothing.
    pub t: f32,
}

impl Separation {
    /// The separation of entry `entry` (normal `entry_normal`) from exit
    /// `exit` (normal `exit_normal`), `distance2` being |entry − exit|².
    /// R is read at the path through the medium
    /// ([`super::through_medium::path_length`]); a pair that path joins
    /// round a concave crease or not at all faces itself across air, so
    /// nothing is transmitted between them.
    #[inline]
    pub fn new(
        entry: glam::Vec3,
        entry_normal: glam::Vec3,
        exit: glam::Vec3,
        exit_normal: glam::Vec3,
        distance2: f32,
        transmits: bool,
    ) -> Self {
        if let Some(distance) = longer_path(entry, entry_normal, exit, exit_normal, distance2) {
            return Separation {
                distance,
                across: distance,
                t: 0.0,
            };
        }
        Self::straight(entry, entry_normal, exit, exit_normal, distance2, transmits)
    }

    /// [`Separation::new`] for a pair known to be joined straight through
    /// the medium ([`super::through_medium::may_cross_air`] false).
    #[inline]
    pub fn straight(
        entry: glam::Vec3,
        entry_normal: glam::Vec3,
        exit: glam::Vec3,
        exit_normal: glam::Vec3,
        distance2: f32,
        transmits: bool,
    ) -> Self {
        let distance = distance2.sqrt();
        if !transmits {
            return Separation {
                distance,
                across: distance,
                t: 0.0,
            };
        }
        let along = (entry - exit).dot(exit_normal);
        Separation {
            distance,
            across: (distance2 - along * along).max(0.0).sqrt(),
            t: transmission_share(entry_normal, exit_normal),
        }
    }
}

impl Kernel {
    /// Tabulates `profile` out to the radius holding all but `epsilon` of
    /// every channel's reflectance and transmittance.
    pub fn new(profile: &dyn Profile, epsilon: f64) -> Self {
        let d_r = profile.d_max(epsilon);
        let transmits = profile.total_transmittance().iter().any(|&t| t > 0.0);
        let mut d_max = d_r.iter().cloned().fold(0.0, f64::max);
        if transmits {
            let scale = profile.length_scale().iter().cloned().fold(0.0, f64::max);
            let whole = profile.total_transmittance();
            for (c, &total) in whole.iter().enumerate() {
                if total > 0.0 {
                    let target = (1.0 - epsilon) * total;
                    let enclosed_t = |r: f64| enclosed(|s| profile.transmittance(s)[c], r);
                    d_max = d_max.max(sssbake_profile::numerics::roots::radius_where(
                        enclosed_t, target, scale,
                    ));
                }
            }
        }
        Self::tabulated(profile, d_max)
    }

    /// [`Kernel::new`] reaching at most `most` mm: for a profile whose
    /// tallies cannot say where its light ends (a slab so thin that what
    /// it scatters is within their noise), the reach of a thicker body.
    pub fn within(profile: &dyn Profile, epsilon: f64, most: f64) -> Self {
        let kernel = Self::new(profile, epsilon);
        if f64::from(kernel.d_max) <= most {
            return kernel;
        }
        Self::tabulated(profile, most)
    }

    /// `profile` tabulated out to `d_max` mm.
    fn tabulated(profile: &dyn Profile, d_max: f64) -> Self {
        let transmits = profile.total_transmittance().iter().any(|&t| t > 0.0);
        let d_max = if d_max.is_finite() && d_max > 0.0 {
            d_max
        } else {
            0.0
        };
        let radius = |k: usize| d_max * (k as f64 / (ENTRIES - 1) as f64).powi(2);
        let reflectance = (0..ENTRIES)
            .map(|k| finite(profile.enclosed_reflectance(radius(k))))
            .collect();
        let density = (0..ENTRIES)
            .map(|k| finite(profile.reflectance(radius(k))))
            .collect();
        let (transmittance, transmit_density) = if transmits {
            (
                cumulative(|r| profile.transmittance(r), &radius),
                (0..ENTRIES)
                    .map(|k| finite(profile.transmittance(radius(k))))
                    .collect(),
            )
        } else {
            (Vec::new(), Vec::new())
        };
        Kernel {
            d_max: d_max as f32,
            reflectance,
            transmittance,
            density,
            transmit_density,
        }
    }

    /// True when the profile carries light to the far face.
    pub fn transmits(&self) -> bool {
        !self.transmittance.is_empty()
    }

    /// The reflectance within radius `r`, per channel.
    pub fn enclosed(&self, r: f32) -> [f32; 3] {
        lookup(&self.reflectance, r, self.d_max)
    }

    /// R(r) read from the table (zero beyond d_max), 1/mm².
    pub fn reflectance(&self, r: f32) -> [f32; 3] {
        if r > self.d_max {
            return [0.0; 3];
        }
        lookup(&self.density, r, self.d_max)
    }

    /// P = (1 − t)R + tT at a point, read from the tables (zero beyond
    /// d_max), 1/mm².
    pub fn point(&self, separation: Separation) -> [f32; 3] {
        let reflected = self.reflectance(separation.distance);
        let t = separation.t;
        if self.transmit_density.is_empty() || t <= 0.0 || separation.distance > self.d_max {
            return reflected;
        }
        let transmitted = lookup(&self.transmit_density, separation.across, self.d_max);
        [0, 1, 2].map(|c| (1.0 - t) * reflected[c] + t * transmitted[c])
    }

    /// The mean of R over the parallelogram with edges `u`, `v` centred on
    /// the point of exit (mm; 1/mm²): a texel's weight for its own light.
    /// In polar form ∫R dA = (1/2π)∫ E(ρ(φ)) dφ, with E the enclosed
    /// reflectance and ρ(φ) the distance to the edge in direction φ, so a
    /// profile sharper than the texel and one as wide as it are both exact.
    pub(super) fn parallelogram_mean(&self, u: glam::Vec3, v: glam::Vec3) -> [f32; 3] {
        let area = u.cross(v).length();
        if area.is_nan() || area <= 0.0 {
            return self.reflectance(0.0);
        }
        // Directions in the plane of u and v, each written as α u + β v.
        let (uu, uv, vv) = (u.dot(u), u.dot(v), v.dot(v));
        let e1 = u / uu.sqrt();
        let e2 = (v - e1 * e1.dot(v)).normalize_or_zero();
        let det = uu * vv - uv * uv;
        // The distance to the edge in every direction, a vector at a time
        // (component by component, as Vec3's own operations would).
        let (cos, sin) = directions();
        let mut rho = [0.0f32; ANGLES];
        for k in 0..ANGLES {
            let d = [0, 1, 2].map(|i| e1[i] * cos[k] + e2[i] * sin[k]);
            let du = d[0] * u.x + d[1] * u.y + d[2] * u.z;
            let dv = d[0] * v.x + d[1] * v.y + d[2] * v.z;
            let alpha = (vv * du - uv * dv) / det;
            let beta = (uu * dv - uv * du) / det;
            rho[k] = 0.5 / alpha.abs().max(beta.abs()).max(1e-30);
        }
        let mut sum = [0.0f32; 3];
        for rho in rho {
            let enclosed = lookup(&self.reflectance, rho, self.d_max);
            for c in 0..3 {
                sum[c] += enclosed[c];
            }
        }
        sum.map(|s| (s / ANGLES as f32 / area).max(0.0))
    }

    /// The means of R and of T over a disk of radius `a` whose centre is
    /// `d` from the point of entry (the 2-D convolution of the profile with
    /// the disk, so a sample's weight keeps the profile's integral however
    /// sharp the profile is against the sample spacing). Written as the
    /// Stieltjes sum Σ g(r) ΔE(r) over rings about the entry point, with
    /// g the share of each ring inside the disk: the enclosed tables carry
    /// the mass exactly, even of a profile narrower than the disk.
    pub(super) fn disk_mean(&self, d: f32, a: f32) -> [[f32; 3]; 2] {
        let area = std::f32::consts::PI * a * a;
        let mut out = [[0.0f32; 3]; 2];
        if area <= 0.0 {
            return [self.reflectance(d), self.point_transmittance(d)];
        }
        let lo = (d - a).abs();
        let hi = d + a;
        // The rings' edges, where each sits in the tables and each ring's
        // share of the disk depend on d and a alone: found once for R and T
        // (a slab's kernel has both; the share's arccosine is most of a
        // mean's cost).
        let spacing = ring_spacing();
        let mut edges = [Entry::default(); RINGS + 1];
        for (edge, &s) in edges.iter_mut().zip(spacing) {
            *edge = Entry::at(lo + (hi - lo) * 0.5 * s, self.d_max);
        }
        let mut shares = [0.0f32; RINGS];
        for (i, share) in shares.iter_mut().enumerate() {
            let mid = 0.5 * (edges[i].radius + edges[i + 1].radius);
            *share = super::disk_kernel::ring_share(mid, d, a);
        }
        let tables: [&[[f32; 3]]; 2] = [&self.reflectance, &self.transmittance];
        for (k, table) in tables.iter().enumerate() {
            if table.is_empty() {
                continue;
            }
            let mut sum = if d < a {
                lookup(table, lo, self.d_max)
            } else {
                [0.0; 3]
            };
            let mut previous = edges[0].read(table);
            for (edge, &g) in edges[1..].iter().zip(&shares) {
                let next = edge.read(table);
                for c in 0..3 {
                    sum[c] += g * (next[c] - previous[c]);
                }
                previous = next;
            }
            out[k] = sum.map(|v| (v / area).max(0.0));
        }
        out
    }

    /// T(r) read from the table (zero beyond d_max or without transmission).
    pub(super) fn point_transmittance(&self, r: f32) -> [f32; 3] {
        if self.transmit_density.is_empty() || r > self.d_max {
            return [0.0; 3];
        }
        lookup(&self.transmit_density, r, self.d_max)
    }

    /// Draws a radius in [0, d_max] for channel `c` with density
    /// ∝ 2πr R(r) by inverting the enclosed-reflectance table.
    pub fn sample_radius(&self, c: usize, xi: f32) -> f32 {
        let total = self.reflectance[ENTRIES - 1][c];
        if total.is_nan() || total <= 0.0 {
            return xi.sqrt() * self.d_max;
        }
        let target = xi.clamp(0.0, 1.0) * total;
        let k = self
            .reflectance
            .partition_point(|e| e[c] < target)
            .clamp(1, ENTRIES - 1);
        let (lo, hi) = (self.reflectance[k - 1][c], self.reflectance[k][c]);
        let f = if hi > lo {
            (target - lo) / (hi - lo)
        } else {
            0.5
        };
        let x = (k as f32 - 1.0 + f) / (ENTRIES - 1) as f32;
        self.d_max * x * x
    }
}

fn finite(v: [f64; 3]) -> [f32; 3] {
    v.map(|x| {
        if x.is_finite() {
            x.max(0.0) as f32
        } else {
            0.0
        }
    })
}

/// ∫_0^r 2πs f(s) ds by Simpson's rule in s = r x² (dense near 0).
fn enclosed(f: impl Fn(f64) -> f64, r: f64) -> f64 {
    let steps = 512;
    let g = |x: f64| {
        let s = r * x * x;
        2.0 * std::f64::consts::PI * s * f(s) * 2.0 * r * x
    };
    let h = 1.0 / steps as f64;
    let mut sum = g(0.0) + g(1.0);
    for i in 1..steps {
        sum += g(i as f64 * h) * if i % 2 == 1 { 4.0 } else { 2.0 };
    }
    sum * h / 3.0
}

/// Running ∫ 2πs f(s) ds over the table's radii, trapezoids in x.
fn cumulative(f: impl Fn(f64) -> [f64; 3], radius: &impl Fn(usize) -> f64) -> Vec<[f32; 3]> {
    let mut out = Vec::with_capacity(ENTRIES);
    let mut sum = [0.0f64; 3];
    let mut previous: Option<(f64, [f64; 3])> = None;
    for k in 0..ENTRIES {
        let r = radius(k);
        let v = f(r).map(|x| if x.is_finite() { x.max(0.0) } else { 0.0 });
        if let Some((r0, v0)) = previous {
            for c in 0..3 {
                sum[c] += std::f64::consts::PI * (r0 * v0[c] + r * v[c]) * (r - r0);
            }
        }
        previous = Some((r, v));
        out.push(sum.map(|x| x as f32));
    }
    out
}

/// Directions about a texel's centre for [`Kernel::parallelogram_mean`].
const ANGLES: usize = 64;

/// cos φ and sin φ of the [`ANGLES`] directions φ = (k + ½)·2π/ANGLES,
/// computed once rather than for every texel.
fn directions() -> &'static ([f32; ANGLES], [f32; ANGLES]) {
    static DIRECTIONS: OnceLock<([f32; ANGLES], [f32; ANGLES])> = OnceLock::new();
    DIRECTIONS.get_or_init(|| {
        let phi = |k: usize| (k as f32 + 0.5) * std::f32::consts::TAU / ANGLES as f32;
        (
            std::array::from_fn(|k| phi(k).cos()),
            std::array::from_fn(|k| phi(k).sin()),
        )
    })
}

/// Rings of [`Kernel::disk_mean`].
const RINGS: usize = 48;

/// 1 − cos(πi/RINGS) for i in 0..=RINGS: where the rings of a disk mean
/// lie between their ends (clustered at both), computed once rather than
/// for every ring of every mean.
fn ring_spacing() -> &'static [f32; RINGS + 1] {
    static SPACING: OnceLock<[f32; RINGS + 1]> = OnceLock::new();
    SPACING.get_or_init(|| {
        std::array::from_fn(|i| {
            let x = i as f32 / RINGS as f32;
            1.0 - (std::f32::consts::PI * x).cos()
        })
    })
}

/// Linear interpolation in a table indexed by √(r/d_max).
#[inline]
fn lookup(table: &[[f32; 3]], r: f32, d_max: f32) -> [f32; 3] {
    Entry::at(r, d_max).read(table)
}

/// Where a radius sits in the tables indexed by √(r/d_max): found once,
/// read from any of them.
#[derive(Clone, Copy, Default)]
struct Entry {
    /// The radius, mm.
    radius: f32,
    /// The entry below, or `None` for an empty kernel (every read zero).
    below: Option<usize>,
    /// The weight of the entry above.
    fraction: f32,
}

impl Entry {
    #[inline]
    fn at(r: f32, d_max: f32) -> Self {
        if d_max.is_nan() || d_max <= 0.0 {
            return Entry {
                radius: r,
                below: None,
                fraction: 0.0,
            };
        }
        let x = (r / d_max).clamp(0.0, 1.0).sqrt() * (ENTRIES - 1) as f32;
        let k = (x as usize).min(ENTRIES - 2);
        Entry {
            radius: r,
            below: Some(k),
            fraction: x - k as f32,
        }
    }

    #[inline]
    fn read(&self, table: &[[f32; 3]]) -> [f32; 3] {
        let Some(k) = self.below else {
            return [0.0; 3];
        };
        let (a, b) = (table[k], table[k + 1]);
        [0, 1, 2].map(|c| a[c] + (b[c] - a[c]) * self.fraction)
    }
}
