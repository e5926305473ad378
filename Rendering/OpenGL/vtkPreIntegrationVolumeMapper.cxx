// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
#include "vtkPreIntegrationVolumeMapper.h"

#include "vtkDataArray.h"
#include "vtkFloatArray.h"
#include "vtkImageData.h"
#include "vtkMath.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkOpenGLPreIntegrationTableBuilder.h"
#include "vtkOpenGLRenderWindow.h"
#include "vtkPiecewiseFunction.h"
#include "vtkPointData.h"
#include "vtkPreIntegrationTableSizer.h"
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
  , TableSizer(vtkPreIntegrationTableSizer::New())
  , GPUBuilder(vtkOpenGLPreIntegrationTableBuilder::New())
  , NormalTexture(vtkTextureObject::New())
  , TableTexture(vtkTextureObject::New())
  , EmptyRunsTexture(vtkTextureObject::New())
{
}

//------------------------------------------------------------------------------
vtkPreIntegrationVolumeMapper::~vtkPreIntegrationVolumeMapper()
{
  this->FirstOrderTable->Delete();
  this->ShadingModel->Delete();
  this->SecondOrderTable->Delete();
  this->TableSizer->Delete();
  this->GPUBuilder->Delete();
  this->TableTexture->Delete();
  this->EmptyRunsTexture->Delete();
  this->NormalTexture->Delete();
  this->SetNormalArrayName(nullptr);
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
  if (!vtkPreIntegrationTable::ComputeScalarRange(scalars, dataRange, range))
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
  if (layers < 0 || (layers > 0 && !this->UploadNormals(ren, dims)))
  {
    return DrawNothing;
  }
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
  if (!this->SizeTable(context, scalars, cellFlag, range))
  {
    return DrawNothing;
  }
  // A GPU build integrates from what Update() prepares; the CPU then skips the entries. The
  // GPU builder integrates colours, not moments: shaded tables are built on the CPU.
  table->SetComputeEntries(!(secondOrder && layers == 0 && this->BuildOnGPU(context)));
  if (!table->Update() || !this->UploadTable(ren))
  {
    vtkErrorMacro("The pre-integration table could not be built; not drawing.");
    return DrawNothing;
  }

  // raw texture value -> data value -> table texture coordinate (entries at texel centres).
  double scale, shift;
  vtkPreIntegrationVolumeMapper::GetTextureValueMapping(
    this->ChooseTextureScalars(scalars), scale, shift);
  const int size = table->GetTableSize();
  const double toIndex = (size - 1.0) / (range[1] - range[0]);
  this->RawToTable[0] = static_cast<float>(scale * toIndex / size);
  this->RawToTable[1] = static_cast<float>(((shift - range[0]) * toIndex + 0.5) / size);
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
  if (!this->NormalArrayName || !*this->NormalArrayName)
  {
    this->NormalTexture->ReleaseGraphicsResources(ren->GetRenderWindow());
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
  vtkOpenGLRenderWindow* context = vtkOpenGLRenderWindow::SafeDownCast(ren->GetRenderWindow());
  if (this->NormalTexture->GetContext() == context && this->UploadedNormals == normals &&
    this->UploadedNormalsTime == normals->GetMTime() && this->NormalTexture->GetHandle() != 0)
  {
    return true;
  }
  vtkNew<vtkFloatArray> values; // float, whatever the array's type
  values->DeepCopy(normals);
  this->NormalTexture->ReleaseGraphicsResources(context);
  this->NormalTexture->SetInternalFormat(GL_RGB32F);
  this->NormalTexture->SetFormat(GL_RGB);
  this->NormalTexture->SetDataType(GL_FLOAT);
  std::string why;
  if (!this->CreateTexture3D(this->NormalTexture, context, dims, 3, VTK_FLOAT,
        values->GetVoidPointer(0), "normal texture", why))
  {
    vtkErrorMacro(<< why << "; not drawing.");
    return false;
  }
  this->NormalTexture->SetWrapS(vtkTextureObject::ClampToEdge);
  this->NormalTexture->SetWrapT(vtkTextureObject::ClampToEdge);
  this->NormalTexture->SetWrapR(vtkTextureObject::ClampToEdge);
  this->NormalTexture->SetMinificationFilter(vtkTextureObject::Linear);
  this->NormalTexture->SetMagnificationFilter(vtkTextureObject::Linear);
  this->UploadedNormals = normals;
  this->UploadedNormalsTime = normals->GetMTime();
  this->NormalTextureMemorySize = points * 3 * static_cast<vtkIdType>(sizeof(float));
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
    this->TableSizeKey.clear();
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
    return true;
  }
  const int precision = this->GetEffectiveTablePrecision();
  // Bytes per entry, all moment layers of a shaded table included.
  const int bytes[4] = { 16 * layers, 4 * layers, 8 * layers, 16 * layers };
  // Measured again only when something it depends on changed.
  const std::vector<double> key = { static_cast<double>(reinterpret_cast<uintptr_t>(scalars)),
    static_cast<double>(scalars->GetMTime()),
    static_cast<double>(input->GetMTime()),
    static_cast<double>(table->GetSampler()->GetMTime()),
    static_cast<double>(this->Integration),
    this->SampleDistance,
    range[0],
    range[1],
    this->TableMemoryLimit,
    static_cast<double>(bytes[precision]),
    static_cast<double>(limit),
    static_cast<double>(this->TablePrefilter),
    static_cast<double>(table->GetIterations()) };
  if (key == this->TableSizeKey)
  {
    return true;
  }
  // The sizer takes at most 64 bytes per entry, no more than 4 float layers hold, fewer than 8: it
  // sizes one layer within the limit's share of one layer.
  this->TableSizer->SetMaximumMemory(std::max(this->TableMemoryLimit / layers, 1024.0));
  this->TableSizer->SetBytesPerEntry(bytes[precision] / layers);
  this->TableSizer->SetMaximumAxisSize(limit);
  this->TableSizer->SetOpacityThreshold(this->OpacityThreshold);
  this->TableSizer->SetMeasurePrefilter(measurePrefilter);
  if (!this->TableSizer->Choose(input, scalars, table, secondOrder ? 2 : 1, this->SampleDistance))
  {
    vtkErrorMacro("No pre-integration table could be sized; not drawing.");
    return false;
  }
  if (secondOrder)
  {
    table->SetDeviationSize(std::min(table->GetDeviationSize(), deviationLimit));
  }
  this->TableSizeKey = key;
  return true;
}

//------------------------------------------------------------------------------
vtkDataArray* vtkPreIntegrationVolumeMapper::ChooseTextureScalars(vtkDataArray* scalars)
{
  // The copy holds the same values, so VTK's own scalar range and lookup tables stay those of
  // the data; only the texel format changes (VTK uploads 16-bit integers as 16-bit textures).
  const int precision = this->VolumePrecision;
  vtkDataArray* widened = nullptr;
  if (precision == VOLUME_PRECISION_AUTOMATIC || precision == VOLUME_PRECISION_16BIT)
  {
    widened = this->WidenedTextureScalars(scalars);
  }
  else if (precision == VOLUME_PRECISION_FLOAT32)
  {
    widened = this->WidenedTextureScalars(scalars, VTK_FLOAT);
  }
  else
  {
    this->WidenedTextureScalars(nullptr); // native: release any copy
  }
  vtkDataArray* uploaded = widened ? widened : scalars;
  this->SetTextureScalars(widened);
  const vtkIdType values = scalars->GetNumberOfValues();
  const int uploadedType = uploaded->GetDataType();
  const int bytes =
    uploadedType == VTK_UNSIGNED_CHAR || uploadedType == VTK_SIGNED_CHAR || uploadedType == VTK_CHAR
    ? 1
    : uploadedType == VTK_UNSIGNED_SHORT || uploadedType == VTK_SHORT ? 2
                                                                      : 4;
  this->VolumeTextureMemorySize = values * bytes;
  this->VolumeCopyMemorySize = uploaded == scalars ? 0 : values * bytes;
  return uploaded;
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
      ? this->CreateTexture3D(this->TableTexture, context, size3, 4, VTK_FLOAT, data, "table texture", why)
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
    this->NormalTexture->Activate();
  }
}

//------------------------------------------------------------------------------
void vtkPreIntegrationVolumeMapper::DeactivateExtensionTextures()
{
  this->TableTexture->Deactivate();
  this->EmptyRunsTexture->Deactivate();
  if (this->UploadedNormals)
  {
    this->NormalTexture->Deactivate();
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
  ok = ok &&
    Self::ReplaceShaderTag(
      fragmentShader, "//VTK::Shading::Init", "hovr_preintInit();", Self::ReplaceTag);
  ok = ok &&
    Self::ReplaceShaderTag(
      fragmentShader, "//VTK::Shading::Impl", "hovr_preintStep();", Self::ReplaceTag);
  ok = ok &&
    Self::ReplaceShaderTag(
      fragmentShader, "//VTK::Shading::Exit", "hovr_preintExit();", Self::ReplaceTag);
  // Declared late, after every uniform and global the functions use; the switches of the
  // GLSL first.
  const bool shaded = !this->ShadingSwitches.empty();
  const std::string switches = std::string("#define HOVR_SKIP_EMPTY ") +
    (this->SkipEmptySegments ? "1" : "0") + "\n#define HOVR_SHADED " + (shaded ? "1" : "0") + "\n" +
    this->ShadingSwitches;
  // Shading calls computeRayDirection(): declared after it.
  ok = ok &&
    Self::ReplaceShaderTag(fragmentShader,
      "//VTK::ComputeRayDirection::Dec",
      switches + hovrPreIntegrationCommon +
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
    program->SetUniformi("hovr_normals", this->NormalTexture->GetTextureUnit());
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
  this->NormalTexture->ReleaseGraphicsResources(window);
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
  os << indent << "VolumeTextureMemorySize: " << this->VolumeTextureMemorySize << "\n";
  os << indent << "VolumeCopyMemorySize: " << this->VolumeCopyMemorySize << "\n";
  os << indent << "TableTextureMemorySize: " << this->TableTextureMemorySize << "\n";
  os << indent << "NormalArrayName: " << (this->NormalArrayName ? this->NormalArrayName : "(none)")
     << "\n";
  os << indent << "GradientInterpolation: " << this->GetGradientInterpolation() << "\n";
  os << indent << "Gooch: " << this->GetGooch() << "\n";
  os << indent << "TableMemoryLimit: " << static_cast<vtkIdType>(this->TableMemoryLimit) << "\n";
}
