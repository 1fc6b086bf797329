// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// The large per-frame scratch buffers of the draw paths, one of each per renderer whatever the
// number of characters: every character's draws reuse them in turn.

#include <glad/gl.h>

#include <cstdint>
#include <vector>

#include "gl/programs/program_set.h"
#include "gl/resources/gl_allocation.h"
#include "gl/resources/layer_compose_buffers.h"
#include "gl/resources/upload_ring.h"
#include "si/core/status.h"

namespace si::detail {

/// A buffer of pre-skinned vertices (16 bytes each; 4 for a tangent ring) that the compute
/// passes write and the pulling draws read.
struct VertexRing {
  explicit VertexRing(uint32_t bytes_per_vertex = 16) : vertex_bytes(bytes_per_vertex) {}

  uint32_t vertex_bytes;
  GLuint buffer = kNoObject;
  uint64_t vertices = 0;  ///< Capacity; 0 until created.

  /// (Re)creates the ring with `vertices` unless it already has exactly that many (`exact`) or
  /// at least that many (otherwise). `what` names it in errors.
  Status ensure(uint64_t vertices, bool exact, const char* what);
  void release();
};

struct ScratchBuffers {
  VertexRing compute_ring;     ///< The compute path's (RendererDesc::compute_ring_bytes).
  /// Its twin for previous positions (RendererDesc::motion_vectors): the same vertex slots.
  VertexRing compute_previous_ring;
  VertexRing gpu_driven_ring;  ///< The GPU-driven path's (RendererDesc::gpu_driven_ring_bytes).
  /// Its twin for previous positions (motion vectors): the same vertex slots.
  VertexRing gpu_driven_previous_ring;
  /// The skinned tangents of characters with tangents (pre_skin_common.glsl's siPackTangent),
  /// beside compute_ring and gpu_driven_ring at the same vertex slots; created on the first
  /// such character's draw.
  VertexRing compute_tangent_ring{4};
  VertexRing gpu_driven_tangent_ring{4};
  GLuint cpu_stream = kNoObject;  ///< The CPU-skinning path's vertex stream (orphaned per chunk).
  size_t cpu_stream_bytes = 0;    ///< Its size: grown to the largest character's chunk.
  /// Layered animation: the drawn crowd's mask table (si::layerMaskTable).
  TableBuffer mask_table;
  /// Composed layers (drawCrowd's vertex-shader path): the compose table and rows.
  LayerComposeBuffers layer_compose;
  /// The GPU-driven path's staged uploads (crowd state, overlays, view seeds), every crowd's
  /// and character's: bounded whatever their sizes (upload_ring.h).
  UploadRing uploads;

  /// Makes mask_table hold `table` (TableBuffer::upload) and binds it at storage binding 8
  /// (si_skinning.glsl's SI_MASK_BINDING).
  Status uploadMaskTable(const std::vector<int32_t>& table);

  void release();
};

}  // namespace si::detail
