// The C++ half of the bridge between sssbake and xatlas: one call that charts
// and packs one mesh and copies the result into Rust-owned vectors, so no
// xatlas object outlives the call.

#pragma once

#include <cstdint>

#include "rust/cxx.h"

namespace sssbake_xatlas {

struct PackSettings;
struct Output;

// Runs xatlas on one triangle mesh (positions as x, y, z triples, three
// indices per triangle). The caller has checked the inputs; xatlas's own
// verdict on them is returned in Output::add_mesh_status.
Output unwrap_mesh(rust::Slice<const float> positions, rust::Slice<const std::uint32_t> indices,
                   const PackSettings &settings);

}  // namespace sssbake_xatlas
