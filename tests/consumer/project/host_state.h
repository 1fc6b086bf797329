// The engine's side of the guest contract (docs/rendering.md, "A guest in the host's engine"):
// the GL state an engine keeps between its own passes, set to values no default has, and a
// snapshot of all of it to compare before and after each library call. Written against whatever
// `glad/gl.h` the including build provides: the consumer's own glad (an engine's loader) or, in
// the library's render tests, si::gl's.
#pragma once

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace host {

/// Every piece of state the check covers, as (name, value) pairs in a fixed order (indexed
/// bindings per index; float state by its bits).
struct GlSnapshot {
  std::vector<std::pair<std::string, int64_t>> values;
};

/// Reads the snapshot. Queries nothing that the context lacks (indexed bindings up to the
/// context's limits). Appends "snapshot: GL error X" to `errors` when a query failed.
GlSnapshot snapshot(std::vector<std::string>* errors);

/// Names each piece that differs ("GL_CURRENT_PROGRAM 7 -> 0"), comma-separated; "" when none.
/// Pieces whose name starts with `ignore_prefix` (when non-empty) are not compared.
std::string differences(const GlSnapshot& before, const GlSnapshot& after,
                        const std::string& ignore_prefix = "");

/// The engine's objects and its non-default state: a program, a vertex array, buffers bound to
/// every generic and indexed buffer binding, textures of five targets and a sampler on units
/// 0-7 (unit 5 active), image units 0-3, a transform feedback object, two framebuffers (draw
/// and read), a renderbuffer, pixel pack and unpack buffers with non-default pixel store, and
/// non-default enables, depth, colour mask, culling, blending, stencil, viewport, scissor,
/// depth range, clear values, polygon mode, primitive restart and provoking vertex. The draw
/// framebuffer has two colour attachments (RGBA8 and RG16F, both drawn) and a depth
/// attachment, so motion vector draws have somewhere to write. Needs a GL 4.5 context.
class HostState {
 public:
  /// Creates the objects and applies the state. "" or what failed.
  std::string create(uint32_t width, uint32_t height);
  /// Applies the state again (after the host's own drawing changed it).
  void apply() const;
  /// Deletes the objects (context current).
  void release();
  /// The engine's draw framebuffer (bound by apply()).
  uint32_t drawFramebuffer() const { return framebuffers_[0]; }
  /// A 2D array texture of 4 layers, for Renderer::setCustomTextureArray.
  uint32_t customTextureArray() const { return custom_array_; }

 private:
  uint32_t program_ = 0, vertex_array_ = 0, feedback_ = 0, renderbuffer_ = 0;
  uint32_t buffers_[64] = {};
  uint32_t textures_[8][5] = {};
  uint32_t samplers_[8] = {};
  uint32_t images_[4] = {};
  uint32_t framebuffers_[2] = {}, attachments_[4] = {};
  uint32_t custom_array_ = 0;
  uint32_t width_ = 0, height_ = 0;
  int32_t uniform_alignment_ = 256, storage_alignment_ = 256;
};

}  // namespace host
