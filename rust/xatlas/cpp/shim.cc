#include "sssbake-xatlas/cpp/shim.h"

#include "sssbake-xatlas/src/lib.rs.h"
#include "xatlas.h"

namespace sssbake_xatlas {

namespace {

// Destroys the atlas on every way out of unwrap_mesh, exceptions included.
class AtlasGuard {
  public:
    AtlasGuard() : atlas_(xatlas::Create()) {}
    ~AtlasGuard() { xatlas::Destroy(atlas_); }
    AtlasGuard(const AtlasGuard &) = delete;
    AtlasGuard &operator=(const AtlasGuard &) = delete;
    xatlas::Atlas *get() const { return atlas_; }

  private:
    xatlas::Atlas *atlas_;
};

}  // namespace

Output unwrap_mesh(rust::Slice<const float> positions, rust::Slice<const std::uint32_t> indices,
                   const PackSettings &settings) {
    Output out{};
    AtlasGuard atlas;

    xatlas::MeshDecl decl;
    decl.vertexCount = static_cast<std::uint32_t>(positions.size() / 3);
    decl.vertexPositionData = positions.data();
    decl.vertexPositionStride = 3 * sizeof(float);
    decl.indexCount = static_cast<std::uint32_t>(indices.size());
    decl.indexData = indices.data();
    decl.indexFormat = xatlas::IndexFormat::UInt32;
    const xatlas::AddMeshError::Enum status = xatlas::AddMesh(atlas.get(), decl);
    out.add_mesh_status = static_cast<std::uint32_t>(status);
    if (status != xatlas::AddMeshError::Success) return out;

    xatlas::PackOptions pack;
    pack.resolution = settings.resolution;
    // A chart larger than the map could never be placed in it; xatlas scales
    // charts down to this size instead. Without a resolution, xatlas's default
    // stands.
    if (settings.resolution > 0) pack.maxChartSize = settings.resolution;
    pack.texelsPerUnit = settings.texels_per_unit;
    // xatlas only dilates charts by the padding when packing conservatively.
    pack.conservative = settings.padding > 0;
    pack.padding = settings.padding;
    xatlas::Generate(atlas.get(), xatlas::ChartOptions(), nullptr, pack, nullptr, nullptr);

    const xatlas::Atlas &result = *atlas.get();
    out.width = result.width;
    out.height = result.height;
    out.atlas_count = result.atlasCount;
    out.texels_per_unit = result.texelsPerUnit;
    if (result.meshCount == 0) return out;
    const xatlas::Mesh &mesh = result.meshes[0];
    out.vertices.reserve(mesh.vertexCount);
    for (std::uint32_t i = 0; i < mesh.vertexCount; ++i) {
        const xatlas::Vertex &v = mesh.vertexArray[i];
        out.vertices.push_back(OutputVertex{v.atlasIndex, v.uv[0], v.uv[1], v.xref});
    }
    out.indices.reserve(mesh.indexCount);
    for (std::uint32_t i = 0; i < mesh.indexCount; ++i) out.indices.push_back(mesh.indexArray[i]);
    return out;
}

}  // namespace sssbake_xatlas
