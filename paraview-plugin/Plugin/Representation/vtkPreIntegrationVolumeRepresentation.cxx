// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
#include "vtkPreIntegrationVolumeRepresentation.h"

#include "vtkImageData.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPreIntegrationVolumeMapper.h"
#include "vtkRectilinearGrid.h"

#include <cmath>

vtkStandardNewMacro(vtkPreIntegrationVolumeRepresentation);

//------------------------------------------------------------------------------
vtkPreIntegrationVolumeRepresentation::vtkPreIntegrationVolumeRepresentation()
{
  // Replaces the superclass's vtkMultiBlockVolumeMapper before anything is connected to it:
  // the superclass connects and configures whatever VolumeMapper holds when it renders.
  vtkNew<vtkPreIntegrationVolumeMapper> mapper;
  this->Integration = mapper->GetIntegration();
  this->TableSize = mapper->GetTableSize();
  this->TablePrecision = mapper->GetTablePrecision();
  this->Iterations = mapper->GetIterations();
  this->TablePrefilter = mapper->GetTablePrefilter();
  this->VolumeMapper = mapper;
}

//------------------------------------------------------------------------------
vtkPreIntegrationVolumeRepresentation::~vtkPreIntegrationVolumeRepresentation() = default;

//------------------------------------------------------------------------------
double vtkPreIntegrationVolumeRepresentation::ComputeAutomaticSampleDistance()
{
  // Grid steps along each axis: an image's spacing, a rectilinear grid's mean step (the mapper
  // draws those with VTK's stock compositing, which also needs a sensible step).
  double steps[3] = { 0.0, 0.0, 0.0 };
  vtkDataSet* input = this->VolumeMapper->GetInput();
  if (auto* image = vtkImageData::SafeDownCast(input))
  {
    image->GetSpacing(steps);
  }
  else if (auto* grid = vtkRectilinearGrid::SafeDownCast(input))
  {
    int dims[3];
    double bounds[6];
    grid->GetDimensions(dims);
    grid->GetBounds(bounds);
    for (int a = 0; a < 3; ++a)
    {
      steps[a] = dims[a] > 1 ? (bounds[2 * a + 1] - bounds[2 * a]) / (dims[a] - 1) : 0.0;
    }
  }
  double smallest = 0.0;
  for (double step : steps)
  {
    // A zero step (a flat axis) is no step at all: skip it.
    step = std::abs(step);
    if (step > 0.0 && (smallest == 0.0 || step < smallest))
    {
      smallest = step;
    }
  }
  return 0.5 * smallest;
}

//------------------------------------------------------------------------------
void vtkPreIntegrationVolumeRepresentation::UpdateMapperParameters()
{
  // The superclass selects the array, the scalar mode and the cropping planes and sets the
  // mapper on the actor; where it needs vtkSmartVolumeMapper or vtkMultiBlockVolumeMapper it
  // down-casts, so for this mapper those settings are skipped rather than misapplied.
  this->Superclass::UpdateMapperParameters();

  auto* mapper = vtkPreIntegrationVolumeMapper::SafeDownCast(this->VolumeMapper);
  if (!mapper)
  {
    return;
  }
  mapper->SetIntegration(this->Integration);
  mapper->SetTableSize(this->TableSize);
  mapper->SetTablePrecision(this->TablePrecision);
  mapper->SetIterations(this->Iterations);
  mapper->SetTablePrefilter(this->TablePrefilter);

  double distance = this->SampleDistance;
  if (!(distance > 0.0))
  {
    distance = this->ComputeAutomaticSampleDistance();
  }
  // Without input (a process that only draws the outline) the mapper draws nothing, so its
  // sample distance is left alone.
  if (distance > 0.0 && std::isfinite(distance))
  {
    mapper->SetSampleDistance(distance);
    this->EffectiveSampleDistance = distance;
  }
}

//------------------------------------------------------------------------------
void vtkPreIntegrationVolumeRepresentation::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Integration: " << this->Integration << "\n";
  os << indent << "SampleDistance: " << this->SampleDistance << "\n";
  os << indent << "TableSize: " << this->TableSize << "\n";
  os << indent << "TablePrecision: " << this->TablePrecision << "\n";
  os << indent << "Iterations: " << this->Iterations << "\n";
  os << indent << "TablePrefilter: " << (this->TablePrefilter ? "On" : "Off") << "\n";
  os << indent << "EffectiveSampleDistance: " << this->EffectiveSampleDistance << "\n";
}
