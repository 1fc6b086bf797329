// SkinnedInstancing - SPDX-License-Identifier: MIT (see LICENSE)
// Animated impostors (Renderer::buildImpostor): one quad per instance at the crowd's impostor
// level, a triangle strip of 4 vertices (impostor_quad.glsl: the cell and quad from the
// instance's record; its clip and frame are the heavier clip's of a crossfade).
// SI_GPU_DRIVEN: the quad the impostor quads pass computed and kept (impostor_quads.comp.glsl),
// by gl_InstanceID, with the instance's handle.
// SI_DEPTH_ONLY: the atlas coordinate alone (the fragment stage tests coverage only).
// SI_INSTANCE_HANDLE: also the instance's handle (instance_handle.glsl).
#include "impostor_quad.glsl"
#include "instance_handle.glsl"
#ifdef SI_GPU_DRIVEN
// The impostor quads pass's quads (impostor_quads.comp.glsl), 4 words each (the last: the
// instance's handle), by instance.
layout(std430, binding = 15) readonly buffer SiImpostorQuads { uvec4 si_impostor_quads[]; };
#else
layout(std140, binding = 0) uniform SiInstances { SiInstance si_instances[SI_MAX_INSTANCES]; };
#endif
uniform uint u_lod;  // The crowd's impostor level (SiSurface.lod).
out vec2 v_uv;
#ifndef SI_DEPTH_ONLY
out vec3 v_position;
flat out uint v_color;
flat out uint v_lod;
// The quad's frame in world axes: right, up, towards the viewer (the atlas normal's axes).
flat out vec3 v_right;
flat out vec3 v_up;
flat out vec3 v_towards;
#endif
void main() {
#ifdef SI_GPU_DRIVEN
  uint i = 4u * uint(gl_InstanceID);
  SiImpostorQuad q =
      siUnpackImpostorQuad(si_impostor_quads[i], si_impostor_quads[i + 1u], si_impostor_quads[i + 2u]);
#ifdef SI_INSTANCE_HANDLE
  v_instance_handle = si_impostor_quads[i + 3u].x;
#endif
#else
  SiImpostorQuad q = siImpostorQuad(si_instances[gl_InstanceID]);
#ifdef SI_INSTANCE_HANDLE
  v_instance_handle = siSlotHandle(uint(gl_InstanceID));
#endif
#endif
  vec2 corner = mix(q.rect.xy, q.rect.zw, vec2(float(gl_VertexID & 1), float(gl_VertexID >> 1)));
  v_uv = (vec2(float(q.cell % u_impostor_grid.x), float(q.cell / u_impostor_grid.x)) + corner) /
         vec2(u_impostor_grid.xy);
  vec3 world = q.centre + (corner.x - 0.5) * q.right + (corner.y - 0.5) * q.up;
#ifndef SI_DEPTH_ONLY
  v_position = world;
  v_color = q.color;
  v_lod = u_lod;
  v_right = normalize(q.right);
  v_up = normalize(q.up);
  v_towards = u_viewer.w > 0.5 ? u_viewer.xyz : -normalize(q.centre);  // As the quad faced.
#endif
  gl_Position = u_view_projection * vec4(world, 1.0);
}
