// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// Bake throughput in joint-frames per second (items/s), per format, with and without the error
// measurement. Not part of ctest. Run: build/release/tests/bench/si_bake_bench
#include <benchmark/benchmark.h>

#include "si/bake/animation_baker.h"
#include "si/core/default_character.h"

namespace {

const si::Character& character() {
  static const si::Character c = [] {
    si::Character out;
    if (!si::makeDefaultCharacter({}, &out).isOk()) std::abort();
    return out;
  }();
  return c;
}

void bake(benchmark::State& state, si::PaletteFormat format, bool measure) {
  si::BakeDesc d;
  d.format = format;
  d.rate_mode = si::RateMode::kFixed;
  d.sample_rate_hz = 30.0f;
  uint64_t joint_frames = 0;
  for (auto _ : state) {
    si::BakedPalette p;
    si::BakeReport r;
    if (!si::bakePalette(character(), d, &p, measure ? &r : nullptr).isOk()) {
      state.SkipWithError("bake failed");
      return;
    }
    uint64_t frames = 0;
    for (const si::BakedClip& c : p.clips) frames += c.frame_count;
    joint_frames = frames * p.palette_joints.size();
    benchmark::DoNotOptimize(p.texel_bytes.data());
  }
  state.SetItemsProcessed(int64_t(state.iterations() * joint_frames));
  state.counters["joint_frames"] = double(joint_frames);
}

void BM_BakeF32(benchmark::State& s) { bake(s, si::PaletteFormat::kMatrix3x4F32, false); }
void BM_BakeF16(benchmark::State& s) { bake(s, si::PaletteFormat::kMatrix3x4F16, false); }
void BM_BakeQuat(benchmark::State& s) { bake(s, si::PaletteFormat::kQuatTranslationF32, false); }
void BM_BakeF32WithReport(benchmark::State& s) {
  bake(s, si::PaletteFormat::kMatrix3x4F32, true);
}
BENCHMARK(BM_BakeF32)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_BakeF16)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_BakeQuat)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_BakeF32WithReport)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
