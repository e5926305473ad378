// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
#include "vtkThinFeatureSource.h"

#include "vtkDataArray.h"
#include "vtkImageData.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkStreamingDemandDrivenPipeline.h"

#include <vtksys/SystemInformation.hxx>

#include <algorithm>
#include <cmath>

vtkStandardNewMacro(vtkThinFeatureSource);

namespace
{
// Features in coordinates relative to the grid: a point (fraction of the extent along each
// axis) and a direction (sheet normal or tube axis), none aligned with the grid.
struct Feature
{
  double Point[3];
  double Direction[3];
  bool Tube;
};
const Feature Features[] = {
  { { 0.5, 0.5, 0.5 }, { 1.0, 2.0, 3.0 }, false },
  { { 0.3, 0.6, 0.4 }, { -2.0, 1.0, 1.5 }, false },
  { { 0.7, 0.35, 0.6 }, { 0.3, -1.0, 2.0 }, false },
  { { 0.5, 0.5, 0.5 }, { 1.0, 0.9, 0.8 }, true },
  { { 0.25, 0.75, 0.5 }, { 0.2, 1.0, -0.7 }, true },
  { { 0.6, 0.2, 0.3 }, { -1.0, 0.35, 0.55 }, true },
  { { 0.4, 0.4, 0.8 }, { 0.75, -0.6, 0.1 }, true },
};
}

//------------------------------------------------------------------------------
vtkThinFeatureSource::vtkThinFeatureSource()
{
  this->SetNumberOfInputPorts(0);
}

//------------------------------------------------------------------------------
double vtkThinFeatureSource::Evaluate(const double p[3], const int dims[3], double thickness)
{
  double value = 0.0;
  for (const Feature& f : Features)
  {
    double q[3], n[3];
    const double norm = std::sqrt(f.Direction[0] * f.Direction[0] +
      f.Direction[1] * f.Direction[1] + f.Direction[2] * f.Direction[2]);
    double along = 0.0;
    for (int a = 0; a < 3; ++a)
    {
      q[a] = p[a] - f.Point[a] * (dims[a] - 1);
      n[a] = f.Direction[a] / norm;
      along += q[a] * n[a];
    }
    double d;
    if (f.Tube)
    {
      // Distance to the axis line: the component of q across the direction.
      double across = 0.0;
      for (int a = 0; a < 3; ++a)
      {
        const double c = q[a] - along * n[a];
        across += c * c;
      }
      d = std::sqrt(across);
    }
    else
    {
      d = std::abs(along);
    }
    value = std::max(value, 1.0 - d / thickness);
  }
  return value;
}

//------------------------------------------------------------------------------
int vtkThinFeatureSource::RequestInformation(vtkInformation*,
  vtkInformationVector**,
  vtkInformationVector* outputVector)
{
  int extent[6];
  for (int a = 0; a < 3; ++a)
  {
    extent[2 * a] = 0;
    extent[2 * a + 1] = std::max(this->Dimensions[a], 2) - 1;
  }
  const double spacing[3] = { 1, 1, 1 }, origin[3] = { 0, 0, 0 };
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
void vtkThinFeatureSource::ExecuteDataWithInformation(vtkDataObject* outputObject,
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
  if (memory > 0.0 && points * sizeof(float) > memory)
  {
    vtkErrorMacro("A volume of " << points << " points does not fit in this machine's "
                                 << std::floor(memory / 1048576.0) << " MiB of memory.");
    return;
  }
  vtkImageData* output = this->AllocateOutputData(outputObject, outInfo);
  vtkDataArray* scalars = output->GetPointData()->GetScalars();
  scalars->SetName("ThinFeatures");
  const int* extent = output->GetExtent();
  int dims[3];
  vtkInformation* info = this->GetOutputInformation(0);
  const int* whole = info->Get(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT());
  for (int a = 0; a < 3; ++a)
  {
    dims[a] = whole[2 * a + 1] - whole[2 * a] + 1;
  }
  vtkIdType id = 0;
  for (int k = extent[4]; k <= extent[5]; ++k)
  {
    for (int j = extent[2]; j <= extent[3]; ++j)
    {
      for (int i = extent[0]; i <= extent[1]; ++i, ++id)
      {
        const double p[3] = {
          static_cast<double>(i), static_cast<double>(j), static_cast<double>(k)
        };
        scalars->SetComponent(id, 0, vtkThinFeatureSource::Evaluate(p, dims, this->Thickness));
      }
    }
  }
}

//------------------------------------------------------------------------------
void vtkThinFeatureSource::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Dimensions: " << this->Dimensions[0] << " " << this->Dimensions[1] << " "
     << this->Dimensions[2] << "\n";
  os << indent << "Thickness: " << this->Thickness << "\n";
}
