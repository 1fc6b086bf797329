// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// si-bake as a build pipeline runs it: exit codes, messages, whole-or-nothing output, and a
// written palette identical to the same bake done in process.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>

#include "si/bake/animation_baker.h"
#include "si/bake/palette_file.h"
#include "si/core/default_character.h"
#include "gltf/parts_asset.h"
#include "test_assets.h"

namespace si {
namespace {

struct ToolRun {
  int exit_code = -1;
  std::string output;  // stdout and stderr together.
};

// Runs si-bake with `args` (a shell-quoted string) and captures its output and exit code.
ToolRun runTool(const std::string& args) {
  ToolRun r;
  const std::string command = std::string("'") + SI_BAKE_EXE + "' " + args + " 2>&1";
  std::FILE* p = popen(command.c_str(), "r");
  if (p == nullptr) return r;
  char buffer[4096];
  size_t n = 0;
  while ((n = std::fread(buffer, 1, sizeof buffer, p)) > 0) r.output.append(buffer, n);
  const int status = pclose(p);
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

std::string tempPath(const std::string& name) {
  return ::testing::TempDir() + "si_bake_" + std::to_string(getpid()) + "_" + name;
}

bool exists(const std::string& path) { return std::ifstream(path).good(); }

std::string fox() { return test::assetPath("Fox/glTF-Binary/Fox.glb"); }

TEST(SiBake, WritesThePaletteTheLibraryBakes) {
  const std::string out = tempPath("embedded.sipal"), csv = tempPath("embedded.csv");
  const ToolRun r = runTool("--embedded --rate 30 --no-progress -o '" + out + "' --csv '" + csv + "'");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("max error"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("walk"), std::string::npos) << r.output;
  // The LOD table: every level's triangles (all sub-meshes, as instances draw them).
  Character lod_character;
  ASSERT_TRUE(makeDefaultCharacter({}, &lod_character).isOk());
  for (size_t l = 0; l < lod_character.mesh.maxLodCount(); ++l) {
    uint64_t triangles = 0;
    for (const SubMesh& sm : lod_character.mesh.sub_meshes)
      triangles += sm.lods[std::min(l, sm.lods.size() - 1)].index_count / 3;
    char row[64];
    std::snprintf(row, sizeof(row), "LOD %-2zu %10llu ", l,
                  static_cast<unsigned long long>(triangles));
    EXPECT_NE(r.output.find(row), std::string::npos) << row << "\n" << r.output;
  }
  BakedPalette loaded;
  ASSERT_TRUE(loadPaletteFile(out, &loaded).isOk());
  // The same bake in process gives the same bytes.
  Character c;
  ASSERT_TRUE(makeDefaultCharacter({}, &c).isOk());
  BakeDesc d;
  d.rate_mode = RateMode::kFixed;
  d.sample_rate_hz = 30.0f;
  BakedPalette expected;
  ASSERT_TRUE(bakePalette(c, d, &expected, nullptr).isOk());
  EXPECT_EQ(loaded.texel_bytes, expected.texel_bytes);
  ASSERT_EQ(loaded.clips.size(), expected.clips.size());
  for (size_t i = 0; i < loaded.clips.size(); ++i) {
    EXPECT_EQ(loaded.clips[i].name, expected.clips[i].name);
    EXPECT_EQ(loaded.clips[i].frame_count, expected.clips[i].frame_count);
  }
  // The CSV: a header and one row per clip.
  std::ifstream f(csv);
  std::string line;
  size_t lines = 0;
  while (std::getline(f, line)) ++lines;
  EXPECT_EQ(lines, 1 + expected.clips.size());
  std::remove(out.c_str());
  std::remove(csv.c_str());
}

// Root motion: the travelling clips baked in place, their motion in the table and the file;
// an unknown clip or joint is a bake failure.
TEST(SiBake, RootMotionIsExtractedReportedAndWritten) {
  const std::string out = tempPath("moving.sipal");
  ToolRun r = runTool("--embedded --moving-clips --rate 30 --clips walk,walk_forward "
                      "--no-progress -o '" + out + "'");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const size_t table = r.output.find("root motion");
  ASSERT_NE(table, std::string::npos) << r.output;
  const size_t row = r.output.find("walk_forward     root", table);
  ASSERT_NE(row, std::string::npos) << r.output;
  EXPECT_NE(r.output.substr(row, 60).find(" 1.3 "), std::string::npos) << r.output.substr(row, 80);
  BakedPalette loaded;
  ASSERT_TRUE(loadPaletteFile(out, &loaded).isOk());
  ASSERT_EQ(loaded.clips.size(), 2u);
  EXPECT_TRUE(loaded.clips[0].root_motion.empty());
  EXPECT_EQ(loaded.clips[1].root_motion.size(), loaded.clips[1].frame_count);
  // --root-motion on a clip of the plain embedded character, from a named joint.
  r = runTool("--embedded --rate 10 --clips walk --root-motion walk --root-joint pelvis -q -o '" +
              out + "'");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  ASSERT_TRUE(loadPaletteFile(out, &loaded).isOk());
  EXPECT_FALSE(loaded.clips[0].root_motion.empty());
  std::remove(out.c_str());
  for (const char* args : {"--root-motion jump", "--root-motion all --root-joint tail"}) {
    r = runTool(std::string("--embedded --rate 10 -q -o '") + out + "' " + args);
    EXPECT_EQ(r.exit_code, 4) << args << "\n" << r.output;
    EXPECT_NE(r.output.find(std::string(args).find("tail") != std::string::npos ? "'tail'" : "'jump'"),
              std::string::npos) << r.output;
    EXPECT_FALSE(exists(out));
  }
}

// --image-errors: each LOD level's image error, measured in an offscreen context, beside the
// geometric one (a build without a headless back-end refuses the option, exit 2).
TEST(SiBake, ImageErrorsPerLevel) {
  const std::string out = tempPath("image_errors.sipal");
  const ToolRun r =
      runTool("--embedded --rate 30 --no-progress -q --image-errors --impostor -o '" + out + "'");
#if SI_BAKE_IMAGE_ERRORS
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("Image error per LOD level"), std::string::npos) << r.output;
  // LOD 1 and the impostor change pixels at 64 px: a number past 0 in their rows' last column.
  for (const char* name : {"\nLOD 1 ", "\nimp. "}) {
    const size_t row = r.output.rfind(name);
    ASSERT_NE(row, std::string::npos) << name << r.output;
    const std::string line = r.output.substr(row + 1, r.output.find('\n', row + 1) - row - 1);
    EXPECT_GT(std::stod(line.substr(line.rfind(' ') + 1)), 0.0) << line;
  }
  // Where the impostor takes over: a positive error in units, a height in pixels.
  const size_t handover = r.output.find("The impostor takes over at ");
  ASSERT_NE(handover, std::string::npos) << r.output;
  EXPECT_GT(std::stod(r.output.substr(handover + 27)), 0.0) << r.output.substr(handover);
  EXPECT_NE(r.output.find(" px tall", handover), std::string::npos) << r.output.substr(handover);
  EXPECT_TRUE(exists(out));
#else
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("SI_HEADLESS"), std::string::npos) << r.output;
#endif
  std::remove(out.c_str());
}

TEST(SiBake, BadCommandLinesExitWith2) {
  for (const char* args :
       {"",
        "--embedded",
        "-o x.sipal",
        "--embedded -o x.sipal --bogus",
        "--embedded -o x.sipal --rate 0",
        "--embedded -o x.sipal --rate fast",
        "--embedded -o x.sipal --format f64",
        "--embedded -o x.sipal --rate",
        "a.glb b.glb -o x.sipal",
        "a.glb --embedded -o x.sipal",
        "--embedded -o x.sipal --tolerance -1",
        "--embedded -o x.sipal --lods 9",
        "--embedded -o x.sipal --interpolation spline",
        "--cast",
        "--cast --embedded -o x.sipal",
        "--moving-clips -o x.sipal a.glb",
        "--embedded -o x.sipal --root-joint root",
        "--embedded -o x.sipal --root-motion ,",
        "--embedded -o x.sipal --impostor",
        "--embedded -o x.sipal --image-errors --impostor-capture 2",
        "--embedded -o x.sipal --image-errors --impostor --impostor-capture 3"}) {
    const ToolRun r = runTool(args);
    EXPECT_EQ(r.exit_code, 2) << args << "\n" << r.output;
    EXPECT_NE(r.output.find("si-bake: error:"), std::string::npos) << args;
    EXPECT_NE(r.output.find("usage:"), std::string::npos) << args;
  }
  EXPECT_FALSE(exists("x.sipal"));
  EXPECT_EQ(runTool("--help").exit_code, 0);
}

// --interpolation writes a cubic palette; --cast prints every format x interpolation per
// character and the cast's totals, which add up the rows.
TEST(SiBake, CubicPalettesAndTheCastTable) {
  const std::string out = tempPath("cubic.sipal");
  ToolRun r = runTool("--embedded --rate 30 --interpolation cubic --no-progress -o '" + out + "'");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find(" cubic "), std::string::npos) << r.output;
  BakedPalette loaded;
  ASSERT_TRUE(loadPaletteFile(out, &loaded).isOk());
  EXPECT_EQ(loaded.layout.border_frames, 1u);
  for (const BakedClip& c : loaded.clips) EXPECT_EQ(c.interpolation, FrameInterpolation::kCubic);
  std::remove(out.c_str());

  // Automatic rates: each row has the grid placement and the default one side by side.
  r = runTool("--cast --embedded --clips idle,run");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  unsigned long long row_sum[2][3][3] = {}, total[2][3][3] = {};
  const char* formats[] = {"matrix3x4_f32", "matrix3x4_f16", "quat_translation_f32"};
  const char* choices[] = {"linear", "cubic", "smaller"};
  std::istringstream lines(r.output);
  std::string line;
  int rows = 0;
  while (std::getline(lines, line)) {
    char who[64], format[64], choice[64], place[2][16];
    unsigned frames[2] = {};
    unsigned long long bytes[2] = {}, chars = 0;
    int f = -1, c = -1;
    if (std::sscanf(line.c_str(), "%63s %63s %63s", who, format, choice) != 3) continue;
    for (int i = 0; i < 3; ++i) {
      if (std::string(format) == formats[i]) f = i;
      if (std::string(choice) == choices[i]) c = i;
    }
    if (f < 0 || c < 0) continue;
    const size_t bar = line.find('|'), bar2 = line.find('|', bar + 1);
    if (bar == std::string::npos || bar2 == std::string::npos) continue;
    if (std::string(who) == "(cast)") {
      char ok[8];
      if (std::sscanf(line.c_str() + bar + 1, "%llu %llu %7s", &chars, &total[0][f][c], ok) == 3 &&
          std::sscanf(line.c_str() + bar2 + 1, "%llu", &total[1][f][c]) == 1) {
        EXPECT_EQ(chars, 1u) << line;
      }
      continue;
    }
    double error[2] = {};
    char met[2][8] = {};
    if (std::sscanf(line.c_str() + bar + 1, "%15s %u %llu %lf %7s", place[0], &frames[0],
                    &bytes[0], &error[0], met[0]) != 5 ||
        std::sscanf(line.c_str() + bar2 + 1, "%15s %u %llu %lf %7s", place[1], &frames[1],
                    &bytes[1], &error[1], met[1]) != 5)
      continue;
    EXPECT_STREQ(place[0], "grid") << line;
    EXPECT_STREQ(place[1], "fewer") << line;
    // Where both meet the tolerance the default placement takes no more frames than the grid
    // (it picks the fewer); where the format cannot, it aims at the lower floor it can reach.
    if (std::string(met[0]) == "yes" && std::string(met[1]) == "yes") {
      EXPECT_LE(frames[1], frames[0]) << line;
    } else {
      EXPECT_LE(error[1], error[0] * 1.05) << line;
    }
    for (int p = 0; p < 2; ++p) row_sum[p][f][c] += bytes[p];
    ++rows;
  }
  EXPECT_EQ(rows, 9) << r.output;
  for (int p = 0; p < 2; ++p)
    for (int f = 0; f < 3; ++f)
      for (int c = 0; c < 3; ++c) {
        EXPECT_GT(row_sum[p][f][c], 0u) << formats[f] << " " << choices[c];
        EXPECT_EQ(total[p][f][c], row_sum[p][f][c]) << formats[f] << " " << choices[c];
      }
}

TEST(SiBake, UnreadableInputsExitWith3) {
  const std::string out = tempPath("never.sipal");
  ToolRun r = runTool("/nonexistent/model.glb -o '" + out + "'");
  EXPECT_EQ(r.exit_code, 3) << r.output;
  EXPECT_NE(r.output.find("/nonexistent/model.glb"), std::string::npos) << r.output;
  const std::string garbage = tempPath("garbage.glb");
  std::ofstream(garbage, std::ios::binary) << "glTF\x02\x00\x00\x00 not really a glb";
  r = runTool("'" + garbage + "' -o '" + out + "'");
  EXPECT_EQ(r.exit_code, 3) << r.output;
  EXPECT_FALSE(exists(out));
  std::remove(garbage.c_str());
}

TEST(SiBake, BakeFailuresExitWith4) {
  const std::string out = tempPath("never.sipal");
  const ToolRun r = runTool("--embedded --rate 30 --clips walk,nosuch -o '" + out + "'");
  EXPECT_EQ(r.exit_code, 4) << r.output;
  EXPECT_NE(r.output.find("nosuch"), std::string::npos) << r.output;
  EXPECT_FALSE(exists(out));
}

TEST(SiBake, UnwritableOutputsExitWith5AndLeaveNothing) {
  ToolRun r = runTool("--embedded --rate 10 --clips idle -q -o /nonexistent/dir/x.sipal");
  EXPECT_EQ(r.exit_code, 5) << r.output;
  EXPECT_NE(r.output.find("/nonexistent/dir/x.sipal"), std::string::npos) << r.output;
  const std::string out = tempPath("csvfail.sipal");
  r = runTool("--embedded --rate 10 --clips idle -q -o '" + out + "' --csv /nonexistent/x.csv");
  EXPECT_EQ(r.exit_code, 5) << r.output;
  EXPECT_FALSE(exists(out));
}

TEST(SiBake, MissedToleranceExitsWith6WhenRequired) {
  // Half floats cannot meet 1e-4 of the height (their floor is about 7e-4).
  const std::string out = tempPath("f16.sipal");
  ToolRun r = runTool("--embedded --format f16 --rate 30 --clips walk --require-tolerance -o '" +
                  out + "'");
  EXPECT_EQ(r.exit_code, 6) << r.output;
  EXPECT_NE(r.output.find("walk"), std::string::npos) << r.output;
  EXPECT_FALSE(exists(out));
  // Without --require-tolerance the same bake is written, and the table says NO.
  r = runTool("--embedded --format f16 --rate 30 --clips walk -o '" + out + "'");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("NO"), std::string::npos) << r.output;
  EXPECT_TRUE(exists(out));
  std::remove(out.c_str());
}

TEST(SiBake, AnAutomaticBakeThatMissesExitsWith6UnlessAccepted) {
  // Automatic rates (the default) refuse a miss by name: the library's kToleranceNotMet.
  const std::string out = tempPath("f16auto.sipal");
  ToolRun r = runTool("--embedded --format f16 --clips idle -o '" + out + "'");
  EXPECT_EQ(r.exit_code, 6) << r.output;
  EXPECT_NE(r.output.find("ToleranceNotMet"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("clip 'idle'"), std::string::npos) << r.output;
  EXPECT_FALSE(exists(out));
  r = runTool("--embedded --format f16 --clips idle --accept-tolerance-miss -o '" + out + "'");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("NO"), std::string::npos) << r.output;
  EXPECT_TRUE(exists(out));
  std::remove(out.c_str());
}

TEST(SiBake, ProgressBarWhenAsked) {
  const std::string out = tempPath("progress.sipal");
  ToolRun r = runTool("--embedded --rate 30 --clips walk,wave --progress -o '" + out + "'");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("100%"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("measuring clip 2/2"), std::string::npos) << r.output;
  r = runTool("--embedded --rate 30 --clips walk -q -o '" + out + "'");  // Not a terminal.
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(r.output, "");
  std::remove(out.c_str());
}

TEST(SiBake, BakesAGltfSample) {
  ASSERT_TRUE(test::assetExists(fox()));
  const std::string out = tempPath("fox.sipal");
  const ToolRun r = runTool("'" + fox() + "' --rate 15 --clips Walk --no-progress -o '" + out + "'");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  BakedPalette loaded;
  ASSERT_TRUE(loadPaletteFile(out, &loaded).isOk());
  ASSERT_EQ(loaded.clips.size(), 1u);
  EXPECT_EQ(loaded.clips[0].name, "Walk");
  // Frames end exactly on the clip's end, so the rate is 15 Hz rounded up to fit.
  EXPECT_GE(loaded.clips[0].sampleRateHz(), 15.0);
  EXPECT_LT(loaded.clips[0].sampleRateHz(), 16.0);
  std::remove(out.c_str());
}

TEST(SiBake, ReportsPartsAndVariationGroups) {
  const std::string in = tempPath("parts.gltf"), out = tempPath("parts.sipal");
  {
    std::ofstream f(in);
    f << test::partsAsset({{"Body", 190}, {"VAR_Helmet", 10}}, 100);
  }
  ToolRun r = runTool("'" + in + "' --rate 15 --no-progress -o '" + out + "'");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("import: 200 primitives (200 skinned, 0 moved by their nodes) as 200 "
                          "parts in 2 variation groups; 101 materials"),
            std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("sub-mesh 0 'base' (always worn): 190 parts, 100 materials"),
            std::string::npos) << r.output;
  EXPECT_NE(r.output.find("sub-mesh 1 'Helmet' (convention): 10 parts"), std::string::npos)
      << r.output;
  r = runTool("'" + in + "' --rate 15 --no-progress --variations each-mesh -o '" + out + "'");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("sub-mesh 0 'Body' (each mesh)"), std::string::npos) << r.output;
  r = runTool("'" + in + "' --variations some -o '" + out + "'");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  std::remove(in.c_str());
  std::remove(out.c_str());
}

}  // namespace
}  // namespace si
