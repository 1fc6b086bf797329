// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once

/// \file
/// si::core: the data model of skinned instancing (skeleton, clips, skinned meshes with
/// sub-meshes and LODs), the double-precision reference evaluator and the embedded character.
/// GLM and the standard library only: no GL, no file IO.
///
/// Usage:
/// \code
///   #include "si/core/core.h"
///   si::Character c;
///   if (!si::makeDefaultCharacter({}, &c).isOk()) return 1;
///   si::ReferencePose pose;
///   si::Status s = si::evaluatePose(c.skeleton, c.clips[c.findClip("walk")], 0.5, &pose);
///   // pose.skinning[j] maps bind-pose vertices weighted to joint j to their posed positions.
/// \endcode

#include "si/core/baked_palette.h"
#include "si/core/bounds.h"
#include "si/core/character.h"
#include "si/core/clip.h"
#include "si/core/default_character.h"
#include "si/core/log.h"
#include "si/core/layer_mask.h"
#include "si/core/lod_error.h"
#include "si/core/palette_layout.h"
#include "si/core/part_lod.h"
#include "si/core/reference_evaluator.h"
#include "si/core/shader_inputs.h"
#include "si/core/skeleton.h"
#include "si/core/skinned_mesh.h"
#include "si/core/span.h"
#include "si/core/status.h"
#include "si/core/transform.h"
