//! glTF and GLB broken one way at a time: references to what does not
//! exist, data that does not fit its buffers, types the reader cannot
//! decode, numbers that are not finite, extensions of the wrong shape,
//! files cut short.

use super::{Case, quad};
use serde_json::{Value, json};

/// The quad with `break_it` applied to its document and buffer.
fn broken(name: &str, words: &[&str], break_it: impl FnOnce(&mut Value, &mut Vec<u8>)) -> Case {
    let mut document = quad::document(Some("quad.bin"));
    let mut bin = quad::bin();
    break_it(&mut document, &mut bin);
    let text = serde_json::to_vec_pretty(&document).unwrap();
    Case::new(
        name,
        vec![("quad.gltf", text), ("quad.bin", bin)],
        "quad.gltf",
        &[],
        "quad.gltf",
        words,
    )
}

/// A .gltf or .glb file of exactly `bytes`.
fn raw(name: &str, file: &str, bytes: Vec<u8>, words: &[&str]) -> Case {
    Case::new(name, vec![(file, bytes)], file, &[], file, words)
}

fn set_f32(bin: &mut [u8], at: usize, value: f32) {
    bin[at..at + 4].copy_from_slice(&value.to_le_bytes());
}

/// The quad's material with `extensions`, volume included when asked.
fn material_extensions(document: &mut Value, extensions: Value) {
    document["materials"][0]["extensions"] = extensions;
}

/// The glTF cases.
pub fn cases() -> Vec<Case> {
    let valid_glb = quad::glb(&quad::document(None), &quad::bin());
    let mut cases = vec![
        // The issue's case: a primitive naming an accessor that is not there.
        raw(
            "position-accessor-99",
            "three.gltf",
            br#"{"asset": {"version": "2.0"},
"meshes": [{"primitives": [{"attributes": {"POSITION": 99}}]}],
"nodes": [{"mesh": 0}]}"#
                .to_vec(),
            &[
                "mesh 0, primitive 0",
                "POSITION names accessor 99",
                "0 accessors",
            ],
        ),
        broken(
            "normal-accessor-99",
            &["NORMAL", "out of bounds"],
            |d, _| d["meshes"][0]["primitives"][0]["attributes"]["NORMAL"] = 99.into(),
        ),
        broken(
            "texcoord-accessor-99",
            &["TEXCOORD_0", "out of bounds"],
            |d, _| d["meshes"][0]["primitives"][0]["attributes"]["TEXCOORD_0"] = 99.into(),
        ),
        broken(
            "indices-accessor-99",
            &["indices", "out of bounds"],
            |d, _| d["meshes"][0]["primitives"][0]["indices"] = 99.into(),
        ),
        broken("material-99", &["material", "out of bounds"], |d, _| {
            d["meshes"][0]["primitives"][0]["material"] = 99.into()
        }),
        broken(
            "node-mesh-99",
            &["nodes[0].mesh", "out of bounds"],
            |d, _| d["nodes"][0]["mesh"] = 99.into(),
        ),
        broken(
            "scene-node-99",
            &["scenes[0].nodes", "out of bounds"],
            |d, _| d["scenes"][0]["nodes"] = json!([99]),
        ),
        broken("child-node-99", &["children", "out of bounds"], |d, _| {
            d["nodes"][0]["children"] = json!([99])
        }),
        broken(
            "accessor-view-99",
            &["bufferView", "out of bounds"],
            |d, _| d["accessors"][0]["bufferView"] = 99.into(),
        ),
        broken(
            "view-buffer-99",
            &["bufferViews[0].buffer", "out of bounds"],
            |d, _| d["bufferViews"][0]["buffer"] = 99.into(),
        ),
        broken("node-cycle", &["cycle"], |d, _| {
            d["nodes"][0]["children"] = json!([0])
        }),
        // Data that does not fit its buffers.
        broken(
            "view-past-buffer",
            &["buffer view 3", "ends at byte 1140"],
            |d, _| d["bufferViews"][3]["byteOffset"] = 1128.into(),
        ),
        broken(
            "view-offset-overflows",
            &["buffer view 0", "ends at byte"],
            |d, _| d["bufferViews"][0]["byteOffset"] = json!(u64::MAX - 8),
        ),
        broken("buffer-shorter-than-said", &["buffer"], |_, bin| {
            bin.truncate(100)
        }),
        broken(
            "accessor-count-huge",
            &["accessor 0", "needs", "buffer view 0 has 48"],
            |d, _| d["accessors"][0]["count"] = json!(1u64 << 60),
        ),
        broken(
            "accessor-count-u64-max",
            &["accessor 0", "needs"],
            |d, _| d["accessors"][0]["count"] = json!(u64::MAX),
        ),
        broken("accessor-count-zero", &["accessor 0", "count 0"], |d, _| {
            d["accessors"][0]["count"] = 0.into()
        }),
        broken(
            "accessor-offset-past-view",
            &["accessor 1", "needs"],
            |d, _| d["accessors"][1]["byteOffset"] = 40.into(),
        ),
        broken(
            "stride-shorter-than-element",
            &["byteStride 4", "12-byte"],
            |d, _| d["bufferViews"][0]["byteStride"] = 4.into(),
        ),
        broken("stride-not-allowed", &["byteStride"], |d, _| {
            d["bufferViews"][0]["byteStride"] = 2.into()
        }),
        // Types the reader cannot decode.
        broken(
            "position-u16",
            &["POSITION", "accessor 0 is U16 Vec3", "F32 Vec3"],
            |d, _| d["accessors"][0]["componentType"] = 5123.into(),
        ),
        broken(
            "position-vec2",
            &["POSITION", "accessor 0 is F32 Vec2"],
            |d, _| d["accessors"][0]["type"] = "VEC2".into(),
        ),
        broken(
            "normal-vec4",
            &["NORMAL", "accessor 1 is F32 Vec4"],
            |d, _| {
                d["accessors"][1]["type"] = "VEC4".into();
                d["accessors"][1]["count"] = 3.into()
            },
        ),
        broken(
            "texcoord-scalar",
            &["TEXCOORD_0", "accessor 2 is F32 Scalar"],
            |d, _| d["accessors"][2]["type"] = "SCALAR".into(),
        ),
        broken(
            "texcoord-bytes-not-normalized",
            &["TEXCOORD_0", "normalized"],
            |d, _| d["accessors"][2]["componentType"] = 5121.into(),
        ),
        broken(
            "indices-float",
            &["indices", "accessor 3 is F32 Scalar"],
            |d, _| {
                d["accessors"][3]["componentType"] = 5126.into();
                d["accessors"][3]["count"] = 3.into()
            },
        ),
        broken(
            "indices-vec3",
            &["indices", "accessor 3 is U16 Vec3"],
            |d, _| {
                d["accessors"][3]["type"] = "VEC3".into();
                d["accessors"][3]["count"] = 2.into()
            },
        ),
        broken("component-type-unknown", &["componentType"], |d, _| {
            d["accessors"][0]["componentType"] = 1234.into()
        }),
        broken("mode-unknown", &["mode"], |d, _| {
            d["meshes"][0]["primitives"][0]["mode"] = 9.into()
        }),
        broken(
            "index-past-vertices",
            &["object `Tile`", "index 9", "4 vertices"],
            |_, bin| bin[128..130].copy_from_slice(&9u16.to_le_bytes()),
        ),
        // Sparse accessors.
        broken(
            "sparse-indices-past-view",
            &["accessor 0's sparse.indices", "needs"],
            |d, _| {
                d["accessors"][0]["sparse"] = json!({"count": 2,
                "indices": {"bufferView": 3, "byteOffset": 10, "componentType": 5123},
                "values": {"bufferView": 1}})
            },
        ),
        broken(
            "sparse-values-past-view",
            &["accessor 0's sparse.values", "needs"],
            |d, _| {
                d["accessors"][0]["sparse"] = json!({"count": 2,
                "indices": {"bufferView": 3, "componentType": 5123},
                "values": {"bufferView": 1, "byteOffset": 30}})
            },
        ),
        broken(
            "sparse-count-over-count",
            &["accessor 0", "sparse.count is 5"],
            |d, _| {
                d["accessors"][0]["sparse"] = json!({"count": 5,
                "indices": {"bufferView": 3, "componentType": 5123},
                "values": {"bufferView": 1}})
            },
        ),
        broken(
            "sparse-without-data-huge",
            &["accessor 0", "no buffer view", "claims"],
            |d, _| {
                d["accessors"][0]["bufferView"] = Value::Null;
                d["accessors"][0]["count"] = json!(1u64 << 40);
                d["accessors"][0]["sparse"] = json!({"count": 2,
                "indices": {"bufferView": 3, "componentType": 5123},
                "values": {"bufferView": 1}})
            },
        ),
        broken(
            "sparse-indices-view-99",
            &["sparse", "out of bounds"],
            |d, _| {
                d["accessors"][0]["sparse"] = json!({"count": 2,
                "indices": {"bufferView": 99, "componentType": 5123},
                "values": {"bufferView": 1}})
            },
        ),
        // Buffers that cannot be loaded.
        broken(
            "data-uri-not-base64",
            &["cannot load its buffers"],
            |d, _| d["buffers"][0]["uri"] = "data:application/octet-stream;base64,@@@@".into(),
        ),
        broken(
            "data-uri-too-short",
            &["cannot load its buffers"],
            |d, _| d["buffers"][0]["uri"] = "data:application/octet-stream;base64,AAAA".into(),
        ),
        broken(
            "buffer-file-missing",
            &["cannot load its buffers", "buffer 0", "absent.bin"],
            |d, _| d["buffers"][0]["uri"] = "absent.bin".into(),
        ),
        broken(
            "buffer-file-missing-escaped",
            &["cannot load its buffers", "absent quad.bin"],
            |d, _| d["buffers"][0]["uri"] = "absent%20quad.bin".into(),
        ),
        // Another version of glTF than 2.x.
        broken(
            "gltf-version-1",
            &["asset.version", "\"1.0\"", "2.x"],
            |d, _| d["asset"]["version"] = "1.0".into(),
        ),
        broken("gltf-version-3", &["asset.version", "\"3.0\""], |d, _| {
            d["asset"]["version"] = "3.0".into()
        }),
        broken(
            "gltf-min-version-3",
            &["asset.minVersion", "\"3.0\""],
            |d, _| d["asset"]["minVersion"] = "3.0".into(),
        ),
        broken("buffer-uri-remote", &["cannot load its buffers"], |d, _| {
            d["buffers"][0]["uri"] = "https://example.com/quad.bin".into()
        }),
        // Numbers that are not finite.
        broken(
            "nan-position",
            &["object `Tile`", "non-finite position"],
            |_, bin| set_f32(bin, 12, f32::NAN),
        ),
        broken(
            "infinite-position",
            &["object `Tile`", "non-finite position"],
            |_, bin| set_f32(bin, 20, f32::INFINITY),
        ),
        broken(
            "scale-overflows",
            &["object `Tile`", "non-finite position"],
            |d, _| d["nodes"][0]["scale"] = json!([1e38, 1e38, 1e38]),
        ),
        // JSON of the wrong shape.
        broken("accessors-a-string", &["not a valid glTF"], |d, _| {
            d["accessors"] = "many".into()
        }),
        broken("count-negative", &["not a valid glTF"], |d, _| {
            d["accessors"][0]["count"] = (-4).into()
        }),
        broken(
            "volume-thickness-a-string",
            &["not a valid glTF", "thick"],
            |d, _| {
                material_extensions(
                    d,
                    json!({"KHR_materials_volume": {"thicknessFactor": "thick"}}),
                )
            },
        ),
        broken(
            "transmission-factor-a-string",
            &["material `wax`", "diffuseTransmissionFactor", "\"high\""],
            |d, _| {
                material_extensions(
                    d,
                    json!({"KHR_materials_diffuse_transmission": {"diffuseTransmissionFactor": "high"}}),
                )
            },
        ),
        broken(
            "transmission-colour-two-numbers",
            &["material `wax`", "diffuseTransmissionColorFactor", "three"],
            |d, _| {
                material_extensions(
                    d,
                    json!({"KHR_materials_diffuse_transmission": {"diffuseTransmissionColorFactor": [1, 1]}}),
                )
            },
        ),
        broken(
            "transmission-not-an-object",
            &["KHR_materials_diffuse_transmission", "not an object"],
            |d, _| material_extensions(d, json!({"KHR_materials_diffuse_transmission": 3})),
        ),
        broken(
            "multiscatter-a-string",
            &["material `wax`", "multiscatterColor"],
            |d, _| {
                material_extensions(
                    d,
                    json!({"KHR_materials_volume": {"attenuationDistance": 0.01},
                       "KHR_materials_volume_scatter": {"multiscatterColor": "red"}}),
                )
            },
        ),
        broken(
            "multiscatter-negative",
            &["material `wax`", "multiscatterColor"],
            |d, _| {
                material_extensions(
                    d,
                    json!({"KHR_materials_volume": {"attenuationDistance": 0.01},
                       "KHR_materials_volume_scatter": {"multiscatterColor": [0.5, -1, 0.5]}}),
                )
            },
        ),
        broken(
            "anisotropy-out-of-range",
            &["material `wax`", "scatterAnisotropy", "outside"],
            |d, _| {
                material_extensions(
                    d,
                    json!({"KHR_materials_volume": {"attenuationDistance": 0.01},
                       "KHR_materials_volume_scatter": {"scatterAnisotropy": 5}}),
                )
            },
        ),
        broken(
            "texture-transform-a-string",
            &["not a valid glTF"],
            |d, _| {
                d["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"] =
                    json!({"index": 0, "extensions": {"KHR_texture_transform": {"scale": "big"}}});
                d["textures"] = json!([{"source": 0}]);
                d["images"] = json!([{"uri": "colour.png"}]);
            },
        ),
        // Found by fuzzing: the gltf crate unwraps an image's missing source.
        broken(
            "image-without-source",
            &["image 0", "neither a uri nor a bufferView"],
            |d, _| {
                d["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"] = json!({"index": 0});
                d["textures"] = json!([{"source": 0}]);
                d["images"] = json!([{"name": "colour"}]);
            },
        ),
        broken(
            "image-view-without-mime-type",
            &["image 0", "no mimeType"],
            |d, _| {
                d["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"] = json!({"index": 0});
                d["textures"] = json!([{"source": 0}]);
                d["images"] = json!([{"bufferView": 0}]);
            },
        ),
        broken("light-of-unknown-type", &["not a valid glTF"], |d, _| {
            d["extensions"] = json!({"KHR_lights_punctual": {"lights": [{"type": "laser"}]}});
        }),
        // Files cut short or not glTF at all.
        raw(
            "json-cut-short",
            "cut.gltf",
            serde_json::to_vec(&quad::document(Some("quad.bin"))).unwrap()[..300].to_vec(),
            &["not a valid glTF"],
        ),
        raw(
            "not-json",
            "noise.gltf",
            (0..=255u8).cycle().take(999).collect(),
            &["not a valid glTF"],
        ),
        raw(
            "empty-file",
            "empty.gltf",
            Vec::new(),
            &["not a valid glTF"],
        ),
        raw(
            "glb-cut-short",
            "cut.glb",
            valid_glb[..valid_glb.len() / 2].to_vec(),
            &["not a valid glTF"],
        ),
        raw(
            "glb-asset-version-1",
            "quad.glb",
            {
                let mut document = quad::document(None);
                document["asset"]["version"] = "1.0".into();
                quad::glb(&document, &quad::bin())
            },
            &["asset.version", "\"1.0\""],
        ),
        raw(
            "glb-header-only",
            "header.glb",
            valid_glb[..12].to_vec(),
            &["not a valid glTF"],
        ),
    ];
    let mut glb = |name: &str, words: &[&str], break_it: &dyn Fn(&mut Vec<u8>)| {
        let mut bytes = valid_glb.clone();
        break_it(&mut bytes);
        cases.push(raw(name, "quad.glb", bytes, words));
    };
    glb("glb-length-too-long", &["not a valid glTF"], &|b| {
        b[8..12].copy_from_slice(&u32::MAX.to_le_bytes())
    });
    glb("glb-length-under-header", &["not a valid glTF"], &|b| {
        b[8..12].copy_from_slice(&4u32.to_le_bytes())
    });
    glb("glb-version-3", &["not a valid glTF"], &|b| {
        b[4..8].copy_from_slice(&3u32.to_le_bytes())
    });
    glb("glb-json-chunk-too-long", &["not a valid glTF"], &|b| {
        b[12..16].copy_from_slice(&(u32::MAX - 3).to_le_bytes())
    });
    glb("glb-bin-chunk-short", &["cannot load its buffers"], &|b| {
        let json_len = u32::from_le_bytes(b[12..16].try_into().unwrap()) as usize;
        let bin_at = 20 + json_len;
        b[bin_at..bin_at + 4].copy_from_slice(&100u32.to_le_bytes());
        b.truncate(bin_at + 8 + 100);
        let total = b.len() as u32;
        b[8..12].copy_from_slice(&total.to_le_bytes());
    });
    cases
}
