// hovr: second-order pre-integrated classification (El Hajjar, Marchesin, Dischler and
// Mongenet 2008, Eq. 2-3). The ray is cut into slabs of two sample distances whose front,
// middle and back samples fix a quadratic scalar profile; a slab's premultiplied colour and
// opacity, self-attenuation included, come from a 3D table built for that slab length over
// the chord's centre (front + back) / 2, the chord back - front and the middle sample's
// deviation from the centre (the same three samples, where slabs fall). Each sample is fetched once (a slab's back is the next one's front),
// the table once per slab.
//
// One iteration of VTK's ray loop handles one slab: the loop's sample is the slab's middle and
// the step fetches the back one sample further and moves the ray there (g_dataPos and
// g_currentT), so VTK's own advance lands on the next middle; the loop runs half as often.
// Slabs start at the ray's entry point when VTK places the first sample one full step inside
// (no jittering); with jittering the short piece before the first sample is integrated on its
// own and slabs start at the first sample. What remains after the last full slab, up to where
// the ray leaves the volume or is terminated, is integrated as one shorter slab through its
// front, its midpoint and its end (two extra fetches per ray): no thin shell at the exit face
// is lost and no slab reaches past it. A shorter slab keeps the table's colour per opacity and
// rescales the optical depth by its length, exact for a constant scalar.
//
// Inserted into vtkOpenGLGPUVolumeRayCastMapper's fragment shader by
// vtkPreIntegrationVolumeMapper, which calls hovr_preintInit, hovr_preintStep and
// hovr_preintExit where VTK's shading code would initialise, sample and finish a ray. With
// HOVR_SHADED, the slab's colour comes from the normals at its three samples as well.

// Deviation coordinate of a difference of centre-axis coordinates (0 at 1/2).
uniform float hovr_deviationScale;

#if !HOVR_SHADED
uniform sampler3D hovr_preintTable;

vec3 hovr_normalAt(vec3 pos)
{
  return vec3(0.0);
}

vec4 hovr_slab(float sf, float sm, float sb, vec3 nf, vec3 nm, vec3 nb)
{
  float centre = 0.5 * (sf + sb);
  return texture(hovr_preintTable,
    vec3(centre, 0.5 + (sb - sf) * hovr_chordScale, 0.5 + (sm - centre) * hovr_deviationScale));
}
#else
// Shaded (hovrPreIntegrationShading.glsl, inserted before, with HOVR_SLABS): each half slab
// is shaded as a first-order segment between the normals at its ends, (front, middle) and
// (middle, back), from its own moment layers; the arc passes through the middle normal. The
// two halves' colours and opacities add up to the slab's.
vec4 hovr_slab(float sf, float sm, float sb, vec3 nf, vec3 nm, vec3 nb)
{
  float centre = 0.5 * (sf + sb);
  vec3 coord =
    vec3(centre, 0.5 + (sb - sf) * hovr_chordScale, 0.5 + (sm - centre) * hovr_deviationScale);
  return hovr_shade(0, coord, nf, nm) + hovr_shade(HOVR_LAYERS, coord, nm, nb);
}
#endif

// hovr_emptyRuns, hovr_tableSize, hovr_rawToTable, hovr_tableCoord, hovr_emptyRun and
// hovr_stepsToExit: hovrPreIntegrationCommon.glsl.

float hovr_sFront;      // table coordinate of the slab's front sample
vec3 hovr_nFront;       // its normal (shaded only)
float hovr_runFront;    // its zero-opacity run
float hovr_frontIndex;  // its position in sample distances from the first sample
vec3 hovr_frontPos;     // and in texture coordinates
float hovr_endIndex;    // where the ray ends (box exit or termination), in the same units

// True when the quadratic through the three samples stays inside one zero-opacity run: its
// range is spanned by its ends and, when inside the slab, its extremum (Eq. 2).
bool hovr_slabIsEmpty(float sf, float sm, float sb, float runFront, float runBack)
{
  if (runFront < 0.0 || runFront != runBack)
  {
    return false;
  }
  float a = 2.0 * sf - 4.0 * sm + 2.0 * sb;
  float b = -3.0 * sf + 4.0 * sm - sb;
  float extremum;
  return !hovr_slabExtremum(sf, b, a, extremum) || hovr_emptyRun(extremum) == runFront;
}

// Composite the slab (sf, sm, sb) with normals (nf, nm, nb) covering `fraction` of the
// table's slab length.
void hovr_compositeSlab(float sf, float sm, float sb, vec3 nf, vec3 nm, vec3 nb, float fraction)
{
  if (!(fraction > 0.0) || isnan(sf) || isnan(sm) || isnan(sb))
  {
    return;
  }
  vec4 slab = hovr_slab(sf, sm, sb, nf, nm, nb);
  if (fraction < 1.0)
  {
    float alpha = 1.0 - pow(max(1.0 - slab.a, 0.0), fraction);
    slab.rgb *= slab.a > 1e-6 ? alpha / slab.a : fraction;
    slab.a = alpha;
  }
  g_fragColor += (1.0 - g_fragColor.a) * slab;
}

// A piece shorter than a slab from `from`, `steps` sample distances long: its midpoint and
// end are fetched, then it is composited as a slab scaled to its length.
void hovr_compositePiece(vec3 from, float sFrom, vec3 nFrom, float steps)
{
  if (steps > 0.0)
  {
    vec3 middle = from + 0.5 * steps * g_dirStep, end = from + steps * g_dirStep;
    hovr_compositeSlab(sFrom, hovr_tableCoord(middle), hovr_tableCoord(end), nFrom,
      hovr_normalAt(middle), hovr_normalAt(end), 0.5 * steps);
  }
}

void hovr_preintInit()
{
#if HOVR_SHADED
  hovr_view = -computeRayDirection();
#endif
  vec3 entry = g_dataPos - g_rayJitter;
  float jitter = length(g_rayJitter) / length(g_dirStep);
  hovr_endIndex = min(hovr_stepsToExit(entry) - jitter, g_terminatePointMax);
  float sEntry = hovr_tableCoord(entry);
  if (jitter > 0.999)
  {
    // The first sample lies one step inside: the entry is the first slab's front.
    hovr_sFront = sEntry;
    hovr_nFront = hovr_normalAt(entry);
    hovr_frontPos = entry;
    hovr_frontIndex = -1.0;
  }
  else
  {
    // Jittered: the piece before the first sample on its own, then slabs from that sample,
    // whose middle is the next one.
    hovr_compositePiece(
      entry, sEntry, hovr_normalAt(entry), min(jitter, hovr_endIndex + jitter));
    hovr_sFront = hovr_tableCoord(g_dataPos);
    hovr_nFront = hovr_normalAt(g_dataPos);
    hovr_frontPos = g_dataPos;
    hovr_frontIndex = 0.0;
    g_dataPos += g_dirStep;
    g_currentT += 1.0;
  }
  hovr_runFront = hovr_emptyRun(hovr_sFront);
}

void hovr_preintStep()
{
  if (hovr_frontIndex + 2.0 > hovr_endIndex)
  {
    g_exit = true; // no full slab fits any more: the exit code integrates the rest
    return;
  }
  float sMiddle = hovr_tableCoord(g_dataPos);
  vec3 backPos = g_dataPos + g_dirStep;
  float sBack = hovr_tableCoord(backPos);
  vec3 nBack = hovr_normalAt(backPos);
  float runBack = hovr_emptyRun(sBack);
  // Both ends and the extremum in one zero-opacity run: the slab is empty, no table fetch.
#if HOVR_SKIP_EMPTY
  if (!g_skip && !hovr_slabIsEmpty(hovr_sFront, sMiddle, sBack, hovr_runFront, runBack))
#else
  if (!g_skip)
#endif
  {
    hovr_compositeSlab(
      hovr_sFront, sMiddle, sBack, hovr_nFront, hovr_normalAt(g_dataPos), nBack, 1.0);
  }
  hovr_sFront = sBack;
  hovr_nFront = nBack;
  hovr_runFront = runBack;
  hovr_frontPos = backPos;
  hovr_frontIndex += 2.0;
  // Move to the back; VTK's own advance then lands on the next slab's middle.
  g_dataPos = backPos;
  g_currentT += 1.0;
}

void hovr_preintExit()
{
  if (g_fragColor.a > g_opacityThreshold)
  {
    return;
  }
  // What lies between the last slab's back and the ray's end is less than a slab.
  hovr_compositePiece(
    hovr_frontPos, hovr_sFront, hovr_nFront, min(hovr_endIndex - hovr_frontIndex, 2.0));
}
