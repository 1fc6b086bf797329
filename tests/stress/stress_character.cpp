// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#include "stress/stress_character.h"

#include <cmath>
#include <string>
#include <vector>

#include <glm/gtc/quaternion.hpp>

namespace si::test {

namespace {

constexpr double kTwoPi = 6.283185307179586;

// How much each joint moves: its three angles' amplitude (radians) and top frequency (Hz).
struct JointSpec {
  const char* name;
  int parent;
  float offset[3];  // Rest translation from the parent.
  float radius;     // Tube radius of the bone ending at this joint.
  float amplitude;
  float frequency;
  bool scales;      // Keyed with a uniform scale that varies.
};

const JointSpec kJoints[] = {
    {"hips", -1, {0.0f, 1.0f, 0.0f}, 0.0f, 0.25f, 0.8f, false},
    {"spine1", 0, {0.0f, 0.12f, 0.0f}, 0.15f, 0.2f, 0.9f, true},
    {"spine2", 1, {0.0f, 0.14f, 0.0f}, 0.16f, 0.2f, 0.9f, true},
    {"spine3", 2, {0.0f, 0.14f, 0.0f}, 0.17f, 0.2f, 0.9f, true},
    {"neck", 3, {0.0f, 0.12f, 0.0f}, 0.06f, 0.3f, 1.1f, false},
    {"head", 4, {0.0f, 0.2f, 0.0f}, 0.1f, 0.4f, 1.3f, false},
    {"clavicle_l", 3, {0.08f, 0.08f, 0.0f}, 0.05f, 0.2f, 1.0f, false},
    {"upperarm_l", 6, {0.14f, 0.0f, 0.0f}, 0.06f, 0.9f, 1.8f, false},
    {"forearm_l", 7, {0.28f, 0.0f, 0.0f}, 0.05f, 1.2f, 2.5f, false},
    {"hand_l", 8, {0.26f, 0.0f, 0.0f}, 0.04f, 0.8f, 2.2f, false},
    {"finger1a_l", 9, {0.08f, 0.0f, 0.02f}, 0.012f, 0.7f, 2.0f, false},
    {"finger1b_l", 10, {0.04f, 0.0f, 0.0f}, 0.01f, 0.7f, 2.0f, false},
    {"finger2a_l", 9, {0.08f, 0.0f, -0.02f}, 0.012f, 0.7f, 2.0f, false},
    {"finger2b_l", 12, {0.04f, 0.0f, 0.0f}, 0.01f, 0.7f, 2.0f, false},
    {"clavicle_r", 3, {-0.08f, 0.08f, 0.0f}, 0.05f, 0.2f, 1.0f, false},
    {"upperarm_r", 14, {-0.14f, 0.0f, 0.0f}, 0.06f, 0.9f, 1.8f, false},
    {"forearm_r", 15, {-0.28f, 0.0f, 0.0f}, 0.05f, 1.2f, 2.5f, false},
    {"hand_r", 16, {-0.26f, 0.0f, 0.0f}, 0.04f, 0.8f, 2.2f, false},
    {"finger1a_r", 17, {-0.08f, 0.0f, 0.02f}, 0.012f, 0.7f, 2.0f, false},
    {"finger1b_r", 18, {-0.04f, 0.0f, 0.0f}, 0.01f, 0.7f, 2.0f, false},
    {"finger2a_r", 17, {-0.08f, 0.0f, -0.02f}, 0.012f, 0.7f, 2.0f, false},
    {"finger2b_r", 20, {-0.04f, 0.0f, 0.0f}, 0.01f, 0.7f, 2.0f, false},
    {"thigh_l", 0, {0.1f, -0.05f, 0.0f}, 0.09f, 0.8f, 1.6f, false},
    {"shin_l", 22, {0.0f, -0.45f, 0.0f}, 0.07f, 1.2f, 2.5f, false},
    {"foot_l", 23, {0.0f, -0.42f, 0.0f}, 0.05f, 0.6f, 2.0f, false},
    {"toe_l", 24, {0.0f, -0.05f, 0.14f}, 0.03f, 0.5f, 2.0f, false},
    {"thigh_r", 0, {-0.1f, -0.05f, 0.0f}, 0.09f, 0.8f, 1.6f, false},
    {"shin_r", 26, {0.0f, -0.45f, 0.0f}, 0.07f, 1.2f, 2.5f, false},
    {"foot_r", 27, {0.0f, -0.42f, 0.0f}, 0.05f, 0.6f, 2.0f, false},
    {"toe_r", 28, {0.0f, -0.05f, 0.14f}, 0.03f, 0.5f, 2.0f, false},
    {"cape1", 3, {0.0f, 0.05f, -0.12f}, 0.04f, 0.4f, 1.5f, true},
    {"cape2", 30, {0.0f, -0.12f, -0.02f}, 0.04f, 0.5f, 1.7f, true},
    {"cape3", 31, {0.0f, -0.12f, -0.02f}, 0.04f, 0.6f, 1.9f, true},
    {"cape4", 32, {0.0f, -0.12f, -0.02f}, 0.04f, 0.7f, 2.1f, true},
    {"cape5", 33, {0.0f, -0.12f, -0.02f}, 0.04f, 0.8f, 2.3f, true},
    {"cape6", 34, {0.0f, -0.12f, -0.02f}, 0.04f, 0.9f, 2.5f, true},
};
constexpr size_t kJointCount = sizeof(kJoints) / sizeof(kJoints[0]);
constexpr uint32_t kSubMeshes = 30;
constexpr double kAngleJitter = 0.003, kTranslationJitter = 0.002;

// A deterministic value in [-1, 1] for (a, b, c).
double jitter(uint32_t a, uint32_t b, uint32_t c) {
  uint32_t h = a * 0x9E3779B1u ^ (b + 0x7F4A7C15u) * 0x85EBCA77u ^ (c + 0x165667B1u) * 0xC2B2AE3Du;
  h ^= h >> 15;
  h *= 0x2C1B3C6Du;
  h ^= h >> 12;
  h *= 0x297A2D39u;
  h ^= h >> 15;
  return double(h) / 2147483647.5 - 1.0;
}

// Angle `axis` of joint `j` at time t: three sines at frequency f, 0.61 f and 0.27 f with
// amplitudes A/2, A/3 and A/6 (|a| <= A, |da/dt| <= 2 pi f A (1/2 + 0.61/3 + 0.27/6)).
double angle(size_t j, int axis, double t, double scale) {
  const JointSpec& s = kJoints[j];
  const double a = s.amplitude * scale, f = s.frequency;
  const double phase = 1.7 * double(j) + 2.3 * axis;
  return a / 2 * std::sin(kTwoPi * f * t + phase) + a / 3 * std::sin(kTwoPi * 0.61 * f * t + 2 * phase) +
         a / 6 * std::sin(kTwoPi * 0.27 * f * t + 3 * phase);
}

glm::vec3 globalRest(size_t j) {
  glm::vec3 p(0.0f);
  for (int k = int(j); k >= 0; k = kJoints[k].parent)
    p += glm::vec3(kJoints[k].offset[0], kJoints[k].offset[1], kJoints[k].offset[2]);
  return p;
}

}  // namespace

double stressMaxAngularSpeed() {
  double top = 0.0;
  for (const JointSpec& s : kJoints)
    top = std::max(top, kTwoPi * s.frequency * s.amplitude * (0.5 + 0.61 / 3 + 0.27 / 6));
  return top;
}

Character makeStressCharacter(const StressDesc& desc) {
  Character c;
  c.name = "stress";
  Skeleton& sk = c.skeleton;
  for (size_t j = 0; j < kJointCount; ++j) {
    sk.joint_names.push_back(kJoints[j].name);
    sk.parents.push_back(kJoints[j].parent);
    Transform t;
    t.translation = glm::vec3(kJoints[j].offset[0], kJoints[j].offset[1], kJoints[j].offset[2]);
    sk.rest_pose.push_back(t);
    glm::mat4 ibm(1.0f);
    ibm[3] = glm::vec4(-globalRest(j), 1.0f);
    sk.inverse_bind_matrices.push_back(ibm);
  }

  // One tube per bone (parent -> joint), weighted to the parent's bone, blending into the
  // joint's near the far end and into the grandparent's near the near end.
  SkinnedMesh& m = c.mesh;
  const uint32_t rings = std::max(desc.rings, 2u), around = std::max(desc.around, 3u);
  std::vector<uint32_t> tube_first_index;
  for (size_t j = 1; j < kJointCount; ++j) {
    const int p = kJoints[j].parent;
    const int gp = kJoints[p].parent;
    const glm::vec3 a = globalRest(size_t(p)), b = globalRest(j);
    const glm::vec3 axis = glm::normalize(b - a);
    const glm::vec3 helper = std::fabs(axis.y) < 0.9f ? glm::vec3(0, 1, 0) : glm::vec3(1, 0, 0);
    const glm::vec3 u = glm::normalize(glm::cross(axis, helper)), v = glm::cross(axis, u);
    const uint32_t base = uint32_t(m.positions.size());
    tube_first_index.push_back(uint32_t(m.indices.size()));
    for (uint32_t r = 0; r < rings; ++r) {
      const float s = float(r) / float(rings - 1);
      float w_next = s > 0.7f ? 0.5f * (s - 0.7f) / 0.3f : 0.0f;
      float w_prev = gp >= 0 && s < 0.2f ? 0.3f * (0.2f - s) / 0.2f : 0.0f;
      for (uint32_t k = 0; k < around; ++k) {
        const float phi = float(kTwoPi) * float(k) / float(around);
        const glm::vec3 n = std::cos(phi) * u + std::sin(phi) * v;
        m.positions.push_back(a + s * (b - a) + kJoints[j].radius * n);
        m.normals.push_back(n);
        const bool tiny = (m.positions.size() % 9) == 0;
        glm::u16vec4 js(uint16_t(p), uint16_t(j), uint16_t(gp >= 0 ? gp : 0), 0);
        glm::vec4 ws(1.0f - w_next - w_prev, w_next, w_prev, tiny ? 1e-6f : 0.0f);
        ws.x -= ws.w;
        m.joints.push_back(js);
        m.weights.push_back(ws);
      }
    }
    for (uint32_t r = 0; r + 1 < rings; ++r)
      for (uint32_t k = 0; k < around; ++k) {
        const uint32_t i0 = base + r * around + k, i1 = base + r * around + (k + 1) % around;
        m.indices.insert(m.indices.end(), {i0, i1, i0 + around, i1, i1 + around, i0 + around});
      }
  }
  const size_t tubes = tube_first_index.size();
  tube_first_index.push_back(uint32_t(m.indices.size()));
  for (uint32_t s = 0; s < kSubMeshes; ++s) {
    const uint32_t first = tube_first_index[s * tubes / kSubMeshes];
    const uint32_t end = tube_first_index[(s + 1) * tubes / kSubMeshes];
    m.sub_meshes.push_back(
        SubMesh{"part" + std::to_string(s), {IndexRange{first, end - first}}, 0, {}});
  }

  Clip clip;
  clip.name = "mocap";
  clip.duration_seconds = desc.duration_seconds;
  clip.loop_mode = LoopMode::kOnce;
  clip.joint_tracks.resize(kJointCount);
  const uint32_t keys = uint32_t(std::floor(double(desc.duration_seconds) * desc.key_rate_hz)) + 1;
  for (size_t j = 0; j < kJointCount; ++j) {
    JointTracks& tr = clip.joint_tracks[j];
    for (auto* track : {&tr.translation, &tr.scale}) track->interpolation = Interpolation::kLinear;
    tr.rotation.interpolation = Interpolation::kLinear;
    const glm::vec3 rest(kJoints[j].offset[0], kJoints[j].offset[1], kJoints[j].offset[2]);
    for (uint32_t k = 0; k < keys; ++k) {
      const float tf = std::min(float(k) / desc.key_rate_hz, desc.duration_seconds);
      const double t = tf;
      glm::dvec3 ang;
      for (int a = 0; a < 3; ++a)
        ang[a] = angle(j, a, t, desc.motion_scale) + kAngleJitter * jitter(uint32_t(j), k, uint32_t(a));
      const glm::dquat q = glm::angleAxis(ang.x, glm::dvec3(1, 0, 0)) *
                           glm::angleAxis(ang.y, glm::dvec3(0, 1, 0)) *
                           glm::angleAxis(ang.z, glm::dvec3(0, 0, 1));
      glm::dvec3 offset(rest);
      if (j == 0)
        offset += glm::dvec3(0.05 * std::sin(kTwoPi * 0.9 * t), 0.05 * std::sin(kTwoPi * 1.8 * t),
                             0.03 * std::sin(kTwoPi * 0.4 * t));
      for (int a = 0; a < 3; ++a) offset[a] += kTranslationJitter * jitter(uint32_t(j), k, uint32_t(a + 3));
      const double sc = kJoints[j].scales ? 1.0 + 0.03 * std::sin(kTwoPi * 0.7 * t + double(j)) : 1.0;
      tr.translation.times_seconds.push_back(tf);
      tr.rotation.times_seconds.push_back(tf);
      tr.scale.times_seconds.push_back(tf);
      tr.translation.values.push_back(glm::vec3(offset));
      tr.rotation.values.push_back(glm::quat(q));
      tr.scale.values.push_back(glm::vec3(float(sc)));
    }
  }
  c.clips.push_back(std::move(clip));
  return c;
}

}  // namespace si::test
