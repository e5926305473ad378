// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
#include "vtkCurvedShellSource.h"

#include "vtkObjectFactory.h"

#include <algorithm>
#include <cmath>
#include <limits>

vtkStandardNewMacro(vtkCurvedShellSource);

namespace
{
// The shells of the class comment: centre, radius and polar axis of the wobble.
struct Shell
{
  double Centre[3];
  double Radius;
  int Axis;
};
const Shell Shells[] = {
  { { 0.0, 0.0, 0.0 }, 0.5, 2 },
  { { 0.0, 0.0, 0.05 }, 0.8, 0 },
  { { 0.35, 0.3, -0.3 }, 0.3, 1 },
  { { -0.4, -0.3, 0.35 }, 0.25, 2 },
};

// d_k of the class comment, for q relative to the shell's centre.
double ShellDistance(const double q[3], const Shell& shell, double wobble)
{
  const double rho = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2]);
  const double inner = shell.Radius * (1.0 - wobble), outer = shell.Radius * (1.0 + wobble);
  const double layer = std::max(0.0, std::max(inner - rho, rho - outer));
  if (rho == 0.0)
  {
    // The centre has no direction; the distance to the layer is all that is known there, and
    // all that matters, the layer being far from the centre.
    return layer;
  }
  const double n[3] = { q[0] / rho, q[1] / rho, q[2] / rho };
  const double product = n[0] * n[1] * n[2];
  const double polar = n[shell.Axis];
  const double factor = 4.0 * polar * polar - 3.0;
  const double shape = 2.0 * product * factor; // W_k
  // Gradient of the polynomial W in R^3; only its part tangent to the sphere tilts the
  // surface, so the radial part is removed.
  double gradient[3] = {
    2.0 * n[1] * n[2] * factor, 2.0 * n[0] * n[2] * factor, 2.0 * n[0] * n[1] * factor
  };
  gradient[shell.Axis] += 16.0 * product * polar;
  const double radial = gradient[0] * n[0] + gradient[1] * n[1] + gradient[2] * n[2];
  double tangent = 0.0;
  for (int a = 0; a < 3; ++a)
  {
    const double t = gradient[a] - radial * n[a];
    tangent += t * t;
  }
  const double r = shell.Radius * (1.0 + wobble * shape);
  const double slope = shell.Radius * wobble * std::sqrt(tangent) / r;
  const double plane = std::abs(rho - r) / std::sqrt(1.0 + slope * slope);
  return std::max(plane, layer);
}
}

//------------------------------------------------------------------------------
double vtkCurvedShellSource::Evaluate(const double p[3], double thickness, double wobble)
{
  double distance = std::numeric_limits<double>::infinity();
  for (const Shell& shell : Shells)
  {
    const double q[3] = { p[0] - shell.Centre[0], p[1] - shell.Centre[1], p[2] - shell.Centre[2] };
    distance = std::min(distance, ShellDistance(q, shell, wobble));
  }
  // The nearest shell gives the largest of the shells' values.
  const double s = distance / thickness;
  return std::exp(-s * s);
}

//------------------------------------------------------------------------------
bool vtkCurvedShellSource::CheckFieldSettings()
{
  if (!(this->ShellThickness > 0.0) || !std::isfinite(this->ShellThickness))
  {
    vtkErrorMacro("ShellThickness " << this->ShellThickness << " is not a positive finite number.");
    return false;
  }
  // The clamp of the setter lets a NaN through.
  if (!std::isfinite(this->Wobble))
  {
    vtkErrorMacro("Wobble " << this->Wobble << " is not a number.");
    return false;
  }
  return true;
}

//------------------------------------------------------------------------------
double vtkCurvedShellSource::EvaluateField(const double point[3])
{
  return vtkCurvedShellSource::Evaluate(point, this->ShellThickness, this->Wobble);
}

//------------------------------------------------------------------------------
void vtkCurvedShellSource::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "ShellThickness: " << this->ShellThickness << "\n";
  os << indent << "Wobble: " << this->Wobble << "\n";
}
