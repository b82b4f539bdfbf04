//! The USD reader's hand-over: JSON in the shape `usd/read_stage.py`
//! prints, turned into a scene (the Python side is tested under tests/).

use serde_json::json;
use sssbake::LightKind;
use sssbake_io::ReadOptions;
use sssbake_io::usd_reader::scene_from_json;

fn quad(corner_vertices: Vec<u32>) -> serde_json::Value {
    json!({
        "meters_per_unit": 0.01,
        "up_axis": "Y",
        "meshes": [{
            "name": "Card", "path": "/World/Card",
            "points": [[0, 0, 0], [10, 0, 0], [10, 10, 0], [0, 10, 0]],
            "corner_vertices": corner_vertices,
            "triangles": [[0, 1, 2], [0, 2, 3]],
            "uvs": [[0, 0], [1, 0], [1, 1], [0, 1]],
            "normals": null,
            "faces": 1, "subsets": []
        }],
        "lights": [{"name": "Key", "type": "SphereLight", "intensity": 10.0, "exposure": 1.0, "radius": 0.5,
                    "color": [1, 1, 1], "position": [0, 0, 50], "direction": [0, 0, -1]}]
    })
}

#[test]
fn stage_units_become_millimetres() {
    let scene = scene_from_json(
        &quad(vec![0, 1, 2, 3]),
        "card.usda",
        &ReadOptions::default(),
    )
    .unwrap();
    assert_eq!(scene.millimetres_per_unit, 10.0);
    let card = &scene.objects[0];
    assert_eq!(card.mesh.name, "Card");
    assert!((card.mesh.area() - 100.0 * 100.0).abs() < 1e-3);
    assert_eq!(card.mesh.uvs.as_ref().unwrap()[2], glam::Vec2::ONE);
    let light = &scene.lights[0];
    assert_eq!(light.kind, LightKind::Point { radius_mm: 5.0 });
    // Radiance 10 × 2¹ over a sphere of 5 mm: π r² L W/sr.
    let expected = 20.0 * std::f32::consts::PI * 0.005f32.powi(2);
    assert!((light.intensity - expected).abs() < 1e-6 * expected);
    assert_eq!(light.position, glam::Vec3::new(0.0, 0.0, 500.0));
}

#[test]
fn a_face_pointing_past_the_points_is_refused() {
    let error = scene_from_json(
        &quad(vec![0, 1, 2, 7]),
        "card.usda",
        &ReadOptions::default(),
    )
    .unwrap_err();
    let message = error.to_string();
    assert!(
        message.starts_with("card.usda: object `Card`") && message.contains("point 7"),
        "{message}"
    );
}

#[test]
fn openpbr_subsurface_becomes_colour_and_mean_free_path() {
    let mut stage = quad(vec![0, 1, 2, 3]);
    stage["meshes"][0]["material"] = json!({
        "name": "Wax", "shader": "ND_open_pbr_surface_surfaceshader",
        "inputs": {"subsurface_weight": 1.0, "subsurface_color": [0.9, 0.7, 0.5],
                   "subsurface_radius": 0.5, "subsurface_scatter_anisotropy": 0.3, "specular_ior": 1.4},
        "connected": ["base_color"]
    });
    let scene = scene_from_json(&stage, "wax.usda", &ReadOptions::default()).unwrap();
    let material = scene.objects[0].material.as_ref().unwrap();
    assert_eq!(material.name, "Wax");
    assert_eq!(material.ior, Some(1.4));
    let subsurface = material.subsurface.as_ref().unwrap();
    assert_eq!(subsurface.colour, [0.9, 0.7, 0.5]);
    // 0.5 stage units × OpenPBR's default radius scale (1, 0.5, 0.25), in mm.
    assert_eq!(subsurface.mean_free_path_mm, [5.0, 2.5, 1.25]);
    assert_eq!(subsurface.anisotropy, 0.3);
    assert!(
        scene
            .notes
            .iter()
            .any(|n| n.contains("`base_color` is driven by a texture"))
    );
}

#[test]
fn preview_surface_and_unweighted_openpbr_give_only_a_colour() {
    for material in [
        json!({"name": "Plastic", "shader": "UsdPreviewSurface",
               "inputs": {"diffuseColor": [0.2, 0.3, 0.4]}, "connected": []}),
        json!({"name": "Plastic", "shader": "ND_open_pbr_surface_surfaceshader",
               "inputs": {"base_color": [0.2, 0.3, 0.4], "subsurface_weight": 0.0}, "connected": []}),
    ] {
        let mut stage = quad(vec![0, 1, 2, 3]);
        stage["meshes"][0]["material"] = material;
        let scene = scene_from_json(&stage, "card.usda", &ReadOptions::default()).unwrap();
        let hint = scene.objects[0].material.as_ref().unwrap();
        assert!(hint.subsurface.is_none() && !hint.is_translucent());
        assert_eq!(hint.ior, Some(1.5));
        let (appearance, from) = hint.appearance([1.0, 0.5, 0.25]);
        assert!(from.is_none());
        assert!((appearance.colour[2] - 0.4).abs() < 1e-6);
        assert_eq!(appearance.mean_free_path_mm, [1.0, 0.5, 0.25]);
    }
}

#[test]
fn unknown_shaders_give_no_material() {
    let mut stage = quad(vec![0, 1, 2, 3]);
    stage["meshes"][0]["material"] =
        json!({"name": "Custom", "shader": "MyRenderer_surface", "inputs": {}, "connected": []});
    let scene = scene_from_json(&stage, "card.usda", &ReadOptions::default()).unwrap();
    assert!(scene.objects[0].material.is_none());
}

fn refused(stage: &serde_json::Value) -> String {
    scene_from_json(stage, "card.usda", &ReadOptions::default())
        .unwrap_err()
        .to_string()
}

#[test]
fn a_wrong_typed_field_is_named_with_its_object_and_path() {
    let mut stage = quad(vec![0, 1, 2, 3]);
    stage["meshes"][0]["triangles"][1] = json!([0, 2, "3"]);
    assert_eq!(
        refused(&stage),
        "card.usda: object `Card`: triangles[1][2]: invalid type: string \"3\", expected u32"
    );

    let mut stage = quad(vec![0, 1, 2, 3]);
    stage["meshes"][0]["points"][2] = json!([10, 10]);
    assert_eq!(
        refused(&stage),
        "card.usda: object `Card`: points[2]: invalid length 2, expected an array of length 3"
    );

    let mut stage = quad(vec![0, 1, 2, 3]);
    stage["lights"][0]["intensity"] = json!("bright");
    assert_eq!(
        refused(&stage),
        "card.usda: light `Key`: intensity: invalid type: string \"bright\", expected f32"
    );

    let mut stage = quad(vec![0, 1, 2, 3]);
    stage["meshes"][0]["material"] = json!({"name": "Wax", "shader": 3});
    assert_eq!(
        refused(&stage),
        "card.usda: object `Card`: material.shader: invalid type: integer `3`, expected a string"
    );

    let mut stage = quad(vec![0, 1, 2, 3]);
    stage["meters_per_unit"] = json!("cm");
    assert_eq!(
        refused(&stage),
        "card.usda: meters_per_unit: invalid type: string \"cm\", expected f64"
    );
}

#[test]
fn a_missing_field_is_named_with_its_object() {
    let mut stage = quad(vec![0, 1, 2, 3]);
    stage["meshes"][0].as_object_mut().unwrap().remove("points");
    assert_eq!(
        refused(&stage),
        "card.usda: object `Card`: missing field `points`"
    );
}
