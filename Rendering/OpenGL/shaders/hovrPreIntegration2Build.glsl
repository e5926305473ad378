//VTK::System::Dec
// hovr: the second-order pre-integration table built on the GPU (El Hajjar, Marchesin,
// Dischler and Mongenet 2008, section 6.2), drawn by vtkOpenGLPreIntegrationTableBuilder.
//
// One full-screen pass per z slice of the table: the slice is the deviation k (uniform),
// fragment (i, j) of the viewport is the entry with chord centre i and chord j. Every step
// mirrors vtkSecondOrderPreIntegrationTableKernel (the CPU builder's), in the same float
// operations and order:
//   - the path of Eq. 2 in the table's axes, in iteration-table samples:
//     x(t) = x0 + t (b + a t), x0 = p i - chord / 2, b = chord + 4 dev, a = -4 dev;
//   - a path inside one zero-opacity run of the iteration table is zero;
//   - otherwise one midpoint step per sample swept (at least 1, at most hovr_maximumSteps),
//     each step's (c tau, tau) interpolated linearly between two texels of the iteration
//     table, alpha = 1 - exp(-tau h) (its series below 0.01), composited front to back.
// The CPU integrates chord j and its mirror ChordSize - 1 - j from one evaluation of the
// path of the smaller one, the mirror compositing the same steps backwards; the shader does
// the same so that both round alike.

in vec2 texCoord; // (i + 1/2, j + 1/2) / (centre entries, chord entries) at entry (i, j)
//VTK::Output::Dec

// The iteration table, RGBA = (c tau, tau), texel q at (q & mask, q >> rowShift).
uniform sampler2D hovr_steps;
// Zero-opacity run of each iteration-table spacing (-1: some opacity), same layout.
uniform sampler2D hovr_stepRuns;
uniform int hovr_rowShift;
uniform int hovr_centreSize;
uniform int hovr_samplesPerSpacing; // iteration-table samples per centre spacing
uniform int hovr_samples;           // iteration-table samples
uniform int hovr_chordSize;
uniform int hovr_deviationSize;
uniform float hovr_chordHalfStep;     // half a chord spacing, in samples
uniform float hovr_deviationHalfStep; // half a deviation spacing, in samples
uniform int hovr_maximumSteps;
uniform float hovr_length; // slab length, world units
uniform int hovr_deviation; // k, the slice being drawn

//HOVR::SlabExtremum

ivec2 hovr_texel(int q)
{
  return ivec2(q & ((1 << hovr_rowShift) - 1), q >> hovr_rowShift);
}

// Whether the path stays inside one zero-opacity run: its range over t in [0, 1] is spanned
// by its ends and, when inside, its extremum.
bool hovr_isEmpty(float x0, float b, float a)
{
  float top = float(hovr_samples - 1);
  float x1 = x0 + b + a;
  float lo = min(x0, x1);
  float hi = max(x0, x1);
  float extremum;
  if (hovr_slabExtremum(x0, b, a, extremum))
  {
    lo = min(lo, extremum);
    hi = max(hi, extremum);
  }
  lo = min(max(lo, 0.0), top);
  hi = min(max(hi, 0.0), top);
  int qlo = min(int(lo), hovr_samples - 2);
  int qhi = min(int(hi), hovr_samples - 2);
  float runLo = texelFetch(hovr_stepRuns, hovr_texel(qlo), 0).r;
  float runHi = texelFetch(hovr_stepRuns, hovr_texel(qhi), 0).r;
  return runLo >= 0.0 && runLo == runHi;
}

void main()
{
  int i = min(int(texCoord.x * float(hovr_centreSize)), hovr_centreSize - 1);
  int j = min(int(texCoord.y * float(hovr_chordSize)), hovr_chordSize - 1);
  int mirror = hovr_chordSize - 1 - j;
  bool reversed = j > mirror;
  int chordIndex = reversed ? mirror : j;
  float chord = float(2 * chordIndex - (hovr_chordSize - 1)) * hovr_chordHalfStep;
  float deviation = float(2 * hovr_deviation - (hovr_deviationSize - 1)) * hovr_deviationHalfStep;
  float x0 = float(hovr_samplesPerSpacing * i) - 0.5 * chord;
  float b = chord + 4.0 * deviation;
  float a = -4.0 * deviation;
  if (hovr_isEmpty(x0, b, a))
  {
    gl_FragData[0] = vec4(0.0); // inside one zero-opacity run
    return;
  }
  float sweep = max(abs(b), abs(2.0 * a + b));
  int n = int(min(max(ceil(sweep), 1.0), float(hovr_maximumSteps)));
  float h = hovr_length / float(n);
  float width = 1.0 / float(n);
  float top = float(hovr_samples - 1);

  // Front to back: RGBA += T (c alpha, alpha), T *= 1 - alpha. Alpha is accumulated like the
  // colour, not taken as 1 - T, which in float would lose the opacity of very thin steps.
  vec4 slab = vec4(0.0);
  float transmittance = 1.0;
  for (int m = 0; m < n; ++m)
  {
    int s = reversed ? n - 1 - m : m;
    float t = (float(s) + 0.5) * width;
    float x = min(max(x0 + t * (b + a * t), 0.0), top);
    int q = min(int(x), hovr_samples - 2);
    float w = x - float(q);
    vec4 v0 = texelFetch(hovr_steps, hovr_texel(q), 0);
    vec4 v1 = texelFetch(hovr_steps, hovr_texel(q + 1), 0);
    vec4 v = v0 + w * (v1 - v0);
    float depth = v.a * h;
    float alpha = depth < 0.01 ? depth * (1.0 - depth * (0.5 - depth * (1.0 / 6.0)))
                               : 1.0 - exp(-depth);
    // Colour weight alpha / tau: the step's length where tau vanishes.
    float weight = v.a > 0.0 ? alpha / v.a : h;
    vec4 step = vec4(v.rgb * weight, alpha);
    slab += transmittance * step;
    transmittance *= 1.0 - alpha;
  }
  gl_FragData[0] = vec4(slab.rgb, min(slab.a, 1.0)); // 1 at most, up to rounding
}
