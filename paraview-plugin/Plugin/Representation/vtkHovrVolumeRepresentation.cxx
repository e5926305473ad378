// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
#include "vtkHovrVolumeRepresentation.h"

#include "vtkAdaptiveRayVolumeMapper.h"
#include "vtkAdaptiveSamplingOracle.h"
#include "vtkAdaptiveSamplingVolumeMapper.h"
#include "vtkAlgorithm.h"
#include "vtkAlgorithmOutput.h"
#include "vtkAnalyticVolumeMapper.h"
#include "vtkCamera.h"
#include "vtkCommunicator.h"
#include "vtkDataArray.h"
#include "vtkDataSet.h"
#include "vtkExtensibleGPUVolumeRayCastMapper.h"
#include "vtkExtractVOI.h"
#include "vtkImageData.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkMultiProcessController.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkObjectOrderRayCaster.h"
#include "vtkObjectOrderVolumeMapper.h"
#include "vtkOpenGLGPUVolumeRayCastMapper.h"
#include "vtkPVRenderView.h"
#include "vtkPVView.h"
#include "vtkPointData.h"
#include "vtkPreIntegrationTableRefiner.h"
#include "vtkPreIntegrationTableSizing.h"
#include "vtkPreIntegrationVolumeMapper.h"
#include "vtkProcessModule.h"
#include "vtkRectilinearGrid.h"
#include "vtkSecondOrderPreIntegrationTable.h"
#include "vtkStreamingDemandDrivenPipeline.h"
#include "vtkUnsignedCharArray.h"
#include "vtkVolumeProperty.h"
#include "vtkWholeVolumeAssembler.h"

#include <algorithm>
#include <cmath>
#include <cstring>

vtkStandardNewMacro(vtkHovrVolumeRepresentation);

namespace
{
// Whether an Integration value is a projection (MIP or MinIP), which composites by extremum.
bool IsProjection(int integration)
{
  return integration == vtkHovrVolumeRepresentation::ANALYTIC_MIP ||
    integration == vtkHovrVolumeRepresentation::ANALYTIC_MINIP;
}

// Whether an Integration value pre-integrates (measures its table sizes).
bool IsPreIntegration(int integration)
{
  return integration == vtkPreIntegrationVolumeMapper::FIRST_ORDER ||
    integration == vtkPreIntegrationVolumeMapper::SECOND_ORDER;
}

// Which ghost points a method reads on several ranks: none (its piece is cropped), those of
// the segments and slabs of pre-integration and object order, those of the adaptive ray's
// walk and oracle, or those of the slice pyramid's walks and oracle.
enum GhostKinds
{
  NO_GHOSTS,
  SEGMENT_GHOSTS,
  ADAPTIVE_RAY_GHOSTS,
  PYRAMID_GHOSTS
};
int GhostKind(int integration)
{
  using R = vtkHovrVolumeRepresentation;
  return IsPreIntegration(integration) || integration == R::OBJECT_ORDER ? SEGMENT_GHOSTS
    : integration == R::ADAPTIVE_RAY                                     ? ADAPTIVE_RAY_GHOSTS
    : integration == R::ADAPTIVE_3D                                      ? PYRAMID_GHOSTS
                                                                         : NO_GHOSTS;
}
}

//------------------------------------------------------------------------------
vtkHovrVolumeRepresentation::vtkHovrVolumeRepresentation()
{
  // Replaces the superclass's vtkMultiBlockVolumeMapper before anything is connected to it:
  // the superclass connects and configures whatever VolumeMapper holds when it renders.
  vtkNew<vtkPreIntegrationVolumeMapper> mapper;
  this->Integration = mapper->GetIntegration();
  this->TableSize = mapper->GetTableSize();
  this->TableMemoryLimit = mapper->GetTableMemoryLimit();
  this->TablePrecision = mapper->GetTablePrecision();
  this->Iterations = mapper->GetIterations();
  this->TablePrefilter = mapper->GetTablePrefilter();
  this->VolumePrecision = mapper->GetVolumePrecision();
  this->GradientInterpolation = mapper->GetGradientInterpolation();
  this->Gooch = mapper->GetGooch();
  this->SetNormalArrayName(mapper->GetNormalArrayName());
  this->VolumeMapper = mapper;
  this->PreIntegrationMapper = mapper;
  this->Cropper = vtkSmartPointer<vtkExtractVOI>::New();
  this->AnalyticMapper = vtkSmartPointer<vtkAnalyticVolumeMapper>::New();
  auto cpuMapper = vtkSmartPointer<vtkObjectOrderVolumeMapper>::New();
  vtkObjectOrderRayCaster* caster = cpuMapper->GetCaster();
  this->ObjectOrderClassification = caster->GetClassification();
  this->ObjectOrderShading = caster->GetShadingMode();
  this->InterleavedSampling = caster->GetInterleavedSampling();
  this->HiddenVolumeRemoval = caster->GetHiddenVolumeRemoval();
  this->OpacityThreshold = caster->GetOpacityThreshold();
  this->LeafSize = caster->GetLeafSize();
  this->InstructionSet = caster->GetInstructionSet();
  this->ObjectOrderMapper = cpuMapper;
  auto rayMapper = vtkSmartPointer<vtkAdaptiveRayVolumeMapper>::New();
  this->MaximumLevel = rayMapper->GetMaximumLevel();
  this->AdaptiveRayMapper = rayMapper;
  this->AdaptivePyramidMapper = vtkSmartPointer<vtkAdaptiveSamplingVolumeMapper>::New();
  this->Oracle = vtkSmartPointer<vtkAdaptiveSamplingOracle>::New();
  this->OracleMode = this->Oracle->GetMode();
  this->OracleEpsilon = this->Oracle->GetEpsilon();
  // The oracle reads the opacity map the volume is drawn with: an edit of the map makes its
  // next update recompute the distances.
  this->Oracle->SetScalarOpacity(this->Property->GetScalarOpacity());
}

//------------------------------------------------------------------------------
vtkHovrVolumeRepresentation::~vtkHovrVolumeRepresentation()
{
  this->SetNormalArrayName(nullptr);
}

//------------------------------------------------------------------------------
double vtkHovrVolumeRepresentation::ComputeAutomaticSampleDistance()
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
void vtkHovrVolumeRepresentation::SetSampleDistance(double distance)
{
  if (distance != this->SampleDistance)
  {
    this->SampleDistance = distance;
    // On several ranks the ghost points asked for depend on it.
    this->MarkModified();
  }
}

//------------------------------------------------------------------------------
void vtkHovrVolumeRepresentation::SetMaximumLevel(int level)
{
  if (level != this->MaximumLevel)
  {
    this->MaximumLevel = level;
    // On several ranks the adaptive ray's ghost points depend on it.
    this->MarkModified();
  }
}

//------------------------------------------------------------------------------
int vtkHovrVolumeRepresentation::GhostLevels(double spacing)
{
  // Pre-integration and object order read a slab or a segment (two sample distances) past a
  // piece; the adaptive ray walks to the next slice of 2^l_max and its oracle sees as far again.
  const int kind = GhostKind(this->Integration);
  if (kind == NO_GHOSTS)
  {
    return 0;
  }
  // The slice pyramid's walk reaches 2^(l_max + 2) slice spacings (a pixel each, which the
  // view gives: see ProcessViewRequest).
  const int level = std::min(std::max(this->MaximumLevel, 0), 16);
  const bool pyramid = kind == PYRAMID_GHOSTS && this->PyramidSliceSpacing > 0.0;
  const double reach = kind == SEGMENT_GHOSTS ? 2.0
    : pyramid                                 ? std::ldexp(4.0, level)
                                              : std::ldexp(2.0, level);
  const double distance = pyramid ? this->PyramidSliceSpacing
    : this->SampleDistance > 0.0  ? this->SampleDistance
                                  : 0.5 * spacing;
  if (!(spacing > 0.0) || !std::isfinite(distance / spacing))
  {
    return static_cast<int>(reach) + 2;
  }
  return static_cast<int>(std::min(std::ceil(reach * distance / spacing - 1e-9), 1e3)) + 2;
}

//------------------------------------------------------------------------------
int vtkHovrVolumeRepresentation::RequestUpdateExtent(vtkInformation* request,
  vtkInformationVector** inputVector,
  vtkInformationVector* outputVector)
{
  const int result = this->Superclass::RequestUpdateExtent(request, inputVector, outputVector);
  auto* controller = vtkMultiProcessController::GetGlobalController();
  if (!controller || controller->GetNumberOfProcesses() < 2)
  {
    return result;
  }
  for (int k = 0; k < inputVector[0]->GetNumberOfInformationObjects(); ++k)
  {
    vtkInformation* info = inputVector[0]->GetInformationObject(k);
    if (!vtkImageData::SafeDownCast(info->Get(vtkDataObject::DATA_OBJECT())))
    {
      continue; // ghost points are cropped off image data only
    }
    double spacing[3] = { 1.0, 1.0, 1.0 };
    if (info->Has(vtkDataObject::SPACING()))
    {
      info->Get(vtkDataObject::SPACING(), spacing);
    }
    const double smallest =
      std::min(std::abs(spacing[0]), std::min(std::abs(spacing[1]), std::abs(spacing[2])));
    const int levels = this->GhostLevels(smallest);
    if (levels > 0)
    {
      info->Set(vtkStreamingDemandDrivenPipeline::UPDATE_NUMBER_OF_GHOST_LEVELS(), levels);
    }
  }
  return result;
}

//------------------------------------------------------------------------------
int vtkHovrVolumeRepresentation::RequestData(vtkInformation* request,
  vtkInformationVector** inputVector,
  vtkInformationVector* outputVector)
{
  const int result = this->Superclass::RequestData(request, inputVector, outputVector);
  // The superclass crops the ghost points off into Cache (whose bounds order the pieces):
  // its extent is the piece's own, and the piece with its ghost points is delivered instead.
  std::fill(this->OwnedExtent, this->OwnedExtent + 6, 0);
  this->OwnedExtent[1] = this->OwnedExtent[3] = this->OwnedExtent[5] = -1;
  this->GhostWidth = 0;
  auto* ghosted = vtkImageData::GetData(inputVector[0], 0);
  auto* cropped = vtkImageData::SafeDownCast(this->Cache);
  if (ghosted && cropped && ghosted->HasAnyGhostCells() && cropped->GetNumberOfPoints() > 0)
  {
    cropped->GetExtent(this->OwnedExtent);
    const int* all = ghosted->GetExtent();
    int width = VTK_INT_MAX;
    for (int k = 0; k < 6; ++k)
    {
      // A face with ghost points past it (one of the whole volume's faces has none).
      const int past = k % 2 == 0 ? this->OwnedExtent[k] - all[k] : all[k] - this->OwnedExtent[k];
      width = past > 0 ? std::min(width, past) : width;
    }
    this->GhostWidth = width == VTK_INT_MAX ? 0 : width;
    auto piece = vtkSmartPointer<vtkImageData>::New();
    piece->ShallowCopy(ghosted);
    this->Cache = piece;
  }
  // Every rank takes part in the reduction, whatever its piece, so that none waits for a rank
  // that left early. Minima of: the range's low, -high, and the bounds' lows and -highs.
  double local[8];
  std::fill(local, local + 8, VTK_DOUBLE_MAX);
  vtkDataObject* input = inputVector[0]->GetNumberOfInformationObjects() > 0
    ? vtkDataObject::GetData(inputVector[0], 0)
    : nullptr;
  vtkDataArray* scalars = input ? this->GetInputArrayToProcess(0, input) : nullptr;
  if (scalars && scalars->GetNumberOfTuples() > 0)
  {
    double range[2];
    scalars->GetFiniteRange(range, 0);
    if (range[0] <= range[1])
    {
      local[0] = range[0];
      local[1] = -range[1];
    }
  }
  auto* dataSet = vtkDataSet::SafeDownCast(input);
  if (dataSet && dataSet->GetNumberOfPoints() > 0)
  {
    double bounds[6];
    dataSet->GetBounds(bounds);
    for (int k = 0; k < 6; ++k)
    {
      local[2 + k] = k % 2 == 0 ? bounds[k] : -bounds[k];
    }
  }
  double whole[8];
  std::copy(local, local + 8, whole);
  auto* controller = vtkMultiProcessController::GetGlobalController();
  if (controller && controller->GetNumberOfProcesses() > 1)
  {
    controller->AllReduce(local, whole, 8, vtkCommunicator::MIN_OP);
  }
  const double range[2] = { whole[0], -whole[1] };
  const bool any = range[0] <= range[1];
  this->WholeScalarRange[0] = any ? range[0] : 1.0;
  this->WholeScalarRange[1] = any ? range[1] : 0.0;
  for (int k = 0; k < 6; ++k)
  {
    const double b = k % 2 == 0 ? whole[2 + k] : -whole[2 + k];
    this->WholeBounds[k] = whole[2] <= -whole[3] ? b : (k % 2 == 0 ? 1.0 : 0.0);
  }
  this->AssembleSizingVolume(inputVector[0]->GetNumberOfInformationObjects() > 0
      ? inputVector[0]->GetInformationObject(0)
      : nullptr,
    input,
    scalars);
  return result;
}

//------------------------------------------------------------------------------
void vtkHovrVolumeRepresentation::AssembleSizingVolume(vtkInformation* inInfo,
  vtkDataObject* input,
  vtkDataArray* scalars)
{
  auto* controller = vtkMultiProcessController::GetGlobalController();
  // (The Integration value is the same on every rank.)
  if (!controller || controller->GetNumberOfProcesses() < 2 || !IsPreIntegration(this->Integration))
  {
    this->SizingVolume = nullptr;
    this->SizingSource = nullptr;
    return;
  }
  // Every rank takes part in every reduction below, and decides from reduced values alone.
  auto* image = vtkImageData::SafeDownCast(input);
  bool point = false;
  for (int a = 0; image && scalars && a < image->GetPointData()->GetNumberOfArrays(); ++a)
  {
    point = point || image->GetPointData()->GetAbstractArray(a) == scalars;
  }
  point = point && scalars->GetNumberOfComponents() == 1 &&
    scalars->GetNumberOfTuples() == image->GetNumberOfPoints();
  int extent[6] = { 0, -1, 0, -1, 0, -1 };
  const bool known = inInfo && inInfo->Has(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT());
  if (known)
  {
    inInfo->Get(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT(), extent);
  }
  const bool needed = point &&
    (!this->SizingVolume || scalars != this->SizingSource ||
      scalars->GetMTime() != this->SizingSourceTime);
  // Minima of: minus the array's type, the whole extent's lows and minus its highs, and minus
  // whether this rank needs the whole volume again (its array changed).
  int local[8] = { VTK_INT_MAX,
    VTK_INT_MAX,
    VTK_INT_MAX,
    VTK_INT_MAX,
    VTK_INT_MAX,
    VTK_INT_MAX,
    VTK_INT_MAX,
    needed ? -1 : 0 };
  if (point)
  {
    local[0] = -scalars->GetDataType();
  }
  for (int k = 0; known && point && k < 6; ++k)
  {
    local[1 + k] = k % 2 == 0 ? extent[k] : -extent[k];
  }
  int reduced[8];
  controller->AllReduce(local, reduced, 8, vtkCommunicator::MIN_OP);
  if (reduced[0] == VTK_INT_MAX || reduced[1] == VTK_INT_MAX)
  {
    this->SizingVolume = nullptr; // no rank has a point array of one component
    this->SizingSource = nullptr;
    return;
  }
  if (reduced[7] == 0)
  {
    return; // no rank's data changed
  }
  const int type = -reduced[0];
  for (int k = 0; k < 6; ++k)
  {
    extent[k] = k % 2 == 0 ? reduced[1 + k] : -reduced[1 + k];
  }
  vtkNew<vtkWholeVolumeAssembler> assembler;
  const int size = vtkDataArray::GetDataTypeSize(type);
  const int stride = vtkWholeVolumeAssembler::ComputeStride(extent, size, 64.0 * 1024.0 * 1024.0);
  const bool prepared = assembler->Prepare(point ? image : nullptr,
    point && scalars->GetDataType() == type ? scalars : nullptr,
    type,
    extent,
    stride);
  int ready = prepared ? 1 : 0, everywhere = 0;
  controller->AllReduce(&ready, &everywhere, 1, vtkCommunicator::MIN_OP);
  this->SizingVolume = nullptr;
  this->SizingSource = nullptr;
  if (!everywhere)
  {
    vtkWarningMacro("The whole volume could not be put together on every rank (see the "
                    "errors): pre-integration measures its table sizes on each rank's piece, "
                    "and the ranks may draw different tables.");
    return;
  }
  vtkSmartPointer<vtkDataArray> values;
  values.TakeReference(assembler->GetValues()->NewInstance());
  vtkNew<vtkUnsignedCharArray> coverage;
  controller->AllReduce(assembler->GetValues(), values, vtkCommunicator::MAX_OP);
  controller->AllReduce(assembler->GetCoverage(), coverage, vtkCommunicator::MAX_OP);
  if (!point)
  {
    return; // a rank without data draws nothing
  }
  auto whole = vtkSmartPointer<vtkImageData>::New();
  if (assembler->Finish(values, coverage, image, scalars->GetName(), whole))
  {
    this->SizingVolume = whole;
    this->SizingSource = scalars;
    this->SizingSourceTime = scalars->GetMTime();
  }
}

//------------------------------------------------------------------------------
void vtkHovrVolumeRepresentation::UpdateMapperParameters()
{
  // The mapper the Integration value chooses, in place before the superclass connects the
  // input, selects the array, the scalar mode and the cropping planes and sets the mapper on
  // the actor; where it needs vtkSmartVolumeMapper or vtkMultiBlockVolumeMapper it
  // down-casts, so for these mappers those settings are skipped rather than misapplied.
  vtkVolumeMapper* chosen = this->Integration == ADAPTIVE_RAY ? this->AdaptiveRayMapper
    : this->Integration == ADAPTIVE_3D                        ? this->AdaptivePyramidMapper
    : this->Integration == OBJECT_ORDER                       ? this->ObjectOrderMapper
    : this->Integration >= ANALYTIC_ISOSURFACE                ? this->AnalyticMapper
                                                              : this->PreIntegrationMapper;
  // The data: what the render view connected to the current mapper, unless that is the
  // oracle's output (a second call without a render request in between).
  vtkAlgorithmOutput* data = this->VolumeMapper->GetInputConnection(0, 0);
  if (data && data == this->Cropper->GetOutputPort())
  {
    data = this->Cropper->GetInputConnection(0, 0);
  }
  if (data && data == this->Oracle->GetOutputPort())
  {
    data = this->Oracle->GetInputConnection(0, 0);
  }
  // The piece's ghost points (on several ranks) are read by pre-integration, object order and
  // the adaptive methods when they reach as far as those need; otherwise, and for the other
  // methods, they are cropped off (after the oracle, which is computed with them).
  const bool ghosts = this->OwnedExtent[0] <= this->OwnedExtent[1];
  bool readsGhosts = false;
  if (ghosts && GhostKind(this->Integration) != NO_GHOSTS)
  {
    double spacing[3] = { 1.0, 1.0, 1.0 };
    if (auto* piece = vtkImageData::SafeDownCast(this->Cache))
    {
      piece->GetSpacing(spacing);
    }
    const double smallest =
      std::min(std::abs(spacing[0]), std::min(std::abs(spacing[1]), std::abs(spacing[2])));
    // (The slice pyramid's need depends on the camera: its mapper checks it every frame.)
    readsGhosts = GhostKind(this->Integration) == PYRAMID_GHOSTS
      ? this->GhostWidth > 0
      : this->GhostWidth >= this->GhostLevels(smallest);
  }
  const bool adaptive = chosen == this->AdaptiveRayMapper || chosen == this->AdaptivePyramidMapper;
  if (adaptive && data)
  {
    this->Oracle->SetInputConnection(data);
    data = this->Oracle->GetOutputPort();
  }
  if (ghosts && !readsGhosts && data)
  {
    auto* cropper = vtkExtractVOI::SafeDownCast(this->Cropper);
    cropper->SetVOI(this->OwnedExtent);
    cropper->SetInputConnection(data);
    data = cropper->GetOutputPort();
  }
  chosen->SetInputConnection(data);
  if (auto* extensible = vtkExtensibleGPUVolumeRayCastMapper::SafeDownCast(chosen))
  {
    const int none[6] = { 0, -1, 0, -1, 0, -1 };
    extensible->SetOwnedExtent(readsGhosts ? this->OwnedExtent : none);
  }
  else if (auto* objectOrder = vtkObjectOrderVolumeMapper::SafeDownCast(chosen))
  {
    const int none[6] = { 0, -1, 0, -1, 0, -1 };
    objectOrder->GetCaster()->SetOwnedExtent(readsGhosts ? this->OwnedExtent : none);
  }
  this->VolumeMapper = chosen;
  // On several ranks a projection's pixels are composited by depth (see ProcessViewRequest),
  // unless another representation makes the view composite front to back ("over"), which is
  // not the maximum or minimum over the pieces: say so rather than draw a silently different
  // image.
  auto* controller = vtkMultiProcessController::GetGlobalController();
  const int ranks = controller ? controller->GetNumberOfProcesses() : 1;
  const bool overProjection = this->DistributedProjection() && this->OrderedCompositingInView;
  if (overProjection && !this->WarnedDistributedProjection && controller->GetLocalProcessId() == 0)
  {
    vtkWarningMacro(<< (this->Integration == ANALYTIC_MIP ? "Analytic MIP" : "Analytic MinIP")
                    << " on " << ranks
                    << " ranks with another representation that needs ordered compositing: "
                       "ParaView composites the pieces' images front to back, not by maximum "
                       "or minimum, so where pieces overlap on screen the image is not the "
                       "projection of the whole volume. Hide the other representations, or "
                       "render on one rank, for an exact projection.");
  }
  this->WarnedDistributedProjection = overProjection;
  // Every rank's tables span the whole volume's range (empty: each its own).
  if (auto* extensible = vtkExtensibleGPUVolumeRayCastMapper::SafeDownCast(this->VolumeMapper))
  {
    extensible->SetScalarRange(this->WholeScalarRange);
    extensible->SetWholeBounds(this->WholeBounds);
  }
  else if (auto* objectOrder = vtkObjectOrderVolumeMapper::SafeDownCast(this->VolumeMapper))
  {
    objectOrder->GetCaster()->SetScalarRange(this->WholeScalarRange);
    objectOrder->GetCaster()->SetWholeBounds(this->WholeBounds);
  }
  this->VolumeMapper->SetCropping(this->Cropping != 0);
  this->VolumeMapper->SetBlendMode(this->BlendMode);
  this->Superclass::UpdateMapperParameters();
  // A batch process's frames are its results: they wait for their measured tables and oracle.
  vtkProcessModule* module = vtkProcessModule::GetProcessModule();
  const bool batch = module && module->GetProcessType() == vtkProcessModule::PROCESS_BATCH;

  if (auto* mapper = vtkPreIntegrationVolumeMapper::SafeDownCast(this->VolumeMapper))
  {
    mapper->SetIntegration(this->Integration);
    mapper->SetTableSize(this->TableSize);
    mapper->SetTableMemoryLimit(this->TableMemoryLimit);
    mapper->SetTablePrecision(this->TablePrecision);
    mapper->SetIterations(this->Iterations);
    mapper->SetTablePrefilter(this->TablePrefilter);
    mapper->SetVolumePrecision(this->VolumePrecision);
    mapper->SetGradientInterpolation(this->GradientInterpolation);
    mapper->SetGooch(this->Gooch);
    // The GUI's array list offers "None" for no array; the mapper takes nullptr for that.
    const char* normals = this->NormalArrayName;
    if (normals && (!*normals || std::strcmp(normals, "None") == 0))
    {
      normals = nullptr;
    }
    mapper->SetNormalArrayName(normals);
    mapper->SetRefineInBackground(this->RefineInBackground && !batch);
    mapper->SetSizingVolume(this->SizingVolume);
  }
  else if (auto* objectOrder = vtkObjectOrderVolumeMapper::SafeDownCast(this->VolumeMapper))
  {
    vtkObjectOrderRayCaster* caster = objectOrder->GetCaster();
    caster->SetClassification(this->ObjectOrderClassification);
    caster->SetShadingMode(this->ObjectOrderShading);
    caster->SetInterleavedSampling(this->InterleavedSampling);
    caster->SetHiddenVolumeRemoval(this->HiddenVolumeRemoval);
    caster->SetOpacityThreshold(this->OpacityThreshold);
    caster->SetLeafSize(this->LeafSize);
    caster->SetInstructionSet(this->InstructionSet);
  }
  else if (adaptive)
  {
    // The oracle reads the array the superclass selected for colouring.
    vtkInformation* arrayInfo = this->GetInputArrayInformation(0);
    const char* arrayName = arrayInfo && arrayInfo->Has(vtkDataObject::FIELD_NAME())
      ? arrayInfo->Get(vtkDataObject::FIELD_NAME())
      : nullptr;
    if (arrayName)
    {
      this->Oracle->SetInputArrayToProcess(
        0, 0, 0, vtkDataObject::FIELD_ASSOCIATION_POINTS, arrayName);
    }
    this->Oracle->SetMode(this->OracleMode);
    this->Oracle->SetEpsilon(this->OracleEpsilon);
    this->Oracle->SetRefineInBackground(this->RefineInBackground && !batch);
    // Distances capped at the data's diagonal, not at the filter's automatic 8 voxels: the
    // mappers clamp them to 2^l_max steps themselves, which can be more than 8 voxels (l_max
    // 4, or the pyramid's pixel-sized steps when zoomed out). The transform costs the same.
    vtkAlgorithmOutput* input = this->Oracle->GetInputConnection(0, 0);
    auto* data = input
      ? vtkDataSet::SafeDownCast(input->GetProducer()->GetOutputDataObject(input->GetIndex()))
      : nullptr;
    if (data && data->GetNumberOfPoints() > 0)
    {
      const double diagonal = data->GetLength();
      if (diagonal > 0.0 && std::isfinite(diagonal))
      {
        this->Oracle->AutomaticMaximumDistanceOff();
        this->Oracle->SetMaximumDistance(diagonal);
      }
    }
    if (this->Oracle->GetScalarOpacity() != this->Property->GetScalarOpacity())
    {
      this->Oracle->SetScalarOpacity(this->Property->GetScalarOpacity());
    }
    // MIN is d = 1 everywhere: the mappers know it without an oracle volume.
    const bool minimum = this->OracleMode == vtkAdaptiveSamplingOracle::MIN;
    if (auto* ray = vtkAdaptiveRayVolumeMapper::SafeDownCast(this->VolumeMapper))
    {
      ray->SetMaximumLevel(this->MaximumLevel);
      ray->SetOracleMode(minimum ? vtkAdaptiveRayVolumeMapper::ORACLE_MINIMUM
                                 : vtkAdaptiveRayVolumeMapper::ORACLE_ARRAY);
      ray->SetOracleArrayName(this->Oracle->GetOutputArrayName());
    }
    else if (auto* pyramid = vtkAdaptiveSamplingVolumeMapper::SafeDownCast(this->VolumeMapper))
    {
      pyramid->SetMaximumLevel(this->MaximumLevel);
      pyramid->SetOracleMode(minimum ? vtkAdaptiveSamplingVolumeMapper::ORACLE_MINIMUM
                                     : vtkAdaptiveSamplingVolumeMapper::ORACLE_ARRAY);
      pyramid->SetOracleArrayName(this->Oracle->GetOutputArrayName());
    }
  }
  else if (auto* analyticMapper = vtkAnalyticVolumeMapper::SafeDownCast(this->VolumeMapper))
  {
    analyticMapper->SetAutoAdjustSampleDistances(0);
    analyticMapper->SetExtremumDepth(this->DistributedProjection());
    analyticMapper->SetBlendMode(this->Integration == ANALYTIC_ISOSURFACE
        ? vtkVolumeMapper::ISOSURFACE_BLEND
        : (this->Integration == ANALYTIC_MIP ? vtkVolumeMapper::MAXIMUM_INTENSITY_BLEND
                                             : vtkVolumeMapper::MINIMUM_INTENSITY_BLEND));
  }

  double distance = this->SampleDistance;
  if (!(distance > 0.0))
  {
    distance = this->ComputeAutomaticSampleDistance();
  }
  // Without input (a process that only draws the outline) the mapper draws nothing, so its
  // sample distance is left alone.
  auto* gpuMapper = vtkOpenGLGPUVolumeRayCastMapper::SafeDownCast(this->VolumeMapper);
  auto* cpuMapper = vtkObjectOrderVolumeMapper::SafeDownCast(this->VolumeMapper);
  if ((gpuMapper || cpuMapper) && distance > 0.0 && std::isfinite(distance))
  {
    if (gpuMapper)
    {
      gpuMapper->SetSampleDistance(distance);
    }
    else
    {
      cpuMapper->SetSampleDistance(distance);
    }
    this->EffectiveSampleDistance = distance;
  }
}

//------------------------------------------------------------------------------
void vtkHovrVolumeRepresentation::SetIntegration(int integration)
{
  if (integration == this->Integration)
  {
    return;
  }
  const bool changes = IsProjection(integration) != IsProjection(this->Integration) ||
    IsPreIntegration(integration) != IsPreIntegration(this->Integration) ||
    GhostKind(integration) != GhostKind(this->Integration);
  this->Integration = integration;
  this->Modified();
  if (changes)
  {
    // The view asks its representations again whether it composites in order, and the data
    // update puts the sizing volume together (or drops it) and asks for the ghost points the
    // method reads. Every process marks it (a client and its server alike), so that they
    // update together.
    this->MarkModified();
  }
}

//------------------------------------------------------------------------------
bool vtkHovrVolumeRepresentation::DistributedProjection()
{
  auto* controller = vtkMultiProcessController::GetGlobalController();
  return controller && controller->GetNumberOfProcesses() > 1 && IsProjection(this->Integration);
}

//------------------------------------------------------------------------------
int vtkHovrVolumeRepresentation::ProcessViewRequest(vtkInformationRequestKey* request_type,
  vtkInformation* inInfo,
  vtkInformation* outInfo)
{
  auto* view = vtkPVRenderView::SafeDownCast(inInfo->Get(vtkPVView::VIEW()));
  if (request_type == vtkPVView::REQUEST_RENDER())
  {
    // Before the superclass sets the mapper up: whether this frame composites in order (the
    // view decided at its last update).
    this->OrderedCompositingInView = view && view->GetUseOrderedCompositing();
  }
  if (view && view->GetActiveCamera())
  {
    // The slice pyramid's slice spacing, one pixel: for this camera, or for the camera that
    // shows the whole volume if that is larger (zoomed in, fewer ghost points would do), so
    // that the ghost points asked for at the next data update serve both.
    const int* size = view->GetSize();
    const double* b = this->WholeBounds;
    if (size && size[1] > 0)
    {
      double delta = 2.0 * view->GetActiveCamera()->GetParallelScale() / size[1];
      if (b[0] <= b[1] && b[2] <= b[3] && b[4] <= b[5])
      {
        const double diagonal = std::sqrt((b[1] - b[0]) * (b[1] - b[0]) +
          (b[3] - b[2]) * (b[3] - b[2]) + (b[5] - b[4]) * (b[5] - b[4]));
        delta = std::max(delta, diagonal / size[1]);
      }
      this->PyramidSliceSpacing = std::isfinite(delta) && delta > 0.0 ? delta : 0.0;
    }
  }
  if (!this->Superclass::ProcessViewRequest(request_type, inInfo, outInfo))
  {
    return 0;
  }
  if (request_type == vtkPVView::REQUEST_UPDATE() && this->DistributedProjection())
  {
    outInfo->Set(vtkPVRenderView::NEED_ORDERED_COMPOSITING(), 0);
  }
  return 1;
}

//------------------------------------------------------------------------------
int* vtkHovrVolumeRepresentation::GetTableSizes()
{
  std::fill(this->TableSizes, this->TableSizes + 3, 0);
  auto* mapper = vtkPreIntegrationVolumeMapper::SafeDownCast(this->VolumeMapper);
  if (mapper && IsPreIntegration(this->Integration))
  {
    vtkSecondOrderPreIntegrationTable* table = mapper->GetActiveTable();
    this->TableSizes[0] = table->GetTableSize();
    this->TableSizes[1] = table->GetChordSize();
    this->TableSizes[2] = table->GetDeviationSize();
  }
  return this->TableSizes;
}

//------------------------------------------------------------------------------
int vtkHovrVolumeRepresentation::GetRefinementState()
{
  if (auto* mapper = vtkPreIntegrationVolumeMapper::SafeDownCast(this->VolumeMapper))
  {
    if (!mapper->GetRefining())
    {
      return REFINEMENT_NONE;
    }
    return mapper->GetRefinementReady() ? REFINEMENT_READY : REFINEMENT_RUNNING;
  }
  // The adaptive mappers' oracle: ready distances mark the filter modified, so that the render
  // the view then makes outputs them.
  const bool adaptive = this->VolumeMapper == this->AdaptiveRayMapper ||
    this->VolumeMapper == this->AdaptivePyramidMapper;
  if (!adaptive || !this->Oracle->GetRefining())
  {
    return REFINEMENT_NONE;
  }
  this->Oracle->CheckRefinement();
  return this->Oracle->GetRefinementReady() ? REFINEMENT_READY : REFINEMENT_RUNNING;
}

//------------------------------------------------------------------------------
int vtkHovrVolumeRepresentation::GetRefinementCount()
{
  auto* mapper = vtkPreIntegrationVolumeMapper::SafeDownCast(this->PreIntegrationMapper);
  return mapper ? static_cast<int>(mapper->GetTableSizing()->GetRefiner()->GetNumberOfCompleted())
                : 0;
}

//------------------------------------------------------------------------------
double vtkHovrVolumeRepresentation::GetRefinementProgress()
{
  if (auto* mapper = vtkPreIntegrationVolumeMapper::SafeDownCast(this->VolumeMapper))
  {
    return mapper->GetRefinementProgress();
  }
  const bool adaptive = this->VolumeMapper == this->AdaptiveRayMapper ||
    this->VolumeMapper == this->AdaptivePyramidMapper;
  return adaptive ? this->Oracle->GetRefinementProgress() : 1.0;
}

//------------------------------------------------------------------------------
void vtkHovrVolumeRepresentation::SetBlendMode(int blend)
{
  if (this->BlendMode != blend)
  {
    this->BlendMode = blend;
    this->Modified();
  }
}

//------------------------------------------------------------------------------
void vtkHovrVolumeRepresentation::SetCropping(int crop)
{
  if (this->Cropping != crop)
  {
    this->Cropping = crop;
    this->Modified();
  }
}

//------------------------------------------------------------------------------
void vtkHovrVolumeRepresentation::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Integration: " << this->Integration << "\n";
  os << indent << "BlendMode: " << this->BlendMode << "\n";
  os << indent << "Cropping: " << this->Cropping << "\n";
  os << indent << "SampleDistance: " << this->SampleDistance << "\n";
  os << indent << "TableSize: " << this->TableSize << "\n";
  os << indent << "TableMemoryLimit: " << this->TableMemoryLimit << "\n";
  os << indent << "TablePrecision: " << this->TablePrecision << "\n";
  os << indent << "Iterations: " << this->Iterations << "\n";
  os << indent << "TablePrefilter: " << this->TablePrefilter << "\n";
  os << indent << "VolumePrecision: " << this->VolumePrecision << "\n";
  os << indent << "GradientInterpolation: " << this->GradientInterpolation << "\n";
  os << indent << "Gooch: " << (this->Gooch ? "On" : "Off") << "\n";
  os << indent << "NormalArrayName: " << (this->NormalArrayName ? this->NormalArrayName : "(none)")
     << "\n";
  os << indent << "ObjectOrderClassification: " << this->ObjectOrderClassification << "\n";
  os << indent << "ObjectOrderShading: " << this->ObjectOrderShading << "\n";
  os << indent << "InterleavedSampling: " << (this->InterleavedSampling ? "On" : "Off") << "\n";
  os << indent << "HiddenVolumeRemoval: " << (this->HiddenVolumeRemoval ? "On" : "Off") << "\n";
  os << indent << "OpacityThreshold: " << this->OpacityThreshold << "\n";
  os << indent << "LeafSize: " << this->LeafSize << "\n";
  os << indent << "InstructionSet: " << this->InstructionSet << "\n";
  os << indent << "MaximumLevel: " << this->MaximumLevel << "\n";
  os << indent << "OracleMode: " << this->OracleMode << "\n";
  os << indent << "OracleEpsilon: " << this->OracleEpsilon << "\n";
  os << indent << "EffectiveSampleDistance: " << this->EffectiveSampleDistance << "\n";
  os << indent << "RefineInBackground: " << this->RefineInBackground << "\n";
  os << indent << "WholeScalarRange: " << this->WholeScalarRange[0] << ", "
     << this->WholeScalarRange[1] << "\n";
  os << indent << "SizingVolume: " << this->SizingVolume.Get() << "\n";
  os << indent << "WholeBounds:";
  for (double b : this->WholeBounds)
  {
    os << " " << b;
  }
  os << "\n";
}
