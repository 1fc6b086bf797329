// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once

/// \file
/// GPU time per pass of a draw, read a frame (or more) later so that nothing waits: with
/// RendererDesc::measure_gpu_passes on, every draw that returns stats stamps its passes with
/// GPU timestamps and names them by DrawStats::gpu_pass_ticket; Renderer::readGpuPasses reads
/// them once the GPU is past them (ready stays false until then: read again next frame).
///
/// \code
///   si::RendererDesc rd;
///   rd.measure_gpu_passes = true;
///   ...
///   si::DrawStats st;
///   renderer.drawCrowdGpuCulled(id, view, camera, &st);
///   pending.push_back(st.gpu_pass_ticket);
///   // a frame later:
///   si::GpuPassTimes t;
///   if (renderer.readGpuPasses(pending.front(), &t).isOk() && t.ready)
///     printf("cull %.3f ms of %.3f\n", t.at(si::GpuPass::kCull), t.total_ms);
/// \endcode
///
/// Every pass of the GPU-driven path (drawCrowdGpuCulled) is told apart; drawCrowd's compute
/// path splits its skinning from its draws; the other paths count their uploads and their draws.

#include <cstddef>
#include <cstdint>

namespace si {

/// What a draw's GPU time went to.
enum class GpuPass : uint8_t {
  kUpload = 0,    ///< Uploads and their scatter (the GPU-driven state, live poses, records).
  kCull,          ///< Culling and LOD selection (both phases of occlusion culling).
  kCommands,      ///< The GPU-driven path's command writing (bucket offsets, indirect commands).
  kScatter,       ///< Record scatter into buckets (GPU-driven).
  kCompose,       ///< Layer composition (RendererDesc::compose_layers).
  kSkin,          ///< Compute pre-skinning.
  kDraw,          ///< Mesh draws (vertex-shader skinned and pre-skinned).
  kImpostors,     ///< Impostor draws (CrowdDesc::impostor_lod).
  kDepthPyramid,  ///< The occlusion path's depth pyramid.
  kCount
};

/// Number of GpuPass values (kCount).
constexpr uint32_t kGpuPassCount = uint32_t(GpuPass::kCount);

/// "upload", "cull", "commands", "scatter", "compose", "skin", "draw", "impostors",
/// "depth-pyramid"; "unknown" for another value.
const char* gpuPassName(GpuPass pass);

/// One draw's GPU milliseconds by pass (Renderer::readGpuPasses).
struct GpuPassTimes {
  /// False while the GPU has not finished the draw: nothing below is set yet.
  bool ready = false;
  /// Milliseconds by GpuPass (a pass that ran twice, as culling does with occlusion, summed).
  double ms[kGpuPassCount] = {};
  /// From the draw's first timestamp to its last: the passes' sum.
  double total_ms = 0.0;
  double at(GpuPass pass) const { return ms[size_t(pass)]; }
};

}  // namespace si
