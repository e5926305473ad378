// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
#include "vtkBlobSource.h"

#include "vtkFloatArray.h"
#include "vtkImageData.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkSMPTools.h"
#include "vtkStreamingDemandDrivenPipeline.h"

#include <vtksys/SystemInformation.hxx>

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
vtkBlobSource::vtkBlobSource()
{
  this->SetNumberOfInputPorts(0);
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
int vtkBlobSource::RequestInformation(vtkInformation*,
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
void vtkBlobSource::ExecuteDataWithInformation(vtkDataObject* outputObject, vtkInformation* outInfo)
{
  const int* update = outInfo->Get(vtkStreamingDemandDrivenPipeline::UPDATE_EXTENT());
  if (update[0] > update[1] || update[2] > update[3] || update[4] > update[5])
  {
    // Bad dimensions, already reported by RequestInformation, or an empty piece.
    return;
  }
  const double scale = this->BlobScale;
  if (!(scale > 0.0) || !std::isfinite(scale))
  {
    vtkErrorMacro("BlobScale " << scale << " is not a positive finite number.");
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
  scalars->SetName("Blobs");
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
            row[i - extent[0]] = static_cast<float>(vtkBlobSource::Evaluate(p, scale));
          }
        }
      }
    });
}

//------------------------------------------------------------------------------
void vtkBlobSource::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Dimensions: " << this->Dimensions[0] << " " << this->Dimensions[1] << " "
     << this->Dimensions[2] << "\n";
  os << indent << "BlobScale: " << this->BlobScale << "\n";
}
