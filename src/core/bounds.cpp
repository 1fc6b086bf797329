// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#include "si/core/bounds.h"

namespace si {

Aabb computeBounds(Span<const glm::vec3> points) {
  Aabb box;
  for (const glm::vec3& p : points) box.extend(p);
  return box;
}

}  // namespace si
