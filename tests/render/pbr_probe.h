// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// A host material that writes the metallic-roughness surface it is handed, for the tests of
// what impostors and meshes hand a material.

namespace si::test {

// Metallic, roughness and occlusion at output 0; the material's index and whether the fragment
// is an impostor's at output 1 (alpha 1 where drawn). Two targets (two_targets.h), float.
inline constexpr const char* kPbrProbe = R"(
layout(location = 0) out vec4 o_pbr;
layout(location = 1) out vec4 o_index;
void siMaterial(SiSurface s) {
  o_pbr = vec4(s.metallic, s.roughness, s.occlusion, 1.0);
  o_index = vec4(float(s.material), s.impostor ? 1.0 : 0.0, 0.0, 1.0);
})";

}  // namespace si::test
