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
#include "vtkPointData.h"
#include "vtkPreIntegrationRayMarch.h"
#include "vtkPreIntegrationTable.h"
#include "vtkSMPTools.h"
#include "vtkSecondOrderPreIntegrationTable.h"
#include "vtkVolumeShadingModel.h"
#include "vtkVolumeTransferFunctionSampler.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

vtkStandardNewMacro(vtkPreIntegrationRayCaster);
vtkCxxSetObjectMacro(vtkPreIntegrationRayCaster, Table, vtkPreIntegrationTable);
vtkCxxSetObjectMacro(vtkPreIntegrationRayCaster, ShadingModel, vtkVolumeShadingModel);

//------------------------------------------------------------------------------
vtkPreIntegrationRayCaster::vtkPreIntegrationRayCaster() = default;

//------------------------------------------------------------------------------
vtkPreIntegrationRayCaster::~vtkPreIntegrationRayCaster()
{
  this->SetTable(nullptr);
  this->SetShadingModel(nullptr);
  this->SetNormalArrayName(nullptr);
}

//------------------------------------------------------------------------------
vtkMTimeType vtkPreIntegrationRayCaster::GetMTime()
{
  vtkMTimeType time = this->Superclass::GetMTime();
  if (this->Table)
  {
    time = std::max(time, this->Table->GetMTime());
  }
  if (this->ShadingModel)
  {
    time = std::max(time, this->ShadingModel->GetMTime());
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
  vtkVolumeShadingModel* model = this->ShadingModel;
  // The moment layers the table path reads (per half slab for second order), as
  // vtkPreIntegrationVolumeMapper asks them.
  const int needed = !model                                                 ? 0
    : model->GetGradientInterpolation() != vtkVolumeShadingModel::NONLINEAR ? 2
                                                                            : 4;
  if (model && !this->ExactSegments && order == 1)
  {
    const int moments = chordTable ? chordTable->GetMoments() : 0;
    if (!chordTable || moments < needed)
    {
      vtkErrorMacro("Shaded compositing from the table needs the moment layers of a first-order "
                    "vtkSecondOrderPreIntegrationTable (DeviationSize 1, Moments at least "
        << needed << " for this gradient interpolation); the table has "
        << (chordTable ? "Moments " + std::to_string(moments)
                       : std::string("none (a vtkFirstOrderPreIntegrationTable)"))
        << ". The image is empty.");
      return 1;
    }
  }
  if (model && !this->ExactSegments && order == 2)
  {
    const int moments = chordTable->GetSlabMoments();
    if (moments < needed || chordTable->GetDeviationSize() < 2)
    {
      vtkErrorMacro("Shaded second-order compositing from the table needs the slab moment "
                    "layers of a vtkSecondOrderPreIntegrationTable (DeviationSize above 1, "
                    "SlabMoments at least "
        << needed << " for this gradient interpolation); the table has DeviationSize "
        << chordTable->GetDeviationSize() << " and SlabMoments " << moments
        << ". The image is empty.");
      return 1;
    }
  }
  std::vector<double> normals;
  if (model && this->NormalArrayName && *this->NormalArrayName)
  {
    if (!this->ReadNormalArray(input, this->NormalArrayName, scalars->GetNumberOfTuples(), normals))
    {
      return 1;
    }
  }
  this->Table->SetVolumeProperty(this->VolumeProperty);
  this->Table->SetSegmentLength((order == 2 ? 2.0 : 1.0) * this->SampleDistance);
  this->Table->SetScalarRange(range);
  this->Table->ComputeEntriesOn();
  if (!this->Table->Update())
  {
    return 1;
  }

  vtkPreIntegrationRayMarch::Grid grid;
  if (!grid.Values.SetArray(scalars))
  {
    vtkErrorMacro("Not enough memory for a double copy of the volume; the image is empty.");
    return 1;
  }
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
    for (int a = 0; a < 3; ++a)
    {
      grid.WorldToIndex[3 * r + a] = toIndex->GetElement(r, a);
    }
  }
  grid.Normals = normals.empty() ? nullptr : normals.data();
  grid.CellStepGradients = this->GradientOperator == GPU_GRADIENTS;

  // Shaded pieces (their view is set per ray).
  vtkPreIntegrationRayMarch::ShadedTablePieces shadedTable;
  vtkPreIntegrationRayMarch::ShadedExactPieces shadedExact;
  if (model)
  {
    shadedTable.Table = table.Table;
    shadedTable.Layers = chordTable ? chordTable->GetNumberOfLayers() : 1;
    shadedTable.LayerStride =
      static_cast<vtkIdType>(table.Table.Size[0]) * table.Table.Size[1] * table.Table.Size[2];
    shadedTable.Model = model;
    shadedExact.Sampler = this->Sampler;
    shadedExact.Model = model;
    shadedExact.Substeps = this->ShadedSubsteps;
    shadedExact.DataRange = exact.DataRange;
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
          if (model)
          {
            // Towards the eye: the pixel ray reversed (unit, world coordinates).
            const double view[3] = { -direction[0], -direction[1], -direction[2] };
            if (this->ExactSegments)
            {
              auto pieces = shadedExact;
              std::copy(view, view + 3, pieces.View);
              cast(pieces);
            }
            else
            {
              auto pieces = shadedTable;
              std::copy(view, view + 3, pieces.View);
              cast(pieces);
            }
          }
          else if (this->ExactSegments)
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
  os << indent << "ShadingModel: " << this->ShadingModel << "\n";
  os << indent << "NormalArrayName: " << (this->NormalArrayName ? this->NormalArrayName : "(none)")
     << "\n";
  os << indent << "ShadedSubsteps: " << this->ShadedSubsteps << "\n";
  os << indent << "GradientOperator: "
     << (this->GradientOperator == GPU_GRADIENTS ? "GPU_GRADIENTS" : "POINT_GRADIENTS") << "\n";
}
