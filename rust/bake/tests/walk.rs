//! The volumetric random walk against the slab Monte Carlo, its noise, its
//! confinement to the medium, and extreme media.

use glam::{Vec2, Vec3};
use sssbake::Mesh;
use sssbake::control::Control;
use sssbake::walk::{
    Boundary, ChannelMedium, Enclosure, ExitLight, StartDirection, WalkEstimate, WalkMedium,
    WalkSettings, WalkTargets, walk_exitance,
};
use sssbake_profile::material::Layer;
use sssbake_profile::monte_carlo::{Settings, simulate};

/// Texels of the light map the box faces fall in (a 4 × 4 map): the top
/// face covers texels x, y ∈ {0, 1}, the bottom x ∈ {2, 3}, y ∈ {0, 1},
/// the sides y ∈ {2, 3}.
const MAP: u32 = 4;

/// Appends an axis-aligned box (`centre`, half extents, mm) to the buffers,
/// one quad per face with its own UV rectangle: top face at `top_uv`,
/// bottom at `bottom_uv`, each side in a strip of `side_uv`.
struct BoxBuilder {
    positions: Vec<Vec3>,
    uvs: Vec<Vec2>,
    triangles: Vec<[u32; 3]>,
}

impl BoxBuilder {
    fn new() -> Self {
        BoxBuilder {
            positions: Vec::new(),
            uvs: Vec::new(),
            triangles: Vec::new(),
        }
    }

    /// A quad centred at `c` spanning ±u, ±v, facing u × v, with UVs in
    /// [lo, hi].
    fn quad(&mut self, c: Vec3, u: Vec3, v: Vec3, lo: Vec2, hi: Vec2) {
        let base = self.positions.len() as u32;
        for (su, sv) in [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)] {
            self.positions.push(c + su * u + sv * v);
            let t = Vec2::new((su + 1.0) / 2.0, (sv + 1.0) / 2.0);
            self.uvs.push(lo + (hi - lo) * t);
        }
        self.triangles.push([base, base + 1, base + 2]);
        self.triangles.push([base, base + 2, base + 3]);
    }

    /// A box whose top face lies in UV rectangle `top` and every other
    /// face in `rest` (split into five strips).
    fn cuboid(&mut self, centre: Vec3, half: Vec3, top: [Vec2; 2], rest: [Vec2; 2]) {
        let (x, y, z) = (Vec3::X * half.x, Vec3::Y * half.y, Vec3::Z * half.z);
        self.quad(centre + z, x, y, top[0], top[1]);
        let strip = |k: f32| {
            let width = (rest[1].x - rest[0].x) / 5.0;
            let lo = Vec2::new(rest[0].x + k * width + 0.01, rest[0].y);
            [lo, Vec2::new(lo.x + width - 0.02, rest[1].y)]
        };
        let faces = [
            (centre - z, y, x),
            (centre + x, y, z),
            (centre - x, z, y),
            (centre + y, z, x),
            (centre - y, x, z),
        ];
        for (k, (c, u, v)) in faces.into_iter().enumerate() {
            let [lo, hi] = strip(k as f32);
            self.quad(c, u, v, lo, hi);
        }
    }

    fn mesh(self) -> (Mesh, Vec<Vec2>) {
        let uvs = self.uvs.clone();
        let (mesh, _) = Mesh::new("box", self.positions, None, Some(self.uvs), self.triangles)
            .expect("a valid box");
        (mesh, uvs)
    }
}

const TOP_UV: [Vec2; 2] = [Vec2::new(0.05, 0.05), Vec2::new(0.45, 0.45)];
const BOTTOM_UV: [Vec2; 2] = [Vec2::new(0.55, 0.05), Vec2::new(0.95, 0.45)];
const SIDE_UV: [Vec2; 2] = [Vec2::new(0.05, 0.55), Vec2::new(0.95, 0.95)];

/// A 200 mm square slab `thickness` mm thick, top face at z = 0. Its top
/// and bottom face get UV rectangles of their own; the sides share the
/// rest (the bottom strip of `rest` is unused).
fn slab(thickness: f32) -> (Mesh, Vec<Vec2>) {
    let mut builder = BoxBuilder::new();
    let half = Vec3::new(100.0, 100.0, thickness / 2.0);
    // The bottom face is the first of `rest`'s five strips: give it its
    // own rectangle by building it apart.
    builder.cuboid(Vec3::new(0.0, 0.0, -thickness / 2.0), half, TOP_UV, SIDE_UV);
    // Move the bottom face's UVs (quad 1, vertices 4..8) to BOTTOM_UV.
    for (k, t) in [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)]
        .iter()
        .enumerate()
    {
        builder.uvs[4 + k] = BOTTOM_UV[0] + (BOTTOM_UV[1] - BOTTOM_UV[0]) * Vec2::new(t.0, t.1);
    }
    builder.mesh()
}

/// A 4 × 4 light map with `value` on the top face's texels only.
fn top_lit(value: f32) -> Vec<[f32; 3]> {
    (0..MAP * MAP)
        .map(|t| {
            if t % MAP < 2 && t / MAP < 2 {
                [value; 3]
            } else {
                [0.0; 3]
            }
        })
        .collect()
}

/// The triangle of `mesh` that holds `point` (on its plane).
fn triangle_at(mesh: &Mesh, point: Vec3) -> u32 {
    mesh.triangles
        .iter()
        .position(|t| {
            let [a, b, c] = t.map(|v| mesh.positions[v as usize]);
            let n = (b - a).cross(c - a);
            let inside = |p: Vec3, q: Vec3| (q - p).cross(point - p).dot(n) >= -1e-6;
            (point - a).dot(n.normalize()).abs() < 1e-4
                && inside(a, b)
                && inside(b, c)
                && inside(c, a)
        })
        .expect("the point lies on the mesh") as u32
}

/// Walks from each (point, outward normal) of `mesh`.
fn walk_at(
    mesh: &Mesh,
    uvs: &[Vec2],
    light: &[[f32; 3]],
    medium: &WalkMedium,
    points: &[(Vec3, Vec3)],
    settings: &WalkSettings,
) -> WalkEstimate {
    let enclosure = Enclosure::new(mesh, uvs);
    let position: Vec<Vec3> = points.iter().map(|p| p.0).collect();
    let normal: Vec<Vec3> = points.iter().map(|p| p.1).collect();
    let triangle: Vec<u32> = position.iter().map(|&p| triangle_at(mesh, p)).collect();
    walk_exitance(
        &enclosure,
        &ExitLight {
            irradiance: light,
            resolution: MAP,
        },
        medium,
        &WalkTargets {
            position: &position,
            normal: &normal,
            triangle: &triangle,
        },
        settings,
        &Control::new(),
    )
    .expect("not cancelled")
}

/// Three media, one per channel, sharing g = 0.5 (σa, σs in 1/mm): a
/// reach of about 4 mm at high albedo, a dark one, and a far-reaching one.
const SIGMA_A: [f64; 3] = [0.02, 0.3, 0.004];
const SIGMA_S: [f64; 3] = [2.0, 2.0, 0.6];
const G: f64 = 0.5;

fn layer(ior: f64, thickness_mm: Option<f64>) -> Layer {
    Layer {
        sigma_a: SIGMA_A,
        sigma_s: SIGMA_S,
        g: G,
        ior,
        thickness_mm,
    }
}

fn medium(ior: f64) -> WalkMedium {
    WalkMedium {
        channels: [0, 1, 2].map(|c| ChannelMedium::new(SIGMA_A[c], SIGMA_S[c], G)),
        boundary: Boundary::of_index(ior),
    }
}

/// The pencil-started walk at the top centre (R) and bottom centre (T) of
/// a slab `thickness` mm thick, top lit uniformly, against the slab Monte
/// Carlo's totals at normal incidence for the same layer. Both count the
/// flux leaving into air per unit entering (the MC's diffuse totals plus
/// its unscattered ones, since the walk's score does not ask whether a
/// walk scattered). The walk enters the bottom going up and leaves by the
/// lit top: the slab is symmetric, so that is the MC's T.
fn compare_with_slab_monte_carlo(thickness: f64, ior: f64) {
    let (mesh, uvs) = slab(thickness as f32);
    let light = top_lit(1.0);
    let settings = WalkSettings {
        walks: 20_000,
        max_events: 100_000,
        seed: 7,
        start: StartDirection::Pencil,
    };
    let points = [
        (Vec3::new(0.7, 0.3, 0.0), Vec3::Z),
        (Vec3::new(0.3, 0.7, -thickness as f32), Vec3::NEG_Z),
    ];
    let walked = walk_at(&mesh, &uvs, &light, &medium(ior), &points, &settings);
    let photons = 200_000;
    let mc = simulate(
        &[layer(ior, Some(thickness))],
        &Settings::new(photons, 11, vec![0.0, 1.0]),
    );
    for c in 0..3 {
        assert!(walked.truncated[c] < 1e-6 && walked.lost[c] < 1e-6);
        // The unscattered tallies carry weight 1 each: binomial noise.
        let binomial = |p: f64| (p * (1.0 - p) / photons as f64).sqrt();
        let expected = [
            (
                mc.total_reflectance[c] + mc.unscattered_reflectance[c],
                mc.total_reflectance_stderr[c].hypot(binomial(mc.unscattered_reflectance[c])),
            ),
            (
                mc.total_transmittance[c] + mc.unscattered_transmittance[c],
                mc.total_transmittance_stderr[c].hypot(binomial(mc.unscattered_transmittance[c])),
            ),
        ];
        for (k, (value, mc_error)) in expected.into_iter().enumerate() {
            let walk = walked.exitance[k][c] as f64;
            let noise = (walked.standard_error[k][c] as f64).hypot(mc_error);
            let face = ["top (R)", "bottom (T)"][k];
            eprintln!(
                "d {thickness} η {ior} channel {c} {face}: walk {walk:.5} ± {:.5}, MC {value:.5} ± {mc_error:.5}",
                walked.standard_error[k][c]
            );
            assert!(
                (walk - value).abs() <= 4.0 * noise,
                "d {thickness} mm, η {ior}, channel {c}, {face}: walk {walk} vs MC {value} (noise {noise})"
            );
        }
    }
}

#[test]
fn a_thick_index_matched_slab_reflects_as_the_slab_monte_carlo() {
    compare_with_slab_monte_carlo(100.0, 1.0);
}

#[test]
fn a_thick_dielectric_slab_reflects_as_the_slab_monte_carlo() {
    compare_with_slab_monte_carlo(100.0, 1.4);
}

#[test]
fn a_thin_index_matched_slab_reflects_and_transmits_as_the_slab_monte_carlo() {
    compare_with_slab_monte_carlo(4.0, 1.0);
}

#[test]
fn a_thin_dielectric_slab_reflects_and_transmits_as_the_slab_monte_carlo() {
    compare_with_slab_monte_carlo(4.0, 1.4);
}
