// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// Every input that once broke the library (tests/regressions/inputs, see its README) fed to its
// entry point under the sanitizers: each must load with a clear error, or load correctly and
// then behave (a palette validates, samples every clip within its frames and plays in a crowd;
// a glTF file imports and bakes). A file of a kind no entry point below takes fails the test,
// so a new regression input cannot go unreplayed. The inputs are part of the checkout (copies of
// the steering repository's shared/regressions), so every checkout replays them.
#include <gtest/gtest.h>

#include <dirent.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>
#include <cstdlib>
#include <limits>
#include <string>
#include <vector>

#include "si/bake/animation_baker.h"
#include "si/bake/palette_file.h"
#include "si/crowd/crowd_manager.h"
#include "test_assets.h"
#ifdef SI_HAVE_GLTF
#include "si/gltf/gltf_import.h"
#endif

namespace si {
namespace {

using test::regressionsDir;

std::vector<std::string> regressionFiles() {
  std::vector<std::string> files;
  DIR* d = opendir(regressionsDir().c_str());
  if (d == nullptr) return files;
  while (dirent* e = readdir(d)) {
    const std::string name = e->d_name;
    if (name == "." || name == ".." || name.rfind("README", 0) == 0) continue;
    files.push_back(name);
  }
  closedir(d);
  return files;
}

bool endsWith(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

// A palette that loaded: consistent, every clip sampled within its frames at any time, and a
// crowd playing every clip updates.
void exercisePalette(const BakedPalette& p) {
  const Status valid = p.validate();
  ASSERT_TRUE(valid.isOk()) << valid.toString();
  const double inf = std::numeric_limits<double>::infinity();
  for (const BakedClip& c : p.clips)
    for (double t : {0.0, 0.01, double(c.duration_seconds), 1e300, -1.0, inf,
                     std::numeric_limits<double>::quiet_NaN()}) {
      const FrameSample s = sampleFrames(c, t);
      EXPECT_LT(s.frame, c.frame_count);
    }
  CrowdDesc cd;
  cd.palette = &p;
  cd.sub_mesh_count = 1;
  CrowdManager crowd;
  ASSERT_TRUE(crowd.init(cd).isOk());
  for (uint32_t c = 0; c < p.clips.size(); ++c) {
    InstanceDesc d;
    d.clip = c;
    d.position = glm::dvec3(double(c), 0.0, -5.0);
    InstanceHandle h;
    ASSERT_TRUE(crowd.add(d, &h).isOk());
  }
  const Camera camera;
  for (double dt : {0.0, 1.0 / 60.0, 1e6})
    ASSERT_TRUE(crowd.update(dt, camera).isOk());
}

TEST(RegressionInputs, EachLoadsWithAClearErrorOrBehaves) {
  const std::vector<std::string> files = regressionFiles();
  ASSERT_FALSE(files.empty()) << "no regression inputs at " << regressionsDir()
                               << " (tests/regressions/inputs is part of the checkout)";
  for (const std::string& name : files) {
    SCOPED_TRACE(name);
    const std::string path = regressionsDir() + "/" + name;
    if (endsWith(name, ".sipal")) {
      // Entry point: si::loadPalette, then si::sampleFrames on each clip; as the fuzz target
      // does, both the bytes as they are and with the checksum repaired (most fuzzed inputs
      // only reach the checks behind the checksum that way).
      std::ifstream in(path, std::ios::binary);
      std::vector<uint8_t> bytes((std::istreambuf_iterator<char>(in)),
                                 std::istreambuf_iterator<char>());
      ASSERT_GE(bytes.size(), 4u);
      std::vector<uint8_t> repaired = bytes;
      const uint32_t crc = crc32(Span<const uint8_t>(repaired.data(), repaired.size() - 4));
      std::memcpy(repaired.data() + repaired.size() - 4, &crc, 4);
      for (const std::vector<uint8_t>* b : {&bytes, &repaired}) {
        BakedPalette p;
        const Status s = loadPalette(*b, &p);
        std::printf("[ regress  ] %s (%s): %s\n", name.c_str(),
                    b == &bytes ? "as is" : "checksum repaired",
                    s.isOk() ? "loads" : s.toString().c_str());
        if (s.isOk()) exercisePalette(p);
        else EXPECT_FALSE(s.message().empty());
      }
#ifdef SI_HAVE_GLTF
    } else if (endsWith(name, ".glb") || endsWith(name, ".gltf")) {
      // Entry point: si::importGltfFile, then both bake modes.
      Character c;
      const Status s = importGltfFile(path, {}, &c, nullptr);
      std::printf("[ regress  ] %s: %s\n", name.c_str(), s.isOk() ? "imports" : s.toString().c_str());
      if (!s.isOk() || c.clips.empty()) continue;
      for (RateMode mode : {RateMode::kFixed, RateMode::kAutomatic})
        for (PaletteFormat format : {PaletteFormat::kMatrix3x4F32, PaletteFormat::kMatrix3x4F16}) {
          BakeDesc d;
          d.rate_mode = mode;
          d.format = format;
          BakedPalette p;
          const Status b = bakePalette(c, d, &p, nullptr);
          std::printf("[ regress  ] %s (%s, %s): %s\n", name.c_str(),
                      mode == RateMode::kFixed ? "fixed rate" : "automatic",
                      paletteFormatName(format), b.isOk() ? "bakes" : b.toString().c_str());
          if (b.isOk())
            exercisePalette(p);
          else
            EXPECT_FALSE(b.message().empty());
        }
#endif
    } else if (endsWith(name, ".bin") && name.rfind("crowd-api-", 0) == 0) {
      // The crowd API fuzzer's input format: replayed by fuzz_replay.crowd_api (the fuzz
      // target's entry function under the sanitizers, tests/CMakeLists.txt), not here.
    } else {
      ADD_FAILURE() << name << ": no entry point replays this kind of file";
    }
  }
}

}  // namespace
}  // namespace si
