// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
// vtkMarschnerLobbSource against the closed form of Marschner and Lobb (1994),
//   rho(x, y, z) = (1 - sin(pi z / 2) + alpha (1 + cos(2 pi f_M cos(pi r / 2)))) / (2 (1 + alpha)),
// r = sqrt(x^2 + y^2), on the grid [-1, 1]^3 with spacing 2 / (n - 1), for every output type;
// a piece of a parallel pipeline is a part of the grid with the same values.
#include "vtkDataArray.h"
#include "vtkImageData.h"
#include "vtkMarschnerLobbSource.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkStreamingDemandDrivenPipeline.h"
#include "vtkTestErrorObserver.h"
#include "vtkThinFeatureSource.h"

#include <algorithm>
#include <cmath>
#include <iostream>
#include <string>

namespace
{
constexpr double Pi = 3.14159265358979323846;
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

// The closed form, written out independently of vtkMarschnerLobbSource::Evaluate.
double Rho(double x, double y, double z, double fm, double alpha)
{
  const double r = std::hypot(x, y);
  const double modulation = std::cos(2.0 * Pi * fm * std::cos(Pi * r / 2.0));
  return (1.0 - std::sin(Pi * z / 2.0) + alpha * (1.0 + modulation)) / (2.0 * (1.0 + alpha));
}

// Geometry of the output: extent 0..n-1, spacing 2 / (n - 1), origin -1 on each axis.
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

// Largest |value - scale rho| over the grid (scale 1 for float data), skipping, for integer
// data, points where scale rho is within 1e-6 of a rounding tie.
double WorstDeviation(vtkImageData* image,
  const int dims[3],
  double fm,
  double alpha,
  double scale,
  bool rounded)
{
  vtkDataArray* scalars = image->GetPointData()->GetScalars();
  double worst = 0.0;
  vtkIdType id = 0;
  for (int k = 0; k < dims[2]; ++k)
  {
    for (int j = 0; j < dims[1]; ++j)
    {
      for (int i = 0; i < dims[0]; ++i, ++id)
      {
        const double x = -1.0 + 2.0 * i / (dims[0] - 1), y = -1.0 + 2.0 * j / (dims[1] - 1),
                     z = -1.0 + 2.0 * k / (dims[2] - 1);
        double expected = scale * Rho(x, y, z, fm, alpha);
        if (rounded)
        {
          const double fraction = expected - std::floor(expected);
          if (std::abs(fraction - 0.5) < 1e-6)
          {
            continue;
          }
          expected = std::min(std::max(std::round(expected), 0.0), scale);
        }
        worst = std::max(worst, std::abs(scalars->GetComponent(id, 0) - expected));
      }
    }
  }
  return worst;
}
}

int TestMarschnerLobbSource(int, char*[])
{
  // Default: 41^3 float over [-1, 1]^3, f_M = 6, alpha = 0.25.
  vtkNew<vtkMarschnerLobbSource> source;
  source->Update();
  vtkImageData* image = source->GetOutput();
  const int cube[3] = { 41, 41, 41 };
  CheckGeometry(image, cube, "default");
  vtkDataArray* scalars = image->GetPointData()->GetScalars();
  if (!Check(scalars && scalars->GetDataType() == VTK_FLOAT &&
          scalars->GetNumberOfComponents() == 1 && scalars->GetNumberOfTuples() == 41 * 41 * 41,
        "default output: one float scalar per point"))
  {
    return 1;
  }
  Check(std::string(scalars->GetName() ? scalars->GetName() : "") == "MarschnerLobb",
    "the scalar array is named MarschnerLobb");
  // Known values: at r = 0, cos(2 pi 6 cos 0) = 1, so rho = (1 - sin(pi z / 2) + 2 alpha) /
  // (2 (1 + alpha)): 0.6 at z = 0, 0.2 at z = 1, 1.0 at z = -1 (the data range is [0, 1]).
  // Float storage: 2^-24 relative, values <= 1, hence 1.2e-7.
  const double floatTolerance = 1.2e-7;
  auto at = [&](int i, int j, int k) { return scalars->GetComponent(i + 41 * (j + 41 * k), 0); };
  Check(std::abs(at(20, 20, 20) - 0.6) < floatTolerance, "rho(0, 0, 0) = 0.6");
  Check(std::abs(at(20, 20, 40) - 0.2) < floatTolerance, "rho(0, 0, 1) = 0.2");
  Check(std::abs(at(20, 20, 0) - 1.0) < floatTolerance, "rho(0, 0, -1) = 1");
  // At the corner x = y = 1, z = 0: r = sqrt 2.
  const double corner =
    (1.0 + 0.25 * (1.0 + std::cos(12.0 * Pi * std::cos(Pi * std::sqrt(2.0) / 2.0)))) / 2.5;
  Check(std::abs(at(40, 40, 20) - corner) < floatTolerance, "rho(1, 1, 0) from the closed form");
  const double worstFloat = WorstDeviation(image, cube, 6.0, 0.25, 1.0, false);
  Check(worstFloat < floatTolerance,
    "float grid equals the closed form everywhere (largest deviation " +
      std::to_string(worstFloat) + ")");
  double range[2];
  scalars->GetRange(range);
  Check(range[0] >= 0.0 && range[1] <= 1.0 + floatTolerance, "values lie in [0, 1]");

  // The static Evaluate is the same closed form, in double.
  double worstEvaluate = 0.0;
  for (int n = 0; n < 1000; ++n)
  {
    const double x = std::sin(1.3 * n), y = std::cos(0.7 * n), z = std::sin(2.9 * n + 1.0);
    worstEvaluate = std::max(worstEvaluate,
      std::abs(vtkMarschnerLobbSource::Evaluate(x, y, z, 4.5, 0.4) - Rho(x, y, z, 4.5, 0.4)));
  }
  Check(worstEvaluate < 1e-14, "Evaluate equals the closed form in double");

  // Other parameters, non-cubic grid, double output.
  const int dims[3] = { 5, 7, 9 };
  source->SetDimensions(5, 7, 9);
  source->SetFrequency(3.0);
  source->SetAlpha(0.5);
  source->SetOutputScalarType(VTK_DOUBLE);
  source->Update();
  CheckGeometry(source->GetOutput(), dims, "5 x 7 x 9");
  Check(source->GetOutput()->GetScalarType() == VTK_DOUBLE, "double output");
  Check(WorstDeviation(source->GetOutput(), dims, 3.0, 0.5, 1.0, false) < 1e-14,
    "double 5 x 7 x 9 grid with f_M = 3, alpha = 0.5 equals the closed form");

  // Integer outputs: scaled to the full range, rounded, inside the range.
  source->SetDimensions(41, 41, 41);
  source->SetFrequency(6.0);
  source->SetAlpha(0.25);
  for (int type : { VTK_UNSIGNED_CHAR, VTK_UNSIGNED_SHORT })
  {
    const double scale = type == VTK_UNSIGNED_CHAR ? 255.0 : 65535.0;
    const std::string label = type == VTK_UNSIGNED_CHAR ? "uint8" : "uint16";
    source->SetOutputScalarType(type);
    source->Update();
    vtkImageData* out = source->GetOutput();
    Check(out->GetScalarType() == type, label + " output type");
    CheckGeometry(out, cube, label);
    Check(WorstDeviation(out, cube, 6.0, 0.25, scale, true) == 0.0,
      label + ": every value is round(scale rho)");
    double r[2];
    out->GetPointData()->GetScalars()->GetRange(r);
    Check(r[0] >= 0.0 && r[1] == scale,
      label + ": values in [0, max], the maximum rho = 1 at (0, 0, -1)");
  }

  // Piece 1 of 2 (as an MPI rank asks): a part of the grid, not all of it, equal to the
  // whole grid's points there.
  source->SetOutputScalarType(VTK_FLOAT);
  source->Update();
  vtkNew<vtkImageData> whole;
  whole->DeepCopy(source->GetOutput());
  source->UpdatePiece(1, 2, 0);
  vtkImageData* piece = source->GetOutput();
  int pieceExtent[6];
  piece->GetExtent(pieceExtent);
  const vtkIdType piecePoints = piece->GetNumberOfPoints();
  if (Check(piecePoints > 0 && piecePoints < whole->GetNumberOfPoints(),
        "piece 1 of 2 holds a part of the grid (" + std::to_string(piecePoints) + " points)"))
  {
    double worstPiece = 0.0;
    for (int k = pieceExtent[4]; k <= pieceExtent[5]; ++k)
    {
      for (int j = pieceExtent[2]; j <= pieceExtent[3]; ++j)
      {
        for (int i = pieceExtent[0]; i <= pieceExtent[1]; ++i)
        {
          int ijk[3] = { i, j, k };
          worstPiece = std::max(worstPiece,
            std::abs(
              piece->GetPointData()->GetScalars()->GetComponent(piece->ComputePointId(ijk), 0) -
              whole->GetPointData()->GetScalars()->GetComponent(whole->ComputePointId(ijk), 0)));
        }
      }
    }
    Check(worstPiece == 0.0, "the piece's points equal the whole grid's");
  }
  source->UpdateWholeExtent();

  // Dimensions below 2 are raised to 2; an unsupported type is reported and gives float.
  source->SetDimensions(1, 3, 2);
  source->SetOutputScalarType(VTK_FLOAT);
  source->Update();
  const int raised[3] = { 2, 3, 2 };
  CheckGeometry(source->GetOutput(), raised, "dimensions 1 x 3 x 2 raised to 2 x 3 x 2");
  vtkNew<vtkTest::ErrorObserver> errors;
  source->AddObserver(vtkCommand::ErrorEvent, errors);
  source->SetOutputScalarType(VTK_INT);
  source->Update();
  Check(errors->GetError() && errors->GetErrorMessage().find("Unsupported") != std::string::npos,
    "an unsupported output type is reported");
  Check(source->GetOutput()->GetScalarType() == VTK_FLOAT, "an unsupported type gives float");

  // A volume beyond memory: an error and an empty output, not a process killed writing it.
  errors->Clear();
  source->SetDimensions(100000, 100000, 100000);
  source->Update();
  Check(errors->GetError() && errors->GetErrorMessage().find("does not fit") != std::string::npos,
    "a volume of 10^15 points is reported");
  Check(source->GetOutput()->GetNumberOfPoints() == 0, "and nothing is allocated");
  vtkNew<vtkThinFeatureSource> thin;
  thin->AddObserver(vtkCommand::ErrorEvent, errors);
  errors->Clear();
  thin->SetDimensions(100000, 100000, 100000);
  thin->Update();
  Check(errors->GetError() && thin->GetOutput()->GetNumberOfPoints() == 0,
    "the thin-feature source reports a volume of 10^15 points too");

  if (failures)
  {
    std::cerr << "TestMarschnerLobbSource: " << failures << " checks failed\n";
    return 1;
  }
  return 0;
}
