// SkinnedInstancing - SPDX-License-Identifier: MIT (see LICENSE)
// What differs between the three GLSLs the shaders compile as: GLSL 4.50 (OpenGL 4.5), GLSL ES
// 3.00 (OpenGL ES 3.0 and WebGL 2: no binding qualifiers and no uniform locations; the
// application sets the bindings after linking, with glUniformBlockBinding and, for samplers,
// glUniform1i) and Vulkan GLSL (glslang defines VULKAN; every resource in descriptor set
// SI_DESCRIPTOR_SET [0]).
//   SI_WITH_BINDING(b)     ", binding = b" after another layout qualifier: layout(std140 SI_WITH_BINDING(4))
//   SI_BINDING_LAYOUT(b)   "layout(binding = b)" alone (samplers)
//   SI_LOCATION_LAYOUT(l)  "layout(location = l)" of a default-block uniform
//   SI_VARYING_LAYOUT(l)   "layout(location = l)" of a vertex output or fragment input, under
//                          Vulkan only (where the stages meet by location, not by name): the
//                          mesh surface's interface numbers its varyings once (v_position 0
//                          ... v_instance_handle 11) in every stage that declares them
// The first three expand to nothing under GLSL ES 3.00. siUnpackUnorm4x8 is unpackUnorm4x8, which GLSL ES
// gained only in 3.10. Under GLSL ES, declare the default precisions (highp float and int,
// sampler2D, sampler2DArray) before including.
#ifndef SI_PROFILE_GLSL
#define SI_PROFILE_GLSL
#if defined(VULKAN)
#ifndef SI_DESCRIPTOR_SET
#define SI_DESCRIPTOR_SET 0
#endif
#define SI_WITH_BINDING(b) , set = SI_DESCRIPTOR_SET, binding = b
#define SI_BINDING_LAYOUT(b) layout(set = SI_DESCRIPTOR_SET, binding = b)
#define SI_LOCATION_LAYOUT(l) layout(location = l)
#define SI_VARYING_LAYOUT(l) layout(location = l)
#elif defined(GL_ES) && __VERSION__ < 310
#define SI_WITH_BINDING(b)
#define SI_BINDING_LAYOUT(b)
#define SI_LOCATION_LAYOUT(l)
#define SI_VARYING_LAYOUT(l)
#else
#define SI_WITH_BINDING(b) , binding = b
#define SI_BINDING_LAYOUT(b) layout(binding = b)
#define SI_LOCATION_LAYOUT(l) layout(location = l)
#define SI_VARYING_LAYOUT(l)
#endif
#if defined(GL_ES) && __VERSION__ < 310
vec4 siUnpackUnorm4x8(uint v) {
  return vec4(uvec4(v, v >> 8u, v >> 16u, v >> 24u) & uvec4(0xFFu)) / 255.0;
}
#else
vec4 siUnpackUnorm4x8(uint v) { return unpackUnorm4x8(v); }
#endif
#endif
