// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// crowd_demo: the main job. Until the GL back-end lands it prints what it will render: the
// embedded character's joints, clips, LODs, variations and the baked palette size.
#include <cstdio>
#include <cstring>
#include <string>

#include "si/bake/bake_desc.h"
#include "si/core/core.h"

namespace {

void usage(std::FILE* out) {
  std::fprintf(out,
               "usage: crowd_demo [--rate HZ] [--format f32|f16|quat]\n"
               "  Prints the embedded character and the palette a bake would produce.\n");
}

}  // namespace

int main(int argc, char** argv) {
  si::BakeDesc bake;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--help" || arg == "-h") {
      usage(stdout);
      return 0;
    } else if (arg == "--rate" && i + 1 < argc) {
      bake.sample_rate_hz = std::strtof(argv[++i], nullptr);
    } else if (arg == "--format" && i + 1 < argc) {
      const std::string f = argv[++i];
      if (f == "f32") bake.format = si::PaletteFormat::kMatrix3x4F32;
      else if (f == "f16") bake.format = si::PaletteFormat::kMatrix3x4F16;
      else if (f == "quat") bake.format = si::PaletteFormat::kQuatTranslationF32;
      else {
        std::fprintf(stderr, "crowd_demo: unknown format '%s'\n", f.c_str());
        return 2;
      }
    } else {
      std::fprintf(stderr, "crowd_demo: unknown option '%s'\n", arg.c_str());
      usage(stderr);
      return 2;
    }
  }

  si::Character c;
  si::Status s = si::makeDefaultCharacter({}, &c);
  if (!s.isOk()) {
    std::fprintf(stderr, "crowd_demo: %s\n", s.toString().c_str());
    return 1;
  }
  std::printf("Character '%s': %zu joints, %zu vertices, height %.3f units\n", c.name.c_str(),
              c.skeleton.jointCount(), c.mesh.vertexCount(), double(c.height()));
  std::printf("Joints:");
  for (size_t j = 0; j < c.skeleton.jointCount(); ++j)
    std::printf("%s %s", j ? "," : "", c.skeleton.joint_names[j].c_str());
  std::printf("\n\n%-10s %10s %10s %10s\n", "sub-mesh", "LOD0 tris", "LOD1 tris", "LOD2 tris");
  for (size_t sm = 0; sm < c.mesh.sub_meshes.size(); ++sm) {
    std::printf("%-10s", c.mesh.sub_meshes[sm].name.c_str());
    for (size_t l = 0; l < 3; ++l)
      if (l < c.mesh.sub_meshes[sm].lods.size()) std::printf(" %10zu", c.mesh.triangleCount(sm, l));
    std::printf("\n");
  }
  std::printf("\n%-8s %10s %6s %16s\n", "clip", "duration s", "loop", "interpolation");
  for (const si::Clip& clip : c.clips) {
    si::Interpolation interp = si::Interpolation::kDefault;
    for (const si::JointTracks& jt : clip.joint_tracks)
      if (!jt.rotation.empty()) {
        interp = jt.rotation.interpolation;
        break;
      }
    std::printf("%-8s %10.3f %6s %16s\n", clip.name.c_str(), double(clip.duration_seconds),
                clip.loop_mode == si::LoopMode::kLoop ? "yes" : "no",
                si::interpolationName(si::resolveInterpolation(interp)));
  }

  si::PalettePlan plan;
  s = si::planPalette(c, bake, &plan);
  if (!s.isOk()) {
    std::fprintf(stderr, "crowd_demo: %s\n", s.toString().c_str());
    return 1;
  }
  const si::BakeDesc resolved = si::resolveDefaults(bake);
  uint64_t frames = 0;
  for (const si::FramePlan& f : plan.frames) frames += f.frame_count;
  std::printf("\nPalette (%s, %.1f Hz): %llu frames x %u joints, texture %ux%u, %.1f KiB\n",
              si::paletteFormatName(resolved.format), double(resolved.sample_rate_hz),
              static_cast<unsigned long long>(frames), plan.layout.joint_count, plan.layout.width,
              plan.layout.height, double(plan.texture_bytes) / 1024.0);
  std::printf("(Rendering arrives with the GL back-end; see docs/architecture.md.)\n");
  return 0;
}
