//! Several materials on one object and a base-colour image through the C
//! ABI: each texel shows the bake of its own face's material, a material
//! without subsurface leaves its faces empty, an image is read through the
//! UV set it names, a constant image bakes as the same colour without one,
//! and every malformed array is refused with a message.

mod plain_light;

use plain_light::light;
use sssbake_ffi::*;
use std::ffi::{CStr, CString};
use std::ptr::{null, null_mut};

fn last_error() -> String {
    unsafe { CStr::from_ptr(sssbake_last_error()) }
        .to_string_lossy()
        .into_owned()
}

const N: u32 = 8;
const SIDE_MM: f32 = 40.0;
const RESOLUTION: u32 = 32;

/// A flat N × N grid of quads, SIDE_MM across in x and y, facing +z, UVs
/// from its corner (u along x, v along y); the second UV set is the first
/// mirrored in u. Quads in the lower left and upper right quarters have
/// material 0, the rest 1.
struct Grid {
    positions: Vec<f32>,
    normals: Vec<f32>,
    uvs: Vec<f32>,
    mirrored: Vec<f32>,
    indices: Vec<u32>,
    materials: Vec<u32>,
}

fn grid() -> Grid {
    let mut g = Grid {
        positions: vec![],
        normals: vec![],
        uvs: vec![],
        mirrored: vec![],
        indices: vec![],
        materials: vec![],
    };
    for j in 0..=N {
        for i in 0..=N {
            let (u, v) = (i as f32 / N as f32, j as f32 / N as f32);
            g.positions
                .extend([(u - 0.5) * SIDE_MM, (v - 0.5) * SIDE_MM, 0.0]);
            g.normals.extend([0.0, 0.0, 1.0]);
            g.uvs.extend([u, v]);
            g.mirrored.extend([1.0 - u, v]);
        }
    }
    for j in 0..N {
        for i in 0..N {
            let a = j * (N + 1) + i;
            let (b, c, d) = (a + 1, a + N + 1, a + N + 2);
            g.indices.extend([a, b, d, a, d, c]);
            let m = u32::from((i >= N / 2) != (j >= N / 2));
            g.materials.extend([m, m]);
        }
    }
    g
}

struct Scene(*mut SssbakeScene);

impl Drop for Scene {
    fn drop(&mut self) {
        sssbake_scene_free(self.0);
    }
}

/// The grid as "Grid" under a sun straight down (1 W/m²), in mm.
fn scene(g: &Grid) -> Scene {
    let mut scene = null_mut();
    assert_eq!(
        unsafe { sssbake_scene_new(1.0, &mut scene) },
        SssbakeStatus::Ok
    );
    let name = CString::new("Grid").unwrap();
    let mesh = SssbakeMesh {
        name: name.as_ptr(),
        positions: g.positions.as_ptr(),
        normals: g.normals.as_ptr(),
        uvs: g.uvs.as_ptr(),
        vertex_count: g.positions.len() / 3,
        indices: g.indices.as_ptr(),
        index_count: g.indices.len(),
        material_indices: g.materials.as_ptr(),
        texture_uvs: g.mirrored.as_ptr(),
        texture_uv_count: 1,
    };
    assert_eq!(
        unsafe { sssbake_scene_add_mesh(scene, &mesh) },
        SssbakeStatus::Ok,
        "{}",
        last_error()
    );
    let sun = light(SSSBAKE_LIGHT_SUN, 1.0);
    assert_eq!(
        unsafe { sssbake_scene_add_light(scene, &sun) },
        SssbakeStatus::Ok
    );
    Scene(scene)
}

/// A Random Walk Principled of `colour`, 1 mm radius, IOR 1.4.
fn principled(name: &CString, colour: [f32; 3]) -> SssbakeMaterial {
    SssbakeMaterial {
        kind: SSSBAKE_MATERIAL_PRINCIPLED,
        name: name.as_ptr(),
        base_colour: colour,
        subsurface_weight: 1.0,
        radius: [1.0, 0.5, 0.25],
        scale: 4.0,
        ior: 1.4,
        ..SssbakeMaterial::default()
    }
}

/// The bake's subsurface map (RGBA rows from v = 0 up) and its summary, or
/// the failing status.
fn bake(scene: &Scene, materials: &[SssbakeMaterial]) -> Result<(Vec<f32>, String), SssbakeStatus> {
    let object = CString::new("Grid").unwrap();
    let mut settings = std::mem::MaybeUninit::uninit();
    assert_eq!(
        unsafe { sssbake_settings_default(settings.as_mut_ptr()) },
        SssbakeStatus::Ok
    );
    let settings = SssbakeSettings {
        resolution: RESOLUTION,
        method: 1,
        margin: 2,
        outputs: 1,
        ..unsafe { settings.assume_init() }
    };
    let mut result = null_mut();
    let status = unsafe {
        sssbake_bake_materials(
            scene.0,
            object.as_ptr(),
            materials.as_ptr(),
            materials.len(),
            &settings,
            None,
            null_mut(),
            null(),
            &mut result,
        )
    };
    if status != SssbakeStatus::Ok {
        assert!(result.is_null());
        return Err(status);
    }
    let n = RESOLUTION as usize;
    let mut pixels = vec![0.0f32; 4 * n * n];
    let copied = unsafe { sssbake_result_image(result, 0, pixels.as_mut_ptr(), pixels.len()) };
    assert_eq!(copied, SssbakeStatus::Ok, "{}", last_error());
    let summary = unsafe { CStr::from_ptr(sssbake_result_summary(result)) }
        .to_string_lossy()
        .into_owned();
    assert_eq!(sssbake_result_free(result), SssbakeStatus::Ok);
    Ok((pixels, summary))
}

/// The mean red of covered texels whose column is in `columns`.
fn mean_red(pixels: &[f32], columns: std::ops::Range<usize>) -> f32 {
    let n = RESOLUTION as usize;
    let values: Vec<f32> = (0..n * n)
        .filter(|t| columns.contains(&(t % n)) && pixels[4 * t + 3] > 0.0)
        .map(|t| pixels[4 * t])
        .collect();
    values.iter().sum::<f32>() / values.len() as f32
}

#[test]
fn each_texel_shows_the_bake_of_its_own_faces_material() {
    let g = grid();
    let scene = scene(&g);
    let (pale, dark) = (CString::new("Pale").unwrap(), CString::new("Dark").unwrap());
    let materials = [
        principled(&pale, [0.8, 0.6, 0.5]),
        principled(&dark, [0.3, 0.2, 0.1]),
    ];
    let (both, summary) = bake(&scene, &materials).unwrap();
    let (pale_only, _) = bake(&scene, &materials[..1]).unwrap();
    let (dark_only, _) = bake(&scene, &materials[1..]).unwrap();
    let n = RESOLUTION as usize;
    // Away from the middle column and row of texels (whose centres may lie
    // on either side's faces), each texel is the bake of its quarter's
    // material.
    let side = |i: usize| (i + 1 < n / 2, i > n / 2);
    for t in 0..n * n {
        let ((left, right), (low, high)) = (side(t % n), side(t / n));
        let expected = match ((left, right), (low, high)) {
            _ if (left && low) || (right && high) => &pale_only,
            _ if (left && high) || (right && low) => &dark_only,
            _ => continue,
        };
        assert_eq!(
            both[4 * t..4 * t + 4],
            expected[4 * t..4 * t + 4],
            "texel {t}"
        );
    }
    let summary: serde_json::Value = serde_json::from_str(&summary).unwrap();
    let listed = &summary["objects"][0]["materials"];
    assert_eq!(listed[0]["name"], "Pale", "{summary}");
    assert_eq!(listed[1]["name"], "Dark", "{summary}");
    let texels = |i: usize| listed[i]["texels"].as_u64().unwrap();
    assert!(texels(0) > 400 && texels(1) > 400, "{summary}");
}

#[test]
fn a_material_without_subsurface_leaves_its_faces_empty() {
    let g = grid();
    let scene = scene(&g);
    let (pale, glass) = (
        CString::new("Pale").unwrap(),
        CString::new("Glass").unwrap(),
    );
    let none = SssbakeMaterial {
        kind: SSSBAKE_MATERIAL_NONE,
        name: glass.as_ptr(),
        ..SssbakeMaterial::default()
    };
    let (pixels, summary) = bake(&scene, &[principled(&pale, [0.8, 0.6, 0.5]), none]).unwrap();
    let n = RESOLUTION as usize;
    // The mean alpha over a quarter of the map (x and y from its lower left).
    let alpha = |x0: usize, y0: usize| {
        let quarter =
            (y0..y0 + n / 2 - 2).flat_map(|y| (x0..x0 + n / 2 - 2).map(move |x| y * n + x));
        quarter.map(|t| pixels[4 * t + 3]).sum::<f32>() / ((n / 2 - 2) * (n / 2 - 2)) as f32
    };
    let (low, high) = (1, n / 2 + 1);
    assert_eq!((alpha(low, low), alpha(high, high)), (1.0, 1.0));
    assert_eq!((alpha(high, low), alpha(low, high)), (0.0, 0.0));
    assert!(summary.contains("their faces are left out"), "{summary}");
    // Nothing left to bake is an error, not an empty map.
    assert_eq!(bake(&scene, &[none, none]), Err(SssbakeStatus::BadInput));
    assert!(
        last_error().contains("none of its faces"),
        "{}",
        last_error()
    );
}

/// An RGB image of `w` × 1 texels of `colours`.
fn image(colours: &[[f32; 3]]) -> Vec<f32> {
    colours.iter().flatten().copied().collect()
}

#[test]
fn a_constant_image_bakes_as_its_colour_and_two_colours_follow_their_uv_set() {
    let g = grid();
    let scene = scene(&g);
    let name = CString::new("Skin").unwrap();
    let colour = [0.6, 0.4, 0.3];
    let flat = principled(&name, colour);
    let constant = image(&[colour; 4]);
    let textured = SssbakeMaterial {
        base_colour: [0.1, 0.9, 0.1],
        image_pixels: constant.as_ptr(),
        image_width: 2,
        image_height: 2,
        image_channels: 3,
        ..flat
    };
    let (plain, _) = bake(&scene, &[flat, flat]).unwrap();
    let (from_image, summary) = bake(&scene, &[textured, textured]).unwrap();
    for (a, b) in plain.iter().zip(&from_image) {
        assert!((a - b).abs() <= 1e-5 * a.abs().max(1e-3), "{a} vs {b}");
    }
    assert!(summary.contains("\"source\":\"texture\""), "{summary}");
    // Two colours, red on the left of the image: through UV set 0 the left
    // of the grid is redder, through the mirrored set 1 the right.
    let two = image(&[[0.8, 0.3, 0.3], [0.2, 0.3, 0.3]]);
    let split = SssbakeMaterial {
        image_pixels: two.as_ptr(),
        image_width: 2,
        image_height: 1,
        image_channels: 3,
        image_extension: SSSBAKE_EXTENSION_EXTEND,
        ..flat
    };
    let n = RESOLUTION as usize;
    let left_over_right =
        |pixels: &[f32]| mean_red(pixels, 0..n / 4) / mean_red(pixels, 3 * n / 4..n);
    let (direct, _) = bake(&scene, &[split, split]).unwrap();
    let mirrored = SssbakeMaterial {
        image_uv_set: 1,
        ..split
    };
    let (through_set_1, _) = bake(&scene, &[mirrored, mirrored]).unwrap();
    assert!(
        left_over_right(&direct) > 2.0,
        "{}",
        left_over_right(&direct)
    );
    assert!(
        left_over_right(&through_set_1) < 0.5,
        "{}",
        left_over_right(&through_set_1)
    );
}

#[test]
fn rows_run_up_from_v_0() {
    let g = grid();
    let scene = scene(&g);
    let name = CString::new("Skin").unwrap();
    // Bottom row (v = 0) red, top row blue, four channels.
    let pixels = [0.8f32, 0.1, 0.1, 1.0, 0.1, 0.1, 0.8, 1.0];
    let material = SssbakeMaterial {
        image_pixels: pixels.as_ptr(),
        image_width: 1,
        image_height: 2,
        image_channels: 4,
        image_extension: SSSBAKE_EXTENSION_EXTEND,
        ..principled(&name, [0.5; 3])
    };
    let (map, _) = bake(&scene, &[material]).unwrap();
    let n = RESOLUTION as usize;
    let (bottom, top) = (4 * (n + n / 2), 4 * ((n - 2) * n + n / 2));
    assert!(
        map[bottom] > 2.0 * map[bottom + 2],
        "{:?}",
        &map[bottom..bottom + 4]
    );
    assert!(map[top + 2] > 2.0 * map[top], "{:?}", &map[top..top + 4]);
}

#[test]
fn malformed_images_and_indices_are_refused_with_a_message() {
    let g = grid();
    let scene = scene(&g);
    let name = CString::new("Skin").unwrap();
    let flat = principled(&name, [0.5; 3]);
    let mut pixels = image(&[[0.5; 3]; 4]);
    let with = |pixels: &[f32], w, h, c, set| SssbakeMaterial {
        image_pixels: pixels.as_ptr(),
        image_width: w,
        image_height: h,
        image_channels: c,
        image_uv_set: set,
        ..flat
    };
    let cases = [
        (with(&pixels, 0, 2, 3, 0), "both must be positive"),
        (with(&pixels, 2, 2, 2, 0), "2 channels"),
        (
            with(&pixels, 2, 2, 3, 2),
            "reads UV set 2 but the mesh has 2",
        ),
        (
            SssbakeMaterial {
                image_extension: 9,
                ..with(&pixels, 2, 2, 3, 0)
            },
            "extension 9",
        ),
    ];
    for (material, message) in cases {
        assert_eq!(
            bake(&scene, &[material]),
            Err(SssbakeStatus::InvalidArgument)
        );
        assert!(
            last_error().contains(message),
            "{message}: {}",
            last_error()
        );
        assert!(last_error().contains("material `Skin`"), "{}", last_error());
    }
    pixels[7] = f32::NAN;
    assert_eq!(
        bake(&scene, &[with(&pixels, 2, 2, 3, 0)]),
        Err(SssbakeStatus::InvalidArgument)
    );
    assert!(last_error().contains("texel (0, 1)"), "{}", last_error());
    // One material for faces that name two.
    assert_eq!(bake(&scene, &[]), Err(SssbakeStatus::InvalidArgument));
    // Indices beyond the materials given.
    let mut bad = g.materials.clone();
    bad[5] = 4;
    let name = CString::new("Bad").unwrap();
    let mesh = SssbakeMesh {
        name: name.as_ptr(),
        positions: g.positions.as_ptr(),
        uvs: g.uvs.as_ptr(),
        vertex_count: g.positions.len() / 3,
        indices: g.indices.as_ptr(),
        index_count: g.indices.len(),
        material_indices: bad.as_ptr(),
        ..SssbakeMesh::default()
    };
    assert_eq!(
        unsafe { sssbake_scene_add_mesh(scene.0, &mesh) },
        SssbakeStatus::Ok
    );
    let object = CString::new("Bad").unwrap();
    let mut result = null_mut();
    let two = [flat, flat];
    // The settings are the library's defaults: settings out of range are
    // refused before the materials are read.
    let mut settings = std::mem::MaybeUninit::uninit();
    assert_eq!(
        unsafe { sssbake_settings_default(settings.as_mut_ptr()) },
        SssbakeStatus::Ok
    );
    let status = unsafe {
        sssbake_bake_materials(
            scene.0,
            object.as_ptr(),
            two.as_ptr(),
            2,
            settings.as_ptr(),
            None,
            null_mut(),
            null(),
            &mut result,
        )
    };
    assert_eq!(status, SssbakeStatus::InvalidArgument);
    assert!(
        last_error().contains("triangle 5 has material 4, but 2 materials were given"),
        "{}",
        last_error()
    );
    // Texture UVs that are not finite, and a null array with a count.
    let nan_uvs = vec![f32::NAN; g.uvs.len()];
    let name = CString::new("NaN").unwrap();
    for (texture_uvs, message) in [
        (nan_uvs.as_ptr(), "not finite"),
        (null(), "texture_uvs is null"),
    ] {
        let mesh = SssbakeMesh {
            name: name.as_ptr(),
            texture_uvs,
            texture_uv_count: 1,
            ..mesh
        };
        assert_eq!(
            unsafe { sssbake_scene_add_mesh(scene.0, &mesh) },
            SssbakeStatus::InvalidArgument
        );
        assert!(last_error().contains(message), "{}", last_error());
    }
}

/// docs/materials.md's two-layer skin whose epidermis is declared a Stam layer
/// (or, with `top_model` "diffusion", the same stack by diffusion alone).
fn stam_topped_toml(top_model: &str) -> CString {
    CString::new(format!(
        "roughness = 0.4\n\
         [[layers]]\nmodel = \"{top_model}\"\nsigma_a = [2.1, 2.1, 5.0]\n\
         sigma_s = [48.0, 60.0, 65.0]\nior = 1.4\nthickness_mm = 0.03\n\
         [[layers]]\nsigma_a = [0.033, 0.099, 0.268]\nsigma_s = [4.67, 4.60, 4.43]\n\
         g = 0.846\nior = 1.4\n"
    ))
    .unwrap()
}

#[test]
fn a_material_text_declares_a_stam_top_layer_through_the_abi() {
    let g = grid();
    let scene = scene(&g);
    let name = CString::new("skin").unwrap();
    let material = |toml: &CString| SssbakeMaterial {
        kind: SSSBAKE_MATERIAL_TOML,
        name: name.as_ptr(),
        toml: toml.as_ptr(),
        ..SssbakeMaterial::default()
    };
    let stam = stam_topped_toml("stam");
    let diffusion = stam_topped_toml("diffusion");
    let (topped, summary) =
        bake(&scene, &[material(&stam)]).unwrap_or_else(|_| panic!("{}", last_error()));
    let (diffused, plain_summary) =
        bake(&scene, &[material(&diffusion)]).unwrap_or_else(|_| panic!("{}", last_error()));
    assert!(summary.contains("\"stam\""), "{summary}");
    assert!(!plain_summary.contains("\"stam\""), "{plain_summary}");
    // The epidermis solved by discrete ordinates lets a different share of
    // the light through than diffusion does: the maps differ, both lit.
    let all = 0..RESOLUTION as usize;
    let (a, b) = (mean_red(&topped, all.clone()), mean_red(&diffused, all));
    assert!(a > 0.0 && b > 0.0 && a.is_finite() && b.is_finite());
    assert!((a - b).abs() > 0.01 * b, "stam {a}, diffusion {b}");
}
