// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// Where drawCrowd left recent selections' records in the record ring. A frame with motion
// vectors reads its previous records (the view's previous selection's records, byte for byte)
// where the draw of that selection wrote them, while that region survives, instead of copying
// them into its own region again (80 bytes per instance and frame); each slot's index is then
// the record's 16-byte word there (InstanceBatcher::buildRecordPlaces).

#include <cstddef>
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "crowd/ring_frame.h"
#include "gl/resources/record_ring.h"

namespace si::detail {

/// One draw's records in the ring.
struct DrawnRegion {
  uint64_t view = 0;             ///< CrowdView::identity().
  uint64_t selection = 0;        ///< CrowdView::selectionCount() when drawn.
  uint64_t serial = 0;           ///< RecordRing::serial() of the region.
  size_t records = 0;            ///< The records' byte offset in the ring (the region's start).
  size_t records_end = 0;        ///< The end of the records in the ring.
  bool complete = false;         ///< Every record of the selection has a place.
  std::vector<uint32_t> places;  ///< InstanceBatcher::buildRecordPlaces, from `records`.
};

/// The last kKept draws of views that keep previous records.
class DrawnRegions {
 public:
  static constexpr size_t kKept = 8;
  /// The region holding selection `selection` of view `view`, every record placed, that the
  /// current draw may read (RecordRing::canBorrow); null if none.
  const DrawnRegion* find(uint64_t view, uint64_t selection, const RecordRing& ring) const;
  /// Keeps where this draw of `view` (its last selection) wrote its records: the region of
  /// `ring`'s current serial, from byte `records` to `records_end`. It replaces the entry of
  /// the same selection, else one whose region is gone, else the oldest. The batcher's status.
  Status keep(const InstanceBatcher& batcher, const CrowdView& view, const RecordRing& ring,
              size_t records, size_t records_end);
  void clear() { regions_.clear(); }

 private:
  std::vector<DrawnRegion> regions_;
};

/// drawCrowd's plan and the ring reserved for it. With motion, the previous records come from
/// `regions`' region of the view's previous selection (`*previous`, else null) when the draw
/// may read it (RecordRing::canBorrow) and the whole ring fits one storage binding
/// (`storage_limit`); otherwise they are copied. kLimitExceeded when copied indices and records,
/// or the instance handles, exceed `storage_limit`.
Status reserveRingFrame(const InstanceBatcher& batcher, const CrowdView& view, uint32_t alignment,
                        const RingContents& contents, uint64_t storage_limit,
                        const DrawnRegions& regions, RecordRing* ring, RingFrame* plan,
                        const DrawnRegion** previous);

/// What the shaders' previous-record binding covers (shaders/previous_index.glsl): `bytes` of
/// the ring from `base`; in 16-byte words from there, the indices' first word, the previous
/// records' base word and the words per index step (5: records copied, indexed by number; 1:
/// indices are words).
struct PreviousBinding {
  size_t base = 0, bytes = 0;
  glm::uvec3 words{0u};
};
/// For `plan` written at ring byte `base`, its previous records copied or in `previous`.
PreviousBinding previousBinding(const RingFrame& plan, size_t base, const DrawnRegion* previous);

}  // namespace si::detail
