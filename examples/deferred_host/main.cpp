// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// deferred_host: the crowd in a deferred renderer of the host's. The crowd is drawn through a
// G-buffer material (gbuffer.h) into the host's three targets beside the host's own ground;
// near characters are meshes, far ones the impostors of their atlas; then the host's lighting
// pass (lighting.h) lights every pixel by many point lights from the G-buffer alone, so meshes
// and impostors are lit by the same code. Writes the frame as a PNG and checks that meshes and
// impostors both reached the G-buffer and both are lit.
// Usage: deferred_host [--size WxH] [--instances N] [--lights N] [--backend NAME]
//                      [--out FILE.png]; exit 1 naming what failed.
#include <glad/gl.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>
#include <vector>

#include "common/example_options.h"
#include "common/field_crowd.h"
#include "deferred_host/gbuffer.h"
#include "deferred_host/lighting.h"
#include "si/bake/animation_baker.h"
#include "si/core/default_character.h"
#include "si/core/impostor_level.h"
#include "si/crowd/crowd_manager.h"
#include "si/crowd/instance_batcher.h"
#include "si/gl/renderer.h"
#include "si/headless/headless_context.h"

namespace {

struct Options {
  uint32_t width = 960, height = 540, instances = 1600, lights = 96;
  si::HeadlessBackend backend = si::HeadlessBackend::kAuto;
  std::string out = "deferred_host.png";
};

int fail(const std::string& what, const si::Status& s = si::Status::ok()) {
  std::fprintf(stderr, "deferred_host: %s%s%s\n", what.c_str(), s.isOk() ? "" : ": ",
               s.isOk() ? "" : s.toString().c_str());
  return 1;
}

bool parse(int argc, char** argv, Options* o) {
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    const bool has = i + 1 < argc;
    if (a == "--size" && has) {
      if (std::sscanf(argv[++i], "%ux%u", &o->width, &o->height) != 2 || o->width == 0 ||
          o->height == 0)
        return false;
    } else if (a == "--instances" && has) {
      o->instances = uint32_t(std::strtoul(argv[++i], nullptr, 10));
    } else if (a == "--lights" && has) {
      o->lights = uint32_t(std::strtoul(argv[++i], nullptr, 10));
      if (o->lights > deferred::LightingPass::kMaxLights) return false;
    } else if (a == "--backend" && has) {
      if (!si::examples::parseBackend(argv[++i], &o->backend)) return false;
    } else if (a == "--out" && has) {
      o->out = argv[++i];
    } else {
      return false;
    }
  }
  return o->instances > 0;
}

// `n` point lights over the field at head height, their hues round the colour wheel.
std::vector<deferred::PointLight> lightsOver(uint32_t n, float half_side) {
  std::vector<deferred::PointLight> lights;
  const uint32_t side = uint32_t(std::ceil(std::sqrt(double(n))));
  for (uint32_t i = 0; i < n; ++i) {
    deferred::PointLight l;
    const double step = 2.0 * half_side / side;
    l.position = glm::dvec3(-half_side + step * ((i % side) + 0.5 + 0.3 * std::sin(i * 1.7)),
                            1.2 + 0.8 * ((i * 7) % 5) / 4.0,
                            -half_side + step * ((i / side) + 0.5 + 0.3 * std::cos(i * 2.3)));
    l.radius = float(step) * 1.4f;
    const float hue = float(i) * 0.618034f * 6.2831853f;
    l.colour = 9.0f * glm::vec3(0.6f + 0.4f * std::cos(hue), 0.6f + 0.4f * std::cos(hue - 2.094f),
                                0.6f + 0.4f * std::cos(hue + 2.094f));
    lights.push_back(l);
  }
  return lights;
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  if (!parse(argc, argv, &o)) {
    std::fprintf(stderr,
                 "usage: deferred_host [--size WxH] [--instances N] [--lights N (at most %u)] "
                 "[--backend auto|egl-device|egl-surfaceless|osmesa] [--out FILE.png]\n",
                 deferred::LightingPass::kMaxLights);
    return 1;
  }
  si::HeadlessDesc hd;
  hd.width = o.width;
  hd.height = o.height;
  hd.backend = o.backend;
  std::unique_ptr<si::HeadlessContext> context;
  si::Status s = si::HeadlessContext::create(hd, &context);
  if (!s.isOk()) return fail("offscreen context", s);
  si::GlInfo info;
  s = si::loadGl(&si::HeadlessContext::getProcAddress, context.get(), &info);
  if (!s.isOk()) return fail("GL", s);

  // The embedded character with an impostor level past its three mesh levels.
  si::Character character;
  s = si::makeDefaultCharacter({}, &character);
  si::BakedPalette palette;
  if (s.isOk()) s = si::bakePalette(character, {}, &palette, nullptr);
  if (s.isOk()) s = si::appendImpostorLevel(&character.mesh);
  if (!s.isOk()) return fail("the character", s);
  const uint32_t levels = uint32_t(character.mesh.maxLodCount());  // 3 mesh levels, 1 impostor.
  if (levels != 4) return fail("the embedded character's levels changed");

  si::Renderer renderer;
  si::RendererDesc rd;
  rd.skinning_path = si::SkinningPath::kVertexShader;
  s = renderer.init(info, rd);
  si::CharacterId id;
  if (s.isOk()) s = renderer.addCharacter(character, palette, &id);
  si::MaterialId gbuffer_material;
  if (s.isOk()) s = renderer.addMaterial(deferred::GBuffer::material(), &gbuffer_material);
  if (s.isOk()) s = renderer.setMaterial(id, gbuffer_material);
  si::ImpostorDesc atlas;
  atlas.elevations_degrees = {0.0f, 30.0f};
  if (s.isOk()) s = renderer.buildImpostor(id, atlas);
  if (!s.isOk()) return fail("the renderer", s);

  si::CrowdManager crowd;
  si::CrowdDesc cd;
  cd.palette = &palette;
  cd.sub_mesh_count = uint32_t(character.mesh.sub_meshes.size());
  cd.lod_count = levels;
  cd.impostor_lod = levels - 1;
  // Mesh levels at 5 and 10 radii, impostors from 20 on (under about 20 pixels tall here: the
  // default atlas's 32-texel cells stay sharp).
  cd.lod_distances_radii = {5.0f, 10.0f, 20.0f};
  cd.max_distance_radii = -1.0f;
  float half_side = 0.0f;
  s = crowd.init(cd);
  if (s.isOk()) s = si::examples::populateField(o.instances, palette, &crowd, &half_side);
  if (!s.isOk()) return fail("the crowd", s);
  const si::Camera camera =
      si::Camera::lookAt({0.0, 0.3 * half_side, 1.05 * half_side}, {0.0, 0.5, 0.3 * half_side},
                         {0, 1, 0}, 0.8f, float(o.width) / float(o.height), 0.3f, 4.0f * half_side);
  const std::vector<deferred::PointLight> lights = lightsOver(o.lights, half_side);

  deferred::GBuffer gbuffer;
  deferred::LightingPass lighting;
  s = gbuffer.init(o.width, o.height);
  if (s.isOk()) s = lighting.init();
  si::InstanceBatcher batcher;
  if (s.isOk()) s = batcher.init(renderer.batchLimits());
  if (s.isOk()) s = crowd.update(0.5, camera);
  si::DrawStats stats;
  if (s.isOk()) {
    gbuffer.bindAndClear();
    gbuffer.drawGround(camera, half_side);
    s = renderer.drawCrowd(si::CharacterId{}, crowd.view(), batcher, camera,
                           &stats);  // Into the host's G-buffer.
  }
  if (s.isOk()) {
    glBindFramebuffer(GL_FRAMEBUFFER, context->framebuffer());
    glViewport(0, 0, GLsizei(o.width), GLsizei(o.height));
    lighting.draw(gbuffer, camera, lights);
  }
  if (!s.isOk()) return fail("the frame", s);

  // Which pixels are meshes and which impostors (the G-buffer's kind), and how lit each is.
  std::vector<glm::vec4> kinds(size_t(o.width) * o.height);
  glGetTextureImage(gbuffer.texture(1), 0, GL_RGBA, GL_FLOAT, GLsizei(kinds.size() * 16),
                    kinds.data());
  std::vector<uint8_t> rgba;
  s = context->readPixels(&rgba);  // Rows top to bottom.
  if (!s.isOk()) return fail("reading the frame", s);
  size_t pixels[2] = {0, 0};
  double lit[2] = {0.0, 0.0};
  for (uint32_t y = 0; y < o.height; ++y)
    for (uint32_t x = 0; x < o.width; ++x) {
      const float kind = kinds[size_t(y) * o.width + x].a;
      if (kind != 0.5f && kind != 1.0f) continue;
      const int k = kind == 1.0f ? 0 : 1;
      const uint8_t* p = &rgba[(size_t(o.height - 1 - y) * o.width + x) * 4];
      ++pixels[k];
      lit[k] += (0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2]) / 255.0;
    }
  const uint32_t impostors = crowd.view().stats().per_lod[levels - 1];
  const uint32_t meshes = crowd.view().stats().visible - impostors;
  std::printf(
      "deferred: %u meshes, %u impostors, %zu lights; mesh pixels %zu lit %.3f, impostor "
      "pixels %zu lit %.3f\n",
      meshes, impostors, lights.size(), pixels[0], pixels[0] ? lit[0] / pixels[0] : 0.0, pixels[1],
      pixels[1] ? lit[1] / pixels[1] : 0.0);
  s = si::writePng(o.out, o.width, o.height, rgba);
  gbuffer.release();
  lighting.release();
  renderer.shutdown();
  if (!s.isOk()) return fail("writing " + o.out, s);
  if (meshes == 0 || impostors == 0) return fail("the view holds no meshes or no impostors");
  if (pixels[0] == 0 || pixels[1] == 0)
    return fail("meshes or impostors did not reach the G-buffer");
  if (lit[0] / pixels[0] < 0.05 || lit[1] / pixels[1] < 0.05)
    return fail("meshes or impostors are not lit");
  return 0;
}
