// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#include "crowd_bench/bench_scene.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <utility>

#include "crowd_bench/gpu_passes_table.h"
#include "si/crowd/crowd_manager.h"
#include "si/crowd/instance_batcher.h"

namespace si::bench {
double msSince(Clock::time_point t) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t).count();
}

std::string LodChoice::name() const {
  if (fixed_lod >= 0) return "lod" + std::to_string(fixed_lod);
  if (mode == LodMode::kDistance) return "distance";
  char buf[32];
  std::snprintf(buf, sizeof(buf), "screen%gpx", double(pixel_budget));
  return buf;
}

std::vector<glm::dvec3> scenePositions(const std::string& scene, uint32_t count) {
  std::vector<glm::dvec3> p;
  p.reserve(count);
  if (scene == "field" || scene == "plaza") {
    const double spacing = scene == "field" ? 1.5 : 1.2;
    const uint32_t side = uint32_t(std::ceil(std::sqrt(double(count))));
    for (uint32_t i = 0; i < count; ++i) {
      glm::dvec3 q = glm::dvec3(i % side, 0, i / side) * spacing;
      if (scene == "plaza") {  // Milling about: up to 0.4 m off the grid, no straight aisles.
        const uint32_t h = (i + 1u) * 2654435761u;
        q.x += 0.4 * (double(h & 0xFFFFu) / 65535.0 * 2.0 - 1.0);
        q.z += 0.4 * (double(h >> 16) / 65535.0 * 2.0 - 1.0);
      }
      p.push_back(q);
    }
    return p;
  }
  for (uint32_t tier = 0; p.size() < count; ++tier) {
    const double radius = 40.0 + tier * 1.0;
    const uint32_t seats = uint32_t(2.0 * 3.14159265358979 * radius / 0.9);
    for (uint32_t s = 0; s < seats && p.size() < count; ++s) {
      const double a = 2.0 * 3.14159265358979 * s / seats;
      p.push_back(glm::dvec3(radius * std::cos(a), tier * 0.5, radius * std::sin(a)));
    }
  }
  return p;
}

Camera cameraAt(const Setup& setup, const std::string& scene,
                const std::vector<glm::dvec3>& positions, uint32_t f, uint32_t n) {
  const float aspect = float(setup.width) / float(setup.height);
  const double t = n > 1 ? double(f) / double(n - 1) : 0.0;
  Camera cam;
  if (scene == "field") {
    glm::dvec3 lo(1e30), hi(-1e30);
    for (const glm::dvec3& q : positions) lo = glm::min(lo, q), hi = glm::max(hi, q);
    const glm::dvec3 c = 0.5 * (lo + hi);
    const double r = std::max(10.0, glm::length(hi - lo) * 0.75);
    const double a = 0.3 + 0.5 * t;
    cam = Camera::lookAt(c + glm::dvec3(r * std::cos(a), r * 0.8, r * std::sin(a)), c,
                         glm::vec3(0, 1, 0), 0.9f, aspect, 1.0f, float(r * 4));
  } else if (scene == "plaza") {
    double side = 0.0;
    for (const glm::dvec3& q : positions) side = std::max(side, q.x);
    const double a = (t - 0.5) * 0.6;  // Panning 34 degrees across the crowd.
    const glm::dvec3 eye(side * 0.5, 1.7, -4.0);
    cam = Camera::lookAt(eye, eye + glm::dvec3(std::sin(a), -0.05, std::cos(a)), glm::vec3(0, 1, 0),
                         1.0f, aspect, 0.3f, 5000.0f);
  } else {
    const double a = 6.28318530718 * t * 0.25;
    cam = Camera::lookAt({0, 6, 0}, {std::cos(a) * 40, 8, std::sin(a) * 40}, glm::vec3(0, 1, 0),
                         1.2f, aspect, 0.5f, 1000.0f);
  }
  cam.viewport_height_pixels = float(setup.height / std::max(1u, setup.supersample));
  return cam;
}

Status makeCrowd(const Setup& setup, const BakedPalette& palette,
                 const std::vector<glm::dvec3>& positions, const LodChoice& lod,
                 CrowdManager* crowd, std::vector<InstanceHandle>* handles, uint32_t sub_mesh_count,
                 uint32_t live_poses) {
  CrowdDesc cd;
  cd.live_pose_capacity = live_poses;
  cd.palette = &palette;
  cd.sub_mesh_count =
      sub_mesh_count > 0 ? sub_mesh_count : uint32_t(setup.character.mesh.sub_meshes.size());
  cd.lod_count = uint32_t(setup.character.mesh.maxLodCount());
  cd.max_distance_radii = -1.0f;  // Measure everything in view, however far.
  cd.lod_errors_units = setup.lod_errors;
  cd.impostor_lod = setup.impostor ? cd.lod_count - 1 : 0;
  cd.lod_mode = lod.fixed_lod >= 0 ? LodMode::kDistance : lod.mode;
  cd.pixel_error_budget = lod.pixel_budget;
  if (lod.fixed_lod >= 0)  // Lines before the level at (almost) zero, after it out of reach.
    for (uint32_t l = 1; l < cd.lod_count; ++l)
      cd.lod_distances_radii.push_back(int(l) <= lod.fixed_lod ? 1e-6f * float(l) : 1e7f * float(l));
  Status s = crowd->init(cd);
  RandomCrowdDesc rc;
  rc.positions = positions;
  rc.seed = 2026;
  rc.optional_mask = 0xE;
  if (s.isOk()) s = crowd->addRandom(rc, handles);
  return s;
}

bool isGpuSelected(const std::string& path) { return path.compare(0, 4, "gpu-") == 0; }

Status stepCrowd(CrowdManager& crowd, const std::string& path, const Camera& camera, double dt) {
  return isGpuSelected(path) ? crowd.advance(dt) : crowd.update(dt, camera);
}

Status drawPath(Renderer& renderer, const CrowdManager& crowd, InstanceBatcher& batcher,
                const std::string& path, const Camera& camera, DrawStats* stats) {
  renderer.clear(kClearColor);
  return drawKind(renderer, CharacterId{}, crowd, batcher, path, camera, stats);
}

Status drawKind(Renderer& renderer, CharacterId id, const CrowdManager& crowd,
                InstanceBatcher& batcher, const std::string& path, const Camera& camera,
                DrawStats* stats) {
  if (isGpuSelected(path)) {
    const bool occlusion = path.size() > 10 && path.compare(path.size() - 10, 10, "-occlusion") == 0;
    renderer.setGpuOcclusionCulling(occlusion);
    const DrawMode mode = path.compare(0, 10, "gpu-driven") == 0 ? DrawMode::kComputeSkinned
                                                                 : DrawMode::kSkinned;
    const Status s = renderer.drawCrowdGpuCulled(id, crowd.view(), camera, stats, mode);
    renderer.setGpuOcclusionCulling(false);
    return s;
  }
  if (path == "traditional") return renderer.drawTraditional(id, crowd.view(), camera, stats);
  if (path == "cpu") return renderer.drawCpuSkinned(id, crowd.view(), camera, stats);
  const DrawMode mode = path == "compute" ? DrawMode::kComputeSkinned
                        : path == "rigid" ? DrawMode::kRigid
                                          : DrawMode::kSkinned;
  return renderer.drawCrowd(id, crowd.view(), batcher, camera, stats, mode);
}

Status runPath(Setup& setup, Renderer& renderer, const BakedPalette& palette,
               const std::string& scene, uint32_t count, const std::string& path,
               const LodChoice& lod, Row* row) {
  CrowdManager crowd;
  const std::vector<glm::dvec3> positions = scenePositions(scene, count);
  Status s = makeCrowd(setup, palette, positions, lod, &crowd);
  if (!s.isOk()) return s;
  row->scene = scene;
  row->lod = lod.name();
  s = timeCrowd(setup, renderer, crowd, scene, positions, path, row);
  std::vector<uint8_t> rgba;
  if (s.isOk()) s = setup.context->readPixels(&rgba);
  if (!s.isOk()) return s;
  row->covered_pixels = coveredPixels(rgba);
  return Status();
}

Status timeCrowd(Setup& setup, Renderer& renderer, CrowdManager& crowd, const std::string& scene,
                 const std::vector<glm::dvec3>& places, const std::string& path, Row* row,
                 const StepFrame& step) {
  InstanceBatcher batcher;
  const Status s = batcher.init(renderer.batchLimits());
  if (!s.isOk()) return s;
  row->path = path;
  row->instances = uint32_t(places.size());
  PassCollector passes(renderer);
  uint32_t frame = 0;
  const Status timed = timeFrames(
      setup, scene, places, step ? step : StepFrame([&](const Camera& cam) {
        return stepCrowd(crowd, path, cam, 1.0 / 60.0);
      }),
      [&](const Camera& cam, DrawStats* st, uint32_t* visible) {
        const Status drawn = drawPath(renderer, crowd, batcher, path, cam, st);
        *visible = isGpuSelected(path) ? st->gpu_visible : crowd.view().stats().visible;
        if (frame >= kWarmupFrames) {  // Measured frames only.
          passes.add(st->gpu_pass_ticket, frame);
          row->last = *st;
        }
        ++frame;
        return drawn;
      },
      row);
  passes.finish(row);
  // Without the blocking timer (--no-gpu-time), the GPU time is the pass stamps' (read late).
  if (row->gpu_ms < 0.0 && !row->pass_ms.empty()) row->gpu_ms = row->pass_total_ms;
  return timed;
}

Status timeFrames(const Setup& setup, const std::string& scene,
                  const std::vector<glm::dvec3>& places, const StepFrame& step,
                  const DrawFrame& draw, Row* row) {
  const uint32_t warmup = kWarmupFrames, n = setup.frames;
  std::vector<double> update_ms_v, submit_ms_v, gpu_ms_v;
  Status s;
  for (uint32_t f = 0; f < warmup + n && s.isOk(); ++f) {
    const Camera cam = cameraAt(setup, scene, places, f < warmup ? 0 : f - warmup, n);
    const auto t0 = Clock::now();
    s = step(cam);
    const double update_ms = msSince(t0);
    DrawStats st;
    uint32_t visible = 0;
    if (s.isOk()) s = draw(cam, &st, &visible);
    if (!s.isOk() || f < warmup) continue;
    update_ms_v.push_back(update_ms);
    submit_ms_v.push_back(st.cpu_submit_ms);
    gpu_ms_v.push_back(st.gpu_ms);
    row->visible = visible;
    row->draws = st.draw_calls;
    row->triangles = double(st.triangles);
  }
  // Medians: one stalled frame on a shared machine must not move the figure.
  row->update_ms = median(update_ms_v);
  row->submit_ms = median(submit_ms_v);
  row->gpu_ms = median(gpu_ms_v);
  return s;
}

Status timePaired(Setup& setup, Renderer& renderer, const BakedPalette& palette, uint32_t count,
                  const std::string& path, const std::function<Status(int)>& set, Row rows[2]) {
  const std::vector<glm::dvec3> places = scenePositions("field", count);
  CrowdManager crowd;
  Status s = makeCrowd(setup, palette, places, LodChoice(), &crowd);
  InstanceBatcher batcher;
  if (s.isOk()) s = batcher.init(renderer.batchLimits());
  std::vector<double> update, submit[2], gpu[2];
  const uint32_t warmup = kWarmupFrames, n = setup.frames;
  for (uint32_t f = 0; f < warmup + n && s.isOk(); ++f) {
    const Camera cam = cameraAt(setup, "field", places, f < warmup ? 0 : f - warmup, n);
    const auto t0 = Clock::now();
    s = stepCrowd(crowd, path, cam, 1.0 / 60.0);
    const double update_ms = msSince(t0);
    for (int k = 0; k < 2 && s.isOk(); ++k) {
      s = set(k);
      DrawStats st;
      if (s.isOk()) s = drawPath(renderer, crowd, batcher, path, cam, &st);
      if (f < warmup) continue;
      submit[k].push_back(st.cpu_submit_ms);
      gpu[k].push_back(st.gpu_ms);
      rows[k].visible = isGpuSelected(path) ? st.gpu_visible : crowd.view().stats().visible;
      rows[k].draws = st.draw_calls;
      rows[k].triangles = double(st.triangles);
    }
    if (f >= warmup) update.push_back(update_ms);
  }
  for (int k = 0; k < 2; ++k) {
    rows[k].path = path;
    rows[k].instances = count;
    rows[k].update_ms = median(update);
    rows[k].submit_ms = median(submit[k]);
    rows[k].gpu_ms = median(gpu[k]);
  }
  return s;
}

uint64_t coveredPixels(const std::vector<uint8_t>& rgba) {
  const glm::u8vec4 clear = glm::u8vec4(glm::round(kClearColor * 255.0f));
  uint64_t n = 0;
  for (size_t i = 0; i + 3 < rgba.size(); i += 4)
    n += rgba[i] != clear.r || rgba[i + 1] != clear.g || rgba[i + 2] != clear.b;
  return n;
}

double quantile(std::vector<double> v, double q) {
  if (v.empty()) return 0.0;
  const size_t at = std::min(v.size() - 1, size_t(q * double(v.size())));
  std::nth_element(v.begin(), v.begin() + std::ptrdiff_t(at), v.end());
  return v[at];
}

double median(std::vector<double> v) {
  return quantile(std::move(v), 0.5);
}

void printSideBySideHeader(const char* feature) {
  std::printf("%-11s %-6s %9s %9s %6s %9s %9s %9s %8s %8s", "path", feature, "instances",
              "visible", "draws", "update", "submit", "GPU ms", "CPU x", "GPU x");
}

void printSideBySideRow(const Row& r, const Row& off, const char* table, std::FILE* csv) {
  const double cpu_x = (r.update_ms + r.submit_ms) / std::max(1e-9, off.update_ms + off.submit_ms);
  std::printf("%-11s %-6s %9u %9u %6u %9.3f %9.3f %9.3f %8.2f", r.path.c_str(), r.lod.c_str(),
              r.instances, r.visible, r.draws, r.update_ms, r.submit_ms, r.gpu_ms, cpu_x);
  if (r.gpu_ms >= 0.0 && off.gpu_ms > 0.0) std::printf(" %8.2f", r.gpu_ms / off.gpu_ms);
  else std::printf(" %8s", "-");  // No GPU time (--no-gpu-time).
  std::fprintf(csv, "%s,field,%s,%u,%u,%u,%.0f,%.4f,%.4f,%.4f,,,,,%s,,,\n", table,
               r.path.c_str(), r.instances, r.visible, r.draws, r.triangles, r.update_ms,
               r.submit_ms, r.gpu_ms, r.lod.c_str());
}

}  // namespace si::bench
