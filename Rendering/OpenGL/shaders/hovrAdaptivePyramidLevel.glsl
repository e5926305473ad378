//VTK::System::Dec
#extension GL_ARB_gpu_shader_fp64 : require
// hovr: one pass of "Adaptive Sampling in Three Dimensions for Volume Rendering on GPUs":
// Fig. 7 for every pixel of pyramid level `level` on slice `slice` (Sec. 3.2-3.4), the GPU
// mirror of vtkAdaptiveSamplingRayCaster. One fragment per level pixel.
//
// Render targets, read from the previous pass of this level (the *In samplers) and written
// here:
//   0 state:  (s as table index, d high, d low, terminated): d in slice spacings is kept as a
//             float pair so that it holds the double the CPU core decides on;
//   1 counts: (samples, syntheses, accumulates, boundary fetches) since the frame began, when
//             countOperations is 1 (otherwise neither read nor drawn);
//   2 level 0 only, previous: (s_prev as table index, i_prev, 0, 0) (Fig. 6);
//   3 level 0 only, colour: premultiplied (C, alpha).

//VTK::Output::Dec

// The quad helper's texture coordinate: read below only so that its vertex attribute stays
// active (the pixel comes from gl_FragCoord, exact at pixel centres).
in vec2 texCoord;

uniform int level;      // l
uniform int sliceLevel; // l_slice (Table 1)
uniform int maxLevel;   // l_max
uniform int slice;      // i_slice
uniform int lastSlice;  // i_max
uniform int segmentTables; // 2^l_max
uniform int tableSize;
uniform int minimumOracle;    // 1: d = 1 everywhere
uniform int earlyTermination; // 1: stop opaque rays
uniform int countOperations;  // 1: keep the counters
uniform float invalidValue;   // NaN: a sample outside the box
uniform float opacityThreshold;
uniform vec2 imageSize; // the viewport (unpadded) in level-0 pixels

uniform dvec3 rayOrigin; // index-space point of image coordinates (0, 0) on slice 0
uniform dvec3 rayAxisX;  // index-space offset per unit of image x in [-1, 1]
uniform dvec3 rayAxisY;
uniform dvec3 sliceStep; // index-space offset from one slice to the next
uniform dvec3 boxMax;    // grid dimensions - 1
// The whole volume's box (its index space: [0, boxMax] unless the input is a piece of it):
// outside it samples are NaN, and its faces end the rays.
uniform dvec3 wholeMin;
uniform dvec3 wholeMax;
// A piece with ghost points (1): level 0 composites only the segments between the slices of
// 2^l_max that join its walks to the neighbours' (see hovrOwnedSlices), found from the rays in
// structured index (the same operations on every piece): image coordinates (0, 0) on slice 0,
// per unit of x and y, per slice; the owned points' box and which of its faces are shared.
uniform int piece;
uniform dvec3 structuredOrigin;
uniform dvec3 structuredAxisX;
uniform dvec3 structuredAxisY;
uniform dvec3 structuredStep;
uniform dvec3 ownedLo;
uniform dvec3 ownedHi;
uniform ivec3 sharedLo;
uniform ivec3 sharedHi;
uniform dvec3 axisLength; // world length of one index unit along each axis
uniform double sliceSpacing; // Delta, world units

uniform sampler2D stateIn;
uniform sampler2D countsIn;
uniform sampler2D previousIn;
uniform sampler2D colourIn;
uniform sampler2D coarseState; // level + 1, this slice
uniform sampler2D fineState;   // level - 1, its last pass (terminated flags)
// The atlas (hovrVolumeAtlas.glsl) and its samplers (GetAtlasSamplerCode): volumeIndex, the
// scalars in their own type, and oracleWorld, oracle distances in world units, in the same
// tiles.
//HOVR::Atlas
uniform vec2 rawToIndex;        // the scalars' table index: raw * x + y
uniform sampler3D tables;       // tableSize x tableSize x 2^l_max segment tables

// The trilinear value at p (0-based continuous grid index), clamped to the box of the points:
// vtkPreIntegrationRayMarch::Grid::Sample.
void hovrCell(dvec3 p, out ivec3 cell, out dvec3 w)
{
  dvec3 x = min(max(p, dvec3(0.0)), boxMax);
  cell = min(ivec3(x), ivec3(boxMax) - 1);
  w = x - dvec3(cell);
}

float hovrSampleVolume(dvec3 p)
{
  ivec3 c;
  dvec3 wd;
  hovrCell(p, c, wd);
  vec3 w = vec3(wd);
  int page;
  c = hovr_atlasTexel(c, page);
  float v000 = volumeIndex_texelFetch(page, c).r;
  float v100 = volumeIndex_texelFetch(page, c + ivec3(1, 0, 0)).r;
  float v010 = volumeIndex_texelFetch(page, c + ivec3(0, 1, 0)).r;
  float v110 = volumeIndex_texelFetch(page, c + ivec3(1, 1, 0)).r;
  float v001 = volumeIndex_texelFetch(page, c + ivec3(0, 0, 1)).r;
  float v101 = volumeIndex_texelFetch(page, c + ivec3(1, 0, 1)).r;
  float v011 = volumeIndex_texelFetch(page, c + ivec3(0, 1, 1)).r;
  float v111 = volumeIndex_texelFetch(page, c + ivec3(1, 1, 1)).r;
  float c00 = v000 + w.x * (v100 - v000);
  float c10 = v010 + w.x * (v110 - v010);
  float c01 = v001 + w.x * (v101 - v001);
  float c11 = v011 + w.x * (v111 - v011);
  float c0 = c00 + w.y * (c10 - c00);
  float c1 = c01 + w.y * (c11 - c01);
  return (c0 + w.z * (c1 - c0)) * rawToIndex.x + rawToIndex.y;
}

// The oracle in double, as the CPU core interpolates it, so that d decides as it does there.
double hovrSampleOracle(dvec3 p)
{
  ivec3 c;
  dvec3 w;
  hovrCell(p, c, w);
  int page;
  c = hovr_atlasTexel(c, page);
  double v000 = double(oracleWorld_texelFetch(page, c).r);
  double v100 = double(oracleWorld_texelFetch(page, c + ivec3(1, 0, 0)).r);
  double v010 = double(oracleWorld_texelFetch(page, c + ivec3(0, 1, 0)).r);
  double v110 = double(oracleWorld_texelFetch(page, c + ivec3(1, 1, 0)).r);
  double v001 = double(oracleWorld_texelFetch(page, c + ivec3(0, 0, 1)).r);
  double v101 = double(oracleWorld_texelFetch(page, c + ivec3(1, 0, 1)).r);
  double v011 = double(oracleWorld_texelFetch(page, c + ivec3(0, 1, 1)).r);
  double v111 = double(oracleWorld_texelFetch(page, c + ivec3(1, 1, 1)).r);
  double c00 = v000 + w.x * (v100 - v000);
  double c10 = v010 + w.x * (v110 - v010);
  double c01 = v001 + w.x * (v101 - v001);
  double c11 = v011 + w.x * (v111 - v011);
  double c0 = c00 + w.y * (c10 - c00);
  double c1 = c01 + w.y * (c11 - c01);
  return c0 + w.z * (c1 - c0);
}

// Whether p (0-based continuous grid index) lies outside the whole volume's closed box;
// outside receives the squared world distance to the box.
bool hovrOutside(dvec3 p, out double outside)
{
  dvec3 excess = max(wholeMin - p, p - wholeMax);
  outside = 0.0lf;
  for (int a = 0; a < 3; ++a)
  {
    if (excess[a] > 0.0lf)
    {
      outside += excess[a] * excess[a] * axisLength[a] * axisLength[a];
    }
  }
  return outside > 0.0lf;
}

// The slice coordinates where the ray o + t sliceStep enters and leaves the box, clipped to
// [0, i_max] (the slab method per axis): vtkAdaptiveSamplingRayCaster::ClipSlices.
void hovrClipSlices(dvec3 o, out double tEntry, out double tExit)
{
  tEntry = 0.0lf;
  tExit = double(lastSlice);
  for (int a = 0; a < 3 && tEntry <= tExit; ++a)
  {
    if (sliceStep[a] == 0.0lf)
    {
      if (o[a] < wholeMin[a] || o[a] > wholeMax[a])
      {
        tExit = -1.0lf;
      }
      continue;
    }
    double ta = (wholeMin[a] - o[a]) / sliceStep[a], tb = (wholeMax[a] - o[a]) / sliceStep[a];
    tEntry = max(tEntry, min(ta, tb));
    tExit = min(tExit, max(ta, tb));
  }
}

// The slices [first, last] between which a piece's level-0 ray at image coordinates (x, y)
// composites: from the first slice of 2^l_max at or after it enters the owned points through a
// face it shares with another piece, to the first at or after it leaves them so (unbounded
// through a face of the whole volume). Every walk samples those slices and restarts its
// pyramid there, so the pieces' walks join into the whole volume's; a ray in a shared face
// belongs to the piece above it. first > last when the ray owns nothing.
void hovrOwnedSlices(double x, double y, out double first, out double last)
{
  const double far = 1e300lf;
  dvec3 o = structuredOrigin + x * structuredAxisX + y * structuredAxisY;
  double ta = -far, tb = far;
  for (int a = 0; a < 3; ++a)
  {
    bool lo = sharedLo[a] != 0, hi = sharedHi[a] != 0;
    if (structuredStep[a] == 0.0lf)
    {
      if ((lo && o[a] < ownedLo[a]) || (hi && o[a] >= ownedHi[a]))
      {
        first = far;
        last = -far;
        return;
      }
      continue;
    }
    double tLo = (ownedLo[a] - o[a]) / structuredStep[a];
    double tHi = (ownedHi[a] - o[a]) / structuredStep[a];
    bool up = structuredStep[a] > 0.0lf;
    if (up ? lo : hi)
    {
      ta = max(ta, up ? tLo : tHi);
    }
    if (up ? hi : lo)
    {
      tb = min(tb, up ? tHi : tLo);
    }
  }
  double block = double(segmentTables);
  first = ta > -far ? ceil(ta / block) * block : -far;
  last = tb < far ? ceil(tb / block) * block : far;
}

// The segment of k slice spacings from table index sf to sb: the k-th table read as
// vtkPreIntegrationRayMarch::TablePieces reads a first-order table (bilinear, entries at
// texel centres, clamped to the edge entries).
vec4 hovrSegment(float sf, float sb, int k)
{
  float last = float(tableSize - 1);
  vec2 x = clamp(vec2(sf, sb), vec2(0.0), vec2(last));
  ivec2 i = min(ivec2(x), ivec2(tableSize - 2));
  vec2 w = x - vec2(i);
  int z = k - 1;
  vec4 e00 = texelFetch(tables, ivec3(i.x, i.y, z), 0);
  vec4 e10 = texelFetch(tables, ivec3(i.x + 1, i.y, z), 0);
  vec4 e01 = texelFetch(tables, ivec3(i.x, i.y + 1, z), 0);
  vec4 e11 = texelFetch(tables, ivec3(i.x + 1, i.y + 1, z), 0);
  return (1.0 - w.x) * (1.0 - w.y) * e00 + w.x * (1.0 - w.y) * e10 + (1.0 - w.x) * w.y * e01 +
    w.x * w.y * e11;
}

void main()
{
  if (texCoord.x < -1.0)
  {
    discard; // never: the quad's coordinates lie in [0, 1]
  }
  ivec2 pixel = ivec2(gl_FragCoord.xy);
  vec4 state = texelFetch(stateIn, pixel, 0);
  vec4 counts = countOperations != 0 ? texelFetch(countsIn, pixel, 0) : vec4(0.0);
  float s = state.x;
  double d = double(state.y) + double(state.z);

  // This pixel's ray (Fig. 5, lines 137-138): through level-0 pixel
  // (2^l (x + 1/2) - 1/2, 2^l (y + 1/2) - 1/2); o on slice 0, p on this slice.
  double scale = double(1 << level);
  double px = 2.0lf * (scale * (double(pixel.x) + 0.5lf)) / double(imageSize.x) - 1.0lf;
  double py = 2.0lf * (scale * (double(pixel.y) + 0.5lf)) / double(imageSize.y) - 1.0lf;
  dvec3 o = rayOrigin + px * rayAxisX + py * rayAxisY;
  dvec3 p = o + double(slice) * sliceStep;
  double outside = 0.0lf;

  // SYNTHESIZE (Fig. 5): bilinear lookup of level + 1 at this pixel's centre, coarse
  // coordinate x / 2 - 1/4, clamped to the edge (line 127); NaN spreads from any neighbour.
  bool synthesized = level < sliceLevel;
  if (synthesized)
  {
    ivec2 coarseSize = textureSize(coarseState, 0);
    ivec2 odd = pixel & 1;
    ivec2 x0 = pixel / 2 - (1 - odd);
    dvec2 wd = mix(dvec2(0.75), dvec2(0.25), bvec2(odd));
    vec2 wf = vec2(wd);
    ivec2 a = max(x0, ivec2(0));
    ivec2 b = min(x0 + 1, coarseSize - 1);
    vec4 gaa = texelFetch(coarseState, ivec2(a.x, a.y), 0);
    vec4 gba = texelFetch(coarseState, ivec2(b.x, a.y), 0);
    vec4 gab = texelFetch(coarseState, ivec2(a.x, b.y), 0);
    vec4 gbb = texelFetch(coarseState, ivec2(b.x, b.y), 0);
    double daa = double(gaa.y) + double(gaa.z), dba = double(gba.y) + double(gba.z);
    double dab = double(gab.y) + double(gab.z), dbb = double(gbb.y) + double(gbb.z);
    double d0 = daa + wd.x * (dba - daa);
    double d1 = dab + wd.x * (dbb - dab);
    d = d0 + wd.y * (d1 - d0);
    float s0 = gaa.x + wf.x * (gba.x - gaa.x);
    float s1 = gab.x + wf.x * (gbb.x - gab.x);
    s = s0 + wf.y * (s1 - s0);
    counts.y += 1.0;
  }

  // Early ray termination: level 0 by its own opacity; a coarser pixel when every finer pixel
  // whose synthesis reads it (x in 2X - 1 .. 2X + 2, clamped) has stopped.
  vec4 previous = vec4(0.0);
  vec4 colour = vec4(0.0);
  if (level == 0)
  {
    previous = texelFetch(previousIn, pixel, 0);
    colour = texelFetch(colourIn, pixel, 0);
  }
  bool terminated = false;
  if (earlyTermination != 0)
  {
    if (level == 0)
    {
      terminated = colour.a >= opacityThreshold;
    }
    else
    {
      ivec2 fineSize = textureSize(fineState, 0);
      terminated = true;
      for (int j = -1; j <= 2 && terminated; ++j)
      {
        for (int i = -1; i <= 2 && terminated; ++i)
        {
          ivec2 f = clamp(2 * pixel + ivec2(i, j), ivec2(0), fineSize - 1);
          terminated = texelFetch(fineState, f, 0).w > 0.5;
        }
      }
    }
  }

  // Fig. 7 decides both tests on d before it is resampled (lines 177-190).
  bool accumulate = (sliceLevel == maxLevel || d < double(1 << (sliceLevel + 1))) && !terminated;
  // On a slice the pixel accumulates, a NaN from a coarse neighbour outside the box at a point
  // inside it is sampled instead (vtkAdaptiveSamplingRayCaster's rule).
  bool repair = synthesized && accumulate && (isnan(s) || isnan(d)) && !hovrOutside(p, outside);
  bool sampleHere =
    (repair || level == maxLevel || d < double(1 << (level + 1))) && !terminated;
  if (sampleHere)
  {
    // SAMPLE and ORACLE (Fig. 5) on this slice.
    if (hovrOutside(p, outside))
    {
      // Line 68's default value: NaN, a transparent segment end. The oracle is the distance
      // to the box, so that rays approach the entry face with shrinking steps.
      s = invalidValue;
      d = minimumOracle != 0 ? 1.0lf : sqrt(outside) / sliceSpacing;
    }
    else
    {
      s = hovrSampleVolume(p);
      d = minimumOracle != 0 ? 1.0lf : hovrSampleOracle(p) / sliceSpacing;
      counts.x += 1.0;
    }
    d = min(max(d, 1.0lf), double(segmentTables));
  }

  if (level == 0 && accumulate)
  {
    // ACCUMULATECOLOR (Fig. 6): the part of the k = i - i_prev slice spacings inside the box,
    // [max(i_prev, t_in), min(i, t_out)]; an end on a face takes the scalar fetched there
    // (which end is on a face: the slice points' own inside test, as in the CPU core).
    if (previous.y >= 0.0)
    {
      int previousSlice = int(previous.y);
      double tIn, tOut;
      hovrClipSlices(o, tIn, tOut);
      double front = max(double(previousSlice), tIn);
      double back = min(double(slice), tOut);
      double pieceLength = back - front;
      bool owned = true;
      if (piece != 0)
      {
        double first, last;
        hovrOwnedSlices(px, py, first, last);
        owned = double(previousSlice) >= first && double(slice) <= last;
      }
      if (owned && pieceLength > 0.0lf && slice - previousSlice <= segmentTables)
      {
        float sf = previous.x, sb = s;
        double unused;
        if (hovrOutside(o + double(previousSlice) * sliceStep, unused))
        {
          sf = hovrSampleVolume(o + front * sliceStep);
          counts.w += 1.0;
        }
        if (hovrOutside(p, unused))
        {
          sb = hovrSampleVolume(o + back * sliceStep);
          counts.w += 1.0;
        }
        if (!isnan(sf) && !isnan(sb))
        {
          // Table ceil(L) with the optical depth scaled to L (exact for a constant scalar),
          // as first-order pre-integration composites its last piece.
          double layers = ceil(pieceLength);
          vec4 segment = hovrSegment(sf, sb, int(layers));
          float fraction = float(pieceLength / layers);
          if (fraction < 1.0)
          {
            float alpha = 1.0 - pow(max(1.0 - segment.a, 0.0), fraction);
            segment.rgb *= segment.a > 1e-6 ? alpha / segment.a : fraction;
            segment.a = alpha;
          }
          colour += (1.0 - colour.a) * segment;
        }
      }
      counts.z += 1.0;
    }
    previous = vec4(s, float(slice), 0.0, 0.0);
  }

  bool stopped = false;
  if (earlyTermination != 0)
  {
    stopped = level == 0 ? colour.a >= opacityThreshold : terminated;
  }
  float high = float(d);
  gl_FragData[0] = vec4(s, high, float(d - double(high)), stopped ? 1.0 : 0.0);
  gl_FragData[1] = counts;
  gl_FragData[2] = previous;
  gl_FragData[3] = colour;
}
