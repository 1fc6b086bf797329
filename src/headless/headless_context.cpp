// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// Offscreen GL contexts through EGL (device, then surfaceless platform) and OSMesa. The few GL
// calls needed for the framebuffer are loaded here through the context's own get-proc-address,
// so this layer uses no other si target.
#include "si/headless/headless_context.h"

#include <cstring>

#include <GL/gl.h>
#include <GL/glext.h>
#if SI_HEADLESS_EGL
#include <EGL/egl.h>
#include <EGL/eglext.h>
#endif
#if SI_HEADLESS_OSMESA
#include <GL/osmesa.h>
#endif

#include "core/str_cat.h"

namespace si {
using detail::strCat;

const char* headlessBackendName(HeadlessBackend backend) {
  switch (backend) {
    case HeadlessBackend::kAuto: return "auto";
    case HeadlessBackend::kEglDevice: return "egl-device";
    case HeadlessBackend::kEglSurfaceless: return "egl-surfaceless";
    case HeadlessBackend::kOsMesa: return "osmesa";
  }
  return "invalid";
}

HeadlessDesc resolveDefaults(const HeadlessDesc& desc) {
  HeadlessDesc d = desc;
  if (d.width == 0) d.width = 256;
  if (d.height == 0) d.height = 256;
  return d;
}

namespace {

// GL 1.x entry points have no PFN typedefs in glext.h.
using PFNGLGETERRORPROC = GLenum(APIENTRYP)(void);
using PFNGLGETSTRINGPROC = const GLubyte*(APIENTRYP)(GLenum);
using PFNGLREADPIXELSPROC = void(APIENTRYP)(GLint, GLint, GLsizei, GLsizei, GLenum, GLenum, void*);
using PFNGLPIXELSTOREIPROC = void(APIENTRYP)(GLenum, GLint);
using PFNGLVIEWPORTPROC = void(APIENTRYP)(GLint, GLint, GLsizei, GLsizei);
using PFNGLFINISHPROC = void(APIENTRYP)(void);

// The GL entry points this file uses, loaded per context.
struct GlFns {
  PFNGLGETERRORPROC GetError = nullptr;
  PFNGLGETSTRINGPROC GetString = nullptr;
  PFNGLGENFRAMEBUFFERSPROC GenFramebuffers = nullptr;
  PFNGLDELETEFRAMEBUFFERSPROC DeleteFramebuffers = nullptr;
  PFNGLBINDFRAMEBUFFERPROC BindFramebuffer = nullptr;
  PFNGLGENRENDERBUFFERSPROC GenRenderbuffers = nullptr;
  PFNGLDELETERENDERBUFFERSPROC DeleteRenderbuffers = nullptr;
  PFNGLBINDRENDERBUFFERPROC BindRenderbuffer = nullptr;
  PFNGLRENDERBUFFERSTORAGEMULTISAMPLEPROC RenderbufferStorageMultisample = nullptr;
  PFNGLFRAMEBUFFERRENDERBUFFERPROC FramebufferRenderbuffer = nullptr;
  PFNGLCHECKFRAMEBUFFERSTATUSPROC CheckFramebufferStatus = nullptr;
  PFNGLBLITFRAMEBUFFERPROC BlitFramebuffer = nullptr;
  PFNGLREADPIXELSPROC ReadPixels = nullptr;
  PFNGLPIXELSTOREIPROC PixelStorei = nullptr;
  PFNGLVIEWPORTPROC Viewport = nullptr;
  PFNGLFINISHPROC Finish = nullptr;
};

template <typename F>
bool loadFn(const HeadlessContext* ctx, const char* name, F* fn) {
  *fn = reinterpret_cast<F>(HeadlessContext::getProcAddress(const_cast<HeadlessContext*>(ctx),
                                                            name));
  return *fn != nullptr;
}

bool loadFns(const HeadlessContext* c, GlFns* f) {
  return loadFn(c, "glGetError", &f->GetError) && loadFn(c, "glGetString", &f->GetString) &&
         loadFn(c, "glGenFramebuffers", &f->GenFramebuffers) &&
         loadFn(c, "glDeleteFramebuffers", &f->DeleteFramebuffers) &&
         loadFn(c, "glBindFramebuffer", &f->BindFramebuffer) &&
         loadFn(c, "glGenRenderbuffers", &f->GenRenderbuffers) &&
         loadFn(c, "glDeleteRenderbuffers", &f->DeleteRenderbuffers) &&
         loadFn(c, "glBindRenderbuffer", &f->BindRenderbuffer) &&
         loadFn(c, "glRenderbufferStorageMultisample", &f->RenderbufferStorageMultisample) &&
         loadFn(c, "glFramebufferRenderbuffer", &f->FramebufferRenderbuffer) &&
         loadFn(c, "glCheckFramebufferStatus", &f->CheckFramebufferStatus) &&
         loadFn(c, "glBlitFramebuffer", &f->BlitFramebuffer) &&
         loadFn(c, "glReadPixels", &f->ReadPixels) && loadFn(c, "glPixelStorei", &f->PixelStorei) &&
         loadFn(c, "glViewport", &f->Viewport) && loadFn(c, "glFinish", &f->Finish);
}

#if SI_HEADLESS_EGL
// ------------------------------------------------------------------------------------------
class EglContext final : public HeadlessContext {
 public:
  // The display is left initialized: eglGetPlatformDisplay returns one display per platform
  // and device for the whole process, so terminating it here would pull it from under any
  // other context on it (and unload the driver while it still owns memory).
  ~EglContext() override {
    if (display_ != EGL_NO_DISPLAY && context_ != EGL_NO_CONTEXT) {
      bindApi();  // The current context and its release are per client API.
      if (eglGetCurrentContext() == context_) destroyFramebuffer();
      eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
      eglDestroyContext(display_, context_);
    }
  }

  // Tries `platform`; on failure returns why (the object is then destroyed by the caller).
  Status init(HeadlessBackend platform, bool es) {
    backend_ = platform;
    es_ = es;
    const char* client_ext = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
    if (client_ext == nullptr) return {StatusCode::kBackend, "EGL client extensions unavailable"};
    auto get_platform_display = reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(
        eglGetProcAddress("eglGetPlatformDisplayEXT"));
    if (get_platform_display == nullptr)
      return {StatusCode::kBackend, "eglGetPlatformDisplayEXT is missing"};
    if (platform == HeadlessBackend::kEglSurfaceless) {
      if (std::strstr(client_ext, "EGL_MESA_platform_surfaceless") == nullptr)
        return {StatusCode::kBackend, "EGL_MESA_platform_surfaceless is not supported"};
      display_ = get_platform_display(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
      return initDisplay();
    }
    if (std::strstr(client_ext, "EGL_EXT_platform_device") == nullptr)
      return {StatusCode::kBackend, "EGL_EXT_platform_device is not supported"};
    auto query_devices =
        reinterpret_cast<PFNEGLQUERYDEVICESEXTPROC>(eglGetProcAddress("eglQueryDevicesEXT"));
    if (query_devices == nullptr) return {StatusCode::kBackend, "eglQueryDevicesEXT is missing"};
    EGLDeviceEXT devices[16];
    EGLint count = 0;
    if (!query_devices(16, devices, &count) || count <= 0)
      return {StatusCode::kBackend, "eglQueryDevicesEXT found no device"};
    std::string errors;
    for (EGLint i = 0; i < count; ++i) {
      display_ = get_platform_display(EGL_PLATFORM_DEVICE_EXT, devices[i], nullptr);
      Status s = initDisplay();
      if (s.isOk()) return s;
      errors += strCat(i ? "; " : "", "device ", i, ": ", s.message());
      display_ = EGL_NO_DISPLAY;
    }
    return {StatusCode::kBackend, errors};
  }

  Status makeContextCurrent() override {
    bindApi();
    if (!eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, context_))
      return {StatusCode::kBackend, strCat("eglMakeCurrent failed: 0x", std::hex, eglGetError())};
    return Status::ok();
  }
  HeadlessBackend backend() const override { return backend_; }

 protected:
  void* procAddress(const char* name) const override {
    return reinterpret_cast<void*>(eglGetProcAddress(name));
  }

 private:
  Status initDisplay() {
    if (display_ == EGL_NO_DISPLAY) return {StatusCode::kBackend, "no EGL display"};
    EGLint major = 0, minor = 0;
    if (!eglInitialize(display_, &major, &minor))
      return {StatusCode::kBackend, strCat("eglInitialize failed: 0x", std::hex, eglGetError())};
    const char* ext = eglQueryString(display_, EGL_EXTENSIONS);
    if (ext == nullptr || std::strstr(ext, "EGL_KHR_surfaceless_context") == nullptr)
      return {StatusCode::kBackend, "EGL_KHR_surfaceless_context is not supported"};
    if (!bindApi())
      return {StatusCode::kBackend,
              es_ ? "eglBindAPI(EGL_OPENGL_ES_API) failed" : "eglBindAPI(EGL_OPENGL_API) failed"};
    EGLConfig config = nullptr;
    const EGLint config_attribs[] = {EGL_SURFACE_TYPE, EGL_PBUFFER_BIT, EGL_RENDERABLE_TYPE,
                                     es_ ? EGL_OPENGL_ES3_BIT : EGL_OPENGL_BIT, EGL_NONE};
    EGLint configs = 0;
    if (!eglChooseConfig(display_, config_attribs, &config, 1, &configs) || configs == 0) {
      // Surfaceless displays may expose no pbuffer config; fall back to no config.
      if (std::strstr(ext, "EGL_KHR_no_config_context") == nullptr)
        return {StatusCode::kBackend,
                es_ ? "no EGL config for OpenGL ES 3" : "no EGL config for desktop OpenGL"};
      config = nullptr;
    }
    const EGLint desktop_attribs[] = {EGL_CONTEXT_MAJOR_VERSION,
                                      4,
                                      EGL_CONTEXT_MINOR_VERSION,
                                      5,
                                      EGL_CONTEXT_OPENGL_PROFILE_MASK,
                                      EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
                                      EGL_NONE};
    // ES 3.0 or any later version compatible with it (Mesa gives 3.2).
    const EGLint es_attribs[] = {EGL_CONTEXT_MAJOR_VERSION, 3, EGL_CONTEXT_MINOR_VERSION, 0,
                                 EGL_NONE};
    context_ =
        eglCreateContext(display_, config, EGL_NO_CONTEXT, es_ ? es_attribs : desktop_attribs);
    if (context_ == EGL_NO_CONTEXT)
      return {StatusCode::kBackend, strCat("eglCreateContext (", es_ ? "ES 3.0" : "4.5 core",
                                           ") failed: 0x", std::hex, eglGetError())};
    return makeContextCurrent();
  }

  bool bindApi() const { return eglBindAPI(es_ ? EGL_OPENGL_ES_API : EGL_OPENGL_API) == EGL_TRUE; }

  HeadlessBackend backend_ = HeadlessBackend::kEglDevice;
  bool es_ = false;
  EGLDisplay display_ = EGL_NO_DISPLAY;
  EGLContext context_ = EGL_NO_CONTEXT;
};

#endif  // SI_HEADLESS_EGL

#if SI_HEADLESS_OSMESA
// ------------------------------------------------------------------------------------------
class OsMesaContext final : public HeadlessContext {
 public:
  ~OsMesaContext() override {
    if (context_ != nullptr) {
      if (OSMesaGetCurrentContext() == context_) destroyFramebuffer();
      OSMesaDestroyContext(context_);
    }
  }
  Status init() {
    const int attribs[] = {OSMESA_FORMAT, OSMESA_RGBA, OSMESA_DEPTH_BITS, 24,
                           OSMESA_PROFILE, OSMESA_CORE_PROFILE,
                           OSMESA_CONTEXT_MAJOR_VERSION, 4, OSMESA_CONTEXT_MINOR_VERSION, 5, 0};
    context_ = OSMesaCreateContextAttribs(attribs, nullptr);
    if (context_ == nullptr)
      return {StatusCode::kBackend, "OSMesaCreateContextAttribs (4.5 core) failed"};
    // OSMesa needs a buffer for its default framebuffer; we draw into our FBO, so 1x1 is enough.
    buffer_.assign(4, 0);
    return makeContextCurrent();
  }
  Status makeContextCurrent() override {
    if (!OSMesaMakeCurrent(context_, buffer_.data(), GL_UNSIGNED_BYTE, 1, 1))
      return {StatusCode::kBackend, "OSMesaMakeCurrent failed"};
    return Status::ok();
  }
  HeadlessBackend backend() const override { return HeadlessBackend::kOsMesa; }

 protected:
  void* procAddress(const char* name) const override {
    return reinterpret_cast<void*>(OSMesaGetProcAddress(name));
  }

 private:
  OSMesaContext context_ = nullptr;
  std::vector<uint8_t> buffer_;
};
#endif  // SI_HEADLESS_OSMESA

}  // namespace

HeadlessContext::~HeadlessContext() = default;

Status HeadlessContext::makeCurrent() {
  Status s = makeContextCurrent();
  if (!s.isOk() || fbo_ == 0) return s;
  GlFns gl;
  if (!loadFns(this, &gl)) return {StatusCode::kBackend, "makeCurrent: GL entry points missing"};
  gl.BindFramebuffer(GL_FRAMEBUFFER, fbo_);
  return Status::ok();
}

void* HeadlessContext::getProcAddress(void* user_data, const char* name) {
  if (user_data == nullptr || name == nullptr) return nullptr;
  return static_cast<const HeadlessContext*>(user_data)->procAddress(name);
}

Status HeadlessContext::createFramebuffer(uint32_t width, uint32_t height, uint32_t samples) {
  GlFns gl;
  if (!loadFns(this, &gl))
    return {StatusCode::kBackend, "a framebuffer entry point is missing from the context"};
  width_ = width;
  height_ = height;
  samples_ = samples;
  const char* renderer = reinterpret_cast<const char*>(gl.GetString(GL_RENDERER));
  renderer_ = renderer ? renderer : "";
  const auto make = [&](uint32_t* fbo, uint32_t* color, uint32_t* depth, GLsizei s) {
    gl.GenFramebuffers(1, fbo);
    gl.BindFramebuffer(GL_FRAMEBUFFER, *fbo);
    gl.GenRenderbuffers(1, color);
    gl.BindRenderbuffer(GL_RENDERBUFFER, *color);
    gl.RenderbufferStorageMultisample(GL_RENDERBUFFER, s, GL_RGBA8, GLsizei(width), GLsizei(height));
    gl.FramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, *color);
    if (depth != nullptr) {
      gl.GenRenderbuffers(1, depth);
      gl.BindRenderbuffer(GL_RENDERBUFFER, *depth);
      gl.RenderbufferStorageMultisample(GL_RENDERBUFFER, s, GL_DEPTH24_STENCIL8, GLsizei(width),
                                        GLsizei(height));
      gl.FramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_STENCIL_ATTACHMENT, GL_RENDERBUFFER,
                                 *depth);
    }
    return gl.CheckFramebufferStatus(GL_FRAMEBUFFER);
  };
  if (samples > 0) {
    const GLenum st = make(&resolve_fbo_, &resolve_rb_, nullptr, 0);
    if (st != GL_FRAMEBUFFER_COMPLETE)
      return {StatusCode::kBackend, strCat("resolve framebuffer incomplete: 0x", std::hex, st)};
  }
  const GLenum status = make(&fbo_, &color_rb_, &depth_rb_, GLsizei(samples));
  if (status != GL_FRAMEBUFFER_COMPLETE)
    return {StatusCode::kBackend, strCat("framebuffer incomplete: 0x", std::hex, status)};
  gl.Viewport(0, 0, GLsizei(width), GLsizei(height));
  const GLenum err = gl.GetError();
  if (err != GL_NO_ERROR)
    return {StatusCode::kBackend, strCat("creating the framebuffer: GL error 0x", std::hex, err)};
  return Status::ok();
}

void HeadlessContext::destroyFramebuffer() {
  GlFns gl;
  if (!loadFns(this, &gl)) return;
  const uint32_t rbs[] = {color_rb_, depth_rb_, resolve_rb_};
  const uint32_t fbos[] = {fbo_, resolve_fbo_};
  gl.DeleteRenderbuffers(3, rbs);
  gl.DeleteFramebuffers(2, fbos);
  fbo_ = color_rb_ = depth_rb_ = resolve_fbo_ = resolve_rb_ = 0;
}

Status HeadlessContext::readPixels(std::vector<uint8_t>* rgba) {
  if (rgba == nullptr) return {StatusCode::kInvalidArgument, "readPixels: rgba is null"};
  GlFns gl;
  if (!loadFns(this, &gl)) return {StatusCode::kBackend, "readPixels: GL entry points missing"};
  uint32_t source = fbo_;
  if (samples_ > 0) {
    gl.BindFramebuffer(GL_READ_FRAMEBUFFER, fbo_);
    gl.BindFramebuffer(GL_DRAW_FRAMEBUFFER, resolve_fbo_);
    gl.BlitFramebuffer(0, 0, GLint(width_), GLint(height_), 0, 0, GLint(width_), GLint(height_),
                       GL_COLOR_BUFFER_BIT, GL_NEAREST);
    source = resolve_fbo_;
  }
  std::vector<uint8_t> pixels(size_t(width_) * height_ * 4);
  gl.BindFramebuffer(GL_READ_FRAMEBUFFER, source);
  gl.PixelStorei(GL_PACK_ALIGNMENT, 1);
  gl.ReadPixels(0, 0, GLsizei(width_), GLsizei(height_), GL_RGBA, GL_UNSIGNED_BYTE, pixels.data());
  gl.BindFramebuffer(GL_FRAMEBUFFER, fbo_);
  const GLenum err = gl.GetError();
  if (err != GL_NO_ERROR)
    return {StatusCode::kBackend, strCat("glReadPixels: GL error 0x", std::hex, err)};
  // GL rows run bottom to top; flip to top to bottom.
  const size_t row = size_t(width_) * 4;
  rgba->resize(pixels.size());
  for (uint32_t y = 0; y < height_; ++y)
    std::memcpy(rgba->data() + y * row, pixels.data() + (height_ - 1 - y) * row, row);
  return Status::ok();
}

Status HeadlessContext::create(const HeadlessDesc& in_desc, std::unique_ptr<HeadlessContext>* out) {
  if (out == nullptr) return {StatusCode::kInvalidArgument, "HeadlessContext::create: out is null"};
  const HeadlessDesc d = resolveDefaults(in_desc);
  if (d.width > 16384 || d.height > 16384)
    return {StatusCode::kInvalidArgument, "HeadlessDesc width and height must be 1 to 16384"};
  if (d.samples > 64) return {StatusCode::kInvalidArgument, "HeadlessDesc.samples must be <= 64"};
  std::vector<HeadlessBackend> order;
  if (d.backend == HeadlessBackend::kAuto)
    order = {HeadlessBackend::kEglDevice, HeadlessBackend::kEglSurfaceless,
             HeadlessBackend::kOsMesa};
  else
    order = {d.backend};
  std::string tried;
  for (HeadlessBackend b : order) {
    std::unique_ptr<HeadlessContext> ctx;
    Status s;
    if (b == HeadlessBackend::kOsMesa && d.es) {
      s = Status(StatusCode::kUnsupported, "OSMesa makes no OpenGL ES contexts");
    } else if (b == HeadlessBackend::kOsMesa) {
#if SI_HEADLESS_OSMESA
      auto c = std::make_unique<OsMesaContext>();
      s = c->init();
      ctx = std::move(c);
#else
      s = Status(StatusCode::kUnsupported, "not built in (SI_HEADLESS has no OSMESA)");
#endif
    } else if (b == HeadlessBackend::kEglDevice || b == HeadlessBackend::kEglSurfaceless) {
#if SI_HEADLESS_EGL
      auto c = std::make_unique<EglContext>();
      s = c->init(b, d.es);
      ctx = std::move(c);
#else
      s = Status(StatusCode::kUnsupported, "not built in (SI_HEADLESS has no EGL)");
#endif
    } else {
      return {StatusCode::kInvalidArgument, "HeadlessDesc.backend is not a known backend"};
    }
    if (s.isOk() && ctx) s = ctx->createFramebuffer(d.width, d.height, d.samples);
    if (s.isOk() && ctx) {
      *out = std::move(ctx);
      return Status::ok();
    }
    tried += strCat(tried.empty() ? "" : "; ", headlessBackendName(b), ": ", s.message());
  }
  return {StatusCode::kBackend,
          strCat(d.es ? "no offscreen OpenGL ES 3 context: " : "no offscreen OpenGL 4.5 context: ",
                 tried)};
}

}  // namespace si
