//! Colour maps: a texture sampled through its own UV set, transform, wrap
//! and filter, and the colour counted once (the profile built for the
//! map's nominal colour, the split relative to it).

mod lit_scenes;

use glam::{Vec2, Vec3};
use lit_scenes::*;
use sssbake::colour::{ColourTexture, UvTransform, Wrap, sample};
use sssbake::control::Control;
use sssbake::image::Image;
use sssbake::scene::Subsurface;
use sssbake::transport::Method;
use sssbake::{BakeRequest, MaterialHint, Output, Scene, bake, plan};
use std::sync::Arc;

/// A 2 × 1 image: left texel `left`, right texel `right`.
fn halves(left: [f32; 3], right: [f32; 3]) -> Image {
    Image::new(2, 1, vec![left, right]).unwrap()
}

fn texture(image: Image) -> ColourTexture {
    ColourTexture {
        material: "skin".into(),
        input: "baseColorTexture".into(),
        file: "test.png".into(),
        image: Ok(Arc::new(image)),
        colour_space: "sRGB".into(),
        uv_set: 0,
        uv_set_name: "TEXCOORD_0".into(),
        transform: None,
        wrap: [Wrap::Repeat; 2],
        nearest: true,
        scale: [1.0; 3],
        bias: [0.0; 3],
    }
}

/// A material of colour `colour` with a 1, 0.5, 0.25 mm mean free path.
fn hint(colour: [f64; 3]) -> MaterialHint {
    MaterialHint {
        name: "skin".into(),
        base_color: [1.0; 4],
        ior: Some(1.4),
        subsurface: Some(Subsurface {
            colour,
            mean_free_path_mm: [1.0, 0.5, 0.25],
            anisotropy: 0.0,
            from: "test".into(),
        }),
        ..MaterialHint::default()
    }
}

/// A 60 mm square under a sun, its material `material` and texture
/// `texture`.
fn square(material: MaterialHint, texture: Option<ColourTexture>) -> Scene {
    let mut scene = scene(
        vec![centred_square(60.0, "square")],
        vec![sun_from(Vec3::NEG_Z)],
    );
    scene.objects[0].material = Some(material);
    scene.objects[0].colour_texture = texture;
    scene
}

/// The subsurface map of `scene` at 32² (brute force), and the plan's
/// nominal colour.
fn bake_map(scene: &Scene, alpha: f32) -> (Vec<[f32; 3]>, Option<[f64; 3]>) {
    let request = BakeRequest {
        resolution: 32,
        margin: 0,
        outputs: vec![Output::Subsurface],
        method: Method::Brute,
        colour_split: alpha,
        ..BakeRequest::default()
    };
    let plan = plan(scene, &request).unwrap();
    let nominal = plan.objects[0].colour.nominal;
    let (baked, _) = bake(scene, &plan, &Control::new()).unwrap();
    (baked[0].render(Output::Subsurface).unwrap().texels, nominal)
}

#[test]
fn a_constant_texture_bakes_what_the_factor_bakes() {
    let c = [0.8, 0.45, 0.3];
    let (factor, _) = bake_map(&square(hint(c), None), 0.5);
    // The colour factor 1 times a texture of c, and a factor times c / factor.
    let constant = |value: [f64; 3]| Image::new(4, 4, vec![value.map(|v| v as f32); 16]).unwrap();
    let scale = [0.5f32, 0.9, 1.0];
    for (scene, what) in [
        (
            square(hint([1.0; 3]), Some(texture(constant(c)))),
            "factor 1",
        ),
        (
            square(
                hint(scale.map(f64::from)),
                Some(ColourTexture {
                    scale,
                    ..texture(constant([0, 1, 2].map(|k| c[k] / f64::from(scale[k]))))
                }),
            ),
            "factor × texture",
        ),
    ] {
        for alpha in [0.0, 0.5, 1.0] {
            let (textured, nominal) = bake_map(&scene, alpha);
            let m = nominal.unwrap();
            assert!((0..3).all(|k| (m[k] / c[k] - 1.0).abs() < 1e-6), "{m:?}");
            let (reference, _) = bake_map(&square(hint(c), None), alpha);
            for (t, r) in textured.iter().zip(&reference) {
                for k in 0..3 {
                    let (t, r): (f32, f32) = (t[k], r[k]);
                    assert!(t.is_finite() && r.is_finite());
                    assert!(
                        (t - r).abs() <= 1e-5 * r.abs().max(1e-12),
                        "{what}, α {alpha}: {t} vs {r}"
                    );
                }
            }
        }
    }
    assert!(factor.iter().flatten().any(|v| *v > 0.0));
}

/// The mean of `map` over the texels with x in `columns`, rows 8..24.
fn mean_over(map: &[[f32; 3]], columns: std::ops::Range<usize>) -> [f64; 3] {
    let mut sum = [0.0; 3];
    let mut n = 0.0;
    for y in 8..24 {
        for x in columns.clone() {
            for k in 0..3 {
                sum[k] += f64::from(map[y * 32 + x][k]);
            }
            n += 1.0;
        }
    }
    sum.map(|s| s / n)
}

#[test]
fn a_two_colour_texture_bakes_two_halves_and_the_split_moves_only_the_edge() {
    let (left, right) = ([0.8, 0.3, 0.2], [0.3, 0.6, 0.7]);
    let scene = square(hint([1.0; 3]), Some(texture(halves(left, right))));
    let (half, m) = bake_map(&scene, 0.5);
    let m = m.unwrap();
    for k in 0..3 {
        assert!(
            (m[k] - f64::from(left[k] + right[k]) / 2.0).abs() < 1e-3,
            "{m:?}"
        );
    }
    let (l, r) = (mean_over(&half, 2..12), mean_over(&half, 20..30));
    for k in 0..3 {
        // Deep in each half, the exitance is in the ratio of the colours
        // (within what the 2 mm reach of the red channel carries over).
        let ratio = l[k] / r[k];
        let expected = f64::from(left[k] / right[k]);
        assert!(
            (ratio / expected - 1.0).abs() < 0.1,
            "channel {k}: {ratio} vs {expected}"
        );
    }
    // α = 0 and α = 1 agree deep in each half and differ at the edge.
    let (before, _) = bake_map(&scene, 1.0);
    let (after, _) = bake_map(&scene, 0.0);
    for columns in [2..12, 20..30] {
        let (b, a) = (
            mean_over(&before, columns.clone()),
            mean_over(&after, columns),
        );
        for k in 1..3 {
            assert!((b[k] / a[k] - 1.0).abs() < 0.05, "{b:?} vs {a:?}");
        }
    }
    // At the edge, colour after scattering (α = 0) keeps it sharp: the
    // texel just left of it takes the left colour's share whole.
    let edge = |map: &[[f32; 3]]| map[16 * 32 + 15][0] / map[16 * 32 + 16][0];
    assert!(
        edge(&after) > edge(&before),
        "{} {}",
        edge(&after),
        edge(&before)
    );
    for map in [&half, &before, &after] {
        assert!(map.iter().flatten().all(|v| v.is_finite() && *v >= 0.0));
    }
}

#[test]
fn black_and_white_channels_stay_finite() {
    // Red black everywhere, green white everywhere, blue black on one half.
    let scene = square(
        hint([1.0; 3]),
        Some(texture(halves([0.0, 1.0, 0.0], [0.0, 1.0, 0.5]))),
    );
    for alpha in [0.0, 0.5, 1.0] {
        let (map, m) = bake_map(&scene, alpha);
        let m = m.unwrap();
        assert_eq!(m[0], 0.0);
        assert!(map.iter().flatten().all(|v| v.is_finite() && *v >= 0.0));
        assert!(
            map.iter().all(|t| t[0] == 0.0),
            "a black channel bakes black"
        );
        assert!(map.iter().any(|t| t[1] > 0.0));
        assert!(mean_over(&map, 2..12)[2] < 1e-3 * mean_over(&map, 20..30)[2]);
    }
}

#[test]
fn the_texture_reads_its_own_uv_set() {
    // Set 1 mirrors u: the texture's left half lands on the square's right.
    let mut scene = square(hint([1.0; 3]), None);
    let mirrored: Vec<Vec2> = scene.objects[0].uv_sets[0]
        .iter()
        .map(|uv| Vec2::new(1.0 - uv.x, uv.y))
        .collect();
    scene.objects[0].uv_sets.push(mirrored);
    let (left, right) = ([0.8, 0.3, 0.2], [0.3, 0.6, 0.7]);
    let by_set = |set: usize| {
        let mut scene = scene.clone();
        scene.objects[0].colour_texture = Some(ColourTexture {
            uv_set: set,
            ..texture(halves(left, right))
        });
        bake_map(&scene, 0.5).0
    };
    let (zero, one) = (by_set(0), by_set(1));
    let (z, o) = (mean_over(&zero, 2..12), mean_over(&one, 20..30));
    for k in 0..3 {
        assert!((z[k] / o[k] - 1.0).abs() < 1e-3, "{z:?} vs {o:?}");
    }
    assert!(mean_over(&zero, 2..12)[0] > 1.5 * mean_over(&one, 2..12)[0]);
    // A set the object lacks is an error naming the file, material and set.
    let mut missing = scene.clone();
    missing.objects[0].colour_texture = Some(ColourTexture {
        uv_set: 5,
        uv_set_name: "TEXCOORD_5".into(),
        ..texture(halves(left, right))
    });
    let message = plan(&missing, &BakeRequest::default())
        .err()
        .unwrap()
        .to_string();
    for word in ["test.png", "`skin`", "TEXCOORD_5", "square"] {
        assert!(message.contains(word), "{message}");
    }
    // So is an image that could not be read.
    let mut unreadable = scene;
    unreadable.objects[0].colour_texture = Some(ColourTexture {
        image: Err("cannot decode the image: truncated".into()),
        ..texture(halves(left, right))
    });
    let message = plan(&unreadable, &BakeRequest::default())
        .err()
        .unwrap()
        .to_string();
    for word in ["test.png", "`skin`", "truncated", "baseColorTexture"] {
        assert!(message.contains(word), "{message}");
    }
}

#[test]
fn sampling_wraps_filters_and_transforms() {
    // 2 × 2: rows top to bottom, so (0, 0) is the bottom-left texel.
    let image = Image::new(
        2,
        2,
        vec![[0.0; 3], [1.0; 3], [2.0; 3], [3.0; 3]], // top: 0 1, bottom: 2 3
    )
    .unwrap();
    let at = |u: f32, v: f32, wrap: Wrap, nearest: bool| {
        sample(&image, Vec2::new(u, v), [wrap; 2], nearest)[0]
    };
    // Texel centres.
    assert_eq!(at(0.25, 0.25, Wrap::Repeat, false), 2.0);
    assert_eq!(at(0.75, 0.75, Wrap::Repeat, false), 1.0);
    // Bilinear halfway between the bottom two.
    assert!((at(0.5, 0.25, Wrap::Clamp, false) - 2.5).abs() < 1e-6);
    // Nearest.
    assert_eq!(at(0.6, 0.3, Wrap::Repeat, true), 3.0);
    // Outside [0, 1]: repeat, mirror, clamp, black.
    assert_eq!(at(1.25, 0.25, Wrap::Repeat, true), 2.0);
    assert_eq!(at(1.25, 0.25, Wrap::Mirror, true), 3.0);
    assert_eq!(at(1.25, 0.25, Wrap::Clamp, true), 3.0);
    assert_eq!(at(1.25, 0.25, Wrap::Black, true), 0.0);
    assert_eq!(at(-0.25, 0.25, Wrap::Mirror, true), 2.0);
    assert_eq!(at(-0.75, 0.25, Wrap::Mirror, true), 3.0);
    // Bilinear across the repeat seam blends the two edges.
    assert!((at(0.0, 0.25, Wrap::Repeat, false) - 2.5).abs() < 1e-6);
    assert!((at(0.0, 0.25, Wrap::Clamp, false) - 2.0).abs() < 1e-6);

    // KHR_texture_transform in glTF's v-down space: offset and scale.
    let gltf = UvTransform::Gltf {
        offset: Vec2::new(0.5, 0.25),
        rotation: 0.0,
        scale: Vec2::new(2.0, 0.5),
    };
    // sssbake (0.1, 0.8) is glTF (0.1, 0.2) → (0.7, 0.35) → sssbake (0.7, 0.65).
    assert!(
        gltf.apply(Vec2::new(0.1, 0.8))
            .abs_diff_eq(Vec2::new(0.7, 0.65), 1e-6)
    );
    // A quarter turn: glTF's rotation turns (1, 0) to (0, −1) in v-down space.
    let turn = UvTransform::Gltf {
        offset: Vec2::ZERO,
        rotation: std::f32::consts::FRAC_PI_2,
        scale: Vec2::ONE,
    };
    // sssbake (1, 1) is glTF (1, 0) → (0, −1) → sssbake (0, 2).
    assert!(
        turn.apply(Vec2::new(1.0, 1.0))
            .abs_diff_eq(Vec2::new(0.0, 2.0), 1e-6)
    );
    // UsdTransform2d: scale, rotate counter-clockwise (degrees), translate.
    let usd = UvTransform::Usd {
        translation: Vec2::new(0.5, 0.0),
        rotation_degrees: 90.0,
        scale: Vec2::new(2.0, 1.0),
    };
    // (0.25, 0.5) → (0.5, 0.5) → (−0.5, 0.5) → (0, 0.5).
    assert!(
        usd.apply(Vec2::new(0.25, 0.5))
            .abs_diff_eq(Vec2::new(0.0, 0.5), 1e-6)
    );
}
