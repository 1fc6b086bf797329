// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// The small interface every draw path implements (one file per path in this folder), and what
// they share: the uploaded resources, the frame's inputs, the shading uniforms. The renderer
// (src/gl/renderer.cpp) validates, times and fences; a path only issues its GL commands.

#include <glad/gl.h>

#include <cstdint>
#include <vector>

#include "crowd/ring_frame.h"
#include "gl/programs/program_set.h"
#include "gl/resources/character_buffers.h"
#include "gl/resources/drawn_regions.h"
#include "gl/resources/impostor_atlas.h"
#include "gl/resources/palette_texture.h"
#include "gl/resources/pass_timer.h"
#include "gl/resources/preskin_lists.h"
#include "gl/resources/record_ring.h"
#include "gl/resources/scratch_buffers.h"
#include "si/crowd/camera.h"
#include "si/crowd/crowd_manager.h"
#include "si/crowd/instance_batcher.h"
#include "si/gl/renderer.h"

namespace si::detail {

/// What the renderer uploaded and configured, read by every path.
struct DrawResources {
  const GlInfo* info = nullptr;
  const RendererDesc* desc = nullptr;
  /// The renderer's programs through the character's material (Renderer::setMaterial).
  ProgramTable programs;
  const PaletteTexture* palette = nullptr;
  const CharacterBuffers* character = nullptr;
  const PreSkinLists* preskin = nullptr;  ///< The character's pre-skinning lists.
  RecordRing* ring = nullptr;
  ScratchBuffers* scratch = nullptr;  ///< The renderer's, shared by every character's draws.
  uint32_t block_size = 0;  ///< Bytes of the instance uniform block.
  uint32_t capacity = 0;    ///< Records per block.
  uint32_t alignment = 256; ///< Uniform buffer offset alignment.
  /// The application's custom texture array (Renderer::setCustomTextureArray) and its layers;
  /// kNoObject and 0 when none is set.
  GLuint custom_texture = kNoObject;
  uint32_t custom_layers = 0;
  /// The character's impostor atlas (Renderer::buildImpostor; not ready when none was built).
  const ImpostorAtlas* impostor = nullptr;
  /// The renderer's pass timer (RendererDesc::measure_gpu_passes; null when off): paths stamp
  /// the end of each pass they tell apart (markPass).
  PassTimer* passes = nullptr;
};

/// Ends GPU pass `pass` of the draw (resources/pass_timer.h) when passes are timed.
inline void markPass(const DrawResources& r, GpuPass pass) {
  if (r.passes != nullptr) r.passes->mark(pass);
}

/// One frame's inputs.
struct PathFrame {
  const CrowdManager* crowd = nullptr;
  /// The selection drawn (the instanced paths and the baselines): the crowd's own view or a
  /// CrowdView of it. The GPU-driven path selects on the GPU with the view's rules and keeps
  /// the view's own state (gpu_view_slots.h).
  const CrowdView* view = nullptr;
  Camera camera;
  glm::vec3 light{0.0f, -1.0f, 0.0f};
  /// The vertex-shader path's program (skinned, depth-only or rigid).
  ProgramId program = ProgramId::kSkinned;
  /// The batcher's draws and the ring region holding their records (the instanced paths), and
  /// the bytes of it the frame uses (resources/ring_frame.h).
  const std::vector<DrawBatch>* batches = nullptr;
  size_t ring_base = 0;
  size_t ring_bytes = 0;
  /// The GPU-driven path: pre-skin (compute) rather than skin in the vertex shader; draw depth
  /// only (no colour, no motion vectors).
  bool preskin = false;
  bool depth_only = false;
  /// Motion vectors (the instanced paths, RendererDesc::motion_vectors): each slot's
  /// previous-record index and the previous records (copied, or the previous frame's),
  /// `previous_bytes` at `previous_base` of the ring, with `previous_words` (the indices' first
  /// word, the records' base word, words per index step: shaders/previous_index.glsl,
  /// resources/drawn_regions.h), the fallback's shift (si::previousRecordShift), and the crowd's
  /// last and previous update cameras' view-projections. The GPU-driven path: `motion` and the
  /// view-projection its motion uses for this frame (it keeps the previous frame's).
  bool motion = false;
  size_t previous_base = 0;
  size_t previous_bytes = 0;
  glm::uvec3 previous_words{0u};
  glm::vec3 previous_shift{0.0f};
  glm::mat4 motion_view_projection{1.0f}, previous_view_projection{1.0f};
  /// Layered animation (the instanced paths): the batches' layer records at `layer_base` of the
  /// ring (DrawBatch::layer_byte_offset); the mask table is bound.
  bool layers = false;
  size_t layer_base = 0;
  /// Both: the previous layer records (InstanceBatcher::buildPreviousLayers) at uniform binding
  /// 3 from `previous_layer_base`.
  size_t previous_layer_base = 0;
  /// Composed layers (both skinning paths, layer_compose_pass.h): the compose pass runs first
  /// and the program reads its rows, `compose_lanes` invocations per record of the view
  /// (`compose_records` of them, `composed_records` drawn); where each record is drawn and
  /// each slot's record (crowd/composed_places.h) at `compose_entries_base` and
  /// `compose_slots_base` of the ring, the slots' `compose_slot_bytes` bound at storage
  /// binding 30 for the draws.
  bool composed = false;
  /// 2D blends: the extra layer records (and with motion the previous ones) at these bases of
  /// the ring, read by the compose pass only (2D blends are drawn composed).
  bool extras = false;
  size_t extra_layer_base = 0;
  size_t previous_extra_base = 0;
  uint32_t compose_lanes = 0;
  uint32_t compose_records = 0, composed_records = 0;
  size_t compose_entries_base = 0;
  size_t compose_slots_base = 0, compose_slot_bytes = 0;
  /// The crowd's impostor level (CrowdDesc::impostor_lod; 0 none): its instances are drawn as
  /// impostor quads (impostor_draw.h), not as meshes.
  uint32_t impostor_lod = 0;
  /// A material that reads the instance handle (MaterialDesc::instance_handle): each slot's
  /// handle (InstanceBatcher::buildHandles), `handle_bytes` at `handle_base` of the ring,
  /// bound at storage binding 29 (shaders/instance_handle.glsl).
  bool handles = false;
  size_t handle_base = 0;
  size_t handle_bytes = 0;
};

/// The frame of `view` from `camera` under `light` that every draw starts from: the crowd, the
/// view, the camera and light, the crowd's impostor level and the view's motion
/// view-projections (its last and previous select cameras'). Each draw adds what its path needs.
PathFrame viewFrame(const CrowdView& view, const Camera& camera, const glm::vec3& light);

/// Points `f` at the blocks of ring frame `plan` written at ring byte `base`, with the previous
/// records where `previous` says: the one place where the region's layout (ring_frame.h) meets
/// the paths' frame. Sets the records' extent, the previous records and indices, the layer and
/// extra layer records, the composed places and the slot handles, and which of them the frame
/// has (motion, layers, extras, handles).
void placeRingFrame(const RingFrame& plan, size_t base, const PreviousBinding& previous,
                    PathFrame* f);

class DrawPath {
 public:
  virtual ~DrawPath() = default;
  /// Builds what the path keeps per character; called after every character upload.
  virtual Status prepare(const DrawResources& r) = 0;
  /// The frame's validation and uploads, done before the renderer starts its GPU timer.
  virtual Status uploadFrame(const DrawResources&, const PathFrame&) { return Status::ok(); }
  /// Issues the frame's GL commands and adds what it drew to `stats` (draw calls, triangles,
  /// instances and the path's own counters).
  virtual Status draw(const DrawResources& r, const PathFrame& frame, DrawStats* stats) = 0;
  /// Deletes the path's GL objects (context current). Idempotent.
  virtual void release() = 0;
};

/// Binds what the surface of `program` reads (surface.frag.glsl): the character's materials
/// (CharacterBuffers::bindMaterials) and the custom texture array at unit 2 with its layer count.
void bindAppearance(const DrawResources& r, const Program& program);

/// Sets the shared uniforms `program` declares: the camera's view-projection and the light.
void setCameraUniforms(const Program& program, const Camera& camera, const glm::vec3& light);

/// Binds `program`, the character's vertex array, the palette (texture and info block), the
/// appearance (bindAppearance), and sets the shared uniforms it declares (setCameraUniforms).
void bindShading(const DrawResources& r, const Program& program, const Camera& camera,
                 const glm::vec3& light);

/// Motion vectors: sets `program`'s two motion view-projections when `frame.motion` (each
/// batch then binds its previous records at uniform binding 1).
void setMotionUniforms(const Program& program, const PathFrame& frame);

/// Motion vectors of drawCrowd: binds `frame`'s previous-record blocks at storage binding 25
/// and sets `program`'s previous_index.glsl uniforms (locations 8 and 9).
void bindPreviousRecords(const DrawResources& r, const Program& program, const PathFrame& frame);

/// A material that reads the instance handle: binds `frame`'s slot handles at storage binding
/// 29 (nothing without).
void bindSlotHandles(const DrawResources& r, const PathFrame& frame);

/// Sets `batch`'s first slot (shaders/batch_slot.glsl) where `program` reads one: its composed
/// rows, previous indices or instance handles start there.
void setBatchSlot(const Program& program, const DrawBatch& batch);

/// Dispatches `groups` groups of 64 invocations for the bound program (which indexes them with
/// siFlatInvocation(), shaders/dispatch_index.glsl) in rows within GlInfo's limits
/// (dispatch_grid.h); kLimitExceeded naming `what` and the count when they do not fit, nothing
/// dispatched.
Status dispatchGroups(const GlInfo& info, uint64_t groups, const char* what);

/// What the instanced shader computes for palette slot `slot` of the crowd's record `record`:
/// clip A's frames lerped, crossfaded towards clip B by the record's weight, and the overlay on
/// its mask when the crowd plays any (the two CPU baselines use it).
glm::mat4 recordJointMatrix(const BakedPalette& palette, const CrowdView& view, size_t record,
                            uint32_t slot);

/// What the instanced shader computes for the morph target weights of the crowd's record
/// `record` (si_morph.glsl's siMorphLayerWeight), into `out`, which holds
/// palette.layout.morph_target_count weights: clip A's, crossfaded towards clip B's, and the
/// overlay on its mask when the crowd plays any (the two CPU baselines use it).
Status recordMorphWeights(const BakedPalette& palette, const CrowdView& view, size_t record,
                          Span<float> out);

}  // namespace si::detail
