// SkinnedInstancing - SPDX-License-Identifier: MIT (see LICENSE)
// Depth only (shadow maps, depth pre-passes, transform feedback capture).
void main() {}
