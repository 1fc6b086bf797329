// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// ogre_host: a SkinnedInstancing crowd drawn inside OGRE 1.12's frame (render system GL3Plus),
// the engine the issue "The engine's look on every path" asks for as a host. OGRE draws its
// scene (a ground, boxes in front of and among the crowd, a box drawn after the crowd in a later
// render queue); a render queue listener (crowd_pass.h) draws the crowd after OGRE's main queue
// with OGRE's camera and a material lit by OGRE's light. Checks, pixel for pixel: OGRE's image
// outside the crowd's pixels is the image of the same frame without the crowd, also where OGRE
// draws after it; the crowd is there and OGRE's boxes in front of it hide some of it (it depth
// tests against OGRE's depth); a frame drawn without the crowd afterwards equals the first.
// Usage: ogre_host [--size WxH] [--out FILE.png]; exit 1 with the failed check named.
// Run under a display, or `xvfb-run -a -s "-screen 0 640x480x24" ogre_host`.
#include <glad/gl.h>

#include <Bites/OgreSGTechniqueResolverListener.h>
#include <Ogre.h>
#include <OgreRTShaderSystem.h>

#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "ogre_host/crowd_pass.h"
#include "si/headless/headless_context.h"

extern "C" void (*glXGetProcAddressARB(const unsigned char* name))();

namespace {

void* getProc(void*, const char* name) {
  return reinterpret_cast<void*>(glXGetProcAddressARB(reinterpret_cast<const unsigned char*>(name)));
}

// A material of OGRE's own: lit, one colour (the RTSS writes its shaders).
Ogre::MaterialPtr colourMaterial(const std::string& name, const Ogre::ColourValue& colour) {
  Ogre::MaterialPtr m = Ogre::MaterialManager::getSingleton().create(
      name, Ogre::ResourceGroupManager::DEFAULT_RESOURCE_GROUP_NAME);
  Ogre::Pass* pass = m->getTechnique(0)->getPass(0);
  pass->setLightingEnabled(true);
  pass->setDiffuse(colour);
  pass->setAmbient(colour * 0.4f);
  return m;
}

Ogre::SceneNode* box(Ogre::SceneManager* scene, const std::string& material,
                     const Ogre::Vector3& at, const Ogre::Vector3& size, uint8_t queue) {
  Ogre::Entity* e = scene->createEntity(Ogre::SceneManager::PT_CUBE);
  e->setMaterialName(material);
  e->setRenderQueueGroup(queue);
  Ogre::SceneNode* node = scene->getRootSceneNode()->createChildSceneNode(at);
  node->setScale(size / 100.0f);  // PT_CUBE is 100 units a side.
  node->attachObject(e);
  return node;
}

// OGRE's window as RGBA8, rows from the bottom.
std::vector<uint8_t> grab(Ogre::RenderWindow* window) {
  const uint32_t w = window->getWidth(), h = window->getHeight();
  std::vector<uint8_t> rgba(size_t(w) * h * 4);
  Ogre::PixelBox box(w, h, 1, Ogre::PF_BYTE_RGBA, rgba.data());
  window->copyContentsToMemory(box, box, Ogre::RenderTarget::FB_AUTO);
  // copyContentsToMemory gives rows from the top: turn them as glReadPixels gives them.
  std::vector<uint8_t> flipped(rgba.size());
  for (uint32_t y = 0; y < h; ++y)
    std::memcpy(&flipped[size_t(h - 1 - y) * w * 4], &rgba[size_t(y) * w * 4], size_t(w) * 4);
  return flipped;
}

size_t differing(const std::vector<uint8_t>& a, const std::vector<uint8_t>& b,
                 const std::vector<uint8_t>& mask, bool inside) {
  size_t n = 0;
  for (size_t p = 0; p < mask.size(); ++p) {
    if ((mask[p] != 0) != inside) continue;
    n += std::memcmp(&a[p * 4], &b[p * 4], 3) != 0;
  }
  return n;
}

int fail(const std::string& what) {
  std::fprintf(stderr, "ogre_host: %s\n", what.c_str());
  return 1;
}

}  // namespace

int main(int argc, char** argv) {
  uint32_t width = 480, height = 320;
  std::string out;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--size" && i + 1 < argc && std::sscanf(argv[i + 1], "%ux%u", &width, &height) == 2)
      ++i;
    else if (a == "--out" && i + 1 < argc) out = argv[++i];
    else return fail("usage: ogre_host [--size WxH] [--out FILE.png]");
  }
  Ogre::LogManager log;
  log.createLog("ogre_host.log", true, false, true);  // OGRE's own log, quiet.
  Ogre::Root root("", "", "");
  root.loadPlugin(std::string(SI_OGRE_PLUGIN_DIR) + "/RenderSystem_GL3Plus");
  Ogre::RenderSystem* gl = root.getRenderSystemByName("OpenGL 3+ Rendering Subsystem");
  if (gl == nullptr) return fail("OGRE's GL3Plus render system did not load");
  root.setRenderSystem(gl);
  root.initialise(false);
  Ogre::NameValuePairList misc;
  misc["hidden"] = "true";
  Ogre::RenderWindow* window = root.createRenderWindow("ogre_host", width, height, false, &misc);
  Ogre::ResourceGroupManager& resources = Ogre::ResourceGroupManager::getSingleton();
  resources.addResourceLocation(std::string(SI_OGRE_MEDIA_DIR) + "/RTShaderLib/GLSL", "FileSystem");
  resources.addResourceLocation(std::string(SI_OGRE_MEDIA_DIR) + "/ShadowVolume", "FileSystem");
  if (!Ogre::RTShader::ShaderGenerator::initialize()) return fail("the RTSS did not start");
  Ogre::RTShader::ShaderGenerator* generator = Ogre::RTShader::ShaderGenerator::getSingletonPtr();
  OgreBites::SGTechniqueResolverListener resolver(generator);
  Ogre::MaterialManager::getSingleton().addListener(&resolver);
  Ogre::SceneManager* scene = root.createSceneManager();
  generator->addSceneManager(scene);
  resources.initialiseAllResourceGroups();

  // OGRE's scene: a ground, a box in front of the crowd, boxes among it, and one drawn after the
  // crowd (a later render queue); a directional light and an ambient colour.
  scene->setAmbientLight(Ogre::ColourValue(0.25f, 0.25f, 0.3f));
  Ogre::Light* sun = scene->createLight("sun");
  sun->setType(Ogre::Light::LT_DIRECTIONAL);
  sun->setDiffuseColour(Ogre::ColourValue(0.9f, 0.85f, 0.75f));
  Ogre::SceneNode* sun_node = scene->getRootSceneNode()->createChildSceneNode();
  sun_node->setDirection(Ogre::Vector3(-0.4f, -1.0f, -0.5f).normalisedCopy(),
                         Ogre::Node::TS_WORLD);
  sun_node->attachObject(sun);
  Ogre::MeshManager::getSingleton().createPlane(
      "ground", Ogre::ResourceGroupManager::DEFAULT_RESOURCE_GROUP_NAME,
      Ogre::Plane(Ogre::Vector3::UNIT_Y, 0.0f), 40.0f, 40.0f, 1, 1, true, 1, 1.0f, 1.0f,
      Ogre::Vector3::UNIT_Z);
  colourMaterial("ground", Ogre::ColourValue(0.45f, 0.5f, 0.42f));
  colourMaterial("front", Ogre::ColourValue(0.8f, 0.3f, 0.2f));
  colourMaterial("among", Ogre::ColourValue(0.2f, 0.4f, 0.8f));
  colourMaterial("after", Ogre::ColourValue(0.85f, 0.8f, 0.2f));
  Ogre::Entity* ground = scene->createEntity("ground");
  ground->setMaterialName("ground");
  scene->getRootSceneNode()->createChildSceneNode()->attachObject(ground);
  box(scene, "front", Ogre::Vector3(-1.2f, 0.6f, -0.4f), Ogre::Vector3(1.2f), Ogre::RENDER_QUEUE_MAIN);
  box(scene, "among", Ogre::Vector3(1.8f, 0.6f, -5.0f), Ogre::Vector3(0.8f, 1.2f, 0.8f),
      Ogre::RENDER_QUEUE_MAIN);
  box(scene, "after", Ogre::Vector3(2.6f, 1.3f, -1.2f), Ogre::Vector3(0.6f), Ogre::RENDER_QUEUE_9);
  Ogre::Camera* camera = scene->createCamera("eye");
  camera->setNearClipDistance(0.1f);
  camera->setFarClipDistance(200.0f);
  camera->setAutoAspectRatio(true);
  Ogre::SceneNode* eye = scene->getRootSceneNode()->createChildSceneNode(Ogre::Vector3(0.5f, 2.2f, 4.5f));
  eye->lookAt(Ogre::Vector3(0.0f, 0.8f, -4.0f), Ogre::Node::TS_WORLD);
  eye->attachObject(camera);
  Ogre::Viewport* viewport = window->addViewport(camera);
  viewport->setBackgroundColour(Ogre::ColourValue(0.55f, 0.65f, 0.8f));
  viewport->setMaterialScheme(Ogre::RTShader::ShaderGenerator::DEFAULT_SCHEME_NAME);

  // The guest: loaded once OGRE's context exists (OGRE keeps it current), drawn by the listener.
  root.renderOneFrame();  // OGRE compiles its shaders on the first frame.
  si::ogre_host::CrowdPass pass;
  si::Status s = pass.init(&getProc, 32);
  if (!s.isOk()) return fail("setting up the crowd: " + s.toString());
  scene->addRenderQueueListener(&pass);

  pass.enable(camera, sun, false);
  root.renderOneFrame();
  const std::vector<uint8_t> without = grab(window);
  pass.enable(camera, sun, true);
  root.renderOneFrame();
  const std::vector<uint8_t> with = grab(window);
  if (!pass.error().isOk()) return fail("drawing the crowd: " + pass.error().toString());
  pass.enable(camera, sun, false);
  root.renderOneFrame();
  const std::vector<uint8_t> after = grab(window);
  std::vector<uint8_t> crowd;
  s = pass.coverage(width, height, &crowd);
  if (!s.isOk()) return fail("the crowd's coverage: " + s.toString());

  size_t covered = 0;
  for (uint8_t c : crowd) covered += c;
  const size_t outside = differing(with, without, crowd, false);
  const size_t shown = differing(with, without, crowd, true);
  const size_t again = differing(after, without, std::vector<uint8_t>(crowd.size(), 0), false);
  std::printf("ogre_host: OGRE %s, %s; crowd of 32 drawn in %u draws (%llu triangles) covering "
              "%zu pixels, %zu of them showing (the rest behind OGRE's boxes); %zu of OGRE's "
              "pixels outside the crowd differ from the frame without it, %zu in the frame after\n",
              OGRE_VERSION_NAME, reinterpret_cast<const char*>(glGetString(GL_RENDERER)),
              pass.stats().draw_calls, static_cast<unsigned long long>(pass.stats().triangles),
              covered, shown, outside, again);
  if (!out.empty()) {
    std::vector<uint8_t> top_down(with.size());
    for (uint32_t y = 0; y < height; ++y)
      std::memcpy(&top_down[size_t(y) * width * 4], &with[size_t(height - 1 - y) * width * 4],
                  size_t(width) * 4);
    for (size_t p = 3; p < top_down.size(); p += 4) top_down[p] = 255;
    s = si::writePng(out, width, height, top_down);
    if (!s.isOk()) return fail("writing " + out + ": " + s.toString());
  }
  pass.shutdown();
  scene->removeRenderQueueListener(&pass);
  // OGRE's own order: the RTSS goes before the root (the resolver listener with it).
  Ogre::MaterialManager::getSingleton().removeListener(&resolver);
  Ogre::RTShader::ShaderGenerator::destroy();
  root.shutdown();
  if (covered < 2000) return fail("the crowd covers too few pixels");
  if (outside != 0) return fail("OGRE's image outside the crowd changed");
  if (covered - shown < 500 || shown < covered / 2)
    return fail("the crowd is not partly hidden by OGRE's boxes (depth test against OGRE's depth)");
  if (again != 0) return fail("the frame after the crowd differs from the frame before");
  std::printf("ogre_host: ok\n");
  return 0;
}
