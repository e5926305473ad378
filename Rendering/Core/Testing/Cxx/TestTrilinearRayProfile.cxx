// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
// vtkTrilinearRayProfile: the cubic along a ray equals direct trilinear interpolation, its
// derivative equals the gradient of the interpolant along the ray, and GetMaximumSlope bounds
// (tightly) the derivative over the segment. The analytic isosurface/MIP numerics: Eq. 4
// from four samples, critical points and range (Eq. 5-6), the first crossing, degenerate
// profiles.
#include "vtkMinimalStandardRandomSequence.h"
#include "vtkNew.h"
#include "vtkTrilinearRayProfile.h"

#include "hovrTestUtilities.h"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace
{
hovrTest::Checker check;

// Direct trilinear interpolation, corners indexed i + 2 j + 4 k.
double Trilinear(const double f[8], const double u[3])
{
  double value = 0.0;
  for (int c = 0; c < 8; ++c)
  {
    const double wx = (c & 1) ? u[0] : 1.0 - u[0];
    const double wy = (c & 2) ? u[1] : 1.0 - u[1];
    const double wz = (c & 4) ? u[2] : 1.0 - u[2];
    value += wx * wy * wz * f[c];
  }
  return value;
}

// Gradient of the trilinear interpolant at u.
void TrilinearGradient(const double f[8], const double u[3], double g[3])
{
  g[0] = g[1] = g[2] = 0.0;
  for (int c = 0; c < 8; ++c)
  {
    const double w[3] = {
      (c & 1) ? u[0] : 1.0 - u[0], (c & 2) ? u[1] : 1.0 - u[1], (c & 4) ? u[2] : 1.0 - u[2]
    };
    const double dw[3] = { (c & 1) ? 1.0 : -1.0, (c & 2) ? 1.0 : -1.0, (c & 4) ? 1.0 : -1.0 };
    g[0] += dw[0] * w[1] * w[2] * f[c];
    g[1] += w[0] * dw[1] * w[2] * f[c];
    g[2] += w[0] * w[1] * dw[2] * f[c];
  }
}
}

int TestTrilinearRayProfile(int, char*[])
{
  vtkNew<vtkMinimalStandardRandomSequence> random;
  random->SetSeed(42);
  auto next = [&]()
  {
    random->Next();
    return random->GetValue();
  };

  // Corner values in [-1, 1], points in the unit cube, |v| t <= sqrt(3): every quantity is
  // O(1) and the two evaluations differ only by rounding (~1e-15), so 1e-12 is loose yet
  // catches any wrong coefficient.
  const double tolerance = 1e-12;
  double worstValue = 0.0, worstDerivative = 0.0, worstBound = 0.0, worstTightness = 0.0;
  int interiorVertices = 0;
  for (int trial = 0; trial < 2000; ++trial)
  {
    double f[8], u0[3], u1[3], v[3];
    for (double& c : f)
    {
      c = 2.0 * next() - 1.0;
    }
    // The segment from u0 to u1, both in the cell, traversed in "length" units of t.
    const double length = 0.1 + 2.9 * next();
    for (int a = 0; a < 3; ++a)
    {
      u0[a] = next();
      u1[a] = next();
      if (trial % 11 == a)
      {
        u1[a] = u0[a]; // a direction with a zero component
      }
      v[a] = (u1[a] - u0[a]) / length;
    }
    vtkTrilinearRayProfile profile;
    profile.Set(f, u0, v);
    const int samples = 4000;
    double sampledMaximum = 0.0;
    for (int k = 0; k <= samples; ++k)
    {
      const double t = length * k / samples;
      const double u[3] = { u0[0] + t * v[0], u0[1] + t * v[1], u0[2] + t * v[2] };
      worstValue = std::max(worstValue, std::abs(profile.Evaluate(t) - Trilinear(f, u)));
      double g[3];
      TrilinearGradient(f, u, g);
      const double slope = g[0] * v[0] + g[1] * v[1] + g[2] * v[2];
      worstDerivative = std::max(worstDerivative, std::abs(profile.Derivative(t) - slope));
      sampledMaximum = std::max(sampledMaximum, std::abs(profile.Derivative(t)));
    }
    const double bound = profile.GetMaximumSlope(length);
    // The bound must hold at every sample...
    worstBound = std::max(worstBound, sampledMaximum - bound);
    // ...and be tight: ds/dt is a quadratic with curvature 6 c3, and the nearest sample is at
    // most delta = length / (2 samples) from its maximiser, so the sampled maximum is within
    // 3 |c3| delta^2 (at an interior vertex) of the true one.
    const double* c = profile.GetCoefficients();
    const double delta = length / (2.0 * samples);
    worstTightness =
      std::max(worstTightness, bound - sampledMaximum - 3.0 * std::abs(c[3]) * delta * delta);
    const double vertex = c[3] != 0.0 ? -c[2] / (3.0 * c[3]) : -1.0;
    interiorVertices += vertex > 0.0 && vertex < length ? 1 : 0;
  }
  check.Near(
    worstValue, 0.0, tolerance, "cubic equals trilinear interpolation (largest deviation)");
  check.Near(worstDerivative, 0.0, tolerance, "derivative equals gradient . v (largest deviation)");
  check(worstBound <= tolerance, "GetMaximumSlope bounds |ds/dt| at every sample");
  check(worstTightness <= tolerance, "GetMaximumSlope is the maximum, not just a bound");
  // The interior-vertex case is the interesting one: make sure the random segments exercise it.
  check(interiorVertices > 50,
    "random segments with the slope extremum inside (" + std::to_string(interiorVertices) + ")");

  // Closed forms: a linear field f = x gives s(t) = u0x + vx t; f = x y z gives
  // c3 = vx vy vz; a constant field gives zero slope.
  {
    const double fx[8] = { 0, 1, 0, 1, 0, 1, 0, 1 };
    const double u0[3] = { 0.25, 0.5, 0.75 }, v[3] = { 0.5, -0.25, 0.125 };
    vtkTrilinearRayProfile profile;
    profile.Set(fx, u0, v);
    const double* c = profile.GetCoefficients();
    check(c[0] == 0.25 && c[1] == 0.5 && c[2] == 0.0 && c[3] == 0.0, "f = x gives 0.25 + 0.5 t");
    check(profile.GetMaximumSlope(1.0) == 0.5, "f = x has slope 0.5");
    const double fxyz[8] = { 0, 0, 0, 0, 0, 0, 0, 1 };
    profile.Set(fxyz, u0, v);
    check(profile.GetCoefficients()[3] == 0.5 * -0.25 * 0.125, "f = xyz gives c3 = vx vy vz");
    const double constant[8] = { 3, 3, 3, 3, 3, 3, 3, 3 };
    profile.Set(constant, u0, v);
    check(profile.Evaluate(0.7) == 3.0 && profile.GetMaximumSlope(2.0) == 0.0,
      "constant field: value 3, slope 0");
    // s = x y along u(t) = (t, t, 0.5): s(t) = t^2, slope 2t, largest on [0, 1] is 2.
    const double fxy[8] = { 0, 0, 0, 1, 0, 0, 0, 1 };
    const double o[3] = { 0, 0, 0.5 }, d[3] = { 1, 1, 0 };
    profile.Set(fxy, o, d);
    check(profile.Evaluate(0.5) == 0.25 && profile.GetMaximumSlope(1.0) == 2.0,
      "f = xy along the diagonal: s = t^2, largest slope 2");
    // s = x y z along (t, t, t) from 0: s = t^3; on [0, 1] the largest slope 3 is at t = 1,
    // and from (1, 1, 1) backwards s = (1 - t)^3 with the largest slope 3 at t = 0.
    const double one[3] = { 1, 1, 1 }, back[3] = { -1, -1, -1 }, zero[3] = { 0, 0, 0 };
    profile.Set(fxyz, zero, one);
    check(std::abs(profile.GetMaximumSlope(1.0) - 3.0) < tolerance, "s = t^3: largest slope 3");
    profile.Set(fxyz, one, back);
    check(
      std::abs(profile.GetMaximumSlope(1.0) - 3.0) < tolerance, "s = (1 - t)^3: largest slope 3");
    // Along u(t) = (t, 1 - t, 1/2), f = x y gives s = t - t^2, slope 1 - 2t: the largest
    // |slope| on [0, 1] is 1, at both ends.
    const double o2[3] = { 0, 1, 0.5 }, d2[3] = { 1, -1, 0 };
    profile.Set(fxy, o2, d2);
    check(profile.Evaluate(0.5) == 0.25 && profile.GetMaximumSlope(1.0) == 1.0,
      "f = xy along the anti-diagonal: s = t - t^2, largest slope 1");
    // Along u(t) = (t, t, 1 - t), f = x y z gives s = t^2 - t^3, slope 2t - 3t^2: on
    // [0, 1/2] the ends give 0 and 1/4, the interior vertex t = 1/3 gives the maximum 1/3.
    const double o3[3] = { 0, 0, 1 }, d3[3] = { 1, 1, -1 };
    profile.Set(fxyz, o3, d3);
    check(std::abs(profile.GetMaximumSlope(0.5) - 1.0 / 3.0) < tolerance,
      "s = t^2 - t^3 on [0, 1/2]: largest slope 1/3 at the interior vertex");
  }

  // Eq. 4: four samples at t = 0, 1/3, 2/3, 1 give the corner-built cubic of a unit segment.
  // Critical points, range and first crossing against dense sampling of random profiles.
  {
    double worstCoefficient = 0.0, worstRoot = 0.0;
    int crossings = 0, earlyMisses = 0, rangeFailures = 0, criticalFailures = 0;
    for (int trial = 0; trial < 3000; ++trial)
    {
      double f[8], u0[3], v[3];
      for (double& c : f)
      {
        c = 2.0 * next() - 1.0;
      }
      for (int a = 0; a < 3; ++a)
      {
        u0[a] = next();
        v[a] = next() - u0[a]; // the segment ends at a random point of the cell
      }
      vtkTrilinearRayProfile corners, samples;
      corners.Set(f, u0, v);
      samples.SetFromSamples(corners.Evaluate(0.0),
        corners.Evaluate(1.0 / 3.0),
        corners.Evaluate(2.0 / 3.0),
        corners.Evaluate(1.0));
      for (int k = 0; k < 4; ++k)
      {
        worstCoefficient = std::max(
          worstCoefficient, std::abs(samples.GetCoefficients()[k] - corners.GetCoefficients()[k]));
      }
      // Critical points: zeros of the derivative inside (0, 1).
      double tc[2];
      const int n = corners.GetCriticalPoints(1.0, tc);
      for (int k = 0; k < n; ++k)
      {
        criticalFailures +=
          (tc[k] <= 0.0 || tc[k] >= 1.0 || std::abs(corners.Derivative(tc[k])) > 1e-12 ||
            (k == 1 && tc[1] < tc[0]))
          ? 1
          : 0;
      }
      // Range: contains every dense sample and is attained within the dense spacing.
      double smin, smax;
      corners.GetRange(1.0, smin, smax);
      const int dense = 2000;
      double dmin = corners.Evaluate(0.0), dmax = dmin;
      for (int k = 1; k <= dense; ++k)
      {
        const double value = corners.Evaluate(static_cast<double>(k) / dense);
        dmin = std::min(dmin, value);
        dmax = std::max(dmax, value);
      }
      rangeFailures +=
        (smin > dmin + 1e-15 || smax < dmax - 1e-15 || dmin - smin > 1e-5 || smax - dmax > 1e-5)
        ? 1
        : 0;
      // First crossing of a value inside the range: a root, and no sign change before it.
      const double value = smin + (smax - smin) * next();
      double t;
      if (!corners.FindFirstCrossing(value, 1.0, t))
      {
        ++earlyMisses; // the range brackets the value, so there must be a crossing
        continue;
      }
      ++crossings;
      worstRoot = std::max(worstRoot, std::abs(corners.Evaluate(t) - value));
      const double g0 = corners.Evaluate(0.0) - value;
      for (int k = 0; k < dense && g0 != 0.0; ++k)
      {
        const double tk = t * k / dense;
        if ((corners.Evaluate(tk) - value) * g0 < 0.0 && t - tk > 1e-9)
        {
          ++earlyMisses; // a sign change before the reported first crossing
          break;
        }
      }
      double unused;
      earlyMisses += corners.FindFirstCrossing(smax + 1e-9, 1.0, unused) ? 1 : 0;
      earlyMisses += corners.FindFirstCrossing(smin - 1e-9, 1.0, unused) ? 1 : 0;
    }
    check.Near(
      worstCoefficient, 0.0, 1e-12, "Eq. 4 coefficients from 4 samples equal the corners'");
    check(criticalFailures == 0, "critical points are zeros of ds/dt inside (0, 1), sorted");
    check(rangeFailures == 0, "GetRange is the dense range, up to the dense spacing");
    check(crossings > 2900 && earlyMisses == 0,
      "FindFirstCrossing finds the first crossing of every value in the range, none outside (" +
        std::to_string(earlyMisses) + " failures)");
    check.Near(worstRoot, 0.0, 1e-14, "crossings are roots to double precision");
  }

  // Degenerate profiles, set from samples (exact dyadic values).
  {
    vtkTrilinearRayProfile p;
    double t = -1.0, lo, hi;
    p.SetFromSamples(2, 2, 2, 2); // flat data
    check(p.FindFirstCrossing(2.0, 1.0, t) && t == 0.0, "flat profile at the value: hit at 0");
    check(!p.FindFirstCrossing(2.5, 1.0, t), "flat profile off the value: miss");
    p.GetRange(1.0, lo, hi);
    check(lo == 2.0 && hi == 2.0, "flat profile: range [2, 2]");
    double tc[2];
    check(p.GetCriticalPoints(1.0, tc) == 0, "flat profile: no critical point");
    p.SetFromSamples(0, 1, 2, 3); // linear: a = b = 0
    check(p.FindFirstCrossing(1.5, 3.0, t) && std::abs(t - 0.5) < 1e-15,
      "linear profile: root of the line");
    check(p.GetCriticalPoints(1.0, tc) == 0, "linear profile: no critical point");
    // s = (t - 1/2)^2: a = 0, a tangent touch at the value 0 is a hit at exactly 1/2.
    p.SetFromSamples(0.25, 1.0 / 36.0, 1.0 / 36.0, 0.25);
    check(p.GetCriticalPoints(1.0, tc) == 1 && std::abs(tc[0] - 0.5) < 1e-15,
      "parabola: one critical point at 1/2");
    check(p.FindFirstCrossing(0.0, 1.0, t) && std::abs(t - 0.5) < 1e-8,
      "tangent ray touching the value: hit at the touching point");
    check(!p.FindFirstCrossing(-1e-6, 1.0, t), "tangent ray passing just beside the value: miss");
    p.GetRange(1.0, lo, hi);
    check(std::abs(lo) < 1e-15 && hi == 0.25, "parabola: range [0, 1/4]");
    // s = 4 (t - 1/2)^3: double root of the derivative (zero-slope inflection).
    p.SetFromSamples(-0.5, -1.0 / 54.0, 1.0 / 54.0, 0.5);
    check(p.GetCriticalPoints(1.0, tc) == 1 && std::abs(tc[0] - 0.5) < 1e-7,
      "zero-slope inflection: one critical point");
    check(p.FindFirstCrossing(0.0, 1.0, t) && std::abs(t - 0.5) < 1e-5,
      "zero-slope inflection: crossing at 1/2");
    // Value equal to the end sample (a voxel value on an axis-aligned ray): hit at the end;
    // equal to both end samples of a bump: hit at the start.
    p.SetFromSamples(0, 1, 2, 3);
    check(p.FindFirstCrossing(3.0, 1.0, t) && t == 1.0, "value equal to the end sample: t = 1");
    p.SetFromSamples(1, 2, 2, 1);
    check(p.FindFirstCrossing(1.0, 1.0, t) && t == 0.0, "value equal to the start sample: t = 0");
    // A profile that rises above the value and comes back inside one cell: the first of two.
    p.SetFromSamples(0, 1, 1, 0); // s = 4.5 t (1 - t)
    check(p.FindFirstCrossing(1.0, 1.0, t) && std::abs(t - (0.5 - std::sqrt(1.0 / 36.0))) < 1e-12,
      "two crossings in a cell: the first");
    p.GetRange(1.0, lo, hi);
    check(std::abs(hi - 1.125) < 1e-15, "analytic maximum between samples: 9/8 at t = 1/2");
  }

  std::cout << "largest deviations: value " << worstValue << ", derivative " << worstDerivative
            << "; segments with an interior slope extremum: " << interiorVertices << "\n";
  return check.Result("TestTrilinearRayProfile");
}
