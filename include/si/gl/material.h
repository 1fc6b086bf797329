// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once

/// \file
/// Materials: the engine's own fragment stage on every draw path. A material is GLSL that the
/// renderer compiles into the fragment stage of each path (vertex-shader skinning, compute
/// pre-skinning, GPU-driven with and without occlusion culling, impostors, the traditional and
/// CPU-skinning baselines). The library builds the fragment's surface (si_surface.glsl: position,
/// skinned normal, texture coordinates, the material table's base colour, tint, custom layer,
/// LOD, impostor, motion clip positions, the instance's handle on request) and calls the material's
/// `siMaterial`, which writes the material's own outputs: one colour target, or a G-buffer of
/// several. The built-in look (si::kBuiltinMaterial, shaders/builtin_material.glsl) is such a
/// material.
///
/// Usage (docs/rendering.md, "Materials"):
/// \code
///   si::MaterialDesc desc;
///   desc.name = "gbuffer";
///   desc.source = R"(
///     layout(location = 0) out vec4 o_albedo;
///     layout(location = 1) out vec4 o_normal;
///     layout(std140, binding = 7) uniform Tone { vec4 tone; };  // the host binds binding 7
///     void siMaterial(SiSurface s) {
///       o_albedo = vec4(siSurfaceAlbedo(s) * tone.rgb, 1.0);
///       o_normal = vec4(s.normal * 0.5 + 0.5, 1.0);
///     })";
///   si::MaterialId gbuffer;
///   renderer.addMaterial(desc, &gbuffer);       // compiles its programs now
///   renderer.setMaterial(soldiers, gbuffer);    // the character's draws use it from now on
/// \endcode

#include <cstdint>
#include <string>

#include "si/core/status.h"

namespace si {

/// A material added to a Renderer (Renderer::addMaterial gives it); 0 is the built-in one.
struct MaterialId {
  uint32_t index = 0;
  bool operator==(const MaterialId& o) const { return index == o.index; }
  bool operator!=(const MaterialId& o) const { return index != o.index; }
};

/// The built-in material: the base colour (with the custom layer and the tint under the tint
/// mask, siSurfaceAlbedo) lit by Renderer::setLightDirection's light, Lambert over a constant
/// ambient of 0.35, at fragment output 0; with motion vectors the screen motion at output 1.
inline constexpr MaterialId kBuiltinMaterial{0};

/// A host material.
struct MaterialDesc {
  /// Names the material in errors and logs. Must not be empty.
  std::string name;
  /// GLSL 4.50 that the renderer appends to each fragment stage, after the surface's
  /// declarations (si_surface.glsl): the material's outputs (`layout(location = k) out ...`),
  /// its uniform blocks, storage blocks and samplers at bindings of its own choosing (bound by
  /// the host before it draws), helper functions, and
  ///   void siMaterial(SiSurface surface);
  /// which writes the outputs and may `discard`. No `#version` line (the renderer writes it).
  /// The defines SI_MOTION_VECTORS, SI_DEPTH_ONLY and SI_IMPOSTOR tell which pass compiles it,
  /// SI_INSTANCE_HANDLE that `instance_handle` is set.
  /// Not allowed, and refused by addMaterial: a loose (default-block) uniform that is not a
  /// sampler (nothing could set it: the programs are the library's), and a sampler, uniform
  /// block or storage block at a texture unit or binding the library's draw of that path binds
  /// for its own resources (docs/rendering.md, "Materials", lists them).
  std::string source;
  /// Depth-only draws (DrawMode::kDepthOnly, shadow views) also run the material, compiled
  /// with SI_DEPTH_ONLY, so its discards (an alpha test) cut the depth too; its outputs are
  /// then masked. False (the default): depth-only draws write every covered fragment's depth
  /// without running it.
  bool depth_discard = false;
  /// The material reads SiSurface.instance, the drawn instance's InstanceHandle::id (to pick
  /// out, highlight or key the engine's own per-instance data). Its programs then pass the
  /// handle from the vertex stage (one flat word), and drawCrowd writes 4 bytes a drawn
  /// instance into its ring region for it; a material that leaves this false pays nothing and
  /// reads 0 (the null handle).
  bool instance_handle = false;

  /// ok, or kInvalidArgument naming the rule broken: a non-empty name; a non-empty source with
  /// no `#version` line.
  Status validate() const;
};

}  // namespace si
