// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
#include "vtkCurvedShellSource.h"

#include "vtkFloatArray.h"
#include "vtkImageData.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkSMPTools.h"
#include "vtkStreamingDemandDrivenPipeline.h"

#include <vtksys/SystemInformation.hxx>

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
vtkCurvedShellSource::vtkCurvedShellSource()
{
  this->SetNumberOfInputPorts(0);
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
int vtkCurvedShellSource::RequestInformation(vtkInformation*,
  vtkInformationVector**,
  vtkInformationVector* outputVector)
{
  int extent[6] = { 0, -1, 0, -1, 0, -1 };
  double spacing[3] = { 1, 1, 1 }, origin[3] = { -1, -1, -1 };
  if (this->Dimensions[0] < 2 || this->Dimensions[1] < 2 || this->Dimensions[2] < 2)
  {
    // An empty whole extent makes the output empty without a failed request in the pipeline.
    vtkErrorMacro("Dimensions " << this->Dimensions[0] << " x " << this->Dimensions[1] << " x "
                                << this->Dimensions[2] << " need at least 2 points per axis.");
  }
  else
  {
    for (int a = 0; a < 3; ++a)
    {
      extent[2 * a + 1] = this->Dimensions[a] - 1;
      spacing[a] = 2.0 / (this->Dimensions[a] - 1);
    }
  }
  vtkInformation* outInfo = outputVector->GetInformationObject(0);
  outInfo->Set(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT(), extent, 6);
  outInfo->Set(vtkDataObject::SPACING(), spacing, 3);
  outInfo->Set(vtkDataObject::ORIGIN(), origin, 3);
  vtkDataObject::SetPointDataActiveScalarInfo(outInfo, VTK_FLOAT, 1);
  // Any sub-extent is computed on its own, so a parallel pipeline (ParaView under MPI) or a
  // streaming one asks each piece for its extent only, not every piece for the whole volume.
  outInfo->Set(CAN_PRODUCE_SUB_EXTENT(), 1);
  return 1;
}

//------------------------------------------------------------------------------
void vtkCurvedShellSource::ExecuteDataWithInformation(vtkDataObject* outputObject,
  vtkInformation* outInfo)
{
  const int* update = outInfo->Get(vtkStreamingDemandDrivenPipeline::UPDATE_EXTENT());
  if (update[0] > update[1] || update[2] > update[3] || update[4] > update[5])
  {
    // Bad dimensions, already reported by RequestInformation, or an empty piece.
    return;
  }
  const double thickness = this->ShellThickness;
  if (!(thickness > 0.0) || !std::isfinite(thickness))
  {
    vtkErrorMacro("ShellThickness " << thickness << " is not a positive finite number.");
    return;
  }
  // The clamp of the setter lets a NaN through.
  const double wobble = this->Wobble;
  if (!std::isfinite(wobble))
  {
    vtkErrorMacro("Wobble " << wobble << " is not a number.");
    return;
  }
  // An impossible size is an error and an empty output, not an allocation that overcommits
  // and is killed when written.
  const double points =
    (update[1] - update[0] + 1.0) * (update[3] - update[2] + 1.0) * (update[5] - update[4] + 1.0);
  vtksys::SystemInformation system;
  system.RunMemoryCheck();
  const double memory = 1048576.0 * static_cast<double>(system.GetTotalPhysicalMemory()); // MiB
  if (memory > 0.0 && points * sizeof(float) > memory)
  {
    vtkErrorMacro("A volume of " << points << " points does not fit in this machine's "
                                 << std::floor(memory / 1048576.0) << " MiB of memory.");
    return;
  }
  vtkImageData* output = this->AllocateOutputData(outputObject, outInfo);
  vtkFloatArray* scalars = vtkFloatArray::SafeDownCast(output->GetPointData()->GetScalars());
  if (!scalars)
  {
    vtkErrorMacro("The output scalars are not float.");
    return;
  }
  scalars->SetName("CurvedShells");
  float* values = scalars->GetPointer(0);
  int extent[6];
  output->GetExtent(extent);
  const double* spacing = output->GetSpacing();
  const double* origin = output->GetOrigin();
  const vtkIdType nx = extent[1] - extent[0] + 1, ny = extent[3] - extent[2] + 1;
  // Slices are independent: each task fills its own range of them.
  vtkSMPTools::For(extent[4],
    extent[5] + 1,
    [&](vtkIdType k0, vtkIdType k1)
    {
      for (vtkIdType k = k0; k < k1; ++k)
      {
        float* slice = values + (k - extent[4]) * nx * ny;
        for (int j = extent[2]; j <= extent[3]; ++j)
        {
          float* row = slice + (j - extent[2]) * nx;
          for (int i = extent[0]; i <= extent[1]; ++i)
          {
            const double p[3] = {
              origin[0] + i * spacing[0], origin[1] + j * spacing[1], origin[2] + k * spacing[2]
            };
            row[i - extent[0]] =
              static_cast<float>(vtkCurvedShellSource::Evaluate(p, thickness, wobble));
          }
        }
      }
    });
}

//------------------------------------------------------------------------------
void vtkCurvedShellSource::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Dimensions: " << this->Dimensions[0] << " " << this->Dimensions[1] << " "
     << this->Dimensions[2] << "\n";
  os << indent << "ShellThickness: " << this->ShellThickness << "\n";
  os << indent << "Wobble: " << this->Wobble << "\n";
}
