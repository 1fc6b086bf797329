// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// One character uploaded into a renderer (Renderer::addCharacter): its palette texture, its mesh
// and materials, its pre-skinning lists, the draw paths' per-character state (vertex arrays,
// the GPU-driven path's state per crowd) and its skinning path. The programs, the record ring and
// the scratch buffers are the renderer's, shared by every character.

#include <string>

#include "gl/paths/compute_path.h"
#include "gl/paths/cpu_skinning_path.h"
#include "gl/paths/gpu_culled_crowds.h"
#include "gl/resources/character_buffers.h"
#include "gl/resources/impostor_atlas.h"
#include "gl/resources/palette_texture.h"
#include "gl/resources/preskin_lists.h"
#include "si/gl/renderer.h"

namespace si::detail {

struct CharacterSlot {
  PaletteTexture palette;
  CharacterBuffers character;
  PreSkinLists preskin;
  ImpostorAtlas impostor;  ///< Renderer::buildImpostor's atlas (not ready when none).
  ComputePath compute_path;
  CpuSkinningPath cpu_path;
  GpuCulledCrowds gpu_culled;                       ///< The GPU-driven path's state, per crowd.
  SkinningPath path = SkinningPath::kVertexShader;  ///< DrawMode::kDefault's path.
  uint32_t material = 0;  ///< Renderer::setMaterial (0: the built-in material).
  std::string path_reason = "explicit setting";

  bool ready() const { return character.ready() && palette.ready(); }
  /// Deletes every GL object of the character (context current). Idempotent.
  void release() {
    compute_path.release();
    cpu_path.release();
    gpu_culled.release();
    preskin.release();
    impostor.release();
    character.release();
    palette.release();
  }
};

}  // namespace si::detail
