// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
#include "vtkPreIntegrationRayCaster.h"

#include "vtkCameraRayModel.h"
#include "vtkDataArray.h"
#include "vtkFloatArray.h"
#include "vtkImageData.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkMatrix4x4.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPreIntegrationRayMarch.h"
#include "vtkPreIntegrationTable.h"
#include "vtkSMPTools.h"
#include "vtkSecondOrderPreIntegrationTable.h"
#include "vtkVolumeTransferFunctionSampler.h"

#include <algorithm>
#include <cmath>
#include <vector>

vtkStandardNewMacro(vtkPreIntegrationRayCaster);
vtkCxxSetObjectMacro(vtkPreIntegrationRayCaster, Table, vtkPreIntegrationTable);

//------------------------------------------------------------------------------
vtkPreIntegrationRayCaster::vtkPreIntegrationRayCaster() = default;

//------------------------------------------------------------------------------
vtkPreIntegrationRayCaster::~vtkPreIntegrationRayCaster()
{
  this->SetTable(nullptr);
}

//------------------------------------------------------------------------------
vtkMTimeType vtkPreIntegrationRayCaster::GetMTime()
{
  vtkMTimeType time = this->Superclass::GetMTime();
  if (this->Table)
  {
    time = std::max(time, this->Table->GetMTime());
  }
  return time;
}

//------------------------------------------------------------------------------
int vtkPreIntegrationRayCaster::RequestData(vtkInformation*,
  vtkInformationVector** inputVector,
  vtkInformationVector* outputVector)
{
  vtkImageData* input = vtkImageData::GetData(inputVector[0]);
  vtkFloatArray* rgba = this->InitializeOutput(vtkImageData::GetData(outputVector));
  int dims[3];
  vtkDataArray* scalars = rgba ? this->PrepareFrame(input, inputVector, dims) : nullptr;
  if (!scalars)
  {
    return 1;
  }
  if (!this->CheckSampleDistance(input, this->SampleDistance, this->MaximumSamplesPerRay))
  {
    return 1;
  }
  if (!this->Table)
  {
    vtkErrorMacro("No pre-integration table was given.");
    return 1;
  }
  double range[2];
  scalars->GetFiniteRange(range, 0); // not empty and finite: checked by PrepareFrame
  if (!(range[1] > range[0]))
  {
    range[1] = range[0] + std::max(1.0, std::abs(range[0]) * 1e-6); // the mapper's
  }
  auto* chordTable = vtkSecondOrderPreIntegrationTable::SafeDownCast(this->Table);
  const int order = this->Integration != 0 ? this->Integration : chordTable ? 2 : 1;
  if (order == 1 && chordTable && chordTable->GetDeviationSize() != 1)
  {
    vtkErrorMacro("First-order compositing needs a table of deviation 0 (DeviationSize 1).");
    return 1;
  }
  if (order == 2 && !chordTable)
  {
    vtkErrorMacro("Second-order compositing needs a vtkSecondOrderPreIntegrationTable.");
    return 1;
  }
  this->Table->SetVolumeProperty(this->VolumeProperty);
  this->Table->SetSegmentLength((order == 2 ? 2.0 : 1.0) * this->SampleDistance);
  this->Table->SetScalarRange(range);
  this->Table->ComputeEntriesOn();
  if (!this->Table->Update())
  {
    return 1;
  }

  std::vector<double> values(static_cast<size_t>(scalars->GetNumberOfTuples()));
  for (vtkIdType i = 0; i < scalars->GetNumberOfTuples(); ++i)
  {
    values[i] = scalars->GetComponent(i, 0);
  }
  vtkPreIntegrationRayMarch::Grid grid;
  grid.Values = values.data();
  std::copy(dims, dims + 3, grid.Dims);
  vtkPreIntegrationRayMarch::TablePieces table;
  table.Table = vtkPreIntegrationRayMarch::TableView::Of(this->Table);
  vtkPreIntegrationRayMarch::ExactPieces exact;
  exact.Sampler = this->Sampler;
  exact.DataRange = range[1] - range[0];

  // World -> 0-based continuous grid index; t stays the world distance along the ray.
  vtkNew<vtkMatrix4x4> toIndex;
  toIndex->DeepCopy(input->GetPhysicalToIndexMatrix());
  const int* extent = input->GetExtent();
  for (int r = 0; r < 3; ++r)
  {
    toIndex->SetElement(r, 3, toIndex->GetElement(r, 3) - extent[2 * r]);
  }
  const int* size = this->RayModel->GetImageSize();
  const int width = std::max(size[0], 1), height = std::max(size[1], 1);
  float* out = rgba->GetPointer(0);
  const vtkCameraRayModel* rays = this->RayModel;
  vtkSMPTools::For(0,
    static_cast<vtkIdType>(width) * height,
    [&](vtkIdType begin, vtkIdType end)
    {
      for (vtkIdType p = begin; p < end; ++p)
      {
        double origin[3], direction[3], o[4], v[4];
        rays->GetPixelRay(
          static_cast<int>(p % width), static_cast<int>(p / width), origin, direction);
        const double point[4] = { origin[0], origin[1], origin[2], 1.0 };
        const double vector[4] = { direction[0], direction[1], direction[2], 0.0 };
        toIndex->MultiplyPoint(point, o);
        toIndex->MultiplyPoint(vector, v);
        double result[4] = { 0, 0, 0, 0 }, t0, t1;
        if (grid.Clip(o, v, t0, t1))
        {
          auto cast = [&](const auto& pieces)
          {
            vtkPreIntegrationRayMarch::Cast(grid,
              pieces,
              order,
              this->SampleDistance,
              this->OpacityThreshold,
              o,
              v,
              t0,
              t1,
              result);
          };
          if (this->ExactSegments)
          {
            cast(exact);
          }
          else
          {
            cast(table);
          }
        }
        for (int c = 0; c < 4; ++c)
        {
          out[4 * p + c] = static_cast<float>(result[c]);
        }
      }
    });
  this->WarnIfTransparent(rgba);
  return 1;
}

//------------------------------------------------------------------------------
void vtkPreIntegrationRayCaster::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "SampleDistance: " << this->SampleDistance << "\n";
  os << indent << "Table: " << this->Table << "\n";
  os << indent << "ExactSegments: " << this->ExactSegments << "\n";
  os << indent << "Integration: " << this->Integration << "\n";
  os << indent << "OpacityThreshold: " << this->OpacityThreshold << "\n";
  os << indent << "MaximumSamplesPerRay: " << this->MaximumSamplesPerRay << "\n";
}
