// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
#include "vtkMarschnerLobbSource.h"

#include "vtkDataArray.h"
#include "vtkImageData.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkMath.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkSMPTools.h"
#include "vtkStreamingDemandDrivenPipeline.h"

#include <vtksys/SystemInformation.hxx>

#include <algorithm>
#include <cmath>
#include <vector>

vtkStandardNewMacro(vtkMarschnerLobbSource);

//------------------------------------------------------------------------------
vtkMarschnerLobbSource::vtkMarschnerLobbSource()
{
  this->SetNumberOfInputPorts(0);
}

//------------------------------------------------------------------------------
double vtkMarschnerLobbSource::Evaluate(double x, double y, double z, double fm, double alpha)
{
  const double pi = vtkMath::Pi();
  const double r = std::sqrt(x * x + y * y);
  const double rho = std::cos(2.0 * pi * fm * std::cos(pi * r / 2.0));
  return (1.0 - std::sin(pi * z / 2.0) + alpha * (1.0 + rho)) / (2.0 * (1.0 + alpha));
}

//------------------------------------------------------------------------------
int vtkMarschnerLobbSource::RequestInformation(vtkInformation*,
  vtkInformationVector**,
  vtkInformationVector* outputVector)
{
  int type = this->OutputScalarType;
  if (type != VTK_FLOAT && type != VTK_DOUBLE && type != VTK_UNSIGNED_CHAR &&
    type != VTK_UNSIGNED_SHORT)
  {
    vtkErrorMacro("Unsupported output scalar type " << type << "; producing float.");
    type = VTK_FLOAT;
  }
  int dims[3];
  double spacing[3], origin[3] = { -1, -1, -1 };
  for (int a = 0; a < 3; ++a)
  {
    dims[a] = std::max(this->Dimensions[a], 2);
    spacing[a] = 2.0 / (dims[a] - 1);
  }
  vtkInformation* outInfo = outputVector->GetInformationObject(0);
  int extent[6] = { 0, dims[0] - 1, 0, dims[1] - 1, 0, dims[2] - 1 };
  outInfo->Set(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT(), extent, 6);
  outInfo->Set(vtkDataObject::SPACING(), spacing, 3);
  outInfo->Set(vtkDataObject::ORIGIN(), origin, 3);
  vtkDataObject::SetPointDataActiveScalarInfo(outInfo, type, 1);
  // Any sub-extent is computed on its own, so a parallel pipeline (ParaView under MPI) or a
  // streaming one asks each piece for its extent only, not every piece for the whole volume.
  outInfo->Set(CAN_PRODUCE_SUB_EXTENT(), 1);
  return 1;
}

//------------------------------------------------------------------------------
void vtkMarschnerLobbSource::ExecuteDataWithInformation(vtkDataObject* outputObject,
  vtkInformation* outInfo)
{
  // An impossible size is an error and an empty output, not an allocation that overcommits
  // and is killed when written.
  const int* update = outInfo->Get(vtkStreamingDemandDrivenPipeline::UPDATE_EXTENT());
  const double points =
    (update[1] - update[0] + 1.0) * (update[3] - update[2] + 1.0) * (update[5] - update[4] + 1.0);
  vtksys::SystemInformation system;
  system.RunMemoryCheck();
  const double memory = 1048576.0 * static_cast<double>(system.GetTotalPhysicalMemory()); // MiB
  if (memory > 0.0 &&
    points * vtkDataArray::GetDataTypeSize(vtkImageData::GetScalarType(outInfo)) > memory)
  {
    vtkErrorMacro("A volume of " << points << " points does not fit in this machine's "
                                 << std::floor(memory / 1048576.0) << " MiB of memory.");
    return;
  }
  vtkImageData* output = this->AllocateOutputData(outputObject, outInfo);
  vtkDataArray* scalars = output->GetPointData()->GetScalars();
  scalars->SetName("MarschnerLobb");
  const int* extent = output->GetExtent();
  const double* spacing = output->GetSpacing();
  const double* origin = output->GetOrigin();
  double scale = 1.0;
  if (scalars->GetDataType() == VTK_UNSIGNED_CHAR)
  {
    scale = 255.0;
  }
  else if (scalars->GetDataType() == VTK_UNSIGNED_SHORT)
  {
    scale = 65535.0;
  }
  const bool integer = scale != 1.0;
  // Eq. of Evaluate() with its terms in x, y and in z computed once per column and per
  // slice (the same operations, so the same values), slices in parallel.
  const double pi = vtkMath::Pi();
  const double fm = this->Frequency, alpha = this->Alpha;
  const vtkIdType nx = extent[1] - extent[0] + 1, ny = extent[3] - extent[2] + 1;
  std::vector<double> rho(static_cast<size_t>(nx * ny));
  for (vtkIdType j = 0; j < ny; ++j)
  {
    for (vtkIdType i = 0; i < nx; ++i)
    {
      const double x = origin[0] + (extent[0] + i) * spacing[0];
      const double y = origin[1] + (extent[2] + j) * spacing[1];
      const double r = std::sqrt(x * x + y * y);
      rho[i + nx * j] = std::cos(2.0 * pi * fm * std::cos(pi * r / 2.0));
    }
  }
  vtkSMPTools::For(extent[4], extent[5] + 1,
    [&](vtkIdType begin, vtkIdType end)
    {
      for (vtkIdType k = begin; k < end; ++k)
      {
        const double z = origin[2] + k * spacing[2];
        const double sz = std::sin(pi * z / 2.0);
        vtkIdType id = (k - extent[4]) * nx * ny;
        for (vtkIdType c = 0; c < nx * ny; ++c, ++id)
        {
          double v = scale * ((1.0 - sz + alpha * (1.0 + rho[c])) / (2.0 * (1.0 + alpha)));
          if (integer)
          {
            v = std::min(std::max(std::round(v), 0.0), scale);
          }
          scalars->SetComponent(id, 0, v);
        }
      }
    });
}

//------------------------------------------------------------------------------
void vtkMarschnerLobbSource::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Dimensions: " << this->Dimensions[0] << " " << this->Dimensions[1] << " "
     << this->Dimensions[2] << "\n";
  os << indent << "Frequency: " << this->Frequency << "\n";
  os << indent << "Alpha: " << this->Alpha << "\n";
  os << indent << "OutputScalarType: " << this->OutputScalarType << "\n";
}
