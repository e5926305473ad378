// hovr: first-order pre-integrated classification (Engel, Kraus and Ertl 2001; El Hajjar et
// al., section 3.2.2). The ray is cut into segments between consecutive samples; a segment's
// premultiplied colour and opacity, self-attenuation included, come from a 2D table over
// (chord centre (front + back) / 2, chord back - front) built for the sample distance. The first segment starts at the
// ray's entry point and the last one ends where the ray leaves the volume or is terminated,
// so that no slab at the faces is lost or counted twice.
//
// Inserted into vtkOpenGLGPUVolumeRayCastMapper's fragment shader by
// vtkPreIntegrationVolumeMapper, which calls hovr_preintInit, hovr_preintStep and
// hovr_preintExit where VTK's shading code would initialise, sample and finish a ray. With
// HOVR_SHADED, hovrPreIntegrationShading.glsl (inserted before) gives the segment's colour
// from the normals at its ends as well.

// hovr_emptyRuns, hovr_tableSize, hovr_rawToTable, hovr_tableCoord, hovr_emptyRun and
// hovr_stepsToExit: hovrPreIntegrationCommon.glsl.
#if !HOVR_SHADED
uniform sampler2D hovr_preintTable;

vec3 hovr_normalAt(vec3 pos)
{
  return vec3(0.0);
}

vec4 hovr_segment(float sFront, float sBack, vec3 nFront, vec3 nBack)
{
  return texture(
    hovr_preintTable, vec2(0.5 * (sFront + sBack), 0.5 + (sBack - sFront) * hovr_chordScale));
}
#endif

float hovr_sFront;    // table coordinate of the previous sample
vec3 hovr_nFront;     // its normal (shaded only)
float hovr_runFront;  // its zero-opacity run
float hovr_fraction;  // the next segment's length in sample distances (1 inside the ray)
vec3 hovr_entry;      // where the ray entered the volume (texture coordinates)

// Composite the segment (sFront, sBack) covering `fraction` of the sample distance. A partial
// segment keeps the table's colour per opacity and rescales the optical depth by its length,
// which is exact for a constant scalar.
void hovr_compositeSegment(float sFront, float sBack, vec3 nFront, vec3 nBack, float fraction)
{
  if (!(fraction > 0.0) || isnan(sFront) || isnan(sBack))
  {
    return;
  }
  vec4 segment = hovr_segment(sFront, sBack, nFront, nBack);
  if (fraction < 1.0)
  {
    float alpha = 1.0 - pow(max(1.0 - segment.a, 0.0), fraction);
    segment.rgb *= segment.a > 1e-6 ? alpha / segment.a : fraction;
    segment.a = alpha;
  }
  g_fragColor += (1.0 - g_fragColor.a) * segment;
}

void hovr_preintInit()
{
#if HOVR_SHADED
  hovr_view = -computeRayDirection();
#endif
  hovr_entry = g_dataPos - g_rayJitter;
  hovr_sFront = hovr_tableCoord(hovr_entry);
  hovr_nFront = hovr_normalAt(hovr_entry);
  hovr_runFront = hovr_emptyRun(hovr_sFront);
  // From the entry to the first sample: one jitter offset, unless the box ends first; then
  // that shorter segment is all there is before the first sample.
  hovr_fraction = length(g_rayJitter) / length(g_dirStep);
  float inside = hovr_stepsToExit(hovr_entry);
  if (inside < hovr_fraction)
  {
    vec3 end = hovr_entry + inside * g_dirStep;
    hovr_compositeSegment(
      hovr_sFront, hovr_tableCoord(end), hovr_nFront, hovr_normalAt(end), max(inside, 0.0));
    hovr_fraction = 0.0;
  }
}

void hovr_preintStep()
{
  float sBack = hovr_tableCoord(g_dataPos);
  vec3 nBack = hovr_normalAt(g_dataPos);
  float runBack = hovr_emptyRun(sBack);
  // Both ends in one zero-opacity run: the segment is empty, no table fetch.
#if HOVR_SKIP_EMPTY
  if (!g_skip && (runBack < 0.0 || runBack != hovr_runFront))
#else
  if (!g_skip)
#endif
  {
    hovr_compositeSegment(hovr_sFront, sBack, hovr_nFront, nBack, hovr_fraction);
  }
  hovr_sFront = sBack;
  hovr_nFront = nBack;
  hovr_runFront = runBack;
  // The next segment counts only up to a termination point (depth buffer, clipping).
  hovr_fraction = clamp(g_terminatePointMax - g_currentT, 0.0, 1.0);
}

void hovr_preintExit()
{
  // The loop stopped after the sample at g_dataPos - g_dirStep (index g_currentT): add the
  // partial segment from it to the box exit or the termination point, whichever comes first.
  if (g_skip || g_fragColor.a > g_opacityThreshold)
  {
    return;
  }
  vec3 last = g_dataPos - g_dirStep;
  float fraction = min(hovr_stepsToExit(last), g_terminatePointMax - g_currentT);
  fraction = min(fraction, 1.0);
  if (fraction > 0.0)
  {
    vec3 end = last + fraction * g_dirStep;
    hovr_compositeSegment(
      hovr_sFront, hovr_tableCoord(end), hovr_nFront, hovr_normalAt(end), fraction);
  }
}
