//! Safe bindings to [xatlas](https://github.com/jpcy/xatlas), which cuts a
//! triangle mesh into charts, flattens each chart and packs them into one or
//! more square texture atlases.
//!
//! xatlas is compiled by this crate's build script from the source the pinned
//! `xatlas-rs` crate ships, without xatlas's thread pool (whose shutdown can
//! hang: see `build.rs`), so it runs in the calling thread; the Rust bindings
//! of `xatlas-rs` are not used. The C++ side lives in `cpp/shim.cc` and is reached
//! through a [`cxx`] bridge, and every call copies xatlas's output into Rust
//! vectors before the atlas is destroyed, so nothing here holds C++ memory.

#[cxx::bridge(namespace = "sssbake_xatlas")]
mod ffi {
    /// What the shim passes to xatlas's `PackOptions`.
    struct PackSettings {
        resolution: u32,
        padding: u32,
        /// 0 asks xatlas to estimate the scale.
        texels_per_unit: f32,
    }

    /// One output vertex as xatlas gives it.
    struct OutputVertex {
        atlas_index: i32,
        u: f32,
        v: f32,
        xref: u32,
    }

    /// Everything one unwrap produced.
    struct Output {
        /// xatlas's `AddMeshError`: 0 is success, and nothing else is set
        /// otherwise.
        add_mesh_status: u32,
        width: u32,
        height: u32,
        atlas_count: u32,
        texels_per_unit: f32,
        vertices: Vec<OutputVertex>,
        indices: Vec<u32>,
    }

    unsafe extern "C++" {
        include!("sssbake-xatlas/cpp/shim.h");

        // A `Result` so that a C++ exception becomes an error here rather
        // than terminating the process.
        fn unwrap_mesh(
            positions: &[f32],
            indices: &[u32],
            settings: &PackSettings,
        ) -> Result<Output>;
    }
}

/// How to chart and pack a mesh.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Options {
    /// Width and height of every atlas, in texels. Charts that do not fit
    /// such an atlas are scaled down to fit, and charts that do not fit
    /// together open further atlases (see [`Atlas::atlas_count`]). 0 packs
    /// everything into one atlas whose size follows from
    /// [`texels_per_unit`](Self::texels_per_unit).
    pub resolution: u32,
    /// Texels by which each chart is dilated when packing, so that charts
    /// stay at least this far apart. 0 packs charts edge to edge.
    pub padding: u32,
    /// Texels per unit of length of the positions (a unit square covers
    /// about this many texels squared). `None` lets xatlas estimate the scale
    /// at which the charts fill `resolution`² (or about 1024² when the
    /// resolution is 0) at 75% utilisation. When given, it must be positive
    /// and finite.
    pub texels_per_unit: Option<f32>,
}

impl Default for Options {
    /// xatlas's defaults: one atlas of about 1024², no padding.
    fn default() -> Self {
        Options {
            resolution: 0,
            padding: 0,
            texels_per_unit: None,
        }
    }
}

/// One vertex of the unwrapped mesh. Vertices on chart seams are split, so
/// one input vertex may become several.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Vertex {
    /// Position in the atlas in texels: u in [0, [`Atlas::width`]], v in
    /// [0, [`Atlas::height`]]; divide by those for [0, 1] coordinates. (0, 0)
    /// for a vertex of no chart.
    pub uv: [f32; 2],
    /// The input vertex this one copies (an index into the positions'
    /// triples).
    pub xref: u32,
    /// The atlas that holds this vertex's chart, or `None` when the vertex
    /// belongs to no chart (it is used only by faces xatlas left out, such as
    /// degenerate ones).
    pub atlas_index: Option<u32>,
}

/// The result of [`unwrap`].
#[derive(Clone, Debug, PartialEq)]
pub struct Atlas {
    /// Width of every atlas, in texels.
    pub width: u32,
    /// Height of every atlas, in texels.
    pub height: u32,
    /// Number of atlases the charts were packed into. xatlas reports 0 when
    /// [`Options::resolution`] is 0 (then there is one atlas) and when there
    /// was nothing to pack.
    pub atlas_count: u32,
    /// The scale used, in texels per unit of length of the positions: the one
    /// given in [`Options`] or xatlas's estimate. 0 when there was nothing to
    /// pack.
    pub texels_per_unit: f32,
    /// The output vertices.
    pub vertices: Vec<Vertex>,
    /// Three indices into [`vertices`](Self::vertices) per triangle, the
    /// input's triangles in the input's order.
    pub indices: Vec<u32>,
}

/// Why [`unwrap`] failed.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum Error {
    /// The positions are not a whole number of x, y, z triples.
    #[error("{0} position components are not a whole number of x, y, z triples")]
    PositionsNotTriples(usize),
    /// The indices are not a whole number of triangles.
    #[error("{0} indices are not a whole number of triangles")]
    IndicesNotTriangles(usize),
    /// The mesh has more vertices or indices than xatlas can count (2³² − 1).
    #[error("the mesh is too large for xatlas")]
    TooLarge,
    /// An index names a vertex that does not exist.
    #[error("index {index} is out of range for {vertices} vertices")]
    IndexOutOfRange {
        /// The offending index.
        index: u32,
        /// Number of vertices.
        vertices: u32,
    },
    /// A position is infinite or NaN.
    #[error("vertex {0} has a position that is not finite")]
    NonFinitePosition(usize),
    /// [`Options::texels_per_unit`] is given but not positive and finite.
    #[error("texels per unit must be positive and finite, got {0}")]
    InvalidTexelsPerUnit(f32),
    /// xatlas's `AddMesh` refused the mesh with this `AddMeshError` status.
    #[error("xatlas refused the mesh (status {0})")]
    Refused(u32),
    /// The C++ side threw an exception, with its message.
    #[error("xatlas failed: {0}")]
    Exception(String),
    /// xatlas's output refers to vertices that do not exist.
    #[error("xatlas returned indices out of range")]
    InvalidOutput,
}

/// Charts and packs the triangle mesh given by `positions` (x, y, z per
/// vertex, in any unit of length) and `indices` (three per triangle, into the
/// vertices). The result is deterministic for the same input and options.
/// Faces xatlas cannot chart (those with a repeated vertex, a zero-length edge
/// or no area) keep their place in [`Atlas::indices`] but get vertices of no
/// chart. A mesh without triangles gives an empty [`Atlas`].
///
/// # Errors
///
/// When the input is malformed (see [`Error`]), when `options` are invalid,
/// or when xatlas refuses the mesh or fails.
pub fn unwrap(positions: &[f32], indices: &[u32], options: &Options) -> Result<Atlas, Error> {
    if !positions.len().is_multiple_of(3) {
        return Err(Error::PositionsNotTriples(positions.len()));
    }
    if !indices.len().is_multiple_of(3) {
        return Err(Error::IndicesNotTriangles(indices.len()));
    }
    let vertex_count = u32::try_from(positions.len() / 3).map_err(|_| Error::TooLarge)?;
    u32::try_from(indices.len()).map_err(|_| Error::TooLarge)?;
    if let Some(&index) = indices.iter().find(|&&i| i >= vertex_count) {
        return Err(Error::IndexOutOfRange {
            index,
            vertices: vertex_count,
        });
    }
    // xatlas computes grid cells and chart extents from the positions; a NaN
    // or an infinity there would be converted to an integer, which C++ leaves
    // undefined.
    if let Some(vertex) = positions.iter().position(|p| !p.is_finite()) {
        return Err(Error::NonFinitePosition(vertex / 3));
    }
    let texels_per_unit = match options.texels_per_unit {
        None => 0.0,
        Some(t) if t.is_finite() && t > 0.0 => t,
        Some(t) => return Err(Error::InvalidTexelsPerUnit(t)),
    };
    // xatlas reads a mesh without indices as a triangle soup of its
    // vertices; here no triangles means nothing to unwrap.
    if indices.is_empty() {
        return Ok(Atlas {
            width: 0,
            height: 0,
            atlas_count: 0,
            texels_per_unit: 0.0,
            vertices: Vec::new(),
            indices: Vec::new(),
        });
    }
    let settings = ffi::PackSettings {
        resolution: options.resolution,
        padding: options.padding,
        texels_per_unit,
    };
    let output = ffi::unwrap_mesh(positions, indices, &settings)
        .map_err(|e| Error::Exception(e.what().to_owned()))?;
    if output.add_mesh_status != 0 {
        return Err(Error::Refused(output.add_mesh_status));
    }
    let output_vertices = output.vertices.len();
    if output.indices.len() != indices.len()
        || output
            .indices
            .iter()
            .any(|&i| i as usize >= output_vertices)
        || output.vertices.iter().any(|v| v.xref >= vertex_count)
    {
        return Err(Error::InvalidOutput);
    }
    Ok(Atlas {
        width: output.width,
        height: output.height,
        atlas_count: output.atlas_count,
        texels_per_unit: output.texels_per_unit,
        vertices: output
            .vertices
            .iter()
            .map(|v| Vertex {
                uv: [v.u, v.v],
                xref: v.xref,
                atlas_index: u32::try_from(v.atlas_index).ok(),
            })
            .collect(),
        indices: output.indices,
    })
}
