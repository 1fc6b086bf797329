// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// si-bake: the baking step of a content pipeline. Reads a skinned glTF character (or the
// embedded one), bakes its clips into a palette, prints the baker's error report as a table and
// writes the palette file that the runtime loads (si::loadPaletteFile).
//
// Exit codes (stable, for build pipelines):
//   0  the palette was written (and, with --require-tolerance, every clip met the tolerance)
//   2  bad command line
//   3  the input could not be read or imported (missing file, malformed glTF, no clips, ...)
//   4  the bake failed (unknown clip or root joint, a format the character cannot use, texture
//      too large)
//   5  the output (palette or CSV) could not be written
//   6  a clip's max error is above the tolerance (nothing written): with automatic rates (the
//      default) unless --accept-tolerance-miss, with a fixed --rate under --require-tolerance
// Errors go to stderr as one line "si-bake: error: ..."; the table goes to stdout.
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "cast_table.h"
#include "lod_table.h"
#include "si/bake/animation_baker.h"
#include "si/bake/palette_file.h"
#include "si/core/default_character.h"
#include "si/core/root_motion.h"
#include "si/gltf/gltf_import.h"

namespace {

enum ExitCode : int {
  kExitOk = 0,
  kExitUsage = 2,
  kExitInput = 3,
  kExitBake = 4,
  kExitOutput = 5,
  kExitTolerance = 6,
};

struct Options {
  std::string input;  // Empty with --embedded.
  bool cast = false;  // --cast: every input (and --embedded) in one memory table, no output.
  std::vector<std::string> more_inputs;  // With --cast.
  bool embedded = false;
  bool moving_clips = false;              // --moving-clips: the embedded character's travelling clips.
  std::vector<std::string> root_motion;   // --root-motion: clip names, or "all".
  std::string root_joint;                 // --root-joint.
  std::string output;
  std::string csv;
  si::BakeDesc bake;
  si::GltfImportDesc import;
  bool require_tolerance = false;
  bool image_errors = false;  // --image-errors: each LOD level's image error (a GL context).
  bool impostor = false;      // --impostor: with --image-errors, the impostor's too.
  si::ImpostorDesc impostor_desc;  // --impostor-capture N: its capture_supersample.
  bool quiet = false;
  int progress = -1;  // -1: when stderr is a terminal; 0 never; 1 always.
};

void usage(std::FILE* f) {
  std::fprintf(
      f,
      "usage: si-bake (INPUT.gltf|INPUT.glb | --embedded) -o OUTPUT.sipal [options]\n"
      "       si-bake --cast [--embedded] [INPUT ...] [options]\n"
      "Bakes a skinned character's clips into a palette file for the runtime to load.\n"
      "  --cast                   bake every input (and --embedded) in each format and\n"
      "                           interpolation; print bytes and error per character and\n"
      "                           in total (a cast's memory budget); writes no file\n"
      "  -o, --output PATH        palette file to write (written whole or not at all)\n"
      "  --embedded               bake the library's embedded procedural character\n"
      "  --format f32|f16|quat    3x4 float32 matrices (default), 3x4 half floats, or\n"
      "                           quaternion + translation + uniform scale (rigid joints only)\n"
      "  --rate auto|HZ           per-clip automatic rate (default) or one fixed rate\n"
      "  --interpolation linear|cubic|smaller\n"
      "                           between baked frames: lerp (default), Catmull-Rom, or per\n"
      "                           clip whichever needs fewer frames at the tolerance\n"
      "  --placement P            automatic frames: fewer (default: per clip the fewer of\n"
      "                           the two), grid (one rate) or keys (at every key, each key\n"
      "                           interval divided for its own error)\n"
      "  --tolerance RATIO        automatic rate target: max error / character height (1e-4)\n"
      "  --max-rate HZ            highest automatic rate tried (240)\n"
      "  --clips NAME,NAME,...    clips to bake, in palette order (default: all)\n"
      "  --root-motion all|NAME,NAME,...\n"
      "                           bake these clips in place and keep their root motion\n"
      "                           (the root joint's ground travel and yaw) for the runtime\n"
      "  --root-joint NAME        the joint root motion is taken from (default: the first\n"
      "                           joint with a translation track in the clip)\n"
      "  --moving-clips           with --embedded: add its travelling clips (walk_forward,\n"
      "                           walk_turn_left), marked for root motion\n"
      "  --skin NAME|INDEX        the skin to import when the file has several\n"
      "  --lods N                 generate N coarser LODs when the file has none (for the\n"
      "                           report's vertex set; the runtime imports the mesh itself)\n"
      "  --variations convention|each-mesh\n"
      "                           variation groups: meshes named VAR_<group> (default; the\n"
      "                           rest is always worn) or one group per glTF mesh\n"
      "  --csv PATH               also write the error table as CSV\n"
      "  --image-errors           also measure each LOD level's image error (pixels of the\n"
      "                           character's image it changes) in an offscreen GL context\n"
      "  --impostor               with --image-errors: also the animated impostor's (drawn\n"
      "                           past the last level), every level measured between its views\n"
      "  --impostor-capture N     with --impostor: capture texels each way per atlas texel\n"
      "                           (ImpostorDesc::capture_supersample: 1, 2 or 4; default 2)\n"
      "  --require-tolerance      fail (exit 6, nothing written) when a clip misses it\n"
      "                           (automatic rates always do, unless told otherwise:)\n"
      "  --accept-tolerance-miss  write an automatic bake that misses the tolerance\n"
      "  --progress / --no-progress  force the progress bar on or off (default: on a terminal)\n"
      "  -q, --quiet              no table, errors only\n"
      "Exit codes: 0 written, 2 usage, 3 input, 4 bake, 5 output, 6 tolerance missed.\n");
}

// The import report: parts, variation groups and materials.
void printImport(const si::GltfImportReport& r) {
  std::printf(
      "import: %u primitives (%u skinned, %u moved by their nodes) as %u parts in %zu "
      "variation group%s; %u materials, %u images\n",
      r.skinned_primitives + r.rigid_primitives, r.skinned_primitives, r.rigid_primitives, r.parts,
      r.groups.size(), r.groups.size() == 1 ? "" : "s", r.materials, r.images);
  for (size_t g = 0; g < r.groups.size(); ++g)
    std::printf("  sub-mesh %zu '%s' (%s): %u parts, %u materials, one draw\n", g,
                r.groups[g].name.c_str(), r.groups[g].source.c_str(), r.groups[g].parts,
                r.groups[g].materials);
}

bool parseFloat(const char* text, float* out) {
  char* end = nullptr;
  const float v = std::strtof(text, &end);
  if (end == text || *end != '\0' || !(v > 0.0f) || !std::isfinite(v)) return false;
  *out = v;
  return true;
}

// Returns kExitOk, or kExitUsage after printing why.
int parse(int argc, char** argv, Options* o) {
  const auto bad = [](const std::string& why) {
    std::fprintf(stderr, "si-bake: error: %s\n", why.c_str());
    usage(stderr);
    return int(kExitUsage);
  };
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    const bool has = i + 1 < argc;
    const auto needsValue = [&] { return !has ? bad("option " + a + " needs a value") : 0; };
    if (a == "-h" || a == "--help") {
      usage(stdout);
      std::exit(kExitOk);
    } else if (a == "--embedded") {
      o->embedded = true;
    } else if (a == "--moving-clips") {
      o->moving_clips = true;
    } else if (a == "--cast") {
      o->cast = true;
    } else if (a == "--require-tolerance") {
      o->require_tolerance = true;
    } else if (a == "--impostor") {
      o->impostor = true;
    } else if (a == "--image-errors") {
#if SI_BAKE_IMAGE_ERRORS
      o->image_errors = true;
#else
      return bad("--image-errors needs a build with a headless GL back-end (SI_HEADLESS)");
#endif
    } else if (a == "--accept-tolerance-miss") {
      o->bake.accept_tolerance_miss = true;
    } else if (a == "-q" || a == "--quiet") {
      o->quiet = true;
    } else if (a == "--progress") {
      o->progress = 1;
    } else if (a == "--no-progress") {
      o->progress = 0;
    } else if (a == "-o" || a == "--output" || a == "--format" || a == "--rate" ||
               a == "--interpolation" || a == "--placement" || a == "--tolerance" ||
               a == "--max-rate" || a == "--clips" || a == "--skin" || a == "--root-motion" ||
               a == "--root-joint" || a == "--csv" || a == "--lods" || a == "--variations" ||
               a == "--impostor-capture") {
      if (int r = needsValue()) return r;
      const std::string v = argv[++i];
      if (a == "-o" || a == "--output") {
        o->output = v;
      } else if (a == "--csv") {
        o->csv = v;
      } else if (a == "--format") {
        if (v == "f32") o->bake.format = si::PaletteFormat::kMatrix3x4F32;
        else if (v == "f16") o->bake.format = si::PaletteFormat::kMatrix3x4F16;
        else if (v == "quat") o->bake.format = si::PaletteFormat::kQuatTranslationF32;
        else return bad("unknown --format '" + v + "' (f32, f16 or quat)");
      } else if (a == "--interpolation") {
        if (v == "linear") o->bake.interpolation = si::InterpolationChoice::kLinear;
        else if (v == "cubic") o->bake.interpolation = si::InterpolationChoice::kCubic;
        else if (v == "smaller") o->bake.interpolation = si::InterpolationChoice::kSmaller;
        else return bad("unknown --interpolation '" + v + "' (linear, cubic or smaller)");
      } else if (a == "--placement") {
        if (v == "fewer") o->bake.placement = si::FramePlacement::kFewer;
        else if (v == "grid") o->bake.placement = si::FramePlacement::kGrid;
        else if (v == "keys") o->bake.placement = si::FramePlacement::kKeys;
        else return bad("unknown --placement '" + v + "' (fewer, grid or keys)");
      } else if (a == "--rate") {
        if (v == "auto") {
          o->bake.rate_mode = si::RateMode::kAutomatic;
        } else if (parseFloat(v.c_str(), &o->bake.sample_rate_hz)) {
          o->bake.rate_mode = si::RateMode::kFixed;
        } else {
          return bad("--rate must be 'auto' or a rate in Hz > 0, not '" + v + "'");
        }
      } else if (a == "--tolerance") {
        if (!parseFloat(v.c_str(), &o->bake.error_tolerance_ratio))
          return bad("--tolerance must be a ratio > 0, not '" + v + "'");
      } else if (a == "--max-rate") {
        if (!parseFloat(v.c_str(), &o->bake.max_sample_rate_hz))
          return bad("--max-rate must be a rate in Hz > 0, not '" + v + "'");
      } else if (a == "--clips" || a == "--root-motion") {
        std::vector<std::string>& names = a == "--clips" ? o->bake.clip_names : o->root_motion;
        for (size_t at = 0; at <= v.size();) {
          const size_t comma = std::min(v.find(',', at), v.size());
          if (comma > at) names.push_back(v.substr(at, comma - at));
          at = comma + 1;
        }
        if (names.empty()) return bad(a + " names no clip");
      } else if (a == "--root-joint") {
        if (v.empty()) return bad("--root-joint names no joint");
        o->root_joint = v;
      } else if (a == "--skin") {
        char* end = nullptr;
        const long index = std::strtol(v.c_str(), &end, 10);
        if (!v.empty() && *end == '\0' && index >= 0) o->import.skin_index = int32_t(index);
        else o->import.skin_name = v;
      } else if (a == "--variations") {
        if (v != "convention" && v != "each-mesh")
          return bad("--variations must be convention or each-mesh");
        o->import.variations =
            v == "each-mesh" ? si::VariationSource::kEachMesh : si::VariationSource::kConvention;
      } else if (a == "--lods") {
        char* end = nullptr;
        const unsigned long n = std::strtoul(v.c_str(), &end, 10);
        if (v.empty() || *end != '\0' || n > 7) return bad("--lods must be 0 to 7");
        o->import.generate_lods = uint32_t(n);
      } else if (a == "--impostor-capture") {
        if (v != "1" && v != "2" && v != "4") return bad("--impostor-capture must be 1, 2 or 4");
        o->impostor_desc.capture_supersample = uint32_t(v[0] - '0');
      }
    } else if (!a.empty() && a[0] == '-') {
      return bad("unknown option '" + a + "'");
    } else if (o->input.empty()) {
      o->input = a;
    } else if (o->cast) {
      o->more_inputs.push_back(a);
    } else {
      return bad("more than one input ('" + o->input + "', '" + a + "')");
    }
  }
  if (o->cast) {
    if (!o->embedded && o->input.empty()) return bad("--cast needs inputs or --embedded");
    if (!o->output.empty()) return bad("--cast writes no palette (drop -o)");
    return kExitOk;
  }
  if (o->moving_clips && !o->embedded) return bad("--moving-clips is for --embedded");
  if (o->impostor && !o->image_errors) return bad("--impostor is for --image-errors");
  if (o->impostor_desc.capture_supersample != 0 && !o->impostor)
    return bad("--impostor-capture is for --impostor");
  if (!o->root_joint.empty() && o->root_motion.empty())
    return bad("--root-joint without --root-motion");
  if (o->embedded == !o->input.empty())
    return bad(o->embedded ? "give an input file or --embedded, not both"
                           : "no input (a .gltf or .glb file, or --embedded)");
  if (o->output.empty()) return bad("no output (-o PATH)");
  return kExitOk;
}

int error(int code, const std::string& message) {
  std::fprintf(stderr, "si-bake: error: %s\n", message.c_str());
  return code;
}

// A one-line bar on stderr, drawn only once the bake has run for a moment.
class ProgressBar {
 public:
  explicit ProgressBar(bool enabled) : enabled_(enabled), start_(Clock::now()) {}
  void update(const si::BakeProgress& p) {
    if (!enabled_) return;
    const double seconds = std::chrono::duration<double>(Clock::now() - start_).count();
    if (!shown_ && seconds < 0.3 && p.fraction < 1.0) return;
    const int width = 30, filled = int(p.fraction * width + 0.5);
    std::fprintf(stderr, "\r[%s%s] %3d%% %s clip %u/%u   ", std::string(size_t(filled), '#').c_str(),
                 std::string(size_t(width - filled), '-').c_str(), int(p.fraction * 100.0 + 0.5),
                 p.stage, p.clip + 1, p.clip_count);
    std::fflush(stderr);
    shown_ = true;
  }
  void finish() {
    if (shown_) std::fprintf(stderr, "\n");
  }

 private:
  using Clock = std::chrono::steady_clock;
  bool enabled_, shown_ = false;
  Clock::time_point start_;
};

void printTable(std::FILE* f, const si::BakedPalette& p, const si::BakeReport& r, double height,
                double tolerance_ratio) {
  std::fprintf(f, "%-16s %-6s %8s %7s %10s %11s %11s %10s %10s %4s\n", "clip", "interp",
               "rate Hz", "frames", "KiB", "max units", "P99 units", "max/h", "P99/h", "ok");
  for (size_t c = 0; c < r.clips.size(); ++c) {
    const si::ClipErrorReport& e = r.clips[c];
    std::fprintf(f, "%-16s %-6s %8.1f %7u %10.1f %11.3g %11.3g %10.3g %10.3g %4s\n",
                 e.name.c_str(), si::frameInterpolationName(e.interpolation),
                 e.sample_rate_hz, e.frame_count, double(e.palette_bytes) / 1024.0,
                 e.max_error_units, e.p99_error_units, e.max_error_ratio, e.p99_error_ratio,
                 e.tolerance_met ? "yes" : "NO");
  }
  std::fprintf(f,
               "palette %s %ux%u texels, %.1f KiB, %zu joints stored (%zu left out), height %.4g "
               "units; max error %.3g units = %.3g of the height (tolerance %.3g)\n",
               si::paletteFormatName(p.format), p.layout.width, p.layout.height,
               double(r.palette_bytes) / 1024.0, p.palette_joints.size(),
               r.joints_left_out.size(), height, r.max_error_units, r.max_error_ratio,
               tolerance_ratio);
}

bool writeCsv(const std::string& path, const si::BakedPalette& p, const si::BakeReport& r) {
  std::FILE* f = std::fopen(path.c_str(), "w");
  if (f == nullptr) return false;
  std::fprintf(f, "clip,format,interpolation,rate_hz,frames,bytes,max_units,p99_units,"
                  "mean_units,max_ratio,p99_ratio,shell_max_units,tolerance_met\n");
  for (const si::ClipErrorReport& e : r.clips)
    std::fprintf(f, "%s,%s,%s,%.3f,%u,%llu,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%d\n", e.name.c_str(),
                 si::paletteFormatName(p.format), si::frameInterpolationName(e.interpolation),
                 e.sample_rate_hz, e.frame_count,
                 static_cast<unsigned long long>(e.palette_bytes), e.max_error_units,
                 e.p99_error_units, e.mean_error_units, e.max_error_ratio, e.p99_error_ratio,
                 e.shell_max_error_units, e.tolerance_met ? 1 : 0);
  return std::fclose(f) == 0;
}

// Marks the clips --root-motion names (or all) for extraction from --root-joint; false (and
// `why`) for a name that is no clip of the character.
bool markRootMotion(const Options& o, si::Character* character, si::Status* why) {
  const bool all = o.root_motion.size() == 1 && o.root_motion[0] == "all";
  for (const std::string& name : o.root_motion)
    if (!all && character->findClip(name) < 0) {
      *why = si::Status(si::StatusCode::kNotFound, "no clip named '" + name + "'");
      return false;
    }
  for (si::Clip& clip : character->clips) {
    if (all || std::find(o.root_motion.begin(), o.root_motion.end(), clip.name) != o.root_motion.end())
      clip.root_motion.extract = true;
    if (clip.root_motion.extract && !o.root_joint.empty()) clip.root_motion.joint = o.root_joint;
  }
  return true;
}

// The clips baked in place: where their motion comes from, how fast it goes, and its error.
void printRootMotionTable(std::FILE* f, const si::BakedPalette& p, const si::BakeReport& r) {
  bool any = false;
  for (const si::BakedClip& c : p.clips) any |= !c.root_motion.empty();
  if (!any) return;
  std::fprintf(f, "%-16s %-12s %10s %10s %12s %11s %10s\n", "root motion", "joint", "units/s",
               "deg/s", "per cycle", "max units", "max/h");
  for (size_t c = 0; c < p.clips.size(); ++c) {
    if (p.clips[c].root_motion.empty()) continue;
    const si::RootMotionSummary m = si::summarizeRootMotion(p.clips[c]);
    std::fprintf(f, "%-16s %-12s %10.4g %10.4g %12.4g %11.3g %10.3g\n", p.clips[c].name.c_str(),
                 r.clips[c].root_motion_joint.c_str(), m.average_speed,
                 m.average_yaw_rate * 57.29577951308232, glm::length(m.whole_clip.translation),
                 r.clips[c].root_motion_max_error_units, r.clips[c].root_motion_max_error_ratio);
  }
}

}  // namespace

// --cast: imports every input, then prints the cast table.
int runCast(const Options& o) {
  std::vector<si_bake::CastMember> cast;
  if (o.embedded) {
    cast.push_back({"embedded", {}});
    if (!si::makeDefaultCharacter({}, &cast.back().character).isOk())
      return error(kExitInput, "embedded character");
  }
  std::vector<std::string> inputs = o.more_inputs;
  if (!o.input.empty()) inputs.insert(inputs.begin(), o.input);
  for (const std::string& path : inputs) {
    si_bake::CastMember m;
    m.name = path.substr(path.find_last_of('/') + 1);
    si::GltfImportReport ir;
    const si::Status s = si::importGltfFile(path, o.import, &m.character, &ir);
    if (!s.isOk()) return error(kExitInput, path + ": " + s.toString());
    cast.push_back(std::move(m));
  }
  return si_bake::printCastTable(stdout, cast, o.bake) ? kExitOk : kExitBake;
}

int main(int argc, char** argv) {
  Options o;
  if (int r = parse(argc, argv, &o)) return r;
  if (o.cast) return runCast(o);

  si::Character character;
  si::Status s;
  if (o.embedded) {
    si::DefaultCharacterDesc embedded;
    embedded.moving_clips = o.moving_clips;
    s = si::makeDefaultCharacter(embedded, &character);
  } else {
    si::GltfImportReport ir;
    s = si::importGltfFile(o.input, o.import, &character, &ir);
    if (!o.quiet) {
      for (const std::string& w : ir.warnings) std::fprintf(stderr, "si-bake: warning: %s\n", w.c_str());
      if (s.isOk()) printImport(ir);
    }
    if (s.isOk() && character.clips.empty())
      s = si::Status(si::StatusCode::kUnsupported, "the character has no animation clips");
  }
  if (!s.isOk()) return error(kExitInput, (o.embedded ? "embedded" : o.input) + ": " + s.toString());
  if (!markRootMotion(o, &character, &s)) return error(kExitBake, "--root-motion: " + s.message());

  ProgressBar bar(o.progress == 1 || (o.progress == -1 && !o.quiet && isatty(STDERR_FILENO)));
  o.bake.progress = [&](const si::BakeProgress& p) { bar.update(p); };
  const auto start = std::chrono::steady_clock::now();
  si::BakedPalette palette;
  si::BakeReport report;
  s = si::bakePalette(character, o.bake, &palette, &report);
  bar.finish();
  if (s.code() == si::StatusCode::kToleranceNotMet)
    return error(kExitTolerance, "bake: " + s.toString() + "; nothing written");
  if (!s.isOk()) return error(kExitBake, "bake: " + s.toString());
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  const si::BakeDesc resolved = si::resolveDefaults(o.bake);
  if (!o.quiet) {
    std::printf("%s: %zu joints, %zu vertices, %zu clips; baked in %.2f s\n",
                o.embedded ? "embedded character" : o.input.c_str(),
                character.skeleton.jointCount(), character.mesh.vertexCount(),
                palette.clips.size(), seconds);
    printTable(stdout, palette, report, double(character.height()),
               double(resolved.error_tolerance_ratio));
    printRootMotionTable(stdout, palette, report);
  }
  std::string why;
  if ((!o.quiet || o.image_errors) &&
      !si_bake::printLodTable(stdout, character, palette, o.image_errors,
                              o.impostor ? &o.impostor_desc : nullptr, &why))
    return error(kExitBake, "--image-errors: " + why);
  if (!o.csv.empty() && !writeCsv(o.csv, palette, report))
    return error(kExitOutput, "cannot write the CSV '" + o.csv + "'");
  if (o.require_tolerance)
    for (const si::ClipErrorReport& e : report.clips)
      if (!e.tolerance_met)
        return error(kExitTolerance,
                     "clip '" + e.name + "' misses the tolerance (max error " +
                         std::to_string(e.max_error_ratio) + " of the height > " +
                         std::to_string(resolved.error_tolerance_ratio) + "); nothing written");

  // Whole or nothing: write beside the target, then rename over it.
  std::vector<uint8_t> bytes;
  s = si::savePalette(palette, &bytes);
  if (!s.isOk()) return error(kExitBake, "serializing the palette: " + s.toString());
  const std::string temp = o.output + ".tmp" + std::to_string(getpid());
  std::FILE* f = std::fopen(temp.c_str(), "wb");
  bool written = f != nullptr && std::fwrite(bytes.data(), 1, bytes.size(), f) == bytes.size();
  if (f != nullptr) written = (std::fclose(f) == 0) && written;
  if (!written || std::rename(temp.c_str(), o.output.c_str()) != 0) {
    std::remove(temp.c_str());
    return error(kExitOutput, "cannot write '" + o.output + "': " + std::strerror(errno));
  }
  if (!o.quiet) std::printf("wrote %s (%zu bytes)\n", o.output.c_str(), bytes.size());
  return kExitOk;
}
