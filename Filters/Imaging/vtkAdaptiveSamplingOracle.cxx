// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
#include "vtkAdaptiveSamplingOracle.h"

#include "vtkArrayDispatch.h"
#include "vtkBackgroundWorker.h"
#include "vtkCallbackCommand.h"
#include "vtkDataArray.h"
#include "vtkDataArrayRange.h"
#include "vtkFloatArray.h"
#include "vtkImageData.h"
#include "vtkImagingInputCheck.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkLowPriorityThreads.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkOutputWindow.h"
#include "vtkPiecewiseFunction.h"
#include "vtkPointData.h"
#include "vtkSMPTools.h"
#include "vtkStreamingDemandDrivenPipeline.h"

#include <vtksys/SystemInformation.hxx>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstring>
#include <limits>
#include <mutex>
#include <new>
#include <string>
#include <thread>
#include <type_traits>
#include <utility>
#include <vector>

vtkStandardNewMacro(vtkAdaptiveSamplingOracle);
vtkCxxSetObjectMacro(vtkAdaptiveSamplingOracle, ScalarOpacity, vtkPiecewiseFunction);

namespace
{
// Chunks of each pass between progress events and abort checks.
constexpr vtkIdType ChunksPerPass = 10;
// The automatic cap in smallest spacings: l_max = 3 of the paper (line 236), a largest
// sampling distance of 2^3 = 8 samples, at one sample per voxel.
constexpr double AutomaticCapInSpacings = 8.0;
// Columns the y and z passes of the distance transform gather at once: a row's 64 bytes of
// floats, one cache line, per point along the axis.
constexpr int ColumnBlock = 16;
constexpr double Infinity = std::numeric_limits<double>::infinity();

// Runs functor over [0, count) in chunks on the SMP back end, with a progress event after each
// chunk (from progressBegin to progressEnd) when there is a filter to report to; false when
// aborted.
template <typename Functor>
bool RunPass(vtkAdaptiveSamplingOracle* self,
  vtkIdType count,
  const Functor& functor,
  double progressBegin,
  double progressEnd)
{
  const vtkIdType chunks = std::max<vtkIdType>(1, std::min(count, ChunksPerPass));
  for (vtkIdType c = 0; c < chunks; ++c)
  {
    if (self && self->GetAbortExecute())
    {
      return false;
    }
    const vtkIdType begin = count * c / chunks;
    const vtkIdType end = count * (c + 1) / chunks;
    if (self && self->GetLowPriority())
    {
      // Beside a renderer that answers first: its threads keep the cores they want.
      vtkLowPriorityThreads::For(end - begin,
        std::max<vtkIdType>(1, (end - begin) / 64),
        [&](vtkIdType b, vtkIdType e) { functor(begin + b, begin + e); });
    }
    else
    {
      vtkSMPTools::For(begin, end, functor);
    }
    if (self)
    {
      self->UpdateProgress(
        progressBegin + (progressEnd - progressBegin) * static_cast<double>(c + 1) / chunks);
    }
  }
  return !self || !self->GetAbortExecute();
}

//------------------------------------------------------------------------------
// The opacity transfer function, copied out of the vtkPiecewiseFunction so that threads read
// it without calling into it, with the extremes of its node values over any run of nodes.
class Opacity
{
public:
  void Copy(vtkPiecewiseFunction* function)
  {
    const int n = function->GetSize();
    this->Nodes.resize(n);
    this->X.resize(n);
    for (int i = 0; i < n; ++i)
    {
      function->GetNodeValue(i, this->Nodes[i].Value);
      this->X[i] = this->Nodes[i].Value[0];
    }
    this->Clamping = function->GetClamping() != 0;
    this->LogScale = function->GetUseLogScale();
    // Sparse tables: level l holds the least and greatest node value over [i, i + 2^l).
    this->Lowest.assign(1, std::vector<double>(n));
    this->Highest.assign(1, std::vector<double>(n));
    for (int i = 0; i < n; ++i)
    {
      this->Lowest[0][i] = this->Highest[0][i] = this->Nodes[i].Value[1];
    }
    for (int width = 2; width <= n; width *= 2)
    {
      const std::vector<double>& lo = this->Lowest.back();
      const std::vector<double>& hi = this->Highest.back();
      std::vector<double> nextLo(n - width + 1), nextHi(n - width + 1);
      for (int i = 0; i + width <= n; ++i)
      {
        nextLo[i] = std::min(lo[i], lo[i + width / 2]);
        nextHi[i] = std::max(hi[i], hi[i + width / 2]);
      }
      this->Lowest.push_back(std::move(nextLo));
      this->Highest.push_back(std::move(nextHi));
    }
  }

  // alpha(x) as vtkPiecewiseFunction::GetValue computes it (VTK 9.1's GetTable for one sample,
  // operation for operation), with NaN (a log-scale function at x <= 0, a NaN node) as 0.
  double operator()(double x) const
  {
    const double a = this->Evaluate(x);
    return std::isnan(a) ? 0.0 : a;
  }

  // max - min of alpha over [a, b], a < b; with the opacity 0 of a NaN neighbour when nan.
  // Between two nodes the function is monotonic, so the extremes are at a, at b or at a node
  // inside (class description).
  double Range(double a, double b, bool nan) const
  {
    const double fa = (*this)(a), fb = (*this)(b);
    double lo = std::min(fa, fb), hi = std::max(fa, fb);
    const size_t first = std::lower_bound(this->X.begin(), this->X.end(), a) - this->X.begin();
    const size_t last = std::upper_bound(this->X.begin(), this->X.end(), b) - this->X.begin();
    if (first < last)
    {
      // The two overlapping power-of-two runs that cover [first, last).
      int level = 0;
      while ((size_t(2) << level) <= last - first)
      {
        ++level;
      }
      const size_t other = last - (size_t(1) << level);
      lo = std::min(lo, std::min(this->Lowest[level][first], this->Lowest[level][other]));
      hi = std::max(hi, std::max(this->Highest[level][first], this->Highest[level][other]));
    }
    if (nan)
    {
      lo = std::min(lo, 0.0);
      hi = std::max(hi, 0.0);
    }
    return hi - lo;
  }

private:
  double Evaluate(double x) const
  {
    const size_t n = this->Nodes.size();
    if (n == 0)
    {
      return 0.0;
    }
    // GetTable walks to the first node whose X is not below x.
    const size_t idx = std::lower_bound(this->X.begin(), this->X.end(), x) - this->X.begin();
    if (idx >= n)
    {
      return this->Clamping ? this->Nodes[n - 1].Value[1] : 0.0;
    }
    if (idx == 0)
    {
      return this->Clamping ? this->Nodes[0].Value[1] : 0.0;
    }
    const double* left = this->Nodes[idx - 1].Value;
    const double x1 = left[0], y1 = left[1];
    const double x2 = this->Nodes[idx].Value[0], y2 = this->Nodes[idx].Value[1];
    const double midpoint = std::min(std::max(left[2], 0.00001), 0.99999);
    const double sharpness = left[3];
    double s;
    if (this->LogScale)
    {
      const double xLog = std::log10(x), x1Log = std::log10(x1), x2Log = std::log10(x2);
      s = (xLog - x1Log) / (x2Log - x1Log);
    }
    else
    {
      s = (x - x1) / (x2 - x1);
    }
    if (s < midpoint)
    {
      s = 0.5 * s / midpoint;
    }
    else
    {
      s = 0.5 + 0.5 * (s - midpoint) / (1.0 - midpoint);
    }
    if (sharpness > 0.99)
    {
      return s < 0.5 ? y1 : y2;
    }
    if (sharpness < 0.01)
    {
      return (1 - s) * y1 + s * y2;
    }
    if (s < .5)
    {
      s = 0.5 * std::pow(s * 2, 1.0 + 10 * sharpness);
    }
    else if (s > .5)
    {
      s = 1.0 - 0.5 * std::pow((1.0 - s) * 2, 1 + 10 * sharpness);
    }
    const double ss = s * s;
    const double sss = ss * s;
    const double h1 = 2 * sss - 3 * ss + 1;
    const double h2 = -2 * sss + 3 * ss;
    const double h3 = sss - 2 * ss + s;
    const double h4 = sss - ss;
    const double t = (1.0 - sharpness) * (y2 - y1);
    double value = h1 * y1 + h2 * y2 + h3 * t + h4 * t;
    const double lo = (y1 < y2) ? y1 : y2;
    const double hi = (y1 > y2) ? y1 : y2;
    value = (value < lo) ? lo : value;
    value = (value > hi) ? hi : value;
    return value;
  }

  struct Node
  {
    double Value[4]; // X, Y, midpoint, sharpness as GetNodeValue gives them
  };
  std::vector<Node> Nodes;
  std::vector<double> X;
  std::vector<std::vector<double>> Lowest, Highest;
  bool Clamping = true;
  bool LogScale = false;
};

//------------------------------------------------------------------------------
// The grid: point (i, j, k) is i + nx (j + ny k).
struct Grid
{
  int Dims[3];
  vtkIdType Rows() const { return static_cast<vtkIdType>(this->Dims[1]) * this->Dims[2]; }
  vtkIdType Points() const { return this->Rows() * this->Dims[0]; }
};

// The OPACITY_RANGE feature test (beyond the paper's test:
// it sees a transfer-function spike between two voxel values) of one point, from the least
// and greatest scalar of its neighbourhood and whether that holds a NaN. An interval without
// width has no opacity change; neither has an empty one (every neighbour NaN).
inline bool RangeFeature(const Opacity& opacity, double lo, double hi, bool nan, double epsilon)
{
  double change;
  if (lo < hi)
  {
    change = opacity.Range(lo, hi, nan);
  }
  else if (lo == hi)
  {
    change = nan ? std::abs(opacity(lo)) : 0.0;
  }
  else
  {
    change = 0.0;
  }
  return change > epsilon;
}

// The smin/smax volumes of OPACITY_RANGE for one value type, and the mask they give.
class RangeVolumes
{
public:
  virtual ~RangeVolumes() = default;
  // mask[p] = whether point p is a feature, for p in [begin, end); returns how many are.
  virtual vtkIdType Mask(const Opacity& opacity,
    double epsilon,
    unsigned char* mask,
    vtkIdType begin,
    vtkIdType end) const = 0;
};

template <typename T>
class TypedRangeVolumes : public RangeVolumes
{
public:
  std::vector<T> Min, Max;
  std::vector<unsigned char> NaN; // per point: a NaN in the neighbourhood; empty if none at all

  vtkIdType Mask(const Opacity& opacity,
    double epsilon,
    unsigned char* mask,
    vtkIdType begin,
    vtkIdType end) const override
  {
    vtkIdType count = 0;
    const bool nans = !this->NaN.empty();
    for (vtkIdType p = begin; p < end; ++p)
    {
      const bool feature = RangeFeature(opacity,
        static_cast<double>(this->Min[p]),
        static_cast<double>(this->Max[p]),
        nans && this->NaN[p],
        epsilon);
      mask[p] = feature ? 1 : 0;
      count += feature ? 1 : 0;
    }
    return count;
  }
};

template <typename T>
constexpr bool CanBeNaN()
{
  return std::is_floating_point<T>::value;
}

template <typename T>
bool IsNaN(T v)
{
  if constexpr (CanBeNaN<T>())
  {
    return std::isnan(v);
  }
  else
  {
    (void)v;
    return false;
  }
}

// The start of a running least/greatest value: the empty interval.
template <typename T>
T EmptyMin()
{
  return std::numeric_limits<T>::has_infinity ? std::numeric_limits<T>::infinity()
                                              : std::numeric_limits<T>::max();
}
template <typename T>
T EmptyMax()
{
  return std::numeric_limits<T>::has_infinity ? -std::numeric_limits<T>::infinity()
                                              : std::numeric_limits<T>::lowest();
}

// The three passes of the 3 x 3 x 3 least/greatest value (truncated at the faces), each a
// window of 3 along one axis over the previous pass's result; NaN values are left out of the
// interval and flagged.
template <typename ArrayT, typename T>
struct RangeRowPass
{
  ArrayT* Array;
  const Grid& G;
  TypedRangeVolumes<T>& V;
  void operator()(vtkIdType begin, vtkIdType end) const
  {
    const auto values = vtk::DataArrayValueRange<1>(this->Array);
    const int nx = this->G.Dims[0];
    const bool flags = !this->V.NaN.empty();
    for (vtkIdType row = begin; row < end; ++row)
    {
      const vtkIdType base = row * nx;
      for (int i = 0; i < nx; ++i)
      {
        T lo = EmptyMin<T>(), hi = EmptyMax<T>();
        bool nan = false;
        for (int q = std::max(i - 1, 0); q <= std::min(i + 1, nx - 1); ++q)
        {
          const T v = static_cast<T>(values[base + q]);
          if (IsNaN(v))
          {
            nan = true;
            continue;
          }
          lo = v < lo ? v : lo;
          hi = v > hi ? v : hi;
        }
        this->V.Min[base + i] = lo;
        this->V.Max[base + i] = hi;
        if (flags)
        {
          this->V.NaN[base + i] = nan ? 1 : 0;
        }
      }
    }
  }
};

// Combines n lines of width entries (line stride lineStride in the volumes, starting at base)
// along the line index with a window of 3, through copies of the lines in lo/hi/nan.
template <typename T>
void WindowLines(TypedRangeVolumes<T>& v,
  vtkIdType base,
  vtkIdType lineStride,
  int n,
  int width,
  std::vector<T>& lo,
  std::vector<T>& hi,
  std::vector<unsigned char>& nan)
{
  const bool flags = !v.NaN.empty();
  for (int p = 0; p < n; ++p)
  {
    const vtkIdType at = base + p * lineStride;
    std::copy(v.Min.begin() + at, v.Min.begin() + at + width, lo.begin() + p * width);
    std::copy(v.Max.begin() + at, v.Max.begin() + at + width, hi.begin() + p * width);
    if (flags)
    {
      std::copy(v.NaN.begin() + at, v.NaN.begin() + at + width, nan.begin() + p * width);
    }
  }
  for (int p = 0; p < n; ++p)
  {
    const vtkIdType at = base + p * lineStride;
    const int first = std::max(p - 1, 0), last = std::min(p + 1, n - 1);
    for (int c = 0; c < width; ++c)
    {
      T a = lo[first * width + c], b = hi[first * width + c];
      unsigned char f = flags ? nan[first * width + c] : 0;
      for (int q = first + 1; q <= last; ++q)
      {
        const T qa = lo[q * width + c], qb = hi[q * width + c];
        a = qa < a ? qa : a;
        b = qb > b ? qb : b;
        f = static_cast<unsigned char>(f | (flags ? nan[q * width + c] : 0));
      }
      v.Min[at + c] = a;
      v.Max[at + c] = b;
      if (flags)
      {
        v.NaN[at + c] = f;
      }
    }
  }
}

// Along y, one z slice at a time.
template <typename T>
struct RangeSlicePass
{
  const Grid& G;
  TypedRangeVolumes<T>& V;
  void operator()(vtkIdType begin, vtkIdType end) const
  {
    const int nx = this->G.Dims[0], ny = this->G.Dims[1];
    const size_t size = static_cast<size_t>(nx) * ny;
    std::vector<T> lo(size), hi(size);
    std::vector<unsigned char> nan(this->V.NaN.empty() ? 0 : size);
    for (vtkIdType k = begin; k < end; ++k)
    {
      WindowLines(this->V, k * static_cast<vtkIdType>(size), nx, ny, nx, lo, hi, nan);
    }
  }
};

// Along z, the rows of one y at a time.
template <typename T>
struct RangeColumnPass
{
  const Grid& G;
  TypedRangeVolumes<T>& V;
  void operator()(vtkIdType begin, vtkIdType end) const
  {
    const int nx = this->G.Dims[0], ny = this->G.Dims[1], nz = this->G.Dims[2];
    const size_t size = static_cast<size_t>(nx) * nz;
    std::vector<T> lo(size), hi(size);
    std::vector<unsigned char> nan(this->V.NaN.empty() ? 0 : size);
    for (vtkIdType j = begin; j < end; ++j)
    {
      WindowLines(this->V, j * nx, static_cast<vtkIdType>(nx) * ny, nz, nx, lo, hi, nan);
    }
  }
};

template <typename ArrayT>
struct NaNSearch
{
  ArrayT* Array;
  std::atomic<bool>& Found;
  void operator()(vtkIdType begin, vtkIdType end) const
  {
    const auto values = vtk::DataArrayValueRange<1>(this->Array);
    for (vtkIdType p = begin; p < end && !this->Found.load(std::memory_order_relaxed); ++p)
    {
      if (std::isnan(static_cast<double>(values[p])))
      {
        this->Found = true;
      }
    }
  }
};

// Computes the range volumes of one input array type; Volumes stays empty when aborted or out
// of memory (Failed says which).
struct RangeWorker
{
  vtkAdaptiveSamplingOracle* Self;
  const Grid* G;
  double ProgressBegin, ProgressEnd;
  std::unique_ptr<RangeVolumes> Volumes;
  bool OutOfMemory = false;

  template <typename ArrayT>
  void operator()(ArrayT* array)
  {
    using T = vtk::GetAPIType<ArrayT>;
    const Grid& g = *this->G;
    const vtkIdType points = g.Points();
    std::unique_ptr<TypedRangeVolumes<T>> v;
    try
    {
      v.reset(new TypedRangeVolumes<T>);
      v->Min.resize(points);
      v->Max.resize(points);
      if constexpr (CanBeNaN<T>())
      {
        std::atomic<bool> found(false);
        vtkSMPTools::For(0, points, NaNSearch<ArrayT>{ array, found });
        if (found)
        {
          v->NaN.resize(points);
        }
      }
    }
    catch (const std::bad_alloc&)
    {
      this->OutOfMemory = true;
      return;
    }
    const double b = this->ProgressBegin, w = this->ProgressEnd - this->ProgressBegin;
    if (RunPass(this->Self, g.Rows(), RangeRowPass<ArrayT, T>{ array, g, *v }, b, b + 0.4 * w) &&
      RunPass(this->Self, g.Dims[2], RangeSlicePass<T>{ g, *v }, b + 0.4 * w, b + 0.7 * w) &&
      RunPass(this->Self, g.Dims[1], RangeColumnPass<T>{ g, *v }, b + 0.7 * w, b + w))
    {
      this->Volumes = std::move(v);
    }
  }
};

//------------------------------------------------------------------------------
// The feature masks, each point's flag in mask and the count added to Count.

struct RangeMaskPass
{
  const RangeVolumes& V;
  const Opacity& Alpha;
  double Epsilon;
  unsigned char* Mask;
  std::atomic<vtkIdType>& Count;
  void operator()(vtkIdType begin, vtkIdType end) const
  {
    this->Count += this->V.Mask(this->Alpha, this->Epsilon, this->Mask, begin, end);
  }
};

// alpha at every point, into the output array (as floats), NaN scalars transparent.
template <typename ArrayT>
struct AlphaPass
{
  ArrayT* Array;
  const Opacity& Alpha;
  float* Out;
  void operator()(vtkIdType begin, vtkIdType end) const
  {
    const auto values = vtk::DataArrayValueRange<1>(this->Array);
    // Opacities beyond the float range (a function can hold any value) saturate.
    const double largest = std::numeric_limits<float>::max();
    for (vtkIdType p = begin; p < end; ++p)
    {
      const double v = static_cast<double>(values[p]);
      const double a = std::isnan(v) ? 0.0 : this->Alpha(v);
      this->Out[p] = static_cast<float>(std::min(std::max(a, -largest), largest));
    }
  }
};

struct AlphaWorker
{
  const Opacity* Alpha;
  float* Out;
  vtkAdaptiveSamplingOracle* Self;
  vtkIdType Points;
  double ProgressBegin, ProgressEnd;
  bool Completed = false;
  template <typename ArrayT>
  void operator()(ArrayT* array)
  {
    this->Completed = RunPass(this->Self,
      this->Points,
      AlphaPass<ArrayT>{ array, *this->Alpha, this->Out },
      this->ProgressBegin,
      this->ProgressEnd);
  }
};

// |grad alpha| > epsilon by central differences in per-voxel units, one-sided on the faces
// (the paper's test, lines 231-236), from the alpha volume in Alpha.
struct GradientMaskPass
{
  const Grid& G;
  const float* Alpha;
  double Epsilon;
  unsigned char* Mask;
  std::atomic<vtkIdType>& Count;

  // Half the difference along an axis at index p of n points, step apart: central, one-sided
  // on a face, 0 on a line of one point.
  static double Difference(const float* a, int p, int n, vtkIdType step)
  {
    if (n < 2)
    {
      return 0.0;
    }
    if (p == 0)
    {
      return static_cast<double>(a[step]) - static_cast<double>(a[0]);
    }
    if (p == n - 1)
    {
      return static_cast<double>(a[0]) - static_cast<double>(a[-step]);
    }
    return 0.5 * (static_cast<double>(a[step]) - static_cast<double>(a[-step]));
  }

  void operator()(vtkIdType begin, vtkIdType end) const
  {
    const int nx = this->G.Dims[0], ny = this->G.Dims[1], nz = this->G.Dims[2];
    const vtkIdType sy = nx, sz = static_cast<vtkIdType>(nx) * ny;
    vtkIdType count = 0;
    for (vtkIdType row = begin; row < end; ++row)
    {
      const int j = static_cast<int>(row % ny), k = static_cast<int>(row / ny);
      for (int i = 0; i < nx; ++i)
      {
        const vtkIdType p = row * nx + i;
        const float* a = this->Alpha + p;
        const double gx = Difference(a, i, nx, 1);
        const double gy = Difference(a, j, ny, sy);
        const double gz = Difference(a, k, nz, sz);
        const bool feature = std::sqrt(gx * gx + gy * gy + gz * gz) > this->Epsilon;
        this->Mask[p] = feature ? 1 : 0;
        count += feature ? 1 : 0;
      }
    }
    this->Count += count;
  }
};

//------------------------------------------------------------------------------
// The distance transform. Distances are computed in units of the smallest spacing (weights
// (spacing / smallest)^2 per axis) so that no spacing can overflow the squares, and squared
// distances are kept in the output floats between the passes, infinite beyond the cap.

struct DistanceSetup
{
  Grid G;
  double Weight[3]; // squared spacing of each axis, in smallest spacings
  double Cap2;      // the squared cap in smallest spacings (may be infinite)
  double Unit;      // the smallest spacing
  double Cap;       // the cap in world units
  const unsigned char* Mask;
  float* Out;
};

// Pass x: the squared distance to the nearest feature of the point's row, by a forward and a
// backward scan.
struct DistanceRowPass
{
  const DistanceSetup& S;
  void operator()(vtkIdType begin, vtkIdType end) const
  {
    const int nx = this->S.G.Dims[0];
    const int none = std::numeric_limits<int>::max();
    std::vector<int> gap(nx);
    for (vtkIdType row = begin; row < end; ++row)
    {
      const unsigned char* mask = this->S.Mask + row * nx;
      float* out = this->S.Out + row * nx;
      int last = -1;
      for (int i = 0; i < nx; ++i)
      {
        last = mask[i] ? i : last;
        gap[i] = last >= 0 ? i - last : none;
      }
      last = -1;
      for (int i = nx - 1; i >= 0; --i)
      {
        last = mask[i] ? i : last;
        if (last >= 0)
        {
          gap[i] = std::min(gap[i], last - i);
        }
        const double d = gap[i];
        const double d2 = d * d * this->S.Weight[0];
        out[i] = gap[i] != none && d2 <= this->S.Cap2 ? static_cast<float>(d2)
                                                      : std::numeric_limits<float>::infinity();
      }
    }
  }
};

// The lower envelope of the parabolas w (p - q)^2 + f[q] over the sites q with finite f, at
// every p of [0, n): algorithm DT of Felzenszwalb and Huttenlocher (2012), with v the sites of
// the envelope and z the boundaries between their pieces. Infinite everywhere without a site.
void LowerEnvelope(const double* f, double* d, int n, double w, int* v, double* z)
{
  int k = -1;
  for (int q = 0; q < n; ++q)
  {
    if (!(f[q] < Infinity))
    {
      continue;
    }
    if (k < 0)
    {
      k = 0;
      v[0] = q;
      z[0] = -Infinity;
      z[1] = Infinity;
      continue;
    }
    const double fq = f[q] + w * q * q;
    double s;
    for (;;)
    {
      // Where the parabola of q overtakes that of the envelope's last site.
      const int r = v[k];
      s = (fq - (f[r] + w * r * r)) / (2.0 * w * (q - r));
      if (s <= z[k] && k > 0)
      {
        --k;
        continue;
      }
      break;
    }
    ++k;
    v[k] = q;
    z[k] = s;
    z[k + 1] = Infinity;
  }
  if (k < 0)
  {
    std::fill(d, d + n, Infinity);
    return;
  }
  int j = 0;
  for (int p = 0; p < n; ++p)
  {
    while (z[j + 1] < p)
    {
      ++j;
    }
    const double e = p - v[j];
    d[p] = w * e * e + f[v[j]];
  }
}

// Passes y and z: the envelope along the axis of every line, ColumnBlock neighbouring lines at
// a time. The last pass writes the distances, min(sqrt(d2), cap), in world units.
struct DistanceLinePass
{
  const DistanceSetup& S;
  int Axis; // 1 or 2
  bool Final;

  int Blocks() const { return (this->S.G.Dims[0] + ColumnBlock - 1) / ColumnBlock; }
  vtkIdType Units() const
  {
    return static_cast<vtkIdType>(this->Blocks()) * this->S.G.Dims[this->Axis == 1 ? 2 : 1];
  }

  void operator()(vtkIdType begin, vtkIdType end) const
  {
    const int nx = this->S.G.Dims[0], ny = this->S.G.Dims[1];
    const int n = this->S.G.Dims[this->Axis];
    const vtkIdType stride = this->Axis == 1 ? nx : static_cast<vtkIdType>(nx) * ny;
    const vtkIdType outerStep = this->Axis == 1 ? static_cast<vtkIdType>(nx) * ny : nx;
    const double w = this->S.Weight[this->Axis];
    const int blocks = this->Blocks();
    std::vector<double> lines(static_cast<size_t>(ColumnBlock) * n), d(n), z(n + 1);
    std::vector<int> v(n);
    for (vtkIdType u = begin; u < end; ++u)
    {
      const vtkIdType outer = u / blocks;
      const int i0 = static_cast<int>(u % blocks) * ColumnBlock;
      const int count = std::min(ColumnBlock, nx - i0);
      const vtkIdType base = outer * outerStep + i0;
      for (int p = 0; p < n; ++p)
      {
        const float* row = this->S.Out + base + p * stride;
        for (int c = 0; c < count; ++c)
        {
          lines[c * n + p] = row[c];
        }
      }
      for (int c = 0; c < count; ++c)
      {
        double* line = lines.data() + static_cast<size_t>(c) * n;
        LowerEnvelope(line, d.data(), n, w, v.data(), z.data());
        for (int p = 0; p < n; ++p)
        {
          line[p] = this->Finish(d[p]);
        }
      }
      for (int p = 0; p < n; ++p)
      {
        float* row = this->S.Out + base + p * stride;
        for (int c = 0; c < count; ++c)
        {
          row[c] = static_cast<float>(lines[c * n + p]);
        }
      }
    }
  }

  double Finish(double d2) const
  {
    if (this->Final)
    {
      return d2 <= this->S.Cap2 ? std::min(std::sqrt(d2) * this->S.Unit, this->S.Cap) : this->S.Cap;
    }
    // A later pass only adds to a squared distance: one beyond the cap stays beyond it.
    return d2 <= this->S.Cap2 ? d2 : Infinity;
  }
};

// The three passes; false when aborted.
bool Distances(vtkAdaptiveSamplingOracle* self,
  const DistanceSetup& s,
  double progressBegin,
  double progressEnd)
{
  const double w = progressEnd - progressBegin;
  const DistanceLinePass alongY{ s, 1, false }, alongZ{ s, 2, true };
  return RunPass(self, s.G.Rows(), DistanceRowPass{ s }, progressBegin, progressBegin + 0.2 * w) &&
    RunPass(self, alongY.Units(), alongY, progressBegin + 0.2 * w, progressBegin + 0.6 * w) &&
    RunPass(self, alongZ.Units(), alongZ, progressBegin + 0.6 * w, progressEnd);
}

// Fills the setup's scales from its grid, a spacing (finite, non-zero) and a cap (finite, > 0);
// false when the spacings differ so much that a squared distance across the grid, in smallest
// spacings, would overflow the floats that hold it between the passes.
bool SetScales(DistanceSetup& s, const double spacing[3], double cap)
{
  s.Unit = std::min(std::abs(spacing[0]), std::min(std::abs(spacing[1]), std::abs(spacing[2])));
  double across = 0.0; // the squared diagonal of the grid in smallest spacings
  for (int a = 0; a < 3; ++a)
  {
    const double ratio = std::abs(spacing[a]) / s.Unit;
    s.Weight[a] = ratio * ratio;
    const double extent = (s.G.Dims[a] - 1.0) * ratio;
    across += extent * extent;
  }
  const double capInUnits = cap / s.Unit;
  s.Cap2 = capInUnits * capInUnits;
  s.Cap = cap;
  return across < 0.5 * std::numeric_limits<float>::max();
}

void Fill(float* out, vtkIdType points, float value)
{
  vtkSMPTools::For(0,
    points,
    [out, value](vtkIdType begin, vtkIdType end) { std::fill(out + begin, out + end, value); });
}
}

//------------------------------------------------------------------------------
// The kept smin/smax volumes and what they were computed from: the input image and array, and
// their modification times and the grid, which change whenever the values may have.
struct vtkAdaptiveSamplingOracle::RangeCache
{
  std::unique_ptr<RangeVolumes> Volumes;
  const void* Image = nullptr;
  const void* Array = nullptr;
  vtkMTimeType ImageTime = 0;
  vtkMTimeType ArrayTime = 0;
  int Dims[3] = { 0, 0, 0 };

  bool Matches(vtkImageData* image, vtkDataArray* array, const int dims[3]) const
  {
    return this->Volumes && this->Image == image && this->Array == array &&
      this->ImageTime == image->GetMTime() && this->ArrayTime == array->GetMTime() &&
      std::equal(dims, dims + 3, this->Dims);
  }
};

//------------------------------------------------------------------------------
// RefineInBackground: a second instance (the Computer, never in the background itself) computes
// the distances, in the worker's thread or, when there are no interim distances to output, in
// the caller's. Its kept range volumes serve both.
struct vtkAdaptiveSamplingOracle::vtkBackground
{
  // The Computer outlives the worker (members are destroyed in reverse), whose thread uses it.
  vtkNew<vtkAdaptiveSamplingOracle> Computer;
  vtkBackgroundWorker Worker;
  vtkAdaptiveSamplingOracle* Self = nullptr;
  std::thread::id Owner = std::this_thread::get_id();
  // The newest job and what it computes (the key of RequestDataInBackground).
  vtkIdType Job = 0;
  std::vector<double> JobKey;
  bool JobChecked = false; // CheckRefinement saw it end
  // When the last job was submitted (the rhythm of an interactive drag).
  std::chrono::steady_clock::time_point LastSubmission;
  // The job's result, written by the worker, read after GetState says it ended.
  vtkSmartPointer<vtkDataArray> Result;
  bool ResultRanges = false;
  vtkIdType ResultFeatures = 0;
  double ResultCap = 0.0;
  std::string ResultError;
  // The worker's stop flag while a job runs (read by the Computer's progress observer).
  std::atomic<const std::atomic<bool>*> Stop{ nullptr };
  // The input as the worker sees it: a shallow copy made again only when the data change, so
  // that the Computer's range volumes are kept across edits of the opacity.
  vtkSmartPointer<vtkImageData> Snapshot;
  std::vector<double> SnapshotKey;
  // The distances last output, their grid and the settings they were computed with.
  vtkSmartPointer<vtkDataArray> Shown;
  std::vector<double> ShownGrid;
  std::vector<double> ShownKey;
  // Whether the last output holds interim distances.
  bool Interim = false;
  vtkTimeStamp Ended; // when a job's end was seen: the next update takes its result

  // Errors and warnings of the Computer: the owner's own on the caller's thread, kept for the
  // next update in the worker's.
  static void Report(vtkObject*, unsigned long event, void* clientData, void* callData)
  {
    vtkBackground& b = *static_cast<vtkBackground*>(clientData);
    vtkAdaptiveSamplingOracle* self = b.Self;
    const char* text = static_cast<const char*>(callData);
    if (std::this_thread::get_id() == b.Owner)
    {
      self->InvokeEvent(event, callData);
      if (!self->HasObserver(event) && text)
      {
        if (event == vtkCommand::ErrorEvent)
        {
          vtkOutputWindowDisplayErrorText(text);
        }
        else
        {
          vtkOutputWindowDisplayWarningText(text);
        }
      }
    }
    else if (event == vtkCommand::ErrorEvent && text)
    {
      b.ResultError += text;
    }
  }

  // A stopped job aborts the Computer between its chunks.
  static void Abort(vtkObject*, unsigned long, void* clientData, void*)
  {
    vtkBackground& b = *static_cast<vtkBackground*>(clientData);
    const std::atomic<bool>* stop = b.Stop.load();
    if (stop && *stop)
    {
      b.Computer->SetAbortExecute(1);
    }
  }

  // The owner's settings, copied for the worker.
  struct Settings
  {
    int Mode;
    double Epsilon;
    vtkTypeBool AutomaticMaximumDistance;
    double MaximumDistance;
    std::string OutputArrayName;
  };

  // Computes the distances of snapshot for the settings and the given opacity, on the calling
  // thread; false when it failed or was stopped.
  bool Compute(const Settings& owner,
    vtkImageData* snapshot,
    vtkPiecewiseFunction* opacity,
    vtkInformation* arrayInfo)
  {
    vtkAdaptiveSamplingOracle* c = this->Computer;
    c->LowPriority = std::this_thread::get_id() != this->Owner;
    c->SetInputData(snapshot);
    c->SetInputArrayToProcess(0, arrayInfo);
    c->SetScalarOpacity(opacity);
    c->SetMode(owner.Mode);
    c->SetEpsilon(owner.Epsilon);
    c->SetAutomaticMaximumDistance(owner.AutomaticMaximumDistance);
    c->SetMaximumDistance(owner.MaximumDistance);
    c->SetOutputArrayName(owner.OutputArrayName.c_str());
    c->SetAbortExecute(0);
    c->Modified(); // an aborted execution must not pass for an up-to-date one
    this->ResultError.clear();
    c->Update();
    vtkDataArray* distances =
      c->GetOutput()->GetPointData()->GetArray(owner.OutputArrayName.c_str());
    this->Result = c->GetAbortExecute() ? nullptr : distances;
    this->ResultRanges = c->GetLastRecomputedRanges();
    this->ResultFeatures = c->GetLastNumberOfFeaturePoints();
    this->ResultCap = c->GetLastMaximumDistance();
    c->SetInputData(nullptr);
    return this->Result != nullptr;
  }
};

//------------------------------------------------------------------------------
vtkAdaptiveSamplingOracle::vtkAdaptiveSamplingOracle()
{
  this->SetOutputArrayName("OracleDistance");
  this->SetInputArrayToProcess(
    0, 0, 0, vtkDataObject::FIELD_ASSOCIATION_POINTS, vtkDataSetAttributes::SCALARS);
}

//------------------------------------------------------------------------------
vtkAdaptiveSamplingOracle::~vtkAdaptiveSamplingOracle()
{
  if (this->Background)
  {
    this->Background->Worker.Cancel();
    this->Background->Worker.Wait();
  }
  this->SetOutputArrayName(nullptr);
  this->SetScalarOpacity(nullptr);
}

//------------------------------------------------------------------------------
const char* vtkAdaptiveSamplingOracle::GetModeAsString()
{
  switch (this->Mode)
  {
    case OPACITY_GRADIENT:
      return "OpacityGradient";
    case MIN:
      return "Min";
    case MAX:
      return "Max";
    default:
      return "OpacityRange";
  }
}

//------------------------------------------------------------------------------
void vtkAdaptiveSamplingOracle::AddOpacityPoint(double scalar, double opacity)
{
  if (!this->ScalarOpacity)
  {
    vtkNew<vtkPiecewiseFunction> function;
    this->SetScalarOpacity(function);
  }
  this->ScalarOpacity->AddPoint(scalar, opacity);
}

//------------------------------------------------------------------------------
void vtkAdaptiveSamplingOracle::RemoveAllOpacityPoints()
{
  if (this->ScalarOpacity)
  {
    this->ScalarOpacity->RemoveAllPoints();
  }
}

//------------------------------------------------------------------------------
vtkMTimeType vtkAdaptiveSamplingOracle::GetMTime()
{
  vtkMTimeType mtime = this->Superclass::GetMTime();
  if (this->ScalarOpacity)
  {
    mtime = std::max(mtime, this->ScalarOpacity->GetMTime());
  }
  if (this->Background)
  {
    mtime = std::max(mtime, this->Background->Ended.GetMTime());
  }
  return mtime;
}

//------------------------------------------------------------------------------
void vtkAdaptiveSamplingOracle::SetRefineInBackground(bool refine)
{
  if (refine == this->RefineInBackground)
  {
    return;
  }
  this->RefineInBackground = refine;
  if (refine)
  {
    if (!this->Background)
    {
      this->Background.reset(new vtkBackground);
      vtkBackground& b = *this->Background;
      b.Self = this;
      vtkNew<vtkCallbackCommand> report;
      report->SetCallback(vtkBackground::Report);
      report->SetClientData(&b);
      b.Computer->AddObserver(vtkCommand::ErrorEvent, report);
      b.Computer->AddObserver(vtkCommand::WarningEvent, report);
      vtkNew<vtkCallbackCommand> abort;
      abort->SetCallback(vtkBackground::Abort);
      abort->SetClientData(&b);
      b.Computer->AddObserver(vtkCommand::ProgressEvent, abort);
    }
    this->Cache.reset(); // the Computer keeps its own
  }
  else if (this->Background)
  {
    this->Background.reset(); // stops and joins the worker
  }
  this->Modified();
}

//------------------------------------------------------------------------------
bool vtkAdaptiveSamplingOracle::GetRefining()
{
  return this->Background && this->Background->Interim;
}

//------------------------------------------------------------------------------
bool vtkAdaptiveSamplingOracle::GetRefinementReady()
{
  if (!this->GetRefining() || this->Background->Job == 0)
  {
    return false;
  }
  const int state = this->Background->Worker.GetState(this->Background->Job);
  return state == vtkBackgroundWorker::DONE || state == vtkBackgroundWorker::FAILED;
}

//------------------------------------------------------------------------------
double vtkAdaptiveSamplingOracle::GetRefinementProgress()
{
  if (!this->GetRefining() || this->GetRefinementReady())
  {
    return 1.0;
  }
  return this->Background->Computer->GetProgress();
}

//------------------------------------------------------------------------------
bool vtkAdaptiveSamplingOracle::CheckRefinement()
{
  if (!this->GetRefinementReady() || this->Background->JobChecked)
  {
    return false;
  }
  this->Background->JobChecked = true;
  this->Background->Ended.Modified();
  this->InvokeEvent(OracleRefinedEvent);
  return true;
}

//------------------------------------------------------------------------------
void vtkAdaptiveSamplingOracle::WaitForRefinement()
{
  if (!this->GetRefining())
  {
    return;
  }
  this->Background->Worker.Wait();
  if (!this->Background->JobChecked)
  {
    this->Background->JobChecked = true;
    this->Background->Ended.Modified();
  }
}

//------------------------------------------------------------------------------
int vtkAdaptiveSamplingOracle::RequestDataInBackground(vtkImageData* input,
  vtkDataArray* scalars,
  int association,
  vtkImageData* output,
  vtkInformation* outInfo)
{
  vtkBackground& b = *this->Background;
  int dims[3];
  input->GetDimensions(dims);
  const double* spacing = input->GetSpacing();
  // What the distances depend on: the grid and settings (which interim distances must share),
  // the data, and the opacity function by content (ParaView sets it again unchanged).
  std::vector<double> grid = { static_cast<double>(dims[0]),
    static_cast<double>(dims[1]),
    static_cast<double>(dims[2]),
    spacing[0],
    spacing[1],
    spacing[2],
    static_cast<double>(this->Mode),
    this->Epsilon,
    static_cast<double>(this->AutomaticMaximumDistance),
    this->MaximumDistance,
    static_cast<double>(std::hash<std::string>()(this->OutputArrayName)) };
  std::vector<double> data = { static_cast<double>(reinterpret_cast<uintptr_t>(input)),
    static_cast<double>(input->GetMTime()),
    static_cast<double>(reinterpret_cast<uintptr_t>(scalars)),
    static_cast<double>(scalars->GetMTime()),
    static_cast<double>(association) };
  std::vector<double> key = grid;
  key.insert(key.end(), data.begin(), data.end());
  if (this->Mode == OPACITY_GRADIENT || this->Mode == OPACITY_RANGE)
  {
    const int n = this->ScalarOpacity->GetSize();
    const double* nodes = this->ScalarOpacity->GetDataPointer();
    key.insert(key.end(), nodes, nodes + 2 * n);
    for (int i = 0; i < n; ++i)
    {
      double node[4];
      this->ScalarOpacity->GetNodeValue(i, node);
      key.push_back(node[2]);
      key.push_back(node[3]);
    }
    key.push_back(this->ScalarOpacity->GetClamping());
    key.push_back(this->ScalarOpacity->GetUseLogScale());
  }

  auto give = [&](vtkDataArray* distances)
  {
    output->ShallowCopy(input);
    output->GetPointData()->AddArray(distances);
    if (outInfo->Has(vtkStreamingDemandDrivenPipeline::UPDATE_EXTENT()))
    {
      output->Crop(outInfo->Get(vtkStreamingDemandDrivenPipeline::UPDATE_EXTENT()));
    }
  };
  auto take = [&]()
  {
    b.Shown = b.Result;
    b.ShownGrid = grid;
    b.ShownKey = key;
    b.Interim = false;
    b.Job = 0;
    this->LastRecomputedRanges = b.ResultRanges;
    this->LastNumberOfFeaturePoints = b.ResultFeatures;
    this->LastMaximumDistance = b.ResultCap;
    give(b.Shown);
    return 1;
  };

  // Nothing changed: the distances output last.
  if (b.Shown && b.ShownKey == key)
  {
    b.Worker.Cancel();
    b.Job = 0;
    b.Interim = false;
    give(b.Shown);
    return 1;
  }
  // The job of this key: its distances when it is done, the interim ones while it runs; when it
  // failed (or was stopped), they are computed here, where errors reach the caller.
  bool here = false;
  if (b.Job != 0 && b.JobKey == key)
  {
    const int state = b.Worker.GetState(b.Job);
    if (state == vtkBackgroundWorker::DONE)
    {
      return take();
    }
    if (state == vtkBackgroundWorker::WAITING || state == vtkBackgroundWorker::RUNNING)
    {
      give(b.Shown);
      return 1;
    }
    here = true;
  }

  if (b.SnapshotKey != data || !b.Snapshot)
  {
    b.Snapshot = vtkSmartPointer<vtkImageData>::New();
    b.Snapshot->ShallowCopy(input);
    b.SnapshotKey = data;
  }
  vtkNew<vtkInformation> arrayInfo;
  arrayInfo->Copy(this->GetInputArrayInformation(0));
  const vtkBackground::Settings settings = { this->Mode,
    this->Epsilon,
    this->AutomaticMaximumDistance,
    this->MaximumDistance,
    this->OutputArrayName };
  vtkSmartPointer<vtkPiecewiseFunction> opacity;
  if (this->ScalarOpacity)
  {
    opacity = vtkSmartPointer<vtkPiecewiseFunction>::New();
    opacity->DeepCopy(this->ScalarOpacity);
  }

  if (here || !b.Shown || b.ShownGrid != grid)
  {
    // Nothing to answer with: computed here (the worker stopped first, as it shares the
    // Computer).
    b.Worker.Cancel();
    b.Worker.Wait();
    b.Job = 0;
    b.Interim = false;
    if (!b.Compute(settings, b.Snapshot, opacity, arrayInfo))
    {
      b.Shown = nullptr;
      output->Initialize();
      return 1;
    }
    return take();
  }

  // Answer with the last distances; compute this key's in the worker.
  vtkSmartPointer<vtkImageData> snapshot = b.Snapshot;
  vtkSmartPointer<vtkInformation> info = arrayInfo.GetPointer();
  b.JobKey = key;
  b.JobChecked = false;
  // A drag of edits supersedes each job by the next: the job waits one and a half times the
  // drag's rhythm (the time since the last update, when under a second) before it starts, so that
  // its passes, which stream through the volume, do not slow the frames of the drag (low priority
  // does not share memory bandwidth), and it starts soon after the drag pauses.
  const auto now = std::chrono::steady_clock::now();
  const double interval =
    b.Job != 0 || b.Interim ? std::chrono::duration<double>(now - b.LastSubmission).count() : -1.0;
  b.LastSubmission = now;
  // An update more than a second after the last is no drag: its job starts at once.
  const double delay = interval > 0.0 && interval < 1.0 ? std::min(1.5 * interval, 1.0) : 0.0;
  vtkBackground* worker = &b;
  b.Job = b.Worker.Submit(
    [worker, settings, snapshot, opacity, info, now, delay](
      vtkIdType, const std::atomic<bool>& stop)
    {
      vtkBackground& w = *worker;
      while (!stop &&
        std::chrono::duration<double>(std::chrono::steady_clock::now() - now).count() < delay)
      {
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
      }
      if (stop)
      {
        return false;
      }
      w.Stop = &stop;
      const bool done = w.Compute(settings, snapshot, opacity, info) && !stop;
      w.Stop = nullptr;
      return done;
    });
  if (b.Job == 0)
  {
    vtkErrorMacro("The worker thread could not start; the distances are computed here.");
    this->Background->Interim = false;
    if (!b.Compute(settings, b.Snapshot, opacity, arrayInfo))
    {
      output->Initialize();
      return 1;
    }
    return take();
  }
  b.Interim = true;
  give(b.Shown);
  return 1;
}

//------------------------------------------------------------------------------
bool vtkAdaptiveSamplingOracle::DistanceTransform(vtkDataArray* mask,
  const int dims[3],
  const double spacing[3],
  double maximumDistance,
  vtkFloatArray* distances)
{
  if (!mask || !distances || !dims || !spacing || dims[0] < 1 || dims[1] < 1 || dims[2] < 1 ||
    mask->GetNumberOfComponents() != 1 || !(maximumDistance > 0.0) ||
    !(maximumDistance <= std::numeric_limits<float>::max()))
  {
    return false;
  }
  for (int a = 0; a < 3; ++a)
  {
    if (!std::isfinite(spacing[a]) || spacing[a] == 0.0)
    {
      return false;
    }
  }
  DistanceSetup s;
  std::copy(dims, dims + 3, s.G.Dims);
  const vtkIdType points = s.G.Points();
  if (mask->GetNumberOfTuples() != points)
  {
    return false;
  }
  std::vector<unsigned char> flags;
  try
  {
    flags.resize(points);
  }
  catch (const std::bad_alloc&)
  {
    return false;
  }
  for (vtkIdType p = 0; p < points; ++p)
  {
    flags[p] = mask->GetComponent(p, 0) != 0.0 ? 1 : 0;
  }
  if (!SetScales(s, spacing, maximumDistance))
  {
    return false;
  }
  distances->SetNumberOfComponents(1);
  distances->SetNumberOfTuples(points);
  s.Mask = flags.data();
  s.Out = distances->GetPointer(0);
  return Distances(nullptr, s, 0.0, 1.0);
}

//------------------------------------------------------------------------------
int vtkAdaptiveSamplingOracle::RequestInformation(vtkInformation* request,
  vtkInformationVector** inputVector,
  vtkInformationVector* outputVector)
{
  if (!this->Superclass::RequestInformation(request, inputVector, outputVector))
  {
    return 0;
  }
  // A piece of a parallel pipeline is cut out of the whole volume's oracle (RequestData).
  outputVector->GetInformationObject(0)->Set(CAN_PRODUCE_SUB_EXTENT(), 1);
  return 1;
}

//------------------------------------------------------------------------------
int vtkAdaptiveSamplingOracle::RequestUpdateExtent(vtkInformation*,
  vtkInformationVector** inputVector,
  vtkInformationVector*)
{
  // A distance can reach across the whole volume: every request, piece or extent, needs all of
  // it (and no ghost levels beyond it).
  vtkInformation* inInfo = inputVector[0]->GetInformationObject(0);
  inInfo->Set(vtkStreamingDemandDrivenPipeline::UPDATE_EXTENT(),
    inInfo->Get(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT()),
    6);
  inInfo->Set(vtkStreamingDemandDrivenPipeline::UPDATE_PIECE_NUMBER(), 0);
  inInfo->Set(vtkStreamingDemandDrivenPipeline::UPDATE_NUMBER_OF_PIECES(), 1);
  inInfo->Set(vtkStreamingDemandDrivenPipeline::UPDATE_NUMBER_OF_GHOST_LEVELS(), 0);
  return 1;
}

//------------------------------------------------------------------------------
int vtkAdaptiveSamplingOracle::RequestData(vtkInformation*,
  vtkInformationVector** inputVector,
  vtkInformationVector* outputVector)
{
  vtkImageData* input = vtkImageData::GetData(inputVector[0]);
  vtkImageData* output = vtkImageData::GetData(outputVector);
  output->Initialize();
  this->LastRecomputedRanges = false;
  this->LastNumberOfFeaturePoints = 0;
  if (!input)
  {
    vtkErrorMacro("The input is not image data.");
    return 1;
  }
  const bool opacityMode = this->Mode == OPACITY_GRADIENT || this->Mode == OPACITY_RANGE;
  if (this->Mode != OPACITY_RANGE)
  {
    this->Cache.reset(); // the ranges are only worth their memory while they are used
  }

  // Settings.
  if (!(this->Epsilon >= 0.0) || !std::isfinite(this->Epsilon))
  {
    vtkErrorMacro("Epsilon must be finite and >= 0, got " << this->Epsilon << ".");
    return 1;
  }
  if (!this->OutputArrayName || !*this->OutputArrayName)
  {
    vtkErrorMacro("OutputArrayName is empty; the distances need a name.");
    return 1;
  }
  if (opacityMode && !this->ScalarOpacity)
  {
    vtkErrorMacro("No ScalarOpacity: mode " << this->GetModeAsString()
                                            << " needs the opacity transfer function.");
    return 1;
  }
  if (opacityMode && this->ScalarOpacity->GetSize() == 0)
  {
    vtkErrorMacro("The ScalarOpacity function has no points: mode "
      << this->GetModeAsString() << " needs the opacity transfer function.");
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
        "the oracle needs values at the grid's points",
        "the distances",
        problem))
  {
    vtkErrorMacro(<< problem);
    return 1;
  }
  if (this->RefineInBackground && this->Background)
  {
    return this->RequestDataInBackground(
      input, scalars, association, output, outputVector->GetInformationObject(0));
  }
  int dims[3];
  input->GetDimensions(dims);
  const vtkIdType points = input->GetNumberOfPoints();
  const double* spacing = input->GetSpacing();
  DistanceSetup setup;
  std::copy(dims, dims + 3, setup.G.Dims);
  const double smallest =
    std::min(std::abs(spacing[0]), std::min(std::abs(spacing[1]), std::abs(spacing[2])));
  const double cap =
    this->AutomaticMaximumDistance ? AutomaticCapInSpacings * smallest : this->MaximumDistance;
  // The cap is written as a float.
  if (!(cap > 0.0) || !(cap <= std::numeric_limits<float>::max()))
  {
    vtkErrorMacro("The maximum distance must be > 0 and finite as a float, got "
      << cap << (this->AutomaticMaximumDistance ? " (8 times the smallest spacing)." : "."));
    return 1;
  }
  if (!SetScales(setup, spacing, cap))
  {
    vtkErrorMacro("The spacings (" << spacing[0] << ", " << spacing[1] << ", " << spacing[2]
                                   << ") differ too much for the distances across the grid.");
    return 1;
  }

  // Memory: the output floats, the mask, and the range volumes when they are to be computed.
  // An impossible size is an error and an empty output, not an allocation that overcommits and
  // is killed when written.
  const bool computeRanges =
    this->Mode == OPACITY_RANGE && !(this->Cache && this->Cache->Matches(input, scalars, dims));
  double bytes = sizeof(float) * static_cast<double>(points);
  if (opacityMode)
  {
    bytes += static_cast<double>(points);
  }
  if (computeRanges)
  {
    this->Cache.reset();
    bytes += (2.0 * scalars->GetDataTypeSize() + 1.0) * static_cast<double>(points);
  }
  vtksys::SystemInformation system;
  system.RunMemoryCheck();
  const double memory = 1048576.0 * static_cast<double>(system.GetTotalPhysicalMemory()); // MiB
  vtkNew<vtkFloatArray> distances;
  distances->SetName(this->OutputArrayName);
  distances->SetNumberOfComponents(1);
  std::vector<unsigned char> mask;
  bool allocated = (memory <= 0.0 || bytes <= memory) && distances->Allocate(points);
  if (allocated && opacityMode)
  {
    try
    {
      mask.resize(points);
    }
    catch (const std::bad_alloc&)
    {
      allocated = false;
    }
  }
  if (!allocated)
  {
    vtkErrorMacro("The oracle of " << points << " points (" << std::ceil(bytes / 1048576.0)
                                   << " MiB) does not fit in memory.");
    return 1;
  }
  distances->SetNumberOfTuples(points);
  float* out = distances->GetPointer(0);
  setup.Out = out;
  setup.Mask = mask.data();

  bool completed = true;
  if (this->Mode == MIN || this->Mode == MAX)
  {
    // MIN is the paper's "min." oracle, always the smallest sampling distance (line 231).
    Fill(out, points, this->Mode == MIN ? 0.0f : static_cast<float>(cap));
    this->UpdateProgress(1.0);
  }
  else
  {
    Opacity alpha;
    alpha.Copy(this->ScalarOpacity);
    std::atomic<vtkIdType> features(0);
    // Progress: the range volumes (when computed) or the alpha volume, the mask, and the
    // distance transform, roughly by their cost.
    double maskBegin = 0.0, distanceBegin = 0.2;
    if (this->Mode == OPACITY_RANGE)
    {
      if (computeRanges)
      {
        maskBegin = 0.45;
        distanceBegin = 0.55;
        RangeWorker worker{ this, &setup.G, 0.0, maskBegin, nullptr };
        if (!vtkArrayDispatch::Dispatch::Execute(scalars, worker))
        {
          worker(scalars); // any other array type, through the vtkDataArray interface
        }
        if (worker.OutOfMemory)
        {
          vtkErrorMacro("The range volumes of " << points << " points do not fit in memory.");
          return 1;
        }
        completed = worker.Volumes != nullptr;
        if (completed)
        {
          this->Cache.reset(new RangeCache);
          this->Cache->Volumes = std::move(worker.Volumes);
          this->Cache->Image = input;
          this->Cache->Array = scalars;
          this->Cache->ImageTime = input->GetMTime();
          this->Cache->ArrayTime = scalars->GetMTime();
          std::copy(dims, dims + 3, this->Cache->Dims);
          this->LastRecomputedRanges = true;
        }
      }
      completed = completed &&
        RunPass(this,
          points,
          RangeMaskPass{ *this->Cache->Volumes, alpha, this->Epsilon, mask.data(), features },
          maskBegin,
          distanceBegin);
    }
    else
    {
      maskBegin = 0.1;
      distanceBegin = 0.25;
      AlphaWorker worker{ &alpha, out, this, points, 0.0, maskBegin };
      if (!vtkArrayDispatch::Dispatch::Execute(scalars, worker))
      {
        worker(scalars);
      }
      completed = worker.Completed &&
        RunPass(this,
          setup.G.Rows(),
          GradientMaskPass{ setup.G, out, this->Epsilon, mask.data(), features },
          maskBegin,
          distanceBegin);
    }
    if (completed)
    {
      this->LastNumberOfFeaturePoints = features;
      if (features == 0)
      {
        Fill(out, points, static_cast<float>(cap));
        this->UpdateProgress(1.0);
      }
      else
      {
        // The paper's oracle: the distance to the nearest feature voxel (line 236).
        completed = Distances(this, setup, distanceBegin, 1.0);
      }
    }
  }

  output->ShallowCopy(input);
  if (completed) // else aborted: the input passed through, without distances
  {
    output->GetPointData()->AddArray(distances);
    this->LastMaximumDistance = cap;
  }
  // The whole extent was computed; give back what was asked for.
  vtkInformation* outInfo = outputVector->GetInformationObject(0);
  if (outInfo->Has(vtkStreamingDemandDrivenPipeline::UPDATE_EXTENT()))
  {
    output->Crop(outInfo->Get(vtkStreamingDemandDrivenPipeline::UPDATE_EXTENT()));
  }
  return 1;
}

//------------------------------------------------------------------------------
void vtkAdaptiveSamplingOracle::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Mode: " << this->GetModeAsString() << "\n";
  os << indent << "ScalarOpacity: ";
  if (this->ScalarOpacity)
  {
    os << this->ScalarOpacity << " (" << this->ScalarOpacity->GetSize() << " points)\n";
  }
  else
  {
    os << "(none)\n";
  }
  os << indent << "Epsilon: " << this->Epsilon << "\n";
  os << indent << "AutomaticMaximumDistance: " << (this->AutomaticMaximumDistance ? "On" : "Off")
     << "\n";
  os << indent << "MaximumDistance: " << this->MaximumDistance << "\n";
  os << indent << "OutputArrayName: " << (this->OutputArrayName ? this->OutputArrayName : "(none)")
     << "\n";
  os << indent << "LastRecomputedRanges: " << this->LastRecomputedRanges << "\n";
  os << indent << "LastNumberOfFeaturePoints: " << this->LastNumberOfFeaturePoints << "\n";
  os << indent << "LastMaximumDistance: " << this->LastMaximumDistance << "\n";
  os << indent << "RefineInBackground: " << this->RefineInBackground << "\n";
  os << indent << "LowPriority: " << this->LowPriority << "\n";
}
