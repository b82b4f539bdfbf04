//! Triangle meshes in millimetres, validated and with normals.

use glam::{Vec2, Vec3};

/// A triangle mesh in world space, millimetres.
#[derive(Clone, Debug, Default)]
pub struct Mesh {
    /// The object's name, for reports and output files.
    pub name: String,
    /// Vertex positions, mm.
    pub positions: Vec<Vec3>,
    /// Unit vertex normals.
    pub normals: Vec<Vec3>,
    /// Texture coordinates per vertex, if the mesh has them.
    pub uvs: Option<Vec<Vec2>>,
    /// Vertex indices, counter-clockwise seen from outside.
    pub triangles: Vec<[u32; 3]>,
}

/// A mesh that cannot be used; says which object and what is wrong.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum MeshError {
    /// A position is NaN or infinite.
    #[error("object `{object}`: vertex {vertex} has a non-finite position {position:?}")]
    NonFinitePosition {
        /// Object name.
        object: String,
        /// Vertex index.
        vertex: usize,
        /// The position.
        position: [f32; 3],
    },
    /// A triangle refers to a vertex that does not exist.
    #[error(
        "object `{object}`: triangle {triangle} refers to vertex {index}, but there are {vertices} vertices"
    )]
    IndexOutOfRange {
        /// Object name.
        object: String,
        /// Triangle index.
        triangle: usize,
        /// The bad vertex index.
        index: u32,
        /// Vertex count.
        vertices: usize,
    },
    /// Per-vertex arrays of different lengths.
    #[error("object `{object}`: {what} has {found} entries for {vertices} vertices")]
    LengthMismatch {
        /// Object name.
        object: String,
        /// Which array.
        what: &'static str,
        /// Its length.
        found: usize,
        /// Vertex count.
        vertices: usize,
    },
    /// Nothing to bake.
    #[error("object `{object}`: has no triangles with area")]
    Empty {
        /// Object name.
        object: String,
    },
}

/// What was repaired or dropped while building a mesh.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct MeshWarnings {
    /// Triangles with zero area, dropped.
    pub degenerate_triangles: usize,
    /// Normals that were missing, zero or not finite, recomputed.
    pub repaired_normals: usize,
    /// UVs that were not finite, set to 0.
    pub repaired_uvs: usize,
}

impl Mesh {
    /// Validates and completes a mesh: positions must be finite and indices
    /// in range; zero-area triangles are dropped; missing or broken normals
    /// are computed from the faces (area-weighted); non-finite UVs become 0.
    pub fn new(
        name: &str,
        positions: Vec<Vec3>,
        normals: Option<Vec<Vec3>>,
        uvs: Option<Vec<Vec2>>,
        triangles: Vec<[u32; 3]>,
    ) -> Result<(Self, MeshWarnings), MeshError> {
        let object = name.to_string();
        let vertices = positions.len();
        if let Some((vertex, p)) = positions.iter().enumerate().find(|(_, p)| !p.is_finite()) {
            return Err(MeshError::NonFinitePosition {
                object,
                vertex,
                position: p.to_array(),
            });
        }
        for (what, found) in [
            ("normals", normals.as_ref().map(Vec::len)),
            ("uvs", uvs.as_ref().map(Vec::len)),
        ] {
            if let Some(found) = found.filter(|&n| n != vertices) {
                return Err(MeshError::LengthMismatch {
                    object,
                    what,
                    found,
                    vertices,
                });
            }
        }
        for (triangle, t) in triangles.iter().enumerate() {
            if let Some(&index) = t.iter().find(|&&i| i as usize >= vertices) {
                return Err(MeshError::IndexOutOfRange {
                    object,
                    triangle,
                    index,
                    vertices,
                });
            }
        }
        let mut warnings = MeshWarnings::default();
        let given = triangles.len();
        let kept: Vec<[u32; 3]> = triangles
            .into_iter()
            .filter(|t| triangle_area(&positions, *t) > 0.0)
            .collect();
        warnings.degenerate_triangles = given - kept.len();
        if kept.is_empty() {
            return Err(MeshError::Empty { object });
        }
        let face_normals = area_weighted_normals(&positions, &kept);
        let mut normals = normals.unwrap_or_else(|| vec![Vec3::ZERO; vertices]);
        for (n, fallback) in normals.iter_mut().zip(&face_normals) {
            if !(n.is_finite() && n.length_squared() > 1e-20) {
                *n = *fallback;
                warnings.repaired_normals += 1;
            } else {
                *n = n.normalize();
            }
        }
        let uvs = uvs.map(|mut uvs| {
            for uv in uvs.iter_mut().filter(|uv| !uv.is_finite()) {
                *uv = Vec2::ZERO;
                warnings.repaired_uvs += 1;
            }
            uvs
        });
        Ok((
            Self {
                name: object,
                positions,
                normals,
                uvs,
                triangles: kept,
            },
            warnings,
        ))
    }

    /// Area of triangle `t`, mm².
    pub fn triangle_area(&self, t: usize) -> f64 {
        triangle_area(&self.positions, self.triangles[t])
    }

    /// Total surface area, mm².
    pub fn area(&self) -> f64 {
        (0..self.triangles.len())
            .map(|t| self.triangle_area(t))
            .sum()
    }
}

/// Area of the triangle with vertex indices `t`, mm², in double precision.
pub fn triangle_area(positions: &[Vec3], t: [u32; 3]) -> f64 {
    let [a, b, c] = t.map(|i| positions[i as usize].as_dvec3());
    0.5 * (b - a).cross(c - a).length()
}

/// Per-vertex normals from the faces around each vertex, weighted by area;
/// +z for a vertex no face touches.
fn area_weighted_normals(positions: &[Vec3], triangles: &[[u32; 3]]) -> Vec<Vec3> {
    let mut sums = vec![glam::DVec3::ZERO; positions.len()];
    for t in triangles {
        let [a, b, c] = t.map(|i| positions[i as usize].as_dvec3());
        let weighted = (b - a).cross(c - a); // length is twice the area
        for &i in t {
            sums[i as usize] += weighted;
        }
    }
    sums.iter()
        .map(|s| s.try_normalize().map_or(Vec3::Z, |n| n.as_vec3()))
        .collect()
}
