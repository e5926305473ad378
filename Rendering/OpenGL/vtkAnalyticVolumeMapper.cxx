// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
#include "vtkAnalyticVolumeMapper.h"

#include "vtkCamera.h"
#include "vtkCameraRayModel.h"
#include "vtkContourValues.h"
#include "vtkDataArray.h"
#include "vtkDoubleArray.h"
#include "vtkFloatArray.h"
#include "vtkImageData.h"
#include "vtkObjectFactory.h"
#include "vtkOpenGLRenderWindow.h"
#include "vtkPiecewiseFunction.h"
#include "vtkRenderer.h"
#include "vtkShaderProgram.h"
#include "vtkTextureObject.h"
#include "vtkVolume.h"
#include "vtkVolumeProperty.h"
#include "vtk_glew.h"

#include "hovrAnalytic.h"       // the GLSL of the analytic ray caster
#include "hovrAnalyticCommon.h" // the GLSL both modes share

#include <algorithm>
#include <cmath>
#include <limits>
#include <new>
#include <sstream>

vtkStandardNewMacro(vtkAnalyticVolumeMapper);

namespace
{
// Largest world coordinate (volume bounds, camera position) of an analytic frame: its square
// and sums of squares stay below float's largest value.
constexpr double MaximumCoordinate = 1e18;

bool IsAnalyticBlend(int blend)
{
  return blend == vtkVolumeMapper::ISOSURFACE_BLEND ||
    blend == vtkVolumeMapper::MAXIMUM_INTENSITY_BLEND ||
    blend == vtkVolumeMapper::MINIMUM_INTENSITY_BLEND;
}

// Per block of size^3 cells, (min, max) of the raw texture values of its points, the points
// on its far faces included (they are corners of its cells); NaN ignored, so a NaN-only block
// gets an empty range (+inf, -inf), and a block with some NaN the whole line (-inf, +inf). Widened
// by a few float roundings, because the texture's own conversion of integers to normalised floats
// may round the other way.
void ComputeBlockRanges(vtkDataArray* scalars,
  const int dims[3],
  int size,
  double scale,
  double shift,
  const int blocks[3],
  std::vector<float>& ranges)
{
  const double inf = std::numeric_limits<double>::infinity();
  std::vector<double> lo(static_cast<size_t>(blocks[0]) * blocks[1] * blocks[2], inf);
  std::vector<double> hi(lo.size(), -inf);
  std::vector<char> partial(lo.size(), 0);
  for (int k = 0; k < dims[2]; ++k)
  {
    // A point on a block boundary belongs to the blocks on both sides.
    const int bk0 = std::min(k / size, blocks[2] - 1), bk1 = std::max((k - 1) / size, 0);
    for (int j = 0; j < dims[1]; ++j)
    {
      const int bj0 = std::min(j / size, blocks[1] - 1), bj1 = std::max((j - 1) / size, 0);
      for (int i = 0; i < dims[0]; ++i)
      {
        const double value = scalars->GetComponent(
          i + static_cast<vtkIdType>(dims[0]) * (j + static_cast<vtkIdType>(dims[1]) * k), 0);
        const bool nan = std::isnan(value);
        const double raw = (value - shift) / scale;
        const int bi0 = std::min(i / size, blocks[0] - 1), bi1 = std::max((i - 1) / size, 0);
        for (int bk = std::min(bk0, bk1); bk <= std::max(bk0, bk1); ++bk)
        {
          for (int bj = std::min(bj0, bj1); bj <= std::max(bj0, bj1); ++bj)
          {
            for (int bi = std::min(bi0, bi1); bi <= std::max(bi0, bi1); ++bi)
            {
              const size_t b =
                bi + static_cast<size_t>(blocks[0]) * (bj + static_cast<size_t>(blocks[1]) * bk);
              if (nan)
              {
                partial[b] = 1;
                continue;
              }
              lo[b] = std::min(lo[b], raw);
              hi[b] = std::max(hi[b], raw);
            }
          }
        }
      }
    }
  }
  ranges.resize(2 * lo.size());
  for (size_t b = 0; b < lo.size(); ++b)
  {
    if (partial[b] && std::isfinite(lo[b]))
    {
      // Some cells of the block are NaN (transparent), so a ray may meet none of its values:
      // its range bounds nothing along a ray (see hovr_blockBound).
      lo[b] = -inf;
      hi[b] = inf;
    }
    const double margin = 1e-6 * std::max(std::abs(lo[b]), std::abs(hi[b]));
    ranges[2 * b] = static_cast<float>(std::isfinite(lo[b]) ? lo[b] - margin : lo[b]);
    ranges[2 * b + 1] = static_cast<float>(std::isfinite(hi[b]) ? hi[b] + margin : hi[b]);
  }
}

// The 4 corners in x and y of each point of a slice, x fastest (see UpdateCornerTexture).
template <typename T, typename Convert>
void PackCorners(vtkDataArray* scalars, const int dims[3], Convert convert, std::vector<T>& out)
{
  const vtkIdType nx = dims[0], ny = dims[1];
  out.resize(static_cast<size_t>(nx - 1) * (ny - 1) * dims[2] * 4);
  T* texel = out.data();
  for (int k = 0; k < dims[2]; ++k)
  {
    for (vtkIdType j = 0; j + 1 < ny; ++j)
    {
      const vtkIdType row = nx * (j + ny * k);
      for (vtkIdType i = 0; i + 1 < nx; ++i, texel += 4)
      {
        texel[0] = convert(scalars->GetComponent(row + i, 0));
        texel[1] = convert(scalars->GetComponent(row + i + 1, 0));
        texel[2] = convert(scalars->GetComponent(row + nx + i, 0));
        texel[3] = convert(scalars->GetComponent(row + nx + i + 1, 0));
      }
    }
  }
}
}

//------------------------------------------------------------------------------
vtkAnalyticVolumeMapper::vtkAnalyticVolumeMapper()
  : BlockTexture(vtkTextureObject::New())
  , RayModel(vtkCameraRayModel::New())
  , CornerTexture(vtkTextureObject::New())
{
}

//------------------------------------------------------------------------------
vtkAnalyticVolumeMapper::~vtkAnalyticVolumeMapper()
{
  this->BlockTexture->Delete();
  this->RayModel->Delete();
  this->CornerTexture->Delete();
}

//------------------------------------------------------------------------------
void vtkAnalyticVolumeMapper::UpdateRayFrame(vtkRenderer* ren, vtkVolume* vol)
{
  // VTK's shader reaches a ray's points through float matrices from window to texture space,
  // with eye-space values of the camera's distance: a ray's points round at the scale of that
  // distance, which a slanted surface magnifies in depth beyond the 1e-3 voxel the analytic hit
  // is held to. The camera model gives each ray's point near the volume and its direction in
  // double, so float only rounds at the volume's own scale.
  this->RayFrameInUse = 0;
  vtkImageData* input = vtkImageData::SafeDownCast(this->GetInput());
  vtkCamera* camera = ren->GetActiveCamera();
  int size[2], lowerLeft[2];
  ren->GetTiledSizeAndOrigin(&size[0], &size[1], &lowerLeft[0], &lowerLeft[1]);
  if (!input || !camera || size[0] < 1 || size[1] < 1)
  {
    return;
  }
  this->RayModel->SetCamera(camera);
  this->RayModel->SetImageSize(size);
  double frame[5][3];
  bool perspective = false;
  // Cameras the model does not describe (window centre, shear, explicit projection) keep
  // VTK's matrices: 1e-9 in normalised device coordinates is far below a pixel.
  if (!this->RayModel->Prepare() || this->RayModel->ComputeProjectionMismatch() > 1e-9 ||
    !this->RayModel->GetGridRayFrame(
      input, vol->GetMatrix(), frame[0], frame[1], frame[2], frame[3], frame[4], perspective))
  {
    return;
  }
  for (int v = 0; v < 5; ++v)
  {
    std::copy(frame[v], frame[v] + 3, this->RayFrame[v]);
  }
  this->RayPixelCentre[0] = 0.5f * size[0];
  this->RayPixelCentre[1] = 0.5f * size[1];
  this->RayPerspective = perspective ? 1 : 0;
  this->RayFrameInUse = 1;
}

//------------------------------------------------------------------------------
bool vtkAnalyticVolumeMapper::UpdateBlockRanges(vtkRenderer* ren,
  vtkDataArray* scalars,
  const int dims[3],
  double scale,
  double shift)
{
  if (this->BlockScalars == scalars && this->BlockBuiltSize == this->BlockSize &&
    this->BlockBuildTime > scalars->GetMTime() && this->BlockTexture->GetHandle())
  {
    return true;
  }
  int blocks[3];
  for (int a = 0; a < 3; ++a)
  {
    blocks[a] = (dims[a] - 2) / this->BlockSize + 1; // cells dims-1, rounded up
  }
  std::vector<float> ranges;
  ComputeBlockRanges(scalars, dims, this->BlockSize, scale, shift, blocks, ranges);
  vtkOpenGLRenderWindow* context = vtkOpenGLRenderWindow::SafeDownCast(ren->GetRenderWindow());
  this->BlockTexture->ReleaseGraphicsResources(context);
  this->BlockTexture->SetInternalFormat(GL_RG32F);
  this->BlockTexture->SetFormat(GL_RG);
  this->BlockTexture->SetDataType(GL_FLOAT);
  std::string why;
  if (!this->CreateTexture3D(
        this->BlockTexture, context, blocks, 2, VTK_FLOAT, ranges.data(), "block-range texture", why))
  {
    vtkErrorMacro(<< why << "; not drawing.");
    this->BlockTextureMemorySize = 0;
    return false;
  }
  this->BlockTexture->SetMinificationFilter(vtkTextureObject::Nearest);
  this->BlockTexture->SetMagnificationFilter(vtkTextureObject::Nearest);

  this->BlockTextureMemorySize = static_cast<vtkIdType>(ranges.size()) * sizeof(float);
  this->BlockScalars = scalars;
  this->BlockBuiltSize = this->BlockSize;
  this->BlockBuildTime.Modified();
  return true;
}

//------------------------------------------------------------------------------
bool vtkAnalyticVolumeMapper::UpdateCornerTexture(vtkRenderer* ren,
  vtkDataArray* scalars,
  const int dims[3],
  double scale,
  double shift)
{
  if (this->CornerScalars == scalars && this->CornerBuildTime > scalars->GetMTime() &&
    this->CornerTexture->GetHandle())
  {
    return true;
  }
  vtkOpenGLRenderWindow* context = vtkOpenGLRenderWindow::SafeDownCast(ren->GetRenderWindow());
  // Texel (i, j, k), i < nx - 1, j < ny - 1, holds the points (i, j), (i + 1, j), (i, j + 1)
  // and (i + 1, j + 1) of slice k: a cell's 8 corners are 2 fetches instead of 8. 8- and
  // 16-bit unsigned data keep their type (the normalised values equal those of VTK's own
  // texture); other types are stored as the float raw values of GetTextureValueMapping.
  const int type = scalars->GetDataType();
  const size_t texels = static_cast<size_t>(dims[0] - 1) * (dims[1] - 1) * dims[2];
  this->CornerTexture->ReleaseGraphicsResources(context);
  this->CornerTexture->SetFormat(GL_RGBA);
  bool created = false;
  // 4 values per point: in the data's type for 8- and 16-bit unsigned data, else float.
  const size_t bytes = texels * 4 *
    (type == VTK_UNSIGNED_CHAR       ? 1
        : type == VTK_UNSIGNED_SHORT ? 2
                                     : 4);
  std::string failure = "the texture could not be created";
  try
  {
    // One texel type per scalar type: its conversion, GL internal format and data type.
    auto upload = [&](auto convert, int internalFormat, int glType, int vtkType)
    {
      std::vector<decltype(convert(0.0))> packed;
      PackCorners(scalars, dims, convert, packed);
      this->CornerTexture->SetInternalFormat(internalFormat);
      this->CornerTexture->SetDataType(glType);
      const int size[3] = { dims[0] - 1, dims[1] - 1, dims[2] };
      return this->CreateTexture3D(this->CornerTexture, context, size, 4, vtkType,
        packed.data(), "packed-corner texture", failure);
    };
    if (type == VTK_UNSIGNED_CHAR)
    {
      created = upload([](double v) { return static_cast<unsigned char>(v); },
        GL_RGBA8,
        GL_UNSIGNED_BYTE,
        VTK_UNSIGNED_CHAR);
    }
    else if (type == VTK_UNSIGNED_SHORT)
    {
      created = upload([](double v) { return static_cast<unsigned short>(v); },
        GL_RGBA16,
        GL_UNSIGNED_SHORT,
        VTK_UNSIGNED_SHORT);
    }
    else
    {
      created = upload([=](double v) { return static_cast<float>((v - shift) / scale); },
        GL_RGBA32F,
        GL_FLOAT,
        VTK_FLOAT);
    }
  }
  catch (const std::bad_alloc&)
  {
    failure = "not enough memory";
  }
  if (!created)
  {
    vtkWarningMacro("Could not make the packed copy of the volume's corners ("
      << dims[0] - 1 << " x " << dims[1] - 1 << " x " << dims[2] << " texels, "
      << std::ceil(bytes / 1048576.0) << " MiB: " << failure
      << "); reading each cell's 8 corners from the volume texture instead (same image).");
    this->CornerTexture->ReleaseGraphicsResources(context);
    this->CornerTextureMemorySize = 0;
    return false;
  }
  this->CornerTexture->SetMinificationFilter(vtkTextureObject::Nearest);
  this->CornerTexture->SetMagnificationFilter(vtkTextureObject::Nearest);
  this->CornerTextureMemorySize = static_cast<vtkIdType>(bytes);
  this->CornerScalars = scalars;
  this->CornerBuildTime.Modified();
  return true;
}

//------------------------------------------------------------------------------
void vtkAnalyticVolumeMapper::ActivateExtensionTextures()
{
  if (this->Method == ANALYTIC && this->BlockSize > 0)
  {
    this->BlockTexture->Activate();
  }
  if (this->PackedThisFrame)
  {
    this->CornerTexture->Activate();
  }
}

//------------------------------------------------------------------------------
void vtkAnalyticVolumeMapper::DeactivateExtensionTextures()
{
  if (this->Method == ANALYTIC && this->BlockSize > 0)
  {
    this->BlockTexture->Deactivate();
  }
  if (this->PackedThisFrame)
  {
    this->CornerTexture->Deactivate();
  }
}

//------------------------------------------------------------------------------
void vtkAnalyticVolumeMapper::ReleaseExtensionResources(vtkWindow* window)
{
  this->BlockTexture->ReleaseGraphicsResources(window);
  this->CornerTexture->ReleaseGraphicsResources(window);
  this->BlockScalars = nullptr;
  this->CornerScalars = nullptr;
  this->BlockTextureMemorySize = 0;
  this->CornerTextureMemorySize = 0;
}

//------------------------------------------------------------------------------
bool vtkAnalyticVolumeMapper::HasNaN(vtkDataArray* scalars)
{
  if (scalars != this->NaNScalars || scalars->GetMTime() > this->NaNTime)
  {
    const vtkIdType n = scalars->GetNumberOfValues();
    bool found = false;
    if (auto* f = vtkFloatArray::SafeDownCast(scalars))
    {
      found =
        std::any_of(f->GetPointer(0), f->GetPointer(0) + n, [](float v) { return std::isnan(v); });
    }
    else if (auto* d = vtkDoubleArray::SafeDownCast(scalars))
    {
      found =
        std::any_of(d->GetPointer(0), d->GetPointer(0) + n, [](double v) { return std::isnan(v); });
    }
    else if (scalars->GetDataType() == VTK_FLOAT || scalars->GetDataType() == VTK_DOUBLE)
    {
      for (vtkIdType i = 0; i < n && !found; ++i)
      {
        found = std::isnan(scalars->GetComponent(i / scalars->GetNumberOfComponents(),
          static_cast<int>(i % scalars->GetNumberOfComponents())));
      }
    }
    this->NaNScalars = scalars;
    this->NaNTime = scalars->GetMTime();
    this->ScalarsHaveNaN = found;
  }
  return this->ScalarsHaveNaN;
}

//------------------------------------------------------------------------------
const char* vtkAnalyticVolumeMapper::GetStockFallbackReason(vtkVolume* vol,
  vtkDataArray* scalars,
  int cellFlag)
{
  vtkVolumeProperty* property = vol->GetProperty();
  if (scalars->GetNumberOfComponents() != 1)
  {
    return "analytic rendering needs single-component scalars";
  }
  if (cellFlag)
  {
    return "analytic rendering interpolates point scalars; these are cell scalars";
  }
  if (this->GetCropping())
  {
    return "analytic rendering does not support cropping";
  }
  if (property->GetTransferFunctionMode() != vtkVolumeProperty::TF_1D)
  {
    return "analytic rendering does not support 2D transfer functions";
  }
  return nullptr;
}

//------------------------------------------------------------------------------
vtkExtensibleGPUVolumeRayCastMapper::FramePlan vtkAnalyticVolumeMapper::PrepareExtension(
  vtkRenderer* ren,
  vtkVolume* vol)
{
  this->PackedThisFrame = false;
  int dims[3], cellFlag;
  FramePlan plan = DrawWithExtension;
  vtkDataArray* scalars = this->GetFrameScalars(dims, cellFlag, plan);
  if (!scalars)
  {
    return plan;
  }
  double range[2];
  scalars->GetFiniteRange(range, 0);
  if (!(range[0] <= range[1]))
  {
    vtkErrorMacro("The scalars hold no finite value (all NaN); not drawing.");
    return DrawNothing;
  }
  if (this->Method == STOCK && IsAnalyticBlend(this->BlendMode) && this->HasNaN(scalars))
  {
    // VTK's sampled projections and isosurface take NaN samples into their comparisons.
    vtkErrorMacro("VTK's sampled "
      << (this->BlendMode == vtkVolumeMapper::ISOSURFACE_BLEND ? "isosurface" : "projection")
      << " does not skip NaN values (its extremum and surface tests go wrong on them); use the "
         "ANALYTIC method, which draws NaN cells transparent, or replace them. Not drawing.");
    return DrawNothing;
  }
  if (this->Method == STOCK && this->OutputQuantity == OUTPUT_COLOR)
  {
    return DrawStock;
  }
  if (!IsAnalyticBlend(this->BlendMode))
  {
    this->WarnFallbackOnce(
      "analytic rendering applies to isosurface, maximum and minimum intensity "
      "blending");
    return DrawStock;
  }
  if (this->Method == ANALYTIC)
  {
    // The analytic rays are computed in float from world coordinates, whose squares must
    // stay finite.
    double bounds[6], eye[3];
    vol->GetBounds(bounds);
    ren->GetActiveCamera()->GetPosition(eye);
    double largest = 0.0;
    for (double v : bounds)
    {
      largest = std::max(largest, std::abs(v));
    }
    for (double v : eye)
    {
      largest = std::max(largest, std::abs(v));
    }
    if (!(largest <= MaximumCoordinate))
    {
      vtkErrorMacro("Analytic rendering computes its rays in float, where coordinates of "
        << largest << " overflow when squared (at most " << MaximumCoordinate
        << "); scale the spacing or move the origin and the camera. Not drawing.");
      return DrawNothing;
    }
    if (const char* reason = this->GetStockFallbackReason(vol, scalars, cellFlag))
    {
      this->WarnFallbackOnce(reason);
      return DrawStock;
    }
  }
  this->ClearFallbackWarning();

  vtkVolumeProperty* property = vol->GetProperty();
  double scale, shift;
  vtkExtensibleGPUVolumeRayCastMapper::GetTextureValueMapping(scalars, scale, shift);
  this->RawToData[0] = static_cast<float>(scale);
  this->RawToData[1] = static_cast<float>(shift);
  this->RawRange[0] = static_cast<float>((range[0] - shift) / scale);
  this->RawRange[1] = static_cast<float>((range[1] - shift) / scale);
  this->IsoRaw.clear();
  if (this->BlendMode == vtkVolumeMapper::ISOSURFACE_BLEND)
  {
    vtkContourValues* values = property->GetIsoSurfaceValues();
    for (int k = 0; values && k < values->GetNumberOfContours(); ++k)
    {
      const double value = values->GetValue(k);
      if (std::isfinite(value))
      {
        this->IsoRaw.push_back(static_cast<float>((value - shift) / scale));
      }
    }
    if (this->IsoRaw.empty())
    {
      vtkErrorMacro("Isosurface blending needs at least one finite isosurface value in the "
                    "volume property (GetIsoSurfaceValues()->SetValue(0, v)); not drawing.");
      return DrawNothing;
    }
    bool inside = false;
    for (int k = 0; k < values->GetNumberOfContours(); ++k)
    {
      inside = inside || (values->GetValue(k) >= range[0] && values->GetValue(k) <= range[1]);
    }
    std::ostringstream message;
    message << "No isosurface value lies in the data range [" << range[0] << ", " << range[1]
            << "]: the image is empty.";
    inside ? this->ClearEmptyWarning() : this->WarnEmptyOnce(message.str());
  }
  else
  {
    const double extreme =
      this->BlendMode == vtkVolumeMapper::MAXIMUM_INTENSITY_BLEND ? range[1] : range[0];
    this->RawExtreme = static_cast<float>((extreme - shift) / scale);
    // The projection draws the opacity of each ray's extremum, all within the data range.
    vtkPiecewiseFunction* opacity = property->GetScalarOpacity();
    double most = 0.0;
    const int nodes = opacity ? opacity->GetSize() : 0;
    for (int k = 0; k < nodes; ++k)
    {
      double node[4];
      opacity->GetNodeValue(k, node);
      if (node[0] > range[0] && node[0] < range[1])
      {
        most = std::max(most, node[1]);
      }
    }
    if (opacity)
    {
      most = std::max({ most, opacity->GetValue(range[0]), opacity->GetValue(range[1]) });
    }
    std::ostringstream message;
    message << "The scalar opacity is zero over the data range [" << range[0] << ", " << range[1]
            << "]: the image is transparent.";
    most > 0.0 ? this->ClearEmptyWarning() : this->WarnEmptyOnce(message.str());
  }

  if (this->Method == ANALYTIC && this->BlockSize > 0 &&
    !this->UpdateBlockRanges(ren, scalars, dims, scale, shift))
  {
    return DrawNothing;
  }
  // Packed corners unless their copy could not be made for these scalars (tried again when
  // they change): the cells are then read from VTK's texture, with the same image.
  const int valueBytes = scalars->GetDataType() == VTK_UNSIGNED_CHAR ? 1
    : scalars->GetDataType() == VTK_UNSIGNED_SHORT                    ? 2
                                                                      : 4;
  const double packedBytes = 4.0 * valueBytes * (dims[0] - 1) * (dims[1] - 1.0) * dims[2];
  this->PackedThisFrame = this->Method == ANALYTIC && this->CornerPacking &&
    packedBytes <= this->CornerPackingMemoryLimit &&
    !(scalars == this->UnpackableScalars && scalars->GetMTime() == this->UnpackableTime);
  if (this->PackedThisFrame && !this->UpdateCornerTexture(ren, scalars, dims, scale, shift))
  {
    this->UnpackableScalars = scalars;
    this->UnpackableTime = scalars->GetMTime();
    this->PackedThisFrame = false;
  }
  if (!this->PackedThisFrame)
  {
    this->CornerTextureMemorySize = 0;
  }
  if (this->Method == ANALYTIC)
  {
    this->UpdateRayFrame(ren, vol);
  }
  if (this->Method != ANALYTIC || this->BlockSize == 0)
  {
    this->BlockTextureMemorySize = 0;
  }

  std::ostringstream key;
  key << this->Method << " " << this->BlockSize << " " << this->BlendMode << " "
      << this->IsoRaw.size() << " " << property->GetShade(0) << " " << this->OutputQuantity << " "
      << this->PackedThisFrame;
  if (key.str() != this->ShaderKey)
  {
    this->ShaderKey = key.str();
    this->ExtensionShaderModified();
  }
  return DrawWithExtension;
}

//------------------------------------------------------------------------------
bool vtkAnalyticVolumeMapper::ReplaceExtensionShaderValues(std::string&,
  std::string& fragmentShader,
  vtkVolume* vol)
{
  using Self = vtkExtensibleGPUVolumeRayCastMapper;
  const bool iso = this->BlendMode == vtkVolumeMapper::ISOSURFACE_BLEND;
  std::ostringstream switches;
  switches << "#define HOVR_BLEND " << this->BlendMode << "\n"
           << "#define HOVR_ISO_COUNT " << std::max<size_t>(this->IsoRaw.size(), 1) << "\n"
           << "#define HOVR_SHADE " << (vol->GetProperty()->GetShade(0) ? 1 : 0) << "\n"
           << "#define HOVR_OUTPUT " << this->OutputQuantity << "\n"
           << "#define HOVR_BLOCK " << this->BlockSize << "\n"
           << "#define HOVR_PACKED " << (this->PackedThisFrame ? 1 : 0) << "\n";
  bool ok = true;
  if (this->Method == ANALYTIC)
  {
    // The whole ray is walked where VTK would initialise its loop, which then never runs.
    ok = Self::ReplaceShaderTag(fragmentShader,
           "//VTK::Shading::Init",
           "hovr_analyticRay();\n  g_exit = true;",
           Self::ReplaceTag) &&
      Self::ReplaceShaderTag(fragmentShader, "//VTK::Shading::Exit", "", Self::ReplaceTag) &&
      Self::ReplaceShaderTag(fragmentShader,
        "//VTK::ComputeRayDirection::Dec",
        switches.str() + hovrAnalyticCommon + hovrAnalytic,
        Self::BeforeTag);
  }
  else
  {
    // VTK's own sampling, observed: where its isosurface first becomes visible, or its
    // sampled extremum at the end.
    const std::string declarations = switches.str() + hovrAnalyticCommon;
    ok = Self::ReplaceShaderTag(
      fragmentShader, "//VTK::ComputeRayDirection::Dec", declarations, Self::BeforeTag);
    if (iso)
    {
      ok = ok &&
        Self::ReplaceShaderTag(fragmentShader,
          "//VTK::Shading::Impl",
          "if (hovr_output.w == 0.0 && g_fragColor.a > 0.0)\n"
          "  {\n"
          "    hovr_output = vec4(hovr_textureToIndex(g_dataPos), 1.0);\n"
          "  }",
          Self::AfterTag);
    }
    else
    {
      const char* value =
        this->BlendMode == vtkVolumeMapper::MAXIMUM_INTENSITY_BLEND ? "l_maxValue" : "l_minValue";
      std::ostringstream exit;
      exit << "if (!l_firstValue)\n"
           << "  {\n"
           << "    float raw = (" << value
           << ".w - in_volume_bias[0].r) / in_volume_scale[0].r;\n"
           // An extremum lies in the data range; VTK's normalised texture loses constant
           // data (zero width), which this restores.
           << "    raw = raw >= hovr_rawRange.x ? raw : hovr_rawRange.x;\n"
           << "    raw = raw <= hovr_rawRange.y ? raw : hovr_rawRange.y;\n"
           << "    hovr_output = vec4(raw * hovr_rawToData.x + hovr_rawToData.y, 0.0, 0.0, 1.0);\n"
           << "  }";
      ok = ok &&
        Self::ReplaceShaderTag(fragmentShader, "//VTK::Shading::Exit", exit.str(), Self::AfterTag);
    }
  }
  if (this->OutputQuantity != OUTPUT_COLOR)
  {
    ok = ok &&
      Self::ReplaceShaderTag(
        fragmentShader, "//VTK::DepthPass::Exit", "gl_FragData[0] = hovr_output;", Self::AfterTag);
  }
  if (!ok)
  {
    vtkErrorMacro("The ray caster's shader template lacks a tag that analytic rendering uses.");
  }
  return ok;
}

//------------------------------------------------------------------------------
void vtkAnalyticVolumeMapper::SetExtensionShaderParameters(vtkShaderProgram* program, vtkVolume*)
{
  program->SetUniform2f("hovr_rawToData", this->RawToData);
  program->SetUniform2f("hovr_rawRange", this->RawRange);
  if (this->Method != ANALYTIC)
  {
    return;
  }
  program->SetUniformi("hovr_rayFrameInUse", this->RayFrameInUse);
  if (this->RayFrameInUse)
  {
    program->SetUniform3f("hovr_rayCentre", this->RayFrame[0]);
    program->SetUniform3f("hovr_rayDx", this->RayFrame[1]);
    program->SetUniform3f("hovr_rayDy", this->RayFrame[2]);
    program->SetUniform3f("hovr_rayEye", this->RayFrame[3]);
    program->SetUniform3f("hovr_rayForward", this->RayFrame[4]);
    program->SetUniform2f("hovr_rayPixelCentre", this->RayPixelCentre);
    program->SetUniformi("hovr_rayPerspective", this->RayPerspective);
  }
  if (this->BlockSize > 0)
  {
    program->SetUniformi("hovr_blockRange", this->BlockTexture->GetTextureUnit());
  }
  if (this->PackedThisFrame)
  {
    program->SetUniformi("hovr_corners", this->CornerTexture->GetTextureUnit());
  }
  if (this->BlendMode == vtkVolumeMapper::ISOSURFACE_BLEND)
  {
    program->SetUniform1fv(
      "hovr_isoRaw", static_cast<int>(this->IsoRaw.size()), this->IsoRaw.data());
  }
  else
  {
    program->SetUniformf("hovr_rawExtreme", this->RawExtreme);
  }
}

//------------------------------------------------------------------------------
void vtkAnalyticVolumeMapper::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Method: " << this->Method << "\n";
  os << indent << "OutputQuantity: " << this->OutputQuantity << "\n";
  os << indent << "BlockSize: " << this->BlockSize << "\n";
  os << indent << "BlockTextureMemorySize: " << this->BlockTextureMemorySize << "\n";
  os << indent << "CornerPacking: " << this->CornerPacking << "\n";
  os << indent << "CornerPackingMemoryLimit: " << this->CornerPackingMemoryLimit << "\n";
  os << indent << "CornerTextureMemorySize: " << this->CornerTextureMemorySize << "\n";
  os << indent << "RayFrameInUse: " << this->RayFrameInUse << "\n";
}
