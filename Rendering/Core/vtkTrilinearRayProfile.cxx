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
