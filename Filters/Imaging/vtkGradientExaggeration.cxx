// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
#include "vtkGradientExaggeration.h"

#include "vtkArrayDispatch.h"
#include "vtkDataArray.h"
#include "vtkDataArrayRange.h"
#include "vtkFloatArray.h"
#include "vtkImageData.h"
#include "vtkImagingInputCheck.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkSMPTools.h"
#include "vtkStreamingDemandDrivenPipeline.h"

#include <vtksys/SystemInformation.hxx>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <utility>
#include <vector>

vtkStandardNewMacro(vtkGradientExaggeration);

namespace
{
// Values are read scaled by 2^-6 (exact) so that the differences and Sobel sums of finite
// doubles, up to 34 times the largest value (one-sided differences are doubled), stay finite.
constexpr double ValueScale = 1.0 / 64.0;
// vtkImageSobel3D's weights (the axis line, the four lines beside it, the four diagonal
// lines) and the factor it scales its sums by, per unit spacing.
constexpr double SobelAxis = 2.0;
constexpr double SobelSide = 1.0;
constexpr double SobelDiagonal = 0.586;
constexpr double SobelTotal = SobelAxis + 4.0 * SobelSide + 4.0 * SobelDiagonal;
constexpr double SobelScale = 0.060445;
// A normal is zero where the value changes by at most this fraction of the data range across
// the finest cell.
constexpr double ZeroGradientFraction = 1e-12;
// Chunks of each pass between progress events and abort checks.
constexpr vtkIdType ChunksPerPass = 10;

// Length of v without overflow or underflow in the squares; 0 for the zero vector.
double Length(const double v[3])
{
  const double m = std::max(std::abs(v[0]), std::max(std::abs(v[1]), std::abs(v[2])));
  if (!(m > 0.0))
  {
    return 0.0;
  }
  const double x = v[0] / m, y = v[1] / m, z = v[2] / m;
  return m * std::sqrt(x * x + y * y + z * z);
}

// v / |v| if |v| > threshold (and finite), else 0; returns whether v was kept.
bool Normalize(double v[3], double threshold)
{
  const double length = Length(v);
  if (!(length > threshold) || !std::isfinite(length))
  {
    v[0] = v[1] = v[2] = 0.0;
    return false;
  }
  v[0] /= length;
  v[1] /= length;
  v[2] /= length;
  return true;
}

// What every pass needs to know of the grid and the settings.
struct Setup
{
  int Dims[3];
  vtkIdType Increments[3]; // point id steps along x, y, z
  // Smallest |spacing| over each axis's spacing (sign included): the gradient, scaled by the
  // smallest spacing, stays finite for any finite spacing.
  double AxisScale[3];
  int Method;
  int Radius[3]; // box radius per axis, at most the axis's point count
  // Zero-gradient threshold on the scaled gradient H = G * (smallest spacing) / GradientUnit.
  double Threshold;
  double Epsilon;
  // Whether N' = N: eps = 0 or a 1-point box, where the box sums are skipped (their float
  // rounding would otherwise be multiplied by eps).
  bool Identity;
  float* Out; // 3 floats per point: box sums, then the output normals
};

// The normal field of one input array: normals of one x row at a time, in double.
template <typename ArrayT>
class NormalField
{
public:
  NormalField(ArrayT* array, const Setup& setup)
    : Values(vtk::DataArrayValueRange<1>(array))
    , S(setup)
  {
  }

  // N for the points (0..nx-1, j, k), 3 doubles each.
  void Row(int j, int k, double* normals) const
  {
    const int nx = this->S.Dims[0];
    vtkIdType id = nx * (j + static_cast<vtkIdType>(this->S.Dims[1]) * k);
    for (int i = 0; i < nx; ++i, ++id, normals += 3)
    {
      const double centre = this->Value(id);
      if (std::isnan(centre))
      {
        normals[0] = normals[1] = normals[2] = 0.0;
        continue;
      }
      const int at[3] = { i, j, k };
      for (int a = 0; a < 3; ++a)
      {
        const double d = this->S.Method == vtkGradientExaggeration::SOBEL
          ? this->Sobel(id, at, a)
          : this->Difference(id, at[a], a, centre);
        normals[a] = d * this->S.AxisScale[a];
      }
      Normalize(normals, this->S.Threshold);
    }
  }

private:
  // The scaled value at a point, NaN where it is not finite.
  double Value(vtkIdType id) const
  {
    const double v = static_cast<double>(this->Values[id]);
    return std::isfinite(v) ? v * ValueScale : std::numeric_limits<double>::quiet_NaN();
  }

  // Twice the derivative times the spacing along axis a at a point of value centre (which may
  // be NaN) and index p along a: the central difference v[p+1] - v[p-1], or twice the
  // one-sided difference where a neighbour is outside the volume or not finite; NaN when
  // neither difference exists.
  double LineDifference(vtkIdType id, int p, int a, double centre) const
  {
    const vtkIdType step = this->S.Increments[a];
    const double left = p > 0 ? this->Value(id - step) : std::numeric_limits<double>::quiet_NaN();
    const double right =
      p < this->S.Dims[a] - 1 ? this->Value(id + step) : std::numeric_limits<double>::quiet_NaN();
    if (!std::isnan(left) && !std::isnan(right))
    {
      return right - left;
    }
    if (!std::isnan(right) && !std::isnan(centre))
    {
      return 2.0 * (right - centre);
    }
    if (!std::isnan(left) && !std::isnan(centre))
    {
      return 2.0 * (centre - left);
    }
    return std::numeric_limits<double>::quiet_NaN();
  }

  double Difference(vtkIdType id, int p, int a, double centre) const
  {
    const double d = this->LineDifference(id, p, a, centre);
    return std::isnan(d) ? 0.0 : d;
  }

  // vtkImageSobel3D's sum along axis a: the weighted line differences of the 3 x 3 lines
  // along a through the point's transverse neighbours (clamped to the volume as VTK does).
  // Lines without a difference (missing data) are left out and the others' weights scaled up.
  double Sobel(vtkIdType id, const int at[3], int a) const
  {
    const int b = (a + 1) % 3, c = (a + 2) % 3;
    double sum = 0.0, weights = 0.0;
    for (int ob = -1; ob <= 1; ++ob)
    {
      const int qb = std::min(std::max(at[b] + ob, 0), this->S.Dims[b] - 1);
      for (int oc = -1; oc <= 1; ++oc)
      {
        const int qc = std::min(std::max(at[c] + oc, 0), this->S.Dims[c] - 1);
        const double w = ob == 0 && oc == 0 ? SobelAxis
          : ob == 0 || oc == 0              ? SobelSide
                                            : SobelDiagonal;
        const vtkIdType line =
          id + (qb - at[b]) * this->S.Increments[b] + (qc - at[c]) * this->S.Increments[c];
        const double d = this->LineDifference(line, at[a], a, this->Value(line));
        if (!std::isnan(d))
        {
          sum += w * d;
          weights += w;
        }
      }
    }
    if (weights == 0.0)
    {
      return 0.0;
    }
    return weights < SobelTotal ? sum * (SobelTotal / weights) : sum;
  }

  decltype(vtk::DataArrayValueRange<1>(std::declval<ArrayT*>())) Values;
  const Setup& S;
};

// Sums a window of radius r along a line of n entries of 3 doubles (entry stride 3 * width
// doubles, width lines side by side) into out (same layout, floats): out[i] = sum of the
// entries max(0, i - r) .. min(n - 1, i + r), by a running sum.
void WindowSums(const double* in,
  float* out,
  vtkIdType outStride,
  int n,
  int width,
  int r,
  double* acc)
{
  const vtkIdType stride = 3 * static_cast<vtkIdType>(width);
  std::fill(acc, acc + stride, 0.0);
  for (int e = 0; e <= std::min(r, n - 1); ++e)
  {
    for (vtkIdType c = 0; c < stride; ++c)
    {
      acc[c] += in[e * stride + c];
    }
  }
  for (int i = 0; i < n; ++i)
  {
    float* o = out + i * outStride;
    for (vtkIdType c = 0; c < stride; ++c)
    {
      o[c] = static_cast<float>(acc[c]);
    }
    const vtkIdType entering = static_cast<vtkIdType>(i) + r + 1, leaving = i - r;
    if (entering < n)
    {
      for (vtkIdType c = 0; c < stride; ++c)
      {
        acc[c] += in[entering * stride + c];
      }
    }
    if (leaving >= 0)
    {
      for (vtkIdType c = 0; c < stride; ++c)
      {
        acc[c] -= in[leaving * stride + c];
      }
    }
  }
}

// Pass 1: N along each x row, summed over the box's x extent into Out.
template <typename ArrayT>
struct RowSums
{
  NormalField<ArrayT> Field;
  const Setup& S;
  void operator()(vtkIdType begin, vtkIdType end) const
  {
    const int nx = this->S.Dims[0];
    std::vector<double> normals(3 * static_cast<size_t>(nx)), acc(3);
    for (vtkIdType row = begin; row < end; ++row)
    {
      const int j = static_cast<int>(row % this->S.Dims[1]);
      const int k = static_cast<int>(row / this->S.Dims[1]);
      this->Field.Row(j, k, normals.data());
      WindowSums(
        normals.data(), this->S.Out + 3 * row * nx, 3, nx, 1, this->S.Radius[0], acc.data());
    }
  }
};

// Pass 2: the x sums of each z slice summed over the box's y extent, in place.
struct SliceSums
{
  const Setup& S;
  void operator()(vtkIdType begin, vtkIdType end) const
  {
    const int nx = this->S.Dims[0], ny = this->S.Dims[1];
    const vtkIdType slice = 3 * static_cast<vtkIdType>(nx) * ny;
    std::vector<double> copy(slice), acc(3 * static_cast<size_t>(nx));
    for (vtkIdType k = begin; k < end; ++k)
    {
      float* out = this->S.Out + k * slice;
      std::copy(out, out + slice, copy.begin());
      WindowSums(
        copy.data(), out, 3 * static_cast<vtkIdType>(nx), ny, nx, this->S.Radius[1], acc.data());
    }
  }
};

// Pass 3: the xy sums of each y row of every slice summed over the box's z extent, in place.
struct ColumnSums
{
  const Setup& S;
  void operator()(vtkIdType begin, vtkIdType end) const
  {
    const int nx = this->S.Dims[0], ny = this->S.Dims[1], nz = this->S.Dims[2];
    const vtkIdType row = 3 * static_cast<vtkIdType>(nx), slice = row * ny;
    std::vector<double> copy(row * nz), acc(row);
    for (vtkIdType j = begin; j < end; ++j)
    {
      float* out = this->S.Out + j * row;
      for (int k = 0; k < nz; ++k)
      {
        std::copy(out + k * slice, out + k * slice + row, copy.begin() + k * row);
      }
      WindowSums(copy.data(), out, slice, nz, nx, this->S.Radius[2], acc.data());
    }
  }
};

// Pass 4: N again, the box sums M in Out, and the exaggerated normal written over M.
template <typename ArrayT>
struct Exaggerate
{
  NormalField<ArrayT> Field;
  const Setup& S;
  void operator()(vtkIdType begin, vtkIdType end) const
  {
    const int nx = this->S.Dims[0];
    std::vector<double> normals(3 * static_cast<size_t>(nx));
    for (vtkIdType row = begin; row < end; ++row)
    {
      const int j = static_cast<int>(row % this->S.Dims[1]);
      const int k = static_cast<int>(row / this->S.Dims[1]);
      this->Field.Row(j, k, normals.data());
      float* out = this->S.Out + 3 * row * nx;
      for (int i = 0; i < nx; ++i, out += 3)
      {
        const double* n = normals.data() + 3 * i;
        if (n[0] == 0.0 && n[1] == 0.0 && n[2] == 0.0)
        {
          out[0] = out[1] = out[2] = 0.0f;
          continue;
        }
        if (this->S.Identity)
        {
          for (int c = 0; c < 3; ++c)
          {
            out[c] = static_cast<float>(n[c]);
          }
          continue;
        }
        // N_m: the normalised box sum, or N itself where the sum cancels.
        double mean[3] = { out[0], out[1], out[2] };
        if (!Normalize(mean, 0.0))
        {
          std::copy(n, n + 3, mean);
        }
        // N' = N + eps (N - N_m), Guetat et al. 2010, line 99 of the paper's text. Written
        // with the difference first, N' is exactly N when N_m = N, however large eps is.
        double difference[3] = { n[0] - mean[0], n[1] - mean[1], n[2] - mean[2] };
        double exaggerated[3];
        for (int c = 0; c < 3; ++c)
        {
          exaggerated[c] = n[c] + this->S.Epsilon * difference[c];
        }
        if (!std::isfinite(exaggerated[0]) || !std::isfinite(exaggerated[1]) ||
          !std::isfinite(exaggerated[2]))
        {
          // eps (N - N_m) overflowed: N' points along N - N_m, its limit for large eps.
          std::copy(difference, difference + 3, exaggerated);
        }
        if (!Normalize(exaggerated, 0.0))
        {
          std::copy(n, n + 3, exaggerated);
        }
        for (int c = 0; c < 3; ++c)
        {
          out[c] = static_cast<float>(exaggerated[c]);
        }
      }
    }
  }
};

// Runs functor over [0, count) in chunks on the SMP back end, with a progress event after
// each chunk (from progressBegin to progressEnd); false when aborted.
template <typename Functor>
bool RunPass(vtkGradientExaggeration* self,
  vtkIdType count,
  Functor& functor,
  double progressBegin,
  double progressEnd)
{
  const vtkIdType chunks = std::max<vtkIdType>(1, std::min(count, ChunksPerPass));
  for (vtkIdType c = 0; c < chunks; ++c)
  {
    if (self->GetAbortExecute())
    {
      return false;
    }
    vtkSMPTools::For(count * c / chunks, count * (c + 1) / chunks, functor);
    self->UpdateProgress(
      progressBegin + (progressEnd - progressBegin) * static_cast<double>(c + 1) / chunks);
  }
  return !self->GetAbortExecute();
}

// The four passes for one input array type (the last one alone when N' = N); Completed stays
// false when aborted.
struct Worker
{
  vtkGradientExaggeration* Self;
  const Setup* S;
  bool Completed = false;

  template <typename ArrayT>
  void operator()(ArrayT* array)
  {
    const Setup& s = *this->S;
    const vtkIdType rows = static_cast<vtkIdType>(s.Dims[1]) * s.Dims[2];
    RowSums<ArrayT> rowSums{ NormalField<ArrayT>(array, s), s };
    SliceSums sliceSums{ s };
    ColumnSums columnSums{ s };
    Exaggerate<ArrayT> exaggerate{ NormalField<ArrayT>(array, s), s };
    if (s.Identity)
    {
      this->Completed = RunPass(this->Self, rows, exaggerate, 0.0, 1.0);
      return;
    }
    // The gradient passes read up to 54 values per point, the sums a few per point.
    this->Completed = RunPass(this->Self, rows, rowSums, 0.0, 0.35) &&
      RunPass(this->Self, s.Dims[2], sliceSums, 0.35, 0.45) &&
      RunPass(this->Self, s.Dims[1], columnSums, 0.45, 0.55) &&
      RunPass(this->Self, rows, exaggerate, 0.55, 1.0);
  }
};
}

//------------------------------------------------------------------------------
vtkGradientExaggeration::vtkGradientExaggeration()
{
  this->SetOutputArrayName("ExaggeratedNormals");
  this->SetInputArrayToProcess(
    0, 0, 0, vtkDataObject::FIELD_ASSOCIATION_POINTS, vtkDataSetAttributes::SCALARS);
}

//------------------------------------------------------------------------------
vtkGradientExaggeration::~vtkGradientExaggeration()
{
  this->SetOutputArrayName(nullptr);
}

//------------------------------------------------------------------------------
const char* vtkGradientExaggeration::GetGradientMethodAsString()
{
  return this->GradientMethod == SOBEL ? "Sobel" : "CentralDifference";
}

//------------------------------------------------------------------------------
int vtkGradientExaggeration::RequestInformation(vtkInformation* request,
  vtkInformationVector** inputVector,
  vtkInformationVector* outputVector)
{
  if (!this->Superclass::RequestInformation(request, inputVector, outputVector))
  {
    return 0;
  }
  // A piece of a parallel pipeline is computed from the piece grown by ghost levels and
  // cropped back to the piece (RequestData).
  outputVector->GetInformationObject(0)->Set(CAN_PRODUCE_SUB_EXTENT(), 1);
  return 1;
}

//------------------------------------------------------------------------------
int vtkGradientExaggeration::RequestUpdateExtent(vtkInformation*,
  vtkInformationVector** inputVector,
  vtkInformationVector* outputVector)
{
  // Each output point depends on the points within the box radius plus one (the gradient's
  // reach): an extent request grows by that margin, never beyond the whole extent, and a piece
  // request asks for that many more ghost levels (the pipeline turns pieces into extents only
  // when it executes).
  vtkInformation* inInfo = inputVector[0]->GetInformationObject(0);
  vtkInformation* outInfo = outputVector->GetInformationObject(0);
  const int margin = std::max(this->NeighborhoodSize, 1) / 2 + 1;
  int whole[6], update[6];
  inInfo->Get(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT(), whole);
  outInfo->Get(vtkStreamingDemandDrivenPipeline::UPDATE_EXTENT(), update);
  int request[6];
  std::copy(update, update + 6, request);
  if (update[0] <= update[1] && update[2] <= update[3] && update[4] <= update[5])
  {
    for (int a = 0; a < 3; ++a)
    {
      request[2 * a] = static_cast<int>(
        std::max<long long>(whole[2 * a], static_cast<long long>(update[2 * a]) - margin));
      request[2 * a + 1] = static_cast<int>(
        std::min<long long>(whole[2 * a + 1], static_cast<long long>(update[2 * a + 1]) + margin));
    }
  }
  inInfo->Set(vtkStreamingDemandDrivenPipeline::UPDATE_EXTENT(), request, 6);
  const long long ghosts =
    outInfo->Get(vtkStreamingDemandDrivenPipeline::UPDATE_NUMBER_OF_GHOST_LEVELS()) +
    static_cast<long long>(margin);
  inInfo->Set(vtkStreamingDemandDrivenPipeline::UPDATE_NUMBER_OF_GHOST_LEVELS(),
    static_cast<int>(std::min<long long>(ghosts, std::numeric_limits<int>::max())));
  return 1;
}

//------------------------------------------------------------------------------
int vtkGradientExaggeration::RequestData(vtkInformation*,
  vtkInformationVector** inputVector,
  vtkInformationVector* outputVector)
{
  vtkImageData* input = vtkImageData::GetData(inputVector[0]);
  vtkImageData* output = vtkImageData::GetData(outputVector);
  output->Initialize();
  if (!input)
  {
    vtkErrorMacro("The input is not image data.");
    return 1;
  }

  // Settings.
  if (!(this->Epsilon >= 0.0) || !std::isfinite(this->Epsilon))
  {
    vtkErrorMacro("Epsilon must be finite and >= 0, got " << this->Epsilon << ".");
    return 1;
  }
  if (this->NeighborhoodSize < 1 || this->NeighborhoodSize % 2 == 0)
  {
    vtkErrorMacro("NeighborhoodSize must be odd and >= 1 (a box centred on the voxel), got "
      << this->NeighborhoodSize << ".");
    return 1;
  }
  if (!this->OutputArrayName || !*this->OutputArrayName)
  {
    vtkErrorMacro("OutputArrayName is empty; the normals need a name.");
    return 1;
  }

  // Input.
  int association = -1;
  vtkDataArray* scalars = this->GetInputArrayToProcess(0, inputVector, association);
  std::string problem;
  if (!vtkImagingInputCheck::Check(input,
        scalars,
        association,
        this->OutputArrayName,
        "gradients need values at the grid's points",
        "the normals",
        problem))
  {
    vtkErrorMacro(<< problem);
    return 1;
  }
  int dims[3];
  input->GetDimensions(dims);
  const vtkIdType points = input->GetNumberOfPoints();
  const double* spacing = input->GetSpacing();
  const double smallest =
    std::min(std::abs(spacing[0]), std::min(std::abs(spacing[1]), std::abs(spacing[2])));
  // An impossible size is an error and an empty output, not an allocation that overcommits
  // and is killed when written.
  vtksys::SystemInformation system;
  system.RunMemoryCheck();
  const double memory = 1048576.0 * static_cast<double>(system.GetTotalPhysicalMemory()); // MiB
  const double bytes = 3.0 * sizeof(float) * static_cast<double>(points);
  vtkNew<vtkFloatArray> normals;
  normals->SetName(this->OutputArrayName);
  normals->SetNumberOfComponents(3);
  if ((memory > 0.0 && bytes > memory) || !normals->Allocate(3 * points))
  {
    vtkErrorMacro("The normals of " << points << " points (" << std::ceil(bytes / 1048576.0)
                                    << " MiB) do not fit in memory.");
    return 1;
  }
  normals->SetNumberOfTuples(points);

  Setup setup;
  std::copy(dims, dims + 3, setup.Dims);
  setup.Increments[0] = 1;
  setup.Increments[1] = dims[0];
  setup.Increments[2] = static_cast<vtkIdType>(dims[0]) * dims[1];
  const int radius = this->NeighborhoodSize / 2;
  for (int a = 0; a < 3; ++a)
  {
    setup.AxisScale[a] = smallest / spacing[a];
    setup.Radius[a] = std::min(radius, dims[a]);
  }
  setup.Method = this->GradientMethod;
  // |G| * smallest spacing = GradientUnit * |H| for the scaled gradient H the field computes:
  // central differences hold 2 G spacing ValueScale, Sobel sums G spacing ValueScale / 0.060445.
  const double gradientUnit =
    this->GradientMethod == SOBEL ? SobelScale / ValueScale : 0.5 / ValueScale;
  double range[2];
  scalars->GetFiniteRange(range, 0);
  // Scaled like the values, so that the width of any finite range is finite.
  const double scaledWidth =
    range[0] <= range[1] ? range[1] * ValueScale - range[0] * ValueScale : 0.0;
  // |H| > fraction * width / gradientUnit, the width unscaled (width = scaledWidth / ValueScale,
  // which may overflow, hence the order of the operations).
  setup.Threshold = ZeroGradientFraction * scaledWidth / (gradientUnit * ValueScale);
  setup.Epsilon = this->Epsilon;
  setup.Identity = this->Epsilon == 0.0 || this->NeighborhoodSize == 1;
  setup.Out = normals->GetPointer(0);

  Worker worker{ this, &setup };
  if (!vtkArrayDispatch::Dispatch::Execute(scalars, worker))
  {
    worker(scalars); // any other array type, through the vtkDataArray interface
  }

  output->ShallowCopy(input);
  if (worker.Completed) // else aborted: the input passed through, without normals
  {
    output->GetPointData()->AddArray(normals);
  }
  // A piece was computed with its margin; give back just the piece.
  vtkInformation* outInfo = outputVector->GetInformationObject(0);
  if (outInfo->Has(vtkStreamingDemandDrivenPipeline::UPDATE_EXTENT()))
  {
    output->Crop(outInfo->Get(vtkStreamingDemandDrivenPipeline::UPDATE_EXTENT()));
  }
  return 1;
}

//------------------------------------------------------------------------------
void vtkGradientExaggeration::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Epsilon: " << this->Epsilon << "\n";
  os << indent << "NeighborhoodSize: " << this->NeighborhoodSize << "\n";
  os << indent << "GradientMethod: " << this->GetGradientMethodAsString() << "\n";
  os << indent << "OutputArrayName: " << (this->OutputArrayName ? this->OutputArrayName : "(none)")
     << "\n";
}
