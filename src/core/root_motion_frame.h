// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// The ground frame of a joint's model matrix, for root motion (si/core/root_motion.h): shared
// by the reference evaluator, which takes the motion out of a clip's poses, and the baker's
// root motion samples.

#include <glm/glm.hpp>

#include "si/core/root_motion.h"

namespace si::detail {

/// The yaw of a model matrix: the twist about +Y of its rotation part (columns normalized,
/// a mirror undone), in (-pi, pi]; 0 for a zero-scale matrix or one turned upside down.
double groundYaw(const glm::dmat4& model);

/// M = G(t) * G(0)^-1 for the ground frames G = T(x, 0, z) * R_y(groundYaw) of a joint's model
/// matrices at clip time 0 and t; the yaw wrapped into (-pi, pi].
GroundMotion groundMotionBetween(const glm::dmat4& model_at_start, const glm::dmat4& model_at_t);

}  // namespace si::detail
