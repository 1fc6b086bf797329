// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// The crowd_demo scene, shared by its headless and windowed front ends: the character (embedded
// or glTF), its palette (baked here or loaded from a si-bake file), the renderer, a seeded
// field of characters and the knobs the window's keys turn. Needs a current GL 4.5 context.

#include <memory>
#include <string>
#include <vector>

#include "demo_cast.h"
#include "demo_shadows.h"
#include "si/bake/animation_baker.h"
#include "si/core/core.h"
#include "si/core/look_at.h"
#include "si/crowd/crowd_manager.h"
#include "si/crowd/instance_batcher.h"
#include "si/gl/motion_target.h"
#include "si/gl/renderer.h"

namespace demo {

/// How the crowd is drawn: the library's paths and its baselines.
/// kInstanced uses the renderer's measured choice of skinning path; kVertexShader and kCompute
/// force one.
enum class DrawPath {
  kInstanced = 0, kVertexShader, kCompute, kRigid, kTraditional, kCpuSkinned, kCount
};
const char* drawPathName(DrawPath p);

struct SceneOptions {
  uint32_t instances = 4000;
  float rate_hz = 0.0f;  // 0: the baker's automatic rates.
  si::PaletteFormat format = si::PaletteFormat::kDefault;
  uint64_t seed = 7;
  std::string model;    // glTF file; empty: the embedded character.
  std::string palette;  // Palette file (si-bake) to load instead of baking.
  std::vector<std::string> clips;
  float lod_pixels = 0.0f;  // > 0: deeper LOD chains, LOD by projected error within this budget.
  bool impostors = false;   // An animated impostor past the last LOD (with lod_pixels).
  bool small_atlas = false;  // Its atlas: 8 azimuths, 2 elevations, 4 frames per clip.
  std::vector<std::string> mix;  // Other kinds (glTF files) of the mixed scene; starts mixed.
  bool events = false;  // Animation events on from the start (key V).
  bool root_motion = false;  // The field travels from the start (key R).
  bool motion_vectors = false;  // Motion vectors measured from the start (key X).
  bool layers = false;  // Every other character overlays layer_clip on layer_root (key L).
  bool props = false;   // Every other character holds a staff (key O; the embedded character).
  bool blend = false;   // Every other character walks and runs by a drifting speed (key B).
  bool shadows = false;  // Cascaded shadows on a ground plane (key H).
  // > 0: this many face-like morph targets on the character's head (examples/common/
  // face_targets.h), their weights animated by every clip, each on its own phase.
  uint32_t faces = 0;
  bool close_up = false;                  // The headless camera among the first rows' faces.
  // Live poses (key G): the nearest characters turn their heads to the camera, and one falls
  // and gets up every two seconds (demo_live.cpp).
  bool live = false;
  std::string layer_root = "r_clavicle";  // The overlay's branch root joint.
  std::string layer_clip = "wave";        // The overlay clip.
};

/// The sample models key M mixes in when --mix named none (the sample Fox and CesiumMan).
std::vector<std::string> defaultMix();

/// Flips `*option` and applies it (`apply`); when that fails the option is flipped back, so the
/// scene keeps its previous state.
template <typename Apply>
si::Status toggleOption(bool* option, Apply apply) {
  *option = !*option;
  const si::Status s = apply();
  if (!s.isOk()) *option = !*option;
  return s;
}

class DemoScene {
 public:
  /// Loads the character and its palette (printing the summary), without GL.
  si::Status loadCharacter(const SceneOptions& options);
  /// Creates the renderer for the current context and lays out the crowd.
  si::Status initGl(const si::GlInfo& info);
  /// Releases the GL objects; call with the context still current (before destroying it).
  void releaseGl() {
    motion_target_.release();
    shadows_.releaseGl();
    renderer_.shutdown();
    cast_.releaseGl();
  }

  /// Draws one frame `dt` seconds after the last one with the current path.
  si::Status frame(double dt, const si::Camera& camera, si::DrawStats* stats);

  // The knobs the window's keys turn; each takes effect from the next frame.
  si::Status setInstanceCount(uint32_t count);
  si::Status cycleFormat();       ///< Re-bakes in the next palette format and re-uploads.
  si::Status scaleLodLines(float factor);
  si::Status crossfadeAll();      ///< Every character blends to the next clip over 0.5 s.
  void cyclePath() { path_ = DrawPath((int(path_) + 1) % int(DrawPath::kCount)); }
  void toggleLodTint() { lod_tint_ = !lod_tint_; restore_colors_ = !lod_tint_; }
  /// The mixed scene on or off: a share of the field becomes the other kinds (--mix, else the
  /// sample Fox and CesiumMan), all in the one renderer (Renderer::addCharacter).
  si::Status toggleMixed();
  /// Animation events on or off: markers at the start and the middle of every clip of the main
  /// character (kept across re-layouts); the events each update reports are counted.
  si::Status toggleEvents();
  /// Root motion on or off: the field plays the palette's clips that carry root motion (the
  /// embedded character's walk_forward and walk_turn_left, baked the first time it is turned
  /// on; a model's from si-bake --root-motion) and the crowd moves every character by it; off,
  /// the clips in place. kUnsupported when no clip carries root motion.
  si::Status toggleRootMotion();
  /// Motion vectors on or off: each frame the crowd is drawn once more, with motion vectors,
  /// into an offscreen colour + motion target the size of the viewport, whose motion is
  /// summarized (motionSummary()). The instanced paths only (the others draw none).
  /// (Not with impostors: they draw no motion vectors.)
  void toggleMotionVectors() {
    if (!options_.impostors) options_.motion_vectors = !options_.motion_vectors;
  }
  /// Cascaded shadows on or off: three CrowdViews of the crowd drawn depth-only from the sun
  /// into a shadow map each frame, and a ground plane that receives their shadows.
  void toggleShadows() { options_.shadows = !options_.shadows; }
  bool shadows() const { return options_.shadows; }
  /// Characters the shadow cascades drew in the last frame (0 when off).
  uint32_t shadowCasters() const { return options_.shadows ? shadows_.drawn() : 0; }
  /// Layered animation on or off: every other character of the main crowd fades in (0.5 s)
  /// SceneOptions::layer_clip on the branch of SceneOptions::layer_root over its own clip,
  /// or fades it out. kNotFound naming the clip or joint the character lacks.
  si::Status toggleLayers();
  /// Props on/off: every other character holds the staff (demo_props.cpp).
  si::Status toggleProps();
  /// Blend space on/off: every other character walks and runs by a speed drifting over time
  /// (demo_blend.cpp); off, they crossfade back to the walk.
  si::Status toggleBlend();
  /// Live poses on/off: the characters nearest the camera (up to kLookers, within 12 m) turn
  /// their heads to it, and every two seconds one of them falls flat and gets back up, all
  /// drawn in the crowd's batches (demo_live.cpp); off, they hand back to their clips. The
  /// baseline paths (traditional, cpu-skinned) draw no live poses: turned off there.
  si::Status toggleLive();
  bool live() const { return options_.live; }
  /// Characters looking at the camera, and falling, in the last frame.
  uint32_t looking() const { return options_.live ? looking_count_ : 0; }
  uint32_t falling() const { return options_.live ? uint32_t(falls_.size()) : 0; }
  /// The size of the framebuffer frames are drawn to (the motion target's).
  void setViewportSize(uint32_t width, uint32_t height) {
    viewport_width_ = width;
    viewport_height_ = height;
  }

  DrawPath path() const { return path_; }
  const si::CrowdManager& crowd() const { return crowd_; }
  const si::Character& character() const { return character_; }
  const si::BakedPalette& palette() const { return palette_; }
  const si::InstanceBatcher& batcher() const { return batcher_; }
  const si::Renderer& renderer() const { return renderer_; }
  uint32_t instanceCount() const { return options_.instances; }
  float lodScale() const { return lod_scale_; }
  bool mixed() const { return mixed_; }
  bool events() const { return options_.events; }
  bool rootMotion() const { return options_.root_motion; }
  bool motionVectors() const { return options_.motion_vectors; }
  bool layers() const { return options_.layers; }
  /// Characters playing the overlay (0 when layers are off).
  uint32_t overlays() const { return overlays_; }
  bool props() const { return options_.props; }
  bool blend() const { return options_.blend; }
  /// Characters blending the walk and the run (0 when the blend is off).
  uint32_t blending() const { return blending_; }
  /// Characters holding the staff (0 when props are off).
  uint32_t propsHeld() const { return props_; }
  /// The last frame's motion (drawn_pixels 0 when off or on a path without motion vectors).
  const si::MotionSummary& motionSummary() const { return motion_summary_; }
  /// Mean distance of the main crowd's characters from where the layout put them.
  double meanTravel() const;
  /// Events reported by the main crowd's last update, and since events were turned on.
  uint32_t lastFrameEvents() const { return last_events_; }
  uint64_t eventsSinceOn() const { return events_since_on_; }
  /// The other kinds drawn now (0 unless mixed) and their visible instances.
  size_t otherKinds() const { return mixed_ ? cast_.size() : 0; }
  uint32_t otherKindsVisible() const { return mixed_ ? cast_.visible() : 0; }
  bool lodTint() const { return lod_tint_; }
  double bakeMs() const { return bake_ms_; }
  /// CPU time of the last frame's CrowdManager::update().
  double updateMs() const { return update_ms_; }
  /// The camera's default view of the field (at the edge, 9 m up, looking in).
  si::Camera overviewCamera(float aspect) const;
  /// At head height within the field's first rows, facing their faces (SceneOptions::close_up).
  si::Camera closeUpCamera(float aspect) const;
  /// The field's centre and half extent in model units.
  glm::dvec3 fieldCenter() const;
  double fieldHalfExtent() const;
  double unit() const { return unit_; }

 private:
  si::Status buildImpostor(const si::GlInfo& info, si::CharacterId id);
  si::Status bake();
  si::Status buildCrowd();
  void printSummary() const;

  SceneOptions options_;
  si::Character character_;
  si::BakedPalette palette_;
  si::BakeReport report_;
  bool report_valid_ = false;
  double bake_ms_ = 0.0, update_ms_ = 0.0;
  double unit_ = 1.0;
  // With --impostors: the crowd's errors per level (si::impostorLodErrorsUnits).
  std::vector<float> impostor_errors_units_;
  si::Renderer renderer_;
  si::CrowdManager crowd_;
  si::InstanceBatcher batcher_;
  std::vector<si::InstanceHandle> handles_;
  std::vector<glm::u8vec4> colors_;
  std::vector<glm::dvec3> starts_;  // Where the layout put each of handles_.
  DrawPath path_ = DrawPath::kInstanced;
  float lod_scale_ = 1.0f;
  bool lod_tint_ = false, restore_colors_ = false;
  bool gl_ready_ = false;
  si::Status addEventMarkers();
  /// Plays (layers on) or stops (off) the overlays over `blend_seconds` (demo_layers.cpp).
  si::Status applyLayers(double blend_seconds);
  /// Attaches the staff to the embedded character (before baking), and shows (props on) or
  /// hides it on every other character (demo_props.cpp).
  si::Status attachStaff();
  si::Status applyProps();
  static constexpr uint32_t kNoStaff = 0xFFFFFFFFu;
  uint32_t staff_bit_ = kNoStaff;
  uint32_t props_ = 0;
  /// Starts (blend on) or ends (off) the blends over `blend_seconds`, moves them each frame
  /// (demo_blend.cpp).
  si::Status applyBlend(double blend_seconds);
  si::Status moveBlends();
  float blendParameter(size_t i) const;
  uint32_t blending_ = 0;
  uint32_t overlays_ = 0;
  /// Starts (live on) or ends (off) the live poses; sets them each frame between the crowd's
  /// advance and its selection (demo_live.cpp).
  si::Status applyLive();
  si::Status poseLive(const si::Camera& camera);
  si::Status setLive(size_t i, const std::vector<glm::dmat4>& skinning);
  static constexpr uint32_t kLookers = 24;
  struct Fall {
    size_t index;                  // Into handles_.
    double start;                  // Crowd clock of the trip.
    std::vector<glm::dmat4> pose;  // Its skinning matrices at the trip.
  };
  si::LookAt look_;
  std::vector<uint8_t> looking_, falling_;  // Per handles_ entry.
  std::vector<Fall> falls_;
  std::vector<glm::mat4> live_slots_;
  double next_fall_ = 0.0;
  uint32_t falls_started_ = 0, looking_count_ = 0;
  /// The embedded character's travelling clips, added and baked (then re-uploaded).
  si::Status addTravellingClips();

  /// Draws the crowd into motion_target_ with motion vectors and summarizes them.
  si::Status measureMotion(const si::Camera& camera);
  si::MotionTarget motion_target_;
  CascadedShadows shadows_;
  si::MotionSummary motion_summary_;
  uint32_t viewport_width_ = 0, viewport_height_ = 0;

  DemoCast cast_;
  bool mixed_ = false;
  uint32_t last_events_ = 0;
  uint64_t events_since_on_ = 0;
};

}  // namespace demo
