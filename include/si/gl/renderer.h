// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once

/// \file
/// si::gl: the thin OpenGL 4.5 core back-end. It assumes a current context (it never makes one),
/// uploads the palette and the character, streams instance records without stalls (a
/// persistently mapped ring guarded by fences) and issues one glDrawElementsInstanced per
/// batch. Baselines in the same back-end: the traditional non-instanced path (one draw per
/// character with its palette in a uniform block) and rigid instancing of the bind-pose mesh.
///
/// Usage:
/// \code
///   si::GlInfo info;
///   si::loadGl(getProc, user, &info);
///   si::Renderer renderer;
///   si::Status s = renderer.init(info, {});
///   si::CharacterId id;
///   s = renderer.addCharacter(character, palette, &id);  // the first character is id 0
///   si::InstanceBatcher batcher;
///   s = batcher.init(renderer.batchLimits());
///   // each frame, after crowd.update(dt, camera):
///   si::DrawStats stats;
///   s = renderer.drawCrowd(id, crowd.view(), batcher, camera, &stats);
/// \endcode
///
/// Several character kinds (soldiers, animals, ...) share one renderer: addCharacter() uploads
/// each with its palette and returns its id; each crowd (made for that character's palette) is
/// drawn with that id. The programs, the record ring and the scratch buffers are shared.
/// \code
///   si::CharacterId soldiers, foxes;
///   renderer.addCharacter(soldier, soldier_palette, &soldiers);
///   renderer.addCharacter(fox, fox_palette, &foxes);
///   renderer.drawCrowd(soldiers, soldier_crowd.view(), batcher, camera, &stats);
///   renderer.drawCrowd(foxes, fox_crowd.view(), batcher, camera, &stats);
/// \endcode
///
/// Vertex format (36 or 32 bytes): position 3 x f32 (12), normal 10:10:10:2 snorm (4),
/// texcoord 2 x f16 (4), joints 4 x u8 when the palette stores at most 256 joints, else
/// 4 x u16 (4 or 8), weights 4 x unorm16 summing to exactly 1 (8). Positions are not
/// quantized; the weights add at most 1.5e-5 of a weight each, which the baker's error report
/// includes (it emulates the quantized weights); normals and texcoords affect shading only.

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "si/core/baked_palette.h"
#include "si/core/character.h"
#include "si/crowd/camera.h"
#include "si/crowd/crowd_view.h"
#include "si/crowd/instance_batcher.h"
#include "si/gl/draw_call.h"
#include "si/gl/gl_context.h"
#include "si/gl/gpu_memory.h"
#include "si/gl/gpu_passes.h"
#include "si/gl/impostor.h"
#include "si/gl/material.h"
#include "si/gl/renderer_desc.h"

namespace si {

/// The back-end. Create after loadGl(); destroy (or shutdown()) with the context current.
class Renderer {
 public:
  Renderer();
  ~Renderer();
  Renderer(const Renderer&) = delete;
  Renderer& operator=(const Renderer&) = delete;

  /// Compiles the programs. kBackend when no GL context is current, or with the driver's log
  /// when a shader fails to compile or link; kInvalidArgument for a uniform block size below
  /// 16384 or above the limit; kLimitExceeded for a compute ring larger than the context's
  /// GL_MAX_SHADER_STORAGE_BLOCK_SIZE.
  ///
  /// Every GL allocation the renderer makes (here, at uploads and while drawing) reports
  /// failure as a named error from the call that made it: kLimitExceeded when the driver is out
  /// of memory (naming what and how large), kBackend for another GL error; never a GL error
  /// left for a later call. A draw that finds the context lost (glGetGraphicsResetStatus)
  /// returns kBackend saying so.
  Status init(const GlInfo& info, const RendererDesc& desc);
  /// Releases every GL object (needs the context current). Idempotent.
  void shutdown();

  /// The limits to give the InstanceBatcher (the block size in use and the offset alignment).
  BatchLimits batchLimits() const;

  /// Uploads a character with the palette baked for it and returns its id in `id`: the number
  /// of characters before it. The palette texture (RGBA32F or RGBA16F) and the mesh (joint
  /// indices remapped to the palette's slots) with its materials (the material table and base
  /// colour texture array) are uploaded together; with SkinningPath::kAutomatic both skinning
  /// paths are then measured for it and the faster kept. The palette is borrowed: keep it
  /// alive while the character is drawn, and draw the crowds that play it. Nothing is added
  /// when it fails: kInvalidArgument for a null `id`, a palette that fails
  /// BakedPalette::validate(), one baked for another skeleton or a mesh that fails
  /// SkinnedMesh::validate(); kLimitExceeded for a palette larger than GL_MAX_TEXTURE_SIZE or
  /// more base colour layers than a texture array holds or morph entries than a texture of
  /// RendererDesc::max_texture_size holds (si::buildMorphStream); kInvalidArgument for a mesh
  /// with morph targets and a palette baked without them; the allocation errors of init().
  Status addCharacter(const Character& character, const BakedPalette& palette, CharacterId* id);
  /// Replaces character `id` with `character` and its `palette` (a re-bake, another format,
  /// content reloaded), uploaded and measured as addCharacter() does; the id stays, and crowds
  /// drawn with it must play the new palette. On failure the old character stays (the same
  /// errors, and kInvalidArgument for an id no addCharacter() gave).
  Status replaceCharacter(CharacterId id, const Character& character, const BakedPalette& palette);
  /// Characters added.
  uint32_t characterCount() const;

  /// Draws character `id`'s animated impostor atlas (si/gl/impostor.h) on the GPU: every
  /// clip's reduced frames from every view direction of `desc`, with this renderer's programs
  /// (vertex-shader skinning), offscreen, supersampled as ImpostorDesc::capture_supersample
  /// says and averaged into the atlas; the host's framebuffers and viewport are kept. Crowds
  /// whose CrowdDesc::impostor_lod is set then draw their instances at that level as impostors
  /// (drawCrowd and drawCrowdGpuCulled; the baselines return kUnsupported for such crowds).
  /// Replaces an earlier atlas; replaceCharacter() drops it. `info` (may be null) gets the
  /// atlas's size and bytes, planned before anything is allocated: also when the build is then
  /// refused for a limit or the budget. kInvalidArgument for an unknown id, more than 4
  /// elevations, elevations not increasing or outside [-90, 90] degrees, a mask wearing no
  /// sub-mesh, a capture_supersample other than 0, 1, 2 or 4; kLimitExceeded, naming the
  /// limit, when a side of the capture (the atlas's times capture_supersample) would pass
  /// GL_MAX_TEXTURE_SIZE, GL_MAX_RENDERBUFFER_SIZE or GL_MAX_VIEWPORT_DIMS, its cells 2^20 (one
  /// capture instance each), or its bytes with the capture's ImpostorDesc::max_bytes; the
  /// allocation errors of init(). The old atlas stays on failure.
  Status buildImpostor(CharacterId id, const ImpostorDesc& desc, ImpostorInfo* info = nullptr);
  /// Whether character `id` has an impostor atlas.
  bool hasImpostor(CharacterId id) const;

  /// The path DrawMode::kDefault uses for character `id`, and why (measured times, or
  /// "explicit setting").
  SkinningPath skinningPath(CharacterId id) const;
  const std::string& skinningPathReason(CharacterId id) const;
  /// Bytes allocated for the compute path's vertex ring, shared by every character (0 until it
  /// is first used).
  uint64_t computeRingBytes() const;
  /// Turns RendererDesc::gpu_occlusion_culling on or off from the next drawCrowdGpuCulled().
  void setGpuOcclusionCulling(bool on);
  /// Turns RendererDesc::motion_vectors on or off from the next draw.
  void setMotionVectors(bool on);
  /// Turns RendererDesc::restore_state on or off from the next call.
  void setRestoreState(bool on);
  /// Turns RendererDesc::compose_layers on or off from the next draw.
  void setComposeLayers(bool on);
  bool motionVectors() const;
  /// drawCrowdGpuCulled's motion vectors: the projection they use in place of the draw camera's
  /// from the next GPU-driven draw on (the draw camera's without its temporal anti-aliasing
  /// jitter, so the jitter does not enter the motion; drawCrowd gets the same from the crowd's
  /// update camera). Null: the draw camera's own. Culling and the image use the draw camera.
  void setGpuMotionProjection(const glm::mat4* projection);

  /// The application's custom texture array, which instances select a layer of
  /// (InstanceDesc::custom_layer: 0 none, k layer k - 1): a GL_TEXTURE_2D_ARRAY name, sampled
  /// with the mesh's texcoords through its own sampler state at texture unit 2. Where the
  /// material's tint mask (its texture's alpha) is, the custom texel (over the base texel by its
  /// own alpha) is what the instance's tint multiplies. Its layer count is read here; layers
  /// past kMaxCustomLayers (255) cannot be selected, and a select past the last layer draws as
  /// no select. Keep the texture alive while set; 0 detaches. kInvalidArgument for a name that
  /// is not a texture, another target or a texture without storage; the previous array stays.
  Status setCustomTextureArray(uint32_t texture);
  /// Layers of the custom texture array instances can select (0: none set).
  uint32_t customTextureLayers() const;

  /// Compiles material `desc` (si/gl/material.h) into the fragment stage of every path's
  /// programs now (25 programs, 32 with depth_discard; measured when they were 21: 254 ms on
  /// llvmpipe, 10.5 s on an H200's NVIDIA driver: add materials at load time) and
  /// returns its id in `id`. Nothing is added when it fails: kInvalidArgument for a null `id`,
  /// a desc that fails MaterialDesc::validate() or a resource MaterialDesc::source must not
  /// declare (named); kBackend with the driver's log, naming the program, when it does not
  /// compile or link (the material's own line numbers, as source string 1); kUnsupported on
  /// the OpenGL ES profile.
  Status addMaterial(const MaterialDesc& desc, MaterialId* id);
  /// The material character `character`'s draws use from the next draw on (every path and
  /// mode; kBuiltinMaterial after addCharacter, kept by replaceCharacter). Switching costs
  /// nothing, so one crowd can be drawn with several materials in a frame (a G-buffer pass and
  /// a forward pass), except the first time a character whose mesh has texture coordinates 1
  /// or colours takes a material: that compiles the material's variants for such meshes (23
  /// programs; kBackend with the driver's log if one fails, the material unchanged).
  /// kInvalidArgument for an unknown character or material.
  Status setMaterial(CharacterId character, MaterialId material);
  /// Character `character`'s material (kBuiltinMaterial for an unknown one).
  MaterialId material(CharacterId character) const;

  /// Sets the directional light (world direction the light travels along).
  void setLightDirection(const glm::vec3& direction) { light_direction_ = direction; }
  /// Clears the bound draw framebuffer's draw buffer 0 to `color` and its depth to `depth`
  /// (1, the far plane; 0 under reverse-Z, DepthConvention::kReversedZeroToOne) with
  /// glClearNamedFramebufferfv: the clear colour and depth of the context are left as they
  /// are; the scissor test and the write masks apply.
  void clear(const glm::vec4& color, float depth = 1.0f);

  /// Builds the batches of `view`'s last selection (si::CrowdView: a crowd's own view(), after
  /// CrowdManager::update(), or a view of its own: a shadow cascade, a second camera) with
  /// `batcher` straight into the mapped record ring and draws each with one
  /// glDrawElementsInstanced, for character `character` (whose palette the view's crowd must
  /// play: kInvalidArgument otherwise, for an unknown id or a view that is not attached).
  /// `camera` must sit where the view's last select() camera sat (the records are relative to
  /// it); motion vectors use the view's previous records (CrowdViewDesc::previous_records) and
  /// cameras. `mode` picks the program. The draws use the bound framebuffer and the host's depth
  /// function; every draw function returns kInvalidArgument when `camera.depth`
  /// (si::DepthConvention, e.g. reverse-Z) does not match the context's clip control depth mode.
  Status drawCrowd(CharacterId character, const CrowdView& view, const InstanceBatcher& batcher,
                   const Camera& camera, DrawStats* stats, DrawMode mode = DrawMode::kDefault);
  /// The traditional path: for each visible instance of the view, computes its joint matrices
  /// (and its morph target weights) on the CPU from the palette, uploads them into a uniform
  /// block and issues one glDrawElements per worn sub-mesh.
  Status drawTraditional(CharacterId character, const CrowdView& view, const Camera& camera,
                         DrawStats* stats);

  /// The CPU-skinning baseline: for each visible instance of the view, computes its joint
  /// matrices from the palette, skins the vertices of its worn sub-meshes at its LOD on the CPU
  /// (si::emulateSkinning arithmetic), streams them to the GPU (camera-relative world space)
  /// and draws them without any skinning in the shader, one glDrawElementsBaseVertex per
  /// sub-mesh.
  Status drawCpuSkinned(CharacterId character, const CrowdView& view, const Camera& camera,
                        DrawStats* stats);

  /// GPU-driven culling and LOD of a view: the crowd's state lives in shader storage buffers
  /// (uploaded again only when CrowdExport::stateVersion() changes, once for all its views); a
  /// compute pass culls every instance against the frustum and the view's far line, picks its LOD
  /// with hysteresis (the same arithmetic and rules as CrowdView::select(), so the same instances
  /// and LODs, lod_bias included), computes its record at the crowd's clock, and buckets it per
  /// (LOD, sub-mesh). Then, with pre-skinning (`mode` kComputeSkinned, or kDefault when the
  /// renderer's path is kCompute), an indirect compute dispatch skins every bucket's vertices
  /// into a ring and one glMultiDrawElementsIndirect draws them by vertex pulling (instances
  /// past the ring: vertex-shader skinning, a second multi-draw); without (kSkinned, or
  /// kDefault on the vertex-shader path), one multi-draw with vertex-shader skinning. The CPU
  /// cost per frame does not grow with the crowd: step it with CrowdManager::advance() (O(1)
  /// without root motion or clip markers) instead of update(); the view needs no select(). With
  /// RendererDesc:: measure_gpu_time, `stats` also gets the visible instances, triangles and
  /// pre-skinned vertices (read back after the timer); otherwise only draw_calls and the CPU time.
  /// kDepthOnly draws depth only (a shadow view) on the renderer's path, with no motion vectors.
  /// Live poses (CrowdManager::setLivePose) draw as drawCrowd draws them: their frames upload
  /// after the palette's, their slots (CrowdExport::livePoses) with the state.
  /// kInvalidArgument for kRigid or a detached view. Each character keeps the
  /// GPU state of the last crowd it drew: draw one crowd per character (another re-uploads).
  ///
  /// Views: each view (CrowdView::identity(); a crowd's own view() is a view like any other)
  /// keeps its own GPU state between frames: its LOD per instance (seeded from
  /// CrowdExport::lods at each upload), its visibility history for two-phase occlusion culling and
  /// its drawn records for motion vectors. Views drawn in any order give the same images. A
  /// view not drawn for 16 frames (crowd clocks), or the least recently drawn past 32 views,
  /// loses that state and starts again as a new view.
  ///
  /// With RendererDesc::motion_vectors, the cull pass also writes each visible instance's
  /// previous record: what this view drew of the same instance (by handle) in the previous
  /// frame, kept on the GPU, or else the camera-motion-only fallback of drawCrowd. A frame is
  /// one crowd clock: draws at the same clock are the same frame, and the previous frame is the
  /// last one drawn at an earlier clock, with the view's camera of its last draw with motion
  /// vectors there. Positions are projected with the draw cameras, or with
  /// setGpuMotionProjection()'s projection (an unjittered one) in their place. A character's
  /// frames follow one crowd: drawing another crowd (CrowdManager::identity()) starts every
  /// view over with the fallback.
  Status drawCrowdGpuCulled(CharacterId character, const CrowdView& view, const Camera& camera,
                            DrawStats* stats, DrawMode mode = DrawMode::kDefault);
  /// The last drawCrowdGpuCulled() frame's selection of character `character`, read
  /// back: (dense index, LOD) per visible instance in no particular order (dense index i is
  /// CrowdExport::state()'s instance i). For tests and tools: it waits for the GPU, and the
  /// list it reads may make later frames' culling wait on some drivers.
  Status readGpuSelection(CharacterId character, std::vector<glm::uvec2>* selection);

  /// The GPU time per pass of the draw that gave `ticket` (DrawStats::gpu_pass_ticket, with
  /// RendererDesc::measure_gpu_passes), without waiting: out->ready is false while the GPU has
  /// not finished it (read again a frame later). The renderer keeps the last kGpuPassTickets
  /// draws' stamps. kInvalidArgument before init(), for a null output or a ticket it never gave;
  /// kNotFound for a ticket older than the last kGpuPassTickets draws (its stamps reused).
  Status readGpuPasses(uint64_t ticket, GpuPassTimes* out) const;
  /// The draws whose pass times readGpuPasses() keeps.
  static constexpr uint32_t kGpuPassTickets = 64;

  /// The renderer's GPU memory by what holds it (si/gl/gpu_memory.h): shared rings, each
  /// character, each GPU-driven crowd. Context current. kInvalidArgument before init() or for
  /// a null output; kUnsupported on the OpenGL ES profile (no texture size queries there).
  Status gpuMemory(GpuMemory* out) const;

  /// Skins every vertex of character `character`'s mesh (in mesh order) for one instance
  /// `record` on the GPU and returns the skinned model-space positions (before the world
  /// transform): the GPU side of the GPU-equals-CPU tests. kVertexShader runs the skinning vertex
  /// shader and reads its output through transform feedback; kCompute runs the compute pre-skinning
  /// pass (with the record's world transform replaced by the identity) and reads its buffer;
  /// kAutomatic uses the renderer's path (skinningPath()).
  Status captureSkinnedPositions(CharacterId character, const InstanceRecord& record,
                                 std::vector<glm::vec3>* out,
                                 SkinningPath path = SkinningPath::kVertexShader);

  /// Triangles of sub-mesh `sub_mesh` at `lod` of `character` as uploaded (0 for an unknown
  /// one).
  uint32_t triangleCount(CharacterId character, uint32_t sub_mesh, uint32_t lod) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  glm::vec3 light_direction_ = glm::normalize(glm::vec3(-0.4f, -1.0f, -0.3f));
};

}  // namespace si
