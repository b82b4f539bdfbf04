/* A host written in C: builds a lit quad from arrays, bakes it with
   sssbake_bake and writes its subsurface map with sssbake_result_write_exr.
   tests/c_host.rs compiles and runs it, and bakes the same quad through
   the Rust library to compare the files byte for byte.

   Usage: bake OUT.exr */

#include <stdio.h>
#include <string.h>

#include "sssbake.h"

/* The quad of tests/c_host.rs: 40 mm square in the xy plane, facing +z. */
static const float POSITIONS[] = {-20, -20, 0, 20, -20, 0, 20, 20, 0, -20, 20, 0};
static const float NORMALS[] = {0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1};
static const float UVS[] = {0.125f, 0.125f, 0.875f, 0.125f, 0.875f, 0.875f, 0.125f, 0.875f};
static const uint32_t INDICES[] = {0, 1, 2, 0, 2, 3};

static int failed(const char *what, SssbakeStatus status) {
    fprintf(stderr, "%s: status %d: %s\n", what, (int)status, sssbake_last_error());
    return 1;
}

int main(int argc, char **argv) {
    if (argc != 2) {
        fprintf(stderr, "usage: %s OUT.exr\n", argv[0]);
        return 2;
    }
    if (sssbake_abi_version() != SSSBAKE_ABI_VERSION) {
        fprintf(stderr, "the library speaks ABI %u, the header %u\n", sssbake_abi_version(),
                (unsigned)SSSBAKE_ABI_VERSION);
        return 1;
    }
    SssbakeScene *scene = NULL;
    SssbakeStatus status = sssbake_scene_new(1.0, &scene);
    if (status != SSSBAKE_STATUS_OK) return failed("sssbake_scene_new", status);

    SssbakeMesh mesh = {
        .name = "Quad",
        .positions = POSITIONS,
        .normals = NORMALS,
        .uvs = UVS,
        .vertex_count = 4,
        .indices = INDICES,
        .index_count = 6,
    };
    status = sssbake_scene_add_mesh(scene, &mesh);
    if (status != SSSBAKE_STATUS_OK) return failed("sssbake_scene_add_mesh", status);

    SssbakeLight sun;
    memset(&sun, 0, sizeof sun);
    sun.kind = SSSBAKE_LIGHT_SUN;
    sun.colour[0] = 1.0f, sun.colour[1] = 0.9f, sun.colour[2] = 0.8f;
    sun.power = 3.0f;
    sun.direction[0] = 0.0f, sun.direction[1] = -0.6f, sun.direction[2] = -0.8f;
    sun.tangent[0] = 1.0f;
    /* Blender's defaults: no temperature tint, all of it diffuse, normalized, shadowed. */
    sun.temperature_colour[0] = sun.temperature_colour[1] = sun.temperature_colour[2] = 1.0f;
    sun.diffuse_factor = 1.0f;
    sun.normalize = 1;
    sun.casts_shadow = 1;
    status = sssbake_scene_add_light(scene, &sun);
    if (status != SSSBAKE_STATUS_OK) return failed("sssbake_scene_add_light", status);

    SssbakeMaterial material;
    memset(&material, 0, sizeof material);
    material.kind = SSSBAKE_MATERIAL_PRESET;
    material.name = "skin1";

    SssbakeSettings settings;
    status = sssbake_settings_default(&settings);
    if (status != SSSBAKE_STATUS_OK) return failed("sssbake_settings_default", status);
    settings.resolution = 32;
    settings.method = 1; /* brute: the exact sum */
    settings.outputs = 1; /* bit 0: subsurface */

    SssbakeResult *result = NULL;
    status = sssbake_bake(scene, "Quad", &material, &settings, NULL, NULL, NULL, &result);
    if (status != SSSBAKE_STATUS_OK) return failed("sssbake_bake", status);
    status = sssbake_result_write_exr(result, 0, argv[1], 0);
    if (status != SSSBAKE_STATUS_OK) return failed("sssbake_result_write_exr", status);
    /* A handle freed twice would be refused with a status; each is freed once. */
    status = sssbake_result_free(result);
    if (status != SSSBAKE_STATUS_OK) return failed("sssbake_result_free", status);
    status = sssbake_scene_free(scene);
    if (status != SSSBAKE_STATUS_OK) return failed("sssbake_scene_free", status);
    return 0;
}
