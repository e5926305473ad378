// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
#include "vtkBlobSource.h"

#include "vtkObjectFactory.h"

#include <cmath>

vtkStandardNewMacro(vtkBlobSource);

namespace
{
// The blobs of the class comment: centre, width, amplitude.
struct Blob
{
  double Centre[3];
  double Width;
  double Amplitude;
};
const Blob Blobs[] = {
  { { -0.5, -0.4, -0.3 }, 0.08, 1.0 },
  { { 0.45, -0.35, 0.2 }, 0.06, 0.8 },
  { { 0.1, 0.5, -0.45 }, 0.1, 0.9 },
  { { -0.3, 0.35, 0.5 }, 0.05, 1.0 },
  { { 0.5, 0.45, 0.55 }, 0.07, 0.7 },
  { { 0.0, 0.0, 0.0 }, 0.1, 0.6 },
};
}

//------------------------------------------------------------------------------
double vtkBlobSource::Evaluate(const double p[3], double scale)
{
  double f = 0.0;
  for (const Blob& blob : Blobs)
  {
    const double dx = p[0] - blob.Centre[0], dy = p[1] - blob.Centre[1], dz = p[2] - blob.Centre[2];
    const double w = scale * blob.Width;
    f += blob.Amplitude * std::exp(-(dx * dx + dy * dy + dz * dz) / (2.0 * w * w));
  }
  return f;
}

//------------------------------------------------------------------------------
bool vtkBlobSource::CheckFieldSettings()
{
  if (!(this->BlobScale > 0.0) || !std::isfinite(this->BlobScale))
  {
    vtkErrorMacro("BlobScale " << this->BlobScale << " is not a positive finite number.");
    return false;
  }
  return true;
}

//------------------------------------------------------------------------------
double vtkBlobSource::EvaluateField(const double point[3])
{
  return vtkBlobSource::Evaluate(point, this->BlobScale);
}

//------------------------------------------------------------------------------
void vtkBlobSource::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "BlobScale: " << this->BlobScale << "\n";
}
