// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
#include "vtkCubeFieldSource.h"

#include "vtkFloatArray.h"
#include "vtkImageData.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkPointData.h"
#include "vtkSMPTools.h"
#include "vtkStreamingDemandDrivenPipeline.h"

#include <vtksys/SystemInformation.hxx>

#include <cmath>

//------------------------------------------------------------------------------
vtkCubeFieldSource::vtkCubeFieldSource()
{
  this->SetNumberOfInputPorts(0);
}

//------------------------------------------------------------------------------
int vtkCubeFieldSource::RequestInformation(vtkInformation*,
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
void vtkCubeFieldSource::ExecuteDataWithInformation(vtkDataObject* outputObject,
  vtkInformation* outInfo)
{
  const int* update = outInfo->Get(vtkStreamingDemandDrivenPipeline::UPDATE_EXTENT());
  if (update[0] > update[1] || update[2] > update[3] || update[4] > update[5])
  {
    // Bad dimensions, already reported by RequestInformation, or an empty piece.
    return;
  }
  if (!this->CheckFieldSettings())
  {
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
  scalars->SetName(this->GetFieldName());
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
            row[i - extent[0]] = static_cast<float>(this->EvaluateField(p));
          }
        }
      }
    });
}

//------------------------------------------------------------------------------
void vtkCubeFieldSource::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Dimensions: " << this->Dimensions[0] << " " << this->Dimensions[1] << " "
     << this->Dimensions[2] << "\n";
}
