// SkinnedInstancing - SPDX-License-Identifier: MIT (see LICENSE)
// The per-instance record (80 bytes; the same offsets in std140 and std430). Its C++ twin is
// si::InstanceRecord (include/si/crowd/instance_record.h); the build checks the two layouts
// (src/gl/shader_layouts.cpp), the render tests each program's by GL introspection.
//   world_rows: rows of the 3x4 camera-relative world matrix (rotation * scale, translation)
//   frames:     x, y: palette texel of clip A's frame and next frame; z, w: the same for clip B
//   blend:      x: fraction A, y: fraction B (float bits; bits 30-31: the interval mode),
//               z: weight of B (float bits); w: appearance: tint RGB8 (R in the low byte),
//               custom texture layer select in the high byte (0: none; k: layer k - 1)
#ifndef SI_INSTANCE_RECORD_GLSL
#define SI_INSTANCE_RECORD_GLSL
#include "si_profile.glsl"
struct SiInstance {
  vec4 world_rows[3];
  uvec4 frames;
  uvec4 blend;
};
// The instance's tint, RGB in [0, 1].
vec3 siInstanceTint(SiInstance inst) { return siUnpackUnorm4x8(inst.blend.w).rgb; }
// The instance's layer of the application's custom texture array; -1 when it selects none.
int siInstanceCustomLayer(SiInstance inst) { return int(inst.blend.w >> 24u) - 1; }
#endif
