// SkinnedInstancing - SPDX-License-Identifier: MIT (see LICENSE)
// The material interface (docs/glsl-interface.md, "Materials"): what the fragment stage of
// every draw path hands a material (si::MaterialDesc), and the library's functions a material
// may call. The renderer compiles a material's source after this file and after its own
// fragment inputs; the material defines
//   void siMaterial(SiSurface surface);
// which writes the material's own outputs (declared by the material: one colour target, or a
// G-buffer of several) and may discard. Defines a material may test: SI_MOTION_VECTORS (the
// draw writes motion vectors: the clip positions below are set), SI_DEPTH_ONLY (a depth-only
// pass of a material with MaterialDesc::depth_discard: only the discard matters),
// SI_IMPOSTOR (an impostor quad's fragment: the surface comes from the impostor atlas),
// SI_INSTANCE_HANDLE (the material asked for the instance's handle: MaterialDesc::instance_handle).
// Interface version 5 (4 had no instance handle; 3 had no uv1 and no vertex colour; 2 gave impostors metallic 0,
// roughness 1, occlusion 1 and no material index; 1 had no tangent frame and no
// metallic-roughness fields).
#ifndef SI_SURFACE_GLSL
#define SI_SURFACE_GLSL
#define SI_MATERIAL_INTERFACE_VERSION 5
// SiSurface.material where there is none (kept for materials that test it; no draw sets it).
#define SI_NO_MATERIAL 0xFFFFFFFFu
struct SiSurface {
  // The fragment's world position relative to the camera (world axes, the camera at the
  // origin: the records' camera-relative space), model units.
  vec3 position;
  // The shading normal in world axes, unit length: the skinned vertex normal, through the
  // material's normal map where it has one (tangent frame below), turned towards the viewer on
  // a double-sided material's back faces.
  vec3 normal;
  // The skinned vertex normal as interpolated, unit length (flipped as `normal` is).
  vec3 vertex_normal;
  // The skinned tangent in world axes (xyz unit, orthogonal to vertex_normal; w the
  // bitangent's sign: bitangent = w * cross(vertex_normal, tangent.xyz)); vec4(0) where the
  // mesh has no tangents and on impostors.
  vec4 tangent;
  // Texture coordinate 0 of the mesh (an impostor: the atlas cell's coordinate).
  vec2 uv0;
  // Texture coordinate 1 of the mesh (si::SkinnedMesh::texcoords1, glTF TEXCOORD_1); vec2(0)
  // where the mesh has none, on impostors and in depth-only passes (SI_DEPTH_ONLY).
  vec2 uv1;
  // The vertex colour (si::SkinnedMesh::colors, glTF COLOR_0), linear RGBA, 8 bits a channel
  // as interpolated; vec4(1) where the mesh has none, on impostors (whose captured base_color
  // has it already) and in depth-only passes. base_color is multiplied by it.
  vec4 color;
  // The vertex's entry of the character's material table (si::MaterialTable). An impostor: the
  // largest entry the capture drew among the 2 x 2 nearest texels of the atlas's full
  // resolution (entries past 254 read as 254; never blended between entries).
  uint material;
  // The material table entry's base colour, linear: its sRGB texture sampled at uv0 times its
  // factor times the vertex colour (an impostor: the texel the atlas captured). Alpha is the
  // tint mask the built-in
  // albedo reads; for an alpha-masked material (si::AlphaMode::kMask) the fragments below its
  // cutoff are discarded before the material runs and alpha is 1 (tint everywhere).
  vec4 base_color;
  // The material's metallic and roughness (factors times the metallic-roughness texture's
  // blue and green), ambient occlusion (1 + strength * (red - 1)) and emissive colour (factor
  // times the sRGB emissive texture, linear). An impostor: the captured metallic, roughness and
  // occlusion (filtered as the base colour is), and no emissive (vec3(0)).
  float metallic;
  float roughness;
  float occlusion;
  vec3 emissive;
  // The instance's tint (InstanceDesc::color's RGB, in [0, 1]).
  vec3 tint;
  // The instance's layer of the application's custom texture array (InstanceDesc::custom_layer
  // - 1); -1 when it selects none or no array is set (always -1 on an impostor).
  int custom_layer;
  // The drawn instance's si::InstanceHandle::id, on every path and on impostors, for a
  // material with MaterialDesc::instance_handle (SI_INSTANCE_HANDLE); 0 (the null handle)
  // for the others.
  uint instance;
  // The LOD level drawn (an impostor: the crowd's impostor level).
  uint lod;
  // Whether the fragment is an impostor quad's.
  bool impostor;
  // SI_MOTION_VECTORS: the fragment's clip positions under the motion camera this frame and
  // under the previous frame's (RendererDesc::motion_vectors); vec4(0) otherwise.
  vec4 clip_position;
  vec4 previous_clip_position;
};
// The library's functions (defined by every fragment stage that calls siMaterial):
// The built-in albedo: the base colour with the instance's custom layer over it by the custom
// texel's alpha, multiplied by the tint where base_color.a (the tint mask) says so.
vec3 siSurfaceAlbedo(SiSurface surface);
// The fragment's screen motion since the previous frame, in texture coordinate units (the
// built-in material's output 1); vec2(0) without SI_MOTION_VECTORS or behind either camera.
vec2 siSurfaceMotion(SiSurface surface);
// The renderer's directional light (Renderer::setLightDirection): the world direction the
// light travels along, as set.
vec3 siLightDirection();
#endif
