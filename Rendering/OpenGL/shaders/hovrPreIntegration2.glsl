// hovr: second-order pre-integrated classification (El Hajjar, Marchesin, Dischler and
// Mongenet 2008, Eq. 2-3). The ray is cut into slabs of two sample distances whose front,
// middle and back samples fix a quadratic scalar profile; a slab's premultiplied colour and
// opacity, self-attenuation included, come from a 3D table built for that slab length over
// the chord's centre (front + back) / 2, the chord back - front and the middle sample's
// deviation from the centre (the same three samples, where slabs fall). Each sample is fetched
// once (a slab's back is the next one's front), the table once per slab.
//
// Slabs lie between the even samples of the ray's own grid (hovrPreIntegrationCommon.glsl,
// inserted before, walks them and calls hovr_pieceStart and hovr_piece): each whole slab's
// middle is the odd sample between. The piece from where the ray enters the volume to the
// first even sample, and the one from the last even sample to where the ray leaves it or is
// terminated, are integrated as shorter slabs through their front, their midpoint and their
// back: no thin shell at a face is lost and no slab reaches past it. A shorter slab keeps the
// table's colour per opacity and rescales the optical depth by its length, exact for a
// constant scalar. With HOVR_SHADED, the slab's colour comes from the normals at its three
// samples as well.

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

float hovr_sFront;   // table coordinate of the slab's front sample
vec3 hovr_nFront;    // its normal (shaded only)
float hovr_runFront; // its zero-opacity run

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

void hovr_pieceStart(float t)
{
  vec3 p = hovr_at(t);
  hovr_sFront = hovr_tableCoord(p);
  hovr_nFront = hovr_normalAt(p);
  hovr_runFront = hovr_emptyRun(hovr_sFront);
}

void hovr_piece(float tFront, float tBack)
{
  vec3 middle = hovr_at(0.5 * (tFront + tBack));
  vec3 back = hovr_at(tBack);
  float sMiddle = hovr_tableCoord(middle);
  float sBack = hovr_tableCoord(back);
  vec3 nBack = hovr_normalAt(back);
  float runBack = hovr_emptyRun(sBack);
  // Both ends and the extremum in one zero-opacity run: the slab is empty, no table fetch. A
  // slab whose back lies in a cropped region is not drawn.
#if HOVR_SKIP_EMPTY
  if (!hovr_cropped(back) && !hovr_slabIsEmpty(hovr_sFront, sMiddle, sBack, hovr_runFront, runBack))
#else
  if (!hovr_cropped(back))
#endif
  {
    hovr_compositeSlab(hovr_sFront, sMiddle, sBack, hovr_nFront, hovr_normalAt(middle), nBack,
      (tBack - tFront) / hovr_span);
  }
  hovr_sFront = sBack;
  hovr_nFront = nBack;
  hovr_runFront = runBack;
}
