// SkinnedInstancing - SPDX-License-Identifier: MIT (see LICENSE)
// Pre-skinning, shared by the skinning passes and the vertex-pulling draws: the raw vertex
// buffer (32 or 36 bytes a vertex, read as words), the compacted vertex list of each (sub-mesh,
// LOD), the pre-skinned vertex (16 bytes: camera-relative world position, octahedral normal as
// 2 x snorm16) with, for meshes with tangents, its skinned tangent in the parallel tangent ring
// (4 bytes: siPackTangent), and skinning one source vertex for an instance (after
// si_skinning.glsl).
// u_chunk: x first ring vertex of the draw, y vertices of the LOD, z offset into the LOD vertex
// list, w first instance of the batch; u_layout: x instances, y words per source vertex (low
// byte; 8 or 9, one more each with a tangent, a second texture coordinate set and a colour,
// in that order at the end) | 0x100 with wide joints | 0x200 when the source has tangents and
// the skinning passes write the tangent ring (storage binding 28; the pulling draws read it
// when compiled with SI_TANGENTS) | 0x400 when the source has texture coordinates 1 | 0x800
// when it has colours | 0x1000 when it has a second set of influences (its joints and weights
// words right after the fixed ones; read with SI_EIGHT_INFLUENCES) | 0x2000 when it has morph
// targets (its morph word last; read with SI_MORPH_TARGETS); bits 16-18: the compute pass's
// LOD level (si_pre_skin_lod).
// The bindings can be moved (the GPU-driven passes use 2 and 3 for other buffers).
#ifndef SI_PRE_SKIN_COMMON_GLSL
#define SI_PRE_SKIN_COMMON_GLSL
#ifndef SI_SOURCE_BINDING
#define SI_SOURCE_BINDING 2
#endif
#ifndef SI_LOD_VERTICES_BINDING
#define SI_LOD_VERTICES_BINDING 3
#endif
layout(std430, binding = SI_SOURCE_BINDING) readonly buffer SiSourceVertices { uint si_source[]; };
layout(std430, binding = SI_LOD_VERTICES_BINDING) readonly buffer SiLodVertices {
  uint si_lod_vertices[];
};
layout(location = 5) uniform uvec4 u_chunk;
layout(location = 6) uniform uvec2 u_layout;

bool siHasTangents() { return (u_layout.y & 0x200u) != 0u; }

vec2 siOctEncode(vec3 n) {
  n /= abs(n.x) + abs(n.y) + abs(n.z);
  vec2 e = n.xy;
  if (n.z < 0.0) e = (1.0 - abs(n.yx)) * vec2(n.x >= 0.0 ? 1.0 : -1.0, n.y >= 0.0 ? 1.0 : -1.0);
  return e;
}
vec3 siOctDecode(vec2 e) {
  vec3 n = vec3(e, 1.0 - abs(e.x) - abs(e.y));
  if (n.z < 0.0) n.xy = (1.0 - abs(n.yx)) * vec2(n.x >= 0.0 ? 1.0 : -1.0, n.y >= 0.0 ? 1.0 : -1.0);
  return normalize(n);
}

// A unit tangent with its bitangent sign (w = +-1) in one word: the octahedral direction as
// 2 x snorm16 whose lowest bit carries the sign (set: w = -1); vec4(0) packs as "no tangent",
// a y of 0x8000, which packSnorm2x16 never writes (it clamps to -32767).
uint siPackTangent(vec4 t) {
  if (t.w == 0.0) return 0x80000000u;
  return (packSnorm2x16(siOctEncode(t.xyz)) & ~1u) | (t.w < 0.0 ? 1u : 0u);
}
vec4 siUnpackTangent(uint word) {
  if ((word >> 16) == 0x8000u) return vec4(0.0);
  return vec4(siOctDecode(unpackSnorm2x16(word & ~1u)), (word & 1u) != 0u ? -1.0 : 1.0);
}

// The words after a source vertex's colour: its morph word when the source has one (0x2000).
uint siMorphWords() { return (u_layout.y >> 13) & 1u; }
// The words after a source vertex's tangent: its texture coordinates 1, colour and morph word,
// each when the source has them (0x400, 0x800, 0x2000).
uint siTrailingWords() {
  return ((u_layout.y >> 10) & 1u) + ((u_layout.y >> 11) & 1u) + siMorphWords();
}

// The texture coordinates of local vertex k of the list starting at `list_offset`.
vec2 siSourceTexcoord(uint list_offset, uint k) {
  return unpackHalf2x16(si_source[si_lod_vertices[list_offset + k] * (u_layout.y & 0xFFu) + 4u]);
}
// Source vertex `source`'s texture coordinates 1 (vec2(0) when the source has none) and colour
// (vec4(1) when it has none): the draws' SiSurface.uv1 and .color.
vec2 siSourceTexcoord1(uint source) {
  if ((u_layout.y & 0x400u) == 0u) return vec2(0.0);
  uint words = u_layout.y & 0xFFu;
  return unpackHalf2x16(
      si_source[source * words + words - 1u - ((u_layout.y >> 11) & 1u) - siMorphWords()]);
}
vec4 siSourceColor(uint source) {
  if ((u_layout.y & 0x800u) == 0u) return vec4(1.0);
  uint words = u_layout.y & 0xFFu;
  return unpackUnorm4x8(si_source[source * words + words - 1u - siMorphWords()]);
}
// Source vertex `source`'s morph word (0, no targets, when the source has none).
uint siSourceMorphWord(uint source) {
  if (siMorphWords() == 0u) return 0u;
  uint words = u_layout.y & 0xFFu;
  return si_source[source * words + words - 1u];
}

// A GL_INT_2_10_10_10_REV word, normalized: what the vertex-shader path's attribute fetch
// computes.
vec4 siUnpackSigned1010102(uint word) {
  int bits = int(word);
  return max(vec4(bitfieldExtract(bits, 0, 10), bitfieldExtract(bits, 10, 10),
                  bitfieldExtract(bits, 20, 10), bitfieldExtract(bits, 30, 2) * 511) / 511.0,
             vec4(-1.0));
}

#ifdef SI_SKINNING_GLSL
// The 4 influences whose words start at source word `at`: palette slots (one word of 4 x uint8,
// or two of 2 x uint16 with wide joints), then the weights (two words of 2 x unorm16).
void siSourceInfluences(uint at, out uvec4 joints, out vec4 weights) {
  if ((u_layout.y & 0x100u) == 0u) {
    joints = uvec4(unpackUnorm4x8(si_source[at]) * 255.0 + 0.5);
  } else {
    uint j01 = si_source[at], j23 = si_source[at + 1u];
    joints = uvec4(j01 & 0xFFFFu, j01 >> 16, j23 & 0xFFFFu, j23 >> 16);
    ++at;
  }
  weights = vec4(unpackUnorm2x16(si_source[at + 1u]), unpackUnorm2x16(si_source[at + 2u]));
}

// Source vertex `source`: bind-pose position and normal, palette slots and weights.
void siSourceVertex(uint source, out vec3 p, out vec3 n, out uvec4 joints, out vec4 weights) {
  uint base = source * (u_layout.y & 0xFFu);
  p = vec3(uintBitsToFloat(si_source[base]), uintBitsToFloat(si_source[base + 1u]),
           uintBitsToFloat(si_source[base + 2u]));
  n = siUnpackSigned1010102(si_source[base + 3u]).xyz;
  siSourceInfluences(base + 5u, joints, weights);
}

#ifdef SI_EIGHT_INFLUENCES
// Source vertex `source`'s influences 5 to 8: right after the fixed words (8, or 9 with wide
// joints).
void siSourceSecondSet(uint source, out uvec4 joints, out vec4 weights) {
  uint words = (u_layout.y & 0x100u) == 0u ? 8u : 9u;
  siSourceInfluences(source * (u_layout.y & 0xFFu) + words, joints, weights);
}
#endif

// The bind-pose tangent of source vertex `source` (the word before the trailing ones;
// siHasTangents()).
vec4 siSourceTangent(uint source) {
  uint words = u_layout.y & 0xFFu;
  return siUnpackSigned1010102(si_source[source * words + words - 1u - siTrailingWords()]);
}

// Layer record `i` of the frame (siPreviousLayer: of the previous frame); none without SI_LAYERS.
#ifdef SI_LAYERS
uvec4 siLayer(uint i) { return si_layers[i]; }
#ifdef SI_PREVIOUS_RECORDS
uvec4 siPreviousLayer(uint i) { return si_previous_layers[i]; }
#endif
#else
uvec4 siLayer(uint i) { return uvec4(0u); }
uvec4 siPreviousLayer(uint i) { return uvec4(0u); }
#endif

// The LOD level of the vertices being pre-skinned (its morph cut, si_morph.glsl): each pass's
// main sets it.
uint si_pre_skin_lod = 0u;

// The blended joint matrix rows of `inst` for `joints` and `weights`: with SI_LAYERS its overlay
// `layer` composed on its mask; with SI_COMPOSED_LAYERS read from composed record `record`'s
// rows (its previous rows with `previous`).
void siPreSkinMatrix(SiInstance inst, uvec4 layer, uint record, bool previous, uvec4 joints,
                     vec4 weights, out vec4 m0, out vec4 m1, out vec4 m2) {
#if defined(SI_COMPOSED_LAYERS)
  siSkinComposed(inst, layer, record, previous, joints, weights, m0, m1, m2);
#elif defined(SI_LAYERS)
  siSkinLayered(inst, layer, joints, weights, m0, m1, m2);
#else
  siSkin(inst, joints, weights, m0, m1, m2);
#endif
}

// Source vertex `source`'s bind-pose position `p`, normal `n` and tangent `t` (vec4(0) without
// siHasTangents()), with SI_MORPH_TARGETS its morph targets added at `inst`'s weights (and its
// overlay `layer`'s on the mask's targets: uvec4(0) without SI_LAYERS), and its
// blended joint matrix rows for `inst` (siPreSkinMatrix).
void siPreSkinSource(uint source, SiInstance inst, uvec4 layer, uint record, bool previous,
                     out vec3 p, out vec3 n, out vec4 t, out vec4 m0, out vec4 m1,
                     out vec4 m2) {
  uvec4 joints;
  vec4 weights;
  siSourceVertex(source, p, n, joints, weights);
  t = siHasTangents() ? siSourceTangent(source) : vec4(0.0);
#ifdef SI_MORPH_TARGETS
  vec3 direction = t.xyz;
#ifdef SI_COMPOSED_LAYERS
  siMorphComposed(inst, layer, record, previous, siSourceMorphWord(source), si_pre_skin_lod, p, n,
                  direction);
#else
  siMorphLayered(inst, layer, siSourceMorphWord(source), si_pre_skin_lod, p, n, direction);
#endif
  t.xyz = direction;
#endif
  siPreSkinMatrix(inst, layer, record, previous, joints, weights, m0, m1, m2);
#ifdef SI_EIGHT_INFLUENCES
  // The skinning sum is linear in the weights: the second set's is added.
  vec4 e0, e1, e2;
  siSourceSecondSet(source, joints, weights);
  siPreSkinMatrix(inst, layer, record, previous, joints, weights, e0, e1, e2);
  m0 += e0;
  m1 += e1;
  m2 += e2;
#endif
}

// Source vertex `source` skinned for `inst` (with SI_LAYERS, its overlay `layer` composed on its
// mask; with SI_COMPOSED_LAYERS read from composed record `record`'s rows): camera-relative
// world position, and the normal octahedral-encoded in the w component's bits; `tangent` the
// packed skinned tangent (as skinned.vert skins it: the blended matrix, then the world rows),
// or the packed "no tangent" without siHasTangents().
vec4 siPreSkin(uint source, SiInstance inst, uvec4 layer, uint record, out uint tangent) {
  vec3 p, n;
  vec4 t, m0, m1, m2;
  siPreSkinSource(source, inst, layer, record, false, p, n, t, m0, m1, m2);
  vec4 w0 = inst.world_rows[0], w1 = inst.world_rows[1], w2 = inst.world_rows[2];
  vec3 world = siTransformPoint(w0, w1, w2, siTransformPoint(m0, m1, m2, p));
  vec3 normal = siTransformNormal(w0, w1, w2, siTransformNormal(m0, m1, m2, n));
  tangent = siPackTangent(vec4(0.0));
  if (siHasTangents()) {  // Uniform: a character without tangents does none of this work.
    vec3 skinned_t = siTransformVector(w0, w1, w2, siTransformVector(m0, m1, m2, t.xyz));
    float t_length = length(skinned_t);
    if (t_length > 0.0) tangent = siPackTangent(vec4(skinned_t / t_length, t.w));
  }
  return vec4(world, uintBitsToFloat(packSnorm2x16(siOctEncode(normal))));
}

#ifdef SI_PREVIOUS_RECORDS
// Source vertex `source` where the previous frame drew it with record `prev` (and, with
// SI_LAYERS, layer record `prev_layer`; SI_COMPOSED_LAYERS: composed record `record`'s previous
// rows), as siSkinPrevious: world position relative to the previous camera.
vec3 siPreSkinPrevious(uint source, SiInstance prev, uvec4 prev_layer, uint record) {
  vec3 p, n;
  vec4 t, m0, m1, m2;
  siPreSkinSource(source, prev, prev_layer, record, true, p, n, t, m0, m1, m2);
  return siPlacePoint(prev, m0, m1, m2, p);
}
#endif

#ifdef SI_SKINNED_OUT_BINDING
// The pre-skinning passes' outputs: vertices (SI_SKINNED_OUT_BINDING), tangents (28) and with
// SI_MOTION_VECTORS the previous positions (SI_SKINNED_PREVIOUS_OUT_BINDING).
layout(std430, binding = SI_SKINNED_OUT_BINDING) writeonly buffer SiSkinnedOut {
  vec4 si_skinned_out[];
};
layout(std430, binding = 28) writeonly buffer SiTangentsOut { uint si_tangents_out[]; };
#ifdef SI_MOTION_VECTORS
layout(std430, binding = SI_SKINNED_PREVIOUS_OUT_BINDING) writeonly buffer SiSkinnedPreviousOut {
  vec4 si_previous_out[];
};
#endif
// Writes source vertex `source` skinned (siPreSkin) as output vertex `at`, its tangent beside.
void siWritePreSkinned(uint at, uint source, SiInstance inst, uvec4 layer, uint record) {
  uint tangent;
  si_skinned_out[at] = siPreSkin(source, inst, layer, record, tangent);
  if (siHasTangents()) si_tangents_out[at] = tangent;
}
#endif
#endif
#endif
