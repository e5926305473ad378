// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
// vtkTrilinearRayProfile: the cubic along a ray equals direct trilinear interpolation, its
// derivative equals the gradient of the interpolant along the ray, and GetMaximumSlope bounds
// (tightly) the derivative over the segment.
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

  std::cout << "largest deviations: value " << worstValue << ", derivative " << worstDerivative
            << "; segments with an interior slope extremum: " << interiorVertices << "\n";
  return check.Result("TestTrilinearRayProfile");
}
