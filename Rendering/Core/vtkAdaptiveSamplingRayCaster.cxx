// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
#include "vtkAdaptiveSamplingRayCaster.h"

#include "vtkCamera.h"
#include "vtkCameraRayModel.h"
#include "vtkDataArray.h"
#include "vtkFirstOrderPreIntegrationTable.h"
#include "vtkFloatArray.h"
#include "vtkImageData.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkMatrix4x4.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPreIntegrationRayMarch.h"
#include "vtkSMPTools.h"
#include "vtkSmartPointer.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <vector>

vtkStandardNewMacro(vtkAdaptiveSamplingRayCaster);

// The k-th table (k = 1..2^MaximumLevel) composites a segment of k slice spacings (Fig. 6).
struct vtkAdaptiveSamplingRayCaster::Tables
{
  std::vector<vtkSmartPointer<vtkFirstOrderPreIntegrationTable>> ByLength;
};

namespace
{
// One pyramid level: per pixel the data sample s, the oracle distance d (slice spacings) and
// the ray's origin in 0-based continuous grid index (Fig. 5's SAMPLE point on slice 0).
struct Level
{
  int Width = 0, Height = 0;
  std::vector<double> S, D, Origin;
};

struct Counts
{
  std::atomic<vtkIdType> Samples{ 0 }, Synthesis{ 0 }, Accumulates{ 0 }, Boundary{ 0 };
};

// Whether the 0-based continuous grid index point is outside the closed box [0, box];
// distance2 receives the squared world distance to the box.
bool Outside(const double point[3],
  const double box[3],
  const double axisLength[3],
  double& distance2)
{
  distance2 = 0.0;
  for (int a = 0; a < 3; ++a)
  {
    const double excess = std::max(-point[a], point[a] - box[a]);
    if (excess > 0.0)
    {
      distance2 += excess * excess * axisLength[a] * axisLength[a];
    }
  }
  return distance2 > 0.0;
}
}

//------------------------------------------------------------------------------
vtkAdaptiveSamplingRayCaster::vtkAdaptiveSamplingRayCaster()
  : SegmentTables(new Tables)
{
  this->SetOracleArrayName("OracleDistance");
}

//------------------------------------------------------------------------------
vtkAdaptiveSamplingRayCaster::~vtkAdaptiveSamplingRayCaster()
{
  this->SetOracleArrayName(nullptr);
}

//------------------------------------------------------------------------------
int vtkAdaptiveSamplingRayCaster::SliceLevel(vtkIdType sliceIndex, int maximumLevel)
{
  int level = 0;
  if (sliceIndex == 0)
  {
    return maximumLevel;
  }
  while (level < maximumLevel && (sliceIndex & (vtkIdType(1) << level)) == 0)
  {
    ++level;
  }
  return level;
}

//------------------------------------------------------------------------------
vtkIdType vtkAdaptiveSamplingRayCaster::NextSampleSlice(vtkIdType sliceIndex,
  double d,
  int maximumLevel)
{
  // Non-skipped slices satisfy d < 2^(l_slice + 1), i.e. l_slice >= floor(log2 d), or
  // l_slice = l_max: the multiples of 2^q.
  const int q =
    std::min(static_cast<int>(std::floor(std::log2(std::max(d, 1.0)))), std::max(maximumLevel, 0));
  const vtkIdType step = vtkIdType(1) << q;
  return (sliceIndex / step + 1) * step;
}

//------------------------------------------------------------------------------
int vtkAdaptiveSamplingRayCaster::RequestData(vtkInformation*,
  vtkInformationVector** inputVector,
  vtkInformationVector* outputVector)
{
  this->NumberOfSampleOperations = 0;
  this->NumberOfOracleOperations = 0;
  this->NumberOfSynthesisOperations = 0;
  this->NumberOfAccumulateOperations = 0;
  this->NumberOfBoundarySampleOperations = 0;
  this->FullRateSampleOperations = 0;
  this->NumberOfSlices = 0;
  this->SliceSpacing = 0.0;

  vtkImageData* input = vtkImageData::GetData(inputVector[0]);
  vtkFloatArray* rgba = this->InitializeOutput(vtkImageData::GetData(outputVector));
  if (!rgba)
  {
    return 1;
  }
  const int lmax = this->MaximumLevel;
  if (lmax < 0 || lmax > 8)
  {
    vtkErrorMacro("MaximumLevel " << lmax << " is outside [0, 8]; the image is empty.");
    return 1;
  }
  vtkCamera* camera = this->GetCamera();
  if (camera && !camera->GetParallelProjection())
  {
    vtkErrorMacro("Adaptive sampling needs a parallel projection (view-aligned slices of "
                  "constant spacing); the camera is perspective. The image is empty.");
    return 1;
  }
  const int* size = this->GetImageSize();
  const int width = size[0], height = size[1];
  const int block = 1 << lmax;
  if (width % block != 0 || height % block != 0)
  {
    vtkErrorMacro("The image size " << width << " x " << height
                                    << " is not divisible by 2^MaximumLevel = " << block
                                    << "; the image is empty.");
    return 1;
  }
  int dims[3];
  vtkDataArray* scalars = this->PrepareFrame(input, inputVector, dims);
  if (!scalars)
  {
    return 1;
  }
  const vtkIdType numberOfPoints = scalars->GetNumberOfTuples();
  std::vector<double> oracle;
  if (this->OracleMode == ORACLE_ARRAY)
  {
    vtkDataArray* array =
      this->OracleArrayName ? input->GetPointData()->GetArray(this->OracleArrayName) : nullptr;
    if (!array || array->GetNumberOfComponents() != 1 ||
      array->GetNumberOfTuples() != numberOfPoints)
    {
      vtkErrorMacro("OracleArrayName \""
        << (this->OracleArrayName ? this->OracleArrayName : "")
        << "\" names no 1-component point array, one value per point; the image is empty.");
      return 1;
    }
    oracle.resize(static_cast<size_t>(numberOfPoints));
    for (vtkIdType i = 0; i < numberOfPoints; ++i)
    {
      oracle[i] = array->GetComponent(i, 0);
      if (!std::isfinite(oracle[i]))
      {
        vtkErrorMacro("The oracle array \"" << this->OracleArrayName << "\" has a value that is "
                                            << "not finite (point " << i
                                            << "); the image is empty.");
        return 1;
      }
    }
  }

  // Slice spacing: the distance between neighbouring view rays (line 68).
  const double delta = 2.0 * camera->GetParallelScale() / height;
  if (!this->CheckSampleDistance(input, delta, this->MaximumSamplesPerRay))
  {
    return 1;
  }

  double dataRange[2], range[2];
  if (!vtkPreIntegrationTable::ComputeScalarRange(scalars, dataRange, range))
  {
    vtkErrorMacro("The scalars hold no finite value (all NaN); the image is empty.");
    return 1;
  }
  auto& tables = this->SegmentTables->ByLength;
  tables.resize(static_cast<size_t>(block));
  std::vector<vtkPreIntegrationRayMarch::TablePieces> pieces(static_cast<size_t>(block));
  for (int k = 1; k <= block; ++k)
  {
    auto& table = tables[k - 1];
    if (!table)
    {
      table = vtkSmartPointer<vtkFirstOrderPreIntegrationTable>::New();
    }
    table->SetVolumeProperty(this->VolumeProperty);
    table->SetSegmentLength(k * delta);
    table->SetScalarRange(range);
    table->SetTableSize(this->TableSize);
    table->ComputeEntriesOn();
    if (!table->Update())
    {
      return 1;
    }
    pieces[k - 1].Table = vtkPreIntegrationRayMarch::TableView::Of(table);
  }

  vtkPreIntegrationRayMarch::Grid grid;
  if (!grid.Values.SetArray(scalars))
  {
    vtkErrorMacro("Not enough memory for a double copy of the volume; the image is empty.");
    return 1;
  }
  std::copy(dims, dims + 3, grid.Dims);
  vtkPreIntegrationRayMarch::Grid oracleGrid = grid;
  oracleGrid.Values.SetValues(oracle.data(), static_cast<vtkIdType>(oracle.size()));

  // World -> 0-based continuous grid index, as the twin maps it.
  vtkNew<vtkMatrix4x4> toIndex;
  toIndex->DeepCopy(input->GetPhysicalToIndexMatrix());
  const int* extent = input->GetExtent();
  for (int r = 0; r < 3; ++r)
  {
    toIndex->SetElement(r, 3, toIndex->GetElement(r, 3) - extent[2 * r]);
  }
  vtkNew<vtkMatrix4x4> toWorld;
  vtkMatrix4x4::Invert(toIndex, toWorld);
  // Slice 0 through the box corner nearest to the plane of the ray origins (the camera
  // position's plane); axisLength: the world length of one index unit along each axis, for the
  // distance to the box outside it.
  double eye[3], forward[3], nearest, axisLength[3];
  this->RayModel->GetRay(0.0, 0.0, eye, forward);
  const vtkIdType iMax =
    ComputeSliceGrid(toWorld, dims, eye, forward, delta, lmax, nearest, axisLength);
  this->NumberOfSlices = iMax + 1;
  this->SliceSpacing = delta;
  const double forward4[4] = { forward[0], forward[1], forward[2], 0.0 };
  double step[4];
  toIndex->MultiplyPoint(forward4, step);
  for (int a = 0; a < 3; ++a)
  {
    step[a] *= delta; // index-space offset from one slice to the next
  }

  // The pyramid (Sec. 3.2): level-l pixel (x, y) on the ray through level-0 pixel
  // (2^l (x + 1/2) - 1/2, 2^l (y + 1/2) - 1/2) (lines 137-138).
  std::vector<Level> levels(static_cast<size_t>(lmax + 1));
  for (int l = 0; l <= lmax; ++l)
  {
    Level& level = levels[l];
    level.Width = width >> l;
    level.Height = height >> l;
    const size_t n = static_cast<size_t>(level.Width) * level.Height;
    level.S.assign(n, std::numeric_limits<double>::quiet_NaN());
    level.D.assign(n, 1.0);
    level.Origin.resize(3 * n);
    for (int y = 0; y < level.Height; ++y)
    {
      for (int x = 0; x < level.Width; ++x)
      {
        const double px = 2.0 * ((1 << l) * (x + 0.5)) / width - 1.0;
        const double py = 2.0 * ((1 << l) * (y + 0.5)) / height - 1.0;
        double origin[3], direction[3];
        this->RayModel->GetRay(px, py, origin, direction);
        const double first[4] = { origin[0] + nearest * forward[0],
          origin[1] + nearest * forward[1],
          origin[2] + nearest * forward[2],
          1.0 };
        double o[4];
        toIndex->MultiplyPoint(first, o);
        std::copy(o, o + 3, level.Origin.begin() + 3 * (static_cast<size_t>(y) * level.Width + x));
      }
    }
  }
  const size_t pixels = static_cast<size_t>(width) * height;
  std::vector<double> previous(pixels, std::numeric_limits<double>::quiet_NaN());
  std::vector<vtkIdType> previousSlice(pixels, -1);
  std::vector<double> colour(4 * pixels, 0.0);

  const double box[3] = { dims[0] - 1.0, dims[1] - 1.0, dims[2] - 1.0 };
  const double dmax = static_cast<double>(block);
  const bool minimum = this->OracleMode == ORACLE_MINIMUM;
  const bool fig3 = this->Algorithm == ALGORITHM_FIG3;
  Counts counts;
  vtkIdType fullRate = 0;

  // Per level-0 pixel, the slice coordinates t_in <= t_out where its ray enters and leaves
  // the box (clipped to [0, i_max], which holds the box: slice 0 touches its nearest corner,
  // i_max lies at or behind the farthest); t_in > t_out when the ray misses it. Full rate:
  // level-0 pixels times the slices whose point is inside the box (closed form from that
  // interval, so that it costs no sampling).
  std::vector<double> tIn(pixels), tOut(pixels);
  {
    const Level& level0 = levels[0];
    for (size_t p = 0; p < pixels; ++p)
    {
      ClipSlices(&level0.Origin[3 * p], step, box, static_cast<double>(iMax), tIn[p], tOut[p]);
      if (tOut[p] >= tIn[p])
      {
        fullRate += static_cast<vtkIdType>(std::floor(tOut[p])) -
          static_cast<vtkIdType>(std::ceil(tIn[p])) + 1;
      }
    }
  }

  for (vtkIdType slice = 0; slice <= iMax; ++slice)
  {
    if (slice % 16 == 0)
    {
      this->UpdateProgress(static_cast<double>(slice) / (iMax + 1));
      if (this->GetAbortExecute())
      {
        break;
      }
    }
    const int lslice = SliceLevel(slice, lmax);
    const double accumulateBelow = std::ldexp(1.0, lslice + 1);
    for (int l = lslice; l >= 0; --l)
    {
      Level& level = levels[l];
      const Level* coarse = l < lmax ? &levels[l + 1] : nullptr;
      const double sampleBelow = std::ldexp(1.0, l + 1);
      vtkSMPTools::For(0,
        static_cast<vtkIdType>(level.Width) * level.Height,
        [&](vtkIdType begin, vtkIdType end)
        {
          vtkIdType samples = 0, synthesis = 0, accumulates = 0, boundary = 0;
          for (vtkIdType p = begin; p < end; ++p)
          {
            double& s = level.S[p];
            double& d = level.D[p];
            // SYNTHESIZE (Fig. 5): bilinear lookup of level l + 1 at the fine pixel's centre,
            // coarse coordinate x / 2 - 1/4, clamped to the edge (line 127).
            const bool synthesize = l < lslice && (!fig3 || lslice == lmax || d < accumulateBelow);
            const double* o = &level.Origin[3 * p];
            const double point[3] = {
              o[0] + slice * step[0], o[1] + slice * step[1], o[2] + slice * step[2]
            };
            double outside = 0.0;
            bool repair = false;
            if (synthesize)
            {
              const int x = static_cast<int>(p % level.Width),
                        y = static_cast<int>(p / level.Width);
              d = Synthesize(coarse->D.data(), coarse->Width, coarse->Height, x, y);
              s = Synthesize(coarse->S.data(), coarse->Width, coarse->Height, x, y);
              ++synthesis;
            }
            // Fig. 7 decides both tests on d before resampling (the depth value z_l, lines
            // 177-190); Fig. 3 decides accumulation on the new d.
            bool accumulate = lslice == lmax || d < accumulateBelow;
            if (synthesize && accumulate)
            {
              // On a slice the pixel accumulates, a NaN from a coarse neighbour outside the box
              // at a point inside it is sampled instead, so that NaN does not spread inwards
              // from the silhouette and drop segments inside. (On other slices the synthesised
              // values are stale and unused: sampling them would cost without effect.)
              repair =
                (std::isnan(s) || std::isnan(d)) && !Outside(point, box, axisLength, outside);
            }
            const bool sample = repair || l == lmax || d < sampleBelow;
            if (sample)
            {
              if (Outside(point, box, axisLength, outside))
              {
                // Default value (line 68): NaN, a transparent segment end; the oracle is the
                // distance to the box. Nothing is fetched.
                s = std::numeric_limits<double>::quiet_NaN();
                d = minimum ? 1.0 : std::sqrt(outside) / delta;
              }
              else
              {
                s = grid.Sample(point);
                d = minimum ? 1.0 : oracleGrid.Sample(point) / delta;
                ++samples;
              }
              d = std::min(std::max(d, 1.0), dmax);
              if (fig3)
              {
                accumulate = lslice == lmax || d < accumulateBelow;
              }
            }
            if (l == 0 && accumulate)
            {
              // ACCUMULATECOLOR (Fig. 6): the part of the k = i - i_prev spacings from the
              // previous accumulated slice that lies inside the box, from its entry or up to
              // its exit where the ray crosses a face in between.
              if (previousSlice[p] >= 0)
              {
                const vtkIdType iPrev = previousSlice[p];
                const double front = std::max(static_cast<double>(iPrev), tIn[p]);
                const double back = std::min(static_cast<double>(slice), tOut[p]);
                const double length = back - front;
                if (length > 0.0 && slice - iPrev <= block)
                {
                  // An end whose slice point is inside the box takes the slice's value; an
                  // end on a face is fetched there (not a slice sample: counted apart). The
                  // choice follows the samples' own inside test rather than comparing i_prev
                  // with t_in and i with t_out, which can disagree by a rounding where a slice
                  // point lies on a face (slice 0 on the entry face of an axis-aligned view):
                  // a slice value that is NaN because its point rounds outside is then never
                  // used.
                  double sf = previous[p], sb = s, unused;
                  const double pf[3] = {
                    o[0] + iPrev * step[0], o[1] + iPrev * step[1], o[2] + iPrev * step[2]
                  };
                  if (Outside(pf, box, axisLength, unused))
                  {
                    const double q[3] = {
                      o[0] + front * step[0], o[1] + front * step[1], o[2] + front * step[2]
                    };
                    sf = grid.Sample(q);
                    ++boundary;
                  }
                  if (Outside(point, box, axisLength, unused))
                  {
                    const double q[3] = {
                      o[0] + back * step[0], o[1] + back * step[1], o[2] + back * step[2]
                    };
                    sb = grid.Sample(q);
                    ++boundary;
                  }
                  if (!std::isnan(sf) && !std::isnan(sb))
                  {
                    // A piece shorter than its whole spacings: table ceil(L) with the optical
                    // depth scaled to L (exact for a constant scalar), as the GLSL of
                    // first-order pre-integration composites its last piece.
                    const double layers = std::ceil(length);
                    double segment[4];
                    pieces[static_cast<size_t>(layers) - 1].Segment(
                      sf, sb, length / layers, layers * delta, segment);
                    double* c = &colour[4 * p];
                    const double transmittance = 1.0 - c[3];
                    for (int q = 0; q < 4; ++q)
                    {
                      c[q] += transmittance * segment[q];
                    }
                  }
                }
                ++accumulates;
              }
              previous[p] = s;
              previousSlice[p] = slice;
            }
          }
          counts.Samples += samples;
          counts.Synthesis += synthesis;
          counts.Accumulates += accumulates;
          counts.Boundary += boundary;
        });
    }
  }
  this->UpdateProgress(1.0);

  float* out = rgba->GetPointer(0);
  for (size_t i = 0; i < 4 * pixels; ++i)
  {
    out[i] = static_cast<float>(colour[i]);
  }
  this->NumberOfSampleOperations = counts.Samples;
  this->NumberOfOracleOperations = minimum ? 0 : counts.Samples.load();
  this->NumberOfSynthesisOperations = counts.Synthesis;
  this->NumberOfAccumulateOperations = counts.Accumulates;
  this->NumberOfBoundarySampleOperations = counts.Boundary;
  this->FullRateSampleOperations = fullRate;
  this->WarnIfTransparent(rgba);
  return 1;
}

//------------------------------------------------------------------------------
vtkIdType vtkAdaptiveSamplingRayCaster::ComputeSliceGrid(vtkMatrix4x4* gridToWorld,
  const int dims[3],
  const double eye[3],
  const double forward[3],
  double delta,
  int maximumLevel,
  double& nearest,
  double axisLength[3])
{
  for (int a = 0; a < 3; ++a)
  {
    axisLength[a] = std::sqrt(gridToWorld->GetElement(0, a) * gridToWorld->GetElement(0, a) +
      gridToWorld->GetElement(1, a) * gridToWorld->GetElement(1, a) +
      gridToWorld->GetElement(2, a) * gridToWorld->GetElement(2, a));
  }
  nearest = std::numeric_limits<double>::infinity();
  double farthest = -nearest;
  for (int c = 0; c < 8; ++c)
  {
    const double corner[4] = { (c & 1) ? dims[0] - 1.0 : 0.0,
      (c & 2) ? dims[1] - 1.0 : 0.0,
      (c & 4) ? dims[2] - 1.0 : 0.0,
      1.0 };
    double w[4];
    gridToWorld->MultiplyPoint(corner, w);
    const double depth =
      (w[0] - eye[0]) * forward[0] + (w[1] - eye[1]) * forward[1] + (w[2] - eye[2]) * forward[2];
    nearest = std::min(nearest, depth);
    farthest = std::max(farthest, depth);
  }
  const vtkIdType block = vtkIdType(1) << maximumLevel;
  const vtkIdType lastSlice = static_cast<vtkIdType>(std::ceil((farthest - nearest) / delta));
  return (lastSlice + block - 1) / block * block;
}

//------------------------------------------------------------------------------
void vtkAdaptiveSamplingRayCaster::ClipSlices(const double origin[3],
  const double step[3],
  const double boxMax[3],
  double lastSlice,
  double& entry,
  double& exit)
{
  // The slab method in index space: per axis the slice coordinates of the two faces.
  entry = 0.0;
  exit = lastSlice;
  for (int a = 0; a < 3 && entry <= exit; ++a)
  {
    if (step[a] == 0.0)
    {
      if (origin[a] < 0.0 || origin[a] > boxMax[a])
      {
        exit = -1.0;
      }
      continue;
    }
    const double ta = -origin[a] / step[a], tb = (boxMax[a] - origin[a]) / step[a];
    entry = std::max(entry, std::min(ta, tb));
    exit = std::min(exit, std::max(ta, tb));
  }
}

//------------------------------------------------------------------------------
double vtkAdaptiveSamplingRayCaster::Synthesize(const double* coarse,
  int coarseWidth,
  int coarseHeight,
  int x,
  int y)
{
  // Fig. 5: the fine pixel's centre in coarse coordinates is x / 2 - 1/4, so the two coarse
  // neighbours weigh (1/4, 3/4) for an even x and (3/4, 1/4) for an odd one; indices -1 and
  // coarseWidth are clamped to the edge.
  const int x0 = (x & 1) ? x / 2 : x / 2 - 1, y0 = (y & 1) ? y / 2 : y / 2 - 1;
  const double wx = (x & 1) ? 0.25 : 0.75, wy = (y & 1) ? 0.25 : 0.75; // of x0 + 1
  const int xa = std::max(x0, 0), xb = std::min(x0 + 1, coarseWidth - 1);
  const int ya = std::max(y0, 0), yb = std::min(y0 + 1, coarseHeight - 1);
  const size_t ra = static_cast<size_t>(ya) * coarseWidth;
  const size_t rb = static_cast<size_t>(yb) * coarseWidth;
  const double a = coarse[ra + xa] + wx * (coarse[ra + xb] - coarse[ra + xa]);
  const double b = coarse[rb + xa] + wx * (coarse[rb + xb] - coarse[rb + xa]);
  return a + wy * (b - a);
}

//------------------------------------------------------------------------------
void vtkAdaptiveSamplingRayCaster::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "MaximumLevel: " << this->MaximumLevel << "\n";
  os << indent << "Algorithm: " << (this->Algorithm == ALGORITHM_FIG7 ? "FIG7" : "FIG3") << "\n";
  os << indent << "OracleMode: " << (this->OracleMode == ORACLE_ARRAY ? "ARRAY" : "MINIMUM")
     << "\n";
  os << indent << "OracleArrayName: " << (this->OracleArrayName ? this->OracleArrayName : "(none)")
     << "\n";
  os << indent << "TableSize: " << this->TableSize << "\n";
  os << indent << "MaximumSamplesPerRay: " << this->MaximumSamplesPerRay << "\n";
  os << indent << "NumberOfSampleOperations: " << this->NumberOfSampleOperations << "\n";
  os << indent << "NumberOfOracleOperations: " << this->NumberOfOracleOperations << "\n";
  os << indent << "NumberOfSynthesisOperations: " << this->NumberOfSynthesisOperations << "\n";
  os << indent << "NumberOfAccumulateOperations: " << this->NumberOfAccumulateOperations << "\n";
  os << indent << "NumberOfBoundarySampleOperations: " << this->NumberOfBoundarySampleOperations
     << "\n";
  os << indent << "FullRateSampleOperations: " << this->FullRateSampleOperations << "\n";
}
