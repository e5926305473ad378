//VTK::System::Dec
// hovr: the second-order pre-integration table built on the GPU (El Hajjar, Marchesin,
// Dischler and Mongenet 2008, section 6.2), drawn by vtkOpenGLPreIntegrationTableBuilder.
//
// One full-screen pass per z slice of the N^3 table: the slice is the back scalar k (uniform),
// fragment (i, j) of the N x N viewport is the entry with front i and middle j. Every step
// mirrors vtkSecondOrderPreIntegrationTable::BuildTable (the CPU builder), in the same float
// operations and order, so that both tables agree to float rounding:
//   - the diagonal i = j = k (constant scalar) is the exact exponential, computed on the CPU;
//   - a slab whose scalar stays in one zero-opacity run of the iteration table is zero;
//   - otherwise Iterations midpoint steps along P(t) = A t^2 + B t + C (Eq. 2, by Horner's
//     rule, in iteration-table units), each step's (c a, a) interpolated linearly between
//     two texels of the iteration table, composited front to back.
// The CPU integrates the pair (i, j, k), (k, j, i) with i <= k from one evaluation of the
// path of (i, j, k), the reversed entry compositing the same steps backwards (entry (k, j, k),
// where the two coincide, keeps the backward result): the shader does the same so that both
// round alike.

in vec2 texCoord; // (i + 1/2, j + 1/2) / N at the fragment of entry (i, j)
//VTK::Output::Dec

// The iteration table, RGBA = (c a, a) of one step, texel q at (q & mask, q >> rowShift).
uniform sampler2D hovr_steps;
// Zero-opacity run of each iteration-table spacing (-1: some opacity), same layout.
uniform sampler2D hovr_stepRuns;
// Entry (i, i, i) of the table at texel (i, 0).
uniform sampler2D hovr_diagonal;
uniform int hovr_rowShift;
uniform int hovr_tableSize;         // N
uniform int hovr_samplesPerSpacing; // iteration-table samples per table spacing
uniform int hovr_fine;              // iteration-table samples
uniform int hovr_iterations;
uniform float hovr_stepWidth; // 1 / iterations, rounded to float as on the CPU
uniform int hovr_back;        // k, the slice being drawn

ivec2 hovr_texel(int q)
{
  return ivec2(q & ((1 << hovr_rowShift) - 1), q >> hovr_rowShift);
}

// ceil(x / d) for d > 0.
uint hovr_ceilDiv(uint x, uint d)
{
  return (x + d - 1u) / d;
}

// First and last iteration-table spacing that the scalar of slab (front i, middle j, back k)
// enters: its range over t in [0, 1] is spanned by the ends and, when t = -B / 2A lies
// inside, the extremum C - B^2 / 4A (Eq. 2). Exact integer arithmetic: the CPU rounds in
// double, which can only differ where the range ends exactly on a spacing boundary, and a
// boundary that is only touched is not entered (the slab adds nothing there: the iteration
// table is zero at both nodes of an empty spacing). So every slab the CPU finds empty is
// empty here too. The product p b^2 <= 16 (Fine - 1)(N - 1) stays below 2^32 for N <= 4096
// (the CPU keeps Fine - 1 <= 65536).
ivec2 hovr_enteredSpacings(int i, int j, int k)
{
  int p = hovr_samplesPerSpacing;
  int a = 2 * i - 4 * j + 2 * k; // A and B in table entries; i <= k
  int b = -3 * i + 4 * j - k;
  int first = p * i;
  int last = p * k - 1;
  if (a > 0 && b < 0 && -b < 2 * a)
  {
    // A minimum inside: floor(p i - p b^2 / 4a).
    first = p * i - int(hovr_ceilDiv(uint(p) * uint(b * b), uint(4 * a)));
  }
  else if (a < 0 && b > 0 && b < -2 * a)
  {
    // A maximum inside: the spacing that ends at or above p i + p b^2 / 4|a|.
    last = p * i + int(hovr_ceilDiv(uint(p) * uint(b * b), uint(-4 * a))) - 1;
  }
  return clamp(ivec2(first, last), 0, hovr_fine - 2);
}

void main()
{
  int n = hovr_tableSize;
  ivec2 entry = min(ivec2(texCoord * float(n)), ivec2(n - 1));
  int front = entry.x;
  int middle = entry.y;
  int back = hovr_back;
  if (front == middle && middle == back)
  {
    gl_FragData[0] = texelFetch(hovr_diagonal, ivec2(front, 0), 0);
    return;
  }

  // The CPU's pair: the path of (i, middle, k) with i <= k, walked backwards for i = back.
  int i = min(front, back);
  int k = max(front, back);
  bool reversed = front >= back;

  ivec2 spacings = hovr_enteredSpacings(i, middle, k);
  float runFirst = texelFetch(hovr_stepRuns, hovr_texel(spacings.x), 0).r;
  float runLast = texelFetch(hovr_stepRuns, hovr_texel(spacings.y), 0).r;
  if (runFirst >= 0.0 && runFirst == runLast)
  {
    gl_FragData[0] = vec4(0.0); // inside one zero-opacity run
    return;
  }

  // Eq. 2 in iteration-table units (integers, exact in float).
  float p = float(hovr_samplesPerSpacing);
  float xf = p * float(i);
  float xm = p * float(middle);
  float xb = p * float(k);
  float a = 2.0 * xf - 4.0 * xm + 2.0 * xb;
  float b = -3.0 * xf + 4.0 * xm - xb;
  float top = float(hovr_fine - 1);

  // Front to back: RGBA += T (c a, a), T *= 1 - a. Alpha is accumulated like the colour, not
  // taken as 1 - T, which in float would lose the opacity of very thin steps.
  vec4 slab = vec4(0.0);
  float transmittance = 1.0;
  for (int it = 0; it < hovr_iterations; ++it)
  {
    int s = reversed ? hovr_iterations - 1 - it : it;
    float t = (float(s) + 0.5) * hovr_stepWidth;
    float x = min(max(xf + t * (b + a * t), 0.0), top);
    int q = min(int(x), hovr_fine - 2);
    float w = x - float(q);
    vec4 v0 = texelFetch(hovr_steps, hovr_texel(q), 0);
    vec4 v1 = texelFetch(hovr_steps, hovr_texel(q + 1), 0);
    vec4 v = v0 + w * (v1 - v0);
    slab += transmittance * v;
    transmittance *= 1.0 - v.a;
  }
  gl_FragData[0] = vec4(slab.rgb, min(slab.a, 1.0)); // 1 at most, up to rounding
}
