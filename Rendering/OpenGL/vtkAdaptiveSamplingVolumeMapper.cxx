// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
#include "vtkAdaptiveSamplingVolumeMapper.h"

#include "vtkAdaptiveSamplingPyramid.h"
#include "vtkAdaptiveSamplingRayCaster.h"

#include "vtkCamera.h"
#include "vtkCameraRayModel.h"
#include "vtkDataArray.h"
#include "vtkErrorForwarder.h"
#include "vtkFirstOrderPreIntegrationTable.h"
#include "vtkFloatArray.h"
#include "vtkImageData.h"
#include "vtkMath.h"
#include "vtkMatrix4x4.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkOpenGLRenderWindow.h"
#include "vtkOpenGLState.h"
#include "vtkOpenGLVolumeBricks.h"
#include "vtkPlaneCollection.h"
#include "vtkPointData.h"
#include "vtkRenderer.h"
#include "vtkSMPTools.h"
#include "vtkSmartPointer.h"
#include "vtkTextureObject.h"
#include "vtkVolume.h"
#include "vtkVolumeBrickLayout.h"
#include "vtkVolumeImageAlgorithm.h"
#include "vtkVolumeProperty.h"
#include "vtk_glew.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

vtkStandardNewMacro(vtkAdaptiveSamplingVolumeMapper);

namespace
{
// The most slices a frame may take: beyond, a frame of hours is an error instead.
constexpr double MaximumSlices = 1e5;

// What a full-rate ray caster samples on the same slice grid: per level-0 pixel of the padded
// image, the slices whose point is inside the box (closed form from the ray's clip interval,
// as the CPU core counts it).
vtkIdType FullRateSamples(const vtkAdaptiveSamplingPyramid::Frame& frame, int width, int height)
{
  vtkIdType samples = 0;
  for (int y = 0; y < height; ++y)
  {
    for (int x = 0; x < width; ++x)
    {
      const double px = 2.0 * (x + 0.5) / frame.Width - 1.0;
      const double py = 2.0 * (y + 0.5) / frame.Height - 1.0;
      double o[3], lo, hi;
      for (int a = 0; a < 3; ++a)
      {
        o[a] = frame.RayOrigin[a] + px * frame.RayAxisX[a] + py * frame.RayAxisY[a];
      }
      vtkAdaptiveSamplingRayCaster::ClipSlices(
        o, frame.SliceStep, frame.BoxMax, static_cast<double>(frame.LastSlice), lo, hi);
      if (hi >= lo)
      {
        samples +=
          static_cast<vtkIdType>(std::floor(hi)) - static_cast<vtkIdType>(std::ceil(lo)) + 1;
      }
    }
  }
  return samples;
}
}

struct vtkAdaptiveSamplingVolumeMapper::Internals
{
  // The k-th table (k = 1..2^MaximumLevel) composites a segment of k slice spacings (Fig. 6).
  std::vector<vtkSmartPointer<vtkFirstOrderPreIntegrationTable>> Tables;
  std::vector<int> UploadedBuilds; // the tables' build counts when they were uploaded
  vtkNew<vtkTextureObject> TableTexture;
  // The oracle in the volume's bricks (the base class's, packed into one texture each: the
  // same tiles), so that an axis may exceed the GPU's 3D texture size.
  vtkNew<vtkOpenGLVolumeBricks> OracleBricks;
  // The oracle array last found finite, and its time.
  vtkDataArray* OracleArray = nullptr; // not referenced: only compared
  vtkMTimeType OracleTime = 0;

  vtkAdaptiveSamplingPyramid Pyramid;
  bool ShadingWarned = false; // warned of shading that is not applied, until it is off
  vtkNew<vtkCameraRayModel> Rays;
  vtkOpenGLRenderWindow* Context = nullptr; // not referenced: the window owns its resources

  void Release(vtkWindow* window)
  {
    this->TableTexture->ReleaseGraphicsResources(window);
    this->OracleBricks->ReleaseGraphicsResources(window);
    this->UploadedBuilds.clear();
    this->OracleArray = nullptr;
    this->Pyramid.ReleaseGraphicsResources(window);
    this->Context = nullptr;
  }
};

//------------------------------------------------------------------------------
vtkAdaptiveSamplingVolumeMapper::vtkAdaptiveSamplingVolumeMapper()
  : Internal(new Internals)
{
  this->SetOracleArrayName("OracleDistance");
  vtkErrorForwarder::Forward(this->Internal->Rays, this);
}

//------------------------------------------------------------------------------
vtkAdaptiveSamplingVolumeMapper::~vtkAdaptiveSamplingVolumeMapper()
{
  this->SetOracleArrayName(nullptr);
}

//------------------------------------------------------------------------------
void vtkAdaptiveSamplingVolumeMapper::ReleaseExtensionResources(vtkWindow* window)
{
  this->Internal->Release(window);
}

//------------------------------------------------------------------------------
bool vtkAdaptiveSamplingVolumeMapper::UploadFloatTexture(vtkTextureObject* texture,
  vtkOpenGLRenderWindow* context,
  const int size[3],
  int components,
  float* data,
  const char* what)
{
  texture->SetInternalFormat(components == 1 ? GL_R32F : GL_RGBA32F);
  texture->SetFormat(components == 1 ? GL_RED : GL_RGBA);
  texture->SetDataType(GL_FLOAT);
  std::string why;
  if (!this->CreateTexture3D(texture, context, size, components, VTK_FLOAT, data, what, why))
  {
    vtkErrorMacro(<< why << "; nothing is drawn.");
    return false;
  }
  texture->SetMinificationFilter(vtkTextureObject::Nearest);
  texture->SetMagnificationFilter(vtkTextureObject::Nearest);
  texture->SetWrapS(vtkTextureObject::ClampToEdge);
  texture->SetWrapT(vtkTextureObject::ClampToEdge);
  texture->SetWrapR(vtkTextureObject::ClampToEdge);
  return true;
}

//------------------------------------------------------------------------------
void vtkAdaptiveSamplingVolumeMapper::GPURender(vtkRenderer* ren, vtkVolume* vol)
{
  this->LastFrameSampleOperations = -1;
  this->LastFrameSynthesisOperations = -1;
  this->LastFrameAccumulateOperations = -1;
  this->LastFrameBoundarySampleOperations = -1;
  this->LastFrameFullRateSampleOperations = -1;
  this->NumberOfSlices = 0;
  this->SliceSpacing = 0.0;
  this->LastFramePasses = 0;
  Internals& internal = *this->Internal;

  // Input: single-component point scalars of a grid with cells (the superclass's checks).
  int dims[3], cellFlag = 0;
  FramePlan plan = DrawNothing;
  vtkDataArray* scalars = this->GetFrameScalars(dims, cellFlag, plan);
  vtkImageData* input = vtkImageData::SafeDownCast(this->GetInput());
  if (!scalars)
  {
    if (plan == DrawStock)
    {
      vtkErrorMacro("The input has no scalars to render; nothing is drawn.");
    }
    return;
  }
  if (cellFlag)
  {
    vtkErrorMacro("Adaptive sampling renders point scalars; the scalar mode selects cell data. "
                  "Nothing is drawn.");
    return;
  }
  const std::string why = vtkVolumeImageAlgorithm::CheckVolume(input, scalars);
  if (!why.empty())
  {
    vtkErrorMacro(<< why << " Nothing is drawn.");
    return;
  }
  const int lmax = this->MaximumLevel;
  if (lmax < 0 || lmax > 8)
  {
    vtkErrorMacro("MaximumLevel " << lmax << " is outside [0, 8]; nothing is drawn.");
    return;
  }
  vtkCamera* camera = ren->GetActiveCamera();
  if (!camera->GetParallelProjection())
  {
    if (!this->PerspectiveReported)
    {
      vtkErrorMacro("Adaptive sampling needs a parallel projection (view-aligned slices of "
                    "constant spacing); the camera is perspective. Nothing is drawn until the "
                    "camera is parallel.");
      this->PerspectiveReported = true;
    }
    return;
  }
  this->PerspectiveReported = false;
  if (this->BlendMode != vtkVolumeMapper::COMPOSITE_BLEND || this->Cropping ||
    (this->ClippingPlanes && this->ClippingPlanes->GetNumberOfItems() > 0))
  {
    vtkErrorMacro("Adaptive sampling draws composite blending without cropping or clipping "
                  "planes; nothing is drawn.");
    return;
  }
  vtkVolumeProperty* property = vol->GetProperty();
  if (property->GetShade(0) && !internal.ShadingWarned)
  {
    vtkWarningMacro("Adaptive sampling composites unshaded emission and absorption (the "
                    "paper's model); the volume property's shading is not applied.");
  }
  internal.ShadingWarned = property->GetShade(0) != 0;
  vtkOpenGLRenderWindow* context = vtkOpenGLRenderWindow::SafeDownCast(ren->GetRenderWindow());
  if (!context)
  {
    vtkErrorMacro("Adaptive sampling draws with OpenGL; the render window is not an OpenGL one.");
    return;
  }

  // The oracle array (world units), checked once per array and modification.
  const vtkIdType points = scalars->GetNumberOfTuples();
  vtkDataArray* oracle = nullptr;
  if (this->OracleMode == ORACLE_ARRAY)
  {
    oracle =
      this->OracleArrayName ? input->GetPointData()->GetArray(this->OracleArrayName) : nullptr;
    if (!oracle || oracle->GetNumberOfComponents() != 1 || oracle->GetNumberOfTuples() != points)
    {
      vtkErrorMacro("OracleArrayName \""
        << (this->OracleArrayName ? this->OracleArrayName : "")
        << "\" names no 1-component point array, one value per point; nothing is drawn.");
      return;
    }
    if (oracle != internal.OracleArray || oracle->GetMTime() != internal.OracleTime)
    {
      for (vtkIdType i = 0; i < points; ++i)
      {
        if (!std::isfinite(oracle->GetComponent(i, 0)))
        {
          vtkErrorMacro("The oracle array \"" << this->OracleArrayName << "\" has a value that "
                                              << "is not finite (point " << i
                                              << "); nothing is drawn.");
          return;
        }
      }
      internal.OracleArray = oracle;
      internal.OracleTime = oracle->GetMTime();
    }
  }

  // The viewport and the slice spacing (line 68).
  int width, height, originX, originY;
  ren->GetTiledSizeAndOrigin(&width, &height, &originX, &originY);
  if (width < 1 || height < 1)
  {
    return;
  }
  const double delta = 2.0 * camera->GetParallelScale() / height;
  const double diagonal = input->GetLength();
  if (!(delta > 0.0) || !std::isfinite(delta) || delta > diagonal ||
    !(diagonal / delta <= MaximumSlices))
  {
    vtkErrorMacro("The slice spacing " << delta << " (2 ParallelScale / viewport height) must be "
                                       << "positive, at most the volume's diagonal " << diagonal
                                       << " and give at most " << MaximumSlices
                                       << " slices across it; nothing is drawn.");
    return;
  }
  internal.Rays->SetCamera(camera);
  internal.Rays->SetImageSize(width, height);
  if (!internal.Rays->Prepare())
  {
    return;
  }

  // The tables: the scalar range as the CPU core takes it, one table per segment length.
  double dataRange[2], range[2];
  if (!vtkPreIntegrationTable::ComputeScalarRange(scalars, dataRange, range, this->ScalarRange))
  {
    vtkErrorMacro("The scalars hold no finite value (all NaN); not drawing.");
    return;
  }
  const int block = 1 << lmax;
  internal.Tables.resize(static_cast<size_t>(block));
  bool tablesChanged = internal.UploadedBuilds.size() != static_cast<size_t>(block);
  internal.UploadedBuilds.resize(static_cast<size_t>(block), -1);
  for (int k = 1; k <= block; ++k)
  {
    auto& table = internal.Tables[k - 1];
    if (!table)
    {
      table = vtkSmartPointer<vtkFirstOrderPreIntegrationTable>::New();
      vtkErrorForwarder::Forward(table, this);
    }
    table->SetVolumeProperty(property);
    table->SetSegmentLength(k * delta);
    table->SetScalarRange(range);
    table->SetTableSize(this->TableSize);
    if (!table->Update())
    {
      return;
    }
    if (table->GetBuildCount() != internal.UploadedBuilds[k - 1])
    {
      tablesChanged = true;
      ++this->TableBuildCount;
    }
  }
  const int n = this->TableSize;
  const double toIndex = (n - 1) / (range[1] - range[0]);
  if (internal.Context != context)
  {
    internal.Release(internal.Context ? static_cast<vtkWindow*>(internal.Context) : nullptr);
    internal.Context = context;
    internal.UploadedBuilds.assign(static_cast<size_t>(block), -1);
    tablesChanged = true;
  }
  if (tablesChanged || !internal.TableTexture->GetHandle())
  {
    const size_t entries = static_cast<size_t>(n) * n * 4;
    std::vector<float> all(entries * block);
    for (int k = 0; k < block; ++k)
    {
      const float* table = internal.Tables[k]->GetTable()->GetPointer(0);
      std::copy(table, table + entries, all.begin() + entries * k);
      internal.UploadedBuilds[k] = internal.Tables[k]->GetBuildCount();
    }
    const int size[3] = { n, n, block };
    if (!this->UploadFloatTexture(
          internal.TableTexture, context, size, 4, all.data(), "segment-table texture"))
    {
      internal.UploadedBuilds.assign(static_cast<size_t>(block), -1);
      return;
    }
  }

  // The volume (in its own type: texel reads are exact) and the oracle (world units, float) in
  // bricks packed into one texture each, read texel by texel; the shader maps the volume's raw
  // values to table indices (the scalars through the table's range, as the CPU core looks them
  // up).
  vtkOpenGLVolumeBricks* volumeBricks = this->GetBricks();
  {
    vtkVolumeBrickLayout* layout = volumeBricks->GetLayout();
    int largest = std::max(vtkTextureObject::GetMaximumTextureSize3D(context), 2);
    if (this->MaximumBrickSize > 0)
    {
      largest = std::min(largest, this->MaximumBrickSize);
    }
    layout->SetGhostPoints(0);
    layout->SetMaximumBrickPoints(largest);
    layout->SetMaximumBrickBytes(static_cast<double>(this->MaximumTextureBytes));
    std::string why;
    volumeBricks->SetPrecision(vtkOpenGLVolumeBricks::NATIVE);
    internal.OracleBricks->SetPrecision(vtkOpenGLVolumeBricks::FLOAT32);
    for (vtkOpenGLVolumeBricks* bricks : { volumeBricks, internal.OracleBricks.Get() })
    {
      bricks->SetFiltered(false);
      bricks->SetAtlas(true);
    }
    // The layout leaves room for the oracle's float texels.
    volumeBricks->SetMinimumBytesPerPoint(oracle ? 4 : 0);
    if (!volumeBricks->Update(context, scalars, dims, why))
    {
      vtkErrorMacro("Cannot draw the volume: " << why << "; nothing is drawn.");
      return;
    }
    if (oracle && !internal.OracleBricks->Update(context, oracle, dims, why, layout))
    {
      vtkErrorMacro("Cannot upload the oracle: " << why << "; nothing is drawn.");
      return;
    }
    // Both are planned for the oracle's bytes per point, so they take the same pages.
    if (oracle &&
      internal.OracleBricks->GetNumberOfTextures() != volumeBricks->GetNumberOfTextures())
    {
      vtkErrorMacro("The oracle's textures do not match the volume's; nothing is drawn.");
      return;
    }
  }
  double scale, shift;
  volumeBricks->GetValueMapping(scale, shift);

  // The slice grid in the volume's 0-based continuous grid index: world -> data -> index.
  vtkNew<vtkMatrix4x4> dataToGrid;
  dataToGrid->DeepCopy(input->GetPhysicalToIndexMatrix());
  const int* extent = input->GetExtent();
  for (int r = 0; r < 3; ++r)
  {
    dataToGrid->SetElement(r, 3, dataToGrid->GetElement(r, 3) - extent[2 * r]);
  }
  vtkNew<vtkMatrix4x4> worldToData;
  vtkMatrix4x4::Invert(vol->GetMatrix(), worldToData);
  vtkNew<vtkMatrix4x4> toGrid;
  vtkMatrix4x4::Multiply4x4(dataToGrid, worldToData, toGrid);
  vtkNew<vtkMatrix4x4> toWorld;
  vtkMatrix4x4::Invert(toGrid, toWorld);
  // The CPU core's slice grid, so that both sample the same points.
  double eye[3], forward[3], nearest, axisLength[3];
  internal.Rays->GetRay(0.0, 0.0, eye, forward);
  vtkIdType iMax = vtkAdaptiveSamplingRayCaster::ComputeSliceGrid(
    toWorld, dims, eye, forward, delta, lmax, nearest, axisLength);
  // Slice 0 through the whole volume's nearest corner when the input is a piece of it
  // (WholeBounds), so that every piece samples the whole volume's slices; found from the whole
  // volume's corners alone, so that every piece finds the same.
  double own[6], whole[6];
  input->GetBounds(own);
  std::copy(own, own + 6, whole);
  this->CoverWholeBounds(whole);
  const PieceFrame piece = this->FindPieceFrame(input, delta, lmax, axisLength);
  vtkIdType firstSlice = 0;
  if (!std::equal(own, own + 6, whole) || piece.Joined)
  {
    double wholeNearest = VTK_DOUBLE_MAX;
    for (int c = 0; c < 8; ++c)
    {
      const double corner[4] = {
        whole[(c & 1) ? 1 : 0], whole[(c & 2) ? 3 : 2], whole[(c & 4) ? 5 : 4], 1.0
      };
      double w[4];
      vol->GetMatrix()->MultiplyPoint(corner, w);
      wholeNearest = std::min(wholeNearest, vtkMath::Dot(w, forward) - vtkMath::Dot(eye, forward));
    }
    // The slices before the piece are counted (so that its first slice has its index in the
    // whole volume), and the last slice is again a multiple of 2^l_max; a piece that joins its
    // walks to its neighbours' starts on the slice of 2^l_max at or before its points.
    const double before = std::max(nearest - wholeNearest, 0.0) / delta;
    const vtkIdType front = static_cast<vtkIdType>(std::ceil(before));
    const vtkIdType block = vtkIdType(1) << lmax;
    nearest = wholeNearest;
    iMax = (iMax + front + block - 1) / block * block;
    if (piece.Joined)
    {
      firstSlice = static_cast<vtkIdType>(std::floor(before)) / block * block;
    }
  }
  // Image coordinates (x, y) -> index-space point on slice 0: affine (parallel projection);
  // for a piece, also in structured index (no shift by its extent: the same on every piece).
  double base[3], axisX[3], axisY[3], step[3];
  double structuredBase[3], structuredX[3], structuredY[3], structuredStep[3];
  vtkNew<vtkMatrix4x4> toStructured;
  vtkMatrix4x4::Multiply4x4(input->GetPhysicalToIndexMatrix(), worldToData, toStructured);
  auto frameOf = [&](vtkMatrix4x4* toIndex, double o[3], double x[3], double y[3], double z[3])
  {
    auto slice0 = [&](double u, double v, double p[3])
    {
      double origin[3], direction[3];
      internal.Rays->GetRay(u, v, origin, direction);
      const double world[4] = { origin[0] + nearest * forward[0],
        origin[1] + nearest * forward[1],
        origin[2] + nearest * forward[2],
        1.0 };
      double q[4];
      toIndex->MultiplyPoint(world, q);
      std::copy(q, q + 3, p);
    };
    double px[3], py[3];
    slice0(0.0, 0.0, o);
    slice0(1.0, 0.0, px);
    slice0(0.0, 1.0, py);
    const double forward4[4] = { forward[0], forward[1], forward[2], 0.0 };
    double s[4];
    toIndex->MultiplyPoint(forward4, s);
    for (int a = 0; a < 3; ++a)
    {
      x[a] = px[a] - o[a];
      y[a] = py[a] - o[a];
      z[a] = s[a] * delta;
    }
  };
  frameOf(toGrid, base, axisX, axisY, step);
  frameOf(toStructured, structuredBase, structuredX, structuredY, structuredStep);

  // The pyramid over the padded viewport.
  const int paddedWidth = (width + block - 1) / block * block;
  const int paddedHeight = (height + block - 1) / block * block;
  if (!internal.Pyramid.Prepare(context,
        lmax,
        paddedWidth,
        paddedHeight,
        volumeBricks->GetAtlasDefines() + volumeBricks->GetAtlasSamplerCode("volumeIndex") +
          volumeBricks->GetAtlasSamplerCode("oracleWorld")))
  {
    vtkErrorMacro("The pyramid pass shader did not compile (it needs "
                  "GL_ARB_gpu_shader_fp64); nothing is drawn.");
    return;
  }
  vtkAdaptiveSamplingPyramid::Frame frame;
  frame.MaximumLevel = lmax;
  frame.LastSlice = iMax;
  frame.Width = width;
  frame.Height = height;
  std::copy(base, base + 3, frame.RayOrigin);
  std::copy(axisX, axisX + 3, frame.RayAxisX);
  std::copy(axisY, axisY + 3, frame.RayAxisY);
  std::copy(step, step + 3, frame.SliceStep);
  std::copy(axisLength, axisLength + 3, frame.AxisLength);
  frame.FirstSlice = firstSlice;
  for (int a = 0; a < 3; ++a)
  {
    frame.BoxMax[a] = dims[a] - 1.0;
    frame.WholeMin[a] = piece.WholeMin[a];
    frame.WholeMax[a] = piece.WholeMax[a];
  }
  frame.Piece = piece.Joined;
  if (piece.Joined)
  {
    const int* first = input->GetExtent();
    for (int a = 0; a < 3; ++a)
    {
      frame.StructuredOrigin[a] = structuredBase[a];
      frame.StructuredAxisX[a] = structuredX[a];
      frame.StructuredAxisY[a] = structuredY[a];
      frame.StructuredStep[a] = structuredStep[a];
      frame.OwnedLo[a] = static_cast<double>(piece.OwnedLo[a]) + first[2 * a];
      frame.OwnedHi[a] = static_cast<double>(piece.OwnedHi[a]) + first[2 * a];
      frame.SharedLo[a] = piece.OwnedLo[a] > piece.WholeMin[a] ? 1 : 0;
      frame.SharedHi[a] = piece.OwnedHi[a] < piece.WholeMax[a] ? 1 : 0;
    }
  }
  this->LastFrameJoinedPieces = piece.Joined;
  frame.SliceSpacing = delta;
  frame.TableSize = n;
  frame.MinimumOracle = this->OracleMode == ORACLE_MINIMUM;
  frame.EarlyTermination = this->EarlyRayTermination;
  frame.Count = this->CountOperations;
  frame.Volume = volumeBricks;
  // The minimum oracle reads nothing; its samplers get the volume's textures.
  frame.Oracle = oracle ? internal.OracleBricks.Get() : volumeBricks;
  frame.Tables = internal.TableTexture;
  frame.RawToIndex[0] = scale * toIndex;
  frame.RawToIndex[1] = (shift - range[0]) * toIndex;
  {
    // Without counting, level 0 draws only the rays that meet the box, widened by how far
    // synthesis chains reach (at most 1.5 (2^l_max - 1) level-0 pixels, plus half a coarse
    // block): every pixel outside sees only NaN samples and stays transparent.
    double lo[2] = { std::numeric_limits<double>::infinity(),
      std::numeric_limits<double>::infinity() };
    double hi[2] = { -lo[0], -lo[1] };
    for (int c = 0; c < 8; ++c)
    {
      const double corner[3] = { (c & 1) ? frame.BoxMax[0] : 0.0,
        (c & 2) ? frame.BoxMax[1] : 0.0,
        (c & 4) ? frame.BoxMax[2] : 0.0 };
      // Solve corner - base = x axisX + y axisY + t forward for the image coordinates (x, y):
      // the grid-index frame is affine, so project with the inverse of [axisX axisY step].
      double m[3][3], r[3];
      for (int a = 0; a < 3; ++a)
      {
        m[a][0] = axisX[a];
        m[a][1] = axisY[a];
        m[a][2] = step[a];
        r[a] = corner[a] - base[a];
      }
      double inverse[3][3];
      vtkMath::Invert3x3(m, inverse);
      double xy[3];
      vtkMath::Multiply3x3(inverse, r, xy);
      // Image coordinates in [-1, 1] -> level-0 pixel indices.
      const double px = (xy[0] + 1.0) * 0.5 * width - 0.5;
      const double py = (xy[1] + 1.0) * 0.5 * height - 0.5;
      lo[0] = std::min(lo[0], px);
      hi[0] = std::max(hi[0], px);
      lo[1] = std::min(lo[1], py);
      hi[1] = std::max(hi[1], py);
    }
    const double margin = 2.0 * block + 2.0;
    const int size[2] = { paddedWidth, paddedHeight };
    for (int a = 0; a < 2; ++a)
    {
      const double first = std::floor(lo[a] - margin), last = std::ceil(hi[a] + margin);
      frame.Rectangle[a] = static_cast<int>(std::min(std::max(first, 0.0), size[a] - 1.0));
      frame.Rectangle[a + 2] = static_cast<int>(std::min(std::max(last, 0.0), size[a] - 1.0));
    }
  }

  vtkOpenGLState* state = context->GetState();
  state->PushFramebufferBindings();
  this->LastFramePasses = internal.Pyramid.Draw(frame);
  if (this->CountOperations)
  {
    vtkIdType totals[4];
    internal.Pyramid.ReadCounts(totals);
    this->LastFrameSampleOperations = totals[0];
    this->LastFrameSynthesisOperations = totals[1];
    this->LastFrameAccumulateOperations = totals[2];
    this->LastFrameBoundarySampleOperations = totals[3];
    this->LastFrameFullRateSampleOperations = FullRateSamples(frame, paddedWidth, paddedHeight);
  }
  state->PopFramebufferBindings();

  // The level-0 image, cropped to the viewport, over what the renderer has drawn: premultiplied
  // colour, so "over" is (1, 1 - alpha).
  {
    vtkOpenGLState::ScopedglBlendFuncSeparate blendSaver(state);
    vtkOpenGLState::ScopedglEnableDisable blendEnabled(state, GL_BLEND);
    vtkOpenGLState::ScopedglEnableDisable depthTest(state, GL_DEPTH_TEST);
    vtkOpenGLState::ScopedglDepthMask depthMask(state);
    state->vtkglEnable(GL_BLEND);
    state->vtkglBlendFuncSeparate(GL_ONE, GL_ONE_MINUS_SRC_ALPHA, GL_ONE, GL_ONE_MINUS_SRC_ALPHA);
    state->vtkglDisable(GL_DEPTH_TEST);
    state->vtkglDepthMask(GL_FALSE);
    vtkTextureObject* image = internal.Pyramid.GetImage();
    image->Activate();
    image->CopyToFrameBuffer(
      0, 0, width - 1, height - 1, 0, 0, width - 1, height - 1, width, height, nullptr, nullptr);
    image->Deactivate();
  }
  this->NumberOfSlices = iMax + 1;
  this->SliceSpacing = delta;
}

//------------------------------------------------------------------------------
vtkAdaptiveSamplingVolumeMapper::PieceFrame vtkAdaptiveSamplingVolumeMapper::FindPieceFrame(
  vtkImageData* input,
  double delta,
  int lmax,
  const double axisLength[3])
{
  PieceFrame piece;
  int dims[3];
  input->GetDimensions(dims);
  for (int a = 0; a < 3; ++a)
  {
    piece.WholeMax[a] = dims[a] - 1.0;
  }
  const int* owned = this->OwnedExtent;
  if (!(owned[0] <= owned[1] && owned[2] <= owned[3] && owned[4] <= owned[5]))
  {
    return piece; // the input is the volume
  }
  double wholeLo[3], wholeHi[3];
  this->GetWholeIndexBox(wholeLo, wholeHi);
  this->GetOwnedIndexBox(piece.OwnedLo, piece.OwnedHi);
  // A walk reads 2^l_max slices past the owned points along the ray and 1.5 (2^l_max - 1)
  // pixels (one slice spacing each) across it through synthesis; the oracle there sees
  // 2^l_max slices farther: 2^(l_max + 2) slice spacings and two points bound it.
  piece.Joined = true;
  for (int a = 0; a < 3; ++a)
  {
    const double reach = std::ldexp(delta, lmax + 2) / axisLength[a];
    const double need = std::isfinite(reach) ? std::ceil(reach) + 2.0 : VTK_DOUBLE_MAX;
    // A face with a neighbour: enough ghost points, or all of them up to the whole's face.
    const bool low =
      piece.OwnedLo[a] <= wholeLo[a] || 0.0 <= wholeLo[a] || piece.OwnedLo[a] >= need;
    const bool high = piece.OwnedHi[a] >= wholeHi[a] || dims[a] - 1.0 >= wholeHi[a] ||
      dims[a] - 1.0 - piece.OwnedHi[a] >= need;
    piece.Joined = piece.Joined && low && high;
  }
  for (int a = 0; a < 3; ++a)
  {
    // Joined: the rays end on the whole volume's faces; otherwise on the owned points' own, as
    // for a volume of its own.
    piece.WholeMin[a] = piece.Joined ? wholeLo[a] : piece.OwnedLo[a];
    piece.WholeMax[a] = piece.Joined ? wholeHi[a] : piece.OwnedHi[a];
  }
  return piece;
}

//------------------------------------------------------------------------------
vtkIdType vtkAdaptiveSamplingVolumeMapper::GetOracleTextureMemorySize()
{
  return this->Internal->OracleBricks->GetMemorySize();
}

//------------------------------------------------------------------------------
void vtkAdaptiveSamplingVolumeMapper::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "MaximumLevel: " << this->MaximumLevel << "\n";
  os << indent << "OracleMode: " << (this->OracleMode == ORACLE_ARRAY ? "ARRAY" : "MINIMUM")
     << "\n";
  os << indent << "OracleArrayName: " << (this->OracleArrayName ? this->OracleArrayName : "(none)")
     << "\n";
  os << indent << "TableSize: " << this->TableSize << "\n";
  os << indent << "EarlyRayTermination: " << this->EarlyRayTermination << "\n";
  os << indent << "CountOperations: " << this->CountOperations << "\n";
  os << indent << "LastFrameSampleOperations: " << this->LastFrameSampleOperations << "\n";
  os << indent << "LastFrameSynthesisOperations: " << this->LastFrameSynthesisOperations << "\n";
  os << indent << "LastFrameAccumulateOperations: " << this->LastFrameAccumulateOperations << "\n";
  os << indent << "LastFrameBoundarySampleOperations: " << this->LastFrameBoundarySampleOperations
     << "\n";
  os << indent << "LastFrameFullRateSampleOperations: " << this->LastFrameFullRateSampleOperations
     << "\n";
  os << indent << "NumberOfSlices: " << this->NumberOfSlices << "\n";
  os << indent << "SliceSpacing: " << this->SliceSpacing << "\n";
  os << indent << "LastFramePasses: " << this->LastFramePasses << "\n";
  os << indent << "LastFrameJoinedPieces: " << this->LastFrameJoinedPieces << "\n";
  os << indent << "TableBuildCount: " << this->TableBuildCount << "\n";
}
