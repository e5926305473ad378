// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
// vtkCurvedShellSource against its definition, written out here in spherical coordinates
// with a finite-difference normal instead of the source's polynomial and its gradient:
//   f(p) = max_k exp(-(d_k / w)^2),
//   r_k(theta, phi) = R_k (1 + a cos(3 theta) sin^2(theta) sin(2 phi)),
// d_k the larger of the distance to the tangent plane at p's radial projection onto shell k
// and the distance to the layer R_k (1 +- a), on the grid [-1, 1]^3 with spacing 2 / (n - 1);
// a piece of a parallel pipeline is a part of the grid with the same values; bad settings are
// errors with an empty output.
#include "vtkCurvedShellSource.h"
#include "vtkDataArray.h"
#include "vtkImageData.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkStreamingDemandDrivenPipeline.h"
#include "vtkTestErrorObserver.h"

#include <algorithm>
#include <cmath>
#include <iostream>
#include <limits>
#include <string>

namespace
{
int failures = 0;
bool Check(bool ok, const std::string& what)
{
  if (!ok)
  {
    std::cerr << "Failed: " << what << "\n";
    ++failures;
  }
  return ok;
}

// The shells of the class comment: centre, radius, polar axis.
struct Shell
{
  double C[3];
  double R;
  int Axis;
};
const Shell Shells[] = {
  { { 0.0, 0.0, 0.0 }, 0.5, 2 },
  { { 0.0, 0.0, 0.05 }, 0.8, 0 },
  { { 0.35, 0.3, -0.3 }, 0.3, 1 },
  { { -0.4, -0.3, 0.35 }, 0.25, 2 },
};

// Radius of a shell in the direction of q, from the polar angle about the shell's axis and
// the azimuth in the plane of the next two axes.
double Radius(const Shell& s, const double q[3], double a)
{
  const double rho = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2]);
  const int u = (s.Axis + 1) % 3, v = (s.Axis + 2) % 3;
  const double theta = std::acos(std::max(-1.0, std::min(1.0, q[s.Axis] / rho)));
  const double phi = std::atan2(q[v], q[u]);
  const double sine = std::sin(theta);
  return s.R * (1.0 + a * std::cos(3.0 * theta) * sine * sine * std::sin(2.0 * phi));
}

// The implicit function of a shell, negative inside.
double Implicit(const Shell& s, const double q[3], double a)
{
  return std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2]) - Radius(s, q, a);
}

double Distance(const Shell& s, const double p[3], double a)
{
  double q[3] = { p[0] - s.C[0], p[1] - s.C[1], p[2] - s.C[2] };
  const double rho = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2]);
  const double layer = std::max({ 0.0, s.R * (1.0 - a) - rho, rho - s.R * (1.0 + a) });
  if (rho == 0.0)
  {
    return layer;
  }
  const double r = Radius(s, q, a);
  double foot[3], normal[3], length = 0.0;
  for (int i = 0; i < 3; ++i)
  {
    foot[i] = q[i] * r / rho;
  }
  const double h = 1e-6;
  for (int i = 0; i < 3; ++i)
  {
    double plus[3] = { foot[0], foot[1], foot[2] }, minus[3] = { foot[0], foot[1], foot[2] };
    plus[i] += h;
    minus[i] -= h;
    normal[i] = (Implicit(s, plus, a) - Implicit(s, minus, a)) / (2.0 * h);
    length += normal[i] * normal[i];
  }
  length = std::sqrt(length);
  double plane = 0.0;
  for (int i = 0; i < 3; ++i)
  {
    plane += (q[i] - foot[i]) * normal[i] / length;
  }
  return std::max(std::abs(plane), layer);
}

double Field(const double p[3], double w, double a)
{
  double value = 0.0;
  for (const Shell& s : Shells)
  {
    const double d = Distance(s, p, a);
    value = std::max(value, std::exp(-(d / w) * (d / w)));
  }
  return value;
}

void CheckGeometry(vtkImageData* image, const int dims[3], const std::string& label)
{
  int extent[6];
  image->GetExtent(extent);
  const double* spacing = image->GetSpacing();
  const double* origin = image->GetOrigin();
  for (int a = 0; a < 3; ++a)
  {
    Check(extent[2 * a] == 0 && extent[2 * a + 1] == dims[a] - 1,
      label + ": extent 0.." + std::to_string(dims[a] - 1) + " on axis " + std::to_string(a));
    Check(std::abs(spacing[a] - 2.0 / (dims[a] - 1)) < 1e-15,
      label + ": spacing 2 / (n - 1) on axis " + std::to_string(a));
    Check(origin[a] == -1.0, label + ": origin -1 on axis " + std::to_string(a));
  }
}

double Value(vtkImageData* image, int i, int j, int k)
{
  int ijk[3] = { i, j, k };
  return image->GetPointData()->GetScalars()->GetComponent(image->ComputePointId(ijk), 0);
}

// A deterministic spread of directions over the sphere.
void Direction(int n, double d[3])
{
  const double z = std::cos(2.3 * n + 0.4), azimuth = 3.7 * n + 1.1;
  const double ring = std::sqrt(1.0 - z * z);
  d[0] = ring * std::cos(azimuth);
  d[1] = ring * std::sin(azimuth);
  d[2] = z;
}
}

int TestCurvedShellSource(int, char*[])
{
  // Default: 129^3 float over [-1, 1]^3, w = 0.04, a = 0.15.
  vtkNew<vtkCurvedShellSource> source;
  Check(source->GetShellThickness() == 0.04 && source->GetWobble() == 0.15,
    "initial thickness 0.04 and wobble 0.15");
  vtkNew<vtkTest::ErrorObserver> errors;
  source->AddObserver(vtkCommand::ErrorEvent, errors);
  source->Update();
  Check(!errors->GetError(), "the default settings are no error");
  vtkImageData* image = source->GetOutput();
  const int cube[3] = { 129, 129, 129 };
  CheckGeometry(image, cube, "default");
  vtkDataArray* scalars = image->GetPointData()->GetScalars();
  if (!Check(scalars && scalars->GetDataType() == VTK_FLOAT &&
          scalars->GetNumberOfComponents() == 1 && scalars->GetNumberOfTuples() == 129 * 129 * 129,
        "default output: one float scalar per point"))
  {
    return 1;
  }
  Check(std::string(scalars->GetName() ? scalars->GetName() : "") == "CurvedShells",
    "the scalar array is named CurvedShells");
  double range[2];
  scalars->GetRange(range);
  Check(range[0] >= 0.0 && range[1] <= 1.0, "values lie in [0, 1]");
  Check(
    range[1] > 0.999, "values reach 1 on the shells (largest " + std::to_string(range[1]) + ")");

  // Grid point (96, 64, 64) is (0.5, 0, 0): on shell 0, whose wobble vanishes on the x axis.
  Check(
    std::abs(Value(image, 96, 64, 64) - 1.0) < 1e-5, "the grid point (0.5, 0, 0) on shell 0 is 1");
  // The corner is more than 0.8 from every shell, 20 widths: exp(-400) is 0 in float.
  Check(Value(image, 0, 0, 0) < 1e-12, "the corner (-1, -1, -1), far from every shell, is 0");
  // The centre of shell 0, inside all layers' holes.
  Check(Value(image, 64, 64, 64) < 1e-6, "the centre (0, 0, 0) is 0");

  // Points on the wobbled surfaces, in directions where the wobble is not small: value 1.
  // On the x axis at w from shell 0 (radial normal there): 1/e, for other widths too.
  int surfacePoints = 0;
  double worstSurface = 0.0;
  for (int n = 0; n < 400; ++n)
  {
    const Shell& s = Shells[n % 4];
    double d[3];
    Direction(n, d);
    if (std::abs(Radius(s, d, 1.0) / s.R - 1.0) < 0.1)
    {
      continue;
    }
    const double r = Radius(s, d, 0.15);
    const double p[3] = { s.C[0] + r * d[0], s.C[1] + r * d[1], s.C[2] + r * d[2] };
    worstSurface =
      std::max(worstSurface, std::abs(vtkCurvedShellSource::Evaluate(p, 0.04, 0.15) - 1.0));
    ++surfacePoints;
  }
  Check(surfacePoints > 100 && worstSurface < 1e-5,
    "points on the wobbled surfaces are 1 (" + std::to_string(surfacePoints) +
      " points, largest deviation " + std::to_string(worstSurface) + ")");
  const double offAxis[3] = { 0.54, 0.0, 0.0 };
  Check(std::abs(vtkCurvedShellSource::Evaluate(offAxis, 0.04, 0.15) - std::exp(-1.0)) < 1e-12,
    "a point at distance w = 0.04 from shell 0 is 1/e");
  Check(std::abs(vtkCurvedShellSource::Evaluate(offAxis, 0.08, 0.15) - std::exp(-0.25)) < 1e-12,
    "a point at distance w / 2 from shell 0 is exp(-1/4)");

  // Evaluate equals the definition, in double, for spheres, the initial and the largest
  // wobble. The definition's normal is a central difference with step 1e-6: an error near
  // 1e-11 in d, times the profile's slope, below 1 / w.
  for (double a : { 0.0, 0.15, 0.5 })
  {
    double worst = 0.0;
    for (int n = 0; n < 3000; ++n)
    {
      const double p[3] = { std::sin(1.3 * n), std::cos(0.7 * n), std::sin(2.9 * n + 1.0) };
      worst =
        std::max(worst, std::abs(vtkCurvedShellSource::Evaluate(p, 0.04, a) - Field(p, 0.04, a)));
    }
    Check(worst < 1e-8,
      "Evaluate equals the definition at wobble " + std::to_string(a) + " (largest deviation " +
        std::to_string(worst) + ")");
  }

  // Piece 1 of 2 (as an MPI rank asks), then an extent offset along every axis: a part of
  // the grid, equal to the whole grid's points there.
  vtkNew<vtkImageData> whole;
  whole->DeepCopy(image);
  source->UpdatePiece(1, 2, 0);
  const int box[6] = { 10, 70, 33, 100, 60, 128 };
  for (int pass = 0; pass < 2; ++pass)
  {
    const std::string label = pass == 0 ? "piece 1 of 2" : "extent 10..70 x 33..100 x 60..128";
    if (pass == 1)
    {
      // One piece with an extent: a request for the extent alone would keep the two pieces.
      source->UpdatePiece(0, 1, 0, box);
    }
    vtkImageData* piece = source->GetOutput();
    int pieceExtent[6];
    piece->GetExtent(pieceExtent);
    const vtkIdType piecePoints = piece->GetNumberOfPoints();
    if (pass == 1)
    {
      Check(std::equal(box, box + 6, pieceExtent), label + ": the requested extent");
    }
    if (Check(piecePoints > 0 && piecePoints < whole->GetNumberOfPoints(),
          label + " holds a part of the grid (" + std::to_string(piecePoints) + " points)"))
    {
      double worstPiece = 0.0;
      for (int k = pieceExtent[4]; k <= pieceExtent[5]; ++k)
      {
        for (int j = pieceExtent[2]; j <= pieceExtent[3]; ++j)
        {
          for (int i = pieceExtent[0]; i <= pieceExtent[1]; ++i)
          {
            worstPiece =
              std::max(worstPiece, std::abs(Value(piece, i, j, k) - Value(whole, i, j, k)));
          }
        }
      }
      Check(worstPiece == 0.0, label + ": the points equal the whole grid's");
    }
  }
  source->UpdateWholeExtent();

  // Other grids and settings against the definition at every point: a non-cubic grid with a
  // wide profile, which still shows near the centres, where the layer decides, and the
  // largest wobble, which tilts the surfaces most. Float storage: 2^-24 relative on values
  // <= 1, plus the definition's finite difference.
  struct Setting
  {
    int Dims[3];
    double Thickness, Wobble;
  };
  for (const Setting& setting :
    { Setting{ { 33, 41, 37 }, 0.1, 0.3 }, Setting{ { 65, 65, 65 }, 0.04, 0.5 } })
  {
    const int* dims = setting.Dims;
    const std::string label = std::to_string(dims[0]) + " x " + std::to_string(dims[1]) + " x " +
      std::to_string(dims[2]) + " grid with w = " + std::to_string(setting.Thickness) +
      ", a = " + std::to_string(setting.Wobble);
    source->SetDimensions(setting.Dims);
    source->SetShellThickness(setting.Thickness);
    source->SetWobble(setting.Wobble);
    source->Update();
    CheckGeometry(source->GetOutput(), dims, label);
    double worstGrid = 0.0;
    for (int k = 0; k < dims[2]; ++k)
    {
      for (int j = 0; j < dims[1]; ++j)
      {
        for (int i = 0; i < dims[0]; ++i)
        {
          const double p[3] = { -1.0 + 2.0 * i / (dims[0] - 1),
            -1.0 + 2.0 * j / (dims[1] - 1),
            -1.0 + 2.0 * k / (dims[2] - 1) };
          worstGrid = std::max(worstGrid,
            std::abs(
              Value(source->GetOutput(), i, j, k) - Field(p, setting.Thickness, setting.Wobble)));
        }
      }
    }
    Check(worstGrid < 1e-6,
      label + " equals the definition (largest deviation " + std::to_string(worstGrid) + ")");
  }

  // The wobble is clamped to [0, 0.5].
  source->SetWobble(2.0);
  Check(source->GetWobble() == 0.5, "a wobble of 2 is clamped to 0.5");
  source->SetWobble(-1.0);
  Check(source->GetWobble() == 0.0, "a wobble of -1 is clamped to 0");
  source->SetWobble(0.15);

  // Bad settings: an error and an empty output; good settings afterwards work again.
  auto expectError = [&](const std::string& label, const std::string& message)
  {
    errors->Clear();
    source->Update();
    Check(errors->GetError() && errors->GetErrorMessage().find(message) != std::string::npos,
      label + " is reported");
    Check(source->GetOutput()->GetNumberOfPoints() == 0, label + " gives an empty output");
  };
  source->SetDimensions(1, 17, 17);
  expectError("dimensions 1 x 17 x 17", "at least 2");
  source->SetDimensions(17, 17, 0);
  expectError("dimensions 17 x 17 x 0", "at least 2");
  source->SetDimensions(17, 17, 17);
  for (double thickness : { 0.0,
         -0.04,
         std::numeric_limits<double>::quiet_NaN(),
         std::numeric_limits<double>::infinity() })
  {
    source->SetShellThickness(thickness);
    expectError("thickness " + std::to_string(thickness), "ShellThickness");
  }
  source->SetShellThickness(0.04);
  source->SetWobble(std::numeric_limits<double>::quiet_NaN());
  expectError("a NaN wobble", "Wobble");
  source->SetWobble(0.15);
  errors->Clear();
  source->Update();
  Check(!errors->GetError() && source->GetOutput()->GetNumberOfPoints() == 17 * 17 * 17,
    "valid settings after bad ones give the volume again");

  // A volume beyond memory: an error and an empty output, not a process killed writing it.
  source->SetDimensions(100000, 100000, 100000);
  expectError("a volume of 10^15 points", "does not fit");

  if (failures)
  {
    std::cerr << "TestCurvedShellSource: " << failures << " checks failed\n";
    return 1;
  }
  return 0;
}
