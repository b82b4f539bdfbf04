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
use sssbake_profile::models::monte_carlo::{Settings, simulate};

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

/// A 10 mm cube with every texel lit by `value`.
fn lit_cube() -> (Mesh, Vec<Vec2>, Vec<[f32; 3]>) {
    let mut builder = BoxBuilder::new();
    builder.cuboid(Vec3::ZERO, Vec3::splat(5.0), TOP_UV, SIDE_UV);
    let (mesh, uvs) = builder.mesh();
    (mesh, uvs, vec![[1.0; 3]; (MAP * MAP) as usize])
}

#[test]
fn the_standard_error_falls_as_one_over_the_root_of_the_walks_and_states_the_spread() {
    let (mesh, uvs) = slab(100.0);
    let light = top_lit(1.0);
    let point = [(Vec3::new(0.7, 0.3, 0.0), Vec3::Z)];
    let run = |walks: u32, seed: u64| {
        let settings = WalkSettings {
            walks,
            max_events: 100_000,
            seed,
            start: StartDirection::Diffuse,
        };
        walk_at(&mesh, &uvs, &light, &medium(1.4), &point, &settings)
    };
    let (few, many) = (run(1000, 1), run(4000, 2));
    for c in 0..3 {
        let ratio = many.standard_error[0][c] / few.standard_error[0][c];
        assert!(
            (0.4..0.6).contains(&ratio),
            "channel {c}: 4× the walks gave {ratio}× the error"
        );
    }
    // The stated error is the spread of independent estimates: 24 seeds.
    let runs: Vec<WalkEstimate> = (0..24).map(|seed| run(250, 100 + seed)).collect();
    for c in 0..3 {
        let values: Vec<f64> = runs.iter().map(|r| r.exitance[0][c] as f64).collect();
        let mean = values.iter().sum::<f64>() / values.len() as f64;
        let spread = (values.iter().map(|v| (v - mean).powi(2)).sum::<f64>()
            / (values.len() - 1) as f64)
            .sqrt();
        let stated = runs
            .iter()
            .map(|r| r.standard_error[0][c] as f64)
            .sum::<f64>()
            / 24.0;
        // 24 samples know a standard deviation to about 15 %.
        assert!(
            (0.6..1.5).contains(&(spread / stated)),
            "channel {c}: spread {spread} of 24 runs, stated {stated}"
        );
    }
}

#[test]
fn no_light_crosses_the_air_between_two_pieces_of_one_mesh() {
    // Two 10 mm boxes 1 mm apart: the left one's faces in the lit left
    // half of the map, the right one's in the dark right half.
    let mut builder = BoxBuilder::new();
    let half = Vec3::new(5.25, 5.0, 5.0);
    builder.cuboid(
        Vec3::new(-5.75, 0.0, -5.0),
        half,
        [Vec2::new(0.05, 0.05), Vec2::new(0.45, 0.45)],
        [Vec2::new(0.05, 0.55), Vec2::new(0.45, 0.95)],
    );
    builder.cuboid(
        Vec3::new(5.75, 0.0, -5.0),
        half,
        [Vec2::new(0.55, 0.05), Vec2::new(0.95, 0.45)],
        [Vec2::new(0.55, 0.55), Vec2::new(0.95, 0.95)],
    );
    let (mesh, uvs) = builder.mesh();
    let light: Vec<[f32; 3]> = (0..MAP * MAP)
        .map(|t| if t % MAP < 2 { [1.0; 3] } else { [0.0; 3] })
        .collect();
    // Far-reaching, hardly absorbing: across air the light would arrive.
    let medium = |ior| WalkMedium {
        channels: [ChannelMedium::new(0.001, 1.0, 0.0); 3],
        boundary: Boundary::of_index(ior),
    };
    let points = [
        (Vec3::new(0.5, 0.2, -5.0), Vec3::NEG_X), // dark box, facing the gap
        (Vec3::new(5.75, 0.2, 0.0), Vec3::Z),     // dark box, top
        (Vec3::new(-0.5, 0.2, -5.0), Vec3::X),    // lit box, facing the gap
    ];
    for ior in [1.0, 1.4] {
        let settings = WalkSettings {
            walks: 2000,
            max_events: 10_000,
            seed: 3,
            start: StartDirection::Diffuse,
        };
        let walked = walk_at(&mesh, &uvs, &light, &medium(ior), &points, &settings);
        for k in 0..2 {
            assert_eq!(walked.exitance[k], [0.0; 3], "η {ior}: point {k}");
            assert_eq!(walked.standard_error[k], [0.0; 3]);
        }
        assert!(
            walked.exitance[2].iter().all(|&m| m > 0.5),
            "η {ior}: the lit box glows {:?}",
            walked.exitance[2]
        );
        assert_eq!(walked.lost, [0.0; 3], "η {ior}: walks escaped the boxes");
    }
}

#[test]
fn a_lossless_medium_returns_all_the_light_it_is_lit_by() {
    // Lit everywhere with 1 and absorbing nothing, every walk leaves with
    // its start weight: index-matched, each scores exactly 1; through a
    // dielectric the diffuse start's weight (1 − F)/(1 − F_dr) has mean 1.
    let (mesh, uvs, light) = lit_cube();
    let points = [(Vec3::new(0.3, 0.7, 5.0), Vec3::Z)];
    for ior in [1.0, 1.4] {
        let settings = WalkSettings {
            walks: 4000,
            max_events: 1_000_000,
            seed: 5,
            start: StartDirection::Diffuse,
        };
        let medium = WalkMedium {
            channels: [0.1, 1.0, 10.0].map(|s| ChannelMedium::new(0.0, s, 0.3)),
            boundary: Boundary::of_index(ior),
        };
        let walked = walk_at(&mesh, &uvs, &light, &medium, &points, &settings);
        assert_eq!(walked.truncated, [0.0; 3]);
        for c in 0..3 {
            let (m, e) = (walked.exitance[0][c], walked.standard_error[0][c]);
            if ior == 1.0 {
                assert_eq!((m, e), (1.0, 0.0), "channel {c}");
            } else {
                assert!((m - 1.0).abs() <= 4.0 * e, "η {ior} channel {c}: {m} ± {e}");
            }
        }
    }
}

#[test]
fn extreme_media_give_finite_bounded_exitance_within_the_event_bound() {
    let (mesh, uvs, light) = lit_cube();
    let points = [
        (Vec3::new(0.3, 0.7, 5.0), Vec3::Z),
        (Vec3::new(5.0, 0.2, -0.4), Vec3::X),
    ];
    let settings = WalkSettings {
        walks: 64,
        max_events: 200,
        seed: 9,
        start: StartDirection::Diffuse,
    };
    for ior in [1.0, 1.4, 3.0] {
        let boundary = Boundary::of_index(ior);
        // The largest score one walk can carry (lit by 1).
        let largest = 1.0 / (1.0 - boundary.diffuse_reflectance());
        for sigma_t in [0.0, 1e-6, 1.0, 1e4] {
            for albedo in [0.0, 1e-6, 0.5, 1.0 - 1e-9, 1.0] {
                let medium = WalkMedium {
                    channels: [
                        ChannelMedium::new(sigma_t * (1.0 - albedo), sigma_t * albedo, 0.0),
                        ChannelMedium::new(sigma_t * (1.0 - albedo), sigma_t * albedo, 0.95),
                        ChannelMedium::new(sigma_t * (1.0 - albedo), sigma_t * albedo, -0.95),
                    ],
                    boundary,
                };
                let walked = walk_at(&mesh, &uvs, &light, &medium, &points, &settings);
                let case = format!("η {ior}, σt {sigma_t}, albedo {albedo}");
                assert!(
                    walked.events <= walked.walks * settings.max_events as u64,
                    "{case}"
                );
                for (m, e) in walked.exitance.iter().zip(&walked.standard_error) {
                    for c in 0..3 {
                        assert!(m[c].is_finite() && m[c] >= 0.0, "{case}: {m:?}");
                        assert!(m[c] as f64 <= largest + 1e-6, "{case}: {m:?}");
                        // Energy: lit by 1, no more than 1 leaves.
                        assert!(m[c] <= 1.0 + 4.0 * e[c] + 1e-6, "{case}: {m:?} ± {e:?}");
                    }
                }
                for c in 0..3 {
                    let dropped = walked.truncated[c] + walked.lost[c];
                    assert!(
                        (0.0..=largest).contains(&dropped),
                        "{case}: dropped {dropped}"
                    );
                }
            }
        }
    }
}

/// The empirical model's light, from its own simulation of exitant
/// hemispheres and the lobes fitted to them, against the walk, which
/// shares none of its transport (its own steps, phase sampling, Fresnel
/// and geometry, in a mesh): the total reflectance of the thick dielectric
/// slab's three media within 1.5% and the two codes' noise (0.1–0.4%
/// apart).
#[test]
fn the_empirical_model_returns_the_light_of_the_walk() {
    use sssbake_profile::material::{Material, Optics, TopLayer};
    use sssbake_profile::models::empirical::{EmpiricalProfile, EmpiricalSettings};
    use sssbake_profile::profile::Profile;
    let material = Material {
        name: "walk's media".into(),
        optics: Optics::Layers(vec![layer(1.4, None)]),
        coat_ior: None,
        top_layer: TopLayer::Diffusion,
        roughness: 0.0,
    };
    let settings = EmpiricalSettings {
        photons: 100_000,
        seed: 3,
        ..EmpiricalSettings::default()
    };
    let empirical = EmpiricalProfile::simulate(&material, &settings).unwrap();
    let (mesh, uvs) = slab(100.0);
    let walk_settings = WalkSettings {
        walks: 20_000,
        max_events: 100_000,
        seed: 9,
        start: StartDirection::Pencil,
    };
    let points = [(Vec3::new(0.7, 0.3, 0.0), Vec3::Z)];
    let walked = walk_at(
        &mesh,
        &uvs,
        &top_lit(1.0),
        &medium(1.4),
        &points,
        &walk_settings,
    );
    for (c, model) in empirical.total_reflectance().into_iter().enumerate() {
        let walk = walked.exitance[0][c] as f64;
        let noise = (walked.standard_error[0][c] as f64)
            .hypot(empirical.slices()[c].simulated_total_stderr);
        eprintln!(
            "channel {c}: empirical {model:.5}, walk {walk:.5} ± {:.5}",
            walked.standard_error[0][c]
        );
        assert!(
            (model - walk).abs() <= 0.015 * walk + 3.0 * noise,
            "channel {c}: empirical {model} vs walk {walk} (noise {noise})"
        );
    }
}
