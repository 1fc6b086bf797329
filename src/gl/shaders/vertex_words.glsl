// SkinnedInstancing - SPDX-License-Identifier: MIT (see LICENSE)
// The optional vertex words of the vertex stages that read the vertex stream as attributes
// (skinned.vert.glsl, preskinned.vert.glsl): with SI_VERTEX_WORDS (the variant for meshes that
// have texture coordinates 1 or colours) both as attributes 8 and 9, passed on to the surface.
// Where the mesh has only one of them the other attribute reads another word of the vertex,
// which the fragment stage ignores (SiMaterial.layer.w). Without the define, nothing.
#ifndef SI_VERTEX_WORDS_GLSL
#define SI_VERTEX_WORDS_GLSL
#ifdef SI_VERTEX_WORDS
layout(location = 8) in vec2 a_texcoord1;
layout(location = 9) in vec4 a_vertex_color;
SI_VARYING_LAYOUT(9) out vec2 v_texcoord1;
SI_VARYING_LAYOUT(10) out vec4 v_vertex_color;
void siPassVertexWords() {
  v_texcoord1 = a_texcoord1;
  v_vertex_color = a_vertex_color;
}
#else
void siPassVertexWords() {}
#endif
#endif
