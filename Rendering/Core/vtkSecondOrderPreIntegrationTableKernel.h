// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
/**
 * @class   vtkSecondOrderPreIntegrationTableKernel
 * @brief   the integration of one entry of vtkSecondOrderPreIntegrationTable, in float
 *
 * What the CPU builder runs for every entry, what the GPU builder's fragment shader
 * (hovrPreIntegration2Build.glsl) repeats operation for operation, and what a size estimate
 * evaluates for single entries without building a table. Units are iteration-table samples:
 * the path of entry (centre i, chord j, deviation k) is
 *   x(t) = x0 + t (b + a t), x0 = p i - chord / 2, b = chord + 4 dev, a = -4 dev,
 * chord = (2 j - (ChordSize - 1)) ChordHalfStep, dev = (2 k - (DeviationSize - 1))
 * DeviationHalfStep (Eq. 2 in the table's axes; the chord grid is symmetric, so entry
 * ChordSize - 1 - j is entry j's path reversed). The path takes one midpoint step per sample
 * it sweeps (max(|b|, |2a + b|), at least 1, at most MaximumSteps), clamped to the samples;
 * each step reads (c tau, tau) with linear interpolation and composites (c alpha, alpha),
 * alpha = 1 - exp(-tau h) (by its series below 0.01, where 1 - exp loses digits in float),
 * h = Length / steps. A path inside one zero-opacity run of the iteration table is zero.
 */
#ifndef vtkSecondOrderPreIntegrationTableKernel_h
#define vtkSecondOrderPreIntegrationTableKernel_h

#include <algorithm>
#include <cmath>
#include <vector>

struct vtkSecondOrderPreIntegrationTableKernel
{
  int SamplesPerSpacing = 2; // iteration-table samples per centre spacing
  int Samples = 2;           // iteration-table samples
  int ChordSize = 1;
  int DeviationSize = 1;
  float ChordHalfStep = 0.0f;     // half the chord spacing, in samples
  float DeviationHalfStep = 0.0f; // half the deviation spacing, in samples
  int MaximumSteps = 4096;
  float Length = 1.0f; // slab length, world units

  void Path(int i, int j, int k, float& x0, float& b, float& a) const
  {
    const float chord = static_cast<float>(2 * j - (this->ChordSize - 1)) * this->ChordHalfStep;
    const float deviation =
      static_cast<float>(2 * k - (this->DeviationSize - 1)) * this->DeviationHalfStep;
    x0 = static_cast<float>(this->SamplesPerSpacing * i) - 0.5f * chord;
    b = chord + 4.0f * deviation;
    a = -4.0f * deviation;
  }

  int Steps(float b, float a) const
  {
    const float sweep = std::max(std::abs(b), std::abs(2.0f * a + b));
    return static_cast<int>(
      std::min(std::max(std::ceil(sweep), 1.0f), static_cast<float>(this->MaximumSteps)));
  }

  // The extremum of the path x(t) = x0 + t (b + a t) for t in [0, 1] (Eq. 2): true and its
  // value when the vertex lies inside. hovrSlabExtremum.glsl mirrors it for both shaders.
  static bool SlabExtremum(float x0, float b, float a, float& extremum)
  {
    extremum = x0;
    if (a == 0.0f)
    {
      return false;
    }
    const float vertex = -b / (2.0f * a);
    if (!(vertex > 0.0f && vertex < 1.0f))
    {
      return false;
    }
    extremum = x0 + vertex * (b + a * vertex);
    return true;
  }

  // Whether the path stays inside one zero-opacity run: its range over t in [0, 1] is spanned
  // by its ends and, when inside, its extremum.
  bool IsEmpty(float x0, float b, float a, const float* runs) const
  {
    const float top = static_cast<float>(this->Samples - 1);
    const float x1 = x0 + b + a;
    float lo = std::min(x0, x1), hi = std::max(x0, x1);
    float extremum;
    if (SlabExtremum(x0, b, a, extremum))
    {
      lo = std::min(lo, extremum);
      hi = std::max(hi, extremum);
    }
    lo = std::min(std::max(lo, 0.0f), top);
    hi = std::min(std::max(hi, 0.0f), top);
    const int qlo = std::min(static_cast<int>(lo), this->Samples - 2);
    const int qhi = std::min(static_cast<int>(hi), this->Samples - 2);
    return runs[qlo] >= 0.0f && runs[qlo] == runs[qhi];
  }

  // The iteration-table samples [first, last] that entry (i, j, k) reads: its path's range
  // (ends and extremum, clamped), and the next sample up for the interpolation.
  void SampleRange(int i, int j, int k, int& first, int& last) const
  {
    float x0, b, a;
    this->Path(i, j, k, x0, b, a);
    const float top = static_cast<float>(this->Samples - 1);
    const float x1 = x0 + b + a;
    float lo = std::min(x0, x1), hi = std::max(x0, x1), extremum;
    if (SlabExtremum(x0, b, a, extremum))
    {
      lo = std::min(lo, extremum);
      hi = std::max(hi, extremum);
    }
    lo = std::min(std::max(lo, 0.0f), top);
    hi = std::min(std::max(hi, 0.0f), top);
    first = std::min(static_cast<int>(lo), this->Samples - 2);
    last = std::min(static_cast<int>(hi) + 1, this->Samples - 1);
  }

  // Whether entry (i, j, k) reads any of the iteration-table samples [first, last].
  bool Reads(int i, int j, int k, int first, int last) const
  {
    int low, high;
    this->SampleRange(i, j, k, low, high);
    return high >= first && low <= last;
  }
  // The samples (4 floats each) where two iteration tables of n samples differ, [first,
  // last] (last < first when none).
  static void ChangedSamples(const float* before, const float* after, int n, int& first, int& last)
  {
    first = n;
    last = -1;
    for (int q = 0; q < n; ++q)
    {
      if (!std::equal(before + 4 * q, before + 4 * q + 4, after + 4 * q))
      {
        first = std::min(first, q);
        last = q;
      }
    }
  }
  // Whether two kernels integrate every entry alike (the same axes, steps and length).
  bool SameAs(const vtkSecondOrderPreIntegrationTableKernel& other) const
  {
    return this->SamplesPerSpacing == other.SamplesPerSpacing && this->Samples == other.Samples &&
      this->ChordSize == other.ChordSize && this->DeviationSize == other.DeviationSize &&
      this->ChordHalfStep == other.ChordHalfStep &&
      this->DeviationHalfStep == other.DeviationHalfStep &&
      this->MaximumSteps == other.MaximumSteps && this->Length == other.Length;
  }

  // The steps of entry (i, j, k)'s path into steps: per step (c alpha, alpha), alpha =
  // 1 - exp(-tau h). Returns their number (at least minimumSteps, even if asked), 0 for a
  // path inside one zero-opacity run.
  int Sample(int i,
    int j,
    int k,
    const float* samples,
    const float* runs,
    std::vector<float>& steps,
    int minimumSteps = 1,
    bool even = false) const
  {
    float x0, b, a;
    this->Path(i, j, k, x0, b, a);
    if (this->IsEmpty(x0, b, a, runs))
    {
      return 0;
    }
    int n = std::max(this->Steps(b, a), minimumSteps);
    n += even ? n % 2 : 0; // halves of a slab end on a step boundary
    const float h = this->Length / static_cast<float>(n);
    const float width = 1.0f / static_cast<float>(n);
    const float top = static_cast<float>(this->Samples - 1);
    steps.resize(4 * static_cast<size_t>(n));
    for (int m = 0; m < n; ++m)
    {
      const float t = (static_cast<float>(m) + 0.5f) * width;
      const float x = std::min(std::max(x0 + t * (b + a * t), 0.0f), top);
      const int q = std::min(static_cast<int>(x), this->Samples - 2);
      const float w = x - static_cast<float>(q);
      const float* v0 = samples + 4 * q;
      float v[4];
      for (int c = 0; c < 4; ++c)
      {
        v[c] = v0[c] + w * (v0[c + 4] - v0[c]);
      }
      const float depth = v[3] * h;
      const float alpha = depth < 0.01f ? depth * (1.0f - depth * (0.5f - depth * (1.0f / 6.0f)))
                                        : 1.0f - std::exp(-depth);
      // Colour weight alpha / tau: the step's length where tau vanishes.
      const float weight = v[3] > 0.0f ? alpha / v[3] : h;
      float* step = steps.data() + 4 * m;
      for (int c = 0; c < 3; ++c)
      {
        step[c] = v[c] * weight;
      }
      step[3] = alpha;
    }
    return n;
  }

  // Entry (i, j, k) into forward and, when backward is given, its reversed path into
  // backward. steps is scratch memory.
  void Integrate(int i,
    int j,
    int k,
    const float* samples,
    const float* runs,
    std::vector<float>& steps,
    float* forward,
    float* backward) const
  {
    const int n = this->Sample(i, j, k, samples, runs, steps);
    // Front to back: RGBA += T (c a, a), T *= 1 - a. Alpha is accumulated like the colour,
    // not taken as 1 - T, which in float would lose the opacity of very thin steps.
    Composite(steps.data(), n, false, forward);
    if (backward)
    {
      Composite(steps.data(), n, true, backward);
    }
  }

  // The moments of a first-order entry (deviation 0) for shaded pre-integration: layer l of
  // `layers` (stride floats apart) gets the integral of the step weights T (c alpha, alpha)
  // times the position weight of the J basis, u the position along the segment: (1 - u),
  // u, u (1 - u)^2, u^2 (1 - u) (J_0..J_3 of Guetat et al.'s Eq. 8 rewritten without
  // cancellation). backward, when given, gets the reversed path's. The position
  // weights are averaged exactly over each step, and a path takes at least MomentSteps steps
  // (the transmittance inside the segment skews the moments even where the scalar is
  // constant).
  //
  // With halves (a second-order slab, any deviation k), the slab's front half [0, 1/2] and
  // back half [1/2, 1] each get the `layers` moments of their own position u' = 2u and
  // 2u - 1 (front half in layers 0..layers-1, back half in layers..2 layers-1), attenuated
  // by the transmittance from the slab's front: each half is shaded as a first-order segment
  // between its end normals (front, middle) and (middle, back), and the two sum to the slab.
  // A slab takes at least 2 MomentSteps steps, an even number of them.
  static constexpr int MomentSteps = 16;
  void IntegrateMoments(int i,
    int j,
    int k,
    bool halves,
    const float* samples,
    const float* runs,
    std::vector<float>& steps,
    int layers,
    size_t stride,
    float* forward,
    float* backward) const
  {
    const int n =
      this->Sample(i, j, k, samples, runs, steps, (halves ? 2 : 1) * MomentSteps, halves);
    CompositeMoments(steps.data(), n, false, layers, stride, forward, halves);
    if (backward)
    {
      CompositeMoments(steps.data(), n, true, layers, stride, backward, halves);
    }
  }

  static void CompositeMoments(const float* steps,
    int n,
    bool reversed,
    int layers,
    size_t stride,
    float* out,
    bool halves = false)
  {
    float sum[2][4][4] = {};
    float transmittance = 1.0f;
    const int parts = halves ? 2 : 1;
    // Step width in the position of the segment or half (no steps: nothing to weigh).
    const float w = n > 0 ? static_cast<float>(parts) / static_cast<float>(n) : 0.0f;
    for (int m = 0; m < n; ++m)
    {
      const float* step = steps + 4 * (reversed ? n - 1 - m : m);
      const int part = halves && 2 * m >= n ? 1 : 0;
      // Averages over the step [u - w/2, u + w/2]: <u^2> = u^2 + w^2/12, <u^3> = u^3 + u w^2/4.
      const float u = (static_cast<float>(m - part * (n / 2)) + 0.5f) * w;
      const float u2 = u * u + w * w / 12.0f, u3 = u * (u * u + w * w / 4.0f);
      const float v = 1.0f - u;
      const float weights[4] = { v, u, u - 2.0f * u2 + u3, u2 - u3 };
      for (int l = 0; l < layers; ++l)
      {
        const float weight = transmittance * weights[l];
        for (int c = 0; c < 4; ++c)
        {
          sum[part][l][c] += weight * step[c];
        }
      }
      transmittance *= 1.0f - step[3];
    }
    for (int p = 0; p < parts; ++p)
    {
      for (int l = 0; l < layers; ++l)
      {
        std::copy(sum[p][l], sum[p][l] + 4, out + (p * layers + l) * stride);
      }
    }
  }

  static void Composite(const float* steps, int n, bool reversed, float* rgba)
  {
    if (n == 0)
    {
      std::fill(rgba, rgba + 4, 0.0f);
      return;
    }
    float sum[4] = { 0.0f, 0.0f, 0.0f, 0.0f };
    float transmittance = 1.0f;
    for (int m = 0; m < n; ++m)
    {
      const float* step = steps + 4 * (reversed ? n - 1 - m : m);
      for (int c = 0; c < 4; ++c)
      {
        sum[c] += transmittance * step[c];
      }
      transmittance *= 1.0f - step[3];
    }
    std::copy(sum, sum + 3, rgba);
    rgba[3] = std::min(sum[3], 1.0f); // 1 at most, up to rounding
  }
};

#endif
