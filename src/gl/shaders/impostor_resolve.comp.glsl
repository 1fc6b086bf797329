// SkinnedInstancing - SPDX-License-Identifier: MIT (see LICENSE)
// The impostor atlas's level 0 from its supersampled capture (resources/impostor_resolve.h):
// each atlas texel the mean of the u_factor x u_factor capture texels it covers, layer by layer.
// The capture draws each texel whole or not at all (all zero), so the mean is the layers' values
// multiplied by the coverage, as impostor.frag.glsl reads them and mip levels average them. With
// u_codes, layer 2 (metallic, roughness, occlusion and the material's code) is instead one
// material's: the largest code among the texels (codes are not averaged, and impostor.frag.glsl
// gathers level 0's as they are) and the mean of that material's texels' values, times the
// coverage, so that a fragment shaded as one material gets that material's values, not a blend
// with its neighbour's.
layout(local_size_x = 8, local_size_y = 8, local_size_z = 1) in;
layout(binding = 0) uniform sampler2DArray u_capture;  // read by texelFetch
layout(binding = 0, rgba8) writeonly uniform image2DArray u_atlas;
layout(location = 0) uniform ivec3 u_size;  // level 0's width and height; the first layer
layout(location = 1) uniform int u_factor;  // capture texels each way per atlas texel
layout(location = 2) uniform int u_codes;   // 1: layer 2's alpha the largest code
void main() {
  ivec3 p = ivec3(gl_GlobalInvocationID.xy, int(gl_GlobalInvocationID.z) + u_size.z);
  if (p.x >= u_size.x || p.y >= u_size.y) return;
  vec4 sum = vec4(0.0);
  float code = 0.0;
  for (int y = 0; y < u_factor; ++y)
    for (int x = 0; x < u_factor; ++x) {
      vec4 t = texelFetch(u_capture, ivec3(p.xy * u_factor + ivec2(x, y), p.z), 0);
      sum += t;
      code = max(code, t.a);
    }
  float texels = float(u_factor * u_factor);
  vec4 texel = sum / texels;
  if (u_codes != 0 && code > 0.0) {
    vec3 values = vec3(0.0);
    float of_code = 0.0, drawn = 0.0;  // texels of that material, and drawn at all
    for (int y = 0; y < u_factor; ++y)
      for (int x = 0; x < u_factor; ++x) {
        vec4 t = texelFetch(u_capture, ivec3(p.xy * u_factor + ivec2(x, y), p.z), 0);
        if (t.a == code) {
          values += t.rgb;
          of_code += 1.0;
        }
        drawn += t.a > 0.0 ? 1.0 : 0.0;
      }
    texel = vec4(values / of_code * (drawn / texels), code);
  }
  imageStore(u_atlas, p, texel);
}
