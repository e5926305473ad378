// hovr: skipping along rays with an oracle ("Adaptive Sampling in Three Dimensions for Volume
// Rendering on GPUs", Sec. 3.1) and first-order pre-integrated segments of variable length
// (Sec. 3.3, Fig. 6). Samples lie on a global grid of slices spaced one sample distance:
// planes perpendicular to the view (parallel camera) or spheres around the eye (perspective),
// slice coordinate 0 at the volume's point nearest to the camera. From a sample on slice i
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
// vtkAdaptiveRayVolumeMapper after computeRayDirection(), with hovrPreIntegrationCommon.glsl
// (hovr_tableSize, hovr_rawToTable, hovr_tableCoord, hovr_stepsToExit) before it and the
// switches HOVR_ORACLE (sample the oracle texture, else d = 1), HOVR_COUNT_SAMPLES (count the
// slice samples in an atomic counter) and HOVR_TILES (more than one layer).

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
uniform sampler3D hovr_oracle;  // oracle distance in world units, trilinear
uniform float hovr_oracleScale; // 1 / Delta
#endif
#if HOVR_COUNT_SAMPLES
layout(binding = 0, offset = 0) uniform atomic_uint hovr_sampleCounter;
#endif

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
  hovr_sFront = hovr_tableCoord(hovr_entry);
  hovr_done = !(hovr_endSteps > 0.0);
  // A ray entering within rounding of a slice starts on it (an axis-aligned view enters on
  // slice 0 exactly).
  float first = ceil(hovr_entrySlice - 1e-3);
  if (hovr_done || first - hovr_entrySlice > hovr_endSteps)
  {
    g_exit = true; // no slice before the end: the exit integrates entry to end
    return;
  }
  hovr_moveToSlice(first, 0.0);
}

void hovr_adaptiveStep()
{
  float s = hovr_tableCoord(g_dataPos);
#if HOVR_COUNT_SAMPLES
  atomicCounterIncrement(hovr_sampleCounter);
#endif
  hovr_compositeSlices(hovr_sFront, s, hovr_slice - hovr_frontSlice);
  hovr_sFront = s;
  hovr_frontSlice = hovr_slice;
#if HOVR_ORACLE
  float d = max(texture(hovr_oracle, g_dataPos).r * hovr_oracleScale, 1.0);
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
      hovr_sFront, hovr_tableCoord(hovr_entry + hovr_endSteps * g_dirStep), slices);
  }
}
