// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once

/// \file
/// What a Renderer draw takes besides the view and the camera, and what it reports: the
/// character drawn (CharacterId, from Renderer::addCharacter), the program (DrawMode) and what
/// the draw did (DrawStats: draws, triangles, instances, CPU and GPU time, per-path counters).
/// Plain data; renderer.h includes it.
///
/// \code
///   si::DrawStats stats;
///   renderer.drawCrowd(soldiers, crowd.view(), batcher, camera, &stats, si::DrawMode::kDepthOnly);
///   printf("%u draws, %llu triangles, %.2f ms GPU\n", stats.draw_calls,
///          (unsigned long long)stats.triangles, stats.gpu_ms);
/// \endcode

#include <cstdint>

namespace si {

/// A character uploaded into a Renderer: its index in upload order (addCharacter gives it; the
/// first added is CharacterId{}, index 0).
struct CharacterId {
  uint32_t index = 0;
  bool operator==(const CharacterId& o) const { return index == o.index; }
  bool operator!=(const CharacterId& o) const { return index != o.index; }
};

/// What one draw call group did.
struct DrawStats {
  uint32_t draw_calls = 0;
  uint64_t triangles = 0;
  uint64_t instances = 0;           ///< Instance-draws (an instance counts once per sub-mesh).
  double cpu_submit_ms = 0.0;       ///< CPU time spent in the draw function (records and GL calls).
  double gpu_ms = -1.0;             ///< GPU time, when RendererDesc::measure_gpu_time, else -1.
  /// With RendererDesc::measure_gpu_passes: what Renderer::readGpuPasses reads this draw's GPU
  /// time per pass with, a frame or more later (si/gl/gpu_passes.h); 0 without.
  uint64_t gpu_pass_ticket = 0;
  uint32_t compute_dispatches = 0;  ///< Compute path: skinning dispatches,
  uint32_t compute_chunks = 0;      ///< times the vertex ring was filled and drawn,
  uint64_t skinned_vertices = 0;    ///< vertices pre-skinned,
  uint64_t ring_bytes_used = 0;     ///< and the most ring bytes one chunk used.
  uint32_t gpu_visible = 0;         ///< drawCrowdGpuCulled: instances selected (read back),
  /// and impostors selected but not drawn: their quads hold no pixel centre of the
  /// single-sampled target, so they would raster nothing (not in `triangles` or `instances`),
  uint64_t impostors_left_out = 0;
  uint64_t vertex_shader_instances = 0;  ///< and instance-draws skinned in the vertex shader
                                         ///< (all without pre-skinning; past the ring with),
  /// drawCrowdGpuCulled: bytes of the crowd's instance state and overlays this draw uploaded
  /// (RendererDesc::gpu_state_upload; 0 when nothing changed or another view's draw of the
  /// same frame uploaded it).
  uint64_t state_bytes_uploaded = 0;
  /// drawCrowdGpuCulled: bytes this draw staged to start its view's LODs over where other
  /// instances sit since the last upload (churn). 0 for views that never selected on the CPU:
  /// the culling pass starts those places over at LOD 0 by itself.
  uint64_t view_seed_bytes = 0;
  /// Draws of overlays (RendererDesc::compose_layers): the compose pass's
  /// dispatches (0 when the draws walked the chains), and the instances drawCrowd's composed
  /// (each once, whatever sub-meshes it wears; the GPU-driven pass's count stays on the GPU).
  uint32_t compose_dispatches = 0;
  uint64_t composed_records = 0;
  /// drawCrowd with motion vectors: previous records copied into the ring this draw (80 bytes
  /// each). 0 when they were read where the draw of the view's previous selection left them,
  /// which this draw does when it is at most RendererDesc::ring_frames - 2 draws of the
  /// character after that one (docs/rendering.md, "Motion vectors").
  uint64_t previous_records_copied = 0;
};

/// Which program draws: kDefault skins by the renderer's skinning path; kSkinned forces the
/// vertex-shader path and kComputeSkinned the compute pre-skinning path; kDepthOnly writes depth
/// only (shadow maps): vertex-shader skinning in drawCrowd, the renderer's skinning path in
/// drawCrowdGpuCulled; kRigid is rigid instancing of the
/// bind pose (the floor baseline).
enum class DrawMode : uint8_t { kDefault = 0, kSkinned, kDepthOnly, kRigid, kComputeSkinned };

}  // namespace si
