// SkinnedInstancing - SPDX-License-Identifier: MIT (see LICENSE)
// Transforms by 3x4 row matrices (three vec4 rows), as the instance record and the palette
// store them.
#ifndef SI_TRANSFORM_GLSL
#define SI_TRANSFORM_GLSL
vec3 siTransformPoint(vec4 r0, vec4 r1, vec4 r2, vec3 p) {
  vec4 h = vec4(p, 1.0);
  return vec3(dot(r0, h), dot(r1, h), dot(r2, h));
}

// Normals (and tangents with siTransformVector) through sign(det) * cofactor: correct under
// non-uniform scale and mirroring.
vec3 siTransformNormal(vec4 r0, vec4 r1, vec4 r2, vec3 n) {
  vec3 c0 = vec3(r0.x, r1.x, r2.x), c1 = vec3(r0.y, r1.y, r2.y), c2 = vec3(r0.z, r1.z, r2.z);
  mat3 cof = mat3(cross(c1, c2), cross(c2, c0), cross(c0, c1));
  if (dot(c0, cof[0]) < 0.0) cof = -cof;
  vec3 t = cof * n;
  float len = length(t);
  return len > 1e-30 ? t / len : n;
}
vec3 siTransformVector(vec4 r0, vec4 r1, vec4 r2, vec3 v) {
  return vec3(dot(r0.xyz, v), dot(r1.xyz, v), dot(r2.xyz, v));
}
#endif
