// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
// vtkBlobSource against its definition, written out here: a sum of six Gaussians, 1e-6 of
// their peaks apart; the grid [-1, 1]^3; most points near zero (a sparse volume); a piece of a
// parallel pipeline is a part of the grid with the same values; bad settings are errors with an
// empty output.
#include "vtkBlobSource.h"
#include "vtkDataArray.h"
#include "vtkImageData.h"
#include "vtkNew.h"
#include "vtkPointData.h"
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

// centre x, y, z, width, amplitude: the class comment's table.
const double Blobs[6][5] = {
  { -0.5, -0.4, -0.3, 0.08, 1.0 },
  { 0.45, -0.35, 0.2, 0.06, 0.8 },
  { 0.1, 0.5, -0.45, 0.1, 0.9 },
  { -0.3, 0.35, 0.5, 0.05, 1.0 },
  { 0.5, 0.45, 0.55, 0.07, 0.7 },
  { 0.0, 0.0, 0.0, 0.1, 0.6 },
};

double Field(const double p[3], double s)
{
  double f = 0.0;
  for (const auto& b : Blobs)
  {
    double r2 = 0.0;
    for (int a = 0; a < 3; ++a)
    {
      r2 += (p[a] - b[a]) * (p[a] - b[a]);
    }
    f += b[4] * std::exp(-0.5 * r2 / (s * b[3] * s * b[3]));
  }
  return f;
}
}

int TestBlobSource(int, char*[])
{
  vtkNew<vtkBlobSource> source;
  Check(source->GetBlobScale() == 1.0, "initial blob scale 1");
  vtkNew<vtkTest::ErrorObserver> errors;
  source->AddObserver(vtkCommand::ErrorEvent, errors);
  source->Update();
  Check(!errors->GetError(), "the default settings are no error");
  vtkImageData* image = source->GetOutput();
  vtkDataArray* scalars = image->GetPointData()->GetScalars();
  if (!Check(scalars && scalars->GetDataType() == VTK_FLOAT &&
          scalars->GetNumberOfTuples() == 129 * 129 * 129 &&
          std::string(scalars->GetName() ? scalars->GetName() : "") == "Blobs",
        "default output: 129^3 float scalars named Blobs"))
  {
    return 1;
  }
  int extent[6];
  image->GetExtent(extent);
  Check(extent[1] == 128 && extent[3] == 128 && extent[5] == 128 &&
      image->GetSpacing()[0] == 2.0 / 128 && image->GetOrigin()[2] == -1.0,
    "grid: extent 0..128, spacing 2 / 128, origin -1");

  // Every point against the definition; the peaks keep their amplitudes; sparse.
  double worst = 0.0;
  vtkIdType small = 0;
  for (vtkIdType id = 0; id < image->GetNumberOfPoints(); ++id)
  {
    double p[3];
    image->GetPoint(id, p);
    const double expected = Field(p, 1.0);
    worst = std::max(worst, std::abs(scalars->GetComponent(id, 0) - expected) / (1.0 + expected));
    small += expected < 1e-3 ? 1 : 0;
  }
  Check(worst < 1e-6, "every point equals the definition to float (" + std::to_string(worst) + ")");
  const double fraction = static_cast<double>(small) / image->GetNumberOfPoints();
  Check(fraction > 0.9, "over 90% of the points are below 1e-3 (" + std::to_string(fraction) + ")");
  for (const auto& b : Blobs)
  {
    Check(std::abs(vtkBlobSource::Evaluate(b, 1.0) - b[4]) < 1e-6,
      "a blob's centre has its amplitude " + std::to_string(b[4]));
    const double side[3] = { b[0] + b[3], b[1], b[2] };
    Check(std::abs(vtkBlobSource::Evaluate(side, 1.0) - b[4] * std::exp(-0.5)) < 1e-6,
      "one width from a centre: amplitude exp(-1/2)");
  }
  const double p[3] = { 0.3, -0.2, 0.1 };
  Check(std::abs(vtkBlobSource::Evaluate(p, 2.5) - Field(p, 2.5)) < 1e-15,
    "BlobScale widens every blob");

  // A piece, from a source that never computed the whole grid, equals the whole grid's points
  // there.
  const int box[6] = { 10, 70, 33, 100, 60, 128 };
  vtkNew<vtkBlobSource> pieceSource;
  pieceSource->UpdatePiece(0, 1, 0, box);
  vtkImageData* piece = pieceSource->GetOutput();
  vtkImageData* whole = image;
  int pieceExtent[6];
  piece->GetExtent(pieceExtent);
  bool same = std::equal(box, box + 6, pieceExtent);
  for (int k = box[4]; same && k <= box[5]; k += 7)
  {
    for (int j = box[2]; j <= box[3]; j += 5)
    {
      for (int i = box[0]; i <= box[1]; i += 3)
      {
        int ijk[3] = { i, j, k };
        same = same &&
          piece->GetPointData()->GetScalars()->GetComponent(piece->ComputePointId(ijk), 0) ==
            whole->GetPointData()->GetScalars()->GetComponent(whole->ComputePointId(ijk), 0);
      }
    }
  }
  Check(same,
    "a sub-extent holds the whole grid's values (extent " + std::to_string(pieceExtent[0]) + ".." +
      std::to_string(pieceExtent[1]) + " x " + std::to_string(pieceExtent[2]) + ".." +
      std::to_string(pieceExtent[3]) + " x " + std::to_string(pieceExtent[4]) + ".." +
      std::to_string(pieceExtent[5]) + ")");

  // Bad settings: errors, empty output.
  for (double scale : { 0.0,
         -1.0,
         std::numeric_limits<double>::quiet_NaN(),
         std::numeric_limits<double>::infinity() })
  {
    vtkNew<vtkBlobSource> bad;
    vtkNew<vtkTest::ErrorObserver> badErrors;
    bad->AddObserver(vtkCommand::ErrorEvent, badErrors);
    bad->SetDimensions(8, 8, 8);
    bad->SetBlobScale(scale);
    bad->Update();
    Check(badErrors->GetError() && bad->GetOutput()->GetNumberOfPoints() == 0,
      "BlobScale " + std::to_string(scale) + " is an error with an empty output");
  }
  vtkNew<vtkBlobSource> flat;
  vtkNew<vtkTest::ErrorObserver> flatErrors;
  flat->AddObserver(vtkCommand::ErrorEvent, flatErrors);
  flat->SetDimensions(8, 1, 8);
  flat->Update();
  Check(flatErrors->GetError() && flat->GetOutput()->GetNumberOfPoints() == 0,
    "one point along an axis is an error with an empty output");
  return failures == 0 ? 0 : 1;
}
