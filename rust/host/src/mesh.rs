//! A host's mesh as flat arrays, read into the library's object: identical
//! vertices shared, triangles without area left out, each kept triangle's
//! material index kept in step.

use glam::{Vec2, Vec3};
use sssbake::{Error, Mesh, SceneObject};
use std::collections::HashMap;

/// One mesh as a host holds it. Positions are x, y, z in scene units, world
/// space; normals unit vectors; UVs u, v with v running up (Blender's and
/// OpenGL's order). Triangles are three indices each, counter-clockwise seen
/// from outside.
#[derive(Clone, Copy, Debug)]
pub struct HostMesh<'a> {
    /// The object's name.
    pub name: &'a str,
    /// 3 floats per vertex.
    pub positions: &'a [f32],
    /// 3 floats per vertex, or `None` to compute them.
    pub normals: Option<&'a [f32]>,
    /// 2 floats per vertex (UV set 0, the one baked into), or `None` to
    /// unwrap.
    pub uvs: Option<&'a [f32]>,
    /// Vertex indices, three per triangle.
    pub indices: &'a [u32],
    /// One material index per triangle (into the materials of
    /// [`bake_materials`](crate::bake_materials)), or `None`: all 0.
    pub material_indices: Option<&'a [u32]>,
    /// Further UV sets (2 floats per vertex each, v running up) that a
    /// base-colour image may read as UV sets 1, 2, …
    pub texture_uvs: &'a [&'a [f32]],
}

/// A setting-kind error about the mesh of `object`.
fn argument(object: &str, message: String) -> Error {
    Error::field("mesh", format!("object `{object}`: {message}"))
}

/// The library's object for `mesh` in a scene of `scale` millimetres per
/// unit, with the material index of each triangle it keeps when the mesh
/// gives them. Vertices equal bit for bit in every attribute are shared, so
/// a host may pass one vertex per triangle corner.
pub fn object_from_host(
    mesh: &HostMesh,
    scale: f64,
) -> Result<(SceneObject, Option<Vec<u32>>), Error> {
    let name = mesh.name;
    if !mesh.positions.len().is_multiple_of(3) {
        return Err(argument(
            name,
            format!(
                "{} position floats is not 3 per vertex",
                mesh.positions.len()
            ),
        ));
    }
    let n = mesh.positions.len() / 3;
    let per_vertex = |what: &str, values: usize, len: usize| {
        if len == values * n {
            Ok(())
        } else {
            Err(argument(
                name,
                format!(
                    "{what} holds {len} floats; {n} vertices need {}",
                    values * n
                ),
            ))
        }
    };
    if let Some(normals) = mesh.normals {
        per_vertex("normals", 3, normals.len())?;
    }
    if let Some(uvs) = mesh.uvs {
        per_vertex("uvs", 2, uvs.len())?;
    }
    for (k, set) in mesh.texture_uvs.iter().enumerate() {
        per_vertex(&format!("texture UV set {}", k + 1), 2, set.len())?;
        if set.iter().any(|c| !c.is_finite()) {
            return Err(argument(
                name,
                "texture_uvs hold a value that is not finite".into(),
            ));
        }
    }
    let indices = mesh.indices;
    if !indices.len().is_multiple_of(3) {
        return Err(argument(
            name,
            format!("{} indices is not three per triangle", indices.len()),
        ));
    }
    if let Some(bad) = indices.iter().find(|&&i| i as usize >= n) {
        return Err(Error::input(format!("index {bad} but {n} vertices")).for_object(name));
    }
    if let Some(m) = mesh.material_indices
        && m.len() != indices.len() / 3
    {
        return Err(argument(
            name,
            format!(
                "{} material indices for {} triangles",
                m.len(),
                indices.len() / 3
            ),
        ));
    }
    // Share vertices equal bit for bit in every attribute.
    let mut shared: HashMap<Vec<u32>, u32> = HashMap::new();
    let mut remap = Vec::with_capacity(n);
    let (mut p, mut nr, mut uv) = (Vec::new(), Vec::new(), Vec::new());
    let mut sets: Vec<Vec<Vec2>> = vec![Vec::new(); mesh.texture_uvs.len()];
    for v in 0..n {
        let position = Vec3::from_slice(&mesh.positions[3 * v..3 * v + 3]);
        let normal = mesh
            .normals
            .map_or(Vec3::ZERO, |s| Vec3::from_slice(&s[3 * v..3 * v + 3]));
        let coord = mesh
            .uvs
            .map_or(Vec2::ZERO, |s| Vec2::from_slice(&s[2 * v..2 * v + 2]));
        let texture_coord = |k: usize| Vec2::from_slice(&mesh.texture_uvs[k][2 * v..2 * v + 2]);
        let mut key: Vec<u32> = [
            position.x, position.y, position.z, normal.x, normal.y, normal.z, coord.x, coord.y,
        ]
        .map(f32::to_bits)
        .to_vec();
        for k in 0..sets.len() {
            key.extend(texture_coord(k).to_array().map(f32::to_bits));
        }
        let index = *shared.entry(key).or_insert_with(|| {
            p.push(position * scale as f32);
            nr.push(normal);
            uv.push(coord);
            for (k, set) in sets.iter_mut().enumerate() {
                set.push(texture_coord(k));
            }
            (p.len() - 1) as u32
        });
        remap.push(index);
    }
    // Triangles without area are left out here (Mesh::new would drop them)
    // so that the material indices stay in step with the mesh's triangles.
    let mut kept_materials = Vec::new();
    let triangles = indices
        .chunks_exact(3)
        .enumerate()
        .map(|(f, t)| (f, [t[0], t[1], t[2]].map(|i| remap[i as usize])))
        .filter(|&(_, t)| sssbake::mesh::triangle_area(&p, t) > 0.0)
        .map(|(f, t)| {
            if let Some(m) = mesh.material_indices {
                kept_materials.push(m[f]);
            }
            t
        })
        .collect();
    let uvs = mesh.uvs.map(|_| uv);
    let (built, _) = Mesh::new(name, p, mesh.normals.map(|_| nr), uvs.clone(), triangles)
        .map_err(|e| Error::input(e.to_string()))?;
    // UV set 0 is the baked one, so texture sets keep their numbers even
    // on a mesh without it.
    let uv_sets = if sets.is_empty() {
        uvs.into_iter().collect()
    } else {
        std::iter::once(uvs.unwrap_or_default())
            .chain(sets)
            .collect()
    };
    let object = SceneObject {
        mesh: built,
        uv_sets,
        ..SceneObject::default()
    };
    Ok((object, mesh.material_indices.map(|_| kept_materials)))
}
