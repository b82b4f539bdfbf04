// A C entry point to xatlas for sssbake.
//
// xatlas itself is compiled from the xatlas-rs crate's sources by that
// crate's build script. This file declares the few xatlas types and
// functions the unwrap uses, as that version of xatlas defines them, and
// offers Rust three plain C functions: unwrap, read the result, free it.

#include <stdint.h>

namespace xatlas {

struct Chart {
    uint32_t atlasIndex;
    uint32_t *indexArray;
    uint32_t indexCount;
};

struct Vertex {
    int32_t atlasIndex;
    float uv[2];
    uint32_t xref;
};

struct Mesh {
    Chart *chartArray;
    uint32_t chartCount;
    uint32_t *indexArray;
    uint32_t indexCount;
    Vertex *vertexArray;
    uint32_t vertexCount;
};

struct Atlas {
    uint32_t width;
    uint32_t height;
    uint32_t atlasCount;
    uint32_t chartCount;
    uint32_t meshCount;
    Mesh *meshes;
    float *utilization;
    float texelsPerUnit;
};

struct IndexFormat {
    enum Enum { UInt16, UInt32 };
};

struct MeshDecl {
    uint32_t vertexCount = 0;
    const void *vertexPositionData = nullptr;
    uint32_t vertexPositionStride = 0;
    const void *vertexNormalData = nullptr;
    uint32_t vertexNormalStride = 0;
    const void *vertexUvData = nullptr;
    uint32_t vertexUvStride = 0;
    uint32_t indexCount = 0;
    const void *indexData = nullptr;
    int32_t indexOffset = 0;
    IndexFormat::Enum indexFormat = IndexFormat::UInt16;
    const bool *faceIgnoreData = nullptr;
};

struct AddMeshError {
    enum Enum { Success, IndexOutOfRange, InvalidIndexCount };
};

struct ProgressCategory {
    enum Enum { ComputeCharts, ParameterizeCharts, PackCharts, BuildOutputMeshes };
};

typedef void (*ProgressFunc)(ProgressCategory::Enum category, int progress, void *userData);
typedef void (*ParameterizeFunc)(const float *positions, float *texcoords, uint32_t vertexCount,
                                 const uint32_t *indices, uint32_t indexCount, bool isPlanar);

struct ChartOptions {
    float maxChartArea = 0.0f;
    float maxBoundaryLength = 0.0f;
    float proxyFitMetricWeight = 2.0f;
    float roundnessMetricWeight = 0.01f;
    float straightnessMetricWeight = 6.0f;
    float normalSeamMetricWeight = 4.0f;
    float textureSeamMetricWeight = 0.5f;
    float maxThreshold = 2.0f;
    uint32_t growFaceCount = 32;
    uint32_t maxIterations = 1;
};

struct PackOptions {
    int attempts = 4096;
    float texelsPerUnit = 0.0f;
    uint32_t resolution = 0;
    uint32_t maxChartSize = 1024;
    bool blockAlign = false;
    bool conservative = false;
    uint32_t padding = 0;
};

Atlas *Create();
void Destroy(Atlas *atlas);
AddMeshError::Enum AddMesh(Atlas *atlas, const MeshDecl &meshDecl);
void Generate(Atlas *atlas, ChartOptions chartOptions, ParameterizeFunc paramFunc,
              PackOptions packOptions, ProgressFunc progressFunc, void *progressUserData);

}  // namespace xatlas

extern "C" {

// Unwraps one triangle mesh into a single atlas of `resolution` texels with
// `padding` texels between charts. Returns an atlas handle (null when the
// mesh was refused) and writes the add-mesh status to `status`.
void *sssbake_unwrap(const float *positions, uint32_t vertex_count, const uint32_t *indices,
                     uint32_t index_count, uint32_t resolution, uint32_t padding, float texels_per_unit,
                     int *status) {
    xatlas::Atlas *atlas = xatlas::Create();
    xatlas::MeshDecl decl;
    decl.vertexCount = vertex_count;
    decl.vertexPositionData = positions;
    decl.vertexPositionStride = 3 * sizeof(float);
    decl.indexCount = index_count;
    decl.indexData = indices;
    decl.indexFormat = xatlas::IndexFormat::UInt32;
    *status = xatlas::AddMesh(atlas, decl);
    if (*status != xatlas::AddMeshError::Success) {
        xatlas::Destroy(atlas);
        return nullptr;
    }
    xatlas::PackOptions pack;
    pack.resolution = resolution;
    pack.maxChartSize = resolution;
    pack.texelsPerUnit = texels_per_unit;
    pack.conservative = padding > 0;
    pack.padding = padding;
    xatlas::Generate(atlas, xatlas::ChartOptions(), nullptr, pack, nullptr, nullptr);
    return atlas;
}

// Sizes of the result: atlas width, height, number of atlases, texels per
// unit, output vertices and indices.
void sssbake_unwrap_sizes(const void *handle, uint32_t *width, uint32_t *height, uint32_t *atlases,
                          float *texels_per_unit, uint32_t *vertices, uint32_t *indices) {
    const xatlas::Atlas *atlas = static_cast<const xatlas::Atlas *>(handle);
    *width = atlas->width;
    *height = atlas->height;
    *atlases = atlas->atlasCount;
    *texels_per_unit = atlas->texelsPerUnit;
    *vertices = atlas->meshCount > 0 ? atlas->meshes[0].vertexCount : 0;
    *indices = atlas->meshCount > 0 ? atlas->meshes[0].indexCount : 0;
}

// Copies the output: per vertex its atlas index, uv (in atlas texels) and
// source vertex; then the triangle indices.
void sssbake_unwrap_read(const void *handle, int32_t *atlas_index, float *uv, uint32_t *xref,
                         uint32_t *indices) {
    const xatlas::Atlas *atlas = static_cast<const xatlas::Atlas *>(handle);
    if (atlas->meshCount == 0) return;
    const xatlas::Mesh &mesh = atlas->meshes[0];
    for (uint32_t i = 0; i < mesh.vertexCount; ++i) {
        atlas_index[i] = mesh.vertexArray[i].atlasIndex;
        uv[2 * i] = mesh.vertexArray[i].uv[0];
        uv[2 * i + 1] = mesh.vertexArray[i].uv[1];
        xref[i] = mesh.vertexArray[i].xref;
    }
    for (uint32_t i = 0; i < mesh.indexCount; ++i) indices[i] = mesh.indexArray[i];
}

void sssbake_unwrap_free(void *handle) { xatlas::Destroy(static_cast<xatlas::Atlas *>(handle)); }

}  // extern "C"
