// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once

/// \file
/// Animated impostors: a character's far LOD drawn as one textured quad per instance. The
/// renderer draws the character into an atlas at upload (Renderer::buildImpostor): every view
/// direction of a ring of azimuths at a few elevations, for a reduced set of every clip's
/// frames, each cell holding the unlit base colour with the coverage, the normal with the tint
/// mask, and the metallic, roughness, occlusion and material index. At draw time each instance at
/// the crowd's impostor level (CrowdDesc::impostor_lod, si::appendImpostorLevel) shows the cell of
/// the view direction and frame nearest its own, lit by the renderer's light and tinted by its
/// colour as the mesh would be.
///
/// What the atlas keeps and loses:
/// - kept: the pose (nearest of the reduced frames, crossfades show the heavier clip; morph
///   targets at that frame's weights), the
///   view direction (nearest of azimuths x elevations), the base colour and material factors,
///   metallic, roughness, occlusion and material index (what a material reads: it lights an
///   impostor as it lights the mesh), the tint and its mask, the lighting (from the captured
///   normals), the instance's scale;
/// - lost: the variation parts (the atlas shows the parts of ImpostorDesc::variation_mask for
///   every instance), the custom texture layer, overlays (layered animation), the depth within
///   the character (the quad has one depth, at the character's centre) and, between the
///   captured views and frames, the in-between views and poses; emissive light; detail finer
///   than a texel of a cell (ImpostorDesc::cell_pixels; the capture is supersampled and
///   averaged, ImpostorDesc::capture_supersample, so thin parts stay as partial coverage, and
///   where two materials share a texel it takes one's code and values). Motion vectors
///   are not drawn for impostors (the draws return kUnsupported while they are on).
/// How much this changes the image is measured like every other level's error:
/// si::measureImageLodErrors with ImageLodErrorDesc::impostor.
///
/// \code
///   si::appendImpostorLevel(&character.mesh);
///   renderer.addCharacter(character, palette, &id);
///   renderer.buildImpostor(id, {}, &info);
///   crowd_desc.impostor_lod = uint32_t(character.mesh.maxLodCount()) - 1;
/// \endcode

#include "si/crowd/impostor_desc.h"
