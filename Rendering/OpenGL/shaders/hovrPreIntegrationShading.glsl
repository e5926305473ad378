// hovr: shaded pre-integration with non-linear gradient interpolation (Guetat, Ancel,
// Marchesin and Dischler 2010), for first-order segments and second-order slabs. A segment's
// shaded colour is a sum of moment tables (J_0..J_3 of the colour-weighted and of the plain
// extinction, layers of the table hovr_preintTable) weighted by dot products of the normals
// at its two ends with each light's direction and half vector. First order: the layers lie
// one above the other in the 2D texture hovr_preintTable (centre along x; layer, then chord
// along y), so a fetch filters bilinearly within its layer. The GLSL mirror of
// vtkVolumeShadingModel::ShadeSegment(), operation for operation.
//
// Switches set by vtkPreIntegrationVolumeMapper: HOVR_LAYERS (2 or 4 moment layers),
// HOVR_INTERPOLATION (0 constant, 1 linear, 2 non-linear), HOVR_GOOCH (Eq. 11 instead of
// Blinn-Phong), HOVR_NORMALS (normals from the texture hovr_normals instead of the normalised
// gradient, hovr_gradient), both in the volume's object coordinates, where the lights are
// given. HOVR_SLABS (second order, hovrPreIntegration2.glsl):
// the table is 3D over (chord centre, chord, deviation) and holds 2 HOVR_LAYERS layers one
// behind the other along its depth, the moments of each half slab (hovr_shade() with base 0
// and HOVR_LAYERS); without it, hovr_segment() shades a first-order segment.

#ifdef HOVR_SLABS
uniform sampler3D hovr_preintTable;
uniform float hovr_deviationTexels; // deviation entries per layer
#define hovr_tableCoord_t vec3
#else
uniform sampler2D hovr_preintTable;
uniform float hovr_chordTexels; // chord entries per layer
#define hovr_tableCoord_t vec2
#endif
uniform int hovr_numberOfLights;
uniform vec3 hovr_lightDirection[8]; // towards the light
uniform vec3 hovr_lightDiffuse[8];
uniform vec3 hovr_lightSpecular[8];
uniform int hovr_lightIsHead[8]; // 1: shines along the view direction
uniform vec4 hovr_lighting;      // Ka, Kd, Ks, the cone's slope n
uniform float hovr_minimumCosHalfAngle;
uniform int hovr_twoSided;
uniform vec3 hovr_goochCool;
uniform vec3 hovr_goochWarm;
uniform vec2 hovr_goochWeights; // a, b

#if HOVR_NORMALS
uniform sampler3D hovr_normals; // the normal array's brick (the volume's layout), trilinear
#endif

// The unit normal at a point of the brick's grid index (zero where the gradient vanishes).
vec3 hovr_normalAt(vec3 p)
{
#if HOVR_NORMALS
  vec3 g = texture(hovr_normals, (p + 0.5) * hovr_volumeInvTexels).xyz;
#else
  vec3 g = hovr_gradient(p);
#endif
  float len = length(g);
  return len > 0.0 ? g / len : vec3(0.0);
}

// The stacked coordinate (chord; deviation for slabs) is clamped to the layer's outer texel
// centres, where a single-layer texture's clamp-to-edge would hold it, so that no fetch
// blends two layers.
#ifdef HOVR_SLABS
vec4 hovr_layer(int l, vec3 coord)
{
  float z = clamp(coord.z, 0.5 / hovr_deviationTexels, 1.0 - 0.5 / hovr_deviationTexels);
  return texture(
    hovr_preintTable, vec3(coord.xy, (float(l) + z) / float(2 * HOVR_LAYERS)));
}
#else
vec4 hovr_layer(int l, vec2 coord)
{
  float y = clamp(coord.y, 0.5 / hovr_chordTexels, 1.0 - 0.5 / hovr_chordTexels);
  return texture(hovr_preintTable, vec2(coord.x, (float(l) + y) / float(HOVR_LAYERS)));
}
#endif

// N . d as a side is lit by it.
float hovr_side(float x)
{
  return hovr_twoSided != 0 ? abs(x) : x;
}

// The end dot products as the segment's shading sees them, and (z = 1) whether two-sided
// lighting splits the segment: its ends face opposite ways and are faded out each on its own.
vec3 hovr_orient(float f, float b)
{
  if (hovr_twoSided != 0 && f < 0.0 && b < 0.0)
  {
    return vec3(-f, -b, 0.0);
  }
  if (hovr_twoSided != 0 && (f < 0.0) != (b < 0.0))
  {
    return vec3(abs(f), abs(b), 1.0);
  }
  return vec3(f, b, 0.0);
}

// The normalised average of two normals (zero if they cancel).
vec3 hovr_average(vec3 a, vec3 b)
{
  vec3 s = a + b;
  float len = length(s);
  return len > 1e-30 ? s / len : vec3(0.0);
}

// m = 4 (1 - cos a) / cos a (= -r of Eq. 8), cos a by the half-angle identity and clamped; 0
// when either normal is zero (no arc). Branch-free: every lane of a SIMD group runs it alike.
float hovr_arc(vec3 a, vec3 b)
{
  float defined = step(0.5, min(dot(a, a), dot(b, b)));
  float ca = sqrt(0.5 * (1.0 + clamp(dot(a, b), -1.0, 1.0)));
  ca = max(ca, hovr_minimumCosHalfAngle);
  return defined * 4.0 * (1.0 - ca) / ca;
}

// The paper's cone (line 182).
float hovr_cone(float x)
{
  return 1.0 + hovr_lighting.w * (x - 1.0);
}

#if HOVR_INTERPOLATION == 2 && !HOVR_GOOCH
// The largest interior critical value of p(u) = fh (1-u) + bh u + m (fh u (1-u)^2 + bh u^2
// (1-u)) = q(u) (1 + m u (1-u)), q(u) = fh (1-u) + bh u, for u in (0, 1): the highlight
// between two samples (line 211). Branch-free, as SIMD rasterisers run every branch anyway.
bool hovr_interiorMaximum(float fh, float bh, float m, out float value)
{
  float a1 = bh - fh + m * fh;
  float a2 = m * (bh - 2.0 * fh);
  float a3 = m * (fh - bh);
  // The roots of p' = a1 + 2 a2 u + 3 a3 u^2, the one without cancellation first and the
  // other from their product; a3 = 0 leaves the linear root a1 / q alone.
  float disc = a2 * a2 - 3.0 * a1 * a3;
  float q = -(a2 + (a2 < 0.0 ? -1.0 : 1.0) * sqrt(max(disc, 0.0)));
  float r0 = a3 != 0.0 ? q / (3.0 * a3) : -1.0;
  float r1 = q != 0.0 ? a1 / q : -1.0;
  bool in0 = disc >= 0.0 && r0 > 0.0 && r0 < 1.0;
  bool in1 = disc >= 0.0 && r1 > 0.0 && r1 < 1.0;
  float p0 = (fh + (bh - fh) * r0) * (1.0 + m * r0 * (1.0 - r0));
  float p1 = (fh + (bh - fh) * r1) * (1.0 + m * r1 * (1.0 - r1));
  value = in0 && in1 ? max(p0, p1) : (in0 ? p0 : p1);
  return in0 || in1;
}
#endif

#if !HOVR_GOOCH
// Light k's diffuse and specular part of a segment's colour (hovr_shade): each light is a
// call of its own rather than an iteration, as llvmpipe caps the loop iterations of a
// fragment in all, and the ray's loop shades every segment.
vec3 hovr_light(int k, vec4 J0, vec4 J1, vec4 J2, vec4 J3, vec4 I0, vec3 nFront, vec3 nBack,
  vec3 nc, float m, float n, float tent)
{
  vec3 l = hovr_lightIsHead[k] != 0 ? hovr_view : hovr_lightDirection[k];
  vec3 h = hovr_average(l, hovr_view);
  vec3 diffuse;
#if HOVR_INTERPOLATION == 0
  diffuse = max(hovr_side(dot(nc, l)), 0.0) * I0.rgb;
#else
  vec3 e = hovr_orient(dot(nFront, l), dot(nBack, l));
  float f = e.x, b = e.y;
  // The paper's three cases (lines 162-173): each end faded, a negative end contributing
  // nothing; the arc term when both ends face the light (and the segment is not split).
  diffuse = max(f, 0.0) * J0.rgb + max(b, 0.0) * J1.rgb;
#if HOVR_INTERPOLATION == 2
  diffuse += (e.z == 0.0 && f >= 0.0 && b >= 0.0) ? m * (f * J2.rgb + b * J3.rgb) : vec3(0.0);
#endif
#endif
  float specular = 0.0;
  if (hovr_lighting.z != 0.0)
  {
#if HOVR_INTERPOLATION == 0
    specular = max(hovr_cone(hovr_side(dot(nc, h))), 0.0) * I0.a;
#else
    vec3 eh = hovr_orient(dot(nFront, h), dot(nBack, h));
    float fh = eh.x, bh = eh.y;
    float threshold = (n - 1.0) / n; // the cone is positive above it (line 207)
    bool upFront = fh > threshold, upBack = bh > threshold;
    // Each end's cone value faded (linear, split segments, and the paper's second case: its
    // value, not its argument, line 210); the arc term when both ends are in the cone.
    specular = (upFront ? hovr_cone(fh) * J0.a : 0.0) + (upBack ? hovr_cone(bh) * J1.a : 0.0);
#if HOVR_INTERPOLATION == 2
    if (eh.z == 0.0)
    {
      specular += upFront && upBack ? n * m * (fh * J2.a + bh * J3.a) : 0.0;
      // Neither end in the cone: a highlight between the samples (lines 211-215). The
      // profile stays below max(fh, bh) (1 + m / 4): no peak reaches the cone then.
      float peak;
      if (!upFront && !upBack && max(fh, bh) * (1.0 + 0.25 * m) > threshold &&
        hovr_interiorMaximum(fh, bh, m, peak) && hovr_cone(peak) > 0.0)
      {
        specular = hovr_cone(peak) * tent;
      }
    }
#endif
#endif
  }
  return hovr_lighting.y * hovr_lightDiffuse[k] * diffuse +
    hovr_lighting.z * hovr_lightSpecular[k] * specular;
}
#endif

// The shaded segment (premultiplied RGB, opacity) whose moments are the layers base ..
// base + HOVR_LAYERS - 1 at table coordinate coord, with unit (or zero) normals nFront and
// nBack at its ends.
vec4 hovr_shade(int base, hovr_tableCoord_t coord, vec3 nFront, vec3 nBack)
{
  vec4 J0 = hovr_layer(base, coord);
  vec4 J1 = hovr_layer(base + 1, coord);
#if HOVR_LAYERS > 2
  vec4 J2 = hovr_layer(base + 2, coord);
  vec4 J3 = hovr_layer(base + 3, coord);
#else
  vec4 J2 = vec4(0.0);
  vec4 J3 = vec4(0.0);
#endif
#if HOVR_INTERPOLATION == 2 && !HOVR_GOOCH
  // The tent integral I'' of the highlight search (line 213) from the moments at hand: 3 u
  // (1 - u), the weight of 3 (J_2 + J_3), has the tent min(2u, 2 - 2u)'s integral against any
  // weight linear in u (both are symmetric about u = 1/2 with integral 1/2).
  float tent = 3.0 * (J2.a + J3.a);
#endif
  vec4 I0 = J0 + J1; // the unshaded segment: colour and opacity
  vec3 rgb;
#if HOVR_GOOCH
  vec3 l = hovr_numberOfLights > 0
    ? (hovr_lightIsHead[0] != 0 ? hovr_view : hovr_lightDirection[0])
    : vec3(0.0);
#if HOVR_INTERPOLATION == 0
  vec3 nc = hovr_average(nFront, nBack);
  vec4 p = dot(nc, l) * I0;
#else
#if HOVR_INTERPOLATION == 2
  float m = hovr_arc(nFront, nBack);
#else
  float m = 0.0;
#endif
  float f = dot(nFront, l), b = dot(nBack, l);
  vec4 p = f * J0 + b * J1 + m * (f * J2 + b * J3);
#endif
  float a = hovr_goochWeights.x, bw = hovr_goochWeights.y, kd = hovr_lighting.y;
  rgb = 0.5 * (hovr_goochCool + hovr_goochWarm) * I0.a + 0.5 * kd * (a + bw) * I0.rgb +
    0.5 * (hovr_goochCool - hovr_goochWarm) * p.a + 0.5 * kd * (a - bw) * p.rgb;
#else
  rgb = hovr_lighting.x * I0.rgb;
  float n = hovr_lighting.w;
#if HOVR_INTERPOLATION == 2
  float m = hovr_arc(nFront, nBack);
#else
  float m = 0.0;
#endif
  vec3 nc = hovr_average(nFront, nBack);
  float lightTent = 0.0;
#if HOVR_INTERPOLATION == 2
  lightTent = tent;
#endif
  // The lights one by one, not in a loop (see hovr_light).
#define HOVR_LIGHT(k)                                                                            \
  if (k < hovr_numberOfLights)                                                                   \
  {                                                                                              \
    rgb += hovr_light(k, J0, J1, J2, J3, I0, nFront, nBack, nc, m, n, lightTent);                \
  }
  HOVR_LIGHT(0)
  HOVR_LIGHT(1)
  HOVR_LIGHT(2)
  HOVR_LIGHT(3)
  HOVR_LIGHT(4)
  HOVR_LIGHT(5)
  HOVR_LIGHT(6)
  HOVR_LIGHT(7)
#undef HOVR_LIGHT
#endif
  return vec4(rgb, I0.a);
}

#ifndef HOVR_SLABS
// The shaded first-order segment between scalars sFront and sBack (centre-axis coordinates).
vec4 hovr_segment(float sFront, float sBack, vec3 nFront, vec3 nBack)
{
  return hovr_shade(
    0, vec2(0.5 * (sFront + sBack), 0.5 + (sBack - sFront) * hovr_chordScale), nFront, nBack);
}
#endif
