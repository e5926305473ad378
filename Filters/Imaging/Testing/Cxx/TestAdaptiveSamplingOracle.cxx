// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
// vtkAdaptiveSamplingOracle, the oracle volume of "Adaptive Sampling in Three Dimensions for
// Volume Rendering on GPUs" (lines 231-236 of the paper's text), against:
// - exact distances on hand-made masks (one point, two points, a plane, none, all) with
//   anisotropic spacing and caps, through DistanceTransform and through the filter;
// - vtkImageEuclideanDistance on random masks (squared distances, square-rooted and capped);
// - a brute-force reference written out here (vtkPiecewiseFunction::GetValue, both feature
//   tests, the distance to every feature point) on random volumes and transfer functions
//   (midpoints, sharpness, steps, duplicate nodes, no clamping, log scale), every input type
//   and NaN values;
// - the transfer-function spike between two voxel values, which only OPACITY_RANGE sees;
// and MIN and MAX, constant volumes, slabs, the cache of the range volumes across
// transfer-function edits and input changes, pieces and sub-extents, progress and abort, and
// bad input (an error and an empty output each).
#include "vtkAdaptiveSamplingOracle.h"
#include "vtkBitArray.h"
#include "vtkCellData.h"
#include "vtkCharArray.h"
#include "vtkCommand.h"
#include "vtkDoubleArray.h"
#include "vtkExecutive.h"
#include "vtkFloatArray.h"
#include "vtkImageData.h"
#include "vtkImageEuclideanDistance.h"
#include "vtkIntArray.h"
#include "vtkLongLongArray.h"
#include "vtkNew.h"
#include "vtkPiecewiseFunction.h"
#include "vtkPointData.h"
#include "vtkSOADataArrayTemplate.h"
#include "vtkShortArray.h"
#include "vtkSmartPointer.h"
#include "vtkTestErrorObserver.h"
#include "vtkTrivialProducer.h"
#include "vtkUnsignedCharArray.h"
#include "vtkUnsignedShortArray.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <functional>
#include <iostream>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

namespace
{
int failures = 0;
bool Check(bool ok, const std::string& what)
{
  if (!ok)
  {
    std::cerr << "Failed: " << what << "\n";
    ++failures;
  }
  return ok;
}

std::string Str(double v)
{
  std::ostringstream s;
  s.precision(9);
  s << v;
  return s.str();
}

const double NaN = std::numeric_limits<double>::quiet_NaN();
const double Inf = std::numeric_limits<double>::infinity();

// Deterministic values in [0, 1).
double Hash(uint32_t x)
{
  x ^= x >> 16;
  x *= 0x7feb352dU;
  x ^= x >> 15;
  x *= 0x846ca68bU;
  x ^= x >> 16;
  return (x & 0xffffff) / 16777216.0;
}

struct Grid
{
  int N[3];
  double Spacing[3];
  vtkIdType Size() const { return static_cast<vtkIdType>(N[0]) * N[1] * N[2]; }
  vtkIdType Id(int i, int j, int k) const
  {
    return i + N[0] * (j + static_cast<vtkIdType>(N[1]) * k);
  }
  void Index(vtkIdType id, int ijk[3]) const
  {
    ijk[0] = static_cast<int>(id % N[0]);
    ijk[1] = static_cast<int>((id / N[0]) % N[1]);
    ijk[2] = static_cast<int>(id / (static_cast<vtkIdType>(N[0]) * N[1]));
  }
};

// The exact capped distance from every point to the nearest feature, by brute force.
std::vector<double> BruteDistances(const Grid& g,
  const std::vector<unsigned char>& mask,
  double cap)
{
  std::vector<std::array<int, 3>> features;
  for (vtkIdType p = 0; p < g.Size(); ++p)
  {
    if (mask[p])
    {
      std::array<int, 3> ijk;
      g.Index(p, ijk.data());
      features.push_back(ijk);
    }
  }
  std::vector<double> out(g.Size(), cap);
  for (vtkIdType p = 0; p < g.Size(); ++p)
  {
    int ijk[3];
    g.Index(p, ijk);
    double best = Inf;
    for (const auto& f : features)
    {
      double d2 = 0.0;
      for (int a = 0; a < 3; ++a)
      {
        const double d = (ijk[a] - f[a]) * g.Spacing[a];
        d2 += d * d;
      }
      best = std::min(best, d2);
    }
    out[p] = std::min(std::sqrt(best), cap);
  }
  return out;
}

// The largest difference, or infinity when sizes differ or a value is not finite.
double Worst(const std::vector<double>& got, const std::vector<double>& expected)
{
  if (got.size() != expected.size() || got.empty())
  {
    return Inf;
  }
  double worst = 0.0;
  for (size_t p = 0; p < got.size(); ++p)
  {
    const double d = std::abs(got[p] - expected[p]);
    worst = std::max(worst, std::isfinite(d) ? d : Inf);
  }
  return worst;
}

// The cap as the float output holds it (the filter writes it unrounded where it applies).
double Capped(double cap)
{
  return static_cast<float>(cap);
}

// Float output: a relative rounding of about 6e-8 per pass on squared distances.
double Tolerance(double cap)
{
  return 1e-6 * cap;
}

std::vector<double> Values(vtkDataArray* array)
{
  std::vector<double> out;
  if (!array)
  {
    return out;
  }
  out.resize(array->GetNumberOfTuples());
  for (vtkIdType p = 0; p < array->GetNumberOfTuples(); ++p)
  {
    out[p] = array->GetComponent(p, 0);
  }
  return out;
}

std::vector<double> Oracle(vtkImageData* image, const char* name = "OracleDistance")
{
  return Values(image ? image->GetPointData()->GetArray(name) : nullptr);
}

std::vector<double> Transform(const Grid& g, const std::vector<unsigned char>& mask, double cap)
{
  vtkNew<vtkUnsignedCharArray> m;
  m->SetNumberOfTuples(g.Size());
  for (vtkIdType p = 0; p < g.Size(); ++p)
  {
    m->SetValue(p, mask[p]);
  }
  vtkNew<vtkFloatArray> out;
  if (!vtkAdaptiveSamplingOracle::DistanceTransform(m, g.N, g.Spacing, cap, out))
  {
    return {};
  }
  return Values(out);
}

template <typename ArrayT = vtkDoubleArray>
vtkSmartPointer<vtkImageData> ToImage(const Grid& g,
  const std::vector<double>& values,
  const char* name = "scalars")
{
  auto image = vtkSmartPointer<vtkImageData>::New();
  image->SetDimensions(g.N[0], g.N[1], g.N[2]);
  image->SetSpacing(g.Spacing[0], g.Spacing[1], g.Spacing[2]);
  image->SetOrigin(0.5, -1.0, 2.0);
  vtkNew<ArrayT> array;
  array->SetName(name);
  array->SetNumberOfComponents(1);
  array->SetNumberOfTuples(g.Size());
  for (vtkIdType p = 0; p < g.Size(); ++p)
  {
    array->SetComponent(p, 0, values[p]);
  }
  image->GetPointData()->SetScalars(array);
  return image;
}

vtkSmartPointer<vtkPiecewiseFunction> Ramp(double x0, double x1)
{
  auto f = vtkSmartPointer<vtkPiecewiseFunction>::New();
  f->AddPoint(x0, 0.0);
  f->AddPoint(x1, 1.0);
  return f;
}

struct Run
{
  vtkSmartPointer<vtkAdaptiveSamplingOracle> Filter;
  std::vector<double> Distances;
};

Run RunFilter(vtkImageData* image,
  vtkPiecewiseFunction* tf,
  int mode,
  double epsilon,
  double cap = 0.0) // 0: automatic
{
  Run r;
  r.Filter = vtkSmartPointer<vtkAdaptiveSamplingOracle>::New();
  r.Filter->SetInputData(image);
  r.Filter->SetScalarOpacity(tf);
  r.Filter->SetMode(mode);
  r.Filter->SetEpsilon(epsilon);
  if (cap > 0.0)
  {
    r.Filter->AutomaticMaximumDistanceOff();
    r.Filter->SetMaximumDistance(cap);
  }
  r.Filter->Update();
  r.Distances = Oracle(r.Filter->GetOutput());
  return r;
}

//------------------------------------------------------------------------------
// The specification written out: alpha = GetValue (NaN scalars and NaN opacities 0), the two
// feature tests, and the brute-force distances.
double Alpha(vtkPiecewiseFunction* tf, double v)
{
  if (std::isnan(v))
  {
    return 0.0;
  }
  const double a = tf->GetValue(v);
  return std::isnan(a) ? 0.0 : a;
}

std::vector<unsigned char> GradientFeatures(const Grid& g,
  const std::vector<double>& values,
  vtkPiecewiseFunction* tf,
  double eps)
{
  // The filter keeps alpha as floats (in its output array) and differences them in double.
  std::vector<double> alpha(g.Size());
  for (vtkIdType p = 0; p < g.Size(); ++p)
  {
    alpha[p] = static_cast<float>(Alpha(tf, values[p]));
  }
  std::vector<unsigned char> mask(g.Size());
  for (vtkIdType p = 0; p < g.Size(); ++p)
  {
    int ijk[3];
    g.Index(p, ijk);
    double sum = 0.0;
    for (int a = 0; a < 3; ++a)
    {
      int lo[3] = { ijk[0], ijk[1], ijk[2] }, hi[3] = { ijk[0], ijk[1], ijk[2] };
      lo[a] = std::max(ijk[a] - 1, 0);
      hi[a] = std::min(ijk[a] + 1, g.N[a] - 1);
      const double span = hi[a] - lo[a]; // 2 inside, 1 on a face, 0 on a line of one point
      const double d = span > 0
        ? (alpha[g.Id(hi[0], hi[1], hi[2])] - alpha[g.Id(lo[0], lo[1], lo[2])]) / span
        : 0.0;
      sum += d * d;
    }
    mask[p] = std::sqrt(sum) > eps ? 1 : 0;
  }
  return mask;
}

std::vector<unsigned char> RangeFeatures(const Grid& g,
  const std::vector<double>& values,
  vtkPiecewiseFunction* tf,
  double eps)
{
  std::vector<double> nodes;
  for (int n = 0; n < tf->GetSize(); ++n)
  {
    double node[4];
    tf->GetNodeValue(n, node);
    nodes.push_back(node[0]);
  }
  std::vector<unsigned char> mask(g.Size());
  for (vtkIdType p = 0; p < g.Size(); ++p)
  {
    int ijk[3];
    g.Index(p, ijk);
    double lo = Inf, hi = -Inf;
    bool nan = false;
    for (int k = std::max(ijk[2] - 1, 0); k <= std::min(ijk[2] + 1, g.N[2] - 1); ++k)
    {
      for (int j = std::max(ijk[1] - 1, 0); j <= std::min(ijk[1] + 1, g.N[1] - 1); ++j)
      {
        for (int i = std::max(ijk[0] - 1, 0); i <= std::min(ijk[0] + 1, g.N[0] - 1); ++i)
        {
          const double v = values[g.Id(i, j, k)];
          if (std::isnan(v))
          {
            nan = true;
            continue;
          }
          lo = std::min(lo, v);
          hi = std::max(hi, v);
        }
      }
    }
    // The opacities the interval's trilinear values take: alpha at both ends and at each node
    // inside (the function is monotonic between nodes), and 0 for a NaN neighbour.
    std::vector<double> alphas;
    if (lo < hi)
    {
      alphas.push_back(Alpha(tf, lo));
      alphas.push_back(Alpha(tf, hi));
      for (int n = 0; n < tf->GetSize(); ++n)
      {
        double node[4];
        tf->GetNodeValue(n, node);
        if (node[0] >= lo && node[0] <= hi)
        {
          alphas.push_back(node[1]);
        }
      }
    }
    else if (lo == hi)
    {
      alphas.push_back(Alpha(tf, lo));
    }
    if (nan)
    {
      alphas.push_back(0.0);
    }
    const double change = alphas.empty() ? 0.0
                                         : *std::max_element(alphas.begin(), alphas.end()) -
        *std::min_element(alphas.begin(), alphas.end());
    mask[p] = change > eps ? 1 : 0;
  }
  return mask;
}

vtkIdType Count(const std::vector<unsigned char>& mask)
{
  return std::count(mask.begin(), mask.end(), 1);
}

// Progress fractions seen, and an abort request on the first one when asked.
class ProgressRecorder : public vtkCommand
{
public:
  static ProgressRecorder* New() { return new ProgressRecorder; }
  void Execute(vtkObject* caller, unsigned long, void* data) override
  {
    this->Values.push_back(*static_cast<double*>(data));
    if (this->AbortOnFirst && this->Values.size() == 1)
    {
      static_cast<vtkAdaptiveSamplingOracle*>(caller)->SetAbortExecute(1);
    }
  }
  std::vector<double> Values;
  bool AbortOnFirst = false;
};

//------------------------------------------------------------------------------
void TestDefaults()
{
  vtkNew<vtkAdaptiveSamplingOracle> filter;
  Check(filter->GetMode() == vtkAdaptiveSamplingOracle::OPACITY_RANGE, "OPACITY_RANGE initially");
  Check(filter->GetEpsilon() == 0.002, "Epsilon is 0.002 initially");
  Check(filter->GetAutomaticMaximumDistance() == 1, "automatic maximum distance initially");
  Check(filter->GetMaximumDistance() == 1.0, "MaximumDistance is 1 initially");
  Check(std::string(filter->GetOutputArrayName()) == "OracleDistance",
    "OutputArrayName is OracleDistance initially");
  Check(filter->GetScalarOpacity() == nullptr, "no ScalarOpacity initially");
  Check(!filter->GetLastRecomputedRanges() && filter->GetLastNumberOfFeaturePoints() == 0 &&
      filter->GetLastMaximumDistance() == 0.0,
    "no results before the first update");
  filter->SetModeToOpacityGradient();
  Check(std::string(filter->GetModeAsString()) == "OpacityGradient", "OpacityGradient by name");
  filter->SetModeToMin();
  Check(std::string(filter->GetModeAsString()) == "Min", "Min by name");
  filter->SetMode(9);
  Check(filter->GetMode() == vtkAdaptiveSamplingOracle::MAX, "a mode out of range is clamped");
  Check(std::string(filter->GetModeAsString()) == "Max", "Max by name");

  // The opacity points: a function is made when there is none, and edited when there is one.
  filter->AddOpacityPoint(0.0, 0.0);
  filter->AddOpacityPoint(10.0, 0.5);
  vtkPiecewiseFunction* made = filter->GetScalarOpacity();
  Check(made && made->GetSize() == 2 && made->GetValue(5.0) == 0.25,
    "AddOpacityPoint builds a linear function");
  vtkNew<vtkPiecewiseFunction> shared;
  shared->AddPoint(1.0, 1.0);
  filter->SetScalarOpacity(shared);
  const vtkMTimeType before = filter->GetMTime();
  filter->AddOpacityPoint(2.0, 0.0);
  Check(shared->GetSize() == 2, "AddOpacityPoint edits the function that is set");
  Check(filter->GetMTime() > before, "an edit of the function modifies the filter");
  filter->RemoveAllOpacityPoints();
  Check(shared->GetSize() == 0, "RemoveAllOpacityPoints empties it");

  std::ostringstream print;
  filter->Print(print);
  Check(print.str().find("Epsilon: 0.002") != std::string::npos &&
      print.str().find("Mode: Max") != std::string::npos,
    "PrintSelf prints the settings");
}

//------------------------------------------------------------------------------
// DistanceTransform on masks whose distances are known in closed form.
void TestHandMadeDistances()
{
  const Grid g{ { 9, 7, 6 }, { 0.5, 1.25, 2.0 } };
  auto closed = [&](const std::function<double(const int*)>& distance, double cap)
  {
    std::vector<double> out(g.Size());
    for (vtkIdType p = 0; p < g.Size(); ++p)
    {
      int ijk[3];
      g.Index(p, ijk);
      out[p] = std::min(distance(ijk), cap);
    }
    return out;
  };
  auto euclid = [&](const int* a, const int* b)
  {
    double d2 = 0.0;
    for (int c = 0; c < 3; ++c)
    {
      const double d = (a[c] - b[c]) * g.Spacing[c];
      d2 += d * d;
    }
    return std::sqrt(d2);
  };
  const int one[3] = { 2, 5, 1 }, two[3] = { 7, 0, 4 };
  for (double cap : { 100.0, 3.0, 0.4 })
  {
    const std::string at = " (cap " + Str(cap) + ")";
    std::vector<unsigned char> mask(g.Size(), 0);
    mask[g.Id(one[0], one[1], one[2])] = 1;
    std::vector<double> expected = closed([&](const int* p) { return euclid(p, one); }, cap);
    std::vector<double> got = Transform(g, mask, cap);
    Check(Worst(got, expected) <= Tolerance(cap),
      "one feature point: the anisotropic Euclidean distance" + at + ", worst " +
        Str(Worst(got, expected)));

    mask[g.Id(two[0], two[1], two[2])] = 1;
    expected = closed([&](const int* p) { return std::min(euclid(p, one), euclid(p, two)); }, cap);
    got = Transform(g, mask, cap);
    Check(Worst(got, expected) <= Tolerance(cap),
      "two feature points: the nearer one's distance" + at + ", worst " +
        Str(Worst(got, expected)));

    // A plane along each axis in turn: the distance across it.
    for (int axis = 0; axis < 3; ++axis)
    {
      const int at0 = g.N[axis] / 2;
      std::vector<unsigned char> plane(g.Size(), 0);
      for (vtkIdType p = 0; p < g.Size(); ++p)
      {
        int ijk[3];
        g.Index(p, ijk);
        plane[p] = ijk[axis] == at0 ? 1 : 0;
      }
      expected =
        closed([&](const int* p) { return std::abs(p[axis] - at0) * g.Spacing[axis]; }, cap);
      got = Transform(g, plane, cap);
      Check(Worst(got, expected) <= Tolerance(cap),
        "a plane across axis " + std::to_string(axis) + at + ", worst " +
          Str(Worst(got, expected)));
    }

    got = Transform(g, std::vector<unsigned char>(g.Size(), 0), cap);
    Check(Worst(got, std::vector<double>(g.Size(), cap)) <= Tolerance(cap),
      "no feature: the cap everywhere" + at);
    got = Transform(g, std::vector<unsigned char>(g.Size(), 1), cap);
    Check(Worst(got, std::vector<double>(g.Size(), 0.0)) == 0.0,
      "every point a feature: 0 everywhere" + at);
  }
  // The cap is exact where it applies: a float of the cap, not a rounded square root.
  {
    std::vector<unsigned char> mask(g.Size(), 0);
    mask[0] = 1;
    const std::vector<double> got = Transform(g, mask, 2.0);
    Check(!got.empty() && got.back() == 2.0, "a capped distance is the cap exactly");
  }
  // Slabs, lines and a single point.
  for (const auto& dims : std::vector<std::array<int, 3>>{
         { 13, 1, 1 }, { 1, 11, 1 }, { 1, 1, 9 }, { 6, 5, 1 }, { 1, 1, 1 } })
  {
    const Grid s{ { dims[0], dims[1], dims[2] }, { 0.3, 0.7, 1.1 } };
    std::vector<unsigned char> mask(s.Size(), 0);
    mask[s.Size() / 2] = 1;
    const std::vector<double> got = Transform(s, mask, 50.0);
    const std::vector<double> expected = BruteDistances(s, mask, 50.0);
    Check(Worst(got, expected) <= Tolerance(50.0),
      "a " + std::to_string(dims[0]) + " x " + std::to_string(dims[1]) + " x " +
        std::to_string(dims[2]) + " grid, worst " + Str(Worst(got, expected)));
  }
  // Bad arguments are refused and leave the output alone.
  {
    vtkNew<vtkUnsignedCharArray> mask;
    mask->SetNumberOfTuples(g.Size());
    mask->Fill(1);
    vtkNew<vtkFloatArray> out;
    out->SetNumberOfTuples(3);
    const double zero[3] = { 1, 0, 1 }, nan[3] = { 1, NaN, 1 }, unequal[3] = { 1e-20, 1, 1 };
    const int wrong[3] = { 9, 7, 5 }, empty[3] = { 9, 0, 6 };
    Check(!vtkAdaptiveSamplingOracle::DistanceTransform(mask, g.N, g.Spacing, 0.0, out) &&
        !vtkAdaptiveSamplingOracle::DistanceTransform(mask, g.N, g.Spacing, -1.0, out) &&
        !vtkAdaptiveSamplingOracle::DistanceTransform(mask, g.N, g.Spacing, Inf, out) &&
        !vtkAdaptiveSamplingOracle::DistanceTransform(mask, g.N, zero, 1.0, out) &&
        !vtkAdaptiveSamplingOracle::DistanceTransform(mask, g.N, nan, 1.0, out) &&
        !vtkAdaptiveSamplingOracle::DistanceTransform(mask, g.N, unequal, 1.0, out) &&
        !vtkAdaptiveSamplingOracle::DistanceTransform(mask, wrong, g.Spacing, 1.0, out) &&
        !vtkAdaptiveSamplingOracle::DistanceTransform(mask, empty, g.Spacing, 1.0, out) &&
        !vtkAdaptiveSamplingOracle::DistanceTransform(nullptr, g.N, g.Spacing, 1.0, out) &&
        out->GetNumberOfTuples() == 3,
      "DistanceTransform refuses bad arguments");
  }
}

//------------------------------------------------------------------------------
// vtkImageEuclideanDistance: 0 = feature (Initialize on), squared distances with the spacing
// (ConsiderAnisotropy on), MaximumDistance the squared cap. In VTK 9.1 it applies the spacing
// of its last pass only (the earlier passes write into intermediate images whose spacing is
// left at 1): the 3D filter is right for spacings (1, 1, s) only. PerAxis works around that
// with one filter per axis, each with the axis's pass as its last: x as a 1D transform of the
// mask, then y and z as the second pass of a 2D transform whose first axis has one point (the
// values laid out as 1 x n x rest, Initialize off).
vtkSmartPointer<vtkImageEuclideanDistance> EDT(const int dims[3],
  const double spacing[3],
  vtkDataArray* values,
  double cap,
  int dimensionality)
{
  vtkNew<vtkImageData> image;
  image->SetDimensions(dims[0], dims[1], dims[2]);
  image->SetSpacing(spacing[0], spacing[1], spacing[2]);
  image->GetPointData()->SetScalars(values);
  auto edt = vtkSmartPointer<vtkImageEuclideanDistance>::New();
  edt->SetInputData(image);
  edt->ConsiderAnisotropyOn();
  edt->SetMaximumDistance(cap * cap);
  edt->SetDimensionality(dimensionality);
  edt->SetInitialize(dimensionality != 2);
  edt->Update();
  return edt;
}

vtkSmartPointer<vtkUnsignedCharArray> ZeroAtFeatures(const std::vector<unsigned char>& mask)
{
  auto values = vtkSmartPointer<vtkUnsignedCharArray>::New();
  values->SetNumberOfTuples(static_cast<vtkIdType>(mask.size()));
  for (size_t p = 0; p < mask.size(); ++p)
  {
    values->SetValue(static_cast<vtkIdType>(p), mask[p] ? 0 : 1);
  }
  return values;
}

std::vector<double> RootAndCap(std::vector<double> squared, double cap)
{
  for (double& d : squared)
  {
    d = std::sqrt(std::min(d, cap * cap));
  }
  return squared;
}

std::vector<double> VTKDistances(const Grid& g, const std::vector<unsigned char>& mask, double cap)
{
  auto edt = EDT(g.N, g.Spacing, ZeroAtFeatures(mask), cap, 3);
  return RootAndCap(Values(edt->GetOutput()->GetPointData()->GetScalars()), cap);
}

std::vector<double> VTKDistancesPerAxis(const Grid& g,
  const std::vector<unsigned char>& mask,
  double cap)
{
  const int nx = g.N[0], ny = g.N[1], nz = g.N[2];
  const int rowDims[3] = { nx, ny * nz, 1 };
  const double rowSpacing[3] = { g.Spacing[0], 1.0, 1.0 };
  auto edt = EDT(rowDims, rowSpacing, ZeroAtFeatures(mask), cap, 1);
  std::vector<double> d2 = Values(edt->GetOutput()->GetPointData()->GetScalars());
  for (int axis = 1; axis <= 2; ++axis)
  {
    // Point (i, j, k) at a + n (b + ...) with a the index along the axis.
    const int n = g.N[axis];
    const vtkIdType rest = g.Size() / n;
    auto id = [&](vtkIdType p)
    {
      int ijk[3];
      g.Index(p, ijk);
      return axis == 1
        ? ijk[1] + static_cast<vtkIdType>(ny) * (ijk[0] + static_cast<vtkIdType>(nx) * ijk[2])
        : ijk[2] + static_cast<vtkIdType>(nz) * (ijk[0] + static_cast<vtkIdType>(nx) * ijk[1]);
    };
    vtkNew<vtkDoubleArray> values;
    values->SetNumberOfTuples(g.Size());
    for (vtkIdType p = 0; p < g.Size(); ++p)
    {
      values->SetValue(id(p), d2[p]);
    }
    const int lineDims[3] = { 1, n, static_cast<int>(rest) };
    const double lineSpacing[3] = { 1.0, g.Spacing[axis], 1.0 };
    edt = EDT(lineDims, lineSpacing, values, cap, 2);
    vtkDataArray* out = edt->GetOutput()->GetPointData()->GetScalars();
    for (vtkIdType p = 0; p < g.Size(); ++p)
    {
      d2[p] = out->GetComponent(id(p), 0);
    }
  }
  return RootAndCap(d2, cap);
}

void TestAgainstVTK()
{
  uint32_t seed = 1;
  for (const auto& dims :
    std::vector<std::array<int, 3>>{ { 23, 17, 29 }, { 40, 33, 8 }, { 1, 31, 19 }, { 64, 3, 5 } })
  {
    for (const auto& spacing : std::vector<std::array<double, 3>>{
           { 1.0, 1.0, 1.0 }, { 1.0, 1.0, 2.5 }, { 0.7, 1.3, 0.4 }, { 2.5, 0.25, 1.0 } })
    {
      for (double density : { 0.0005, 0.01, 0.2, 0.7 })
      {
        const Grid g{ { dims[0], dims[1], dims[2] }, { spacing[0], spacing[1], spacing[2] } };
        std::vector<unsigned char> mask(g.Size());
        for (vtkIdType p = 0; p < g.Size(); ++p)
        {
          mask[p] = Hash(seed * 7919U + static_cast<uint32_t>(p) * 2654435761U) < density;
        }
        ++seed;
        const double smallest = std::min(spacing[0], std::min(spacing[1], spacing[2]));
        for (double cap : { 8.0 * smallest, 1e3 })
        {
          const std::vector<double> got = Transform(g, mask, cap);
          std::ostringstream label;
          label << dims[0] << " x " << dims[1] << " x " << dims[2] << ", spacing " << spacing[0]
                << " " << spacing[1] << " " << spacing[2] << ", density " << density << ", cap "
                << cap << " (" << Count(mask) << " features)";
          std::vector<double> expected = VTKDistancesPerAxis(g, mask, cap);
          Check(Worst(got, expected) <= Tolerance(std::min(cap, 200.0)),
            label.str() + ": equals vtkImageEuclideanDistance axis by axis, worst " +
              Str(Worst(got, expected)));
          if (spacing[0] == 1.0 && spacing[1] == 1.0)
          {
            expected = VTKDistances(g, mask, cap);
            Check(Worst(got, expected) <= Tolerance(std::min(cap, 200.0)),
              label.str() + ": equals the 3D vtkImageEuclideanDistance, worst " +
                Str(Worst(got, expected)));
          }
        }
      }
    }
  }
  // And against brute force on one case, so that an error shared with VTK would show.
  const Grid g{ { 14, 11, 9 }, { 0.7, 1.3, 0.4 } };
  std::vector<unsigned char> mask(g.Size());
  for (vtkIdType p = 0; p < g.Size(); ++p)
  {
    mask[p] = Hash(99U + static_cast<uint32_t>(p) * 2654435761U) < 0.02;
  }
  Check(Worst(Transform(g, mask, 6.0), BruteDistances(g, mask, 6.0)) <= Tolerance(6.0),
    "a random mask: equals brute force");
}

//------------------------------------------------------------------------------
// The filter on volumes whose features are known.
void TestHandMadeFilter()
{
  const Grid g{ { 11, 9, 7 }, { 0.5, 1.25, 2.0 } };
  const double cap = 8.0 * 0.5; // automatic: 8 smallest spacings
  const int c[3] = { 4, 6, 3 };
  auto expect = [&](const std::function<double(const int*)>& d)
  {
    std::vector<double> out(g.Size());
    for (vtkIdType p = 0; p < g.Size(); ++p)
    {
      int ijk[3];
      g.Index(p, ijk);
      out[p] = std::min(d(ijk), cap);
    }
    return out;
  };

  // One voxel of value 1 in zeros, opacity ramp 0..1: OPACITY_RANGE finds the 3 x 3 x 3 box
  // around it (every point whose neighbourhood holds it), so the distance is that to the box.
  std::vector<double> bump(g.Size(), 0.0);
  bump[g.Id(c[0], c[1], c[2])] = 1.0;
  auto ramp = Ramp(0.0, 1.0);
  Run r = RunFilter(ToImage(g, bump), ramp, vtkAdaptiveSamplingOracle::OPACITY_RANGE, 0.002);
  std::vector<double> expected = expect(
    [&](const int* p)
    {
      double d2 = 0.0;
      for (int a = 0; a < 3; ++a)
      {
        const double d = std::max(std::abs(p[a] - c[a]) - 1, 0) * g.Spacing[a];
        d2 += d * d;
      }
      return std::sqrt(d2);
    });
  Check(Worst(r.Distances, expected) <= Tolerance(cap),
    "OPACITY_RANGE, one bright voxel: the distance to its 3 x 3 x 3 box, worst " +
      Str(Worst(r.Distances, expected)));
  Check(r.Filter->GetLastNumberOfFeaturePoints() == 27 && r.Filter->GetLastMaximumDistance() == cap,
    "27 feature points, cap 8 smallest spacings (" +
      std::to_string(r.Filter->GetLastNumberOfFeaturePoints()) + ", " +
      Str(r.Filter->GetLastMaximumDistance()) + ")");
  // OPACITY_GRADIENT on the same voxel: its 6 face neighbours have a central difference of
  // 1/2, the voxel itself 0 (its two neighbours along each axis are equal).
  r = RunFilter(ToImage(g, bump), ramp, vtkAdaptiveSamplingOracle::OPACITY_GRADIENT, 0.3);
  std::vector<unsigned char> six(g.Size(), 0);
  for (int a = 0; a < 3; ++a)
  {
    for (int s : { -1, 1 })
    {
      int q[3] = { c[0], c[1], c[2] };
      q[a] += s;
      six[g.Id(q[0], q[1], q[2])] = 1;
    }
  }
  expected = BruteDistances(g, six, cap);
  Check(
    Worst(r.Distances, expected) <= Tolerance(cap) && r.Filter->GetLastNumberOfFeaturePoints() == 6,
    "OPACITY_GRADIENT, one bright voxel: its 6 face neighbours are the features, worst " +
      Str(Worst(r.Distances, expected)));

  // A step along each axis (0, then 0.5 at the plane, then 1): with eps 0.3 only the plane's
  // central differences (1/2) exceed it, its neighbours have 1/4, the faces 0.
  for (int axis = 0; axis < 3; ++axis)
  {
    std::vector<double> step(g.Size());
    for (vtkIdType p = 0; p < g.Size(); ++p)
    {
      int ijk[3];
      g.Index(p, ijk);
      step[p] = ijk[axis] < c[axis] ? 0.0 : ijk[axis] == c[axis] ? 0.5 : 1.0;
    }
    r = RunFilter(ToImage(g, step), ramp, vtkAdaptiveSamplingOracle::OPACITY_GRADIENT, 0.3);
    expected = expect([&](const int* p) { return std::abs(p[axis] - c[axis]) * g.Spacing[axis]; });
    Check(Worst(r.Distances, expected) <= Tolerance(cap),
      "OPACITY_GRADIENT, a step across axis " + std::to_string(axis) +
        ": the distance to its plane, worst " + Str(Worst(r.Distances, expected)));
    // OPACITY_RANGE sees the three planes around it (their neighbourhoods hold two values).
    r = RunFilter(ToImage(g, step), ramp, vtkAdaptiveSamplingOracle::OPACITY_RANGE, 0.3);
    expected = expect(
      [&](const int* p) { return std::max(std::abs(p[axis] - c[axis]) - 1, 0) * g.Spacing[axis]; });
    Check(Worst(r.Distances, expected) <= Tolerance(cap),
      "OPACITY_RANGE, a step across axis " + std::to_string(axis) +
        ": the distance to the slab of 3 planes, worst " + Str(Worst(r.Distances, expected)));
  }
}

//------------------------------------------------------------------------------
// Voxel values 10 and 20 alternating, an opacity spike at 15 only: alpha is 0 at every voxel,
// so the paper's test finds nothing, while every trilinear cell crosses the spike.
void TestSpike()
{
  const Grid g{ { 12, 9, 7 }, { 1.0, 0.8, 1.5 } };
  std::vector<double> values(g.Size());
  for (vtkIdType p = 0; p < g.Size(); ++p)
  {
    int ijk[3];
    g.Index(p, ijk);
    values[p] = (ijk[0] + ijk[1] + ijk[2]) % 2 ? 20.0 : 10.0;
  }
  vtkNew<vtkPiecewiseFunction> spike;
  spike->AddPoint(0.0, 0.0);
  spike->AddPoint(14.0, 0.0);
  spike->AddPoint(15.0, 1.0);
  spike->AddPoint(16.0, 0.0);
  spike->AddPoint(255.0, 0.0);
  const double cap = 8.0 * 0.8;
  Run r = RunFilter(ToImage<vtkUnsignedCharArray>(g, values),
    spike,
    vtkAdaptiveSamplingOracle::OPACITY_GRADIENT,
    0.002);
  Check(Worst(r.Distances, std::vector<double>(g.Size(), Capped(cap))) == 0.0 &&
      r.Filter->GetLastNumberOfFeaturePoints() == 0,
    "spike: OPACITY_GRADIENT sees no feature (the cap everywhere)");
  r = RunFilter(ToImage<vtkUnsignedCharArray>(g, values),
    spike,
    vtkAdaptiveSamplingOracle::OPACITY_RANGE,
    0.002);
  Check(Worst(r.Distances, std::vector<double>(g.Size(), 0.0)) == 0.0 &&
      r.Filter->GetLastNumberOfFeaturePoints() == g.Size(),
    "spike: OPACITY_RANGE sees features everywhere (0 everywhere)");
  // A spike between the values of no cell (at 25) is seen by neither.
  spike->RemoveAllPoints();
  spike->AddPoint(24.0, 0.0);
  spike->AddPoint(25.0, 1.0);
  spike->AddPoint(26.0, 0.0);
  r.Filter->Update();
  Check(Worst(Oracle(r.Filter->GetOutput()), std::vector<double>(g.Size(), Capped(cap))) == 0.0,
    "a spike outside the data's cells: the cap everywhere");
}

//------------------------------------------------------------------------------
void TestExtremes()
{
  const Grid g{ { 10, 8, 6 }, { 0.3, 0.6, 0.9 } };
  std::vector<double> random(g.Size());
  for (vtkIdType p = 0; p < g.Size(); ++p)
  {
    random[p] = 100.0 * Hash(static_cast<uint32_t>(p) * 2654435761U + 5U);
  }
  auto ramp = Ramp(0.0, 100.0);
  const double cap = 8.0 * 0.3;
  for (int mode : { vtkAdaptiveSamplingOracle::MIN, vtkAdaptiveSamplingOracle::MAX })
  {
    const bool min = mode == vtkAdaptiveSamplingOracle::MIN;
    const std::vector<double> all(g.Size(), min ? 0.0 : Capped(cap));
    Run r = RunFilter(ToImage(g, random), ramp, mode, 0.002);
    Check(
      Worst(r.Distances, all) == 0.0, std::string(min ? "MIN: 0" : "MAX: the cap") + " everywhere");
    // Neither reads the transfer function.
    r = RunFilter(ToImage(g, random), nullptr, mode, 0.002);
    Check(Worst(r.Distances, all) == 0.0,
      std::string(min ? "MIN" : "MAX") + " without a transfer function");
  }
  Run r = RunFilter(ToImage(g, random), ramp, vtkAdaptiveSamplingOracle::MAX, 0.002, 3.5);
  Check(Worst(r.Distances, std::vector<double>(g.Size(), 3.5)) == 0.0 &&
      r.Filter->GetLastMaximumDistance() == 3.5,
    "MAX with MaximumDistance 3.5 (automatic off): 3.5 everywhere");

  // A constant volume: no neighbourhood spans two values, no difference is non-zero.
  for (int mode :
    { vtkAdaptiveSamplingOracle::OPACITY_RANGE, vtkAdaptiveSamplingOracle::OPACITY_GRADIENT })
  {
    r = RunFilter(ToImage(g, std::vector<double>(g.Size(), 42.0)), ramp, mode, 0.0);
    Check(Worst(r.Distances, std::vector<double>(g.Size(), Capped(cap))) == 0.0 &&
        r.Filter->GetLastNumberOfFeaturePoints() == 0,
      std::string("a constant volume, ") + r.Filter->GetModeAsString() +
        ", eps 0: the cap everywhere");
  }
  // A constant opacity: nothing changes, whatever the data.
  vtkNew<vtkPiecewiseFunction> flat;
  flat->AddPoint(0.0, 0.3);
  flat->AddPoint(100.0, 0.3);
  for (int mode :
    { vtkAdaptiveSamplingOracle::OPACITY_RANGE, vtkAdaptiveSamplingOracle::OPACITY_GRADIENT })
  {
    r = RunFilter(ToImage(g, random), flat, mode, 0.0);
    Check(Worst(r.Distances, std::vector<double>(g.Size(), Capped(cap))) == 0.0,
      std::string("a constant opacity, ") + r.Filter->GetModeAsString() +
        ": no feature, the cap everywhere");
    // With a ramp every point of random data is a feature.
    r = RunFilter(ToImage(g, random), ramp, mode, 0.0);
    Check(r.Filter->GetLastNumberOfFeaturePoints() == g.Size() &&
        Worst(r.Distances, std::vector<double>(g.Size(), 0.0)) == 0.0,
      std::string("random data under a ramp, ") + r.Filter->GetModeAsString() +
        ", eps 0: 0 everywhere");
  }
  // An opacity change just below and just above eps.
  std::vector<double> two(g.Size(), 0.0);
  for (vtkIdType p = 0; p < g.Size(); p += 2)
  {
    two[p] = 1.0;
  }
  vtkNew<vtkPiecewiseFunction> small;
  small->AddPoint(0.0, 0.0);
  small->AddPoint(1.0, 0.01);
  r = RunFilter(ToImage(g, two), small, vtkAdaptiveSamplingOracle::OPACITY_RANGE, 0.0099);
  Check(r.Filter->GetLastNumberOfFeaturePoints() == g.Size(), "a change of 0.01 > eps 0.0099");
  r = RunFilter(ToImage(g, two), small, vtkAdaptiveSamplingOracle::OPACITY_RANGE, 0.01);
  Check(r.Filter->GetLastNumberOfFeaturePoints() == 0, "a change of 0.01 is not > eps 0.01");
}

//------------------------------------------------------------------------------
// Random volumes and transfer functions against the brute-force specification.
std::vector<vtkSmartPointer<vtkPiecewiseFunction>> TransferFunctions()
{
  std::vector<vtkSmartPointer<vtkPiecewiseFunction>> out;
  out.push_back(Ramp(20.0, 80.0));
  auto peaks = vtkSmartPointer<vtkPiecewiseFunction>::New();
  peaks->AddPoint(10.0, 0.0);
  peaks->AddPoint(30.0, 0.8, 0.3, 0.0);
  peaks->AddPoint(31.0, 0.1, 0.5, 0.7); // Hermite curve
  peaks->AddPoint(55.5, 0.6, 0.9, 1.0); // a step
  peaks->AddPoint(70.0, 0.05, 0.5, 0.3);
  peaks->AddPoint(90.0, 0.9);
  out.push_back(peaks);
  auto unclamped = vtkSmartPointer<vtkPiecewiseFunction>::New();
  unclamped->ClampingOff();
  unclamped->AddPoint(25.0, 0.4);
  unclamped->AddPoint(60.0, 0.7, 0.2, 0.5);
  unclamped->AddPoint(75.0, 0.3);
  out.push_back(unclamped);
  auto duplicates = vtkSmartPointer<vtkPiecewiseFunction>::New();
  duplicates->AllowDuplicateScalarsOn();
  duplicates->AddPoint(0.0, 0.0);
  duplicates->AddPoint(40.0, 0.0);
  duplicates->AddPoint(40.0, 0.7);
  duplicates->AddPoint(65.0, 0.2);
  duplicates->AddPoint(65.0, 0.0);
  out.push_back(duplicates);
  auto logScale = vtkSmartPointer<vtkPiecewiseFunction>::New();
  logScale->UseLogScaleOn();
  logScale->AddPoint(1.0, 0.0);
  logScale->AddPoint(10.0, 0.5, 0.4, 0.2);
  logScale->AddPoint(100.0, 1.0);
  out.push_back(logScale);
  return out;
}

// The reasoning behind the exact range test: between two nodes the function is monotonic (to
// rounding: VTK's Hermite sum may step back by an ulp near a node).
void TestMonotonicBetweenNodes()
{
  for (const auto& tf : TransferFunctions())
  {
    bool monotonic = true;
    for (int n = 0; n + 1 < tf->GetSize(); ++n)
    {
      double a[4], b[4];
      tf->GetNodeValue(n, a);
      tf->GetNodeValue(n + 1, b);
      int rising = 0, falling = 0;
      double previous = tf->GetValue(a[0] + 1e-9 * (b[0] - a[0]));
      for (int s = 1; s <= 2000; ++s)
      {
        const double v = tf->GetValue(a[0] + (b[0] - a[0]) * s / 2000.0);
        rising += v > previous + 1e-12 ? 1 : 0;
        falling += v < previous - 1e-12 ? 1 : 0;
        previous = v;
      }
      monotonic = monotonic && !(rising && falling);
    }
    Check(monotonic, "the transfer function is monotonic between its nodes");
  }
}

template <typename ArrayT>
void CompareWithSpecification(const Grid& g,
  const std::vector<double>& values,
  vtkPiecewiseFunction* tf,
  double eps,
  const std::string& label)
{
  const double smallest = std::min(g.Spacing[0], std::min(g.Spacing[1], g.Spacing[2]));
  const double cap = 8.0 * smallest;
  for (int mode :
    { vtkAdaptiveSamplingOracle::OPACITY_GRADIENT, vtkAdaptiveSamplingOracle::OPACITY_RANGE })
  {
    const std::vector<unsigned char> mask = mode == vtkAdaptiveSamplingOracle::OPACITY_GRADIENT
      ? GradientFeatures(g, values, tf, eps)
      : RangeFeatures(g, values, tf, eps);
    const std::vector<double> expected = BruteDistances(g, mask, cap);
    Run r = RunFilter(ToImage<ArrayT>(g, values), tf, mode, eps);
    const std::string what = label + ", " + r.Filter->GetModeAsString() + ", eps " + Str(eps);
    Check(r.Filter->GetLastNumberOfFeaturePoints() == Count(mask),
      what + ": " + std::to_string(Count(mask)) + " feature points (got " +
        std::to_string(r.Filter->GetLastNumberOfFeaturePoints()) + ")");
    Check(Worst(r.Distances, expected) <= Tolerance(cap),
      what + ": equals the specification, worst " + Str(Worst(r.Distances, expected)));
  }
}

void TestSpecification()
{
  const auto tfs = TransferFunctions();
  uint32_t seed = 11;
  for (const auto& dims : std::vector<std::array<int, 3>>{ { 13, 11, 9 }, { 17, 6, 1 } })
  {
    const Grid g{ { dims[0], dims[1], dims[2] }, { 0.9, 0.6, 1.4 } };
    // Smooth waves plus noise over 0..100, so that some cells cross nodes and some do not.
    std::vector<double> values(g.Size());
    for (vtkIdType p = 0; p < g.Size(); ++p)
    {
      int ijk[3];
      g.Index(p, ijk);
      values[p] =
        std::round(50.0 + 35.0 * std::sin(0.5 * ijk[0] + 0.3 * ijk[1]) * std::cos(0.4 * ijk[2]) +
          12.0 * Hash(seed + static_cast<uint32_t>(p) * 2654435761U));
    }
    ++seed;
    for (size_t t = 0; t < tfs.size(); ++t)
    {
      for (double eps : { 0.0, 0.0123, 0.071, 0.31 })
      {
        const std::string label = std::to_string(dims[0]) + " x " + std::to_string(dims[1]) +
          " x " + std::to_string(dims[2]) + ", transfer function " + std::to_string(t);
        CompareWithSpecification<vtkDoubleArray>(g, values, tfs[t], eps, label);
      }
    }
    // Every input type gives the same (the values are integers in 0..127).
    CompareWithSpecification<vtkUnsignedCharArray>(g, values, tfs[1], 0.0123, "unsigned char");
    CompareWithSpecification<vtkCharArray>(g, values, tfs[1], 0.0123, "char");
    CompareWithSpecification<vtkShortArray>(g, values, tfs[1], 0.0123, "short");
    CompareWithSpecification<vtkUnsignedShortArray>(g, values, tfs[1], 0.0123, "unsigned short");
    CompareWithSpecification<vtkIntArray>(g, values, tfs[1], 0.0123, "int");
    CompareWithSpecification<vtkLongLongArray>(g, values, tfs[1], 0.0123, "long long");
    CompareWithSpecification<vtkFloatArray>(g, values, tfs[1], 0.0123, "float");
    CompareWithSpecification<vtkSOADataArrayTemplate<float>>(
      g, values, tfs[1], 0.0123, "float SOA");

    // NaN values: transparent, they make features where a neighbour is opaque.
    std::vector<double> holes = values;
    for (vtkIdType p = 0; p < g.Size(); p += 7)
    {
      holes[p] = NaN;
    }
    CompareWithSpecification<vtkDoubleArray>(g, holes, tfs[0], 0.0123, "NaN every 7th point");
    CompareWithSpecification<vtkFloatArray>(g, holes, tfs[1], 0.0123, "float, NaN every 7th");
    std::vector<double> allNaN(g.Size(), NaN);
    CompareWithSpecification<vtkDoubleArray>(g, allNaN, tfs[0], 0.0, "all NaN");
    // Infinite values take the function's ends.
    std::vector<double> infinite = values;
    infinite[3] = Inf;
    infinite[g.Size() / 2] = -Inf;
    CompareWithSpecification<vtkDoubleArray>(g, infinite, tfs[1], 0.0123, "+-Inf values");
    CompareWithSpecification<vtkDoubleArray>(g, infinite, tfs[2], 0.0123, "+-Inf, no clamping");
  }
  // A bit array (through the vtkDataArray interface): the features of a 0/1 volume.
  const Grid g{ { 9, 8, 7 }, { 1.0, 1.0, 1.0 } };
  std::vector<double> bits(g.Size(), 0.0);
  bits[g.Id(4, 4, 3)] = 1.0;
  CompareWithSpecification<vtkBitArray>(g, bits, Ramp(0.0, 1.0), 0.002, "bit array");
}

//------------------------------------------------------------------------------
// Away from the faces OPACITY_RANGE finds every feature OPACITY_GRADIENT finds: with constant
// faces (where the one-sided differences could exceed the range) its distances are never larger.
void TestRangeCoversGradient()
{
  const Grid g{ { 16, 14, 12 }, { 0.5, 0.7, 0.6 } };
  std::vector<double> values(g.Size(), 0.0);
  for (vtkIdType p = 0; p < g.Size(); ++p)
  {
    int ijk[3];
    g.Index(p, ijk);
    const bool inner = ijk[0] > 1 && ijk[1] > 1 && ijk[2] > 1 && ijk[0] < g.N[0] - 2 &&
      ijk[1] < g.N[1] - 2 && ijk[2] < g.N[2] - 2;
    values[p] = inner ? 100.0 * Hash(static_cast<uint32_t>(p) * 2246822519U + 3U) : 0.0;
  }
  for (const auto& tf : TransferFunctions())
  {
    for (double eps : { 0.002, 0.05, 0.2 })
    {
      Run gradient =
        RunFilter(ToImage(g, values), tf, vtkAdaptiveSamplingOracle::OPACITY_GRADIENT, eps);
      Run range = RunFilter(ToImage(g, values), tf, vtkAdaptiveSamplingOracle::OPACITY_RANGE, eps);
      bool covered = gradient.Distances.size() == range.Distances.size();
      for (size_t p = 0; covered && p < range.Distances.size(); ++p)
      {
        covered = range.Distances[p] <= gradient.Distances[p];
      }
      Check(covered &&
          range.Filter->GetLastNumberOfFeaturePoints() >=
            gradient.Filter->GetLastNumberOfFeaturePoints(),
        "OPACITY_RANGE distances <= OPACITY_GRADIENT distances, eps " + Str(eps));
    }
  }
}

//------------------------------------------------------------------------------
// The smin/smax volumes are kept across transfer-function and setting edits and recomputed
// when the input changes.
void TestRangeCache()
{
  const Grid g{ { 15, 12, 10 }, { 1.0, 1.0, 1.0 } };
  std::vector<double> values(g.Size());
  for (vtkIdType p = 0; p < g.Size(); ++p)
  {
    values[p] = 100.0 * Hash(static_cast<uint32_t>(p) * 2654435761U + 17U);
  }
  auto image = ToImage<vtkFloatArray>(g, values);
  vtkNew<vtkPiecewiseFunction> tf;
  tf->AddPoint(0.0, 0.0);
  tf->AddPoint(30.0, 0.0);
  tf->AddPoint(31.0, 1.0);
  tf->AddPoint(100.0, 1.0);
  vtkNew<vtkAdaptiveSamplingOracle> filter;
  filter->SetInputData(image);
  filter->SetScalarOpacity(tf);
  filter->Update();
  Check(filter->GetLastRecomputedRanges(), "the first update computes the ranges");
  const vtkIdType first = filter->GetLastNumberOfFeaturePoints();

  // A transfer-function edit: a new mask and new distances from the same ranges.
  tf->AddPoint(31.0, 0.0);
  tf->AddPoint(60.0, 0.0);
  tf->AddPoint(61.0, 1.0);
  filter->Update();
  Check(!filter->GetLastRecomputedRanges(), "a transfer-function edit reuses the ranges");
  std::vector<double> mine = Oracle(filter->GetOutput());
  Run fresh = RunFilter(image, tf, vtkAdaptiveSamplingOracle::OPACITY_RANGE, 0.002);
  Check(filter->GetLastNumberOfFeaturePoints() != first && Worst(mine, fresh.Distances) == 0.0,
    "and gives what a new filter gives with the edited function");
  Check(fresh.Filter->GetLastRecomputedRanges(), "(which computes its own ranges)");
  filter->SetEpsilon(0.5);
  filter->Update();
  Check(!filter->GetLastRecomputedRanges(), "an Epsilon edit reuses the ranges");
  filter->SetAutomaticMaximumDistance(false);
  filter->SetMaximumDistance(2.0);
  filter->Update();
  Check(!filter->GetLastRecomputedRanges() && filter->GetLastMaximumDistance() == 2.0,
    "a cap edit reuses the ranges");

  // The input array's values changed (and said so): recomputed.
  vtkDataArray* scalars = image->GetPointData()->GetScalars();
  scalars->SetComponent(0, 0, 55.0);
  scalars->Modified();
  filter->Update();
  Check(filter->GetLastRecomputedRanges(), "modified input values recompute the ranges");
  filter->Modified();
  filter->Update();
  Check(!filter->GetLastRecomputedRanges(), "and the next update reuses them");
  // Another array, then another image.
  vtkNew<vtkFloatArray> other;
  other->DeepCopy(scalars);
  other->SetName("other");
  image->GetPointData()->AddArray(other);
  filter->SetInputArrayToProcess(0, 0, 0, vtkDataObject::FIELD_ASSOCIATION_POINTS, "other");
  filter->Update();
  Check(filter->GetLastRecomputedRanges(), "another input array recomputes the ranges");
  filter->SetInputData(ToImage<vtkFloatArray>(g, values, "other"));
  filter->Update();
  Check(filter->GetLastRecomputedRanges(), "another input image recomputes the ranges");
  // Another mode releases them; back in OPACITY_RANGE they are computed again.
  filter->SetModeToOpacityGradient();
  filter->Update();
  Check(!filter->GetLastRecomputedRanges(), "OPACITY_GRADIENT computes no ranges");
  filter->SetModeToOpacityRange();
  filter->Update();
  Check(filter->GetLastRecomputedRanges(), "back in OPACITY_RANGE: computed again");

  // Through a pipeline: a producer's new output recomputes, a transfer-function edit does not.
  vtkNew<vtkTrivialProducer> producer;
  producer->SetOutput(image);
  vtkNew<vtkAdaptiveSamplingOracle> piped;
  piped->SetInputConnection(producer->GetOutputPort());
  piped->SetScalarOpacity(tf);
  piped->Update();
  Check(piped->GetLastRecomputedRanges(), "pipeline: the first update computes the ranges");
  tf->AddPoint(80.0, 0.2);
  piped->Update();
  Check(!piped->GetLastRecomputedRanges(), "pipeline: a transfer-function edit reuses them");
  image->GetPointData()->GetScalars()->SetComponent(1, 0, 3.0);
  image->Modified();
  piped->Update();
  Check(piped->GetLastRecomputedRanges(), "pipeline: a modified input image recomputes them");
}

//------------------------------------------------------------------------------
void TestPieces()
{
  const Grid g{ { 21, 19, 17 }, { 0.5, 0.5, 0.5 } };
  std::vector<double> values(g.Size());
  for (vtkIdType p = 0; p < g.Size(); ++p)
  {
    values[p] = 100.0 * Hash(static_cast<uint32_t>(p) * 2654435761U + 23U);
  }
  vtkNew<vtkPiecewiseFunction> tf;
  tf->AddPoint(0.0, 0.0);
  tf->AddPoint(97.0, 0.0);
  tf->AddPoint(100.0, 1.0);
  vtkNew<vtkTrivialProducer> producer;
  producer->SetOutput(ToImage(g, values));
  vtkNew<vtkAdaptiveSamplingOracle> filter;
  filter->SetInputConnection(producer->GetOutputPort());
  filter->SetScalarOpacity(tf);
  filter->Update();
  vtkNew<vtkImageData> whole;
  whole->DeepCopy(filter->GetOutput());
  const std::vector<double> all = Oracle(whole);
  Check(Worst(all, std::vector<double>(all.size(), 0.0)) > 0.5,
    "a sparse transfer function: distances beyond a voxel");
  auto compare = [&](vtkImageData* out, const std::string& label)
  {
    int extent[6];
    out->GetExtent(extent);
    const std::vector<double> part = Oracle(out);
    bool ok = !part.empty() && out->GetNumberOfPoints() < whole->GetNumberOfPoints();
    double worst = 0.0;
    for (int k = extent[4]; ok && k <= extent[5]; ++k)
    {
      for (int j = extent[2]; j <= extent[3]; ++j)
      {
        for (int i = extent[0]; i <= extent[1]; ++i)
        {
          int ijk[3] = { i, j, k };
          worst = std::max(
            worst, std::abs(part[out->ComputePointId(ijk)] - all[whole->ComputePointId(ijk)]));
        }
      }
    }
    Check(ok && worst == 0.0,
      label + ": a part of the grid with the whole volume's distances (" +
        std::to_string(out->GetNumberOfPoints()) + " points, extent " + std::to_string(extent[0]) +
        ".." + std::to_string(extent[1]) + " x " + std::to_string(extent[2]) + ".." +
        std::to_string(extent[3]) + " x " + std::to_string(extent[4]) + ".." +
        std::to_string(extent[5]) + ", worst " + Str(worst) + ")");
  };
  for (int ghosts : { 0, 1 })
  {
    for (int piece = 0; piece < 3; ++piece)
    {
      filter->UpdatePiece(piece, 3, ghosts);
      compare(filter->GetOutput(),
        "piece " + std::to_string(piece) + " of 3, " + std::to_string(ghosts) + " ghost levels");
    }
  }
  vtkNew<vtkAdaptiveSamplingOracle> sub;
  sub->SetInputConnection(producer->GetOutputPort());
  sub->SetScalarOpacity(tf);
  int extent[6] = { 3, 10, 0, 9, 4, 12 };
  sub->UpdateExtent(extent);
  int got[6];
  sub->GetOutput()->GetExtent(got);
  Check(std::equal(got, got + 6, extent), "a sub-extent request gives that extent");
  compare(sub->GetOutput(), "extent 3..10 x 0..9 x 4..12");
}

//------------------------------------------------------------------------------
void TestProgressAndAbort()
{
  const Grid g{ { 40, 40, 40 }, { 1.0, 1.0, 1.0 } };
  std::vector<double> values(g.Size());
  for (vtkIdType p = 0; p < g.Size(); ++p)
  {
    values[p] = 100.0 * Hash(static_cast<uint32_t>(p) * 2654435761U + 29U);
  }
  vtkNew<vtkPiecewiseFunction> tf;
  tf->AddPoint(0.0, 0.0);
  tf->AddPoint(95.0, 0.0);
  tf->AddPoint(100.0, 1.0);
  vtkNew<vtkAdaptiveSamplingOracle> filter;
  filter->SetInputData(ToImage(g, values));
  filter->SetScalarOpacity(tf);
  vtkNew<ProgressRecorder> progress;
  filter->AddObserver(vtkCommand::ProgressEvent, progress);
  filter->Update();
  std::vector<double>& p = progress->Values;
  Check(p.size() >= 30 && std::is_sorted(p.begin(), p.end()) && p.back() == 1.0,
    "progress events rise to 1 (" + std::to_string(p.size()) + " events)");
  Check(
    filter->GetOutput()->GetPointData()->GetArray("OracleDistance") != nullptr, "distances made");

  p.clear();
  tf->AddPoint(50.0, 0.1); // only the mask and the distances
  filter->Update();
  Check(p.size() >= 20 && std::is_sorted(p.begin(), p.end()) && p.back() == 1.0,
    "after a transfer-function edit, progress rises to 1 as well (" + std::to_string(p.size()) +
      " events)");

  // An abort while the ranges are computed: no distances, and the half-made ranges dropped.
  p.clear();
  progress->AbortOnFirst = true;
  filter->SetInputData(ToImage(g, values));
  filter->Update();
  Check(p.size() <= 3 &&
      filter->GetOutput()->GetPointData()->GetArray("OracleDistance") == nullptr &&
      filter->GetOutput()->GetPointData()->GetScalars() != nullptr,
    "an abort request stops the filter at the next chunk, the input passed through without "
    "distances");
  progress->AbortOnFirst = false;
  filter->Modified();
  filter->Update();
  Check(filter->GetOutput()->GetPointData()->GetArray("OracleDistance") != nullptr &&
      filter->GetLastRecomputedRanges(),
    "the next update runs in full and computes the ranges");
}

//------------------------------------------------------------------------------
// Each bad input or setting: an error through the observers, an empty output, no crash; and a
// good input afterwards works again.
void TestBadInput()
{
  const Grid g{ { 5, 4, 3 }, { 1.0, 1.0, 1.0 } };
  std::vector<double> values(g.Size());
  for (vtkIdType p = 0; p < g.Size(); ++p)
  {
    values[p] = static_cast<double>(p);
  }
  auto ramp = Ramp(0.0, 60.0);
  struct Case
  {
    std::string What;
    std::string Message; // a part of the expected error
    std::function<vtkSmartPointer<vtkImageData>()> Input;
    std::function<void(vtkAdaptiveSamplingOracle*)> Settings;
  };
  auto goodImage = [&]() { return ToImage(g, values); };
  auto none = [](vtkAdaptiveSamplingOracle*) {};
  std::vector<Case> cases = {
    { "no transfer function",
      "No ScalarOpacity",
      goodImage,
      [](vtkAdaptiveSamplingOracle* f) { f->SetScalarOpacity(nullptr); } },
    { "no transfer function (OPACITY_GRADIENT)",
      "No ScalarOpacity",
      goodImage,
      [](vtkAdaptiveSamplingOracle* f)
      {
        f->SetScalarOpacity(nullptr);
        f->SetModeToOpacityGradient();
      } },
    { "a transfer function without points",
      "no points",
      goodImage,
      [](vtkAdaptiveSamplingOracle* f)
      {
        vtkNew<vtkPiecewiseFunction> empty;
        f->SetScalarOpacity(empty);
      } },
    { "no scalars",
      "no point array",
      [&]()
      {
        auto image = vtkSmartPointer<vtkImageData>::New();
        image->SetDimensions(5, 4, 3);
        return image;
      },
      none },
    { "3 components",
      "3 components",
      [&]()
      {
        auto image = ToImage(g, values);
        vtkNew<vtkDoubleArray> rgb;
        rgb->SetNumberOfComponents(3);
        rgb->SetNumberOfTuples(g.Size());
        rgb->Fill(1.0);
        rgb->SetName("rgb");
        image->GetPointData()->SetScalars(rgb);
        return image;
      },
      none },
    { "a cell array",
      "not a point array",
      [&]()
      {
        auto image = ToImage(g, values);
        vtkNew<vtkDoubleArray> cells;
        cells->SetName("cells");
        cells->SetNumberOfTuples(image->GetNumberOfCells());
        cells->Fill(1.0);
        image->GetCellData()->AddArray(cells);
        return image;
      },
      [](vtkAdaptiveSamplingOracle* f)
      { f->SetInputArrayToProcess(0, 0, 0, vtkDataObject::FIELD_ASSOCIATION_CELLS, "cells"); } },
    { "a missing array name",
      "no point array",
      goodImage,
      [](vtkAdaptiveSamplingOracle* f)
      { f->SetInputArrayToProcess(0, 0, 0, vtkDataObject::FIELD_ASSOCIATION_POINTS, "nothing"); } },
    { "too few values",
      "values for the",
      [&]()
      {
        auto image = ToImage(g, values);
        image->GetPointData()->GetScalars()->SetNumberOfTuples(g.Size() - 7);
        return image;
      },
      none },
    { "zero spacing",
      "spacing",
      [&]()
      {
        auto image = ToImage(g, values);
        image->SetSpacing(1, 0, 1);
        return image;
      },
      none },
    { "NaN spacing",
      "spacing",
      [&]()
      {
        auto image = ToImage(g, values);
        image->SetSpacing(1, 1, NaN);
        return image;
      },
      none },
    { "spacings 1 and 1e30",
      "differ too much",
      [&]()
      {
        auto image = ToImage(g, values);
        image->SetSpacing(1, 1e30, 1);
        return image;
      },
      none },
    { "Epsilon -0.001",
      "Epsilon",
      goodImage,
      [](vtkAdaptiveSamplingOracle* f) { f->SetEpsilon(-0.001); } },
    { "Epsilon NaN",
      "Epsilon",
      goodImage,
      [](vtkAdaptiveSamplingOracle* f) { f->SetEpsilon(NaN); } },
    { "Epsilon Inf",
      "Epsilon",
      goodImage,
      [](vtkAdaptiveSamplingOracle* f) { f->SetEpsilon(Inf); } },
    { "MaximumDistance 0",
      "maximum distance",
      goodImage,
      [](vtkAdaptiveSamplingOracle* f)
      {
        f->AutomaticMaximumDistanceOff();
        f->SetMaximumDistance(0.0);
      } },
    { "MaximumDistance -2",
      "maximum distance",
      goodImage,
      [](vtkAdaptiveSamplingOracle* f)
      {
        f->AutomaticMaximumDistanceOff();
        f->SetMaximumDistance(-2.0);
      } },
    { "MaximumDistance NaN (MAX)",
      "maximum distance",
      goodImage,
      [](vtkAdaptiveSamplingOracle* f)
      {
        f->SetModeToMax();
        f->AutomaticMaximumDistanceOff();
        f->SetMaximumDistance(NaN);
      } },
    { "MaximumDistance Inf (MIN)",
      "maximum distance",
      goodImage,
      [](vtkAdaptiveSamplingOracle* f)
      {
        f->SetModeToMin();
        f->AutomaticMaximumDistanceOff();
        f->SetMaximumDistance(Inf);
      } },
    { "MaximumDistance 1e300 (beyond a float)",
      "maximum distance",
      goodImage,
      [](vtkAdaptiveSamplingOracle* f)
      {
        f->SetModeToMax();
        f->AutomaticMaximumDistanceOff();
        f->SetMaximumDistance(1e300);
      } },
    { "empty OutputArrayName",
      "OutputArrayName",
      goodImage,
      [](vtkAdaptiveSamplingOracle* f) { f->SetOutputArrayName(""); } },
    { "null OutputArrayName",
      "OutputArrayName",
      goodImage,
      [](vtkAdaptiveSamplingOracle* f) { f->SetOutputArrayName(nullptr); } },
    { "OutputArrayName = the input's name",
      "input array's name",
      goodImage,
      [](vtkAdaptiveSamplingOracle* f) { f->SetOutputArrayName("scalars"); } },
    { "an empty image",
      "empty",
      [&]()
      {
        auto image = vtkSmartPointer<vtkImageData>::New();
        vtkNew<vtkDoubleArray> scalars;
        scalars->SetName("scalars");
        image->GetPointData()->SetScalars(scalars);
        return image;
      },
      none },
  };
  for (const Case& c : cases)
  {
    vtkNew<vtkAdaptiveSamplingOracle> filter;
    vtkNew<vtkTest::ErrorObserver> errors;
    filter->AddObserver(vtkCommand::ErrorEvent, errors);
    filter->GetExecutive()->AddObserver(vtkCommand::ErrorEvent, errors);
    filter->SetScalarOpacity(ramp);
    auto input = c.Input();
    filter->SetInputData(input);
    c.Settings(filter);
    filter->Update();
    const bool reported =
      errors->GetError() && errors->GetErrorMessage().find(c.Message) != std::string::npos;
    Check(reported,
      c.What + ": reported (" +
        (errors->GetError() ? errors->GetErrorMessage() : std::string("no error")) + ")");
    Check(filter->GetOutput()->GetNumberOfPoints() == 0, c.What + ": empty output");
    // The same filter with a good input and settings works again.
    errors->Clear();
    filter->SetInputData(ToImage(g, values));
    filter->SetInputArrayToProcess(
      0, 0, 0, vtkDataObject::FIELD_ASSOCIATION_POINTS, vtkDataSetAttributes::SCALARS);
    filter->SetScalarOpacity(ramp);
    filter->SetModeToOpacityRange();
    filter->SetEpsilon(0.002);
    filter->AutomaticMaximumDistanceOn();
    filter->SetOutputArrayName("OracleDistance");
    filter->Update();
    Check(
      !errors->GetError() && Oracle(filter->GetOutput()).size() == static_cast<size_t>(g.Size()),
      c.What + ": the next good update works");
  }
}
}

int TestAdaptiveSamplingOracle(int, char*[])
{
  TestDefaults();
  TestHandMadeDistances();
  TestAgainstVTK();
  TestHandMadeFilter();
  TestSpike();
  TestExtremes();
  TestMonotonicBetweenNodes();
  TestSpecification();
  TestRangeCoversGradient();
  TestRangeCache();
  TestPieces();
  TestProgressAndAbort();
  TestBadInput();
  if (failures)
  {
    std::cerr << "TestAdaptiveSamplingOracle: " << failures << " checks failed\n";
    return 1;
  }
  return 0;
}
