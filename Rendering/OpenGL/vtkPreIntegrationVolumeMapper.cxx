// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
#include "vtkPreIntegrationVolumeMapper.h"

#include "vtkCallbackCommand.h"
#include "vtkCamera.h"
#include "vtkDataArray.h"
#include "vtkFloatArray.h"
#include "vtkImageData.h"
#include "vtkMath.h"
#include "vtkMatrix4x4.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkOpenGLPreIntegrationTableBuilder.h"
#include "vtkOpenGLRenderWindow.h"
#include "vtkOpenGLVolumeBricks.h"
#include "vtkPiecewiseFunction.h"
#include "vtkPlane.h"
#include "vtkPlaneCollection.h"
#include "vtkPointData.h"
#include "vtkPreIntegrationTableRefiner.h"
#include "vtkPreIntegrationTableSizer.h"
#include "vtkPreIntegrationTableSizing.h"
#include "vtkRenderWindow.h"
#include "vtkRenderWindowInteractor.h"
#include "vtkRenderer.h"
#include "vtkSMPTools.h"
#include "vtkSecondOrderPreIntegrationTable.h"
#include "vtkShaderProgram.h"
#include "vtkTextureObject.h"
#include "vtkTimerLog.h"
#include "vtkVolume.h"
#include "vtkVolumeProperty.h"
#include "vtkVolumeShadingModel.h"
#include "vtkVolumeTransferFunctionSampler.h"
#include "vtk_glew.h"

#include "hovrPreIntegration1.h"       // the GLSL of first-order pre-integration
#include "hovrPreIntegration2.h"       // the GLSL of second-order pre-integration
#include "hovrPreIntegrationCommon.h"  // the GLSL both orders share
#include "hovrPreIntegrationShading.h" // the GLSL of shaded first-order segments
#include "hovrSlabExtremum.h"          // the slab's extremum, shared with the table builder
#include "hovrWindow.h"                // window to texture coordinates

#include <algorithm>
#include <cmath>
#include <new>
#include <sstream>
#include <string>

vtkStandardNewMacro(vtkPreIntegrationVolumeMapper);

namespace
{
// The most entries along a table axis: a 4097-entry axis already resolves 1/4096 of the range.
constexpr int MaximumAxisSize = 4097;
// The most directional lights a shaded frame sums (the GLSL's array size).
constexpr int MaximumLights = 8;
}

//------------------------------------------------------------------------------
vtkPreIntegrationVolumeMapper::vtkPreIntegrationVolumeMapper()
  : FirstOrderTable(vtkSecondOrderPreIntegrationTable::New())
  , ShadingModel(vtkVolumeShadingModel::New())
  , SecondOrderTable(vtkSecondOrderPreIntegrationTable::New())
  , TableSizing(vtkPreIntegrationTableSizing::New())
  , GPUBuilder(vtkOpenGLPreIntegrationTableBuilder::New())
  , NormalBricks(vtkOpenGLVolumeBricks::New())
  , TableTexture(vtkTextureObject::New())
  , EmptyRunsTexture(vtkTextureObject::New())
{
  vtkNew<vtkCallbackCommand> progress;
  progress->SetCallback(&vtkPreIntegrationVolumeMapper::ForwardProgress);
  progress->SetClientData(this);
  this->TableSizing->GetSizer()->AddObserver(vtkCommand::ProgressEvent, progress);
  this->FirstOrderTable->AddObserver(vtkCommand::ProgressEvent, progress);
  this->SecondOrderTable->AddObserver(vtkCommand::ProgressEvent, progress);
}

//------------------------------------------------------------------------------
vtkPreIntegrationVolumeMapper::~vtkPreIntegrationVolumeMapper()
{
  this->FirstOrderTable->Delete();
  this->ShadingModel->Delete();
  this->SecondOrderTable->Delete();
  this->StopWatching();
  this->TableSizing->Delete();
  this->GPUBuilder->Delete();
  this->TableTexture->Delete();
  this->EmptyRunsTexture->Delete();
  this->NormalBricks->Delete();
  this->SetNormalArrayName(nullptr);
  this->SetSizingVolume(nullptr);
}

//------------------------------------------------------------------------------
void vtkPreIntegrationVolumeMapper::SetIntegration(int mode)
{
  mode = std::min(std::max(mode, static_cast<int>(STOCK)), static_cast<int>(SECOND_ORDER));
  if (mode != this->Integration)
  {
    this->Integration = mode;
    this->ExtensionShaderModified();
    this->Modified();
  }
}

//------------------------------------------------------------------------------
void vtkPreIntegrationVolumeMapper::SetGradientInterpolation(int mode)
{
  if (mode != this->ShadingModel->GetGradientInterpolation())
  {
    this->ShadingModel->SetGradientInterpolation(mode);
    this->Modified();
  }
}

//------------------------------------------------------------------------------
int vtkPreIntegrationVolumeMapper::GetGradientInterpolation()
{
  return this->ShadingModel->GetGradientInterpolation();
}

//------------------------------------------------------------------------------
void vtkPreIntegrationVolumeMapper::SetGooch(bool gooch)
{
  if (gooch != this->ShadingModel->GetGooch())
  {
    this->ShadingModel->SetGooch(gooch);
    this->Modified();
  }
}

//------------------------------------------------------------------------------
bool vtkPreIntegrationVolumeMapper::GetGooch()
{
  return this->ShadingModel->GetGooch();
}

//------------------------------------------------------------------------------
void vtkPreIntegrationVolumeMapper::SetSkipEmptySegments(bool skip)
{
  if (skip != this->SkipEmptySegments)
  {
    this->SkipEmptySegments = skip;
    this->ExtensionShaderModified();
    this->Modified();
  }
}

//------------------------------------------------------------------------------
void vtkPreIntegrationVolumeMapper::SetIterations(int iterations)
{
  iterations = std::min(std::max(iterations, 1), 65536); // the table's own clamp
  if (iterations != this->SecondOrderTable->GetIterations())
  {
    this->FirstOrderTable->SetIterations(iterations);
    this->SecondOrderTable->SetIterations(iterations);
    this->Modified();
  }
}

//------------------------------------------------------------------------------
int vtkPreIntegrationVolumeMapper::GetIterations()
{
  return this->SecondOrderTable->GetIterations();
}

//------------------------------------------------------------------------------
vtkSecondOrderPreIntegrationTable* vtkPreIntegrationVolumeMapper::GetActiveTable()
{
  if (this->Integration == FIRST_ORDER)
  {
    return this->FirstOrderTable;
  }
  return this->Integration == SECOND_ORDER ? this->SecondOrderTable : nullptr;
}

//------------------------------------------------------------------------------
int vtkPreIntegrationVolumeMapper::GetEffectiveTablePrecision()
{
  if (this->TablePrecision != PRECISION_AUTOMATIC)
  {
    return this->TablePrecision;
  }
  // The 2D table is small; 16-bit floats halve the 3D table's memory (relative error 5e-4).
  return this->Integration == SECOND_ORDER ? PRECISION_FLOAT16 : PRECISION_FLOAT32;
}

//------------------------------------------------------------------------------
const char* vtkPreIntegrationVolumeMapper::GetStockFallbackReason(vtkRenderer* ren,
  vtkVolume* vol,
  vtkDataArray* scalars)
{
  this->FallbackReason = this->GetCompositeFallbackReason(vol, scalars, "pre-integration");
  if (!this->FallbackReason.empty())
  {
    return this->FallbackReason.c_str();
  }
  int cellFlag = 0;
  vtkAbstractMapper::GetScalars(this->GetInput(),
    this->ScalarMode,
    this->ArrayAccessMode,
    this->ArrayId,
    this->ArrayName,
    cellFlag);
  if (cellFlag)
  {
    return "pre-integration interpolates point scalars; these are cell scalars";
  }
  this->UpdateRayFrame(ren, vol);
  if (!this->RayFrameInUse)
  {
    return "pre-integration casts the rays of vtkCameraRayModel, which does not describe this "
           "camera (a window centre, a view shear or an explicit projection)";
  }
  if (vol->GetProperty()->GetShade(0))
  {
    vtkNew<vtkVolumeShadingModel> lights;
    if (lights->SetLightsFromRenderer(ren) > 0)
    {
      return "shaded pre-integration models directional lights only, and a positional light "
             "is on";
    }
  }
  return nullptr;
}

//------------------------------------------------------------------------------
void vtkPreIntegrationVolumeMapper::WarnIfTransparent(vtkVolumeTransferFunctionSampler* sampler,
  const double range[2])
{
  if (sampler && !(sampler->GetMaximumOpacity(range[0], range[1]) > 0.0))
  {
    std::ostringstream message;
    message << "The scalar opacity is zero over the data range [" << range[0] << ", " << range[1]
            << "]: the image is transparent.";
    this->WarnEmptyOnce(message.str());
  }
  else
  {
    this->ClearEmptyWarning();
  }
}

//------------------------------------------------------------------------------
vtkExtensibleGPUVolumeRayCastMapper::FramePlan vtkPreIntegrationVolumeMapper::PrepareExtension(
  vtkRenderer* ren,
  vtkVolume* vol)
{
  if (!(this->SampleDistance > 0.0) || !std::isfinite(this->SampleDistance))
  {
    this->CheckFrameSampleDistance(this->SampleDistance, this->MaximumSamplesPerRay);
    return DrawNothing;
  }
  int dims[3], cellFlag;
  FramePlan plan = DrawWithExtension;
  vtkDataArray* scalars = this->GetFrameScalars(dims, cellFlag, plan);
  if (!scalars)
  {
    return plan;
  }
  if (!this->CheckFrameSampleDistance(this->SampleDistance, this->MaximumSamplesPerRay))
  {
    return DrawNothing;
  }
  const bool stock = this->Integration == STOCK;
  if (!stock)
  {
    if (const char* reason = this->GetStockFallbackReason(ren, vol, scalars))
    {
      this->WarnFallbackOnce(reason);
      return DrawStock;
    }
    this->ClearFallbackWarning();
  }

  double dataRange[2], range[2];
  if (!vtkPreIntegrationTable::ComputeScalarRange(scalars, dataRange, range, this->ScalarRange))
  {
    vtkErrorMacro("The scalars hold no finite value (all NaN); not drawing.");
    return DrawNothing;
  }
  if (stock)
  {
    // VTK's own compositing (no table), after the checks of the input it would read
    // unchecked.
    vtkNew<vtkVolumeTransferFunctionSampler> sampler;
    sampler->SetFromVolumeProperty(vol->GetProperty());
    this->WarnIfTransparent(sampler->Prepare() ? sampler.Get() : nullptr, dataRange);
    return DrawStock;
  }
  const bool secondOrder = this->Integration == SECOND_ORDER;
  vtkSecondOrderPreIntegrationTable* table = this->GetActiveTable();
  const int layers = this->PrepareShading(ren, vol);
  if (layers < 0)
  {
    return DrawNothing;
  }
  // The bricks: a piece whose front lies in a brick ends at most one piece (one or two sample
  // distances) past its faces, where the trilinear sample reads the next point and a gradient
  // one more.
  const bool normals = layers > 0 && this->NormalArrayName && *this->NormalArrayName;
  vtkImageData* input = vtkImageData::SafeDownCast(this->GetInput());
  vtkNew<vtkMatrix4x4> worldToObject, worldToIndex;
  vtkMatrix4x4::Invert(vol->GetMatrix(), worldToObject);
  vtkMatrix4x4::Multiply4x4(input->GetPhysicalToIndexMatrix(), worldToObject, worldToIndex);
  double reach = 0.0; // index units per world unit, at most
  for (int r = 0; r < 3; ++r)
  {
    reach = std::max(reach,
      std::abs(worldToIndex->GetElement(r, 0)) + std::abs(worldToIndex->GetElement(r, 1)) +
        std::abs(worldToIndex->GetElement(r, 2)));
  }
  const double span = (this->Integration == SECOND_ORDER ? 2.0 : 1.0) * this->SampleDistance;
  const int ghosts =
    static_cast<int>(std::min(std::ceil(span * reach), 1e6)) + 1 + (layers > 0 && !normals ? 1 : 0);
  const int precision = this->VolumePrecision == VOLUME_PRECISION_NATIVE
    ? vtkOpenGLVolumeBricks::NATIVE
    : this->VolumePrecision == VOLUME_PRECISION_FLOAT32 ? vtkOpenGLVolumeBricks::FLOAT32
                                                        : vtkOpenGLVolumeBricks::WIDE;
  // llvmpipe stops a fragment's loops after 65535 iterations in all: a brick holds at most
  // 60000 pieces along any ray (its diagonal over the step).
  vtkNew<vtkMatrix4x4> indexToWorld;
  vtkMatrix4x4::Invert(worldToIndex, indexToWorld);
  double longest = 0.0; // world length of one index step, at most
  for (int a = 0; a < 3; ++a)
  {
    const double column[3] = {
      indexToWorld->GetElement(0, a), indexToWorld->GetElement(1, a), indexToWorld->GetElement(2, a)
    };
    longest = std::max(longest, vtkMath::Norm(column));
  }
  const double pieceLimit = 60000.0 * this->SampleDistance / (std::sqrt(3.0) * longest);
  const int maximumPoints = static_cast<int>(std::min(pieceLimit, 1e6));
  if (!this->PrepareBricks(
        ren, scalars, dims, ghosts, precision, true, normals ? 12 : 0, maximumPoints) ||
    (layers > 0 && !this->UploadNormals(ren, dims)))
  {
    return DrawNothing;
  }
  this->PrepareRayGeometry(ren, vol);
  // Second order keeps the moments of both halves of a slab (SlabMoments).
  if (secondOrder)
  {
    table->SetSlabMoments(layers);
  }
  else
  {
    table->SetMoments(layers);
  }
  table->SetVolumeProperty(vol->GetProperty());
  // A first-order segment spans one sample distance, a second-order slab two.
  table->SetSegmentLength(secondOrder ? 2.0 * this->SampleDistance : this->SampleDistance);
  table->SetScalarRange(range);
  if (!table->GetSampler()->Prepare())
  {
    vtkErrorMacro("The transfer functions cannot be pre-integrated; not drawing.");
    return DrawNothing;
  }
  this->WarnIfTransparent(table->GetSampler(), dataRange);
  vtkOpenGLRenderWindow* context = vtkOpenGLRenderWindow::SafeDownCast(ren->GetRenderWindow());
  // A GPU build integrates from what Update() prepares; the CPU then skips the entries. The
  // GPU builder integrates colours, not moments: shaded tables are built on the CPU.
  table->SetComputeEntries(!(secondOrder && layers == 0 && this->BuildOnGPU(context)));
  if (!this->SizeTable(context, scalars, cellFlag, range))
  {
    return DrawNothing;
  }
  if (!table->Update() || !this->UploadTable(ren))
  {
    vtkErrorMacro("The pre-integration table could not be built; not drawing.");
    return DrawNothing;
  }

  // raw texture value -> data value -> table texture coordinate (entries at texel centres),
  // over the table's range (a new time step may keep the range its sizes were measured over).
  double scale, shift;
  this->GetBricks()->GetValueMapping(scale, shift);
  const int size = table->GetTableSize();
  const double* tableRange = table->GetScalarRange();
  const double toIndex = (size - 1.0) / (tableRange[1] - tableRange[0]);
  this->RawToTable[0] = static_cast<float>(scale * toIndex / size);
  this->RawToTable[1] = static_cast<float>(((shift - tableRange[0]) * toIndex + 0.5) / size);
  // Differences of centre-axis coordinates -> chord and deviation coordinates (their 0 at the
  // axis' middle texel centre): a coordinate unit is (range / toIndex) size data units.
  const double unit = static_cast<double>(size) / toIndex;
  auto scaleOf = [&](int entries, double extent)
  { return entries > 1 && extent > 0.0 ? unit * (entries - 1) / (2.0 * extent * entries) : 0.0; };
  this->ChordScale =
    static_cast<float>(scaleOf(table->GetChordSize(), table->GetEffectiveChordRange()));
  this->DeviationScale =
    static_cast<float>(scaleOf(table->GetDeviationSize(), table->GetEffectiveDeviationRange()));
  return DrawWithExtension;
}

//------------------------------------------------------------------------------
void vtkPreIntegrationVolumeMapper::PrepareRayGeometry(vtkRenderer* ren, vtkVolume* vol)
{
  vtkImageData* input = vtkImageData::SafeDownCast(this->GetInput());
  vtkCamera* camera = ren->GetActiveCamera();
  // Grid index (0-based) -> data coordinates -> world.
  vtkNew<vtkMatrix4x4> indexToObject, indexToWorld;
  indexToObject->DeepCopy(input->GetIndexToPhysicalMatrix());
  const int* extent = input->GetExtent();
  for (int r = 0; r < 3; ++r)
  {
    double shifted = indexToObject->GetElement(r, 3);
    for (int a = 0; a < 3; ++a)
    {
      shifted += indexToObject->GetElement(r, a) * extent[2 * a];
    }
    indexToObject->SetElement(r, 3, shifted);
  }
  vtkMatrix4x4::Multiply4x4(vol->GetMatrix(), indexToObject, indexToWorld);
  double linear[3][3], inverse[3][3];
  for (int r = 0; r < 3; ++r)
  {
    for (int a = 0; a < 3; ++a)
    {
      // GLSL matrices are column-major: element (r, a) at a * 3 + r.
      this->IndexToWorld[3 * a + r] = static_cast<float>(indexToWorld->GetElement(r, a));
      this->IndexToObject[3 * a + r] = static_cast<float>(indexToObject->GetElement(r, a));
      linear[r][a] = indexToObject->GetElement(r, a);
    }
  }
  vtkMath::Invert3x3(linear, inverse);
  for (int r = 0; r < 3; ++r)
  {
    for (int a = 0; a < 3; ++a)
    {
      // (M^-1)^T: element (r, a) is inverse[a][r].
      this->GradientToObject[3 * a + r] = static_cast<float>(inverse[a][r]);
    }
  }
  double direction[3], position[3];
  camera->GetDirectionOfProjection(direction);
  camera->GetPosition(position);
  for (int a = 0; a < 3; ++a)
  {
    this->ViewDirection[a] = static_cast<float>(direction[a]);
  }
  this->Near = static_cast<float>(camera->GetClippingRange()[0]);
  // Parallel rays: the t of the frame's centre plane, its distance from the camera's plane.
  double centre[4] = { this->RayFrame[0][0], this->RayFrame[0][1], this->RayFrame[0][2], 1.0 };
  indexToWorld->MultiplyPoint(centre, centre);
  this->PlaneT =
    static_cast<float>(vtkMath::Dot(direction, centre) - vtkMath::Dot(direction, position));

  // Cropping planes (data coordinates along the axes) and clipping planes (world), in grid
  // index.
  vtkNew<vtkMatrix4x4> worldToIndex;
  vtkMatrix4x4::Invert(indexToWorld, worldToIndex);
  this->CroppingRegions = this->CroppingRegionFlags;
  for (int a = 0; a < 3; ++a)
  {
    for (int side = 0; side < 2; ++side)
    {
      double point[4] = { 0, 0, 0, 1 }, index[4];
      for (int b = 0; b < 3; ++b)
      {
        point[b] = b == a ? this->CroppingRegionPlanes[2 * a + side] : 0.0;
      }
      vtkNew<vtkMatrix4x4> objectToIndex;
      vtkMatrix4x4::Invert(indexToObject, objectToIndex);
      objectToIndex->MultiplyPoint(point, index);
      this->CroppingPlanes[2 * a + side] = static_cast<float>(index[a]);
    }
  }
  this->ClippingCount = 0;
  vtkPlaneCollection* planes = this->GetClippingPlanes();
  const int count = planes ? planes->GetNumberOfItems() : 0;
  if (count > 6)
  {
    vtkWarningMacro("Pre-integration clips with the first 6 of " << count << " planes.");
  }
  for (int i = 0; i < std::min(count, 6); ++i)
  {
    vtkPlane* plane = planes->GetItem(i);
    // Kept: n . (p_world - o) >= 0 with p_world = W p + w0: (W^T n) . p + n . (w0 - o).
    double n[3], o[3];
    plane->GetNormal(n);
    plane->GetOrigin(o);
    double coefficients[4] = { 0, 0, 0, 0 };
    for (int a = 0; a < 3; ++a)
    {
      for (int r = 0; r < 3; ++r)
      {
        coefficients[a] += indexToWorld->GetElement(r, a) * n[r];
      }
      coefficients[3] += n[a] * (indexToWorld->GetElement(a, 3) - o[a]);
    }
    for (int c = 0; c < 4; ++c)
    {
      this->ClippingPlanes[i][c] = static_cast<float>(coefficients[c]);
    }
    ++this->ClippingCount;
  }
  std::ostringstream switches;
  switches << "#define HOVR_ORDER " << (this->Integration == SECOND_ORDER ? 2 : 1) << "\n"
           << "#define HOVR_JITTER " << (this->UseJittering ? 1 : 0) << "\n"
           << "#define HOVR_CLIPPING " << (this->ClippingCount > 0 ? 1 : 0) << "\n"
           << "#define HOVR_CROPPING " << (this->Cropping ? 1 : 0) << "\n";
  if (switches.str() != this->RaySwitches)
  {
    this->RaySwitches = switches.str();
    this->ExtensionShaderModified();
  }
}

//------------------------------------------------------------------------------
int vtkPreIntegrationVolumeMapper::PrepareShading(vtkRenderer* ren, vtkVolume* vol)
{
  vtkVolumeShadingModel* model = this->ShadingModel;
  this->LastFrameShaded = this->Integration != STOCK && vol->GetProperty()->GetShade(0);
  std::string switches;
  int layers = 0;
  if (this->LastFrameShaded)
  {
    model->SetFromProperty(vol->GetProperty());
    model->SetLightsFromRenderer(ren); // positional lights fell back to the stock path
    if (model->GetNumberOfLights() > MaximumLights)
    {
      vtkWarningMacro("Shaded pre-integration sums " << MaximumLights << " lights; "
                                                     << model->GetNumberOfLights() - MaximumLights
                                                     << " more are ignored.");
    }
    if (!model->TransformLights(vol->GetMatrix()))
    {
      vtkErrorMacro("The volume's matrix is singular: the lights have no direction in its "
                    "coordinates; not drawing.");
      return -1;
    }
    const int mode = model->GetGradientInterpolation();
    // The moment layers the interpolation reads: J_0..J_3 for the arc, J_0 and J_1 otherwise.
    layers = mode == vtkVolumeShadingModel::NONLINEAR ? 4 : 2;
    const bool normals = this->NormalArrayName && *this->NormalArrayName;
    switches = std::string("#define HOVR_NORMALS ") + (normals ? "1" : "0") +
      "\n#define HOVR_LAYERS " + std::to_string(layers) + "\n#define HOVR_INTERPOLATION " +
      std::to_string(mode) + "\n#define HOVR_GOOCH " + (model->GetGooch() ? "1" : "0") + "\n" +
      (this->Integration == SECOND_ORDER ? "#define HOVR_SLABS 1\n" : "");
  }
  if (switches != this->ShadingSwitches)
  {
    this->ShadingSwitches = switches;
    this->ExtensionShaderModified();
  }
  return layers;
}

//------------------------------------------------------------------------------
bool vtkPreIntegrationVolumeMapper::UploadNormals(vtkRenderer* ren, const int dims[3])
{
  vtkOpenGLRenderWindow* context = vtkOpenGLRenderWindow::SafeDownCast(ren->GetRenderWindow());
  if (!this->NormalArrayName || !*this->NormalArrayName)
  {
    this->NormalBricks->ReleaseGraphicsResources(context);
    this->UploadedNormals = nullptr;
    this->NormalTextureMemorySize = 0;
    return true;
  }
  vtkImageData* input = vtkImageData::SafeDownCast(this->GetInput());
  vtkDataArray* normals = input ? input->GetPointData()->GetArray(this->NormalArrayName) : nullptr;
  const vtkIdType points = static_cast<vtkIdType>(dims[0]) * dims[1] * dims[2];
  if (!normals || normals->GetNumberOfComponents() != 3 || normals->GetNumberOfTuples() != points)
  {
    vtkErrorMacro("NormalArrayName \"" << this->NormalArrayName
                                       << "\" names no point array of 3-component vectors, one "
                                          "per point of the volume; not drawing.");
    return false;
  }
  // In the volume's bricks (their layout was planned for 12 bytes per point).
  this->NormalBricks->SetPrecision(vtkOpenGLVolumeBricks::FLOAT32);
  std::string why;
  if (!this->NormalBricks->Update(context, normals, dims, why, this->GetBricks()->GetLayout()))
  {
    vtkErrorMacro("The normals cannot be uploaded: " << why << "; not drawing.");
    return false;
  }
  this->UploadedNormals = normals;
  this->NormalTextureMemorySize = this->NormalBricks->GetMemorySize();
  return true;
}

//------------------------------------------------------------------------------
bool vtkPreIntegrationVolumeMapper::SizeTable(vtkOpenGLRenderWindow* context,
  vtkDataArray* scalars,
  int cellFlag,
  const double range[2])
{
  const bool secondOrder = this->Integration == SECOND_ORDER;
  vtkSecondOrderPreIntegrationTable* table = this->GetActiveTable();
  // Second order is a 3D texture, whose shaded moment layers (both halves of a slab) lie one
  // behind the other along its depth: the deviation axis holds them all, the other axes get
  // the full limit. The moment layers of shaded first order lie one above the other in a 2D
  // one, every axis limited as the stacked one (the sizer has one limit for all axes).
  const int layers = secondOrder ? (table->GetSlabMoments() > 0 ? 2 * table->GetSlabMoments() : 1)
                                 : std::max(table->GetMoments(), 1);
  const int maxSize = secondOrder ? vtkTextureObject::GetMaximumTextureSize3D(context)
                                  : vtkTextureObject::GetMaximumTextureSize(context) / layers;
  const int limit = std::min(maxSize > 0 ? maxSize : 2048, MaximumAxisSize);
  // The largest odd deviation size (an entry at deviation 0) whose layers fit the depth.
  const int stacked = (maxSize > 0 ? maxSize : 2048) / layers;
  const int deviationLimit = std::max(std::min(limit, stacked - (stacked + 1) % 2), 1);
  const bool measurePrefilter =
    this->TablePrefilter == PREFILTER_AUTOMATIC && !secondOrder && this->TableSize == 0;
  if (!measurePrefilter)
  {
    table->SetPrefilter(this->TablePrefilter == PREFILTER_ON);
  }
  if (this->TableSize > 0)
  {
    // N entries on every axis, over every chord and deviation of the range.
    int size = this->TableSize;
    if (size > limit)
    {
      vtkWarningMacro("Table size " << size << " exceeds the limit " << limit << " (OpenGL's, or "
                                    << MaximumAxisSize << "); using " << limit << ".");
      size = limit;
    }
    table->SetTableSize(size);
    table->SetChordSize(size);
    table->SetChordRange(0.0);
    if (secondOrder && size > deviationLimit)
    {
      vtkWarningMacro("Table size " << size << ": " << layers << " moment layers of " << size
                                    << " deviation entries exceed the 3D texture depth " << maxSize
                                    << "; the deviation axis gets " << deviationLimit
                                    << " entries.");
    }
    table->SetDeviationSize(secondOrder ? std::min(size, deviationLimit) : 1);
    table->SetDeviationRange(0.0);
    this->TableSizing->Reset();
    return true;
  }
  vtkImageData* input = vtkImageData::SafeDownCast(this->GetInput());
  // The sizer measures candidate tables on point scalars; cell scalars (and anything it cannot
  // measure) get a table of 256 entries on every axis.
  if (cellFlag != 0 || !input || scalars->GetNumberOfComponents() != 1)
  {
    table->SetPrefilter(this->TablePrefilter == PREFILTER_ON);
    table->SetTableSize(256);
    table->SetChordSize(secondOrder ? 65 : 256);
    table->SetChordRange(0.0);
    table->SetDeviationSize(secondOrder ? 65 : 1);
    table->SetDeviationRange(0.0);
    this->TableSizing->Reset();
    return true;
  }
  // Measured on the whole volume when the input is a piece of it.
  vtkDataArray* sizingScalars =
    this->SizingVolume ? this->SizingVolume->GetPointData()->GetScalars() : nullptr;
  if (this->SizingVolume &&
    (!sizingScalars || sizingScalars->GetNumberOfComponents() != 1 ||
      sizingScalars->GetNumberOfTuples() != this->SizingVolume->GetNumberOfPoints()))
  {
    vtkErrorMacro("The SizingVolume needs one point scalar per point; not drawing.");
    return false;
  }
  if (this->SizingVolume)
  {
    input = this->SizingVolume;
    scalars = sizingScalars;
  }
  const int precision = this->GetEffectiveTablePrecision();
  // Bytes per entry, all moment layers of a shaded table included.
  const int bytes[4] = { 16 * layers, 4 * layers, 8 * layers, 16 * layers };
  // Measured again only when something it depends on changed.
  const std::vector<double> dataKey = { static_cast<double>(reinterpret_cast<uintptr_t>(scalars)),
    static_cast<double>(scalars->GetMTime()),
    static_cast<double>(input->GetMTime()),
    range[0],
    range[1] };
  // The transfer functions by content: an application that rebuilds them unchanged (ParaView
  // does, at each time step) keeps the measured sizes.
  const std::vector<double> key = { table->GetSampler()->GetContentHash(),
    static_cast<double>(this->Integration),
    this->SampleDistance,
    this->TableMemoryLimit,
    static_cast<double>(bytes[precision]),
    static_cast<double>(limit),
    static_cast<double>(this->TablePrefilter),
    static_cast<double>(table->GetIterations()) };
  // The sizer takes at most 64 bytes per entry, no more than 4 float layers hold, fewer than 8: it
  // sizes one layer within the limit's share of one layer.
  vtkPreIntegrationTableSizer* sizer = this->TableSizing->GetSizer();
  sizer->SetMaximumMemory(std::max(this->TableMemoryLimit / layers, 1024.0));
  sizer->SetBytesPerEntry(bytes[precision] / layers);
  sizer->SetMaximumAxisSize(limit);
  sizer->SetOpacityThreshold(this->OpacityThreshold);
  sizer->SetMeasurePrefilter(measurePrefilter);
  this->TableSizing->SetFrameTime(this->GetLastDrawTime());
  if (!this->TableSizing->Update(key,
        dataKey,
        input,
        scalars,
        table,
        secondOrder ? 2 : 1,
        this->SampleDistance,
        secondOrder ? deviationLimit : 1,
        table->GetComputeEntries()))
  {
    vtkErrorMacro("No pre-integration table could be sized; not drawing.");
    return false;
  }
  return true;
}

//------------------------------------------------------------------------------
void vtkPreIntegrationVolumeMapper::SetSizingVolume(vtkImageData* volume)
{
  if (volume != this->SizingVolume)
  {
    vtkImageData* old = this->SizingVolume;
    this->SizingVolume = volume;
    if (volume)
    {
      volume->Register(this);
    }
    if (old)
    {
      old->UnRegister(this);
    }
    this->Modified();
  }
}

//------------------------------------------------------------------------------
vtkPreIntegrationTableSizer* vtkPreIntegrationVolumeMapper::GetTableSizer()
{
  return this->TableSizing->GetSizer();
}

//------------------------------------------------------------------------------
void vtkPreIntegrationVolumeMapper::SetRefineInBackground(bool refine)
{
  if (refine != this->TableSizing->GetRefineInBackground())
  {
    this->TableSizing->SetRefineInBackground(refine);
    this->Modified();
  }
}

//------------------------------------------------------------------------------
bool vtkPreIntegrationVolumeMapper::GetRefineInBackground()
{
  return this->TableSizing->GetRefineInBackground();
}

//------------------------------------------------------------------------------
bool vtkPreIntegrationVolumeMapper::GetRefining()
{
  return this->TableSizing->IsRefining();
}

//------------------------------------------------------------------------------
bool vtkPreIntegrationVolumeMapper::GetRefinementReady()
{
  return this->TableSizing->IsRefinementReady();
}

//------------------------------------------------------------------------------
double vtkPreIntegrationVolumeMapper::GetRefinementProgress()
{
  return this->TableSizing->IsRefining() ? this->TableSizing->GetRefiner()->GetProgress() : 1.0;
}

//------------------------------------------------------------------------------
void vtkPreIntegrationVolumeMapper::ForwardProgress(vtkObject*,
  unsigned long,
  void* clientData,
  void* callData)
{
  static_cast<vtkPreIntegrationVolumeMapper*>(clientData)
    ->InvokeEvent(vtkCommand::ProgressEvent, callData);
}

//------------------------------------------------------------------------------
bool vtkPreIntegrationVolumeMapper::CheckRefinement()
{
  if (!this->TableSizing->IsRefinementReady())
  {
    return false;
  }
  this->InvokeEvent(TablesRefinedEvent);
  return true;
}

//------------------------------------------------------------------------------
void vtkPreIntegrationVolumeMapper::WaitForRefinement()
{
  this->TableSizing->WaitForRefinement();
}

//------------------------------------------------------------------------------
void vtkPreIntegrationVolumeMapper::WatchRefinement(vtkRenderWindowInteractor* interactor)
{
  this->StopWatching();
  this->WatchedInteractor = interactor;
  if (interactor)
  {
    vtkNew<vtkCallbackCommand> callback;
    callback->SetCallback(&vtkPreIntegrationVolumeMapper::OnWatchTimer);
    callback->SetClientData(this);
    this->WatchObserver = interactor->AddObserver(vtkCommand::TimerEvent, callback);
    // One timer for the whole watch, never destroyed from its own callback: VTK's X
    // interactor walks its timers while it calls them, and a timer destroyed there crashes it.
    this->WatchTimer = interactor->CreateRepeatingTimer(50);
  }
}

//------------------------------------------------------------------------------
void vtkPreIntegrationVolumeMapper::StopWatching()
{
  if (vtkRenderWindowInteractor* interactor = this->WatchedInteractor)
  {
    if (this->WatchTimer != 0)
    {
      interactor->DestroyTimer(this->WatchTimer);
    }
    interactor->RemoveObserver(this->WatchObserver);
  }
  this->WatchTimer = 0;
  this->WatchObserver = 0;
  this->WatchedInteractor = nullptr;
}

//------------------------------------------------------------------------------
void vtkPreIntegrationVolumeMapper::OnWatchTimer(vtkObject*,
  unsigned long,
  void* clientData,
  void* callData)
{
  auto* self = static_cast<vtkPreIntegrationVolumeMapper*>(clientData);
  const int timer = callData ? *static_cast<int*>(callData) : -1;
  if (self->WatchTimer != 0 && timer == self->WatchTimer)
  {
    self->CheckRefinement();
  }
}

//------------------------------------------------------------------------------
bool vtkPreIntegrationVolumeMapper::BuildOnGPU(vtkOpenGLRenderWindow* context)
{
  if (this->TableBuilder != BUILD_AUTOMATIC)
  {
    return this->TableBuilder == BUILD_ON_GPU;
  }
  // Software renderers (llvmpipe, softpipe, SwiftShader) run fragment shaders on the CPU,
  // where the CPU builder, which shares each lookup between the two directions of a slab, is
  // faster.
  const char* renderer =
    context ? reinterpret_cast<const char*>(glGetString(GL_RENDERER)) : nullptr;
  const std::string name = renderer ? renderer : "";
  return !name.empty() && name.find("llvmpipe") == std::string::npos &&
    name.find("softpipe") == std::string::npos && name.find("SwiftShader") == std::string::npos;
}

//------------------------------------------------------------------------------
bool vtkPreIntegrationVolumeMapper::UploadTable(vtkRenderer* ren)
{
  vtkOpenGLRenderWindow* context = vtkOpenGLRenderWindow::SafeDownCast(ren->GetRenderWindow());
  vtkSecondOrderPreIntegrationTable* table = this->GetActiveTable();
  const int precision = this->GetEffectiveTablePrecision();
  if (this->TableTexture->GetContext() == context && this->UploadedTable == table &&
    this->UploadedBuildCount == table->GetBuildCount() && this->UploadedPrecision == precision &&
    this->TableTexture->GetHandle() != 0)
  {
    return true;
  }
  const int n = table->GetTableSize();
  const int nb = table->GetChordSize();
  const int nd = table->GetDeviationSize();
  // First order reads a 2D texture over (centre, chord), shaded first order one whose rows
  // hold the moment layers one above the other, second order a 3D one (shaded: the slab
  // moment layers one behind the other).
  const int layers = table->GetNumberOfLayers();
  const bool volume = this->Integration == SECOND_ORDER;
  const int depth = nd * layers;
  const int rows = nb * layers;
  static const unsigned int formats[4] = { GL_RGBA32F, GL_RGBA8, GL_RGBA16F, GL_RGBA32F };
  static const int bytes[4] = { 4, 1, 2, 4 };
  const double start = vtkTimerLog::GetUniversalTime();
  this->LastTableBuiltOnGPU = this->Integration == SECOND_ORDER && !table->GetComputeEntries();
  if (this->LastTableBuiltOnGPU)
  {
    // The GPU builder writes the 3D texture itself, (re)creating it as needed.
    if (!this->GPUBuilder->Build(context, table, this->TableTexture, formats[precision]))
    {
      vtkErrorMacro("The GPU could not build the " << n << " x " << nb << " x " << nd << " table.");
      return false;
    }
  }
  else if (this->TableTexture->GetContext() == context && this->TableTexture->GetHandle() != 0 &&
    this->UploadedTable == table && this->UploadedPrecision == precision &&
    this->UploadedBuildCount + 1 == table->GetBuildCount() &&
    this->TableTexture->GetTarget() ==
      static_cast<unsigned int>(volume ? GL_TEXTURE_3D : GL_TEXTURE_2D) &&
    this->TableTexture->GetWidth() == static_cast<unsigned int>(n) &&
    this->TableTexture->GetHeight() == static_cast<unsigned int>(volume ? nb : rows) &&
    this->TableTexture->GetDepth() == static_cast<unsigned int>(volume ? depth : 1))
  {
    // One build since the last upload, into a texture of the same shape: only the centre
    // entries it integrated (a slab of the table after an incremental build) are sent.
    int centres[2];
    table->GetLastBuildCentres(centres);
    if (centres[1] >= centres[0])
    {
      const float* first = table->GetTable()->GetPointer(0) + 4 * centres[0];
      const int width = centres[1] - centres[0] + 1;
      // Float rows meet any unpack alignment; the row length and image height are restored.
      this->TableTexture->Activate();
      glPixelStorei(GL_UNPACK_ROW_LENGTH, n);
      if (volume)
      {
        glPixelStorei(GL_UNPACK_IMAGE_HEIGHT, nb);
        glTexSubImage3D(
          GL_TEXTURE_3D, 0, centres[0], 0, 0, width, nb, depth, GL_RGBA, GL_FLOAT, first);
        glPixelStorei(GL_UNPACK_IMAGE_HEIGHT, 0);
      }
      else
      {
        glTexSubImage2D(GL_TEXTURE_2D, 0, centres[0], 0, width, rows, GL_RGBA, GL_FLOAT, first);
      }
      glPixelStorei(GL_UNPACK_ROW_LENGTH, 0);
      this->TableTexture->Deactivate();
    }
  }
  else
  {
    this->TableTexture->ReleaseGraphicsResources(context); // 2D and 3D tables differ in target
    this->TableTexture->SetContext(context);
    this->TableTexture->SetInternalFormat(formats[precision]);
    this->TableTexture->SetFormat(GL_RGBA);
    this->TableTexture->SetDataType(GL_FLOAT);
    void* data = table->GetTable()->GetVoidPointer(0);
    const int size3[3] = { n, nb, depth };
    std::string why;
    const bool created = volume
      ? this->CreateTexture3D(
          this->TableTexture, context, size3, 4, VTK_FLOAT, data, "table texture", why)
      : this->TableTexture->Create2DFromRaw(n, rows, 4, VTK_FLOAT, data);
    if (!created)
    {
      vtkErrorMacro("Could not create the "
        << n << " x " << (volume ? nb : rows) << (volume ? " x " : "")
        << (volume ? std::to_string(depth) : std::string()) << " table texture"
        << (why.empty() ? std::string() : ": " + why) << ".");
      return false;
    }
  }
  this->LastTableBuildTime = table->GetLastBuildTime() + (vtkTimerLog::GetUniversalTime() - start);
  this->TableTexture->SetWrapS(vtkTextureObject::ClampToEdge);
  this->TableTexture->SetWrapT(vtkTextureObject::ClampToEdge);
  this->TableTexture->SetWrapR(vtkTextureObject::ClampToEdge);
  this->TableTexture->SetMinificationFilter(vtkTextureObject::Linear);
  this->TableTexture->SetMagnificationFilter(vtkTextureObject::Linear);
  // The zero-opacity runs of the table spacings, read with texelFetch.
  this->EmptyRunsTexture->SetContext(context);
  this->EmptyRunsTexture->SetInternalFormat(GL_R32F);
  this->EmptyRunsTexture->SetFormat(GL_RED);
  this->EmptyRunsTexture->SetDataType(GL_FLOAT);
  if (!this->EmptyRunsTexture->Create2DFromRaw(
        n - 1, 1, 1, VTK_FLOAT, table->GetEmptyRuns()->GetVoidPointer(0)))
  {
    vtkErrorMacro("Could not create the empty-run texture.");
    return false;
  }
  this->EmptyRunsTexture->SetMinificationFilter(vtkTextureObject::Nearest);
  this->EmptyRunsTexture->SetMagnificationFilter(vtkTextureObject::Nearest);
  this->UploadedTable = table;
  this->UploadedBuildCount = table->GetBuildCount();
  this->UploadedPrecision = precision;
  this->TableTextureMemorySize =
    table->GetNumberOfEntries() * 4 * bytes[precision] + static_cast<vtkIdType>(n - 1) * 4;
  return true;
}

//------------------------------------------------------------------------------
void vtkPreIntegrationVolumeMapper::ActivateExtensionTextures()
{
  this->TableTexture->Activate();
  this->EmptyRunsTexture->Activate();
  if (this->UploadedNormals)
  {
    this->NormalBricks->GetTexture(this->GetCurrentBrick())->Activate();
  }
}

//------------------------------------------------------------------------------
void vtkPreIntegrationVolumeMapper::DeactivateExtensionTextures()
{
  this->TableTexture->Deactivate();
  this->EmptyRunsTexture->Deactivate();
  if (this->UploadedNormals)
  {
    this->NormalBricks->GetTexture(this->GetCurrentBrick())->Deactivate();
  }
}

//------------------------------------------------------------------------------
bool vtkPreIntegrationVolumeMapper::ReplaceExtensionShaderValues(std::string&,
  std::string& fragmentShader,
  vtkVolume*)
{
  using Self = vtkExtensibleGPUVolumeRayCastMapper;
  // The early-termination threshold becomes a uniform (VTK declares a constant here).
  bool ok = Self::ReplaceShaderTag(fragmentShader,
    "//VTK::Termination::Dec",
    "uniform float hovr_opacityThreshold;\n#define g_opacityThreshold hovr_opacityThreshold",
    Self::ReplaceTag);
  // The whole ray is walked where VTK would initialise its loop, which then never runs.
  ok = ok &&
    Self::ReplaceShaderTag(fragmentShader,
      "//VTK::Shading::Init",
      "hovr_preintRay();\n  g_exit = true;",
      Self::ReplaceTag);
  ok = ok && Self::ReplaceShaderTag(fragmentShader, "//VTK::Shading::Impl", "", Self::ReplaceTag);
  ok = ok && Self::ReplaceShaderTag(fragmentShader, "//VTK::Shading::Exit", "", Self::ReplaceTag);
  // The rays are clipped here (HOVR_CLIPPING): VTK's clipping of each brick's 2-point box would
  // mix its texture coordinates of two kinds and discard rays it should keep.
  ok = ok && Self::ReplaceShaderTag(fragmentShader, "//VTK::Clipping::Init", "", Self::ReplaceTag);
  // Declared late, after every uniform and global the functions use; the switches of the
  // GLSL first.
  const bool shaded = !this->ShadingSwitches.empty();
  const std::string switches = std::string("#define HOVR_SKIP_EMPTY ") +
    (this->SkipEmptySegments ? "1" : "0") + "\n#define HOVR_SHADED " + (shaded ? "1" : "0") + "\n" +
    this->RaySwitches + this->ShadingSwitches;
  // Shading calls computeRayDirection(): declared after it.
  ok = ok &&
    Self::ReplaceShaderTag(fragmentShader,
      "//VTK::ComputeRayDirection::Dec",
      switches + hovrWindow + hovrPreIntegrationCommon +
        (shaded ? std::string(hovrPreIntegrationShading) : std::string()) +
        (this->Integration == SECOND_ORDER ? std::string(hovrSlabExtremum) + hovrPreIntegration2
                                           : std::string(hovrPreIntegration1)),
      shaded ? Self::AfterTag : Self::BeforeTag);
  if (!ok)
  {
    vtkErrorMacro("The ray caster's shader template lacks a tag that pre-integration replaces.");
  }
  return ok;
}

//------------------------------------------------------------------------------
void vtkPreIntegrationVolumeMapper::SetExtensionShaderParameters(vtkShaderProgram* program,
  vtkVolume*)
{
  program->SetUniformi("hovr_preintTable", this->TableTexture->GetTextureUnit());
  program->SetUniformi("hovr_emptyRuns", this->EmptyRunsTexture->GetTextureUnit());
  program->SetUniformi("hovr_tableSize", this->GetActiveTable()->GetTableSize());
  program->SetUniform2f("hovr_rawToTable", this->RawToTable);
  program->SetUniformf("hovr_chordScale", this->ChordScale);
  if (this->Integration == SECOND_ORDER)
  {
    program->SetUniformf("hovr_deviationScale", this->DeviationScale);
  }
  program->SetUniformf("hovr_opacityThreshold", static_cast<float>(this->OpacityThreshold));
  // The brick and the rays.
  program->SetUniformi("hovr_volume", this->GetBrickTexture()->GetTextureUnit());
  int points[6], cells[6];
  this->GetBrickPoints(points);
  this->GetBrickCells(cells);
  int dims[3];
  vtkImageData::SafeDownCast(this->GetInput())->GetDimensions(dims);
  // A piece with ghost points (OwnedExtent) walks its rays in the whole volume (WholeBounds),
  // and this brick draws the pieces that start in its cells and in the points the input owns;
  // without ghost points a piece is walked as a volume of its own.
  const int* ownedExtent = this->OwnedExtent;
  double wholeLo[3] = { 0.0, 0.0, 0.0 };
  double wholeHi[3] = { dims[0] - 1.0, dims[1] - 1.0, dims[2] - 1.0 };
  if (ownedExtent[0] <= ownedExtent[1] && ownedExtent[2] <= ownedExtent[3] &&
    ownedExtent[4] <= ownedExtent[5])
  {
    this->GetWholeIndexBox(wholeLo, wholeHi);
  }
  int ownedLo[3], ownedHi[3];
  this->GetOwnedIndexBox(ownedLo, ownedHi);
  float invTexels[3], first[3], last[3], ownedMin[3], ownedMax[3], volumeMin[3], volumeMax[3],
    origin[3];
  for (int a = 0; a < 3; ++a)
  {
    invTexels[a] = 1.0f / static_cast<float>(points[2 * a + 1] - points[2 * a] + 1);
    first[a] = static_cast<float>(-points[2 * a]);
    last[a] = static_cast<float>(dims[a] - 1 - points[2 * a]);
    ownedMin[a] = static_cast<float>(std::max(cells[2 * a], ownedLo[a]));
    ownedMax[a] = static_cast<float>(std::min(cells[2 * a + 1], ownedHi[a]));
    volumeMin[a] = static_cast<float>(wholeLo[a]);
    volumeMax[a] = static_cast<float>(wholeHi[a]);
    origin[a] = static_cast<float>(points[2 * a]);
  }
  program->SetUniform3f("hovr_volumeInvTexels", invTexels);
  program->SetUniform3f("hovr_volumeFirst", first);
  program->SetUniform3f("hovr_volumeLast", last);
  program->SetUniform3f("hovr_ownedMin", ownedMin);
  program->SetUniform3f("hovr_ownedMax", ownedMax);
  program->SetUniform3f("hovr_volumeMin", volumeMin);
  program->SetUniform3f("hovr_volumeMax", volumeMax);
  const float dataMax[3] = { dims[0] - 1.0f, dims[1] - 1.0f, dims[2] - 1.0f };
  program->SetUniform3f("hovr_dataMax", dataMax);
  program->SetUniform3f("hovr_brickOrigin", origin);
  this->SetRayFrameUniforms(program);
  program->SetUniformf("hovr_planeT", this->PlaneT);
  program->SetUniformMatrix3x3("hovr_indexToWorld", this->IndexToWorld);
  program->SetUniformMatrix3x3("hovr_indexToObject", this->IndexToObject);
  program->SetUniformMatrix3x3("hovr_gradientToObject", this->GradientToObject);
  program->SetUniform3f("hovr_viewDirection", this->ViewDirection);
  program->SetUniformf("hovr_near", this->Near);
  program->SetUniformf("hovr_step", static_cast<float>(this->SampleDistance));
  if (this->Cropping)
  {
    program->SetUniform1fv("hovr_croppingPlanes", 6, this->CroppingPlanes);
    program->SetUniformi("hovr_croppingRegions", this->CroppingRegions);
  }
  if (this->ClippingCount > 0)
  {
    program->SetUniformi("hovr_clippingCount", this->ClippingCount);
    program->SetUniform4fv("hovr_clippingPlanes", 6, this->ClippingPlanes);
  }
  if (!this->ShadingSwitches.empty())
  {
    this->SetShadingParameters(program);
  }
}

//------------------------------------------------------------------------------
void vtkPreIntegrationVolumeMapper::SetShadingParameters(vtkShaderProgram* program)
{
  vtkVolumeShadingModel* model = this->ShadingModel;
  const int count = std::min(model->GetNumberOfLights(), MaximumLights);
  float direction[MaximumLights][3] = {}, diffuse[MaximumLights][3] = {},
        specular[MaximumLights][3] = {};
  int head[MaximumLights] = {};
  for (int k = 0; k < count; ++k)
  {
    double d[3], c[3], s[3];
    bool headlight;
    model->GetLight(k, d, c, s, headlight);
    for (int a = 0; a < 3; ++a)
    {
      direction[k][a] = static_cast<float>(d[a]);
      diffuse[k][a] = static_cast<float>(c[a]);
      specular[k][a] = static_cast<float>(s[a]);
    }
    head[k] = headlight ? 1 : 0;
  }
  if (this->UploadedNormals)
  {
    program->SetUniformi(
      "hovr_normals", this->NormalBricks->GetTexture(this->GetCurrentBrick())->GetTextureUnit());
  }
  program->SetUniformf(
    "hovr_chordTexels", static_cast<float>(this->GetActiveTable()->GetChordSize()));
  if (this->Integration == SECOND_ORDER)
  {
    program->SetUniformf(
      "hovr_deviationTexels", static_cast<float>(this->GetActiveTable()->GetDeviationSize()));
  }
  program->SetUniformi("hovr_numberOfLights", count);
  program->SetUniform3fv("hovr_lightDirection", MaximumLights, direction);
  program->SetUniform3fv("hovr_lightDiffuse", MaximumLights, diffuse);
  program->SetUniform3fv("hovr_lightSpecular", MaximumLights, specular);
  program->SetUniform1iv("hovr_lightIsHead", MaximumLights, head);
  const float lighting[4] = { static_cast<float>(model->GetAmbient()),
    static_cast<float>(model->GetDiffuse()),
    static_cast<float>(model->GetSpecular()),
    static_cast<float>(model->GetConeSlope()) };
  program->SetUniform4f("hovr_lighting", lighting);
  program->SetUniformf(
    "hovr_minimumCosHalfAngle", static_cast<float>(model->GetMinimumCosHalfAngle()));
  program->SetUniformi("hovr_twoSided", model->GetTwoSidedLighting() ? 1 : 0);
  float cool[3], warm[3];
  for (int a = 0; a < 3; ++a)
  {
    cool[a] = static_cast<float>(model->GetGoochCool()[a]);
    warm[a] = static_cast<float>(model->GetGoochWarm()[a]);
  }
  program->SetUniform3f("hovr_goochCool", cool);
  program->SetUniform3f("hovr_goochWarm", warm);
  const float weights[2] = { static_cast<float>(model->GetGoochAlpha()),
    static_cast<float>(model->GetGoochBeta()) };
  program->SetUniform2f("hovr_goochWeights", weights);
}

//------------------------------------------------------------------------------
void vtkPreIntegrationVolumeMapper::ReleaseExtensionResources(vtkWindow* window)
{
  this->TableTexture->ReleaseGraphicsResources(window);
  this->EmptyRunsTexture->ReleaseGraphicsResources(window);
  this->NormalBricks->ReleaseGraphicsResources(window);
  this->UploadedNormals = nullptr;
  this->NormalTextureMemorySize = 0;
  this->UploadedTable = nullptr;
  this->UploadedBuildCount = -1;
  this->TableTextureMemorySize = 0;
}

//------------------------------------------------------------------------------
void vtkPreIntegrationVolumeMapper::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Integration: " << this->Integration << "\n";
  os << indent << "TableSize: " << this->TableSize << "\n";
  os << indent << "TablePrecision: " << this->TablePrecision << "\n";
  os << indent << "SkipEmptySegments: " << this->SkipEmptySegments << "\n";
  os << indent << "TableBuilder: " << this->TableBuilder << "\n";
  os << indent << "LastTableBuiltOnGPU: " << this->LastTableBuiltOnGPU << "\n";
  os << indent << "LastTableBuildTime: " << this->LastTableBuildTime << "\n";
  os << indent << "Iterations: " << this->GetIterations() << "\n";
  os << indent << "TablePrefilter: " << this->TablePrefilter << "\n";
  os << indent << "OpacityThreshold: " << this->OpacityThreshold << "\n";
  os << indent << "MaximumSamplesPerRay: " << this->MaximumSamplesPerRay << "\n";
  os << indent << "VolumePrecision: " << this->VolumePrecision << "\n";
  os << indent << "VolumeTextureMemorySize: " << this->GetVolumeTextureMemorySize() << "\n";
  os << indent << "TableTextureMemorySize: " << this->TableTextureMemorySize << "\n";
  os << indent << "NormalArrayName: " << (this->NormalArrayName ? this->NormalArrayName : "(none)")
     << "\n";
  os << indent << "GradientInterpolation: " << this->GetGradientInterpolation() << "\n";
  os << indent << "Gooch: " << this->GetGooch() << "\n";
  os << indent << "TableMemoryLimit: " << static_cast<vtkIdType>(this->TableMemoryLimit) << "\n";
  os << indent << "SizingVolume: " << this->SizingVolume << "\n";
  os << indent << "RefineInBackground: " << this->GetRefineInBackground() << "\n";
}
