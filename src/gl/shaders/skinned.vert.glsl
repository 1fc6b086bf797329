// SkinnedInstancing - SPDX-License-Identifier: MIT (see LICENSE)
// The vertex-shader skinning path (B. Dudash, "Skinned Instancing", NVIDIA 2007): the instance's
// record through gl_InstanceID, up to 4 influences (8 with SI_EIGHT_INFLUENCES), the world
// transform.
// Variants: SI_RIGID (no skinning: the rigid-instancing floor), SI_CAPTURE (also outputs the
// model-space position for transform feedback), SI_GPU_DRIVEN (the record through a bucket
// entry, from storage buffers), SI_TRADITIONAL (one character per draw, its joint matrices in
// a uniform block), SI_MOTION_VECTORS (also the clip positions of the vertex under the crowd's
// last update camera and, skinned with its previous record, under the previous one: the
// fragment shader's motion output; drawCrowd's previous records through an index,
// previous_index.glsl; with SI_GPU_DRIVEN the cull pass's previous records),
// SI_LAYERS (each instance's overlay composed on its mask: siSkinLayered; with SI_COMPOSED_LAYERS
// its masked slots' rows read from the compose pass, siSkinComposed, layer_compose.glsl),
// SI_VERTEX_WORDS (also texture coordinates 1 and the colour: meshes that have them),
// SI_INSTANCE_HANDLE (also the instance's handle: instance_handle.glsl), SI_EIGHT_INFLUENCES
// (influences 5 to 8 too, attributes 10 and 11: the skinning sum is linear in the weights, so
// each set's sum is added), SI_MORPH_TARGETS (the vertex's morph targets added before skinning,
// its morph word attribute 12: si_morph.glsl, with SI_LAYERS the overlay's on its mask's
// targets; with SI_TRADITIONAL the weights the CPU computed, in the character's block).
#define SI_VERTEX_MATERIALS
#if defined(SI_GPU_DRIVEN) && defined(SI_LAYERS)
#define SI_LAYERS_IN_STORAGE  // The cull pass's layer records, by visible index.
#define SI_LAYER_BINDING 18
#endif
#ifdef SI_MOTION_VECTORS
#define SI_PREVIOUS_RECORDS
#ifdef SI_GPU_DRIVEN
#define SI_PREVIOUS_IN_STORAGE  // The cull pass's previous (layer) records, by visible index.
#define SI_PREVIOUS_BINDING 20
#define SI_PREVIOUS_LAYER_BINDING 21
#endif
#endif
#include "material_common.glsl"
#ifdef SI_TRADITIONAL
#define SI_INSTANCE_HANDLE_UNIFORM
#include "si_transform.glsl"
#ifdef SI_MORPH_TARGETS
#define SI_TRADITIONAL_MORPH_TARGETS 256  // si::detail::kTraditionalMorphTargets
#endif
layout(std140 SI_WITH_BINDING(1)) uniform SiCharacter {
  vec4 si_world_rows[3];
  uint si_color;
#ifdef SI_MORPH_TARGETS
  vec4 si_morph_weights[SI_TRADITIONAL_MORPH_TARGETS / 4];  // Computed on the CPU.
#endif
  vec4 si_joint_rows[3 * SI_MAX_JOINTS];
};
#ifdef SI_MORPH_TARGETS
#include "si_instance_record.glsl"
layout(std140 SI_WITH_BINDING(4)) uniform SiPaletteInfo {
  uvec4 si_palette_info;
  uvec4 si_morph_info;
  vec4 si_morph_cuts[2];
};
#define SI_MORPH_WEIGHTS_IN_BLOCK  // si_morph.glsl reads the block's weights.
#include "si_morph.glsl"
#endif
#else
#include "si_skinning.glsl"
#ifdef SI_COMPOSED_LAYERS
#define SI_COMPOSED_READ
#ifndef SI_GPU_DRIVEN
#define SI_COMPOSED_BY_SLOT  // drawCrowd: each slot's composed record.
#endif
#include "layer_compose.glsl"
#endif
#if defined(SI_MOTION_VECTORS) && !defined(SI_GPU_DRIVEN)
#include "previous_index.glsl"  // drawCrowd's previous records, by index.
#endif
#if defined(SI_COMPOSED_LAYERS) || defined(SI_MOTION_VECTORS)
#include "batch_slot.glsl"
#endif
#endif
#include "instance_handle.glsl"

layout(location = 0) in vec3 a_position;
layout(location = 1) in vec4 a_normal;
layout(location = 2) in vec2 a_texcoord;
layout(location = 3) in uvec4 a_joints;
layout(location = 4) in vec4 a_weights;
// The tangent (xyz, w the bitangent's sign); w 0 where the mesh has none (the normal's bits).
layout(location = 7) in vec4 a_tangent;
#ifdef SI_EIGHT_INFLUENCES
layout(location = 10) in uvec4 a_joints1;
layout(location = 11) in vec4 a_weights1;
// Adds the second set's rows to m0, m1, m2: CALL is the first set's skinning call with
// a_joints1 and a_weights1, writing si_e0, si_e1, si_e2.
#define SI_SECOND_SET(CALL, m0, m1, m2) \
  {                                     \
    vec4 si_e0, si_e1, si_e2;           \
    CALL;                               \
    m0 += si_e0;                        \
    m1 += si_e1;                        \
    m2 += si_e2;                        \
  }
#else
#define SI_SECOND_SET(CALL, m0, m1, m2)
#endif
#if defined(SI_MORPH_TARGETS) && defined(SI_TRADITIONAL)
layout(location = 12) in uint a_morph;
// The block's weights: no record, no layer.
#define SI_MORPH_VERTEX(inst, layer, previous, lod, p, n, t) siMorphLayered(siNoInstance(), uvec4(0u), a_morph, lod, p, n, t)
#elif defined(SI_MORPH_TARGETS) && defined(SI_COMPOSED_LAYERS)
layout(location = 12) in uint a_morph;
// The compose pass's weights for the instance's composed record (`composed`, in main).
#define SI_MORPH_VERTEX(inst, layer, previous, lod, p, n, t) siMorphComposed(inst, layer, composed, previous, a_morph, lod, p, n, t)
#elif defined(SI_MORPH_TARGETS)
layout(location = 12) in uint a_morph;
#define SI_MORPH_VERTEX(inst, layer, previous, lod, p, n, t) siMorphLayered(inst, layer, a_morph, lod, p, n, t)
#else
#define SI_MORPH_VERTEX(inst, layer, previous, lod, p, n, t)
#endif
#ifdef SI_LAYERS  // The overlay moves the targets its mask holds.
#define SI_MORPH_LAYER(slot) si_layers[slot]
#define SI_MORPH_PREVIOUS_LAYER(slot) si_previous_layers[slot]
#else
#define SI_MORPH_LAYER(slot) uvec4(0u)
#define SI_MORPH_PREVIOUS_LAYER(slot) uvec4(0u)
#endif
#include "vertex_words.glsl"
SI_LOCATION_LAYOUT(1) uniform mat4 u_view_projection;
SI_VARYING_LAYOUT(0) out vec3 v_position;  // Camera-relative world position (SiSurface.position).
SI_VARYING_LAYOUT(1) out vec3 v_normal;
// Skinned as the normal is (the seed's S), w kept; cross(N, T) in the fragment stage gives the
// bitangent.
SI_VARYING_LAYOUT(2) out vec4 v_tangent;
SI_VARYING_LAYOUT(3) out vec2 v_texcoord;
SI_VARYING_LAYOUT(4) flat out uint v_color;
SI_VARYING_LAYOUT(5) flat out uint v_material;
SI_VARYING_LAYOUT(6) flat out uint v_lod;
#ifndef SI_GPU_DRIVEN
uniform uint u_lod;  // The batch's LOD (SiSurface.lod).
#endif
#ifdef SI_CAPTURE
out vec3 tf_position;
#endif
#ifdef SI_MOTION_VECTORS
uniform mat4 u_motion_view_projection;    // The crowd's last update camera.
uniform mat4 u_previous_view_projection;  // The update camera before it.
SI_VARYING_LAYOUT(7) out vec4 v_motion_current;
SI_VARYING_LAYOUT(8) out vec4 v_motion_previous;
#endif
#ifdef SI_GPU_DRIVEN
// GPU-driven culling: the record of this draw's instance, through its bucket entry; a_entry is
// baseInstance + gl_InstanceID (an identity buffer with divisor 1).
layout(location = 5) in uint a_entry;
layout(std430, binding = 4) readonly buffer SiRecords { SiInstance si_records[]; };
layout(std430, binding = 5) readonly buffer SiEntries { uint si_entries[]; };
// The cull pass's visible list: x dense index, y LOD, z worn mask, w handle (cull_common.glsl).
layout(std430, binding = 6) readonly buffer SiVisible { uvec4 si_visible[]; };
#endif
void main() {
#if defined(SI_TRADITIONAL)
  vec4 m0 = vec4(0.0), m1 = vec4(0.0), m2 = vec4(0.0);
#ifdef SI_EIGHT_INFLUENCES
  for (int k = 0; k < 8; ++k) {
    float w = k < 4 ? a_weights[k] : a_weights1[k - 4];
    if (w == 0.0) continue;
    uint j = (k < 4 ? a_joints[k] : a_joints1[k - 4]) * 3u;
#else
  for (int k = 0; k < 4; ++k) {
    float w = a_weights[k];
    if (w == 0.0) continue;
    uint j = a_joints[k] * 3u;
#endif
    m0 += w * si_joint_rows[j];
    m1 += w * si_joint_rows[j + 1u];
    m2 += w * si_joint_rows[j + 2u];
  }
  vec4 w0 = si_world_rows[0], w1 = si_world_rows[1], w2 = si_world_rows[2];
  uint color = si_color;
#else
#if defined(SI_GPU_DRIVEN)
  uint slot = si_entries[a_entry];  // The visible index.
  SiInstance inst = si_records[slot];
#else
  uint slot = uint(gl_InstanceID);
  SiInstance inst = si_instances[slot];
#endif
#if defined(SI_RIGID)
  vec4 m0 = vec4(1, 0, 0, 0), m1 = vec4(0, 1, 0, 0), m2 = vec4(0, 0, 1, 0);
#elif defined(SI_COMPOSED_LAYERS)
#ifdef SI_GPU_DRIVEN
  uint composed = slot;  // The visible index.
#else
  uint composed = siComposedRecord(u_batch_slot + slot);
#endif
  vec4 m0, m1, m2;
  siSkinComposed(inst, si_layers[slot], composed, false, a_joints, a_weights, m0, m1, m2);
  SI_SECOND_SET(siSkinComposed(inst, si_layers[slot], composed, false, a_joints1, a_weights1,
                               si_e0, si_e1, si_e2),
                m0, m1, m2)
#elif defined(SI_LAYERS)
  vec4 m0, m1, m2;
  siSkinLayered(inst, si_layers[slot], a_joints, a_weights, m0, m1, m2);
  SI_SECOND_SET(siSkinLayered(inst, si_layers[slot], a_joints1, a_weights1, si_e0, si_e1, si_e2),
                m0, m1, m2)
#else
  vec4 m0, m1, m2;
  siSkin(inst, a_joints, a_weights, m0, m1, m2);
  SI_SECOND_SET(siSkin(inst, a_joints1, a_weights1, si_e0, si_e1, si_e2), m0, m1, m2)
#endif
  vec4 w0 = inst.world_rows[0], w1 = inst.world_rows[1], w2 = inst.world_rows[2];
  uint color = inst.blend.w;
#endif
#if defined(SI_GPU_DRIVEN)
  uint lod = si_visible[slot].y;
#else
  uint lod = u_lod;
#endif
  // The bind pose, with the vertex's morph targets at the instance's weights (those the LOD
  // keeps).
  vec3 position = a_position, normal = a_normal.xyz, tangent_direction = a_tangent.xyz;
  SI_MORPH_VERTEX(inst, SI_MORPH_LAYER(slot), false, lod, position, normal, tangent_direction);
  vec3 model = siTransformPoint(m0, m1, m2, position);
#ifdef SI_CAPTURE
  tf_position = model;
#endif
  vec3 world = siTransformPoint(w0, w1, w2, model);
  v_position = world;
  v_lod = lod;
  v_normal = siTransformNormal(w0, w1, w2, siTransformNormal(m0, m1, m2, normal));
  vec3 tangent =
      siTransformVector(w0, w1, w2, siTransformVector(m0, m1, m2, tangent_direction));
  float tangent_length = length(tangent);
  v_tangent = vec4(tangent_length > 0.0 ? tangent / tangent_length : tangent, a_tangent.w);
  v_texcoord = a_texcoord;
  siPassVertexWords();
  v_color = color;
#if defined(SI_INSTANCE_HANDLE) && defined(SI_TRADITIONAL)
  v_instance_handle = u_instance_handle;
#elif defined(SI_INSTANCE_HANDLE) && defined(SI_GPU_DRIVEN)
  v_instance_handle = si_visible[slot].w;
#elif defined(SI_INSTANCE_HANDLE)
  v_instance_handle = siSlotHandle(slot);
#endif
  v_material = siVertexMaterial(uint(gl_VertexID));  // The mesh vertex: no base vertex.
  gl_Position = u_view_projection * vec4(world, 1.0);
#ifdef SI_MOTION_VECTORS
  v_motion_current = u_motion_view_projection * vec4(world, 1.0);
#ifdef SI_GPU_DRIVEN
  SiInstance prev = si_previous_instances[slot];
#else
  SiInstance prev = siPreviousRecord(u_batch_slot + slot, inst);
#endif
  vec4 p0, p1, p2;
#if defined(SI_COMPOSED_LAYERS)
  siSkinComposed(prev, si_previous_layers[slot], composed, true, a_joints, a_weights, p0, p1,
                 p2);
  SI_SECOND_SET(siSkinComposed(prev, si_previous_layers[slot], composed, true, a_joints1,
                               a_weights1, si_e0, si_e1, si_e2),
                p0, p1, p2)
#elif defined(SI_LAYERS)
  siSkinLayered(prev, si_previous_layers[slot], a_joints, a_weights, p0, p1, p2);
  SI_SECOND_SET(siSkinLayered(prev, si_previous_layers[slot], a_joints1, a_weights1, si_e0,
                              si_e1, si_e2),
                p0, p1, p2)
#else
  siSkin(prev, a_joints, a_weights, p0, p1, p2);
  SI_SECOND_SET(siSkin(prev, a_joints1, a_weights1, si_e0, si_e1, si_e2), p0, p1, p2)
#endif
  vec3 previous_position = a_position, previous_normal = a_normal.xyz,
       previous_tangent = a_tangent.xyz;
  SI_MORPH_VERTEX(prev, SI_MORPH_PREVIOUS_LAYER(slot), true, lod, previous_position,
                  previous_normal,
                  previous_tangent);
  vec3 previous = siPlacePoint(prev, p0, p1, p2, previous_position);
  v_motion_previous = u_previous_view_projection * vec4(previous, 1.0);
#endif
}
