// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// A host material's resources against the library's (Renderer::addMaterial): a draw call binds
// the library's textures and buffers at the units and bindings its programs (draws and compute
// passes) declare, and sets only its own default-block uniforms, so a material's sampler,
// uniform block or storage block on one of those would read the library's resource, and a loose
// uniform of its own could never be set (the programs are the library's).

#include <glad/gl.h>

#include <map>
#include <set>
#include <string>

#include "si/core/status.h"

namespace si::detail {

/// The texture units, image units, uniform buffer bindings and shader storage bindings the
/// library's programs declare, each with the names of the resources found there, and the names
/// of their default-block uniforms (with u_lod, which the surface declares and the built-in
/// material leaves inactive).
struct LibraryBindings {
  std::map<GLint, std::set<std::string>> units, images, uniform_blocks, storage_blocks;
  std::set<std::string> uniform_names = {"u_lod"};
  /// Adds the resources of linked `program`. Desktop GL (program interface queries, GL 4.3).
  void add(GLuint program);
};

/// Compares linked program `material` (a program built with a host material) with `library`
/// (every built-in program's resources). kInvalidArgument naming the resource when the material
/// adds a default-block uniform that is neither a sampler nor an image, or a sampler, image,
/// uniform block or shader storage block at a unit or binding in `library`; ok otherwise.
/// Desktop GL (program interface queries, GL 4.3).
Status checkMaterialResources(const LibraryBindings& library, GLuint material);

}  // namespace si::detail
