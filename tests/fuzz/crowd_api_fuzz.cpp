// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// libFuzzer target: random sequences of CrowdManager calls (add, remove, play, crossfade,
// setTransform, setColor, setCustomLayer, setVariationMask, setRootMotion, setLivePose,
// setLivePoses, clearLivePose, setLodDistances,
// playOverlay, stopOverlay, playBlend, setBlendParameter, update, queries including
// socketTransform, localPose and a hostile applyLookAt on it; makeSocket and
// attachProp on a copy of the character) with hostile values (NaN, infinities, negative and huge
// times, speeds, scales, stale and forged handles) against a shadow list of the live handles. After
// every call: every live handle resolves, released ones do not, the size matches; after an update
// the statistics add up, buckets are consistent, records are finite with frames inside the
// palette, layer records (overlays on two masks: a branch and the whole chain; a 2D blend's extra
// layer records) likewise. A rejected
// call must return a named error and leave the crowd exactly as it was. Run with scripts/fuzz.sh.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <vector>

#include "si/bake/animation_baker.h"
#include "si/core/layer_mask.h"
#include "si/crowd/crowd_export.h"
#include "si/crowd/crowd_manager.h"
#include "si/crowd/instance_batcher.h"

#include "fuzz_input.h"
#include "layer_fuzz_checks.h"
#include "pose_fuzz_step.h"
#include "previous_fuzz_checks.h"
#include "prop_fuzz_step.h"
#include "record_fuzz_checks.h"

namespace {

[[noreturn]] void fail(const char* what) {
  std::fprintf(stderr, "crowd_api_fuzz: %s\n", what);
  std::abort();
}

// A three-joint chain with a looping clip, a once clip with a STEP key, and a single-frame
// pose: every kind of clip timing.
const si::Character& character() {
  static const si::Character character = [] {
    si::Character c;
    for (int i = 0; i < 3; ++i) {
      c.skeleton.joint_names.push_back("j" + std::to_string(i));
      c.skeleton.parents.push_back(i - 1);
      si::Transform t;
      t.translation = glm::vec3(0.0f, i == 0 ? 0.0f : 1.0f, 0.0f);
      c.skeleton.rest_pose.push_back(t);
      glm::mat4 ibm(1.0f);
      ibm[3] = glm::vec4(0.0f, -float(i), 0.0f, 1.0f);
      c.skeleton.inverse_bind_matrices.push_back(ibm);
      c.mesh.positions.push_back(glm::vec3(0.2f * i, float(i), 0.0f));
      c.mesh.normals.push_back(glm::vec3(0, 0, 1));
      c.mesh.joints.push_back(glm::u16vec4(uint16_t(i), 0, 0, 0));
      c.mesh.weights.push_back(glm::vec4(1, 0, 0, 0));
    }
    c.mesh.indices = {0, 1, 2};
    c.mesh.sub_meshes.push_back(si::SubMesh{"body", {si::IndexRange{0, 3}}, 0, {}});
    const auto clip = [&](const char* name, float duration, si::LoopMode loop) {
      si::Clip k;
      k.name = name;
      k.duration_seconds = duration;
      k.loop_mode = loop;
      k.joint_tracks.resize(3);
      return k;
    };
    si::Clip swing = clip("swing", 1.0f, si::LoopMode::kLoop);
    swing.joint_tracks[1].rotation.times_seconds = {0.0f, 0.5f, 1.0f};
    swing.joint_tracks[1].rotation.values = {glm::quat(1, 0, 0, 0), glm::quat(0.8f, 0.6f, 0, 0),
                                             glm::quat(1, 0, 0, 0)};
    si::Clip step = clip("step", 0.6f, si::LoopMode::kOnce);
    step.joint_tracks[2].translation.interpolation = si::Interpolation::kStep;
    step.joint_tracks[2].translation.times_seconds = {0.0f, 0.3f};
    step.joint_tracks[2].translation.values = {{0, 1, 0}, {0.5f, 1, 0}};
    // Root motion on the loop and on the STEP clip (its frames are not on a uniform grid).
    swing.root_motion.extract = step.root_motion.extract = true;
    swing.joint_tracks[0].translation.times_seconds = {0.0f, 1.0f};
    swing.joint_tracks[0].translation.values = {{0, 0, 0}, {0.3f, 0, 1.2f}};
    swing.joint_tracks[0].rotation.times_seconds = {0.0f, 1.0f};
    swing.joint_tracks[0].rotation.values = {glm::quat(1, 0, 0, 0), glm::quat(0.9f, 0, 0.43f, 0)};
    step.joint_tracks[0].translation.times_seconds = {0.0f, 0.6f};
    step.joint_tracks[0].translation.values = {{0, 0, 0}, {0, 0, -0.7f}};
    // Two morph targets: the loop animates both (LINEAR), the STEP clip the second (STEP); a
    // mask of the second lets overlays move it.
    for (int t = 0; t < 2; ++t) {
      si::MorphTarget target;
      target.name = "m" + std::to_string(t);
      target.vertices = t == 0 ? std::vector<uint32_t>{2} : std::vector<uint32_t>{0, 1};
      for (size_t v = 0; v < target.vertices.size(); ++v)
        target.position_deltas.push_back(glm::vec3(0.1f, 0.0f, 0.2f * float(t + 1)));
      c.mesh.morph_targets.push_back(target);
    }
    swing.morph_tracks.push_back({0, 2, si::Interpolation::kLinear, {0.0f, 1.0f}, {0, 1, 1, 0}});
    step.morph_tracks.push_back({1, 1, si::Interpolation::kStep, {0.0f, 0.3f}, {0.2f, 0.9f}});
    c.clips = {swing, step, clip("pose", 0.0f, si::LoopMode::kOnce)};
    return c;
  }();
  return character;
}

const si::BakedPalette& palette() {
  static const si::BakedPalette p = [] {
    const si::Character& c = character();
    si::BakeDesc d;
    d.rate_mode = si::RateMode::kFixed;
    d.sample_rate_hz = 10.0f;
    si::BakedPalette out;
    if (!si::bakePalette(c, d, &out, nullptr).isOk()) fail("cannot bake the test palette");
    return out;
  }();
  return p;
}

using si::fuzz::Input;

// Everything a call could change, to compare before and after a rejected call.
struct Snapshot {
  std::vector<si::GpuInstanceState> state;
  std::vector<si::InstanceHandle> handles;
  std::vector<si::GpuOverlayState> overlays;
  uint64_t version = 0;
  std::vector<float> lines;
  float far_line = 0.0f;
  double clock = 0.0;
  bool operator==(const Snapshot& o) const {
    return state.size() == o.state.size() &&
           (state.empty() ||
            std::memcmp(state.data(), o.state.data(), state.size() * sizeof(state[0])) == 0) &&
           handles == o.handles && version == o.version && lines == o.lines &&
           overlays.size() == o.overlays.size() &&
           (overlays.empty() || std::memcmp(overlays.data(), o.overlays.data(),
                                            overlays.size() * sizeof(overlays[0])) == 0) &&
           std::memcmp(&far_line, &o.far_line, 4) == 0 && std::memcmp(&clock, &o.clock, 8) == 0;
  }
};

Snapshot snapshot(const si::CrowdManager& crowd) {
  Snapshot s;
  si::CrowdExport(crowd).state(&s.state, &s.handles);
  if (s.handles.size() != s.state.size()) fail("CrowdExport::state: a handle per instance");
  for (size_t i = 0; i < s.state.size(); ++i)
    if (s.state[i].handle != s.handles[i].id)
      fail("CrowdExport::state: the state names another handle");
  s.version = si::CrowdExport(crowd).stateVersion();
  si::CrowdExport(crowd).overlays(&s.overlays);
  s.lines = crowd.desc().lod_distances_radii;
  s.far_line = crowd.desc().max_distance_radii;
  s.clock = crowd.clockSeconds();
  return s;
}

// An instance's state as the GPU-driven pass reads it at crowd clock `clock`: the LOD field
// (update()'s, which the GPU keeps its own of) and a crossfade past its end (update() ends it,
// the GPU sees it over) do not count.
si::GpuInstanceState onGpu(si::GpuInstanceState g, double clock) {
  g.lod = 0;
  if (g.fading == 0 || !(g.fade_duration > 0.0) || !(clock - g.fade_start < g.fade_duration)) {
    g.fading = 0;
    g.fade_start = g.fade_duration = 0.0;
    g.from_start_clock = g.from_start_time = 0.0;
    g.from_clip = g.from_loop = 0;
    g.from_speed = 0.0f;
  }
  return g;
}

// changedSince(before.version) names every dense index whose exported state or overlay now
// differs from `before` on the GPU, or that did not exist then, in sorted ranges within the
// crowd whose range exports equal the whole export; and among them every index that holds
// another instance than then.
void checkChanges(const si::CrowdManager& crowd, const Snapshot& before) {
  const Snapshot after = snapshot(crowd);
  std::vector<si::DenseRange> changed, placed;
  si::CrowdExport(crowd).changedSince(before.version, &changed, &placed);
  const size_t n = after.state.size();
  std::vector<uint8_t> covered(n, 0), moved(n, 0);
  for (int list = 0; list < 2; ++list) {
    uint32_t end = 0;
    for (const si::DenseRange& r : list == 0 ? changed : placed) {
      if (r.count == 0 || r.first < end || size_t(r.first) + r.count > n)
        fail("changedSince: ranges empty, out of order or past the end");
      end = r.first + r.count;
      std::fill((list == 0 ? covered : moved).begin() + r.first,
                (list == 0 ? covered : moved).begin() + end, uint8_t(1));
    }
  }
  size_t changed_count = 0;
  for (const si::DenseRange& r : changed) changed_count += r.count;
  std::vector<si::GpuInstanceState> parts(changed_count);
  si::CrowdExport(crowd).state(changed, parts.data(), nullptr);
  size_t at = 0;
  for (const si::DenseRange& r : changed) {
    if (std::memcmp(&parts[at], &after.state[r.first], r.count * sizeof(parts[0])) != 0)
      fail("a run export differs from the whole export");
    at += r.count;
  }
  const double clock = crowd.clockSeconds();
  for (size_t i = 0; i < n; ++i) {
    if (moved[i] && !covered[i]) fail("changedSince: a re-occupied index is not changed");
    if (covered[i]) continue;
    if (i >= before.state.size() || after.handles[i] != before.handles[i])
      fail("changedSince misses an added or moved instance");
    const si::GpuInstanceState a = onGpu(before.state[i], clock), b = onGpu(after.state[i], clock);
    if (std::memcmp(&a, &b, sizeof(a)) != 0) fail("changedSince misses a changed instance");
    // No overlays exported (none held) reads as a zero overlay per instance.
    const si::GpuOverlayState none{};
    const si::GpuOverlayState& was = i < before.overlays.size() ? before.overlays[i] : none;
    const si::GpuOverlayState& is = i < after.overlays.size() ? after.overlays[i] : none;
    if (std::memcmp(&was, &is, sizeof(is)) != 0) fail("changedSince misses a changed overlay");
  }
  for (size_t i = 0; i < n && i < before.state.size(); ++i)
    if (after.handles[i] != before.handles[i] && !moved[i])
      fail("changedSince: another instance sits at an index not marked placed");
}

void checkFrame(const si::CrowdManager& crowd) {
  const si::CrowdFrameStats& st = crowd.view().stats();
  if (st.visible + st.culled_frustum + st.culled_distance != st.instances) fail("stats do not add up");
  uint32_t per_lod = 0;
  for (uint32_t n : st.per_lod) per_lod += n;
  if (per_lod != st.visible) fail("per-LOD counts do not add up");
  if (crowd.view().records().size() != st.visible ||
      crowd.view().visibleHandles().size() != st.visible)
    fail("records or visible handles do not match the visible count");
  const std::vector<uint32_t>& offsets = crowd.view().bucketOffsets();
  if (offsets.size() != crowd.view().bucketCount() + 1 || offsets.back() != st.bucket_entries ||
      crowd.view().bucketEntries().size() != st.bucket_entries)
    fail("bucket offsets do not match the entries");
  for (size_t b = 0; b + 1 < offsets.size(); ++b)
    if (offsets[b] > offsets[b + 1]) fail("bucket offsets decrease");
  for (uint32_t e : crowd.view().bucketEntries())
    if (e >= crowd.view().records().size()) fail("a bucket entry is past the records");
  // The runs and the zero-copy spans hold exactly the entries, bucket by bucket.
  const std::vector<uint32_t>& run_offsets = crowd.view().bucketRunOffsets();
  if (run_offsets.size() != offsets.size()) fail("run offsets do not match the buckets");
  std::vector<uint32_t> from_runs;
  for (size_t b = 0; b + 1 < run_offsets.size(); ++b)
    for (uint32_t r = run_offsets[b]; r < run_offsets[b + 1]; ++r)
      for (uint32_t k = 0; k < crowd.view().bucketRuns()[r].count; ++k)
        from_runs.push_back(crowd.view().bucketRuns()[r].first + k);
  if (from_runs != crowd.view().bucketEntries()) fail("the runs are not the bucket entries");
  si::InstanceBatcher batcher;
  std::vector<si::RecordSpanDraw> spans;
  if (!batcher.init({16384, 256, 0}).isOk() || !batcher.buildSpans(crowd.view(), &spans).isOk())
    fail("buildSpans failed on a valid frame");
  std::vector<uint32_t> from_spans;
  for (const si::RecordSpanDraw& d : spans)
    for (uint32_t k = 0; k < d.instance_count; ++k) from_spans.push_back(d.first_record + k);
  if (from_spans != crowd.view().bucketEntries()) fail("the spans are not the bucket entries");
  si::fuzz::checkPreviousRecords(crowd, batcher, fail);
  si::fuzz::checkRecordPlaces(crowd, batcher, fail);
  si::fuzz::checkSlotHandles(crowd, batcher, fail);
  si::fuzz::checkLayerRecords(crowd, batcher, palette(), fail);
  si::fuzz::checkRecords(crowd, palette(), fail);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  Input in(data, size);
  si::CrowdDesc cd;
  cd.palette = &palette();
  cd.sub_mesh_count = 1 + in.u8() % 4;
  // Its high bit: previous records; bit 5: the last level is an impostor level (the input
  // layout is kept).
  const uint8_t lods = in.u8();
  cd.lod_count = 1 + lods % 3;
  cd.previous_records = (lods & 0x80) != 0;
  cd.impostor_lod = (lods & 0x20) != 0 && cd.lod_count > 1 ? cd.lod_count - 1 : 0;
  cd.live_pose_capacity = (lods & 0x10) != 0 ? 2 : 0;  // Bit 4: room for two live poses.
  si::CrowdManager crowd;
  if (!crowd.init(cd).isOk()) fail("init refused a valid desc");
  // Three masks: the branch of j1 (anchored on j0), the whole chain (the model anchor) and
  // morph target m1 alone.
  for (const char* root : {"j1", "j0"}) {
    si::LayerMask mask;
    if (!si::buildLayerMask(character().skeleton, palette(), root, {root}, &mask).isOk() ||
        !crowd.addLayerMask(mask, nullptr).isOk())
      fail("cannot add a valid layer mask");
  }
  si::LayerMask face;
  if (!si::buildMorphTargetMask(character().mesh, palette(), "face", {"m1"}, &face).isOk() ||
      !crowd.addLayerMask(face, nullptr).isOk())
    fail("cannot add a valid mask of morph targets");
  const uint32_t masks = uint32_t(crowd.layerMasks().size());
  // A blend space of the loop and the STEP clip on the whole chain; with bit 6 of the LOD byte,
  // a 2D one of both on the branch too (updates then write extra layer records).
  if (!crowd.addBlendSpace({"sway", {0, 1}, {0.0f, 1.0f}, 1}, nullptr).isOk())
    fail("cannot add a valid blend space");
  const bool grid = (lods & 0x40) != 0;
  if (grid &&
      !crowd.addBlendSpace({"grid", {0, 1, 1, 0}, {0.0f, 1.0f}, 0, {0.0f, 1.0f}}, nullptr).isOk())
    fail("cannot add a valid 2D blend space");
  const uint32_t spaces = uint32_t(crowd.blendSpaces().size());
  std::vector<si::InstanceHandle> live, released;
  const uint32_t clips = uint32_t(palette().clips.size());
  for (int op = 0; op < 256 && !in.done(); ++op) {
    const uint8_t kind = in.u8() % 13;
    // A handle: live, released (stale) or forged.
    const uint8_t which = in.u8();
    si::InstanceHandle h;
    if (which < 160 && !live.empty()) h = live[which % live.size()];
    else if (which < 220 && !released.empty()) h = released[which % released.size()];
    else h.id = in.u32();
    const Snapshot before = snapshot(crowd);
    si::Status s;
    switch (kind) {
      case 0: case 1: {  // add (twice as often)
        si::InstanceDesc d;
        d.position = glm::dvec3(in.f64(), in.f64(), in.f64());
        d.rotation = glm::quat(in.f32(), in.f32(), in.f32(), in.f32());
        d.scale = in.f32();
        d.clip = in.u8() % (clips + 1);  // Sometimes out of range.
        d.time_seconds = in.f64();
        d.speed = in.f32();
        d.variation_mask = in.u32();
        d.loop_mode = si::LoopMode(in.u8() % 4);
        d.color = glm::u8vec4(in.u8(), in.u8(), in.u8(), in.u8() < 64 ? in.u8() : 255);
        d.custom_layer = in.u8();
        d.root_motion = in.u8() & 1;
        si::InstanceHandle added;
        s = crowd.add(d, &added);
        if (s.isOk()) live.push_back(added);
        break;
      }
      case 2:
        s = crowd.remove(h);
        if (s.isOk()) {
          live.erase(std::find(live.begin(), live.end(), h));
          released.push_back(h);
        }
        break;
      case 3: s = crowd.play(h, in.u8() % (clips + 1), in.f64(), in.f32()); break;
      case 4: s = crowd.crossfade(h, in.u8() % (clips + 1), in.f64(), in.f64()); break;
      case 5:
        s = crowd.setTransform(h, glm::dvec3(in.f64(), in.f64(), in.f64()),
                               glm::quat(in.f32(), in.f32(), in.f32(), in.f32()), in.f32());
        break;
      case 6: {  // The tint and the custom layer share a word: each keeps the other.
        si::InstanceDesc d0, d1;
        const bool had = crowd.get(h, &d0).isOk();
        const bool tint = in.u8() & 1;
        const uint8_t layer = in.u8();
        s = tint ? crowd.setColor(h, glm::u8vec4(in.u8(), in.u8(), in.u8(), in.u8()))
                 : crowd.setCustomLayer(h, layer);
        if (s.isOk() && had && crowd.get(h, &d1).isOk() &&
            (tint ? d1.custom_layer != d0.custom_layer
                  : d1.custom_layer != layer || d1.color != d0.color))
          fail("setColor or setCustomLayer changed the other");
        break;
      }
      case 7: {  // Variation, root motion, and live poses (hostile matrices, counts).
        const uint8_t call = in.u8() % 4;
        if (call == 0) {
          s = crowd.setVariationMask(h, in.u32());
        } else if (call == 1) {
          s = crowd.setRootMotion(h, in.u8() & 1);
        } else if (call == 2) {
          s = si::fuzz::setFuzzedLivePose(crowd, h, palette(), in);
        } else {
          s = crowd.clearLivePose(h, in.u8() < 128 ? 0.0 : in.f64());
        }
        break;
      }
      case 8: {
        std::vector<float> lines(in.u8() % 4);
        for (float& l : lines) l = in.f32();
        s = crowd.setLodDistances(lines, in.f32());
        break;
      }
      case 9: {
        const si::Camera camera = si::Camera::lookAt(
            glm::dvec3(in.f64(), in.f64(), in.f64()), glm::dvec3(in.f64(), in.f64(), in.f64()),
            glm::vec3(0, 1, 0), in.f32(), in.f32(), in.f32(), in.f32());
        // Sometimes through a ParallelFor that runs the tasks last first (an engine's may).
        const si::ParallelFor backwards = [](uint32_t n, const si::ParallelTask& t) {
          for (uint32_t i = n; i-- > 0;) t(i);
        };
        const double dt = in.f64();
        s = in.u8() & 1 ? crowd.update(dt, camera, backwards) : crowd.update(dt, camera);
        if (s.isOk()) checkFrame(crowd);
        // Markers: hostile clips and times are refused; events name live instances and markers.
        if (in.u8() % 4 == 0) (void)crowd.addClipMarker(in.u8() % (clips + 1), in.f64(), "m");
        if (s.isOk())  // A refused update keeps the last frame's events (of older instances).
          for (const si::AnimationEvent& e : crowd.events())
            if (!crowd.contains(e.instance) || e.marker >= crowd.clipMarkers().size() ||
                e.count == 0)
              fail("an event names a dead instance, an unknown marker or no pass");
        break;
      }
      case 10: {  // Overlays and blends: clip, mask, space sometimes out of range, hostile values.
        const uint8_t which_call = in.u8() % 6;
        if (which_call == 0)
          s = crowd.playOverlay(h, in.u8() % (clips + 1), in.u8() % (masks + 1), in.f32(),
                                in.f64(), in.f64(), in.f32());
        else if (which_call == 1)
          s = crowd.stopOverlay(h, in.f64());
        else if (which_call == 2)
          s = crowd.playBlend(h, in.u8() % (spaces + 1), in.f32(), in.f64(), in.f64(), in.f32());
        else if (which_call == 3)
          s = crowd.setBlendParameter(h, in.f32());
        else if (which_call == 4)
          s = crowd.playBlend(h, in.u8() % (spaces + 1), glm::vec2(in.f32(), in.f32()), in.f64(),
                              in.f64(), in.f32());
        else
          s = crowd.setBlendParameter(h, glm::vec2(in.f32(), in.f32()));
        uint32_t space = 0;
        glm::vec2 parameter(0.0f);
        double phase = 0.0;
        if (crowd.blendState(h, &space, &parameter, &phase).isOk() &&
            (space >= spaces || !(parameter.x >= 0.0f && parameter.x <= 1.0f) ||
             !(parameter.y >= 0.0f && parameter.y <= (space == 1 ? 1.0f : 0.0f)) ||
             !(phase >= 0.0 && phase < 1.0)))
          fail("a blend's state is out of its space");
        break;
      }
      case 11:  // Props: a hostile socket and mesh attached to a copy of the character.
        attachFuzzedProp(character(), in, fail);
        break;
      default: {  // Queries change nothing.
        si::InstanceDesc d;
        uint32_t lod = 0;
        glm::dmat4 m;
        (void)crowd.get(h, &d);
        (void)crowd.view().lodOf(h, &lod);
        if (crowd.jointMatrix(h, in.u8() % 4, &m).isOk())  // The overlay composed too.
          for (int c = 0; c < 4; ++c)
            for (int r = 0; r < 4; ++r)
              if (!std::isfinite(m[c][r])) fail("a joint matrix is not finite");
        // A socket on any joint (sometimes past the skeleton), its frame finite or not.
        si::Socket socket;
        socket.joint = in.u8() % 4;
        for (int c = 0; c < 4; ++c)
          for (int r = 0; r < 3; ++r)
            socket.bind_frame[c][r] = in.u8() < 16 ? in.f32() : 0.25f * float(c == r);
        bool finite_frame = true;
        for (int c = 0; c < 4; ++c)
          for (int r = 0; r < 4; ++r)
            finite_frame = finite_frame && std::isfinite(socket.bind_frame[c][r]);
        const si::Status st = crowd.socketTransform(h, socket, &m);
        if (!st.isOk() && st.message().empty()) fail("a refused socketTransform has no message");
        if (st.isOk() && finite_frame)
          for (int c = 0; c < 4; ++c)
            for (int r = 0; r < 4; ++r)
              if (!std::isfinite(m[c][r])) fail("a socket transform is not finite");
        si::fuzz::fuzzLocalPose(crowd, h, character().skeleton, in, fail);
        if (!(snapshot(crowd) == before)) fail("a query changed the crowd");
        break;
      }
    }
    checkChanges(crowd, before);
    if (kind <= 10 && !s.isOk()) {
      if (s.message().empty()) fail("a rejected call has no message");
      if (!(snapshot(crowd) == before)) fail("a rejected call changed the crowd");
    }
    // Every live handle resolves, released ones do not, the size matches.
    if (crowd.size() != live.size()) fail("the size does not match the live handles");
    for (si::InstanceHandle l : live) {
      si::InstanceDesc d;
      if (!crowd.contains(l) || !crowd.get(l, &d).isOk()) fail("a live handle does not resolve");
    }
    for (si::InstanceHandle r : released)
      if (crowd.contains(r)) fail("a released handle resolves");
  }
  return 0;
}
