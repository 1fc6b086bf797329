// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// What the Vulkan render tests share: the OpenGL fixture (for si::gl's reference images), the
// engine-like Vulkan host of the vulkan_host example (skipped, or failed with SI_REQUIRE_VULKAN=1,
// where the machine has no Vulkan 1.3 device), a vk::Renderer with the embedded character uploaded,
// and the LOD rows' crowd.
#include <cstdlib>
#include <sstream>
#include <string>
#include <vector>

#include "render/render_fixture.h"
#include "si/vk/renderer.h"
#include "vulkan_host/headless_vulkan.h"

namespace si::test {

class VulkanRenderFixture : public RenderTest {
 protected:
  // Creates host_; false (the test skipped, or failed under SI_REQUIRE_VULKAN) without a device.
  bool startHost() {
    const Status created = host_.create(kSize, kSize);
    if (created.isOk()) {
      std::printf("[ vulkan ] %s, validation %s\n", host_.deviceName().c_str(),
                  host_.validation() ? "on" : "not installed");
      return true;
    }
    if (std::getenv("SI_REQUIRE_VULKAN") != nullptr) {
      ADD_FAILURE() << created.toString();
    } else {
      skip_reason_ = created.toString();
    }
    return false;
  }

  // `desc` on host_'s device, the embedded character added and its uploads submitted.
  void startRenderer(vk::RendererDesc desc, vk::Renderer* r, vk::CharacterId* id) {
    desc.physical_device = host_.physicalDevice();
    desc.device = host_.device();
    Status s = r->init(desc);
    ASSERT_TRUE(s.isOk()) << s.toString();
    s = r->addCharacter(character(), palette(), id);
    ASSERT_TRUE(s.isOk()) << s.toString();
    s = host_.submit([&](VkCommandBuffer cmd) { return r->recordUploads(cmd); });
    ASSERT_TRUE(s.isOk()) << s.toString();
    r->uploadsComplete();
  }

  // The validation layer's messages, one a line.
  std::string messages() const {
    std::ostringstream out;
    for (const std::string& m : host_.messages()) out << m << "\n";
    return out.str();
  }

  examples::HeadlessVulkan host_;
  std::string skip_reason_;  // Why startHost() returned false (empty when it failed).
};

// The embedded character's crowd of the LOD rows (populateLodCrowd).
inline void lodCrowd(CrowdManager* crowd) {
  CrowdDesc cd;
  cd.palette = &palette();
  cd.sub_mesh_count = uint32_t(character().mesh.sub_meshes.size());
  cd.lod_count = uint32_t(character().mesh.maxLodCount());
  ASSERT_TRUE(crowd->init(cd).isOk());
  populateLodCrowd(crowd);
}

}  // namespace si::test

// Starts the host in a test body: skips the test (or fails it under SI_REQUIRE_VULKAN=1) when the
// machine has no Vulkan 1.3 device.
#define SI_START_VULKAN_HOST()                                 \
  do {                                                         \
    if (!startHost()) {                                        \
      if (!skip_reason_.empty()) GTEST_SKIP() << skip_reason_; \
      return;                                                  \
    }                                                          \
  } while (false)
