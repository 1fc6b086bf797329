// A game runtime on SkinnedInstancing: it links si::core, si::crowd and si::gl only (no baker,
// no meshoptimizer, no headless layer), makes its own EGL context and framebuffer and loads its
// own glad, reads the palette file with its own file code, parses it with si::loadPalette and
// draws the consumer's crowd. The image must equal the one si_consumer drew with the palette it
// baked (both files are in the folder given as the argument).
#include <glad/gl.h>

#include <EGL/egl.h>
#include <EGL/eglext.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "scene.h"
#include "si/core/default_character.h"
#include "si/core/palette_file.h"
#include "si/crowd/crowd_manager.h"
#include "si/gl/gl_context.h"
#include "si/gl/renderer.h"

namespace {

using consumer::kSize;

int fail(const std::string& what) {
  std::fprintf(stderr, "runtime consumer: %s\n", what.c_str());
  return 1;
}

std::vector<uint8_t> readFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::vector<uint8_t>(std::istreambuf_iterator<char>(in), {});
}

void* eglProc(void*, const char* name) {
  return reinterpret_cast<void*>(eglGetProcAddress(name));
}
GLADapiproc engineLoad(void*, const char* name) { return eglGetProcAddress(name); }

// The runtime's own offscreen context: Mesa's surfaceless EGL platform, GL 4.5 core.
std::string makeContext() {
  auto get_display = reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(
      eglGetProcAddress("eglGetPlatformDisplayEXT"));
  if (get_display == nullptr) return "no eglGetPlatformDisplayEXT";
  EGLDisplay display = get_display(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
  EGLint major = 0, minor = 0;
  if (display == EGL_NO_DISPLAY || !eglInitialize(display, &major, &minor))
    return "no surfaceless EGL display";
  // Drawing into its own framebuffer, the runtime needs no surface: no config at all where the
  // display allows it (EGL_KHR_no_config_context), else a pbuffer one.
  const char* extensions = eglQueryString(display, EGL_EXTENSIONS);
  EGLConfig config = EGL_NO_CONFIG_KHR;
  if (extensions == nullptr || std::strstr(extensions, "EGL_KHR_no_config_context") == nullptr) {
    const EGLint config_attributes[] = {EGL_SURFACE_TYPE, EGL_PBUFFER_BIT, EGL_RENDERABLE_TYPE,
                                        EGL_OPENGL_BIT, EGL_NONE};
    EGLint configs = 0;
    if (!eglChooseConfig(display, config_attributes, &config, 1, &configs) || configs == 0)
      return "no EGL config for OpenGL";
  }
  if (!eglBindAPI(EGL_OPENGL_API)) return "no OpenGL API in EGL";
  const EGLint context_attributes[] = {EGL_CONTEXT_MAJOR_VERSION, 4, EGL_CONTEXT_MINOR_VERSION, 5,
                                       EGL_CONTEXT_OPENGL_PROFILE_MASK,
                                       EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT, EGL_NONE};
  EGLContext context = eglCreateContext(display, config, EGL_NO_CONTEXT, context_attributes);
  if (context == EGL_NO_CONTEXT || !eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, context))
    return "no GL 4.5 core context";
  return "";
}

}  // namespace

int main(int argc, char** argv) {
  const std::string dir = argc > 1 ? argv[1] : ".";
  const std::string made = makeContext();
  if (!made.empty()) {
    if (std::getenv("SI_REQUIRE_GL") != nullptr) return fail(made);
    std::printf("runtime consumer: %s, skipped\n", made.c_str());
    return 0;
  }
  if (gladLoadGLUserPtr(&engineLoad, nullptr) == 0) return fail("the runtime's glad failed");
  GLuint framebuffer = 0, targets[2] = {0, 0};
  glCreateRenderbuffers(2, targets);
  glNamedRenderbufferStorage(targets[0], GL_RGBA8, kSize, kSize);
  glNamedRenderbufferStorage(targets[1], GL_DEPTH_COMPONENT24, kSize, kSize);
  glCreateFramebuffers(1, &framebuffer);
  glNamedFramebufferRenderbuffer(framebuffer, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, targets[0]);
  glNamedFramebufferRenderbuffer(framebuffer, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, targets[1]);
  glBindFramebuffer(GL_FRAMEBUFFER, framebuffer);
  glViewport(0, 0, kSize, kSize);

  // The palette, from the bytes the runtime read itself.
  const std::vector<uint8_t> bytes = readFile(dir + "/consumer.sipal");
  si::BakedPalette palette;
  si::Status s = si::loadPalette(bytes, &palette);
  si::Character character;
  if (s.isOk()) s = si::makeDefaultCharacter({}, &character);
  si::CrowdManager crowd;
  si::Camera camera;
  if (s.isOk()) s = consumer::makeCrowd(palette, &crowd, &camera);
  si::GlInfo info;
  if (s.isOk()) s = si::loadGl(&eglProc, nullptr, &info);
  si::Renderer renderer;
  si::RendererDesc rd;
  rd.skinning_path = si::SkinningPath::kVertexShader;
  if (s.isOk()) s = renderer.init(info, rd);
  si::CharacterId id;
  if (s.isOk()) s = renderer.addCharacter(character, palette, &id);
  si::InstanceBatcher batcher;
  if (s.isOk()) s = batcher.init(renderer.batchLimits());
  renderer.clear(glm::vec4(consumer::kClear[0], consumer::kClear[1], consumer::kClear[2], 1.0f));
  if (s.isOk()) s = renderer.drawCrowd(id, crowd.view(), batcher, camera, nullptr);
  if (!s.isOk()) return fail(s.toString());

  // The consumer's image is top row first (HeadlessContext::readPixels).
  std::vector<uint8_t> image(size_t(kSize) * kSize * 4);
  glReadPixels(0, 0, kSize, kSize, GL_RGBA, GL_UNSIGNED_BYTE, image.data());
  const std::vector<uint8_t> expected = readFile(dir + "/consumer_image.rgba");
  if (expected.size() != image.size()) return fail("no image of the consumer to compare with");
  size_t differing = 0;
  const size_t row = size_t(kSize) * 4;
  for (size_t y = 0; y < kSize; ++y)
    for (size_t x = 0; x < row; x += 4) {
      const uint8_t* a = &image[(kSize - 1 - y) * row + x];
      const uint8_t* b = &expected[y * row + x];
      int m = 0;
      for (int ch = 0; ch < 3; ++ch) m = std::max(m, std::abs(int(a[ch]) - int(b[ch])));
      differing += m > 2;
    }
  std::printf("runtime consumer: palette file of %zu bytes loaded by si::core, %zu of %u pixels "
              "differ from the consumer's image\n",
              bytes.size(), differing, kSize * kSize);
  return differing == 0 ? 0 : fail("the runtime's image differs from the consumer's");
}
