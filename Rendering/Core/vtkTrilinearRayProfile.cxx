// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
#include "vtkTrilinearRayProfile.h"

#include <algorithm>
#include <cmath>

//------------------------------------------------------------------------------
void vtkTrilinearRayProfile::Set(const double f[8], const double u0[3], const double v[3])
{
  // f(x,y,z) = a + bx x + by y + bz z + bxy xy + byz yz + bxz xz + bxyz xyz
  const double a = f[0];
  const double bx = f[1] - f[0];
  const double by = f[2] - f[0];
  const double bz = f[4] - f[0];
  const double bxy = f[3] - f[1] - f[2] + f[0];
  const double bxz = f[5] - f[1] - f[4] + f[0];
  const double byz = f[6] - f[2] - f[4] + f[0];
  const double bxyz = f[7] - f[3] - f[5] - f[6] + f[1] + f[2] + f[4] - f[0];
  const double x = u0[0], y = u0[1], z = u0[2];
  const double X = v[0], Y = v[1], Z = v[2];
  this->C[0] =
    a + bx * x + by * y + bz * z + bxy * x * y + byz * y * z + bxz * x * z + bxyz * x * y * z;
  this->C[1] = bx * X + by * Y + bz * Z + bxy * (x * Y + y * X) + byz * (y * Z + z * Y) +
    bxz * (x * Z + z * X) + bxyz * (x * y * Z + x * z * Y + y * z * X);
  this->C[2] = bxy * X * Y + byz * Y * Z + bxz * X * Z + bxyz * (x * Y * Z + y * X * Z + z * X * Y);
  this->C[3] = bxyz * X * Y * Z;
}

//------------------------------------------------------------------------------
double vtkTrilinearRayProfile::GetMaximumSlope(double length) const
{
  double m = std::max(std::abs(this->Derivative(0.0)), std::abs(this->Derivative(length)));
  // The derivative is a quadratic; its extremum is at the vertex when that lies inside.
  if (this->C[3] != 0.0)
  {
    const double tv = -this->C[2] / (3.0 * this->C[3]);
    if (tv > 0.0 && tv < length)
    {
      m = std::max(m, std::abs(this->Derivative(tv)));
    }
  }
  return m;
}

//------------------------------------------------------------------------------
void vtkTrilinearRayProfile::SetFromSamples(double f1, double f2, double f3, double f4)
{
  // Eq. 4: the cubic through (0, f1), (1/3, f2), (2/3, f3), (1, f4).
  this->C[3] = -4.5 * f1 + 13.5 * f2 - 13.5 * f3 + 4.5 * f4;
  this->C[2] = 9.0 * f1 - 22.5 * f2 + 18.0 * f3 - 4.5 * f4;
  this->C[1] = -5.5 * f1 + 9.0 * f2 - 4.5 * f3 + f4;
  this->C[0] = f1;
}

//------------------------------------------------------------------------------
int vtkTrilinearRayProfile::GetCriticalPoints(double length, double t[2]) const
{
  // Eq. 5: 3 c3 t^2 + 2 c2 t + c1 = 0, written A t^2 + B t + C = 0.
  const double A = 3.0 * this->C[3], B = 2.0 * this->C[2], C = this->C[1];
  double roots[2];
  int n = 0;
  if (A == 0.0)
  {
    if (B != 0.0)
    {
      roots[n++] = -C / B;
    }
  }
  else
  {
    const double disc = B * B - 4.0 * A * C;
    if (disc == 0.0)
    {
      roots[n++] = -B / (2.0 * A);
    }
    else if (disc > 0.0)
    {
      // Eq. 6 in the form that avoids cancellation: q = -(B + sign(B) sqrt(disc)) / 2, the
      // roots are q / A and C / q (q = 0 only when B = 0 and C = 0, excluded by disc > 0).
      const double q = -0.5 * (B + std::copysign(std::sqrt(disc), B));
      roots[n++] = q / A;
      if (q != 0.0)
      {
        roots[n++] = C / q;
      }
    }
  }
  int inside = 0;
  for (int k = 0; k < n; ++k)
  {
    if (roots[k] > 0.0 && roots[k] < length)
    {
      t[inside++] = roots[k];
    }
  }
  if (inside == 2 && t[0] > t[1])
  {
    std::swap(t[0], t[1]);
  }
  return inside;
}

//------------------------------------------------------------------------------
void vtkTrilinearRayProfile::GetRange(double length, double& smin, double& smax) const
{
  smin = std::min(this->Evaluate(0.0), this->Evaluate(length));
  smax = std::max(this->Evaluate(0.0), this->Evaluate(length));
  double t[2];
  const int n = this->GetCriticalPoints(length, t);
  for (int k = 0; k < n; ++k)
  {
    const double s = this->Evaluate(t[k]);
    smin = std::min(smin, s);
    smax = std::max(smax, s);
  }
}

//------------------------------------------------------------------------------
bool vtkTrilinearRayProfile::FindFirstCrossing(double value, double length, double& t) const
{
  double cuts[4] = { 0.0, 0.0, 0.0, 0.0 };
  const int n = this->GetCriticalPoints(length, cuts + 1);
  cuts[n + 1] = length;
  for (int k = 0; k <= n; ++k)
  {
    double lo = cuts[k], hi = cuts[k + 1];
    double glo = this->Evaluate(lo) - value;
    const double ghi = this->Evaluate(hi) - value;
    if (glo == 0.0)
    {
      t = lo;
      return true;
    }
    if (ghi == 0.0)
    {
      t = hi;
      return true;
    }
    if ((glo < 0.0) == (ghi < 0.0))
    {
      continue;
    }
    // Monotone and bracketing: bisect until the interval cannot shrink.
    for (int iteration = 0; iteration < 200; ++iteration)
    {
      const double mid = 0.5 * (lo + hi);
      if (mid <= lo || mid >= hi)
      {
        break;
      }
      const double g = this->Evaluate(mid) - value;
      if (g == 0.0)
      {
        lo = hi = mid;
        break;
      }
      if ((g < 0.0) == (glo < 0.0))
      {
        lo = mid;
        glo = g;
      }
      else
      {
        hi = mid;
      }
    }
    t = 0.5 * (lo + hi);
    return true;
  }
  return false;
}
