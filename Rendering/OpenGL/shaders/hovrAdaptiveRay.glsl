// hovr: skipping along rays with an oracle ("Adaptive Sampling in Three Dimensions for Volume
// Rendering on GPUs", Sec. 3.1) and first-order pre-integrated segments of variable length
// (Sec. 3.3, Fig. 6). Samples lie on a global grid of slices spaced one sample distance:
// planes perpendicular to the view (parallel camera) or spheres around the eye (perspective),
// slice coordinate 0 at the whole volume's point nearest to the camera (the input's box, or
// WholeBounds when the input is a piece). From a sample on slice i
// with oracle distance d (in slices) the next sample is slice (floor(i / 2^q) + 1) 2^q,
// q = min(floor(log2 d), l_max) (the closed form of the skip condition of line 74, as
// vtkAdaptiveSamplingRayCaster::NextSampleSlice computes it). One iteration of VTK's ray loop
// handles one sample: the step moves g_dataPos and g_currentT so that VTK's own advance lands
// on the next sample, and skipped slices cost no iteration. The segment of k slices between
// two samples is composited from layer k of a table (2D first-order tables for lengths
// k * Delta, k = 1 .. 2^l_max, tiles of one 2D texture); the pieces from the ray's entry to
// its first slice and from its last sample to its exit or termination point take the layer of
// the next whole number of slices with the optical depth rescaled to their length (exact for
// a constant scalar).
//
// Inserted into vtkOpenGLGPUVolumeRayCastMapper's fragment shader by
// vtkAdaptiveRayVolumeMapper after computeRayDirection(), with hovrVolumeAtlas.glsl before it
// and the switches HOVR_ORACLE (sample the oracle texture, else d = 1), HOVR_COUNT_SAMPLES
// (count the slice samples in an atomic counter), HOVR_TILES (more than one layer) and
// HOVR_TRICUBIC (the cubic B-spline approximation of the data, else trilinear interpolation).

// Centre-axis table coordinate of a raw texture value: raw * x + y.
uniform vec2 hovr_rawToTable;

// A piece with ghost points (OwnedExtent): its own points (0-based grid index). Samples on
// multiples of 2^l_max slices are taken by every walk, the whole volume's too: where a ray
// enters the own points from ghost points, the walk starts on the first such slice in them,
// and where it leaves them into ghost points, it ends on the first such slice past them, so
// that the pieces' walks join into the whole volume's.
uniform int hovr_owned;
uniform vec3 hovr_ownedLo;
uniform vec3 hovr_ownedHi;

// Steps (in units of g_dirStep) from pos to where the ray leaves the volume's box.
float hovr_stepsToExit(vec3 pos)
{
  vec3 bound = mix(in_texMin[0], in_texMax[0], step(vec3(0.0), g_dirStep));
  vec3 steps = vec3(1e30);
  for (int a = 0; a < 3; ++a)
  {
    if (g_dirStep[a] != 0.0)
    {
      steps[a] = (bound[a] - pos[a]) / g_dirStep[a];
    }
  }
  return min(steps.x, min(steps.y, steps.z));
}

// Layer k - 1 (segments of k slices) is tile ((k - 1) mod columns, (k - 1) / columns) of a 2D
// texture; within a tile, front along x and back along y, entries at texel centres.
uniform sampler2D hovr_adaptiveTables;
uniform vec2 hovr_tileGrid;            // columns and rows of tiles
uniform vec2 hovr_tileScale;           // their reciprocals
uniform float hovr_tileMargin;         // half a texel of a tile, in tile units
uniform float hovr_tableLayers;        // 2^l_max, or 1 when every slice is sampled
uniform float hovr_maximumSpan;        // 2^l_max
uniform int hovr_perspective;          // slices are spheres around the eye, else planes
uniform vec3 hovr_sliceOrigin;         // parallel: a point of slice 0 (dataset coordinates)
uniform float hovr_sliceStart;         // perspective: the radius of slice 0
#if HOVR_ORACLE
// hovr_oracle (GetAtlasSamplerCode): oracle distance in world units, the volume's atlas tiles
uniform float hovr_oracleScale; // 1 / Delta
#endif
#if HOVR_COUNT_SAMPLES
layout(binding = 0, offset = 0) uniform atomic_uint hovr_sampleCounter;
#endif

// The volume's bricks in the atlas's pages (hovrVolumeAtlas.glsl; the sampler hovr_volume
// from GetAtlasSamplerCode), read by the volume's grid index; VTK's own texture is a proxy of
// the volume's box, whose texture coordinates g_dataPos are.

// The volume's 0-based grid index of a position in VTK's texture coordinates.
vec3 hovr_gridOf(vec3 pos)
{
  return (pos - in_texMin[0]) / (in_texMax[0] - in_texMin[0]) *
    vec3(hovr_atlasGrid[0], hovr_atlasGrid[1], hovr_atlasGrid[2]);
}

// The trilinear raw value at p (0-based grid index).
float hovr_volumeAt(vec3 p)
{
  int page;
  vec3 coordinate = hovr_atlasCoord(p, page);
  return hovr_volume_texture(page, coordinate).r;
}

#if HOVR_TRICUBIC
// The cubic B-spline approximation of the volume at pos (texture coordinates) from 8
// trilinear fetches (Sigg and Hadwiger, "Fast Third-Order Texture Filtering", GPU Gems 2,
// ch. 20): per axis, with x = i + f the position in the grid index, the B-spline weights
// w0..w3 of the points i - 1 .. i + 2 pair into two linear fetches, g0 (the fetch between
// i - 1 and i at offset h0 = w1 / g0, g0 = w0 + w1) plus g1 (between i + 1 and i + 2 at offset
// h1 = w3 / g1, g1 = w2 + w3 = 1 - g0). The weights are positive, so the value stays within the
// data range. Fetches beyond the outermost points read copies of them (clamp to edge).
float hovr_volumeValue(vec3 pos)
{
  vec3 x = hovr_gridOf(pos);
  vec3 i = floor(x);
  vec3 f = x - i;
  vec3 f2 = f * f;
  vec3 f3 = f2 * f;
  vec3 w0 = (1.0 - 3.0 * f + 3.0 * f2 - f3) / 6.0;
  vec3 w1 = (4.0 - 6.0 * f2 + 3.0 * f3) / 6.0;
  vec3 w3 = f3 / 6.0;
  vec3 g0 = w0 + w1; // at least 1/6
  vec3 g1 = 1.0 - g0;
  vec3 t0 = i - 1.0 + w1 / g0;
  vec3 t1 = i + 1.0 + w3 / g1;
  float v000 = hovr_volumeAt(vec3(t0.x, t0.y, t0.z));
  float v100 = hovr_volumeAt(vec3(t1.x, t0.y, t0.z));
  float v010 = hovr_volumeAt(vec3(t0.x, t1.y, t0.z));
  float v110 = hovr_volumeAt(vec3(t1.x, t1.y, t0.z));
  float v001 = hovr_volumeAt(vec3(t0.x, t0.y, t1.z));
  float v101 = hovr_volumeAt(vec3(t1.x, t0.y, t1.z));
  float v011 = hovr_volumeAt(vec3(t0.x, t1.y, t1.z));
  float v111 = hovr_volumeAt(vec3(t1.x, t1.y, t1.z));
  // mix(a, b, g1) = g0 a + g1 b along x, then y, then z.
  return mix(mix(mix(v000, v100, g1.x), mix(v010, v110, g1.x), g1.y),
    mix(mix(v001, v101, g1.x), mix(v011, v111, g1.x), g1.y), g1.z);
}
#else
float hovr_volumeValue(vec3 pos)
{
  return hovr_volumeAt(hovr_gridOf(pos));
}
#endif

// Table coordinate of the reconstructed scalar at pos.
float hovr_sampleCoord(vec3 pos)
{
  return hovr_volumeValue(pos) * hovr_rawToTable.x + hovr_rawToTable.y;
}

vec3 hovr_entry;        // where the ray enters the volume (texture coordinates)
float hovr_entrySlice;  // its slice coordinate
float hovr_jitter;      // VTK's first sample, in steps from the entry
float hovr_endSteps;    // where the ray leaves the box or is terminated, in steps from the entry
float hovr_frontSlice;  // slice coordinate of the previous sample (the entry before the first)
float hovr_sFront;      // its table coordinate
float hovr_slice;       // the slice of the sample at g_dataPos
bool hovr_done;         // nothing left to composite after the loop

// Slice coordinate (in sample distances) of a point in dataset coordinates on this ray.
float hovr_sliceCoordinate(vec3 position, vec3 rayDirection)
{
  if (hovr_perspective != 0)
  {
    return (length(position - g_eyePosObj.xyz) - hovr_sliceStart) / in_sampleDistance;
  }
  return dot(position - hovr_sliceOrigin, rayDirection) / in_sampleDistance;
}

// Composite the segment (sFront, sBack) of `slices` slice spacings, 0 < slices <= 2^l_max.
void hovr_compositeSlices(float sFront, float sBack, float slices)
{
  if (!(slices > 0.0) || isnan(sFront) || isnan(sBack))
  {
    return;
  }
  // Whole segments take their own layer exactly (rounding of the slice coordinates aside).
  float layer = clamp(ceil(slices - 1e-3), 1.0, hovr_tableLayers);
  float fraction = slices / layer;
#if HOVR_TILES
  // Clamped to the tile's outer texel centres, so that no lookup blends in a neighbour tile.
  vec2 inTile = clamp(vec2(sFront, sBack), hovr_tileMargin, 1.0 - hovr_tileMargin);
  float row = floor((layer - 0.5) * hovr_tileScale.x);
  vec2 tile = vec2(layer - 1.0 - row * hovr_tileGrid.x, row);
  vec4 segment = texture(hovr_adaptiveTables, (tile + inTile) * hovr_tileScale);
#else
  vec4 segment = texture(hovr_adaptiveTables, vec2(sFront, sBack));
#endif
  if (fraction < 1.0)
  {
    float alpha = 1.0 - pow(max(1.0 - segment.a, 0.0), fraction);
    segment.rgb *= segment.a > 1e-6 ? alpha / segment.a : fraction;
    segment.a = alpha;
  }
  g_fragColor += (1.0 - g_fragColor.a) * segment;
}

// Place the ray on `slice` for the next loop iteration, whose advance adds one g_dirStep.
void hovr_moveToSlice(float slice, float advance)
{
  hovr_slice = slice;
  float steps = slice - hovr_entrySlice;
  g_dataPos = hovr_entry + (steps - advance) * g_dirStep;
  g_currentT = steps - hovr_jitter - advance;
}

void hovr_adaptiveInit()
{
  hovr_entry = g_dataPos - g_rayJitter;
  hovr_jitter = length(g_rayJitter) / length(g_dirStep);
  // VTK counts g_terminatePointMax from its first sample, one jitter offset inside.
  hovr_endSteps = min(hovr_stepsToExit(hovr_entry), g_terminatePointMax + hovr_jitter);
  hovr_entrySlice = hovr_sliceCoordinate(ip_vertexPos.xyz, computeRayDirection());
  hovr_frontSlice = hovr_entrySlice;
  hovr_sFront = hovr_sampleCoord(hovr_entry);
  hovr_done = !(hovr_endSteps > 0.0);
  // A ray entering within rounding of a slice starts on it (an axis-aligned view enters on
  // slice 0 exactly).
  float first = ceil(hovr_entrySlice - 1e-3);
  if (hovr_owned != 0 && !hovr_done)
  {
    // Where the ray is in the own points, in steps from the entry, and whether it enters them
    // from ghost points and leaves them into ghost points: told by the faces it crosses (an
    // own face that is not the input's has ghost points past it), not by comparing rounded
    // distances.
    vec3 g0 = hovr_gridOf(hovr_entry);
    vec3 dg = hovr_gridOf(hovr_entry + g_dirStep) - g0;
    vec3 last = vec3(hovr_atlasGrid[0], hovr_atlasGrid[1], hovr_atlasGrid[2]);
    vec2 span = vec2(-1e30, 1e30);
    bool fromGhosts = false, intoGhosts = false;
    for (int a = 0; a < 3; ++a)
    {
      if (dg[a] != 0.0)
      {
        float ta = (hovr_ownedLo[a] - g0[a]) / dg[a];
        float tb = (hovr_ownedHi[a] - g0[a]) / dg[a];
        bool up = dg[a] > 0.0;
        bool ghostsBelow = hovr_ownedLo[a] > 0.5, ghostsAbove = hovr_ownedHi[a] < last[a] - 0.5;
        if (min(ta, tb) > span.x)
        {
          span.x = min(ta, tb);
          fromGhosts = up ? ghostsBelow : ghostsAbove;
        }
        if (max(ta, tb) < span.y)
        {
          span.y = max(ta, tb);
          intoGhosts = up ? ghostsAbove : ghostsBelow;
        }
      }
      else if (g0[a] < hovr_ownedLo[a] || g0[a] > hovr_ownedHi[a])
      {
        span = vec2(1.0, 0.0);
      }
    }
    if (!(span.x < span.y) || span.y <= 0.0 || span.x >= hovr_endSteps)
    {
      hovr_done = true; // the ray crosses ghost points alone
      g_exit = true;
      return;
    }
    float aligned = hovr_maximumSpan;
    if (fromGhosts)
    {
      // Entering the own points from ghost points: the first aligned slice in them.
      first = ceil((hovr_entrySlice + span.x) / aligned - 1e-4) * aligned;
      hovr_frontSlice = first;
      hovr_sFront = hovr_sampleCoord(hovr_entry + (first - hovr_entrySlice) * g_dirStep);
    }
    if (intoGhosts)
    {
      // Leaving them into ghost points: the walk ends on the first aligned slice past them.
      float end = ceil((hovr_entrySlice + span.y) / aligned - 1e-4) * aligned;
      hovr_endSteps = min(hovr_endSteps, end - hovr_entrySlice);
    }
  }
  if (hovr_done || first - hovr_entrySlice > hovr_endSteps)
  {
    g_exit = true; // no slice before the end: the exit integrates entry to end
    return;
  }
  hovr_moveToSlice(first, 0.0);
}

void hovr_adaptiveStep()
{
  float s = hovr_sampleCoord(g_dataPos);
#if HOVR_COUNT_SAMPLES
  atomicCounterIncrement(hovr_sampleCounter);
#endif
  hovr_compositeSlices(hovr_sFront, s, hovr_slice - hovr_frontSlice);
  hovr_sFront = s;
  hovr_frontSlice = hovr_slice;
#if HOVR_ORACLE
  int page;
  vec3 coordinate = hovr_atlasCoord(hovr_gridOf(g_dataPos), page);
  float oracle = hovr_oracle_texture(page, coordinate).r;
  float d = max(oracle * hovr_oracleScale, 1.0);
#else
  float d = 1.0;
#endif
  // 2^q, q = min(floor(log2 d), l_max): the powers of two up to min(d, 2^l_max), counted
  // exactly (no log2 rounding at powers of two, l_max <= 8).
  float capped = min(d, hovr_maximumSpan);
  float span = 1.0 + dot(step(vec4(2.0, 4.0, 8.0, 16.0), vec4(capped)), vec4(1.0, 2.0, 4.0, 8.0)) +
    dot(step(vec4(32.0, 64.0, 128.0, 256.0), vec4(capped)), vec4(16.0, 32.0, 64.0, 128.0));
  float next = (floor(hovr_slice / span) + 1.0) * span;
  if (next - hovr_entrySlice > hovr_endSteps)
  {
    g_exit = true; // the next slice lies beyond the end: the exit integrates up to it
    return;
  }
  hovr_moveToSlice(next, 1.0);
}

void hovr_adaptiveExit()
{
  // From the last sample (or the entry) to the box exit or the termination point.
  if (hovr_done || g_fragColor.a > g_opacityThreshold)
  {
    return;
  }
  float slices = hovr_endSteps - (hovr_frontSlice - hovr_entrySlice);
  if (slices > 0.0)
  {
    hovr_compositeSlices(
      hovr_sFront, hovr_sampleCoord(hovr_entry + hovr_endSteps * g_dirStep), slices);
  }
}
