// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once

/// \file
/// The library's GPU memory in one renderer, by what holds it (Renderer::gpuMemory): the bytes
/// of every buffer and texture the renderer created, as the driver reports their sizes. What
/// grows with the crowd is the GPU-driven path's state per crowd; everything else is per
/// character (its mesh, palette and atlas) or shared (rings whose sizes are options).
///
///   si::GpuMemory m;
///   renderer.gpuMemory(&m);          // context current
///   m.total();                       // bytes, all of it

#include <cstdint>
#include <vector>

namespace si {

/// One crowd's GPU-driven state (drawCrowdGpuCulled keeps one per crowd of a character).
struct CrowdGpuMemory {
  uint64_t crowd = 0;     ///< CrowdManager::identity().
  uint32_t capacity = 0;  ///< Instances its buffers hold.
  uint32_t views = 0;     ///< Views it keeps state for.
  /// The instance state, overlays, clips and the passes' outputs (records, visible list, bucket
  /// entries, commands, previous records, impostor quads: 64 bytes per instance of capacity
  /// for a crowd with an impostor level).
  uint64_t state_bytes = 0;
  /// Every view's LODs and flags, drawn records (motion vectors) and depth pyramid.
  uint64_t view_bytes = 0;
};

/// One character (Renderer::addCharacter).
struct CharacterGpuMemory {
  /// Its mesh and material textures, palette texture, pre-skinning lists and impostor atlas.
  uint64_t character_bytes = 0;
  std::vector<CrowdGpuMemory> crowds;  ///< The GPU-driven crowds it keeps state for.
};

struct GpuMemory {
  /// drawCrowd's instance-record ring (RendererDesc::ring_frames).
  uint64_t record_ring_bytes = 0;
  /// The pre-skinned vertex rings (RendererDesc::compute_ring_bytes, gpu_driven_ring_bytes, their
  /// previous-position and tangent twins) and the CPU-skinning stream.
  uint64_t vertex_ring_bytes = 0;
  /// The GPU-driven path's staging ring: bounded whatever the crowds (6 regions of at most
  /// twice a 4 MiB chunk).
  uint64_t staging_bytes = 0;
  /// Tables, composed layer rows, the traditional baseline's block.
  uint64_t other_shared_bytes = 0;
  std::vector<CharacterGpuMemory> characters;  ///< By CharacterId.

  /// Every byte above.
  uint64_t total() const {
    uint64_t t = record_ring_bytes + vertex_ring_bytes + staging_bytes + other_shared_bytes;
    for (const CharacterGpuMemory& c : characters) {
      t += c.character_bytes;
      for (const CrowdGpuMemory& k : c.crowds) t += k.state_bytes + k.view_bytes;
    }
    return t;
  }
};

}  // namespace si
