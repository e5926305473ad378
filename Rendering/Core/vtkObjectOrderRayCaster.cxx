// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
#include "vtkObjectOrderRayCaster.h"

#include "vtkCamera.h"
#include "vtkCameraRayModel.h"
#include "vtkDataArray.h"
#include "vtkErrorForwarder.h"
#include "vtkFirstOrderPreIntegrationTable.h"
#include "vtkFloatArray.h"
#include "vtkImageData.h"
#include "vtkMatrix4x4.h"
#include "vtkMinMaxOctree.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkObjectOrderRayCasterFrame.h"
#include "vtkObjectOrderRayCasterTiles.h"
#include "vtkPreIntegrationTable.h"
#include "vtkVolumeProperty.h"
#include "vtkVolumeTransferFunctionSampler.h"

#include <algorithm>
#include <cmath>
#include <new>

vtkStandardNewMacro(vtkObjectOrderRayCaster);
vtkCxxSetObjectMacro(vtkObjectOrderRayCaster, VolumeMatrix, vtkMatrix4x4);

namespace
{
// Clears the image when it goes out of scope before the tiles were walked: the walk clears
// what no tile writes, so that no pixel is written twice.
struct ClearUnlessWalked
{
  vtkFloatArray* Image;
  bool Walked = false;
  ~ClearUnlessWalked()
  {
    if (!this->Walked)
    {
      this->Image->FillValue(0.0f);
    }
  }
};
}

// The frame, and the stages of an update that fill it in (each reports its errors through
// the caster and returns false on one).
class vtkObjectOrderRayCaster::vtkInternals : public vtkObjectOrderRayCasterFrame
{
public:
  explicit vtkInternals(vtkObjectOrderRayCaster* self)
    : Self(self)
  {
  }

  bool CheckInput(vtkImageData* input, vtkDataArray* scalars, double range[2]);
  bool UpdateVolume(vtkDataArray* scalars, const int dims[3]);
  void UpdateClassification(vtkDataArray* scalars, double range[2]);
  bool UpdateRays(vtkImageData* input, vtkMatrix4x4* worldToData);
  bool UpdateShading(vtkImageData* input,
    vtkDataArray* scalars,
    const int dims[3],
    vtkMatrix4x4* worldToData);
  bool UpdateSegments(vtkDataArray* scalars, const double range[2]);
  void UpdateSettings();
  void WalkTiles(float* image, double diagonal);

  vtkObjectOrderRayCaster* Self;
};

//------------------------------------------------------------------------------
vtkObjectOrderRayCaster::vtkObjectOrderRayCaster()
  : SegmentTable(vtkFirstOrderPreIntegrationTable::New())
  , Octree(vtkMinMaxOctree::New())
  , Internals(new vtkInternals(this))
{
  // The table's and octree's errors reach the caster's observers (the Python package's).
  vtkErrorForwarder::Forward(this->SegmentTable, this);
  vtkErrorForwarder::Forward(this->Octree, this);
}

//------------------------------------------------------------------------------
vtkObjectOrderRayCaster::~vtkObjectOrderRayCaster()
{
  this->Octree->Delete();
  this->SegmentTable->Delete();
  this->SetVolumeMatrix(nullptr);
  delete this->Internals;
}

//------------------------------------------------------------------------------
vtkMTimeType vtkObjectOrderRayCaster::GetMTime()
{
  const vtkMTimeType t = this->Superclass::GetMTime();
  return this->VolumeMatrix ? std::max(t, this->VolumeMatrix->GetMTime()) : t;
}

//------------------------------------------------------------------------------
vtkIdType vtkObjectOrderRayCaster::GetMemorySize() const
{
  const vtkInternals& I = *this->Internals;
  return static_cast<vtkIdType>(I.Volume.GetMemorySize() + I.Shading.GetMemorySize()) +
    this->Octree->GetMemorySize();
}

//------------------------------------------------------------------------------
int vtkObjectOrderRayCaster::RequestData(vtkInformation*,
  vtkInformationVector** inputVector,
  vtkInformationVector* outputVector)
{
  vtkInternals& I = *this->Internals;
  I.Ready = false;
  this->LastUpdateOutOfMemory = false;
  this->NumberOfNonTransparentCells = this->NumberOfNodesVisited = this->NumberOfSamples = 0;
  vtkImageData* input = vtkImageData::GetData(inputVector[0]);
  vtkFloatArray* rgba = this->InitializeOutput(vtkImageData::GetData(outputVector), false);
  if (!rgba)
  {
    return 1;
  }
  ClearUnlessWalked clearImage{ rgba };
  int dims[3];
  double range[2];
  vtkDataArray* scalars = this->PrepareFrame(input, inputVector, dims);
  if (!scalars || !I.CheckInput(input, scalars, range) || !I.UpdateVolume(scalars, dims))
  {
    return 1;
  }
  this->UpdateProgress(0.1);
  I.UpdateClassification(scalars, range);
  vtkNew<vtkMatrix4x4> worldToData; // the inverse of the placement (identity without one)
  if (!I.UpdateRays(input, worldToData) || !I.UpdateShading(input, scalars, dims, worldToData) ||
    !I.UpdateSegments(scalars, range))
  {
    return 1;
  }
  I.UpdateSettings();
  clearImage.Walked = true;
  I.WalkTiles(rgba->GetPointer(0), input->GetLength());
  // Cells sampled, each once whatever the tiles and rays that sampled it.
  this->NumberOfNonTransparentCells = I.Volume.CountSampledCells();
  if (!this->GetAbortExecute())
  {
    this->WarnIfTransparent(rgba);
  }
  this->UpdateProgress(1.0);
  return 1;
}

//------------------------------------------------------------------------------
// The settings the walk cannot handle, and the scalar range (finite values) of the volume.
bool vtkObjectOrderRayCaster::vtkInternals::CheckInput(vtkImageData* input,
  vtkDataArray* scalars,
  double range[2])
{
  vtkObjectOrderRayCaster* self = this->Self;
  if (!self->CheckSampleDistance(input, self->SampleDistance, self->MaximumSamplesPerRay))
  {
    return false;
  }
  const double* spacing = input->GetSpacing();
  const double voxel =
    std::min({ std::abs(spacing[0]), std::abs(spacing[1]), std::abs(spacing[2]) });
  if (self->SampleDistance < 1e-5 * voxel)
  {
    vtkErrorWithObjectMacro(self,
      "The sample distance " << self->SampleDistance << " is below 1e-5 voxel (" << voxel
                             << "), where the walker's float positions lose it.");
    return false;
  }
  if (!self->GetCamera()->GetParallelProjection())
  {
    vtkErrorWithObjectMacro(self,
      "Object-order ray casting needs a parallel projection (every cell projects "
      "to the same shape); the camera has a perspective one.");
    return false;
  }
  // The finite range (not empty: checked by PrepareFrame), widened to ScalarRange.
  double widened[2];
  vtkPreIntegrationTable::ComputeScalarRange(scalars, range, widened, self->ScalarRange);
  if (std::max(std::abs(range[0]), std::abs(range[1])) > VTK_FLOAT_MAX)
  {
    vtkErrorWithObjectMacro(self,
      "The scalar range [" << range[0] << ", " << range[1]
                           << "] exceeds float range, in which the caster stores the "
                              "volume; rescale the values.");
    return false;
  }
  return true;
}

//------------------------------------------------------------------------------
// The volume: bricks and octree, once per data. Their allocations are the caster's only
// large ones (about 7 bytes per point): when memory runs out, an error and an empty image
// rather than an exception through the pipeline.
bool vtkObjectOrderRayCaster::vtkInternals::UpdateVolume(vtkDataArray* scalars, const int dims[3])
{
  if (this->Volume.IsBuiltFor(scalars, dims))
  {
    return true;
  }
  try
  {
    this->Volume.Build(scalars, dims);
    if (!this->Self->Octree->Build(scalars, dims))
    {
      this->ReleaseVolume();
      return false;
    }
  }
  catch (const std::bad_alloc&)
  {
    this->Self->OutOfMemory(dims, "the float bricks and octree");
    return false;
  }
  this->Volume.Scalars = scalars;
  this->Volume.ScalarsTime = scalars->GetMTime();
  return true;
}

//------------------------------------------------------------------------------
// The classification table over the data range (widened when the range is a single value).
void vtkObjectOrderRayCaster::vtkInternals::UpdateClassification(vtkDataArray* scalars,
  double range[2])
{
  vtkObjectOrderRayCaster* self = this->Self;
  if (!(range[1] > range[0]))
  {
    // A relative width: range[0] + 1 rounds back to range[0] beyond 2^53.
    range[1] = range[0] + std::max(1.0, std::abs(range[0]) * 1e-6);
  }
  if (this->Classification.Update(
        self->Sampler, scalars->GetDataType(), range, self->SampleDistance))
  {
    this->Volume.NewClassification(); // the bricks' visible cells are found again
  }
  self->TableSize = this->Classification.Entries;
}

//------------------------------------------------------------------------------
// Pixel rays in grid index (0-based from the extent's first point): world -> data (the
// volume's placement) -> grid index. worldToData is set to the inverse of the placement.
bool vtkObjectOrderRayCaster::vtkInternals::UpdateRays(vtkImageData* input,
  vtkMatrix4x4* worldToData)
{
  vtkObjectOrderRayCaster* self = this->Self;
  if (self->VolumeMatrix)
  {
    const double* m = self->VolumeMatrix->GetData();
    const double determinant = self->VolumeMatrix->Determinant();
    if (!std::all_of(m, m + 16, [](double x) { return std::isfinite(x); }) ||
      !(std::abs(determinant) > 0.0) || !std::isfinite(determinant))
    {
      vtkErrorWithObjectMacro(self,
        "The volume matrix must be finite and invertible (determinant " << determinant << ").");
      return false;
    }
    vtkMatrix4x4::Invert(self->VolumeMatrix, worldToData);
  }
  vtkNew<vtkMatrix4x4> toStructured, toIndex;
  vtkMatrix4x4::Multiply4x4(input->GetPhysicalToIndexMatrix(), worldToData, toStructured);
  toIndex->DeepCopy(toStructured);
  const int* extent = input->GetExtent();
  for (int r = 0; r < 3; ++r)
  {
    toIndex->SetElement(r, 3, toIndex->GetElement(r, 3) - extent[2 * r]);
  }
  const int* size = self->GetImageSize();
  const int image[2] = { std::max(size[0], 1), std::max(size[1], 1) };
  this->Rays.Update(self->RayModel, toIndex, image, this->Volume.Cells, self->SampleDistance);
  const int* owned = self->OwnedExtent;
  if (owned[0] <= owned[1] && owned[2] <= owned[3] && owned[4] <= owned[5])
  {
    double wholeLo[3], wholeHi[3];
    int ownedLo[3], ownedHi[3];
    vtkVolumeImageAlgorithm::ComputeWholeIndexBox(input, self->WholeBounds, wholeLo, wholeHi);
    vtkVolumeImageAlgorithm::ComputeOwnedIndexBox(input, owned, ownedLo, ownedHi);
    const int first[3] = { extent[0], extent[2], extent[4] };
    this->Rays.SetPiece(wholeLo, wholeHi, ownedLo, ownedHi, first, toStructured, self->RayModel);
  }
  return true;
}

//------------------------------------------------------------------------------
// Shading: the headlight in data space, where normals are taken; with pre-shading, the
// quantized normals (once per volume) and the reflectance map (per frame).
bool vtkObjectOrderRayCaster::vtkInternals::UpdateShading(vtkImageData* input,
  vtkDataArray* scalars,
  const int dims[3],
  vtkMatrix4x4* worldToData)
{
  vtkObjectOrderRayCaster* self = this->Self;
  using Modes = vtkObjectOrderRayCasterShading::Modes;
  int mode = Modes::NONE;
  if (self->VolumeProperty->GetShade(0))
  {
    mode = self->ShadingMode == PRE_SHADING ? Modes::PRE_SHADING : Modes::POST_SHADING;
  }
  this->Shading.Update(mode, input, self->VolumeProperty, this->Rays.WorldDirection, worldToData);
  if (mode != Modes::PRE_SHADING)
  {
    return true;
  }
  if (!this->Shading.HasNormalsOf(scalars, this->Volume))
  {
    try
    {
      this->Shading.QuantizeNormals(scalars, this->Volume);
    }
    catch (const std::bad_alloc&)
    {
      self->OutOfMemory(dims, "the quantized normals (pre-shading)");
      return false;
    }
  }
  this->Shading.BuildReflectanceMap();
  return true;
}

//------------------------------------------------------------------------------
// Pre-integrated classification: the first-order table for one step over the data range
// (the sampler prepared by PrepareFrame).
bool vtkObjectOrderRayCaster::vtkInternals::UpdateSegments(vtkDataArray* scalars,
  const double range[2])
{
  vtkObjectOrderRayCaster* self = this->Self;
  this->Classification.Preintegrated = self->Classification == PREINTEGRATED;
  return !this->Classification.Preintegrated ||
    this->Classification.UpdateSegments(self->SegmentTable,
      self->VolumeProperty,
      self->Sampler,
      scalars->GetDataType(),
      range,
      self->SampleDistance);
}

//------------------------------------------------------------------------------
void vtkObjectOrderRayCaster::vtkInternals::UpdateSettings()
{
  vtkObjectOrderRayCaster* self = this->Self;
  this->Step = self->SampleDistance;
  this->Interleaved = self->InterleavedSampling;
  this->Removal = self->HiddenVolumeRemoval;
  this->Threshold = static_cast<float>(self->OpacityThreshold);
  // Leaves of LeafSize cells, rounded down to a power of two: at most 8^3 cells, inside one
  // brick.
  constexpr int maxLeafLevel = 3;
  int leafLevel = 0;
  while (leafLevel < maxLeafLevel && (2 << leafLevel) <= self->LeafSize)
  {
    ++leafLevel;
  }
  this->LeafLevel = std::min(leafLevel, self->Octree->GetNumberOfLevels());
  this->Ready = true;
}

//------------------------------------------------------------------------------
// The tiles, with the copy of the walk the settings and the processor allow. A frame expected
// to take many samples (every pixel of the volume's rectangle through the whole diagonal) is
// walked in parts, with progress in between: progress events come from this thread only.
void vtkObjectOrderRayCaster::vtkInternals::WalkTiles(float* image, double diagonal)
{
  vtkObjectOrderRayCaster* self = this->Self;
  const bool hasAVX2 = vtkObjectOrderRayCasterTiles::HasAVX2();
  self->LastInstructionSet =
    self->InstructionSet == INSTRUCTIONS_SSE2 || !hasAVX2 ? INSTRUCTIONS_SSE2 : INSTRUCTIONS_AVX2;
  if (self->InstructionSet == INSTRUCTIONS_AVX2 && !hasAVX2)
  {
    vtkWarningWithObjectMacro(self,
      "The AVX2 sample loop was asked for, but this processor (or this build) "
      "lacks AVX2 and FMA; rendering with the SSE2 one.");
  }
  const int tile = self->TileSize;
  const int tilesX = (this->Rays.Width + tile - 1) / tile;
  const int tilesY = (this->Rays.Height + tile - 1) / tile;
  const vtkIdType tiles = static_cast<vtkIdType>(tilesX) * tilesY;
  const int* pixels = this->Rays.VolumePixels;
  const double expectedSamples =
    (pixels[1] - pixels[0] + 1.0) * (pixels[3] - pixels[2] + 1.0) * diagonal / self->SampleDistance;
  const vtkIdType parts = expectedSamples > (1 << 28) ? std::min<vtkIdType>(tiles, 20) : 1;
  for (vtkIdType part = 0; part < parts; ++part)
  {
    vtkObjectOrderRayCasterTiles::Walk(*this,
      self->Octree,
      self->LastInstructionSet == INSTRUCTIONS_AVX2,
      tile,
      part * tiles / parts,
      (part + 1) * tiles / parts,
      self->AbortExecute,
      image,
      self->NumberOfNodesVisited,
      self->NumberOfSamples);
    if (parts > 1)
    {
      self->UpdateProgress(0.1 + 0.9 * static_cast<double>(part + 1) / parts);
    }
  }
}

//------------------------------------------------------------------------------
void vtkObjectOrderRayCaster::OutOfMemory(const int dims[3], const char* what)
{
  vtkInternals& I = *this->Internals;
  I.ReleaseVolume();
  this->Octree->Initialize();
  this->LastUpdateOutOfMemory = true;
  // What the copies need: bricks of 8^3 cells with their far faces, in float.
  double bricks = vtkObjectOrderRayCasterBricks::BrickValues * sizeof(float);
  for (int a = 0; a < 3; ++a)
  {
    bricks *= vtkObjectOrderRayCasterBricks::BrickCountAlong(dims[a]);
  }
  vtkErrorMacro("Not enough memory for " << what << " of the " << dims[0] << " x " << dims[1]
                                         << " x " << dims[2] << " volume (the bricks alone take "
                                         << std::ceil(bricks / (1 << 20))
                                         << " MiB); the image is empty.");
}

//------------------------------------------------------------------------------
void vtkObjectOrderRayCaster::GetLastVolumePixels(int rect[4]) const
{
  static const int none[4] = { 0, -1, 0, -1 };
  const vtkInternals& I = *this->Internals;
  const int* pixels = I.Ready ? I.Rays.VolumePixels : none;
  std::copy(pixels, pixels + 4, rect);
}

//------------------------------------------------------------------------------
vtkIdType vtkObjectOrderRayCaster::ComputeNonTransparentCells()
{
  const vtkInternals& I = *this->Internals;
  if (!I.Ready)
  {
    return -1;
  }
  return vtkObjectOrderRayCasterTiles::CountNonTransparentCells(I, this->Octree);
}

void vtkObjectOrderRayCaster::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "SampleDistance: " << this->SampleDistance << "\n";
  os << indent << "InterleavedSampling: " << this->InterleavedSampling << "\n";
  os << indent << "HiddenVolumeRemoval: " << this->HiddenVolumeRemoval << "\n";
  os << indent << "OpacityThreshold: " << this->OpacityThreshold << "\n";
  os << indent << "TileSize: " << this->TileSize << "\n";
  os << indent << "LeafSize: " << this->LeafSize << "\n";
  os << indent << "ScalarRange: " << this->ScalarRange[0] << ", " << this->ScalarRange[1] << "\n";
  os << indent << "WholeBounds:";
  for (double b : this->WholeBounds)
  {
    os << " " << b;
  }
  os << "\n";
  os << indent << "OwnedExtent:";
  for (int e : this->OwnedExtent)
  {
    os << " " << e;
  }
  os << "\n";
  os << indent << "InstructionSet: " << this->InstructionSet << "\n";
  os << indent << "LastInstructionSet: " << this->LastInstructionSet << "\n";
  os << indent << "ShadingMode: " << this->ShadingMode << "\n";
  os << indent << "Classification: " << this->Classification << "\n";
  os << indent << "VolumeMatrix: " << this->VolumeMatrix << "\n";
  os << indent << "NumberOfNonTransparentCells: " << this->NumberOfNonTransparentCells << "\n";
  os << indent << "NumberOfNodesVisited: " << this->NumberOfNodesVisited << "\n";
  os << indent << "NumberOfSamples: " << this->NumberOfSamples << "\n";
  os << indent << "TableSize: " << this->TableSize << "\n";
  os << indent << "LastUpdateOutOfMemory: " << this->LastUpdateOutOfMemory << "\n";
}
