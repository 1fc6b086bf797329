// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// crowd_bench's scenes and one timed configuration: seeded crowds (a field, a stadium), the
// fixed camera paths, and runPath(), which times one drawing path with one LOD mode.
#include <chrono>
#include <cstdio>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "si/core/character.h"
#include "si/crowd/crowd_manager.h"
#include "si/crowd/instance_batcher.h"
#include "si/gl/impostor.h"
#include "si/gl/renderer.h"
#include "si/headless/headless_context.h"

namespace si::bench {

/// The clear colour of every frame; a pixel of another colour is covered by a character.
inline constexpr glm::vec4 kClearColor(0.6f, 0.65f, 0.6f, 1.0f);

struct Setup {
  std::unique_ptr<HeadlessContext> context;
  GlInfo info;
  Character character;              ///< The embedded character, with its LOD chain.
  std::vector<float> lod_errors;    ///< Per LOD level, model units (lodErrorsByLevel).
  bool impostor = false;            ///< The last level is the impostor (CrowdDesc::impostor_lod).
  ImpostorDesc impostor_desc;       ///< What its atlas captures (Renderer::buildImpostor).
  uint32_t width = 0, height = 0;  ///< Of the context.
  uint32_t supersample = 1;  ///< The display is width/supersample x height/supersample: the
                             ///< pixels that LOD budgets are counted in.
  uint32_t frames = 0;       ///< Measured frames per configuration (after 2 warm-up).
};

/// How LODs are chosen: the technique's distance lines, or a projected-error pixel budget.
struct LodChoice {
  LodMode mode = LodMode::kDistance;
  float pixel_budget = 1.0f;  ///< kScreenError.
  int fixed_lod = -1;         ///< >= 0: every instance at this LOD (0: the quality reference).
  std::string name() const;
};

/// Seeded, deterministic scenes. Field: a square grid 1.5 m apart. Plaza: a square grid 1.2 m
/// apart, each character up to 0.4 m off its point. Stadium: a bowl of tiers rising around a pitch, seats 0.9 m apart, tiers 1.0 m deeper
/// and 0.5 m higher each.
std::vector<glm::dvec3> scenePositions(const std::string& scene, uint32_t count);

/// The fixed camera path, frame f of n. Field: orbiting high enough to see the whole field.
/// Plaza: at eye height at the crowd's edge, panning across it (most characters hidden behind
/// nearer ones). Stadium: standing on the pitch, turning round.
Camera cameraAt(const Setup& setup, const std::string& scene,
                const std::vector<glm::dvec3>& positions, uint32_t f, uint32_t n);

/// A crowd of random instances at `positions` (scenePositions()), LODs chosen by `lod`; their
/// handles in `handles` when it is not null. `sub_mesh_count` 0: the character's (more for a
/// character with props attached); room for `live_poses` live poses.
Status makeCrowd(const Setup& setup, const BakedPalette& palette,
                 const std::vector<glm::dvec3>& positions, const LodChoice& lod,
                 CrowdManager* crowd, std::vector<InstanceHandle>* handles = nullptr,
                 uint32_t sub_mesh_count = 0, uint32_t live_poses = 0);

/// Paths whose culling and LOD selection run on the GPU (gpu-culled, gpu-driven, and both with
/// two-phase occlusion culling: gpu-culled-occlusion, gpu-driven-occlusion).
bool isGpuSelected(const std::string& path);

/// Advances the crowd by dt for `path`: the clock only for GPU-selected paths, else update().
Status stepCrowd(CrowdManager& crowd, const std::string& path, const Camera& camera, double dt);

/// Clears and draws the crowd with one path: instanced, compute, gpu-culled (GPU culling,
/// vertex-shader skinning), gpu-driven (GPU culling feeding compute pre-skinning), either with
/// -occlusion (two-phase occlusion culling), traditional, cpu, rigid. `batcher` (initialised
/// with the renderer's batch limits) serves the batched paths.
Status drawPath(Renderer& renderer, const CrowdManager& crowd, InstanceBatcher& batcher,
                const std::string& path, const Camera& camera, DrawStats* stats);
/// The same without the clear, for character `id` of the renderer (several kinds per frame).
Status drawKind(Renderer& renderer, CharacterId id, const CrowdManager& crowd,
                InstanceBatcher& batcher, const std::string& path, const Camera& camera,
                DrawStats* stats);

struct Row {
  std::string scene, path, lod;
  uint32_t instances = 0, visible = 0, draws = 0;
  double triangles = 0, update_ms = 0, submit_ms = 0, gpu_ms = 0;  // Medians over the frames.
  uint64_t covered_pixels = 0;  ///< Of the last frame: pixels not of the clear colour.
  /// --gpu-passes (timeCrowd): medians of the GPU time by si::GpuPass and of its total; how
  /// many draws were read and how many of them a frame late without waiting; the last
  /// measured frame's statistics.
  std::vector<double> pass_ms;
  double pass_total_ms = 0;
  uint32_t passes_read = 0, passes_read_late = 0;
  DrawStats last;
  bool pass_bytes = true;  ///< Whether `last` is the frame's one draw (the byte estimates).
};

/// The frame loop every timed table shares: 2 warm-up frames, then setup.frames measured ones
/// on `scene`'s camera path over `places`, each `step(camera)` (the crowds' update or clock,
/// timed as the update) then `draw(camera, &stats, &visible)` (clear and draw, summing its
/// statistics into `stats`). `row` gets the medians of the update, submit and GPU times and
/// the last frame's visible instances, draw calls and triangles. Stops at the first error.
constexpr uint32_t kWarmupFrames = 2;
using StepFrame = std::function<Status(const Camera&)>;
using DrawFrame = std::function<Status(const Camera&, DrawStats*, uint32_t* visible)>;
Status timeFrames(const Setup& setup, const std::string& scene,
                  const std::vector<glm::dvec3>& places, const StepFrame& step,
                  const DrawFrame& draw, Row* row);

/// A side-by-side table's row: `r`'s path, switch (Row::lod), instances, visible, draws,
/// update, submit and GPU times and its CPU and GPU ratios to `off` (the feature off), printed
/// without the line's end; and its CSV row, tagged `table` ("root-motion", ...).
void printSideBySideRow(const Row& r, const Row& off, const char* table, std::FILE* csv);
/// Its header, the feature's column named `feature`, without the line's end.
void printSideBySideHeader(const char* feature);

/// Times `path` drawing `crowd` (standing at `places` of `scene`) by `renderer`: a batcher for
/// the renderer's limits, the crowd stepped 1/60 s a frame (stepCrowd, or `step` when given),
/// each frame cleared and drawn (drawPath); fills the row's path and instance count and its
/// timings (timeFrames).
Status timeCrowd(Setup& setup, Renderer& renderer, CrowdManager& crowd, const std::string& scene,
                 const std::vector<glm::dvec3>& places, const std::string& path, Row* row,
                 const StepFrame& step = {});

/// Two variants of `path` on the field of `count` characters, drawn on every frame by the same
/// renderer one after the other (`set(k)` switches to variant k before its draw), so both see
/// the same crowd, camera and machine load: `rows[k]` gets variant k's path, instances, visible
/// instances, draws and the medians of its update (shared), submit and GPU times.
Status timePaired(Setup& setup, Renderer& renderer, const BakedPalette& palette, uint32_t count,
                  const std::string& path, const std::function<Status(int)>& set, Row rows[2]);

/// Times one path on one scene; returns a named error.
Status runPath(Setup& setup, Renderer& renderer, const BakedPalette& palette,
               const std::string& scene, uint32_t count, const std::string& path,
               const LodChoice& lod, Row* row);

/// Pixels of an RGBA8 image that are not of kClearColor.
uint64_t coveredPixels(const std::vector<uint8_t>& rgba);

/// The value a fraction `q` (0 to 1) of the way through `v` sorted (0 for none); median() is
/// quantile(v, 0.5).
double quantile(std::vector<double> v, double q);
double median(std::vector<double> v);

using Clock = std::chrono::steady_clock;
/// Milliseconds since `t`.
double msSince(Clock::time_point t);

}  // namespace si::bench
