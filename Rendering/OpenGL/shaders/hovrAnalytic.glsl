// hovr: analytic isosurface and maximum/minimum intensity projection (Jozsa, Toth and
// Csebfalvi, "Analytic isosurface rendering and maximum intensity projection on the GPU").
// The ray visits every cell it crosses with the integer-based traversal of section 7 (the
// only state is the integer coordinate of the next plane crossing per axis, so no rounding
// accumulates; mirrored on the CPU by vtkGridRayTraversalT<float>). Inside a cell the
// trilinear field along the ray is a cubic (Eq. 2), set from four samples (Eq. 3-4); its
// extrema come from f'(t) = 0 (Eq. 5-6). The isosurface is searched only in the first cell
// whose range holds an isovalue, and the maximum is the largest end point or interior
// extremum of any cell (section 9).
//
// Samples are trilinear interpolations of the 8 corner voxels (2 reads of a texture packing 4
// points per texel, or 8 texelFetch of VTK's volume texture), computed in float:
// hardware filtering weights have 8 bits on common GPUs and on llvmpipe, which would move the
// surface by up to 1/256 of a voxel. The corner range of a cell bounds the interpolant, so
// cells whose range cannot hold an isovalue (or beat the current maximum) are skipped before
// any sample is computed. With blocks, the ray walks the blocks with the same traversal and
// enters only those whose range may hold what is sought (hovr_walkBlocks, hovr_walkCells).
//
// The mapper draws the volume brick by brick (vtkOpenGLVolumeBricks, no ghosts): each draw
// walks the cells of one brick, from hovr_volume, in the brick's own grid index (point i of
// the texture at i), so that float positions stay at the scale of a brick.
//
// Switches defined before this code by vtkAnalyticVolumeMapper:
//   HOVR_BLEND      1 maximum, 2 minimum intensity, 5 isosurface
//   HOVR_ISO_COUNT  number of isovalues (isosurface only)
//   HOVR_SHADE      1 when the volume property shades
//   HOVR_OUTPUT     0 colour, 1 hit position (grid index, w = 1 on a hit), 2 extremum (data
//                   units in x, w = 1 where the ray meets the volume)
//   HOVR_BLOCK      cells per block edge of hovr_blockRange (0: no block skipping)
//   HOVR_PACKED     1 when the corners come packed 4 per texel from hovr_corners
//   HOVR_ROUNDS     1 for a projection drawn in rounds over several bricks

// hovr_rawToData, hovr_output, hovr_textureToIndex and HOVR_VOLUME (hovr_volume, the
// brick): hovrAnalyticCommon.glsl.
uniform vec3 hovr_spacing;     // the volume's spacing
uniform vec2 hovr_rawToVtkRaw; // raw value -> the raw value of VTK's texture, for its tables
uniform float hovr_brick;      // the brick drawn, for HOVR_OUTPUT 1
#if HOVR_BLOCK
// Per block of HOVR_BLOCK^3 cells: the smallest and largest raw value of its points (the
// interpolant stays between them), for skipping blocks that cannot hold an isovalue or beat
// the current extremum. NaN-only blocks hold an empty range (min > max).
uniform sampler3D hovr_blockRange;
vec3 hovr_blocksInvSize;
#endif
#if HOVR_BLEND == 5
uniform float hovr_isoRaw[HOVR_ISO_COUNT]; // isovalues in raw texture units
#else
uniform float hovr_rawExtreme; // the data's largest (MIP) or smallest (MinIP) raw value
#if HOVR_ROUNDS
// Drawing rounds when there are several bricks: see the end of hovr_analyticRay.
uniform int hovr_round;
uniform sampler2D hovr_extremes; // round 2: each pixel's extremum over the bricks
#endif
#endif

// The rays as an affine frame in the brick's grid index, computed in double on the CPU
// (vtkCameraRayModel::GetGridRayFrame, vtkExtensibleGPUVolumeRayCastMapper::
// SetRayFrameUniforms) when hovr_rayFrameInUse is 1: the ray of the pixel at offset p from
// hovr_localPixelCentre passes through hovr_brickCentre + p.x hovr_brickDx + p.y hovr_brickDy
// (the pixel grid on the plane through the brick's centre), along that point minus
// hovr_localEye (perspective) or along hovr_rayForward (parallel). Otherwise rays go through
// VTK's matrices.
uniform int hovr_rayFrameInUse;
uniform vec3 hovr_brickCentre;
uniform vec3 hovr_brickDx;
uniform vec3 hovr_brickDy;
uniform vec3 hovr_localEye;
uniform vec3 hovr_rayForward;
uniform vec2 hovr_localPixelCentre;
uniform int hovr_rayPerspective;

// The texel c of a texture with nearest filtering, read at its centre: on software renderers
// such as llvmpipe this costs less than texelFetch, and the texel is the same.
// invSize: 1 / the texture's size, computed once per ray.
vec4 hovr_texel(sampler3D s, vec3 invSize, ivec3 c)
{
  return textureLod(s, (vec3(c) + 0.5) * invSize, 0.0);
}

// Corner values of the current cell: (v000, v100, v010, v110) and the same at k + 1.
vec4 hovr_lower;
vec4 hovr_upper;

#if HOVR_PACKED
// Texel (i, j, k) holds the points (i, j, k), (i + 1, j, k), (i, j + 1, k), (i + 1, j + 1, k).
uniform sampler3D hovr_corners;
vec3 hovr_cornersInvSize;
void hovr_fetchCorners(ivec3 c)
{
  hovr_lower = hovr_texel(hovr_corners, hovr_cornersInvSize, c);
  hovr_upper = hovr_texel(hovr_corners, hovr_cornersInvSize, c + ivec3(0, 0, 1));
}
#else
void hovr_fetchCorners(ivec3 c)
{
  hovr_lower = vec4(texelFetch(hovr_volume, c, 0).r, texelFetch(hovr_volume, c + ivec3(1, 0, 0), 0).r,
    texelFetch(hovr_volume, c + ivec3(0, 1, 0), 0).r, texelFetch(hovr_volume, c + ivec3(1, 1, 0), 0).r);
  hovr_upper = vec4(texelFetch(hovr_volume, c + ivec3(0, 0, 1), 0).r,
    texelFetch(hovr_volume, c + ivec3(1, 0, 1), 0).r, texelFetch(hovr_volume, c + ivec3(0, 1, 1), 0).r,
    texelFetch(hovr_volume, c + ivec3(1, 1, 1), 0).r);
}
#endif


// Trilinear interpolation of the corners at local coordinates u in [0, 1]^3.
float hovr_trilinear(vec3 u)
{
  vec4 z = mix(hovr_lower, hovr_upper, u.z);
  vec2 y = mix(z.xy, z.zw, u.y);
  return mix(y.x, y.y, u.x);
}

// Exact gradient of the trilinear interpolant at u, per grid index unit.
vec3 hovr_gradient(vec3 u)
{
  vec4 z = mix(hovr_lower, hovr_upper, u.z);
  vec4 dz = hovr_upper - hovr_lower;
  vec2 dzy = mix(dz.xy, dz.zw, u.y);
  return vec3(mix(z.y - z.x, z.w - z.z, u.y), mix(z.z - z.x, z.w - z.y, u.x), mix(dzy.x, dzy.y, u.x));
}

// Eq. 4: the cubic a t^3 + b t^2 + c t + d through the samples f at t = 0, 1/3, 2/3, 1.
vec4 hovr_cubic(vec4 f)
{
  return vec4(dot(f, vec4(-4.5, 13.5, -13.5, 4.5)), dot(f, vec4(9.0, -22.5, 18.0, -4.5)),
    dot(f, vec4(-5.5, 9.0, -4.5, 1.0)), f.x);
}

#if HOVR_BLEND == 5
// Eq. 5-6: the zeros of f'(t) = 3a t^2 + 2b t + c inside (0, 1), sorted; absent ones are 1.
// The roots are taken as q / A and C / q, which avoids the cancellation of Eq. 6's "+-".
vec2 hovr_criticalPoints(vec4 k)
{
  float A = 3.0 * k.x;
  float B = 2.0 * k.y;
  float C = k.z;
  vec2 r = vec2(1.0);
  if (A == 0.0)
  {
    r.x = B != 0.0 ? -C / B : 1.0;
  }
  else
  {
    float disc = B * B - 4.0 * A * C;
    if (disc >= 0.0)
    {
      float q = -0.5 * (B + (B >= 0.0 ? 1.0 : -1.0) * sqrt(disc));
      r = vec2(q / A, q != 0.0 ? C / q : 1.0);
    }
  }
  r = mix(r, vec2(1.0), bvec2(!(r.x > 0.0 && r.x < 1.0), !(r.y > 0.0 && r.y < 1.0)));
  return vec2(min(r.x, r.y), max(r.x, r.y));
}

// The first t in [0, 1] of the segment ua -> ub where the interpolant equals v, or -1. The
// critical points cut the segment into monotone pieces; the first piece whose ends bracket
// (or touch) v is bisected on the interpolant itself, whose float evaluation is more
// accurate than the cubic's coefficients.
float hovr_firstCrossing(vec3 ua, vec3 ub, vec2 critical, float v)
{
  float cuts[4] = float[4](0.0, critical.x, critical.y, 1.0);
  for (int p = 0; p < 3; ++p)
  {
    float lo = cuts[p];
    float hi = cuts[p + 1];
    float glo = hovr_trilinear(mix(ua, ub, lo)) - v;
    float ghi = hovr_trilinear(mix(ua, ub, hi)) - v;
    if (glo == 0.0)
    {
      return lo;
    }
    if (ghi == 0.0)
    {
      return hi;
    }
    if ((glo < 0.0) == (ghi < 0.0))
    {
      continue;
    }
    for (int n = 0; n < 24; ++n)
    {
      float mid = 0.5 * (lo + hi);
      float g = hovr_trilinear(mix(ua, ub, mid)) - v;
      if ((g < 0.0) == (glo < 0.0))
      {
        lo = mid;
      }
      else
      {
        hi = mid;
      }
    }
    return 0.5 * (lo + hi);
  }
  return -1.0;
}
#endif

// Texture coordinate of the transfer functions for a raw value, as VTK's shader computes it
// from the raw value of its own texture.
float hovr_transferCoord(float raw)
{
  return (raw * hovr_rawToVtkRaw.x + hovr_rawToVtkRaw.y) * in_volume_scale[0].r +
    in_volume_bias[0].r;
}

#if HOVR_BLEND != 5
// Eq. 5-6 for one root: the cubic k's interior local maximum (MIP) or minimum (MinIP), a zero
// of f'(t) = A t^2 + B t + C. Of the roots q / A and C / q (q = -(B + sign(B) sqrt(disc)) / 2,
// which avoids the cancellation of Eq. 6's "+-"), the maximum is (-B - sqrt(disc)) / (2A),
// where f'' < 0: q / A when B >= 0, else C / q; the minimum is the other. A quadratic (A = 0)
// has its extremum at C / q = -C / B, of the right kind when B < 0 (MIP) or B > 0 (MinIP);
// otherwise, and without real roots, the result is not in (0, 1) (or is NaN).
float hovr_interiorExtremum(vec4 k)
{
  float A = 3.0 * k.x;
  float B = 2.0 * k.y;
  float C = k.z;
  float disc = B * B - 4.0 * A * C;
  float q = -0.5 * (B + (B >= 0.0 ? 1.0 : -1.0) * sqrt(max(disc, 0.0)));
#if HOVR_BLEND == 1
  bool first = B >= 0.0;
#else
  bool first = B < 0.0;
#endif
  float t = (first ? q : C) / (first ? A : q);
  return disc >= 0.0 ? t : -1.0;
}

// Section 9: the extremum of the interpolant over the segment ua -> ub of the cell whose
// corners are loaded: the larger (smaller) end point or interior extremum of its cubic. The
// interior is searched only when the cubic's Bernstein coefficients (whose hull holds it) can
// beat both end points and beyond, the value the caller needs to beat. Only the one critical
// point of the right kind is computed, and the cubic itself is evaluated there: where
// fragments run in lockstep (llvmpipe among them) a branch costs its instructions whether or
// not a fragment takes it, so this rarely taken one is kept short.
float hovr_segmentExtremum(vec3 ua, vec3 ub, float beyond)
{
  vec4 f = vec4(hovr_trilinear(ua), hovr_trilinear(mix(ua, ub, 1.0 / 3.0)),
    hovr_trilinear(mix(ua, ub, 2.0 / 3.0)), hovr_trilinear(ub));
  // Inner Bernstein coefficients of the cubic through f at t = 0, 1/3, 2/3, 1.
  vec2 inner = vec2(dot(f, vec4(-5.0, 18.0, -9.0, 2.0)), dot(f, vec4(2.0, -9.0, 18.0, -5.0))) / 6.0;
#if HOVR_BLEND == 1
  float result = max(f.x, f.w);
  if (max(inner.x, inner.y) > max(result, beyond))
#else
  float result = min(f.x, f.w);
  if (min(inner.x, inner.y) < min(result, beyond))
#endif
  {
    vec4 k = hovr_cubic(f);
    float t = hovr_interiorExtremum(k);
    float value = ((k.x * t + k.y) * t + k.z) * t + k.w;
#if HOVR_BLEND == 1
    result = t > 0.0 && t < 1.0 ? max(result, value) : result;
#else
    result = t > 0.0 && t < 1.0 ? min(result, value) : result;
#endif
  }
  return result;
}
#endif

// The ray in grid index, entry + t dir for t in [0, span], set once per fragment.
vec3 hovr_entry;
vec3 hovr_dir;
vec3 hovr_inv; // 1 / dir, 1 on the axes the ray does not move along
bvec3 hovr_still; // axes the ray does not move along
ivec3 hovr_iStep; // sign(dir)
ivec3 hovr_dims; // points per axis

#if HOVR_BLEND == 5
float hovr_lowestIso;
float hovr_highestIso;
#else
// The exact extremum of the cells evaluated so far (when hovr_found), and a value the
// extremum is known to reach (see hovr_blockBound): cells and blocks that cannot beat both
// are skipped.
bool hovr_found = false;
float hovr_extreme = 0.0;
#if HOVR_BLEND == 1
float hovr_bound = -1e30;
#else
float hovr_bound = 1e30;
#endif
#endif

// Section 7, at either scale (cells: size 1, blocks: size HOVR_BLOCK): the state is the
// integer index of the next plane crossed per axis, planes at multiples of size; every
// distance is recomputed from it and the entry, so no rounding accumulates.
// The planes crossed next from the point p of the ray: p rounded against the direction.
ivec3 hovr_nextPlanes(vec3 p, int size)
{
  vec3 q = p / float(size);
  return ivec3(mix(floor(q), ceil(q), lessThan(hovr_dir, vec3(0.0)))) + hovr_iStep;
}

// The distance from the entry where the ray crosses its next planes, and the axes crossed.
float hovr_crossing(ivec3 iNext, int size, out bvec3 crossed)
{
  vec3 dNext = mix((vec3(iNext * size) - hovr_entry) * hovr_inv, vec3(1e30), hovr_still);
  float d = min(min(dNext.x, dNext.y), dNext.z);
  crossed = lessThanEqual(dNext, vec3(d));
  return d;
}

// Whether a plane crossed is a face of the volume: the ray leaves even when the distance
// rounds short of the exit.
bool hovr_atFace(ivec3 iNext, int size, bvec3 crossed)
{
  ivec3 plane = iNext * size;
  vec3 face = mix(vec3(lessThanEqual(plane, ivec3(0))),
    vec3(greaterThanEqual(plane, hovr_dims - ivec3(1))), vec3(greaterThan(hovr_iStep, ivec3(0))));
  return dot(vec3(crossed), face) > 0.0;
}

// One step from before the planes iNext, in a piece of the ray that ends at distance tOut
// at pOut: returns the crossing's distance; crossed: the axes crossed; leaving: whether the
// piece (or the volume) ends there; px: where the step ends, exact on the planes crossed.
float hovr_step(ivec3 iNext, int size, float tOut, vec3 pOut, out bvec3 crossed,
  out bool leaving, out vec3 px)
{
  float d = hovr_crossing(iNext, size, crossed);
  leaving = d >= tOut || hovr_atFace(iNext, size, crossed);
  px = leaving ? pOut : mix(hovr_entry + d * hovr_dir, vec3(iNext * size), crossed);
  return d;
}

// The cell (or block) before the planes iNext.
ivec3 hovr_boxBefore(ivec3 iNext, ivec3 boxes)
{
  return clamp(iNext - max(hovr_iStep, ivec3(0)), ivec3(0), boxes - ivec3(1));
}

// The segment pe -> px of the ray through the cell; true when the ray is done (surface hit,
// or the data's own extremum reached).
bool hovr_cell(ivec3 cell, vec3 pe, vec3 px)
{
  hovr_fetchCorners(cell);
  // A NaN corner makes the whole interpolant NaN: the cell is transparent, with no surface
  // and no extremum. Tested apart, as GLSL's min and max may drop a NaN operand.
  if (any(isnan(hovr_lower)) || any(isnan(hovr_upper)))
  {
    return false;
  }
  vec4 lo4 = min(hovr_lower, hovr_upper);
  vec4 hi4 = max(hovr_lower, hovr_upper);
  float lo = min(min(lo4.x, lo4.y), min(lo4.z, lo4.w));
  float hi = max(max(hi4.x, hi4.y), max(hi4.z, hi4.w));
  vec3 ua = pe - vec3(cell);
  vec3 ub = px - vec3(cell);
#if HOVR_BLEND == 5
  if (!(hi >= hovr_lowestIso && lo <= hovr_highestIso))
  {
    return false;
  }
  vec4 f = vec4(hovr_trilinear(ua), hovr_trilinear(mix(ua, ub, 1.0 / 3.0)),
    hovr_trilinear(mix(ua, ub, 2.0 / 3.0)), hovr_trilinear(ub));
  vec2 critical = hovr_criticalPoints(hovr_cubic(f));
  float best = 2.0;
  float bestIso = 0.0;
  for (int i = 0; i < HOVR_ISO_COUNT; ++i)
  {
    if (hovr_isoRaw[i] >= lo && hovr_isoRaw[i] <= hi)
    {
      float t = hovr_firstCrossing(ua, ub, critical, hovr_isoRaw[i]);
      if (t >= 0.0 && t < best)
      {
        best = t;
        bestIso = hovr_isoRaw[i];
      }
    }
  }
  if (best > 1.0)
  {
    return false;
  }
  vec3 u = mix(ua, ub, best);
  hovr_output = vec4(vec3(cell) + u, 1.0 + hovr_brick);
  vec3 rgb = texture2D(in_colorTransferFunc_0[0], vec2(hovr_transferCoord(bestIso), 0.0)).rgb;
#if HOVR_SHADE
  // A white headlight along the ray, two-sided; angles in physical space: the gradient per
  // unit length is g / spacing, the ray direction dir * spacing.
  vec3 normal = hovr_gradient(u) / hovr_spacing;
  vec3 view = hovr_dir * hovr_spacing;
  float nl = length(normal) > 0.0 ? abs(dot(normalize(normal), normalize(view))) : 0.0;
  rgb = rgb * (in_ambient[0].x + in_diffuse[0].x * nl) +
    vec3(nl > 0.0 ? in_specular[0].x * pow(nl, in_shininess[0]) : 0.0);
#endif
  g_fragColor = vec4(min(rgb, vec3(1.0)), 1.0);
  return true;
#else
#if HOVR_BLEND == 1
  bool better = hi >= hovr_bound && (!hovr_found || hi > hovr_extreme);
#else
  bool better = lo <= hovr_bound && (!hovr_found || lo < hovr_extreme);
#endif
  if (better)
  {
    float candidate = hovr_segmentExtremum(ua, ub, hovr_found ? hovr_extreme : hovr_bound);
#if HOVR_BLEND == 1
    hovr_extreme = hovr_found ? max(hovr_extreme, candidate) : candidate;
#else
    hovr_extreme = hovr_found ? min(hovr_extreme, candidate) : candidate;
#endif
    hovr_found = true;
  }
  // Nothing along the ray can beat the data's own extremum.
#if HOVR_BLEND == 1
  return hovr_found && hovr_extreme >= hovr_rawExtreme;
#else
  return hovr_found && hovr_extreme <= hovr_rawExtreme;
#endif
#endif
}

// The ray's cells from pIn to pOut (at distance tOut from the entry); true when it is done.
bool hovr_walkCells(vec3 pIn, float tOut, vec3 pOut, int guard)
{
  ivec3 iNext = hovr_nextPlanes(pIn, 1);
  vec3 pe = pIn;
  bool done = false;
  for (int n = 0; n < guard; ++n)
  {
    bvec3 crossed;
    bool leaving;
    vec3 px;
    hovr_step(iNext, 1, tOut, pOut, crossed, leaving, px);
    done = hovr_cell(hovr_boxBefore(iNext, hovr_dims - ivec3(1)), pe, px);
    if (done || leaving)
    {
      break;
    }
    iNext += hovr_iStep * ivec3(crossed);
    pe = px;
  }
  return done;
}

#if HOVR_BLOCK
// Whether a block of that range may hold an isovalue (or beat the bound and the extremum).
// NaN blocks have the range (-inf, +inf), NaN-only ones an empty range (min > max).
bool hovr_mayHold(vec2 range)
{
#if HOVR_BLEND == 5
  for (int i = 0; i < HOVR_ISO_COUNT; ++i)
  {
    if (hovr_isoRaw[i] >= range.x && hovr_isoRaw[i] <= range.y)
    {
      return true;
    }
  }
  return false;
#elif HOVR_BLEND == 1
  return range.x <= range.y && range.y >= hovr_bound && (!hovr_found || range.y > hovr_extreme);
#else
  return range.x <= range.y && range.x <= hovr_bound && (!hovr_found || range.x < hovr_extreme);
#endif
}

// The blocks from pIn to pOut (distance tOut): those that may hold what is sought, except
// skipBlock, are walked cell by cell. True when the ray is done.
bool hovr_walkBlocks(vec3 pIn, float tOut, vec3 pOut, ivec3 skipBlock)
{
  ivec3 blocks = textureSize(hovr_blockRange, 0);
  ivec3 iNext = hovr_nextPlanes(pIn, HOVR_BLOCK);
  vec3 pe = pIn;
  int guard = blocks.x + blocks.y + blocks.z + 3;
  bool done = false;
  for (int n = 0; n < guard; ++n)
  {
    bvec3 crossed;
    bool leaving;
    vec3 px;
    float d = hovr_step(iNext, HOVR_BLOCK, tOut, pOut, crossed, leaving, px);
    ivec3 block = hovr_boxBefore(iNext, blocks);
    vec2 range = hovr_texel(hovr_blockRange, hovr_blocksInvSize, block).rg;
    done = block != skipBlock && hovr_mayHold(range) &&
      hovr_walkCells(pe, min(d, tOut), px, 3 * HOVR_BLOCK + 3);
    if (done || leaving)
    {
      break;
    }
    iNext += hovr_iStep * ivec3(crossed);
    pe = px;
  }
  return done;
}

#if HOVR_BLEND != 5
// Before the walk, two values the extremum is known to reach, so that the walk skips every
// block that cannot beat them from the first block on, instead of only those after the
// running extremum has grown. One pass over the blocks (one fetch each, no cell work):
//   - the field in every block the ray crosses lies within the block's range, so the maximum
//     is at least the largest block minimum along the ray (the minimum at most the smallest
//     block maximum): hovr_bound. Blocks with NaN cells (range (-inf, +inf)) and NaN-only
//     ones (min > max) bound nothing;
//   - the exact extremum of the ray's cells in the block of largest maximum (smallest
//     minimum), where it usually lies: hovr_extreme. Returns that block, or -1 when none.
ivec3 hovr_blockBound(float span, vec3 exitPoint)
{
  ivec3 blocks = textureSize(hovr_blockRange, 0);
  ivec3 iNext = hovr_nextPlanes(hovr_entry, HOVR_BLOCK);
  vec3 pe = hovr_entry;
  float promise = hovr_bound;
  ivec3 best = ivec3(-1);
  vec3 bestIn = pe;
  vec3 bestOut = pe;
  float bestT = -1.0;
  int guard = blocks.x + blocks.y + blocks.z + 3;
  for (int n = 0; n < guard; ++n)
  {
    bvec3 crossed;
    bool leaving;
    vec3 px;
    float d = hovr_step(iNext, HOVR_BLOCK, span, exitPoint, crossed, leaving, px);
    ivec3 block = hovr_boxBefore(iNext, blocks);
    vec2 range = hovr_texel(hovr_blockRange, hovr_blocksInvSize, block).rg;
    if (range.x <= range.y)
    {
#if HOVR_BLEND == 1
      hovr_bound = max(hovr_bound, range.x);
      bool promising = range.y > promise && range.y < 1e30;
      promise = promising ? range.y : promise;
#else
      hovr_bound = min(hovr_bound, range.y);
      bool promising = range.x < promise && range.x > -1e30;
      promise = promising ? range.x : promise;
#endif
      best = promising ? block : best;
      bestIn = promising ? pe : bestIn;
      bestOut = promising ? px : bestOut;
      bestT = promising ? min(d, span) : bestT;
    }
    if (leaving)
    {
      break;
    }
    iNext += hovr_iStep * ivec3(crossed);
    pe = px;
  }
  if (bestT > 0.0)
  {
    hovr_walkCells(bestIn, bestT, bestOut, 3 * HOVR_BLOCK + 3);
  }
  return best;
}
#endif
#endif

// Walks the whole ray; called once, where VTK initialises its sampling loop.
void hovr_analyticRay()
{
  ivec3 dims = textureSize(hovr_volume, 0);
  vec3 last = vec3(dims - ivec3(1));
  // The ray runs from the near plane to VTK's termination point (far plane or opaque
  // geometry), as a base point plus [sNear, sFar] along the unit direction.
  vec3 start = hovr_textureToIndex(hovr_windowToTexture(0.0));
  vec3 stop = hovr_textureToIndex(g_rayTermination);
  vec3 base = start;
  vec3 dir = stop - start;
  if (hovr_rayFrameInUse == 1)
  {
    vec2 p = gl_FragCoord.xy - in_windowLowerLeftCorner - hovr_localPixelCentre;
    base = hovr_brickCentre + p.x * hovr_brickDx + p.y * hovr_brickDy;
    dir = hovr_rayPerspective == 1 ? base - hovr_localEye : hovr_rayForward;
  }
  float len = length(dir);
  if (!(len > 0.0))
  {
    return;
  }
  dir /= len;
  float sNear = dot(start - base, dir);
  float sFar = dot(stop - base, dir);
  bvec3 still = equal(dir, vec3(0.0));
  vec3 inv = 1.0 / mix(dir, vec3(1.0), still);
  // Clip to the box of the points, [0, dims - 1]^3.
  vec3 ta = -base * inv;
  vec3 tb = (last - base) * inv;
  vec3 tlo = mix(min(ta, tb), vec3(-1e30), still);
  vec3 thi = mix(max(ta, tb), vec3(1e30), still);
  // (GLSL has no && on boolean vectors: masks as 0/1 floats.)
  vec3 outside = vec3(lessThan(base, vec3(0.0))) + vec3(greaterThan(base, last));
  if (dot(vec3(still), outside) > 0.0)
  {
    return;
  }
  float t0 = max(max(max(tlo.x, tlo.y), tlo.z), sNear);
  float t1 = min(min(min(thi.x, thi.y), thi.z), sFar);
  if (!(t0 < t1))
  {
    return;
  }
  hovr_entry = clamp(base + t0 * dir, vec3(0.0), last);
  hovr_dir = dir;
  hovr_inv = inv;
  hovr_still = still;
  hovr_iStep = ivec3(sign(dir));
  hovr_dims = dims;
#if HOVR_PACKED
  hovr_cornersInvSize = 1.0 / vec3(textureSize(hovr_corners, 0));
#endif
#if HOVR_BLOCK
  hovr_blocksInvSize = 1.0 / vec3(textureSize(hovr_blockRange, 0));
#endif
  float span = t1 - t0;
  vec3 exitPoint = clamp(hovr_entry + span * dir, vec3(0.0), last);
#if HOVR_BLEND == 5
  hovr_lowestIso = hovr_isoRaw[0];
  hovr_highestIso = hovr_isoRaw[0];
  for (int i = 1; i < HOVR_ISO_COUNT; ++i)
  {
    hovr_lowestIso = min(hovr_lowestIso, hovr_isoRaw[i]);
    hovr_highestIso = max(hovr_highestIso, hovr_isoRaw[i]);
  }
#endif
#if HOVR_BLOCK
#if HOVR_BLEND == 5
  ivec3 doneBlock = ivec3(-1);
#else
  ivec3 doneBlock = hovr_blockBound(span, exitPoint);
#endif
  hovr_walkBlocks(hovr_entry, span, exitPoint, doneBlock);
#else
  hovr_walkCells(hovr_entry, span, exitPoint, 4 * (dims.x + dims.y + dims.z));
#endif
#if HOVR_BLEND != 5
  float value = hovr_extreme * hovr_rawToData.x + hovr_rawToData.y;
#if HOVR_ROUNDS
  // Several bricks: round 1 writes each brick's extremum (the target keeps the ray's through
  // maximum or minimum blending), round 2 the colour, from the bricks that hold the ray's.
  if (hovr_round == 1)
  {
    if (!hovr_found)
    {
      discard;
    }
    hovr_output = vec4(value, 0.0, 0.0, HOVR_BLEND == 1 ? 1.0 : -1.0);
    g_fragColor = hovr_output;
    return;
  }
  if (hovr_round == 2 &&
    !(hovr_found && value == texelFetch(hovr_extremes, ivec2(gl_FragCoord.xy), 0).x))
  {
    discard;
  }
#endif
  if (hovr_found)
  {
    hovr_output = vec4(value, 0.0, 0.0, 1.0);
    float coord = hovr_transferCoord(hovr_extreme);
    float opacity = texture2D(in_opacityTransferFunc_0[0], vec2(coord, 0.0)).r;
    vec3 rgb = texture2D(in_colorTransferFunc_0[0], vec2(coord, 0.0)).rgb;
    g_fragColor = vec4(rgb * opacity, opacity);
  }
#endif
}
