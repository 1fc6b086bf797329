// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// The embedded procedural humanoid: capsules skinned with smooth weights where pieces meet,
// a 64x64 texture whose alpha is the tint mask; its clips are default_clips.cpp's.
#include "si/core/default_character.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>

#include "core/default_skeleton.h"
#include "si/core/lod_error.h"

namespace si {
namespace {

using namespace detail::embedded;  // The skeleton (core/default_skeleton.h).

// Texture tiles (a 4x4 grid of 16x16 texels); alpha 255 marks tintable cloth.
enum Tile : int { kSkin, kShirt, kTrousers, kBoots, kMetal, kWood, kShieldFace, kHair };

struct Part {
  int joint;          // The joint the piece is attached to.
  int blend_start;    // Joint blended in near `a` (its parent side), or -1.
  int blend_end;      // Joint blended in near `b` (its child side), or -1.
  glm::dvec3 a, b;    // Capsule axis end points (equal for a sphere).
  double radius;
  double cap_scale;   // Axial extent of the end caps relative to the radius.
  int tile;
};

struct LodShape {
  int segments, cap_rings, rings;
};
// Body triangles: about 4100, 1140 and 230 (see the header).
constexpr std::array<LodShape, 3> kLodShapes = {{{12, 3, 4}, {6, 2, 2}, {3, 1, 1}}};

struct SubMeshDef {
  const char* name;
  std::vector<Part> parts;
};

std::vector<SubMeshDef> subMeshDefs() {
  const auto P = [](int j) { return kJoints[size_t(j)].position; };
  const glm::dvec3 x(1, 0, 0), y(0, 1, 0), z(0, 0, 1);
  std::vector<SubMeshDef> defs;
  defs.push_back({"body",
                  {
                      {kPelvis, -1, kSpine, P(kPelvis) - 0.08 * y, P(kSpine) - 0.04 * y, 0.14, 1, kTrousers},
                      {kSpine, kPelvis, kChest, P(kSpine), P(kChest), 0.13, 1, kShirt},
                      {kChest, kSpine, kNeck, P(kChest), P(kNeck) - 0.06 * y, 0.16, 1, kShirt},
                      {kNeck, kChest, kHead, P(kNeck) - 0.03 * y, P(kHead), 0.05, 1, kSkin},
                      {kHead, kNeck, -1, P(kHead) + 0.08 * y, P(kHead) + 0.13 * y + 0.01 * z, 0.1, 1, kHair},
                      {kLClavicle, kChest, kLUpperArm, P(kLClavicle), P(kLUpperArm), 0.05, 1, kShirt},
                      {kLUpperArm, kLClavicle, kLForearm, P(kLUpperArm), P(kLForearm), 0.05, 1, kShirt},
                      {kLForearm, kLUpperArm, kLHand, P(kLForearm), P(kLHand), 0.045, 1, kSkin},
                      {kLHand, kLForearm, -1, P(kLHand), P(kLHand) - 0.1 * y, 0.04, 1, kSkin},
                      {kRClavicle, kChest, kRUpperArm, P(kRClavicle), P(kRUpperArm), 0.05, 1, kShirt},
                      {kRUpperArm, kRClavicle, kRForearm, P(kRUpperArm), P(kRForearm), 0.05, 1, kShirt},
                      {kRForearm, kRUpperArm, kRHand, P(kRForearm), P(kRHand), 0.045, 1, kSkin},
                      {kRHand, kRForearm, -1, P(kRHand), P(kRHand) - 0.1 * y, 0.04, 1, kSkin},
                      {kLThigh, kPelvis, kLShin, P(kLThigh), P(kLShin), 0.075, 1, kTrousers},
                      {kLShin, kLThigh, kLFoot, P(kLShin), P(kLFoot), 0.06, 1, kTrousers},
                      {kLFoot, kLShin, -1, P(kLFoot) - 0.04 * y - 0.03 * z, P(kLFoot) - 0.04 * y + 0.14 * z, 0.045, 1, kBoots},
                      {kRThigh, kPelvis, kRShin, P(kRThigh), P(kRShin), 0.075, 1, kTrousers},
                      {kRShin, kRThigh, kRFoot, P(kRShin), P(kRFoot), 0.06, 1, kTrousers},
                      {kRFoot, kRShin, -1, P(kRFoot) - 0.04 * y - 0.03 * z, P(kRFoot) - 0.04 * y + 0.14 * z, 0.045, 1, kBoots},
                  }});
  const glm::dvec3 helmet = P(kHead) + 0.125 * y + 0.01 * z;
  defs.push_back({"helmet", {{kHead, -1, -1, helmet, helmet + 0.02 * y, 0.125, 0.9, kMetal}}});
  const glm::dvec3 shield = P(kLShield);
  defs.push_back({"shield", {{kLShield, -1, -1, shield, shield + 0.02 * x, 0.2, 0.15, kShieldFace}}});
  const glm::dvec3 grip = P(kRWeapon);
  defs.push_back({"spear",
                  {{kRWeapon, -1, -1, grip - 0.55 * y, grip + 1.05 * y, 0.014, 1, kWood},
                   {kRWeapon, -1, -1, grip + 1.1 * y, grip + 1.12 * y, 0.03, 3, kMetal}}});
  return defs;
}

// Appends one capsule (or ellipsoidal sphere) to the mesh with smooth weights along its axis.
void appendCapsule(const Part& part, const LodShape& shape, SkinnedMesh* mesh) {
  const glm::dvec3 axis_vec = part.b - part.a;
  const double length = glm::length(axis_vec);
  const glm::dvec3 axis = length > 1e-9 ? axis_vec / length : glm::dvec3(0, 1, 0);
  // Two unit vectors perpendicular to the axis.
  const glm::dvec3 helper = std::fabs(axis.y) < 0.9 ? glm::dvec3(0, 1, 0) : glm::dvec3(0, 0, 1);
  const glm::dvec3 e1 = glm::normalize(glm::cross(helper, axis));
  const glm::dvec3 e2 = glm::cross(axis, e1);

  struct Row {
    glm::dvec3 center;
    double axial;   // Normal's component along the axis (sin of latitude).
    double radial;  // Ring radius factor (cos of latitude).
  };
  std::vector<Row> rows;
  for (int k = 0; k <= shape.cap_rings; ++k) {  // Bottom cap, pole first.
    const double phi = -kPi / 2 + (kPi / 2) * k / shape.cap_rings;
    rows.push_back({part.a + axis * (part.radius * part.cap_scale * std::sin(phi)), std::sin(phi),
                    std::cos(phi)});
  }
  for (int k = 1; k < shape.rings; ++k)
    rows.push_back({part.a + axis_vec * (double(k) / shape.rings), 0.0, 1.0});
  for (int k = 0; k <= shape.cap_rings; ++k) {  // Top cap, pole last.
    const double phi = (kPi / 2) * k / shape.cap_rings;
    rows.push_back({part.b + axis * (part.radius * part.cap_scale * std::sin(phi)), std::sin(phi),
                    std::cos(phi)});
  }

  const uint32_t base = static_cast<uint32_t>(mesh->positions.size());
  const int cols = shape.segments + 1;
  const double tile_u = (part.tile % 4) * 0.25, tile_v = (part.tile / 4) * 0.25;
  const double inset = 1.0 / 64.0;  // One texel of the 64x64 texture.
  for (size_t r = 0; r < rows.size(); ++r) {
    const Row& row = rows[r];
    for (int c = 0; c < cols; ++c) {
      const double theta = 2 * kPi * c / shape.segments;
      const glm::dvec3 radial = std::cos(theta) * e1 + std::sin(theta) * e2;
      const glm::dvec3 p = row.center + radial * (part.radius * row.radial);
      // Normal of the ellipsoidal cap: gradient of the scaled sphere.
      glm::dvec3 n = radial * row.radial + axis * (row.axial / part.cap_scale);
      n = glm::normalize(n);
      mesh->positions.push_back(glm::vec3(p));
      mesh->normals.push_back(glm::vec3(n));
      const double u = double(c) / shape.segments;
      const double v = double(r) / double(rows.size() - 1);
      mesh->texcoords.push_back(glm::vec2(tile_u + inset + u * (0.25 - 2 * inset),
                                          tile_v + inset + v * (0.25 - 2 * inset)));

      // Weights: half to the neighbour joint at either end, fading in over the last 30 %.
      const double s = length > 1e-9 ? glm::dot(p - part.a, axis) / length : 0.5;
      double w_start = part.blend_start >= 0 ? 0.5 * (1.0 - smoothstep(0.0, 0.3, s)) : 0.0;
      double w_end = part.blend_end >= 0 ? 0.5 * smoothstep(0.7, 1.0, s) : 0.0;
      const double w_self = 1.0 - w_start - w_end;
      std::array<std::pair<int, double>, 3> infl = {
          {{part.joint, w_self}, {part.blend_start, w_start}, {part.blend_end, w_end}}};
      std::sort(infl.begin(), infl.end(), [](const auto& l, const auto& rr) {
        return l.second > rr.second || (l.second == rr.second && l.first < rr.first);
      });
      glm::u16vec4 joints(0);
      glm::vec4 weights(0.0f);
      float sum = 0.0f;
      for (int i = 0; i < 3; ++i) {
        if (infl[size_t(i)].second <= 0.0 || infl[size_t(i)].first < 0) continue;
        joints[i] = static_cast<uint16_t>(infl[size_t(i)].first);
        weights[i] = static_cast<float>(infl[size_t(i)].second);
        sum += weights[i];
      }
      weights /= sum;  // Exactly normalized in float.
      mesh->joints.push_back(joints);
      mesh->weights.push_back(weights);
    }
  }
  // Triangles, counter-clockwise seen from outside; pole strips emit one triangle per quad.
  const int nrows = static_cast<int>(rows.size());
  for (int r = 0; r + 1 < nrows; ++r) {
    const bool bottom_pole = r == 0, top_pole = r + 1 == nrows - 1;
    for (int c = 0; c < shape.segments; ++c) {
      const uint32_t i00 = base + uint32_t(r * cols + c), i01 = i00 + 1;
      const uint32_t i10 = i00 + uint32_t(cols), i11 = i10 + 1;
      if (!top_pole) mesh->indices.insert(mesh->indices.end(), {i00, i11, i10});
      if (!bottom_pole) mesh->indices.insert(mesh->indices.end(), {i00, i01, i11});
    }
  }
}

void makeTexture(Image* image) {
  image->width = 64;
  image->height = 64;
  image->rgba8.assign(64 * 64 * 4, 0);
  struct TileLook {
    uint8_t r, g, b, a;
  };
  const TileLook looks[8] = {
      {224, 172, 140, 0},    // skin
      {235, 235, 235, 255},  // shirt: light so the tint shows
      {150, 150, 160, 255},  // trousers: darker, tinted too
      {70, 45, 30, 0},       // boots
      {170, 175, 185, 0},    // metal
      {130, 90, 50, 0},      // wood
      {240, 240, 240, 255},  // shield face (rim untinted below)
      {60, 40, 25, 0},       // hair
  };
  for (uint32_t py = 0; py < 64; ++py)
    for (uint32_t px = 0; px < 64; ++px) {
      const int tile = int(py / 16) * 4 + int(px / 16);
      TileLook look = tile < 8 ? looks[tile] : TileLook{255, 0, 255, 0};
      const uint32_t lx = px % 16, ly = py % 16;
      if (tile == kShirt && (ly / 2) % 4 == 0) {  // Stripes: untinted, slightly darker.
        look = {200, 200, 200, 0};
      }
      if (tile == kShieldFace && (lx < 2 || lx > 13 || ly < 2 || ly > 13)) look = looks[kMetal];
      if (tile == kHair && ly < 6) look = looks[kSkin];  // Face at the bottom of the head tile.
      uint8_t* t = &image->rgba8[(size_t(py) * 64 + px) * 4];
      t[0] = look.r;
      t[1] = look.g;
      t[2] = look.b;
      t[3] = look.a;
    }
}

}  // namespace

DefaultCharacterDesc resolveDefaults(const DefaultCharacterDesc& desc) {
  DefaultCharacterDesc d = desc;
  if (d.lod_count == 0) d.lod_count = 3;
  return d;
}

Status makeDefaultCharacter(const DefaultCharacterDesc& in_desc, Character* out) {
  if (out == nullptr) return {StatusCode::kInvalidArgument, "makeDefaultCharacter: out is null"};
  const DefaultCharacterDesc desc = resolveDefaults(in_desc);
  if (desc.lod_count > kLodShapes.size())
    return {StatusCode::kOutOfRange, "DefaultCharacterDesc.lod_count must be 0 to 3"};

  Character c;
  c.name = "si_default_humanoid";
  Skeleton& sk = c.skeleton;
  for (int j = 0; j < kJointCount; ++j) {
    const JointDef& def = kJoints[size_t(j)];
    sk.joint_names.push_back(def.name);
    sk.parents.push_back(def.parent);
    Transform rest;
    rest.translation = glm::vec3(restOffset(j));
    sk.rest_pose.push_back(rest);
    // Model-space bind matrix is a pure translation (rest rotations are identity).
    sk.inverse_bind_matrices.push_back(
        glm::mat4(1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, -glm::vec3(def.position).x,
                  -glm::vec3(def.position).y, -glm::vec3(def.position).z, 1));
  }

  for (const SubMeshDef& def : subMeshDefs()) {
    SubMesh sm;
    sm.name = def.name;
    for (uint32_t l = 0; l < desc.lod_count; ++l) {
      IndexRange range;
      range.first_index = static_cast<uint32_t>(c.mesh.indices.size());
      for (const Part& part : def.parts) appendCapsule(part, kLodShapes[l], &c.mesh);
      range.index_count = static_cast<uint32_t>(c.mesh.indices.size()) - range.first_index;
      sm.lods.push_back(range);
    }
    c.mesh.sub_meshes.push_back(sm);
  }

  c.clips = detail::embedded::defaultClips(desc.moving_clips);
  c.materials.push_back(Material{"character", glm::vec4(1.0f), 0});
  c.images.emplace_back();
  makeTexture(&c.images.back());

  Status s = measureLodErrors(&c.mesh, true);  // Each LOD's distance from LOD 0, bind pose.
  if (s.isOk()) s = c.validate();
  if (!s.isOk()) return s;  // Guards the generator itself; covered by tests.
  *out = std::move(c);
  return Status::ok();
}

}  // namespace si
