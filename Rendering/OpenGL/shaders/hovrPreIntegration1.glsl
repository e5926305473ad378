// hovr: first-order pre-integrated classification (Engel, Kraus and Ertl 2001; El Hajjar et
// al., section 3.2.2). The ray is cut into segments between consecutive samples; a segment's
// premultiplied colour and opacity, self-attenuation included, come from a 2D table over
// (chord centre (front + back) / 2, chord back - front) built for the sample distance. The
// first segment starts where the ray enters the volume and the last one ends where it leaves
// it or is terminated, so that no piece at the faces is lost or counted twice.
//
// hovrPreIntegrationCommon.glsl (inserted before) walks the ray and calls hovr_pieceStart and
// hovr_piece for this brick's segments. With HOVR_SHADED, hovrPreIntegrationShading.glsl
// (inserted before) gives the segment's colour from the normals at its ends as well.
#if !HOVR_SHADED
uniform sampler2D hovr_preintTable;

vec3 hovr_normalAt(vec3 p)
{
  return vec3(0.0);
}

vec4 hovr_segment(float sFront, float sBack, vec3 nFront, vec3 nBack)
{
  return texture(
    hovr_preintTable, vec2(0.5 * (sFront + sBack), 0.5 + (sBack - sFront) * hovr_chordScale));
}
#endif

float hovr_sFront;   // table coordinate of the segment's front sample
vec3 hovr_nFront;    // its normal (shaded only)
float hovr_runFront; // its zero-opacity run

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

void hovr_pieceStart(float t)
{
  vec3 p = hovr_at(t);
  hovr_sFront = hovr_tableCoord(p);
  hovr_nFront = hovr_normalAt(p);
  hovr_runFront = hovr_emptyRun(hovr_sFront);
}

void hovr_piece(float tFront, float tBack)
{
  vec3 p = hovr_at(tBack);
  float sBack = hovr_tableCoord(p);
  vec3 nBack = hovr_normalAt(p);
  float runBack = hovr_emptyRun(sBack);
  // Both ends in one zero-opacity run: the segment is empty, no table fetch. A segment whose
  // back lies in a cropped region is not drawn.
#if HOVR_SKIP_EMPTY
  if (!hovr_cropped(p) && (runBack < 0.0 || runBack != hovr_runFront))
#else
  if (!hovr_cropped(p))
#endif
  {
    hovr_compositeSegment(hovr_sFront, sBack, hovr_nFront, nBack, (tBack - tFront) / hovr_step);
  }
  hovr_sFront = sBack;
  hovr_nFront = nBack;
  hovr_runFront = runBack;
}
