// Links every layer through the exported targets and runs a little of each.
#include <cstdio>

#include "si/bake/bake_desc.h"
#include "si/core/core.h"
#include "si/crowd/handle_pool.h"
#include "si/gl/gl_context.h"
#include "si/gltf/asset_path.h"
#include "si/headless/headless_context.h"

int main() {
  si::Character c;
  si::Status s = si::makeDefaultCharacter({}, &c);
  si::PalettePlan plan;
  if (s.isOk()) s = si::planPalette(c, {}, &plan);
  si::HandlePool pool;
  si::InstanceHandle h;
  if (s.isOk()) s = pool.allocate(&h);
  std::string path;
  if (s.isOk()) s = si::resolveAssetUri("/a", "b.bin", &path);
  if (!s.isOk()) {
    std::fprintf(stderr, "consumer: %s\n", s.toString().c_str());
    return 1;
  }
  std::printf("consumer ok: %zu joints, palette %ux%u, %s, %s\n", c.skeleton.jointCount(),
              plan.layout.width, plan.layout.height, path.c_str(),
              si::headlessBackendName(si::HeadlessBackend::kAuto));
  return 0;
}
