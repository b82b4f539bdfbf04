//! glTF 2.0 (.gltf, .glb): every mesh instance with its node transform,
//! normals (computed when absent), the chosen TEXCOORD set, material hints
//! (base colour, KHR_materials_volume, KHR_materials_diffuse_transmission,
//! KHR_materials_ior) and KHR_lights_punctual lights. glTF is in metres.

use crate::colour_texture::{self, ColourSpace};
use crate::gltf_checks;
use crate::gltf_uri;
use crate::{InputError, ReadOptions};
use glam::{Mat3, Mat4, Vec2, Vec3};
use gltf::mesh::Mode;
use gltf::texture::{MagFilter, WrappingMode};
use sssbake::colour::{ColourTexture, UvTransform, Wrap};
use sssbake::scene::{Subsurface, Volume, spot_cone};
use sssbake::{ConeFalloff, Light, LightKind, LightRow, MaterialHint, Mesh, Scene, SceneObject};
use std::collections::HashMap;
use std::path::Path;
use std::sync::Arc;

/// Millimetres per glTF unit (metres).
const MILLIMETRES_PER_METRE: f64 = 1000.0;

/// Reads a glTF or GLB file.
pub fn read_gltf(path: &Path, options: &ReadOptions) -> Result<Scene, InputError> {
    let bytes = std::fs::read(path).map_err(|e| InputError {
        file: path.display().to_string(),
        message: format!("cannot read: {e}"),
    })?;
    read_gltf_bytes(&bytes, path, options)
}

/// Reads a glTF or GLB file's `bytes`; `path` names it in messages, and
/// its folder is where relative URIs are found.
pub fn read_gltf_bytes(
    bytes: &[u8],
    path: &Path,
    options: &ReadOptions,
) -> Result<Scene, InputError> {
    let file = path.display().to_string();
    let error = |message: String| InputError {
        file: file.clone(),
        message,
    };
    let (document, blob) = gltf_checks::parse(bytes).map_err(error)?;
    let base = path.parent().unwrap_or(Path::new("."));
    gltf_uri::check_buffer_files(&document, base).map_err(error)?;
    let buffers = gltf::import_buffers(&document, Some(base), blob)
        .map_err(|e| error(format!("cannot load its buffers: {e}")))?;
    let data: Vec<&[u8]> = buffers.iter().map(|b| b.0.as_slice()).collect();
    gltf_checks::check_accessors(&document, &data).map_err(error)?;
    gltf_checks::check_primitives(&document).map_err(error)?;

    let scale = options.unit_scale.unwrap_or(MILLIMETRES_PER_METRE);
    let mut scene = Scene {
        source: file.clone(),
        millimetres_per_unit: scale,
        ..Default::default()
    };
    let mut names: HashMap<String, usize> = HashMap::new();
    let by_blender = document
        .as_json()
        .asset
        .generator
        .as_deref()
        .is_some_and(|g| g.starts_with(BLENDER_GENERATOR));
    let roots: Vec<gltf::Node> = match document
        .default_scene()
        .or_else(|| document.scenes().next())
    {
        Some(s) => s.nodes().collect(),
        None => document.nodes().collect(),
    };
    let mut stack: Vec<(gltf::Node, Mat4)> =
        roots.into_iter().map(|n| (n, Mat4::IDENTITY)).collect();
    let mut visited = 0usize;
    while let Some((node, parent)) = stack.pop() {
        visited += 1;
        if visited > 10 * document.nodes().len() + 10 {
            return Err(error("the node hierarchy has a cycle".into()));
        }
        let world = parent * Mat4::from_cols_array_2d(&node.transform().matrix());
        if let Some(mesh) = node.mesh() {
            let base_name = node
                .name()
                .or(mesh.name())
                .map_or_else(|| format!("node {}", node.index()), String::from);
            let seen = names.entry(base_name.clone()).or_insert(0);
            *seen += 1;
            let name = if *seen == 1 {
                base_name
            } else {
                format!("{base_name}.{}", *seen - 1)
            };
            let context = Context {
                folder: base,
                data: &data,
            };
            if let Some(object) = read_mesh(
                &mesh,
                &name,
                world,
                scale,
                options,
                &context,
                &mut scene.notes,
            )
            .map_err(error)?
            {
                scene.objects.push(SceneObject {
                    node: Some(node.index()),
                    local_to_world: Mat4::from_scale(Vec3::splat(scale as f32)) * world,
                    ..object
                });
            }
        }
        if let Some(light) = node.light() {
            let light = read_light(&light, world, scale, node.index(), by_blender);
            if by_blender && matches!(light.kind, LightKind::Spot { .. }) {
                scene.notes.push(format!(
                    "light `{}`: a spot read as Blender's glTF exporter writes spots \
                     (size 2 × outer cone, blend 1 − inner/outer, faded as Cycles fades it)",
                    light.name
                ));
            }
            scene.lights.push(light);
        }
        stack.extend(node.children().map(|c| (c, world)));
    }
    scene.objects.sort_by(|a, b| a.mesh.name.cmp(&b.mesh.name));
    Ok(scene)
}

/// Where a glTF file's images are found: the folder it names relative
/// paths from, and its buffers.
struct Context<'a> {
    folder: &'a Path,
    data: &'a [&'a [u8]],
}

fn read_mesh(
    mesh: &gltf::Mesh,
    name: &str,
    world: Mat4,
    scale: f64,
    options: &ReadOptions,
    context: &Context,
    notes: &mut Vec<String>,
) -> Result<Option<SceneObject>, String> {
    let data = context.data;
    let normal_matrix = Mat3::from_mat4(world).inverse().transpose();
    let mirrored = Mat3::from_mat4(world).determinant() < 0.0;
    let (mut positions, mut normals, mut triangles) = (Vec::new(), Vec::new(), Vec::new());
    let mut uv_sets: Vec<Vec<Vec2>> = Vec::new();
    let mut all_have_normals = true;
    let mut material = None;
    let mut colour_texture = None;
    for primitive in mesh.primitives() {
        let reader = primitive.reader(|b| data.get(b.index()).copied());
        let Some(points) = reader.read_positions() else {
            return Err(format!(
                "object `{name}`: primitive {} has no POSITION",
                primitive.index()
            ));
        };
        let base = positions.len() as u32;
        let points: Vec<Vec3> = points
            .map(|p| world.transform_point3(Vec3::from(p)) * scale as f32)
            .collect();
        let count = points.len();
        positions.extend(points);
        match reader.read_normals() {
            Some(n) => {
                normals.extend(n.map(|n| (normal_matrix * Vec3::from(n)).normalize_or_zero()))
            }
            None => {
                all_have_normals = false;
                normals.extend(std::iter::repeat_n(Vec3::ZERO, count));
            }
        }
        for set in 0.. {
            let Some(coords) = reader.read_tex_coords(set) else {
                break;
            };
            // glTF's v runs down the image; sssbake's, like USD's t, runs up.
            let coords: Vec<Vec2> = coords
                .into_f32()
                .map(|[u, v]| Vec2::new(u, 1.0 - v))
                .collect();
            if uv_sets.len() <= set as usize {
                uv_sets.push(vec![Vec2::ZERO; base as usize]);
            }
            uv_sets[set as usize].extend(coords);
        }
        for set in uv_sets.iter_mut() {
            set.resize(positions.len(), Vec2::ZERO);
        }
        let indices: Vec<u32> = match reader.read_indices() {
            Some(i) => i.into_u32().collect(),
            None => (0..count as u32).collect(),
        };
        if let Some(bad) = indices.iter().find(|&&i| i as usize >= count) {
            return Err(format!(
                "object `{name}`: primitive {} has index {bad} but {count} vertices",
                primitive.index()
            ));
        }
        let new = match primitive.mode() {
            Mode::Triangles => indices
                .chunks_exact(3)
                .map(|t| [t[0], t[1], t[2]])
                .collect(),
            Mode::TriangleStrip => (2..indices.len())
                .map(|i| {
                    if i % 2 == 0 {
                        [indices[i - 2], indices[i - 1], indices[i]]
                    } else {
                        [indices[i - 1], indices[i - 2], indices[i]]
                    }
                })
                .collect(),
            Mode::TriangleFan => (2..indices.len())
                .map(|i| [indices[0], indices[i - 1], indices[i]])
                .collect(),
            other => {
                notes.push(format!(
                    "object `{name}`: primitive {} ({other:?}) has no faces and is left out",
                    primitive.index()
                ));
                Vec::<[u32; 3]>::new()
            }
        };
        triangles.extend(new.into_iter().map(|t| {
            let t = t.map(|i| i + base);
            if mirrored { [t[0], t[2], t[1]] } else { t }
        }));
        if material.is_none() && primitive.material().index().is_some() {
            let gltf_material = primitive.material();
            let hint = read_material(&gltf_material, scale)?;
            colour_texture = base_colour_texture(&gltf_material, &hint, context);
            notes.extend(radius_texture_notes(&gltf_material));
            material = Some(hint);
        }
    }
    if triangles.is_empty() {
        return Ok(None);
    }
    let uvs = uv_sets.get(options.uv_set).cloned();
    if uvs.is_none() && !uv_sets.is_empty() {
        notes.push(format!(
            "object `{name}`: has no TEXCOORD_{}; it will be unwrapped",
            options.uv_set
        ));
    }
    let normals = all_have_normals.then_some(normals);
    let (mesh, warnings) =
        Mesh::new(name, positions, normals, uvs, triangles).map_err(|e| e.to_string())?;
    if warnings.degenerate_triangles > 0 {
        notes.push(format!(
            "object `{name}`: {} zero-area triangles left out",
            warnings.degenerate_triangles
        ));
    }
    if warnings.repaired_uvs > 0 {
        notes.push(format!(
            "object `{name}`: {} non-finite UVs set to 0",
            warnings.repaired_uvs
        ));
    }
    Ok(Some(SceneObject {
        mesh,
        uv_sets,
        material,
        colour_texture,
        node: None,
        prim: None,
        local_to_world: Mat4::IDENTITY,
    }))
}

fn read_material(material: &gltf::Material, scale: f64) -> Result<MaterialHint, String> {
    let pbr = material.pbr_metallic_roughness();
    let volume = material.volume().map(|v| Volume {
        attenuation_distance_mm: (v.attenuation_distance() as f64 * scale) as f32,
        attenuation_color: v.attenuation_color(),
        thickness_mm: (v.thickness_factor() as f64 * scale) as f32,
    });
    let transmission = Extension::of(material, "KHR_materials_diffuse_transmission")?;
    let diffuse_transmission = match transmission {
        Some(t) => Some((
            t.colour("diffuseTransmissionColorFactor")?
                .unwrap_or([1.0; 3])
                .map(|c| c as f32),
            t.number("diffuseTransmissionFactor")?.unwrap_or(0.0) as f32,
        )),
        None => None,
    };
    let base_color = pbr.base_color_factor();
    let subsurface = match volume.as_ref() {
        Some(v) => subsurface_of(v, &base_color, material)?,
        None => None,
    };
    Ok(MaterialHint {
        name: material.name().unwrap_or("unnamed").to_string(),
        base_color,
        ior: material.ior(),
        volume,
        diffuse_transmission,
        subsurface,
    })
}

/// A material's extension read as its JSON, each property checked for its
/// type so that a wrong one is refused, naming it, instead of read as absent.
struct Extension<'a> {
    /// "material `wax`: KHR_materials_…", for messages.
    at: String,
    object: &'a serde_json::Map<String, serde_json::Value>,
}

impl<'a> Extension<'a> {
    fn of(material: &'a gltf::Material, name: &str) -> Result<Option<Self>, String> {
        let at = format!(
            "material `{}`: {name}",
            material.name().unwrap_or("unnamed")
        );
        match material.extension_value(name) {
            None => Ok(None),
            Some(serde_json::Value::Object(object)) => Ok(Some(Extension { at, object })),
            Some(other) => Err(format!("{at} is {other}, not an object")),
        }
    }

    /// A finite number, or absent.
    fn number(&self, key: &str) -> Result<Option<f64>, String> {
        match self.object.get(key) {
            None => Ok(None),
            Some(v) => v
                .as_f64()
                .filter(|x| x.is_finite())
                .map(Some)
                .ok_or_else(|| format!("{}.{key} is {v}, not a number", self.at)),
        }
    }

    /// Three non-negative numbers, or absent.
    fn colour(&self, key: &str) -> Result<Option<[f64; 3]>, String> {
        let Some(v) = self.object.get(key) else {
            return Ok(None);
        };
        let numbers: Option<Vec<f64>> = v
            .as_array()
            .filter(|c| c.len() == 3)
            .and_then(|c| c.iter().map(|x| x.as_f64()).collect());
        match numbers.as_deref() {
            Some(&[r, g, b]) if [r, g, b].iter().all(|x| x.is_finite() && *x >= 0.0) => {
                Ok(Some([r, g, b]))
            }
            _ => Err(format!(
                "{}.{key} is {v}, not three non-negative numbers",
                self.at
            )),
        }
    }
}

/// The material's `baseColorTexture`, read: its image decoded from sRGB,
/// its texture coordinates (`texCoord`, or `KHR_texture_transform`'s),
/// transform, sampler, and the colour it multiplies (the colour the
/// profile is built for: the base colour factor, or
/// `KHR_materials_volume_scatter`'s `multiscatterColor`).
fn base_colour_texture(
    material: &gltf::Material,
    hint: &MaterialHint,
    context: &Context,
) -> Option<ColourTexture> {
    let info = material.pbr_metallic_roughness().base_color_texture()?;
    let texture = info.texture();
    let (file, image) = image_of(&texture.source(), context);
    let transform = info.texture_transform();
    let uv_set = transform
        .as_ref()
        .and_then(|t| t.tex_coord())
        .unwrap_or(info.tex_coord()) as usize;
    let sampler = texture.sampler();
    let wrap = |mode: WrappingMode| match mode {
        WrappingMode::Repeat => Wrap::Repeat,
        WrappingMode::MirroredRepeat => Wrap::Mirror,
        WrappingMode::ClampToEdge => Wrap::Clamp,
    };
    let factor = hint
        .subsurface
        .as_ref()
        .map_or([0, 1, 2].map(|k| hint.base_color[k]), |s| {
            s.colour.map(|c| c as f32)
        });
    let image = image.and_then(|bytes| colour_texture::decode(&bytes, ColourSpace::Srgb));
    Some(ColourTexture {
        material: hint.name.clone(),
        input: "baseColorTexture".into(),
        file,
        image: image.map(|(image, _)| Arc::new(image)),
        colour_space: "sRGB".into(),
        uv_set,
        uv_set_name: format!("TEXCOORD_{uv_set}"),
        transform: transform.map(|t| UvTransform::Gltf {
            offset: Vec2::from(t.offset()),
            rotation: t.rotation(),
            scale: Vec2::from(t.scale()),
        }),
        wrap: [wrap(sampler.wrap_s()), wrap(sampler.wrap_t())],
        nearest: sampler.mag_filter() == Some(MagFilter::Nearest),
        scale: factor,
        bias: [0.0; 3],
    })
}

/// An image's name for reports (its URI or name) and its bytes, or why
/// they cannot be had.
fn image_of(image: &gltf::Image, context: &Context) -> (String, Result<Vec<u8>, String>) {
    match image.source() {
        gltf::image::Source::Uri { uri, .. } => {
            if let Some(data) = uri.strip_prefix("data:") {
                let name = image
                    .name()
                    .map_or_else(|| format!("image {}", image.index()), String::from);
                let bytes = data
                    .split_once(";base64,")
                    .ok_or_else(|| "a data URI that is not base64".to_string())
                    .and_then(|(_, encoded)| base64_decode(encoded));
                return (name, bytes);
            }
            let path = gltf_uri::local_path(context.folder, uri);
            let bytes =
                std::fs::read(&path).map_err(|e| format!("cannot read {}: {e}", path.display()));
            (path.display().to_string(), bytes)
        }
        gltf::image::Source::View { view, .. } => {
            let name = image
                .name()
                .map_or_else(|| format!("image {}", image.index()), String::from);
            let bytes = context
                .data
                .get(view.buffer().index())
                .and_then(|b| b.get(view.offset()..view.offset() + view.length()))
                .map(<[u8]>::to_vec)
                .ok_or_else(|| format!("buffer view {} lies outside its buffer", view.index()));
            (name, bytes)
        }
    }
}

/// Standard base64 (RFC 4648), as data URIs carry it.
fn base64_decode(text: &str) -> Result<Vec<u8>, String> {
    let mut out = Vec::with_capacity(text.len() * 3 / 4);
    let (mut bits, mut count) = (0u32, 0);
    for c in text
        .bytes()
        .filter(|c| !c.is_ascii_whitespace() && *c != b'=')
    {
        let value = match c {
            b'A'..=b'Z' => c - b'A',
            b'a'..=b'z' => c - b'a' + 26,
            b'0'..=b'9' => c - b'0' + 52,
            b'+' | b'-' => 62,
            b'/' | b'_' => 63,
            _ => return Err("a data URI with a character that is not base64".into()),
        };
        bits = (bits << 6) | u32::from(value);
        count += 6;
        if count >= 8 {
            count -= 8;
            out.push((bits >> count) as u8);
        }
    }
    Ok(out)
}

/// Notes on textures that would vary the scattering distance or colour
/// (`KHR_materials_volume`'s `thicknessTexture`, any texture of
/// `KHR_materials_volume_scatter`): read as their factors, the textures not
/// applied.
fn radius_texture_notes(material: &gltf::Material) -> Vec<String> {
    let name = material.name().unwrap_or("unnamed");
    let note = |what: String| {
        format!(
            "material `{name}`: {what} varies the scattering; it is read as its factor, \
             the texture is not applied"
        )
    };
    let mut notes = Vec::new();
    if let Some(texture) = material.volume().and_then(|v| v.thickness_texture()) {
        notes.push(note(format!(
            "KHR_materials_volume thicknessTexture (texture {})",
            texture.texture().index()
        )));
    }
    if let Some(scatter) = material
        .extension_value("KHR_materials_volume_scatter")
        .and_then(|v| v.as_object())
    {
        for (key, texture) in scatter.iter().filter(|(k, _)| k.ends_with("Texture")) {
            let index = texture.get("index").and_then(|i| i.as_u64());
            notes.push(note(format!(
                "KHR_materials_volume_scatter {key} (texture {})",
                index.map_or_else(|| "?".to_string(), |i| i.to_string())
            )));
        }
    }
    notes
}

/// A volume's extinction σt = −ln(attenuationColor) / attenuationDistance
/// (the KHR_materials_volume definition) gives each channel's mean free
/// path; the colour is KHR_materials_volume_scatter's multiscatterColor
/// when present, else the base colour. A channel the volume does not
/// attenuate is read as attenuating by e^(−0.001) over the distance, so
/// its path stays finite. No subsurface without a finite distance.
fn subsurface_of(
    volume: &Volume,
    base_color: &[f32; 4],
    material: &gltf::Material,
) -> Result<Option<Subsurface>, String> {
    let scatter = Extension::of(material, "KHR_materials_volume_scatter")?;
    let (multiscatter, anisotropy) = match &scatter {
        Some(s) => (
            s.colour("multiscatterColor")?,
            s.number("scatterAnisotropy")?.unwrap_or(0.0),
        ),
        None => (None, 0.0),
    };
    if !(-1.0..=1.0).contains(&anisotropy) {
        return Err(format!(
            "material `{}`: KHR_materials_volume_scatter.scatterAnisotropy is {anisotropy}, \
             outside [-1, 1]",
            material.name().unwrap_or("unnamed")
        ));
    }
    let distance = f64::from(volume.attenuation_distance_mm);
    if !(distance.is_finite() && distance > 0.0) {
        return Ok(None);
    }
    let mean_free_path_mm = volume.attenuation_color.map(|c| {
        let extinction = -f64::from(c).clamp(1e-30, 1.0).ln();
        distance / extinction.max(1e-3)
    });
    let from = if multiscatter.is_some() {
        "KHR_materials_volume attenuation, KHR_materials_volume_scatter colour"
    } else {
        "KHR_materials_volume attenuation, base colour"
    };
    Ok(Some(Subsurface {
        colour: multiscatter.unwrap_or([0, 1, 2].map(|c| f64::from(base_color[c]))),
        mean_free_path_mm,
        anisotropy,
        from: from.to_string(),
    }))
}

/// The start of `asset.generator` in files Blender's glTF exporter writes.
const BLENDER_GENERATOR: &str = "Khronos glTF Blender I/O";

/// The column titles of [`GLTF_LIGHTS`] in docs/lights.md.
pub const GLTF_HEADER: [&str; 3] = [
    "glTF light",
    "read as",
    "irradiance at a point of the plane, × color",
];

/// The glTF table: one row per case, each with a test in
/// `rust/io/tests/light_tables.rs`. d is the distance in metres, θ the
/// angle of incidence, φ the angle from a spot's axis.
pub const GLTF_LIGHTS: &[LightRow] = &[
    LightRow {
        source: "`directional`, `intensity` in lux",
        read_as: "directional",
        irradiance: "(intensity/683)·cos θ",
    },
    LightRow {
        source: "`point`, `intensity` in candela",
        read_as: "point",
        irradiance: "(intensity/683)·cos θ/d²",
    },
    LightRow {
        source: "`spot`, `innerConeAngle` i, `outerConeAngle` o",
        read_as: "spot with the specification's ramp",
        irradiance: "the point's × t², t = clamp((cos φ − cos o)/(cos i − cos o), 0, 1)",
    },
    LightRow {
        source: "`spot` written by Blender (`asset.generator` \"Khronos glTF Blender I/O …\")",
        read_as: "Blender's spot of size 2o and blend b = 1 − i/o",
        irradiance: "the point's × smoothstep((cos φ − cos o)/(b(1 − cos o)))",
    },
];

fn read_light(
    light: &gltf::khr_lights_punctual::Light,
    world: Mat4,
    scale: f64,
    node: usize,
    by_blender: bool,
) -> Light {
    use gltf::khr_lights_punctual::Kind;
    let kind = match light.kind() {
        Kind::Directional => LightKind::Directional { angle: 0.0 },
        Kind::Point => LightKind::Point { radius_mm: 0.0 },
        Kind::Spot {
            inner_cone_angle,
            outer_cone_angle,
        } if by_blender => {
            // Blender writes outer = size/2 and inner = outer × (1 − blend).
            let outer = outer_cone_angle.max(0.0);
            let blend = if outer > 0.0 {
                1.0 - inner_cone_angle / outer
            } else {
                0.0
            };
            let (inner_cone, outer_cone) = spot_cone(outer, blend);
            LightKind::Spot {
                radius_mm: 0.0,
                inner_cone,
                outer_cone,
                falloff: ConeFalloff::Cycles,
            }
        }
        Kind::Spot {
            inner_cone_angle,
            outer_cone_angle,
        } => LightKind::Spot {
            radius_mm: 0.0,
            inner_cone: inner_cone_angle,
            outer_cone: outer_cone_angle,
            falloff: ConeFalloff::Gltf,
        },
    };
    Light {
        name: light
            .name()
            .map_or_else(|| format!("light on node {node}"), String::from),
        kind,
        color: light.color(),
        // Blender's exporter writes a sun's W/m² times 683 lm/W as lux, and
        // a point's W/(4π sr) times 683 lm/W as candela.
        intensity: light.intensity() / LUMENS_PER_WATT,
        position: world.transform_point3(Vec3::ZERO) * scale as f32,
        direction: world
            .transform_vector3(Vec3::NEG_Z)
            .normalize_or(Vec3::NEG_Z),
        tangent: world.transform_vector3(Vec3::X).normalize_or(Vec3::X),
        casts_shadow: true,
    }
}

/// The luminous efficacy glTF exporters (Blender's among them) assume.
const LUMENS_PER_WATT: f32 = 683.0;
