// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
#include "vtkAdaptiveRayVolumeMapper.h"

#include "vtkCamera.h"
#include "vtkDataArray.h"
#include "vtkFirstOrderPreIntegrationTable.h"
#include "vtkFloatArray.h"
#include "vtkImageData.h"
#include "vtkMath.h"
#include "vtkMatrix4x4.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkOpenGLRenderWindow.h"
#include "vtkOpenGLVolumeBricks.h"
#include "vtkPiecewiseFunction.h"
#include "vtkPlaneCollection.h"
#include "vtkPointData.h"
#include "vtkRenderer.h"
#include "vtkShaderProgram.h"
#include "vtkSmartPointer.h"
#include "vtkTextureObject.h"
#include "vtkTimerLog.h"
#include "vtkVolume.h"
#include "vtkVolumeProperty.h"
#include "vtkVolumeTransferFunctionSampler.h"
#include "vtk_glew.h"

#include "hovrAdaptiveRay.h" // the GLSL of the adaptive ray
#include "hovrVolumeAtlas.h" // its volume and oracle lookups

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

vtkStandardNewMacro(vtkAdaptiveRayVolumeMapper);

namespace
{
// Table memory above which the layers are stored in 16-bit floats, and the most in any case.
constexpr double Float32TableLimit = 64.0 * 1024.0 * 1024.0;
constexpr double TableMemoryLimit = 256.0 * 1024.0 * 1024.0;
}

struct vtkAdaptiveRayVolumeMapper::Internals
{
  // Table k - 1 composites k slices (Fig. 6's C_lut and alpha_lut for length k Delta).
  std::vector<vtkSmartPointer<vtkFirstOrderPreIntegrationTable>> Tables;
  vtkNew<vtkTextureObject> TableTexture;
  // The oracle in the volume's bricks (the same atlas tiles).
  vtkNew<vtkOpenGLVolumeBricks> OracleBricks;
  // What the textures hold.
  std::vector<int> UploadedBuilds;
  int UploadedLayers = 0;
  float TileGrid[2] = { 1.0f, 1.0f }; // columns and rows of layer tiles
  unsigned int UploadedFormat = 0;
  // The oracle array last found finite, and its time.
  vtkDataArray* CheckedOracle = nullptr;
  vtkMTimeType CheckedOracleTime = 0;
  // Per frame.
  bool UseOracle = false;
  float RawToTable[2] = { 1.0f, 0.0f };
  float SliceOrigin[3] = { 0.0f, 0.0f, 0.0f };
  float SliceStart = 0.0f;
  int Perspective = 0;
  // The switches of the GLSL last inserted.
  std::string Switches;
  // The last warning about the oracle or the counter, given once until it changes.
  std::string Warning;
  // The atomic counter buffer (0: none) and the context it belongs to.
  unsigned int CounterBuffer = 0;
  vtkOpenGLRenderWindow* CounterContext = nullptr;
  bool CountingThisFrame = false;
};

//------------------------------------------------------------------------------
vtkAdaptiveRayVolumeMapper::vtkAdaptiveRayVolumeMapper()
  : Internal(new Internals)
{
  this->SetOracleArrayName("OracleDistance");
}

//------------------------------------------------------------------------------
vtkAdaptiveRayVolumeMapper::~vtkAdaptiveRayVolumeMapper()
{
  this->SetOracleArrayName(nullptr);
}

//------------------------------------------------------------------------------
void vtkAdaptiveRayVolumeMapper::SetMaximumLevel(int level)
{
  if (level < 0 || level > 8)
  {
    const int clamped = std::min(std::max(level, 0), 8);
    vtkWarningMacro("MaximumLevel " << level << " is outside [0, 8]; using " << clamped << ".");
    level = clamped;
  }
  if (level != this->MaximumLevel)
  {
    this->MaximumLevel = level;
    this->Modified();
  }
}

//------------------------------------------------------------------------------
void vtkAdaptiveRayVolumeMapper::SetReconstruction(int reconstruction)
{
  if (reconstruction != RECONSTRUCTION_TRILINEAR &&
    reconstruction != RECONSTRUCTION_TRICUBIC_BSPLINE)
  {
    vtkWarningMacro("Reconstruction " << reconstruction << " is unknown; using trilinear.");
    reconstruction = RECONSTRUCTION_TRILINEAR;
  }
  if (reconstruction != this->Reconstruction)
  {
    this->Reconstruction = reconstruction;
    this->Modified();
  }
}

//------------------------------------------------------------------------------
void vtkAdaptiveRayVolumeMapper::SetCountSamples(bool count)
{
  if (count != this->CountSamples)
  {
    this->CountSamples = count;
    this->Modified();
  }
}

//------------------------------------------------------------------------------
vtkExtensibleGPUVolumeRayCastMapper::FramePlan vtkAdaptiveRayVolumeMapper::PrepareExtension(
  vtkRenderer* ren,
  vtkVolume* vol)
{
  Internals& internal = *this->Internal;
  internal.CountingThisFrame = false;
  this->LastFrameSampleCount = -1;
  const double delta = this->SampleDistance;
  if (!(delta > 0.0) || !std::isfinite(delta))
  {
    this->CheckFrameSampleDistance(delta, this->MaximumSamplesPerRay);
    return DrawNothing;
  }
  int dims[3], cellFlag;
  FramePlan plan = DrawWithExtension;
  vtkDataArray* scalars = this->GetFrameScalars(dims, cellFlag, plan);
  if (!scalars)
  {
    return plan;
  }
  if (!this->CheckFrameSampleDistance(delta, this->MaximumSamplesPerRay))
  {
    return DrawNothing;
  }
  vtkImageData* input = vtkImageData::SafeDownCast(this->GetInput());
  // The slices are anchored to the whole volume's box (the input's, or WholeBounds' when it is a
  // piece of a larger volume), so that every piece samples on the same slices.
  double bounds[6];
  input->GetBounds(bounds);
  this->CoverWholeBounds(bounds);
  const double lo[3] = { bounds[0], bounds[2], bounds[4] };
  const double hi[3] = { bounds[1], bounds[3], bounds[5] };

  // What the adaptive ray does not model goes to VTK's stock path.
  vtkVolumeProperty* property = vol->GetProperty();
  std::string reason = this->GetCompositeFallbackReason(vol, scalars, "the adaptive ray");
  if (reason.empty() && property->GetShade(0))
  {
    reason = "the adaptive ray does not shade";
  }
  if (reason.empty() && cellFlag)
  {
    reason = "the adaptive ray takes point scalars; these are cell data";
  }
  if (reason.empty() && this->Cropping)
  {
    reason = "the adaptive ray does not support cropping";
  }
  if (reason.empty() && this->ClippingPlanes && this->ClippingPlanes->GetNumberOfItems() > 0)
  {
    reason = "the adaptive ray does not support clipping planes";
  }
  if (!reason.empty())
  {
    this->WarnFallbackOnce(reason.c_str());
    return DrawStock;
  }
  this->ClearFallbackWarning();

  double dataRange[2], range[2];
  if (!vtkPreIntegrationTable::ComputeScalarRange(scalars, dataRange, range, this->ScalarRange))
  {
    vtkErrorMacro("The scalars hold no finite value (all NaN); not drawing.");
    return DrawNothing;
  }

  // The volume in bricks packed into atlas pages (an axis may exceed the GPU's 3D texture
  // size, the volume a texture's bytes); 8-bit data go up as 16-bit texels of the same values
  // (finer interpolation), and the layout leaves room for the oracle's float texels.
  const bool oracleWanted = this->OracleMode == ORACLE_ARRAY && this->MaximumLevel > 0;
  if (!this->PrepareBricks(
        ren, scalars, dims, 0, vtkOpenGLVolumeBricks::WIDE, true, oracleWanted ? 4 : 0, 0, true))
  {
    return DrawNothing;
  }
  this->SetTextureScalars(nullptr);

  // The oracle, or d = 1 after a warning when it cannot be used.
  vtkOpenGLRenderWindow* context = vtkOpenGLRenderWindow::SafeDownCast(ren->GetRenderWindow());
  internal.UseOracle = false;
  // About the oracle or the counter; given once while it lasts.
  std::string warning;
  // With l_max 0 every slice is sampled whatever the oracle says: it is not read.
  if (oracleWanted)
  {
    std::string why;
    vtkDataArray* oracle =
      this->OracleArrayName ? input->GetPointData()->GetArray(this->OracleArrayName) : nullptr;
    const vtkIdType points = input->GetNumberOfPoints();
    if (!oracle)
    {
      why = std::string("the input has no point array \"") +
        (this->OracleArrayName ? this->OracleArrayName : "") + "\" (OracleArrayName)";
    }
    else if (oracle->GetNumberOfComponents() != 1 || oracle->GetNumberOfTuples() != points)
    {
      why = "the oracle array must hold one component per point; it has " +
        std::to_string(oracle->GetNumberOfComponents()) + " x " +
        std::to_string(oracle->GetNumberOfTuples()) + " values for " + std::to_string(points) +
        " points";
    }
    else if (cellFlag)
    {
      why = "the oracle is a point array, the scalars are cell data";
    }
    else if (internal.CheckedOracle != oracle || internal.CheckedOracleTime != oracle->GetMTime())
    {
      internal.CheckedOracle = nullptr;
      for (vtkIdType i = 0; i < points && why.empty(); ++i)
      {
        if (!std::isfinite(oracle->GetComponent(i, 0)))
        {
          why = "the oracle array has a value that is not finite (point " + std::to_string(i) + ")";
        }
      }
      if (why.empty())
      {
        internal.CheckedOracle = oracle;
        internal.CheckedOracleTime = oracle->GetMTime();
      }
    }
    if (why.empty())
    {
      vtkOpenGLVolumeBricks* bricks = internal.OracleBricks;
      bricks->SetPrecision(vtkOpenGLVolumeBricks::FLOAT32);
      bricks->SetFiltered(true);
      bricks->SetAtlas(true);
      if (!bricks->Update(context, oracle, dims, why, this->GetBricks()->GetLayout()))
      {
        why = "the oracle cannot be uploaded: " + why;
      }
      else if (bricks->GetNumberOfTextures() != this->GetBricks()->GetNumberOfTextures())
      {
        // Both are planned for the oracle's bytes per point, so this is not expected.
        why = "the oracle's textures do not match the volume's";
      }
      else
      {
        this->OracleTextureMemorySize = bricks->GetMemorySize();
      }
    }
    if (why.empty())
    {
      internal.UseOracle = true;
    }
    else
    {
      internal.OracleBricks->ReleaseGraphicsResources(context);
      this->OracleTextureMemorySize = 0;
      warning += why + "; the oracle is ignored and every slice is sampled (d = 1).";
    }
  }
  this->LastFrameUsedOracle = internal.UseOracle;

  // The tables: 2^l_max lengths with the oracle, one without (d = 1 samples every slice).
  const int layers = internal.UseOracle ? (1 << this->MaximumLevel) : 1;
  auto& tables = internal.Tables;
  if (static_cast<int>(tables.size()) < layers)
  {
    tables.resize(static_cast<size_t>(layers));
  }
  for (int k = 0; k < layers; ++k)
  {
    if (!tables[k])
    {
      tables[k] = vtkSmartPointer<vtkFirstOrderPreIntegrationTable>::New();
    }
    tables[k]->SetVolumeProperty(property);
  }
  vtkVolumeTransferFunctionSampler* sampler = tables[0]->GetSampler();
  if (!sampler->Prepare())
  {
    vtkErrorMacro("The transfer functions cannot be pre-integrated; not drawing.");
    return DrawNothing;
  }
  if (!(sampler->GetMaximumOpacity(dataRange[0], dataRange[1]) > 0.0))
  {
    std::ostringstream message;
    message << "The scalar opacity is zero over the data range [" << dataRange[0] << ", "
            << dataRange[1] << "]: the image is transparent.";
    this->WarnEmptyOnce(message.str());
  }
  else
  {
    this->ClearEmptyWarning();
  }
  // 256 entries unless set: fewer, chosen from the transfer function's narrowest feature, blur
  // the integrals of long, opaque segments even under smooth transfer functions.
  int size = this->TableSize > 0 ? this->TableSize : 256;
  // The layers are tiles of one 2D texture, columns x rows of them (bilinear lookups: a 3D
  // texture would filter 8 texels per lookup instead of 4).
  const int columns = 1 << ((static_cast<int>(std::log2(layers)) + 1) / 2);
  const int rows = layers / columns;
  const int limit2D = vtkTextureObject::GetMaximumTextureSize(context);
  if (limit2D > 0 && size * columns > limit2D)
  {
    const int reduced = limit2D / columns;
    vtkWarningMacro("Tables of " << size << " entries in " << columns << " x " << rows
                                 << " tiles exceed the OpenGL texture limit; using " << reduced
                                 << " entries.");
    size = reduced;
  }
  auto bytesOf = [layers](int n, int bytesPerChannel)
  { return 4.0 * bytesPerChannel * static_cast<double>(n) * n * layers; };
  if (bytesOf(size, 2) > TableMemoryLimit)
  {
    int reduced = size;
    while (reduced > 16 && bytesOf(reduced, 2) > TableMemoryLimit)
    {
      reduced /= 2;
    }
    vtkWarningMacro("Tables of " << size << " x " << size << " entries in " << layers
                                 << " layers exceed " << TableMemoryLimit / 1048576.0
                                 << " MiB; using " << reduced << " entries per axis.");
    size = reduced;
  }
  const unsigned int format = bytesOf(size, 4) > Float32TableLimit ? GL_RGBA16F : GL_RGBA32F;
  const double start = vtkTimerLog::GetUniversalTime();
  bool changed = internal.UploadedLayers != layers || internal.UploadedFormat != format ||
    internal.TableTexture->GetContext() != context || internal.TableTexture->GetHandle() == 0 ||
    static_cast<int>(internal.UploadedBuilds.size()) != layers;
  for (int k = 0; k < layers; ++k)
  {
    vtkFirstOrderPreIntegrationTable* table = tables[k];
    table->SetSegmentLength((k + 1) * delta);
    table->SetScalarRange(range);
    table->SetTableSize(size);
    if (!table->Update())
    {
      vtkErrorMacro(
        "The pre-integration table for " << k + 1 << " slices could not be built; not drawing.");
      return DrawNothing;
    }
    changed = changed || internal.UploadedBuilds[k] != table->GetBuildCount();
  }
  if (changed)
  {
    // Layer k - 1 (segments of k slices) is tile (k - 1) mod columns, (k - 1) / columns.
    const size_t rowValues = static_cast<size_t>(size) * 4;
    const size_t width = rowValues * columns;
    std::vector<float> tiles(width * size * rows);
    internal.UploadedBuilds.assign(static_cast<size_t>(layers), -1);
    for (int k = 0; k < layers; ++k)
    {
      const float* values = tables[k]->GetTable()->GetPointer(0);
      const size_t column = static_cast<size_t>(k % columns),
                   row = static_cast<size_t>(k / columns);
      for (size_t back = 0; back < static_cast<size_t>(size); ++back)
      {
        std::copy(values + back * rowValues,
          values + (back + 1) * rowValues,
          tiles.begin() + (row * size + back) * width + column * rowValues);
      }
    }
    vtkTextureObject* texture = internal.TableTexture;
    texture->ReleaseGraphicsResources(context);
    texture->SetContext(context);
    texture->SetInternalFormat(format);
    texture->SetFormat(GL_RGBA);
    texture->SetDataType(GL_FLOAT);
    if (!texture->Create2DFromRaw(size * columns, size * rows, 4, VTK_FLOAT, tiles.data()))
    {
      vtkErrorMacro("Could not create the " << size * columns << " x " << size * rows
                                            << " table texture; not drawing.");
      internal.UploadedLayers = 0;
      return DrawNothing;
    }
    texture->SetWrapS(vtkTextureObject::ClampToEdge);
    texture->SetWrapT(vtkTextureObject::ClampToEdge);
    // Bilinear in the scalars; lookups stay between a tile's outer texel centres.
    texture->SetMinificationFilter(vtkTextureObject::Linear);
    texture->SetMagnificationFilter(vtkTextureObject::Linear);
    for (int k = 0; k < layers; ++k)
    {
      internal.UploadedBuilds[k] = tables[k]->GetBuildCount();
    }
    internal.UploadedLayers = layers;
    internal.TileGrid[0] = static_cast<float>(columns);
    internal.TileGrid[1] = static_cast<float>(rows);
    internal.UploadedFormat = format;
    this->TableBuildCount++;
    this->LastTableBuildTime = vtkTimerLog::GetUniversalTime() - start;
    this->TableTextureMemorySize =
      static_cast<vtkIdType>(bytesOf(size, format == GL_RGBA32F ? 4 : 2));
  }
  this->EffectiveTableSize = size;
  this->NumberOfTables = layers;

  // raw texture value -> data value -> table texture coordinate (entries at texel centres).
  double scale, shift;
  this->GetBricks()->GetValueMapping(scale, shift);
  const double toIndex = (size - 1.0) / (range[1] - range[0]);
  internal.RawToTable[0] = static_cast<float>(scale * toIndex / size);
  internal.RawToTable[1] = static_cast<float>(((shift - range[0]) * toIndex + 0.5) / size);

  // Slice 0 through the box's point nearest to the camera, in dataset coordinates (where the
  // shader's rays and VTK's sample distance live).
  vtkCamera* camera = ren->GetActiveCamera();
  vtkNew<vtkMatrix4x4> toData;
  vtkMatrix4x4::Invert(vol->GetMatrix(), toData);
  double position[4] = { 0.0, 0.0, 0.0, 1.0 };
  camera->GetPosition(position);
  double eye[4];
  toData->MultiplyPoint(position, eye);
  internal.Perspective = camera->GetParallelProjection() ? 0 : 1;
  if (internal.Perspective)
  {
    double d2 = 0.0;
    for (int a = 0; a < 3; ++a)
    {
      const double nearest = std::min(std::max(eye[a], lo[a]), hi[a]);
      d2 += (eye[a] - nearest) * (eye[a] - nearest);
    }
    internal.SliceStart = static_cast<float>(std::sqrt(d2));
  }
  else
  {
    double projection[4] = { 0.0, 0.0, 0.0, 0.0 };
    camera->GetDirectionOfProjection(projection);
    double direction[4];
    toData->MultiplyPoint(projection, direction);
    double nearest = std::numeric_limits<double>::infinity();
    for (int c = 0; c < 8; ++c)
    {
      const double corner[3] = {
        (c & 1) ? hi[0] : lo[0], (c & 2) ? hi[1] : lo[1], (c & 4) ? hi[2] : lo[2]
      };
      const double depth = vtkMath::Dot(corner, direction);
      if (depth < nearest)
      {
        nearest = depth;
        std::copy(corner, corner + 3, internal.SliceOrigin);
      }
    }
  }

  // Atomic counters need OpenGL 4.2 or the extension.
  internal.CountingThisFrame =
    this->CountSamples && (GLEW_VERSION_4_2 || glewIsSupported("GL_ARB_shader_atomic_counters"));
  const std::string switches = std::string("#define HOVR_ORACLE ") +
    (internal.UseOracle ? "1" : "0") + "\n#define HOVR_COUNT_SAMPLES " +
    (internal.CountingThisFrame ? "1" : "0") + "\n#define HOVR_TILES " + (layers > 1 ? "1" : "0") +
    "\n#define HOVR_TRICUBIC " +
    (this->Reconstruction == RECONSTRUCTION_TRICUBIC_BSPLINE ? "1" : "0") + "\n" +
    this->GetBricks()->GetAtlasDefines() + this->GetBricks()->GetAtlasSamplerCode("hovr_volume") +
    this->GetBricks()->GetAtlasSamplerCode("hovr_oracle");
  if (switches != internal.Switches)
  {
    internal.Switches = switches;
    this->ExtensionShaderModified();
  }
  if (this->CountSamples && !internal.CountingThisFrame)
  {
    warning += " This OpenGL has no atomic counters: samples are not counted.";
  }
  if (!warning.empty() && warning != internal.Warning)
  {
    vtkWarningMacro(<< warning);
  }
  internal.Warning = warning;
  return DrawWithExtension;
}

//------------------------------------------------------------------------------
void vtkAdaptiveRayVolumeMapper::ActivateExtensionTextures()
{
  Internals& internal = *this->Internal;
  internal.TableTexture->Activate();
  if (internal.UseOracle)
  {
    internal.OracleBricks->Activate(0);
  }
  if (internal.CountingThisFrame)
  {
    vtkOpenGLRenderWindow* context = internal.TableTexture->GetContext();
    if (internal.CounterBuffer == 0 || internal.CounterContext != context)
    {
      internal.CounterBuffer = 0;
      glGenBuffers(1, &internal.CounterBuffer);
      internal.CounterContext = context;
    }
    const GLuint zero = 0;
    glBindBuffer(GL_ATOMIC_COUNTER_BUFFER, internal.CounterBuffer);
    glBufferData(GL_ATOMIC_COUNTER_BUFFER, sizeof(GLuint), &zero, GL_DYNAMIC_READ);
    glBindBufferBase(GL_ATOMIC_COUNTER_BUFFER, 0, internal.CounterBuffer);
  }
}

//------------------------------------------------------------------------------
void vtkAdaptiveRayVolumeMapper::DeactivateExtensionTextures()
{
  Internals& internal = *this->Internal;
  internal.TableTexture->Deactivate();
  if (internal.UseOracle)
  {
    internal.OracleBricks->Deactivate(0);
  }
  if (internal.CountingThisFrame && internal.CounterBuffer != 0)
  {
    glMemoryBarrier(GL_ATOMIC_COUNTER_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
    GLuint count = 0;
    glBindBuffer(GL_ATOMIC_COUNTER_BUFFER, internal.CounterBuffer);
    glGetBufferSubData(GL_ATOMIC_COUNTER_BUFFER, 0, sizeof(GLuint), &count);
    glBindBufferBase(GL_ATOMIC_COUNTER_BUFFER, 0, 0);
    glBindBuffer(GL_ATOMIC_COUNTER_BUFFER, 0);
    this->LastFrameSampleCount = static_cast<vtkIdType>(count);
  }
}

//------------------------------------------------------------------------------
bool vtkAdaptiveRayVolumeMapper::ReplaceExtensionShaderValues(std::string&,
  std::string& fragmentShader,
  vtkVolume*)
{
  using Self = vtkExtensibleGPUVolumeRayCastMapper;
  Internals& internal = *this->Internal;
  bool ok = true;
  if (internal.CountingThisFrame)
  {
    // After the #version line VTK puts at this tag; only preprocessor lines come before.
    ok = Self::ReplaceShaderTag(fragmentShader,
      "//VTK::System::Dec",
      "#extension GL_ARB_shader_atomic_counters : require",
      Self::AfterTag);
  }
  ok = ok &&
    Self::ReplaceShaderTag(
      fragmentShader, "//VTK::Shading::Init", "hovr_adaptiveInit();", Self::ReplaceTag);
  ok = ok &&
    Self::ReplaceShaderTag(
      fragmentShader, "//VTK::Shading::Impl", "hovr_adaptiveStep();", Self::ReplaceTag);
  ok = ok &&
    Self::ReplaceShaderTag(
      fragmentShader, "//VTK::Shading::Exit", "hovr_adaptiveExit();", Self::ReplaceTag);
  // After computeRayDirection(), which the slice coordinate uses.
  ok = ok &&
    Self::ReplaceShaderTag(fragmentShader,
      "//VTK::ComputeRayDirection::Dec",
      internal.Switches + hovrVolumeAtlas + hovrAdaptiveRay,
      Self::AfterTag);
  if (!ok)
  {
    vtkErrorMacro("The ray caster's shader template lacks a tag that the adaptive ray replaces.");
  }
  return ok;
}

//------------------------------------------------------------------------------
void vtkAdaptiveRayVolumeMapper::SetExtensionShaderParameters(vtkShaderProgram* program, vtkVolume*)
{
  Internals& internal = *this->Internal;
  program->SetUniformi("hovr_adaptiveTables", internal.TableTexture->GetTextureUnit());
  this->GetBricks()->SetSamplerUniform(program, "hovr_volume", 0);
  this->GetBricks()->SetAtlasUniforms(program);
  program->SetUniformf("hovr_tableLayers", static_cast<float>(internal.UploadedLayers));
  program->SetUniform2f("hovr_tileGrid", internal.TileGrid);
  const float tileScale[2] = { 1.0f / internal.TileGrid[0], 1.0f / internal.TileGrid[1] };
  program->SetUniform2f("hovr_tileScale", tileScale);
  program->SetUniformf("hovr_tileMargin", 0.5f / this->EffectiveTableSize);
  program->SetUniformf("hovr_maximumSpan", static_cast<float>(1 << this->MaximumLevel));
  program->SetUniform2f("hovr_rawToTable", internal.RawToTable);
  program->SetUniformi("hovr_perspective", internal.Perspective);
  program->SetUniform3f("hovr_sliceOrigin", internal.SliceOrigin);
  // A piece with ghost points walks in its own points only (see the GLSL).
  const int* owned = this->OwnedExtent;
  const bool some = owned[0] <= owned[1] && owned[2] <= owned[3] && owned[4] <= owned[5];
  int lo[3], hi[3];
  this->GetOwnedIndexBox(lo, hi);
  const float ownedLo[3] = {
    static_cast<float>(lo[0]), static_cast<float>(lo[1]), static_cast<float>(lo[2])
  };
  const float ownedHi[3] = {
    static_cast<float>(hi[0]), static_cast<float>(hi[1]), static_cast<float>(hi[2])
  };
  program->SetUniformi("hovr_owned", some ? 1 : 0);
  program->SetUniform3f("hovr_ownedLo", ownedLo);
  program->SetUniform3f("hovr_ownedHi", ownedHi);
  program->SetUniformf("hovr_sliceStart", internal.SliceStart);
  if (internal.UseOracle)
  {
    internal.OracleBricks->SetSamplerUniform(program, "hovr_oracle", 0);
    program->SetUniformf("hovr_oracleScale", static_cast<float>(1.0 / this->SampleDistance));
  }
}

//------------------------------------------------------------------------------
void vtkAdaptiveRayVolumeMapper::ReleaseExtensionResources(vtkWindow* window)
{
  Internals& internal = *this->Internal;
  internal.TableTexture->ReleaseGraphicsResources(window);
  internal.OracleBricks->ReleaseGraphicsResources(window);
  internal.UploadedLayers = 0;
  internal.UploadedBuilds.clear();
  this->TableTextureMemorySize = 0;
  this->OracleTextureMemorySize = 0;
  if (internal.CounterBuffer != 0 && internal.CounterContext == window)
  {
    internal.CounterContext->MakeCurrent();
    glDeleteBuffers(1, &internal.CounterBuffer);
  }
  internal.CounterBuffer = 0;
  internal.CounterContext = nullptr;
}

//------------------------------------------------------------------------------
void vtkAdaptiveRayVolumeMapper::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "MaximumLevel: " << this->MaximumLevel << "\n";
  os << indent << "OracleMode: " << (this->OracleMode == ORACLE_ARRAY ? "ARRAY" : "MINIMUM")
     << "\n";
  os << indent << "Reconstruction: "
     << (this->Reconstruction == RECONSTRUCTION_TRILINEAR ? "TRILINEAR" : "TRICUBIC_BSPLINE")
     << "\n";
  os << indent << "OracleArrayName: " << (this->OracleArrayName ? this->OracleArrayName : "(none)")
     << "\n";
  os << indent << "TableSize: " << this->TableSize << "\n";
  os << indent << "MaximumSamplesPerRay: " << this->MaximumSamplesPerRay << "\n";
  os << indent << "CountSamples: " << this->CountSamples << "\n";
  os << indent << "LastFrameSampleCount: " << this->LastFrameSampleCount << "\n";
  os << indent << "TableBuildCount: " << this->TableBuildCount << "\n";
  os << indent << "LastTableBuildTime: " << this->LastTableBuildTime << "\n";
  os << indent << "EffectiveTableSize: " << this->EffectiveTableSize << "\n";
  os << indent << "NumberOfTables: " << this->NumberOfTables << "\n";
  os << indent << "TableTextureMemorySize: " << this->TableTextureMemorySize << "\n";
  os << indent << "OracleTextureMemorySize: " << this->OracleTextureMemorySize << "\n";
  os << indent << "LastFrameUsedOracle: " << this->LastFrameUsedOracle << "\n";
}
