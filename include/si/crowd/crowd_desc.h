// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once

/// \file
/// si::CrowdDesc: a crowd's options (CrowdManager::init), with how its LODs are chosen.

#include <cstdint>
#include <vector>

#include "si/core/baked_palette.h"

namespace si {

/// How an instance's LOD is chosen.
enum class LodMode : uint8_t {
  kDefault = 0,  ///< kDistance.
  kDistance,     ///< The technique's lines: LOD l + 1 from lod_distances_radii[l] radii on.
  kScreenError,  ///< The coarsest LOD whose geometric error (lod_errors_units), projected at
                 ///< the instance's distance with the camera's vertical field of view and
                 ///< viewport height, stays within pixel_error_budget pixels. A y-flipped
                 ///< projection selects as the upright one; an orthographic one (a shadow
                 ///< cascade) the same level at every distance, judged at scale 1.
};
const char* lodModeName(LodMode mode);

/// Crowd options. Zero fields take the defaults documented on each (resolveDefaults()).
struct CrowdDesc {
  /// The baked palette the instances play; borrowed, must outlive the crowd. Required.
  const BakedPalette* palette = nullptr;
  uint32_t sub_mesh_count = 0;  ///< Sub-meshes of the character, 1..32. Required.
  uint32_t lod_count = 0;       ///< LOD levels of the character, 1..8; 0 means 1.
  /// The character's radius in model units; 0 means the largest clip bounding-sphere radius of
  /// the palette. LOD distances are measured in units of radius * instance scale.
  float character_radius = 0.0f;
  /// lod_count - 1 increasing distances (in radii) where LOD l + 1 starts; empty means
  /// 20, 60, 180, ... (the technique's lines at 20 and 60 radii, then x3).
  std::vector<float> lod_distances_radii;
  /// Instances farther than this many radii are culled; 0 means 100 (the technique's far
  /// line); negative means never, except that an instance whose squared distance from the
  /// camera passes a float (about 1.8e19 units, or whose camera-relative position does) is
  /// always culled by distance: nothing can be drawn there.
  float max_distance_radii = 0.0f;
  /// A LOD changes only once the distance is this fraction past the line (both directions),
  /// so characters at a boundary do not flicker; 0 means 0.05.
  float lod_hysteresis_ratio = 0.0f;
  /// How LODs are chosen; kDefault means kDistance.
  LodMode lod_mode = LodMode::kDefault;
  /// Each LOD level's geometric error in model units (si::lodErrorsByLevel(), or the character's
  /// SubMesh::lod_error_units): lod_count values, non-decreasing, level 0 first. Required for
  /// kScreenError (may also be given for kDistance, to switch with setLodMode() later).
  std::vector<float> lod_errors_units;
  /// kScreenError: the largest projected error allowed, in pixels; 0 means 1.
  float pixel_error_budget = 0.0f;
  /// Impostors (si::Renderer::buildImpostor): the last LOD level is the character's animated
  /// impostor, one textured quad per instance, when this is lod_count - 1 (at least 1); 0 means
  /// none. Its instances join one bucket, sub-mesh 0's, whatever parts they wear (each is drawn
  /// once, not once per part); its value in lod_errors_units is the impostor's measured image
  /// error (si::measureImageLodErrors with ImageLodErrorDesc::impostor).
  uint32_t impostor_lod = 0;
  /// Animation LOD: instances at this LOD or coarser step their animation at
  /// animation_lod_rate_hz instead of interpolating every frame; 0 means off.
  uint32_t animation_lod_start = 0;
  float animation_lod_rate_hz = 0.0f;  ///< 0 means 10 Hz.
  /// Motion vectors: keep the previous update's records and, per record, the index of the same
  /// instance's record in them (previousRecords(), previousRecordIndices()), so a renderer can
  /// skin each vertex where it was drawn last frame. Off by default (it costs two words per
  /// instance and a pass over them per update).
  bool previous_records = false;
  /// Threads update(dt, camera) uses (it runs the work on a WorkerPool of its own, started at
  /// the first update with more than one task): 0 means std::thread::hardware_concurrency(),
  /// at most 16; 1 means the calling thread only. A `parallel_for` given to update() or
  /// advance() runs the tasks instead.
  uint32_t worker_threads = 0;
  /// Live poses (CrowdManager::setLivePose): how many instances the engine may pose itself at
  /// once, each taking one frame of palette texels (CrowdExport::livePoseTexels) that its
  /// record points at. 0 (the default): none. At most kMaxLivePoses.
  uint32_t live_pose_capacity = 0;
  static constexpr uint32_t kMaxLivePoses = 65536;
};

/// Returns the desc with zeros replaced by their documented defaults.
CrowdDesc resolveDefaults(const CrowdDesc& desc);

}  // namespace si
