// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once

/// \file
/// The renderer's options (Renderer::init): which path skins, how the GPU-driven path uploads,
/// the rings' sizes, motion vectors, occlusion culling, the guest contract's switches. Plain
/// data, no GL. Zero fields take the defaults documented on each.
///
///   si::RendererDesc desc;
///   desc.motion_vectors = true;
///   renderer.init(info, desc);

#include <cstdint>

namespace si {

/// Where the crowd's vertices are skinned.
enum class SkinningPath : uint8_t {
  kAutomatic = 0,  ///< Measure both at addCharacter() and keep the faster (logged).
  kVertexShader,   ///< The vertex shader skins each vertex as it draws (the technique's path).
  kCompute,        ///< A compute pass pre-skins the visible vertices into a buffer ring; the
                   ///< draw reads them by vertex id (GL 4.3 compute, vertex pulling).
};
const char* skinningPathName(SkinningPath path);

/// How drawCrowdGpuCulled() brings a crowd's changes to the GPU (RendererDesc::gpu_state_upload).
enum class GpuStateUpload : uint8_t {
  kChanged = 0,  ///< The instances changed since the last upload.
  kWhole,        ///< Every instance, at any change.
};

/// Renderer options. Zero fields take the defaults documented on each.
struct RendererDesc {
  /// Uniform block size to batch for, in bytes; 0 means the context's limit. Lower it (e.g. to
  /// GL's minimum 16384) to test batching; it can never exceed the limit.
  uint32_t uniform_block_size_bytes = 0;
  /// Frames the record ring holds before reusing a region (each guarded by a fence); 0 means 3,
  /// or 4 while motion vectors are on (set again at the next drawCrowd after
  /// setMotionVectors). The ring has this many regions per character (each character's draw
  /// takes one). With motion vectors, drawCrowd reads the previous records where the view's
  /// last draw left them only when this draw is at most ring_frames - 2 draws of the character
  /// after that one (else it copies them), since a region read so is written again only once
  /// the reading draw is done too: with 4 regions and one draw a frame, the CPU stays as far
  /// ahead of the GPU as with 3 and no motion vectors (docs/rendering.md, "Motion vectors").
  uint32_t ring_frames = 0;
  /// Check glGetError after each group of calls (a failing check is the call's kBackend
  /// status, naming the GL error). Errors already pending when a call starts are the host's:
  /// they are drained and logged as warnings naming the call, never returned as its failure.
  /// 0 means: on in debug builds (no NDEBUG), off otherwise; 1 on; 2 off.
  uint32_t debug_checks = 0;
  /// Opt-in: route the driver's KHR_debug messages to si's log callback (si::setLogCallback).
  /// The renderer then installs a debug callback that first hands every message to the
  /// callback installed before it (with that callback's user pointer), so the host's callback
  /// still receives every message; it enables GL_DEBUG_OUTPUT (never the synchronous mode).
  /// shutdown() puts the previous callback and GL_DEBUG_OUTPUT back, if the host has not
  /// installed another callback since. Off (the default), the renderer never touches debug
  /// output. Ignored without KHR_debug (GlInfo::has_khr_debug).
  bool debug_messages = false;
  /// The GL state contract. On (the default), every call that changes context state saves the
  /// state it may change and restores it before it returns: the host finds its program, vertex
  /// array, buffer bindings (indexed ones included), textures and samplers, enables, face
  /// culling, colour and depth masks, blending, framebuffers, viewport, the raster state of the
  /// offscreen passes (depth function and range, clip control, polygon mode, ...) and pixel
  /// store as it left them. Draws write depth and blend nothing whatever the host's last pass
  /// left; offscreen passes (the automatic path measurement, buildImpostor, measureImage-
  /// LodErrors) run under GL's default raster state (docs/rendering.md). Off, the
  /// calls skip the save and restore and leave what docs/rendering.md ("A guest in the host's
  /// engine") lists; the cost of restoring is measured there. Switchable with
  /// setRestoreState().
  bool restore_state = true;
  /// WebGL 2 only (GlInfo::webgl). WebGL answers the face-culling mode (GL_CULL_FACE_MODE), the
  /// front face (GL_FRONT_FACE) and the colour mask (GL_COLOR_WRITEMASK) only through a
  /// synchronous round trip to the browser's GPU process, which waits for all the queued work
  /// (docs/web.md measures it); the depth write mask (GL_DEPTH_WRITEMASK) is treated alike.
  /// Every other value the state contract saves is answered by the page. Off (the default),
  /// the contract does not ask for these four and leaves them at GL's defaults, the values it
  /// draws with: glCullFace(GL_BACK), glFrontFace(GL_CCW), every colour channel and depth
  /// written. On, it asks and restores them like the rest. Ignored elsewhere and with
  /// restore_state off.
  bool webgl_restore_raster_state = false;
  /// Measure GPU time of each draw call group with a timer query (blocks until the result is
  /// available: for benchmarks and tests).
  bool measure_gpu_time = false;
  /// Stamp each pass of every draw that returns stats with GPU timestamps, read later without
  /// waiting (si/gl/gpu_passes.h: DrawStats::gpu_pass_ticket, Renderer::readGpuPasses). Costs
  /// a few timestamp queries a draw. Desktop GL only: init() refuses it on the ES profile.
  bool measure_gpu_passes = false;
  /// The skinning path of DrawMode::kDefault. kAutomatic (the default) times both paths on a
  /// synthetic crowd of about 2^20 vertices of the uploaded character at addCharacter()
  /// (offscreen; milliseconds on a GPU, about 2 s on llvmpipe) and logs the choice with its
  /// reason; the others are explicit.
  SkinningPath skinning_path = SkinningPath::kAutomatic;
  /// Bytes of the compute path's pre-skinned vertex ring (16 bytes a vertex); 0 means 32 MiB.
  /// The visible set is skinned and drawn in chunks that fit; it never grows past this, except
  /// to hold at least one instance of the largest sub-mesh LOD. Once a character with tangents
  /// is drawn, a tangent ring of a quarter as many bytes (4 a vertex) sits beside it.
  uint64_t compute_ring_bytes = 0;
  /// Bytes of the GPU-driven path's pre-skinned vertex ring (16 bytes a vertex); 0 means
  /// 256 MiB or GL_MAX_SHADER_STORAGE_BLOCK_SIZE if smaller. Instances that do not fit in a
  /// frame are drawn with vertex-shader skinning instead (DrawStats::vertex_shader_instances).
  /// With tangents, a tangent ring of a quarter as many bytes beside it, as compute_ring_bytes.
  uint64_t gpu_driven_ring_bytes = 0;
  /// drawCrowdGpuCulled(): two-phase occlusion culling. Phase 1 draws the instances visible at
  /// the end of the last frame; the depth buffer (of the framebuffer bound when drawing, over
  /// the viewport; a multisampled one by each pixel's farthest sample) is reduced into a depth
  /// pyramid; phase 2 tests every
  /// instance in the frustum against it (its bounding sphere's box), draws those not occluded
  /// that phase 1 did not, and remembers which are visible for the next frame. The image is the
  /// one without occlusion culling; what the application drew before also occludes, so it must
  /// have been drawn with the same camera. Switchable with setGpuOcclusionCulling().
  bool gpu_occlusion_culling = false;
  /// drawCrowdGpuCulled(): how a crowd's changes reach the GPU. kChanged (the default) exports
  /// and uploads only the instances that changed since the last upload
  /// (CrowdExport::changedSince: a setter, root motion, an add or a removal), and restarts each
  /// view's per-instance history (LOD hysteresis, visible last frame) only where another
  /// instance now sits. kWhole exports and uploads every instance at any change and restarts
  /// every view's history (the library before 2026-11-26; for comparison).
  GpuStateUpload gpu_state_upload = GpuStateUpload::kChanged;
  /// Motion vectors, for temporal anti-aliasing, upscalers and motion blur. drawCrowd's skinned
  /// colour draws (kDefault, kSkinned, kComputeSkinned; both skinning paths) also write each
  /// fragment's screen motion since the previous frame to fragment output 1 (bind a framebuffer
  /// with a second colour attachment, e.g. GL_RG16F, and both draw buffers): this frame's
  /// position minus the previous one, in texture coordinate units (the viewport spans 1 in x
  /// and y; a pixel p came from p - motion). The previous position skins each vertex with the
  /// instance's previous record (CrowdDesc::previous_records or CrowdViewDesc::
  /// previous_records, required: kInvalidArgument otherwise) and projects it with the camera of
  /// the view's previous selection; the current one uses the camera of its last selection
  /// (CrowdView::previousCamera(), camera()), so a jittered projection given to the draw does not
  /// enter the motion. An instance without a previous record (not drawn then, added or teleported
  /// since) gets the camera's motion only (InstanceBatcher::buildPrevious's fallback; drawCrowd
  /// reads the previous records through InstanceBatcher::buildPreviousIndices, docs/rendering.md).
  /// A frame whose previous records and indices exceed GL_MAX_SHADER_STORAGE_BLOCK_SIZE is refused
  /// (kLimitExceeded). drawCrowdGpuCulled writes them too, from what it drew itself (see there; no
  /// previous records needed). kDepthOnly and kRigid draws write no motion; drawTraditional and
  /// drawCpuSkinned return kUnsupported while it is on. Switchable with setMotionVectors().
  bool motion_vectors = false;
  /// Layered animation on every skinning draw (drawCrowd's and drawCrowdGpuCulled's, both
  /// skinning paths, depth-only included). On (the default), a compute pass first composes each
  /// overlaid record's masked joints once per frame (the overlay's matrices on the base's anchor,
  /// and between weights every masked link blended in local space) into a buffer of 48 bytes per
  /// masked joint and record, and where masks hold morph targets each record's weights of them
  /// (4 bytes per target; the previous records' too with motion vectors), which the vertex
  /// shader or the pre-skinning pass reads in place of walking each influence's chain per vertex;
  /// the image is the same. Off, or where those rows (or drawCrowd's record ring, which the pass
  /// reads) would exceed GL_MAX_SHADER_STORAGE_BLOCK_SIZE or the pass
  /// GL_MAX_COMPUTE_WORK_GROUP_COUNT, each vertex walks the chain (DrawStats::compose_dispatches
  /// tells which). Switchable with setComposeLayers().
  bool compose_layers = true;
  /// Morph targets at coarse LOD levels: each vertex leaves out the targets (its smallest
  /// first) that together move it at most this share of the level's geometric error
  /// (si::morphLodCuts; LOD 0 keeps every target). The level's error on screen then grows by
  /// at most this share: 0.5 keeps a 1-pixel budget within 1.5 pixels. 0 keeps every target at
  /// every level; values outside [0, 1] are refused by init (kInvalidArgument). Read when a
  /// character is added.
  float morph_lod_share = 0.5f;
  /// Largest side of the base colour texture array's layers (si::buildMaterialTable: every
  /// material image resized to one size, so all materials share a draw); 0 means 2048.
  uint32_t max_texture_size = 0;
};

}  // namespace si
