// SkinnedInstancing - SPDX-License-Identifier: MIT (see LICENSE)
// Morph targets (with SI_MORPH_TARGETS; included by si_skinning.glsl): each vertex's run of
// entries in the morph texture (si::MorphStream) and each target's weight in the palette,
// stored per frame after the joints and interpolated exactly as the joints' rows are (then
// crossfaded towards clip B), added to the bind pose before skinning as si::emulateSkinning
// adds them. The vertex's morph word (si::VertexStream::morph_offset) names its run, ordered by
// effect, largest first; each entry carries its tail (how far it and those after it can move
// the vertex), and a LOD level stops at the first entry whose tail is within its cut.
//   SI_MORPH_BINDING [5]  the morph texture (RGBA32UI; the texture unit under OpenGL)
//   si_morph_info         SiPaletteInfo's second member (si::morphShaderInfo()): x log2 of the
//                         morph texture's width, y texels per entry, z where a frame's weights
//                         start, w the target count
//   si_morph_cuts         its last two (si::morphLodCuts()): each LOD level's cut, model units
// (The library's traditional baseline defines SI_MORPH_WEIGHTS_IN_BLOCK: its weights come
// computed from the CPU.)
#ifndef SI_MORPH_GLSL
#define SI_MORPH_GLSL
#ifndef SI_MORPH_BINDING
#define SI_MORPH_BINDING 5
#endif
SI_BINDING_LAYOUT(SI_MORPH_BINDING) uniform highp usampler2D si_morphs;

#ifdef SI_MORPH_WEIGHTS_IN_BLOCK
// The traditional baseline (skinned.vert.glsl): each target's weight computed on the CPU
// (si::emulateLayeredMorphWeights), in the character's block; `inst` and `layer` are unused.
float siMorphLayerWeight(SiInstance inst, uvec4 layer, uint target) {
  return si_morph_weights[target >> 2u][int(target & 3u)];
}
SiInstance siNoInstance() {
  return SiInstance(vec4[3](vec4(0.0), vec4(0.0), vec4(0.0)), uvec4(0u), uvec4(0u));
}
#else

// Texel `at` past a frame's first texel of the frame pair `frame`, `next`, interpolated as
// siInterpolatedRows interpolates a matrix row (the fraction word carries the interval mode).
vec4 siMorphWeightTexel(uint frame, uint next, uint fraction, uint at) {
  float t = uintBitsToFloat(fraction & 0x3FFFFFFFu);
  uint mode = fraction >> 30;
  uint a = frame + at, b = next + at;
  if (mode == 0u) return mix(siFetch(a), siFetch(b), t);
  uint step = next - frame;
  vec4 w = siCubicWeights(t, mode);
  vec4 sum = w.y * siFetch(a) + w.z * siFetch(b);
  if (mode != 2u) sum += w.x * siFetch(a - step);
  if (mode != 3u) sum += w.w * siFetch(b + step);
  return sum;
}

// Morph target `target`'s weight for `inst`: clip A's, crossfaded towards clip B's by the
// record's weight.
float siMorphWeight(SiInstance inst, uint target) {
  uint at = si_morph_info.z + (target >> 2u);
  int c = int(target & 3u);
  float w = siMorphWeightTexel(inst.frames.x, inst.frames.y, inst.blend.x, at)[c];
  float wb = uintBitsToFloat(inst.blend.z);
  if (wb > 0.0)
    w = mix(w, siMorphWeightTexel(inst.frames.z, inst.frames.w, inst.blend.y, at)[c], wb);
  return w;
}

#ifdef SI_LAYERS
// Whether mask `mask` of the mask table moves morph target `target` (its morph bits).
bool siMaskMovesTarget(uint mask, uint target) {
  uint words = uint(si_mask_anchor[1]);
  if ((target >> 5u) >= words) return false;
  uint at = siMaskTable(mask) + 5u * uint(si_mask_anchor[0]) + (target >> 5u);
  return ((uint(si_mask_anchor[at]) >> (target & 31u)) & 1u) != 0u;
}
#endif

#ifdef SI_LAYERS
// Target `target`'s weight for `inst` with its overlay `layer` and a 2D blend's extra layers
// `e1`, `e2` (uvec4(0): none) on the overlay's mask: where the mask moves the target, the base's
// weight mixed towards each layer's clip's by that layer's weight, in turn
// (si::emulateLayeredMorphWeights; the compose pass's weights, layer_compose.comp.glsl).
float siMorphChainWeight(SiInstance inst, uvec4 layer, uvec4 e1, uvec4 e2, uint target) {
  float w = siMorphWeight(inst, target);
  if (!siMaskMovesTarget(siLayerMask(layer), target)) return w;
  uint at = si_morph_info.z + (target >> 2u);
  uvec4 chain[3] = uvec4[3](layer, e1, e2);
  for (int l = 0; l < 3; ++l) {
    float weight = siLayerWeight(chain[l]);
    if (weight > 0.0)
      w = mix(w, siMorphWeightTexel(chain[l].x, chain[l].y, chain[l].z, at)[int(target & 3u)],
              weight);
  }
  return w;
}
#endif

// Target `target`'s weight for `inst` with its overlay, the layer record `layer` (uvec4(0):
// none): where the overlay's weight is above 0 and its mask moves the target, the base's
// weight mixed towards the overlay clip's by it (siMorphChainWeight without extra layers: a 2D
// blend's third and fourth clips move targets through the compose pass's weights,
// siMorphComposed). Without SI_LAYERS, siMorphWeight.
float siMorphLayerWeight(SiInstance inst, uvec4 layer, uint target) {
#ifdef SI_LAYERS
  if (siLayerWeight(layer) > 0.0) return siMorphChainWeight(inst, layer, uvec4(0u), uvec4(0u), target);
#endif
  return siMorphWeight(inst, target);
}

#endif  // SI_MORPH_WEIGHTS_IN_BLOCK

#if defined(SI_COMPOSED_LAYERS) && !defined(SI_MORPH_WEIGHTS_IN_BLOCK)
// layer_compose.glsl: the compose pass's weight of a target, where it composed one.
bool siComposedMorphWeight(uvec4 layer, uint record, bool previous, uint target, out float w);
#endif
// Target `target`'s weight for `inst` with overlay `layer`: with `composed`, the compose pass's
// for composed record `record` (its previous one with `previous`) where it composed one;
// siMorphLayerWeight otherwise.
float siMorphTargetWeight(SiInstance inst, uvec4 layer, bool composed, uint record,
                          bool previous, uint target) {
#if defined(SI_COMPOSED_LAYERS) && !defined(SI_MORPH_WEIGHTS_IN_BLOCK)
  float w;
  if (composed && siComposedMorphWeight(layer, record, previous, target, w)) return w;
#endif
  return siMorphLayerWeight(inst, layer, target);
}

uvec4 siMorphEntry(uint i) {
  return texelFetch(si_morphs,
                    ivec2(int(i & ((1u << si_morph_info.x) - 1u)), int(i >> si_morph_info.x)), 0);
}

// An entry word's target (bits 0-15) and tail (bits 16-31, a float's upper bits).
uint siMorphTarget(uint word) { return word & 0xFFFFu; }
float siMorphTail(uint word) { return uintBitsToFloat(word & 0xFFFF0000u); }
// LOD level `lod`'s cut (model units): its entries whose tail is within it are left out.
float siMorphCut(uint lod) {
  uint level = min(lod, 7u);  // Past the last level its cut, as the CPU path reads it.
  return si_morph_cuts[level >> 2][int(level & 3u)];
}

// siMorphLayered's work, each target's weight from siMorphTargetWeight. Two entries an
// iteration, without a branch on their weights, so their fetches overlap, and the next two
// fetched ahead.
void siMorphWeighted(SiInstance inst, uvec4 layer, bool composed, uint record, bool previous,
                     uint word, uint lod, inout vec3 position, inout vec3 normal,
                     inout vec3 tangent) {
  uint count = word & 511u;
  if (count == 0u) return;
  uint stride = si_morph_info.y;
  uint first = (word >> 9) * stride;
  float cut = siMorphCut(lod);
  vec3 n = normal, t = tangent;
  // Each pair's entries are fetched an iteration ahead, with the pair before's weights, so their
  // waits overlap (the last entry stands in past the run).
  uint last = first + (count - 1u) * stride;
  uvec4 e0 = siMorphEntry(first), e1 = siMorphEntry(min(first + stride, last));
  for (uint i = 0u; i < count; i += 2u) {
    uint at0 = first + i * stride;
    bool pair = i + 1u < count;
    uint at1 = pair ? at0 + stride : at0;
    uvec4 next0 = siMorphEntry(min(at0 + 2u * stride, last)),
          next1 = siMorphEntry(min(at0 + 3u * stride, last));
    if (siMorphTail(e0.x) <= cut) break;
    float second = pair && siMorphTail(e1.x) > cut ? 1.0 : 0.0;
    float w0 = siMorphTargetWeight(inst, layer, composed, record, previous, siMorphTarget(e0.x));
    float w1 =
        second * siMorphTargetWeight(inst, layer, composed, record, previous, siMorphTarget(e1.x));
    position += w0 * uintBitsToFloat(e0.yzw) + w1 * uintBitsToFloat(e1.yzw);
    if (stride > 1u)
      n += w0 * uintBitsToFloat(siMorphEntry(at0 + 1u).yzw) +
           w1 * uintBitsToFloat(siMorphEntry(at1 + 1u).yzw);
    if (stride > 2u)
      t += w0 * uintBitsToFloat(siMorphEntry(at0 + 2u).yzw) +
           w1 * uintBitsToFloat(siMorphEntry(at1 + 2u).yzw);
    if (second == 0.0) break;
    e0 = next0;
    e1 = next1;
  }
  float n_length = length(n);
  if (n_length > 0.0) normal = n / n_length;
  float t_length = length(t);
  if (t_length > 0.0 && dot(tangent, tangent) > 0.0) tangent = t / t_length;
}
// Adds the morph targets of the vertex whose morph word is `word`, at `inst`'s weights (with
// its overlay `layer`: siMorphLayerWeight), to its bind-pose position, normal and tangent
// direction, then renormalizes the normal and a non-zero tangent (the seed "Efficient
// Animation" renormalizes its blended frame so); at LOD level `lod` it stops where the rest of
// the run moves the vertex no farther than the level's cut.
void siMorphLayered(SiInstance inst, uvec4 layer, uint word, uint lod, inout vec3 position,
                    inout vec3 normal, inout vec3 tangent) {
  siMorphWeighted(inst, layer, false, 0u, false, word, lod, position, normal, tangent);
}
#if defined(SI_COMPOSED_LAYERS) && !defined(SI_MORPH_WEIGHTS_IN_BLOCK)
// siMorphLayered with the weights the compose pass composed for record `record` (its previous
// ones with `previous`), a 2D blend's extra layers included.
void siMorphComposed(SiInstance inst, uvec4 layer, uint record, bool previous, uint word,
                     uint lod, inout vec3 position, inout vec3 normal, inout vec3 tangent) {
  siMorphWeighted(inst, layer, true, record, previous, word, lod, position, normal, tangent);
}
#endif
// siMorphLayered without an overlay: the record's clips alone.
void siMorph(SiInstance inst, uint word, uint lod, inout vec3 position, inout vec3 normal,
             inout vec3 tangent) {
  siMorphLayered(inst, uvec4(0u), word, lod, position, normal, tangent);
}
#endif
