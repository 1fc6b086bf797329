// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once

/// \file
/// si::headless: an offscreen OpenGL 4.5 core (or OpenGL ES 3) context for tests, examples and
/// servers without a display, through EGL (the device platform, which NVIDIA needs without a
/// display, then Mesa's surfaceless platform) or OSMesa. The context renders into a framebuffer
/// object of the requested size, bound when the context is made current; readPixels() returns
/// it as RGBA8.
///
/// Usage:
/// \code
///   std::unique_ptr<si::HeadlessContext> ctx;
///   si::Status s = si::HeadlessContext::create({}, &ctx);   // kAuto, 256x256
///   if (!s.isOk()) { /* no offscreen GL here: s.message() says what was tried */ }
///   si::GlInfo info;
///   s = si::loadGl(&si::HeadlessContext::getProcAddress, ctx.get(), &info);   // si::gl
///   ... draw ...
///   std::vector<uint8_t> rgba;
///   s = ctx->readPixels(&rgba);
///   s = si::writePng("frame.png", ctx->width(), ctx->height(), rgba);
/// \endcode

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "si/core/span.h"
#include "si/core/status.h"

namespace si {

/// Which offscreen mechanism to use.
enum class HeadlessBackend : uint8_t {
  kAuto = 0,        ///< The first that works of kEglDevice, kEglSurfaceless, kOsMesa.
  kEglDevice,       ///< EGL_EXT_platform_device on the first device that gives a 4.5 context.
  kEglSurfaceless,  ///< EGL_MESA_platform_surfaceless (Mesa).
  kOsMesa,          ///< OSMesa (Mesa's software off-screen library).
};

/// "auto", "egl-device", "egl-surfaceless", "osmesa".
const char* headlessBackendName(HeadlessBackend backend);

/// Options of HeadlessContext::create().
struct HeadlessDesc {
  uint32_t width = 0;   ///< Framebuffer width in pixels; 0 means 256.
  uint32_t height = 0;  ///< Framebuffer height in pixels; 0 means 256.
  HeadlessBackend backend = HeadlessBackend::kAuto;
  uint32_t samples = 0;  ///< MSAA samples of the framebuffer; 0 means none.
  /// An OpenGL ES 3.0 (or later, compatible) context instead of desktop 4.5 core: the
  /// renderer's ES profile (si::GlInfo::es). EGL only: OSMesa is refused (kUnsupported, in
  /// the message of the kBackend failure).
  bool es = false;
};

/// Returns the desc with zeros replaced by their documented defaults.
HeadlessDesc resolveDefaults(const HeadlessDesc& desc);

/// An offscreen GL 4.5 core context with its framebuffer. Move-only through unique_ptr;
/// destroying it releases the context (making it not current first). EGL displays are shared
/// by the whole process (one per platform and device), so they stay initialized until exit.
class HeadlessContext {
 public:
  /// Creates and makes current a context. Fails with kInvalidArgument for a size outside
  /// 1..16384 or a null `out`, and kBackend when no requested mechanism works; the message lists
  /// each mechanism tried and why it failed. `out` is untouched on failure.
  static Status create(const HeadlessDesc& desc, std::unique_ptr<HeadlessContext>* out);
  virtual ~HeadlessContext();

  /// Makes the context current on this thread and binds its framebuffer (draw and read).
  /// kBackend when the platform refuses.
  Status makeCurrent();
  /// The mechanism in use (never kAuto).
  virtual HeadlessBackend backend() const = 0;
  /// A GlGetProcAddress for si::loadGl; `user_data` must be the context.
  static void* getProcAddress(void* user_data, const char* name);
  /// The framebuffer size.
  uint32_t width() const { return width_; }
  uint32_t height() const { return height_; }
  /// GL_RENDERER of the context, e.g. "llvmpipe (LLVM 15.0.6, 256 bits)".
  const std::string& renderer() const { return renderer_; }
  /// Object name of the framebuffer the context draws into (bound by makeCurrent()).
  uint32_t framebuffer() const { return fbo_; }

  /// Reads the framebuffer as RGBA8, rows top to bottom, into `rgba` (resized to
  /// width * height * 4). Resolves MSAA first. Fails with kBackend naming the GL error.
  Status readPixels(std::vector<uint8_t>* rgba);

 protected:
  HeadlessContext() = default;
  virtual void* procAddress(const char* name) const = 0;
  /// Makes the platform context current (makeCurrent() then binds the framebuffer).
  virtual Status makeContextCurrent() = 0;
  Status createFramebuffer(uint32_t width, uint32_t height, uint32_t samples);
  void destroyFramebuffer();

  uint32_t width_ = 0, height_ = 0, samples_ = 0;
  uint32_t fbo_ = 0, color_rb_ = 0, depth_rb_ = 0;
  uint32_t resolve_fbo_ = 0, resolve_rb_ = 0;
  std::string renderer_;
};

/// Writes RGBA8 pixels (rows top to bottom) as a PNG file. Fails with kCountMismatch when `rgba`
/// does not hold width * height * 4 bytes, and kIo naming the path when writing fails.
Status writePng(const std::string& path, uint32_t width, uint32_t height,
                Span<const uint8_t> rgba);

/// Reads a PNG (or any stb_image format) as RGBA8. kIo naming the path on failure.
Status readPng(const std::string& path, uint32_t* width, uint32_t* height,
               std::vector<uint8_t>* rgba);

}  // namespace si
