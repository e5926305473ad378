// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
#include "vtkAnalyticVolumeMapper.h"

#include "vtkCamera.h"
#include "vtkCameraRayModel.h"
#include "vtkContourValues.h"
#include "vtkDataArray.h"
#include "vtkDoubleArray.h"
#include "vtkFloatArray.h"
#include "vtkImageData.h"
#include "vtkMath.h"
#include "vtkObjectFactory.h"
#include "vtkOpenGLFramebufferObject.h"
#include "vtkOpenGLQuadHelper.h"
#include "vtkOpenGLRenderWindow.h"
#include "vtkOpenGLShaderCache.h"
#include "vtkOpenGLState.h"
#include "vtkOpenGLVolumeBricks.h"
#include "vtkPiecewiseFunction.h"
#include "vtkPlaneCollection.h"
#include "vtkPreIntegrationTable.h"
#include "vtkRenderer.h"
#include "vtkSMPTools.h"
#include "vtkShaderProgram.h"
#include "vtkTextureObject.h"
#include "vtkVolume.h"
#include "vtkVolumeBrickLayout.h"
#include "vtkVolumeProperty.h"
#include "vtkVolumeScalarView.h"
#include "vtk_glew.h"

#include "hovrAnalytic.h"       // the GLSL of the analytic ray caster
#include "hovrAnalyticCommon.h" // the GLSL both modes share
#include "hovrWindow.h"         // window to texture coordinates

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
// The points of a brick are points[0..1] x points[2..3] x points[4..5] of a volume of dims
// points; blocks count from the brick's first point.
void ComputeBlockRanges(vtkDataArray* scalars,
  const int volumeDims[3],
  const int points[6],
  int size,
  double scale,
  double shift,
  const int blocks[3],
  std::vector<float>& ranges)
{
  const int dims[3] = {
    points[1] - points[0] + 1, points[3] - points[2] + 1, points[5] - points[4] + 1
  };
  const double inf = std::numeric_limits<double>::infinity();
  std::vector<double> lo(static_cast<size_t>(blocks[0]) * blocks[1] * blocks[2], inf);
  std::vector<double> hi(lo.size(), -inf);
  std::vector<char> partial(lo.size(), 0);
  // The values in place, converted as they are read; an array that must be copied and cannot
  // be bounds nothing (every block's range is the whole line, which skips no block).
  vtkVolumeScalarView value;
  if (!value.SetArray(scalars))
  {
    std::fill(lo.begin(), lo.end(), -inf);
    std::fill(hi.begin(), hi.end(), inf);
  }
  else
  {
    // Each block reads its own points, those on its far faces included (a point on a block
    // boundary belongs to the blocks on both sides), so blocks are independent tasks.
    vtkSMPTools::For(0,
      static_cast<vtkIdType>(lo.size()),
      [&](vtkIdType begin, vtkIdType end)
      {
        for (vtkIdType b = begin; b < end; ++b)
        {
          const int bi = static_cast<int>(b % blocks[0]);
          const int bj = static_cast<int>((b / blocks[0]) % blocks[1]);
          const int bk = static_cast<int>(b / (static_cast<vtkIdType>(blocks[0]) * blocks[1]));
          const int first[3] = { bi * size, bj * size, bk * size };
          const int last[3] = { std::min(first[0] + size, dims[0] - 1),
            std::min(first[1] + size, dims[1] - 1),
            std::min(first[2] + size, dims[2] - 1) };
          double low = inf, high = -inf;
          bool nan = false, found = false;
          value.Visit(
            [&](const auto* values)
            {
              for (int k = first[2]; k <= last[2]; ++k)
              {
                for (int j = first[1]; j <= last[1]; ++j)
                {
                  const auto* row = values + points[0] +
                    static_cast<vtkIdType>(volumeDims[0]) *
                      (points[2] + j + static_cast<vtkIdType>(volumeDims[1]) * (points[4] + k));
                  for (int i = first[0]; i <= last[0]; ++i)
                  {
                    const double v = row[i];
                    if (std::isnan(v))
                    {
                      nan = true;
                      continue;
                    }
                    found = true;
                    low = std::min(low, v);
                    high = std::max(high, v);
                  }
                }
              }
            });
          // (v - shift) / scale is monotonic: the ends map to the raw range's ends.
          const double a = (low - shift) / scale, c = (high - shift) / scale;
          lo[b] = found ? std::min(a, c) : inf;
          hi[b] = found ? std::max(a, c) : -inf;
          partial[b] = nan ? 1 : 0;
        }
      });
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

// The 4 corners in x and y of each point of slice z of a brick, x fastest (see
// UpdateBrickTextures): texels of type T from values of type S, raw value v stored as
// (v - shift) / scale (v itself when shift is 0 and scale 1).
template <typename T, typename S>
void PackSlice(const S* value,
  const int volumeDims[3],
  const int points[6],
  int z,
  double shift,
  double scale,
  T* texel)
{
  const vtkIdType nx = volumeDims[0], ny = volumeDims[1];
  const bool identity = shift == 0.0 && scale == 1.0;
  for (vtkIdType j = points[2]; j < points[3]; ++j)
  {
    const S* row = value + nx * (j + ny * z);
    const S* next = row + nx;
    if (identity)
    {
      for (vtkIdType i = points[0]; i < points[1]; ++i, texel += 4)
      {
        texel[0] = static_cast<T>(row[i]);
        texel[1] = static_cast<T>(row[i + 1]);
        texel[2] = static_cast<T>(next[i]);
        texel[3] = static_cast<T>(next[i + 1]);
      }
      continue;
    }
    for (vtkIdType i = points[0]; i < points[1]; ++i, texel += 4)
    {
      texel[0] = static_cast<T>((row[i] - shift) / scale);
      texel[1] = static_cast<T>((row[i + 1] - shift) / scale);
      texel[2] = static_cast<T>((next[i] - shift) / scale);
      texel[3] = static_cast<T>((next[i + 1] - shift) / scale);
    }
  }
}
}

//------------------------------------------------------------------------------
vtkAnalyticVolumeMapper::vtkAnalyticVolumeMapper()
{
  this->ExtremeTexture = vtkTextureObject::New();
  this->ColourTexture = vtkTextureObject::New();
  this->Targets = vtkOpenGLFramebufferObject::New();
  // Float positions in a brick's grid index round at the brick's scale: 256 points keep the
  // hit within 1e-4 voxel at any volume size.
  this->MaximumBrickSize = 256;
}

//------------------------------------------------------------------------------
vtkAnalyticVolumeMapper::~vtkAnalyticVolumeMapper()
{
  this->ExtremeTexture->Delete();
  this->ColourTexture->Delete();
  this->Targets->Delete();
}

//------------------------------------------------------------------------------
bool vtkAnalyticVolumeMapper::UpdateBrickTextures(vtkRenderer* ren,
  vtkDataArray* scalars,
  const int dims[3],
  double scale,
  double shift)
{
  vtkOpenGLRenderWindow* context = vtkOpenGLRenderWindow::SafeDownCast(ren->GetRenderWindow());
  vtkVolumeBrickLayout* layout = this->GetBricks()->GetLayout();
  const int bricks = this->GetBricks()->GetNumberOfBricks();
  std::ostringstream key;
  key << scalars << " " << scalars->GetMTime() << " " << this->GetBricks()->GetUploadCount() << " "
      << context;
  const std::string base = key.str();
  key << " " << this->BlockSize;
  if (this->BlockSize > 0 && key.str() != this->BlockKey)
  {
    this->BlockKey.clear();
    this->BlockTextureMemorySize = 0;
    this->BlockTextures.clear();
    for (int b = 0; b < bricks; ++b)
    {
      int points[6], blocks[3];
      layout->GetBrickPoints(b, points);
      for (int a = 0; a < 3; ++a)
      {
        // cells points - 1, rounded up
        blocks[a] = (points[2 * a + 1] - points[2 * a] - 1) / this->BlockSize + 1;
      }
      std::vector<float> ranges;
      ComputeBlockRanges(scalars, dims, points, this->BlockSize, scale, shift, blocks, ranges);
      vtkNew<vtkTextureObject> texture;
      texture->SetInternalFormat(GL_RG32F);
      texture->SetFormat(GL_RG);
      texture->SetDataType(GL_FLOAT);
      std::string why;
      if (!this->CreateTexture3D(
            texture, context, blocks, 2, VTK_FLOAT, ranges.data(), "block-range texture", why))
      {
        vtkErrorMacro(<< why << "; not drawing.");
        this->BlockTextures.clear();
        this->BlockTextureMemorySize = 0;
        return false;
      }
      texture->SetMinificationFilter(vtkTextureObject::Nearest);
      texture->SetMagnificationFilter(vtkTextureObject::Nearest);
      this->BlockTextures.emplace_back(texture);
      this->BlockTextureMemorySize += static_cast<vtkIdType>(ranges.size()) * sizeof(float);
    }
    this->BlockKey = key.str();
  }

  if (!this->PackedThisFrame || base == this->CornerKey)
  {
    return true;
  }
  // Texel (i, j, k), i < nx - 1, j < ny - 1, of a brick of nx x ny x nz points holds its points
  // (i, j), (i + 1, j), (i, j + 1) and (i + 1, j + 1) of slice k: a cell's 8 corners are 2
  // fetches instead of 8. 8- and 16-bit unsigned data keep their type (the normalised values
  // equal those of the brick textures); other types are stored as the float raw values.
  const int type = scalars->GetDataType();
  const int texelType = type == VTK_UNSIGNED_CHAR || type == VTK_UNSIGNED_SHORT ? type : VTK_FLOAT;
  const double packShift = texelType == VTK_FLOAT ? shift : 0.0;
  const double packScale = texelType == VTK_FLOAT ? scale : 1.0;
  // A new time step on the same bricks is written into the textures already made.
  std::vector<vtkSmartPointer<vtkTextureObject>> previous;
  previous.swap(this->CornerTextures);
  this->CornerKey.clear();
  this->CornerTextureMemorySize = 0;
  std::string failure = "not enough memory";
  vtkVolumeScalarView value;
  bool created = value.SetArray(scalars);
  for (int b = 0; b < bricks && created; ++b)
  {
    int points[6];
    layout->GetBrickPoints(b, points);
    const int size[3] = { points[1] - points[0], points[3] - points[2], points[5] - points[4] + 1 };
    vtkSmartPointer<vtkTextureObject> texture;
    if (b < static_cast<int>(previous.size()) &&
      vtkOpenGLVolumeBricks::HasTexture3D(previous[b], context, size, 4, texelType))
    {
      texture = previous[b];
      previous[b] = nullptr;
    }
    else
    {
      texture = vtkSmartPointer<vtkTextureObject>::New();
      texture->SetFormat(GL_RGBA);
      texture->SetInternalFormat(texelType == VTK_UNSIGNED_CHAR ? GL_RGBA8
          : texelType == VTK_UNSIGNED_SHORT                     ? GL_RGBA16
                                                                : GL_RGBA32F);
      texture->SetDataType(texelType == VTK_UNSIGNED_CHAR ? GL_UNSIGNED_BYTE
          : texelType == VTK_UNSIGNED_SHORT               ? GL_UNSIGNED_SHORT
                                                          : GL_FLOAT);
      created = this->CreateTexture3D(
        texture, context, size, 4, texelType, nullptr, "packed-corner texture", failure);
    }
    if (created)
    {
      auto fill = [&](int z, void* out)
      {
        z += points[4];
        value.Visit(
          [&](const auto* values)
          {
            if (texelType == VTK_UNSIGNED_CHAR)
            {
              PackSlice(values, dims, points, z, 0.0, 1.0, static_cast<unsigned char*>(out));
            }
            else if (texelType == VTK_UNSIGNED_SHORT)
            {
              PackSlice(values, dims, points, z, 0.0, 1.0, static_cast<unsigned short*>(out));
            }
            else
            {
              PackSlice(values, dims, points, z, packShift, packScale, static_cast<float*>(out));
            }
          });
      };
      const int origin[3] = { 0, 0, 0 };
      const bool written =
        vtkOpenGLVolumeBricks::WriteSlices(texture, origin, size, 4, texelType, fill);
      const GLenum error = glGetError();
      created = written && error == GL_NO_ERROR;
      failure = !written ? "not enough memory"
        : created        ? failure
                         : "OpenGL could not write the packed-corner texture";
    }
    if (created)
    {
      texture->SetMinificationFilter(vtkTextureObject::Nearest);
      texture->SetMagnificationFilter(vtkTextureObject::Nearest);
      this->CornerTextures.emplace_back(texture);
      this->CornerTextureMemorySize += static_cast<vtkIdType>(size[0]) * size[1] * size[2] * 4 *
        vtkDataArray::GetDataTypeSize(texelType);
    }
  }
  for (auto& unused : previous)
  {
    if (unused)
    {
      unused->ReleaseGraphicsResources(context);
    }
  }
  if (!created)
  {
    vtkWarningMacro("Could not make the packed copy of the volume's corners ("
      << failure
      << "); reading each cell's 8 corners from the volume's bricks instead (same image).");
    for (auto& texture : this->CornerTextures)
    {
      texture->ReleaseGraphicsResources(context);
    }
    this->CornerTextures.clear();
    this->CornerTextureMemorySize = 0;
    return false;
  }
  this->CornerKey = base;
  return true;
}

//------------------------------------------------------------------------------
vtkTextureObject* vtkAnalyticVolumeMapper::GetCurrentBrickTexture(
  std::vector<vtkSmartPointer<vtkTextureObject>>& textures)
{
  const int b = this->GetCurrentBrick();
  return b < static_cast<int>(textures.size()) ? textures[b].Get() : nullptr;
}

//------------------------------------------------------------------------------
void vtkAnalyticVolumeMapper::ActivateExtensionTextures()
{
  if (this->Method != ANALYTIC)
  {
    return;
  }
  if (this->BlockSize > 0)
  {
    this->GetCurrentBrickTexture(this->BlockTextures)->Activate();
  }
  if (this->PackedThisFrame)
  {
    this->GetCurrentBrickTexture(this->CornerTextures)->Activate();
  }
}

//------------------------------------------------------------------------------
void vtkAnalyticVolumeMapper::DeactivateExtensionTextures()
{
  if (this->Method != ANALYTIC)
  {
    return;
  }
  if (this->BlockSize > 0)
  {
    this->GetCurrentBrickTexture(this->BlockTextures)->Deactivate();
  }
  if (this->PackedThisFrame)
  {
    this->GetCurrentBrickTexture(this->CornerTextures)->Deactivate();
  }
}

//------------------------------------------------------------------------------
void vtkAnalyticVolumeMapper::ReleaseExtensionResources(vtkWindow* window)
{
  for (auto& texture : this->BlockTextures)
  {
    texture->ReleaseGraphicsResources(window);
  }
  for (auto& texture : this->CornerTextures)
  {
    texture->ReleaseGraphicsResources(window);
  }
  this->BlockTextures.clear();
  this->CornerTextures.clear();
  this->BlockKey.clear();
  this->CornerKey.clear();
  this->ExtremeTexture->ReleaseGraphicsResources(window);
  this->ColourTexture->ReleaseGraphicsResources(window);
  this->Targets->ReleaseGraphicsResources(window);
  this->ExtremeCopy.reset();
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
  if (this->GetClippingPlanes() && this->GetClippingPlanes()->GetNumberOfItems() > 0)
  {
    return "analytic rendering does not support clipping planes";
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
  this->Context = vtkOpenGLRenderWindow::SafeDownCast(ren->GetRenderWindow());
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
  double tableRange[2];
  vtkPreIntegrationTable::ComputeScalarRange(
    scalars, this->DepthRange, tableRange, this->ScalarRange);
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
  // Raw values: those of the brick textures (analytic) or of VTK's texture (stock); the
  // transfer-function tables are VTK's, looked up from its own raw values.
  double scale, shift, vtkScale, vtkShift;
  // The proxy VTK draws bricks from spans ScalarRange too; VTK's own drawing spans the data.
  vtkExtensibleGPUVolumeRayCastMapper::GetTextureValueMapping(
    scalars, vtkScale, vtkShift, this->Method == ANALYTIC ? this->ScalarRange : nullptr);
  scale = vtkScale;
  shift = vtkShift;
  if (this->Method == ANALYTIC)
  {
    // Each cell's corners are read exactly (texelFetch): the data's own precision suffices.
    if (!this->PrepareBricks(ren, scalars, dims, 0, vtkOpenGLVolumeBricks::NATIVE, false))
    {
      return DrawNothing;
    }
    this->GetBricks()->GetValueMapping(scale, shift);
  }
  this->RawToVtkRaw[0] = static_cast<float>(scale / vtkScale);
  this->RawToVtkRaw[1] = static_cast<float>((shift - vtkShift) / vtkScale);
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

  // Packed corners unless their copy would exceed the limit or could not be made for these
  // scalars (tried again when they change): the cells are then read from the bricks, with the
  // same image.
  const int valueBytes = scalars->GetDataType() == VTK_UNSIGNED_CHAR ? 1
    : scalars->GetDataType() == VTK_UNSIGNED_SHORT                   ? 2
                                                                     : 4;
  const double packedBytes = 4.0 * valueBytes * (dims[0] - 1) * (dims[1] - 1.0) * dims[2];
  // Each brick's copy is one texture, within MaximumTextureBytes too.
  double largestBrick = 0.0;
  for (int b = 0; this->Method == ANALYTIC && b < this->GetNumberOfBricks(); ++b)
  {
    int size[3];
    this->GetBricks()->GetLayout()->GetBrickSize(b, size);
    largestBrick =
      std::max(largestBrick, 4.0 * valueBytes * (size[0] - 1) * (size[1] - 1.0) * size[2]);
  }
  this->PackedThisFrame = this->Method == ANALYTIC && this->CornerPacking &&
    packedBytes <= this->CornerPackingMemoryLimit &&
    largestBrick <= static_cast<double>(this->MaximumTextureBytes) &&
    !(scalars == this->UnpackableScalars && scalars->GetMTime() == this->UnpackableTime);
  if (this->Method == ANALYTIC && !this->UpdateBrickTextures(ren, scalars, dims, scale, shift))
  {
    if (this->BlockSize > 0 && this->BlockTextures.empty())
    {
      return DrawNothing;
    }
    this->UnpackableScalars = scalars;
    this->UnpackableTime = scalars->GetMTime();
    this->PackedThisFrame = false;
  }
  if (!this->PackedThisFrame)
  {
    this->CornerTextures.clear();
    this->CornerKey.clear();
    this->CornerTextureMemorySize = 0;
  }
  if (this->Method == ANALYTIC)
  {
    this->UpdateRayFrame(ren, vol);
  }
  if (this->Method != ANALYTIC || this->BlockSize == 0)
  {
    this->BlockTextures.clear();
    this->BlockKey.clear();
    this->BlockTextureMemorySize = 0;
  }

  // Rounds for several bricks, and for one when the depth comes from the extremum (which the
  // last round reads).
  this->Rounds = this->Method == ANALYTIC && this->BlendMode != vtkVolumeMapper::ISOSURFACE_BLEND &&
    (this->GetNumberOfBricks() > 1 ||
      (this->ExtremumDepth && this->OutputQuantity == OUTPUT_COLOR));
  std::ostringstream key;
  key << this->Rounds << " " << this->Method << " " << this->BlockSize << " " << this->BlendMode
      << " " << this->IsoRaw.size() << " " << property->GetShade(0) << " " << this->OutputQuantity
      << " " << this->PackedThisFrame;
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
           << "#define HOVR_PACKED " << (this->PackedThisFrame ? 1 : 0) << "\n"
           << "#define HOVR_ROUNDS " << (this->Rounds ? 1 : 0) << "\n"
           << (this->Method == ANALYTIC ? "#define HOVR_BRICKED 1\n" : "");
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
        switches.str() + hovrWindow + hovrAnalyticCommon + hovrAnalytic,
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
    // Misses write nothing: bricks drawn later (nearer) must not erase a farther hit.
    ok = ok &&
      Self::ReplaceShaderTag(fragmentShader,
        "//VTK::DepthPass::Exit",
        "if (hovr_output.w == 0.0)\n"
        "  {\n"
        "    discard;\n"
        "  }\n"
        "  gl_FragData[0] = hovr_output;",
        Self::AfterTag);
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
  program->SetUniformi("hovr_volume", this->GetBrickTexture()->GetTextureUnit());
  program->SetUniformf("hovr_brick", static_cast<float>(this->GetCurrentBrick()));
  program->SetUniform2f("hovr_rawToVtkRaw", this->RawToVtkRaw);
  vtkImageData* input = vtkImageData::SafeDownCast(this->GetInput());
  double spacing[3];
  input->GetSpacing(spacing);
  program->SetUniform3f("hovr_spacing", spacing);
  this->SetRayFrameUniforms(program);
  if (this->BlockSize > 0)
  {
    program->SetUniformi(
      "hovr_blockRange", this->GetCurrentBrickTexture(this->BlockTextures)->GetTextureUnit());
  }
  if (this->PackedThisFrame)
  {
    program->SetUniformi(
      "hovr_corners", this->GetCurrentBrickTexture(this->CornerTextures)->GetTextureUnit());
  }
  vtkOpenGLState* state = this->Context ? this->Context->GetState() : nullptr;
  if (this->BlendMode == vtkVolumeMapper::ISOSURFACE_BLEND)
  {
    program->SetUniform1fv(
      "hovr_isoRaw", static_cast<int>(this->IsoRaw.size()), this->IsoRaw.data());
    if (state && this->OutputQuantity != OUTPUT_COLOR)
    {
      // Measured hits replace what is there (w is 1 + the brick, not an opacity).
      state->vtkglDisable(GL_BLEND);
    }
  }
  else
  {
    program->SetUniformf("hovr_rawExtreme", this->RawExtreme);
    if (this->Rounds)
    {
      program->SetUniformi("hovr_round", this->Round);
      // Round 1 reads no extremes, but its sampler needs a 2D texture's unit of its own.
      program->SetUniformi("hovr_extremes",
        (this->Round == 2 ? this->ExtremeTexture : this->ColourTexture)->GetTextureUnit());
    }
    if (state && this->Round == 1)
    {
      state->vtkglEnable(GL_BLEND);
      state->vtkglBlendEquation(
        this->BlendMode == vtkVolumeMapper::MAXIMUM_INTENSITY_BLEND ? GL_MAX : GL_MIN);
    }
    else if (state && this->Round == 2)
    {
      // Every brick that writes a pixel writes the same colour.
      state->vtkglDisable(GL_BLEND);
    }
  }
}

//------------------------------------------------------------------------------
void vtkAnalyticVolumeMapper::DrawBrickedFrame(vtkRenderer* ren, vtkVolume* vol)
{
  const bool projection = this->BlendMode != vtkVolumeMapper::ISOSURFACE_BLEND;
  vtkOpenGLRenderWindow* context = this->Context;
  const bool colour = this->OutputQuantity == OUTPUT_COLOR;
  const bool depth = projection && colour && this->ExtremumDepth;
  if (!projection || (this->GetNumberOfBricks() < 2 && !depth) || !context)
  {
    this->Superclass::DrawBrickedFrame(ren, vol);
    return;
  }
  // A maximum or minimum does not composite by "over": round 1 keeps each pixel's extremum
  // over the bricks in a float target (maximum or minimum blending), round 2 draws the colour
  // of the bricks that hold it into another, which goes over the frame last.
  vtkOpenGLState* state = context->GetState();
  const int* size = context->GetSize();
  auto target = [&](vtkTextureObject* texture)
  {
    if (texture->GetWidth() != static_cast<unsigned int>(size[0]) ||
      texture->GetHeight() != static_cast<unsigned int>(size[1]) ||
      texture->GetContext() != context)
    {
      texture->ReleaseGraphicsResources(context);
      texture->SetContext(context);
      texture->SetInternalFormat(GL_RGBA32F);
      texture->SetFormat(GL_RGBA);
      texture->SetDataType(GL_FLOAT);
      texture->Allocate2D(size[0], size[1], 4, VTK_FLOAT);
      texture->SetMinificationFilter(vtkTextureObject::Nearest);
      texture->SetMagnificationFilter(vtkTextureObject::Nearest);
    }
  };
  target(this->ExtremeTexture);
  target(this->ColourTexture);
  const bool maximum = this->BlendMode == vtkVolumeMapper::MAXIMUM_INTENSITY_BLEND;
  const float inf = std::numeric_limits<float>::infinity();
  {
    vtkOpenGLState::ScopedglClearColor clearColor(state);
    vtkOpenGLState::ScopedglEnableDisable scissor(state, GL_SCISSOR_TEST);
    state->vtkglDisable(GL_SCISSOR_TEST);
    // Rays read the frame's depth (VTK copies it from the read framebuffer); only the draw
    // framebuffer is the target.
    state->PushFramebufferBindings();
    this->Targets->SetContext(context);
    this->Targets->Bind(GL_DRAW_FRAMEBUFFER);
    this->Targets->AddColorAttachment(0, this->ExtremeTexture);
    this->Targets->ActivateDrawBuffers(1);
    state->vtkglClearColor(maximum ? -inf : inf, 0.0f, 0.0f, 0.0f);
    state->vtkglClear(GL_COLOR_BUFFER_BIT);
    this->Round = 1;
    this->ColourTexture->Activate();
    this->DrawBrickRound(ren, vol);
    this->ColourTexture->Deactivate();
    state->vtkglBlendEquation(GL_FUNC_ADD);
    if (colour)
    {
      this->Targets->Bind(GL_DRAW_FRAMEBUFFER);
      this->Targets->AddColorAttachment(0, this->ColourTexture);
      this->Targets->ActivateDrawBuffers(1);
      state->vtkglClearColor(0.0f, 0.0f, 0.0f, 0.0f);
      state->vtkglClear(GL_COLOR_BUFFER_BIT);
      this->ExtremeTexture->Activate();
      this->Round = 2;
      this->DrawBrickRound(ren, vol);
      this->ExtremeTexture->Deactivate();
    }
    this->Round = 0;
    this->Targets->RemoveColorAttachment(0);
    state->PopFramebufferBindings();
  }

  // Over the frame: the colour (premultiplied, transparent where no ray met the volume) or the
  // measured extremum.
  vtkOpenGLState::ScopedglBlendFuncSeparate blendSaver(state);
  vtkOpenGLState::ScopedglEnableDisable blendEnabled(state, GL_BLEND);
  vtkOpenGLState::ScopedglEnableDisable depthTest(state, GL_DEPTH_TEST);
  vtkOpenGLState::ScopedglDepthMask depthMask(state);
  state->vtkglDisable(GL_DEPTH_TEST);
  state->vtkglDepthMask(GL_FALSE);
  int width, height, x0, y0;
  ren->GetTiledSizeAndOrigin(&width, &height, &x0, &y0);
  if (depth)
  {
    this->DrawWithExtremumDepth(ren, maximum);
    return;
  }
  if (colour)
  {
    state->vtkglEnable(GL_BLEND);
    state->vtkglBlendFuncSeparate(GL_ONE, GL_ONE_MINUS_SRC_ALPHA, GL_ONE, GL_ONE_MINUS_SRC_ALPHA);
    this->ColourTexture->Activate();
    this->ColourTexture->CopyToFrameBuffer(x0,
      y0,
      x0 + width - 1,
      y0 + height - 1,
      x0,
      y0,
      x0 + width - 1,
      y0 + height - 1,
      size[0],
      size[1],
      nullptr,
      nullptr);
    this->ColourTexture->Deactivate();
    return;
  }
  // Measured: (extremum, 0, 0, 1) where a ray met the volume, nothing elsewhere.
  if (!this->ExtremeCopy)
  {
    this->ExtremeCopy.reset(new vtkOpenGLQuadHelper(context,
      nullptr,
      "//VTK::System::Dec\n"
      "in vec2 texCoord;\n"
      "uniform sampler2D extremes;\n"
      "//VTK::Output::Dec\n"
      "void main()\n"
      "{\n"
      "  vec4 v = texture(extremes, texCoord);\n"
      "  if (v.w == 0.0)\n"
      "  {\n"
      "    discard;\n"
      "  }\n"
      "  gl_FragData[0] = vec4(v.x, 0.0, 0.0, 1.0);\n"
      "}\n",
      ""));
  }
  state->vtkglDisable(GL_BLEND);
  context->GetShaderCache()->ReadyShaderProgram(this->ExtremeCopy->Program);
  this->ExtremeTexture->Activate();
  this->ExtremeCopy->Program->SetUniformi("extremes", this->ExtremeTexture->GetTextureUnit());
  vtkOpenGLState::ScopedglViewport viewport(state);
  state->vtkglViewport(x0, y0, width, height);
  this->ExtremeCopy->Render();
  this->ExtremeTexture->Deactivate();
}

//------------------------------------------------------------------------------
void vtkAnalyticVolumeMapper::DrawWithExtremumDepth(vtkRenderer* ren, bool maximum)
{
  // Over the frame, as the colour copy, and each met pixel's depth from its extremum: the
  // depth test passes always (a disabled test would not write the depth).
  vtkOpenGLRenderWindow* context = this->Context;
  vtkOpenGLState* state = context->GetState();
  if (!this->DepthCopy)
  {
    this->DepthCopy.reset(new vtkOpenGLQuadHelper(context,
      nullptr,
      "//VTK::System::Dec\n"
      "in vec2 texCoord;\n"
      "uniform sampler2D colours;\n"
      "uniform sampler2D extremes;\n"
      "uniform vec2 depthMap;\n"
      "//VTK::Output::Dec\n"
      "void main()\n"
      "{\n"
      "  vec4 e = texture(extremes, texCoord);\n"
      "  if (e.w == 0.0)\n"
      "  {\n"
      "    discard;\n"
      "  }\n"
      "  gl_FragData[0] = texture(colours, texCoord);\n"
      "  gl_FragDepth = clamp(depthMap.x + depthMap.y * e.x, 0.25, 0.75);\n"
      "}\n",
      ""));
  }
  // MIP: 0.75 - 0.5 u; MinIP: 0.25 + 0.5 u; u = (e - low) / (high - low).
  const double low = this->DepthRange[0];
  const double width = this->DepthRange[1] > low ? this->DepthRange[1] - low : 1.0;
  const float depthMap[2] = { static_cast<float>(
                                maximum ? 0.75 + 0.5 * low / width : 0.25 - 0.5 * low / width),
    static_cast<float>((maximum ? -0.5 : 0.5) / width) };
  vtkOpenGLState::ScopedglBlendFuncSeparate blendSaver(state);
  vtkOpenGLState::ScopedglEnableDisable blendEnabled(state, GL_BLEND);
  vtkOpenGLState::ScopedglEnableDisable depthTest(state, GL_DEPTH_TEST);
  vtkOpenGLState::ScopedglDepthMask depthMask(state);
  vtkOpenGLState::ScopedglDepthFunc depthFunc(state);
  state->vtkglEnable(GL_BLEND);
  state->vtkglBlendFuncSeparate(GL_ONE, GL_ONE_MINUS_SRC_ALPHA, GL_ONE, GL_ONE_MINUS_SRC_ALPHA);
  state->vtkglEnable(GL_DEPTH_TEST);
  state->vtkglDepthFunc(GL_ALWAYS);
  state->vtkglDepthMask(GL_TRUE);
  context->GetShaderCache()->ReadyShaderProgram(this->DepthCopy->Program);
  this->ColourTexture->Activate();
  this->ExtremeTexture->Activate();
  this->DepthCopy->Program->SetUniformi("colours", this->ColourTexture->GetTextureUnit());
  this->DepthCopy->Program->SetUniformi("extremes", this->ExtremeTexture->GetTextureUnit());
  this->DepthCopy->Program->SetUniform2f("depthMap", depthMap);
  int width_, height, x0, y0;
  ren->GetTiledSizeAndOrigin(&width_, &height, &x0, &y0);
  vtkOpenGLState::ScopedglViewport viewport(state);
  state->vtkglViewport(x0, y0, width_, height);
  this->DepthCopy->Render();
  this->ExtremeTexture->Deactivate();
  this->ColourTexture->Deactivate();
}

//------------------------------------------------------------------------------
void vtkAnalyticVolumeMapper::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Method: " << this->Method << "\n";
  os << indent << "OutputQuantity: " << this->OutputQuantity << "\n";
  os << indent << "ExtremumDepth: " << (this->ExtremumDepth ? "On" : "Off") << "\n";
  os << indent << "BlockSize: " << this->BlockSize << "\n";
  os << indent << "BlockTextureMemorySize: " << this->BlockTextureMemorySize << "\n";
  os << indent << "CornerPacking: " << this->CornerPacking << "\n";
  os << indent << "CornerPackingMemoryLimit: " << this->CornerPackingMemoryLimit << "\n";
  os << indent << "CornerTextureMemorySize: " << this->CornerTextureMemorySize << "\n";
}
