// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
// vtkGradientExaggeration, N' = N + eps (N - N_m) of Guetat et al. 2010 (line 99 of the
// paper's text), against:
// - a brute-force reference written out here (gradient, zero mask, k^3 box mean truncated at
//   the borders, exaggeration) on random volumes, for both gradient methods and several eps
//   and k;
// - vtkImageGradient and vtkImageSobel3D, normalised, for eps = 0;
// - closed forms: a linear field keeps its normal everywhere, a crease sharpens by the angle
//   derived below;
// and its behaviour on zero gradients, 1-voxel-thick volumes, NaN and Inf, huge and tiny
// values, every input type, pieces, progress and abort, and bad input (an error and an empty
// output each).
#include "vtkCellData.h"
#include "vtkCommand.h"
#include "vtkDoubleArray.h"
#include "vtkExecutive.h"
#include "vtkFloatArray.h"
#include "vtkGradientExaggeration.h"
#include "vtkImageData.h"
#include "vtkImageGradient.h"
#include "vtkImageSobel3D.h"
#include "vtkMarschnerLobbSource.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkSOADataArrayTemplate.h"
#include "vtkShortArray.h"
#include "vtkSmartPointer.h"
#include "vtkTestErrorObserver.h"
#include "vtkUnsignedCharArray.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <functional>
#include <iostream>
#include <limits>
#include <sstream>
#include <string>
#include <type_traits>
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

using Vec = std::array<double, 3>;
const double NaN = std::numeric_limits<double>::quiet_NaN();

double Dot(const Vec& a, const Vec& b)
{
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}
double Norm(const Vec& a)
{
  return std::sqrt(Dot(a, a));
}
Vec Unit(const Vec& a)
{
  const double n = Norm(a);
  return n > 0.0 ? Vec{ a[0] / n, a[1] / n, a[2] / n } : Vec{ 0, 0, 0 };
}
double Distance(const Vec& a, const Vec& b)
{
  return Norm(Vec{ a[0] - b[0], a[1] - b[1], a[2] - b[2] });
}
double Angle(const Vec& a, const Vec& b)
{
  return std::acos(std::min(1.0, std::max(-1.0, Dot(Unit(a), Unit(b)))));
}

// A volume as the test sees it: values indexed i + nx (j + ny k).
struct Volume
{
  int N[3];
  double Spacing[3];
  double Origin[3];
  std::vector<double> Values;
  vtkIdType Id(int i, int j, int k) const
  {
    return i + N[0] * (j + static_cast<vtkIdType>(N[1]) * k);
  }
  double At(int i, int j, int k) const { return Values[Id(i, j, k)]; }
  vtkIdType Size() const { return static_cast<vtkIdType>(N[0]) * N[1] * N[2]; }
};

Volume MakeVolume(const int n[3],
  const double spacing[3],
  const double origin[3],
  const std::function<double(double, double, double)>& f)
{
  Volume v;
  std::copy(n, n + 3, v.N);
  std::copy(spacing, spacing + 3, v.Spacing);
  std::copy(origin, origin + 3, v.Origin);
  v.Values.resize(v.Size());
  for (int k = 0; k < n[2]; ++k)
  {
    for (int j = 0; j < n[1]; ++j)
    {
      for (int i = 0; i < n[0]; ++i)
      {
        v.Values[v.Id(i, j, k)] =
          f(origin[0] + i * spacing[0], origin[1] + j * spacing[1], origin[2] + k * spacing[2]);
      }
    }
  }
  return v;
}

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

// A rough volume: smooth waves plus noise, so that normals vary from voxel to voxel.
Volume RandomVolume(const int n[3], const double spacing[3], uint32_t seed)
{
  const double origin[3] = { 0.3, -0.2, 0.1 };
  Volume v = MakeVolume(n,
    spacing,
    origin,
    [](double x, double y, double z) { return std::sin(1.3 * x) + std::cos(0.7 * y + 0.4 * z); });
  for (vtkIdType p = 0; p < v.Size(); ++p)
  {
    v.Values[p] += 0.6 * Hash(seed + static_cast<uint32_t>(p) * 2654435761U);
  }
  return v;
}

template <typename ArrayT = vtkDoubleArray>
vtkSmartPointer<vtkImageData> ToImage(const Volume& v, const char* name = "scalars")
{
  auto image = vtkSmartPointer<vtkImageData>::New();
  image->SetDimensions(v.N[0], v.N[1], v.N[2]);
  image->SetSpacing(v.Spacing[0], v.Spacing[1], v.Spacing[2]);
  image->SetOrigin(v.Origin[0], v.Origin[1], v.Origin[2]);
  vtkNew<ArrayT> array;
  array->SetName(name);
  array->SetNumberOfComponents(1);
  array->SetNumberOfTuples(v.Size());
  for (vtkIdType p = 0; p < v.Size(); ++p)
  {
    array->SetComponent(p, 0, v.Values[p]);
  }
  image->GetPointData()->SetScalars(array);
  return image;
}

// The brute-force reference. Central differences: (v[p+1] - v[p-1]) / (2 h), one-sided
// (v[p+1] - v[p]) / h or (v[p] - v[p-1]) / h where a neighbour is outside the volume or NaN,
// 0 without either neighbour.
Vec CentralGradient(const Volume& v, int i, int j, int k)
{
  const int p[3] = { i, j, k };
  Vec g{ 0, 0, 0 };
  const double c = v.At(i, j, k);
  for (int a = 0; a < 3; ++a)
  {
    int lo[3] = { i, j, k }, hi[3] = { i, j, k };
    lo[a] -= 1;
    hi[a] += 1;
    const double left = p[a] > 0 ? v.At(lo[0], lo[1], lo[2]) : NaN;
    const double right = p[a] < v.N[a] - 1 ? v.At(hi[0], hi[1], hi[2]) : NaN;
    const bool l = std::isfinite(left), r = std::isfinite(right);
    const double h = v.Spacing[a];
    g[a] = l && r ? (right - left) / (2 * h) : r ? (right - c) / h : l ? (c - left) / h : 0.0;
  }
  return g;
}

// vtkImageSobel3D's operator (its source, VTK 9.1: weights 2, 1 and 0.586, transverse
// neighbours clamped to the volume, 0.060445 / spacing), with the difference along the axis
// doubled at the volume's faces (a one-sided difference over one spacing, not two).
Vec SobelGradient(const Volume& v, int i, int j, int k)
{
  const int p[3] = { i, j, k };
  Vec g{ 0, 0, 0 };
  for (int a = 0; a < 3; ++a)
  {
    const int b = (a + 1) % 3, c = (a + 2) % 3;
    double sum = 0.0;
    for (int ob = -1; ob <= 1; ++ob)
    {
      for (int oc = -1; oc <= 1; ++oc)
      {
        const double w = ob == 0 && oc == 0 ? 2.0 : ob == 0 || oc == 0 ? 1.0 : 0.586;
        int q[3];
        q[b] = std::min(std::max(p[b] + ob, 0), v.N[b] - 1);
        q[c] = std::min(std::max(p[c] + oc, 0), v.N[c] - 1);
        int lo[3] = { 0, 0, 0 }, hi[3] = { 0, 0, 0 };
        lo[b] = hi[b] = q[b];
        lo[c] = hi[c] = q[c];
        lo[a] = std::max(p[a] - 1, 0);
        hi[a] = std::min(p[a] + 1, v.N[a] - 1);
        const double scale = (hi[a] - lo[a] == 1) ? 2.0 : 1.0; // one-sided: twice
        sum += w * scale * (v.At(hi[0], hi[1], hi[2]) - v.At(lo[0], lo[1], lo[2]));
      }
    }
    g[a] = sum * 0.060445 / v.Spacing[a];
  }
  return g;
}

// The zero-gradient threshold of the class description: |G| * (smallest spacing) <=
// 1e-12 * (finite data range).
double GradientThreshold(const Volume& v)
{
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (double x : v.Values)
  {
    if (std::isfinite(x))
    {
      lo = std::min(lo, x);
      hi = std::max(hi, x);
    }
  }
  const double smallest =
    std::min(std::abs(v.Spacing[0]), std::min(std::abs(v.Spacing[1]), std::abs(v.Spacing[2])));
  return lo <= hi ? 1e-12 * (hi - lo) / smallest : 0.0;
}

struct Reference
{
  std::vector<Vec> Normals; // N
  std::vector<Vec> Sums;    // M
  std::vector<int> Counts;  // voxels in the truncated box
  std::vector<Vec> Output;  // N' / |N'|
};

Reference BruteForce(const Volume& v, bool sobel, double eps, int k)
{
  Reference ref;
  const vtkIdType n = v.Size();
  ref.Normals.resize(n);
  ref.Sums.assign(n, Vec{ 0, 0, 0 });
  ref.Counts.assign(n, 0);
  ref.Output.resize(n);
  const double threshold = GradientThreshold(v);
  for (int z = 0; z < v.N[2]; ++z)
  {
    for (int y = 0; y < v.N[1]; ++y)
    {
      for (int x = 0; x < v.N[0]; ++x)
      {
        Vec g = sobel ? SobelGradient(v, x, y, z) : CentralGradient(v, x, y, z);
        const bool keep = std::isfinite(v.At(x, y, z)) && Norm(g) > threshold;
        ref.Normals[v.Id(x, y, z)] = keep ? Unit(g) : Vec{ 0, 0, 0 };
      }
    }
  }
  const int r = k / 2;
  for (int z = 0; z < v.N[2]; ++z)
  {
    for (int y = 0; y < v.N[1]; ++y)
    {
      for (int x = 0; x < v.N[0]; ++x)
      {
        const vtkIdType id = v.Id(x, y, z);
        Vec& m = ref.Sums[id];
        for (int c = std::max(z - r, 0); c <= std::min(z + r, v.N[2] - 1); ++c)
        {
          for (int b = std::max(y - r, 0); b <= std::min(y + r, v.N[1] - 1); ++b)
          {
            for (int a = std::max(x - r, 0); a <= std::min(x + r, v.N[0] - 1); ++a)
            {
              const Vec& q = ref.Normals[v.Id(a, b, c)];
              m[0] += q[0];
              m[1] += q[1];
              m[2] += q[2];
              ++ref.Counts[id];
            }
          }
        }
        const Vec& nn = ref.Normals[id];
        if (Norm(nn) == 0.0)
        {
          ref.Output[id] = Vec{ 0, 0, 0 };
          continue;
        }
        const Vec mean = Norm(m) > 0.0 ? Unit(m) : nn;
        ref.Output[id] = Unit(Vec{ nn[0] + eps * (nn[0] - mean[0]),
          nn[1] + eps * (nn[1] - mean[1]),
          nn[2] + eps * (nn[2] - mean[2]) });
      }
    }
  }
  return ref;
}

std::vector<Vec> Normals(vtkImageData* image, const char* name = "ExaggeratedNormals")
{
  std::vector<Vec> out;
  vtkDataArray* array = image ? image->GetPointData()->GetArray(name) : nullptr;
  if (!array || array->GetNumberOfComponents() != 3)
  {
    return out;
  }
  out.resize(array->GetNumberOfTuples());
  for (vtkIdType p = 0; p < array->GetNumberOfTuples(); ++p)
  {
    array->GetTuple(p, out[p].data());
  }
  return out;
}

std::vector<Vec> Run(vtkImageData* image, int method, double eps, int k)
{
  vtkNew<vtkGradientExaggeration> filter;
  filter->SetInputData(image);
  filter->SetGradientMethod(method);
  filter->SetEpsilon(eps);
  filter->SetNeighborhoodSize(k);
  filter->Update();
  return Normals(filter->GetOutput());
}

// The largest distance to expected over all voxels, or infinity when sizes differ or an
// output is not finite.
double Worst(const std::vector<Vec>& got, const std::vector<Vec>& expected)
{
  if (got.size() != expected.size() || got.empty())
  {
    return std::numeric_limits<double>::infinity();
  }
  double worst = 0.0;
  for (size_t p = 0; p < got.size(); ++p)
  {
    const double d = Distance(got[p], expected[p]);
    worst = std::max(worst, std::isfinite(d) ? d : std::numeric_limits<double>::infinity());
  }
  return worst;
}

// Tolerance of the filter's float output: 2^-24 per component for the output and for each of
// the three box-sum passes; the box sum's error, relative to |M|, enters N_m and is multiplied
// by eps in N'. A factor of about 5 over that estimate.
double Tolerance(double eps, int count, double sumLength)
{
  return 2e-6 + eps * 1e-6 * count / std::max(sumLength, 1e-300);
}

void CheckAgainstBruteForce(const Volume& v,
  bool sobel,
  double eps,
  int k,
  const std::string& label)
{
  const Reference ref = BruteForce(v, sobel, eps, k);
  const std::vector<Vec> got = Run(ToImage(v),
    sobel ? vtkGradientExaggeration::SOBEL : vtkGradientExaggeration::CENTRAL_DIFFERENCE,
    eps,
    k);
  if (!Check(got.size() == ref.Output.size(), label + ": one normal per point"))
  {
    return;
  }
  int bad = 0;
  double worstExcess = 0.0;
  for (size_t p = 0; p < got.size(); ++p)
  {
    const double d = Distance(got[p], ref.Output[p]);
    const double tol = Tolerance(eps, ref.Counts[p], Norm(ref.Sums[p]));
    if (!(d <= tol))
    {
      ++bad;
      worstExcess = std::max(worstExcess, d / tol);
    }
  }
  Check(bad == 0,
    label + ": equals the brute-force reference (" + std::to_string(bad) +
      " points outside the tolerance, worst at " + Str(worstExcess) + " times it)");
}

// The normalised output of a VTK gradient filter (vtkImageGradient or vtkImageSobel3D), with
// the component along an axis doubled where the point is on that axis's faces: VTK repeats the
// edge value there (half the one-sided difference), the filter takes the one-sided difference.
template <typename FilterT>
std::vector<Vec> VTKNormals(vtkImageData* image, bool doubleFaces)
{
  vtkNew<FilterT> gradient;
  gradient->SetInputData(image);
  if constexpr (std::is_same<FilterT, vtkImageGradient>::value)
  {
    gradient->SetDimensionality(3);
    gradient->HandleBoundariesOn();
  }
  gradient->Update();
  vtkDataArray* g = gradient->GetOutput()->GetPointData()->GetScalars();
  int dims[3];
  image->GetDimensions(dims);
  std::vector<Vec> out(g->GetNumberOfTuples());
  for (int k = 0; k < dims[2]; ++k)
  {
    for (int j = 0; j < dims[1]; ++j)
    {
      for (int i = 0; i < dims[0]; ++i)
      {
        const int p[3] = { i, j, k };
        const vtkIdType id = i + dims[0] * (j + static_cast<vtkIdType>(dims[1]) * k);
        Vec v;
        g->GetTuple(id, v.data());
        for (int a = 0; doubleFaces && a < 3; ++a)
        {
          if (dims[a] > 1 && (p[a] == 0 || p[a] == dims[a] - 1))
          {
            v[a] *= 2.0;
          }
        }
        out[id] = Unit(v);
      }
    }
  }
  return out;
}

bool OnFace(const Volume& v, vtkIdType id)
{
  const int i = static_cast<int>(id % v.N[0]);
  const int j = static_cast<int>((id / v.N[0]) % v.N[1]);
  const int k = static_cast<int>(id / (static_cast<vtkIdType>(v.N[0]) * v.N[1]));
  return i == 0 || j == 0 || k == 0 || i == v.N[0] - 1 || j == v.N[1] - 1 || k == v.N[2] - 1;
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
      static_cast<vtkGradientExaggeration*>(caller)->SetAbortExecute(1);
    }
  }
  std::vector<double> Values;
  bool AbortOnFirst = false;
};

//------------------------------------------------------------------------------
void TestDefaults()
{
  vtkNew<vtkGradientExaggeration> filter;
  Check(filter->GetEpsilon() == 1.0, "Epsilon is 1 initially");
  Check(filter->GetNeighborhoodSize() == 5, "NeighborhoodSize is 5 initially");
  Check(filter->GetGradientMethod() == vtkGradientExaggeration::CENTRAL_DIFFERENCE,
    "central differences initially");
  Check(std::string(filter->GetOutputArrayName()) == "ExaggeratedNormals",
    "OutputArrayName is ExaggeratedNormals initially");
  filter->SetGradientMethodToSobel();
  Check(std::string(filter->GetGradientMethodAsString()) == "Sobel", "Sobel by name");
  filter->SetGradientMethod(7);
  Check(filter->GetGradientMethod() == vtkGradientExaggeration::SOBEL,
    "a gradient method out of range is clamped");
  std::ostringstream print;
  filter->Print(print);
  Check(
    print.str().find("NeighborhoodSize: 5") != std::string::npos, "PrintSelf prints the settings");
}

// Brute force on random volumes: every combination of method, eps and box size, anisotropic
// spacing, boxes truncated everywhere (k = 7 on 6 points) and larger than the volume.
void TestBruteForce()
{
  const int n[3] = { 9, 7, 6 };
  const double spacing[3] = { 0.5, 1.25, 2.0 };
  const Volume v = RandomVolume(n, spacing, 17);
  for (bool sobel : { false, true })
  {
    for (double eps : { 0.0, 1.0, 3.0 })
    {
      for (int k : { 1, 3, 5, 7, 101 })
      {
        CheckAgainstBruteForce(v,
          sobel,
          eps,
          k,
          std::string(sobel ? "Sobel" : "central") + ", eps " + Str(eps) + ", k " +
            std::to_string(k));
      }
    }
  }
  // Negative spacing: world x decreases with i, and so does the gradient's sign.
  const double flipped[3] = { -0.5, 1.25, 2.0 };
  CheckAgainstBruteForce(RandomVolume(n, flipped, 5), false, 1.0, 5, "negative x spacing");
}

// eps = 0: the normalised gradients, as the test's own differences and as VTK's filters give
// them.
void TestNoExaggeration()
{
  const int n[3] = { 8, 7, 6 };
  const double spacing[3] = { 0.5, 1.25, 2.0 };
  const Volume v = RandomVolume(n, spacing, 99);
  auto image = ToImage(v);
  for (bool sobel : { false, true })
  {
    const std::string label = sobel ? "Sobel" : "central";
    const std::vector<Vec> got = Run(image,
      sobel ? vtkGradientExaggeration::SOBEL : vtkGradientExaggeration::CENTRAL_DIFFERENCE,
      0.0,
      5);
    std::vector<Vec> own(v.Size());
    for (int k = 0; k < n[2]; ++k)
    {
      for (int j = 0; j < n[1]; ++j)
      {
        for (int i = 0; i < n[0]; ++i)
        {
          own[v.Id(i, j, k)] =
            Unit(sobel ? SobelGradient(v, i, j, k) : CentralGradient(v, i, j, k));
        }
      }
    }
    // Float output of a unit vector: within 2^-24 per component.
    Check(Worst(got, own) < 1e-6,
      label + ", eps 0: the normalised gradients (worst " + Str(Worst(got, own)) + ")");
    const std::vector<Vec> vtk = sobel ? VTKNormals<vtkImageSobel3D>(image, false)
                                       : VTKNormals<vtkImageGradient>(image, false);
    const std::vector<Vec> vtkFaces =
      sobel ? VTKNormals<vtkImageSobel3D>(image, true) : VTKNormals<vtkImageGradient>(image, true);
    double inner = 0.0, faces = 0.0, facesUndoubled = 0.0;
    for (vtkIdType p = 0; p < v.Size(); ++p)
    {
      if (OnFace(v, p))
      {
        faces = std::max(faces, Distance(got[p], vtkFaces[p]));
        facesUndoubled = std::max(facesUndoubled, Distance(got[p], vtk[p]));
      }
      else
      {
        inner = std::max(inner, Distance(got[p], vtk[p]));
      }
    }
    const std::string vtkName = sobel ? "vtkImageSobel3D" : "vtkImageGradient";
    Check(inner < 1e-6,
      label + ", eps 0: equals normalised " + vtkName + " inside (worst " + Str(inner) + ")");
    Check(faces < 1e-6,
      label + ", eps 0: on the faces, equals " + vtkName +
        " with the face-normal component doubled (worst " + Str(faces) + ")");
    Check(facesUndoubled > 1e-3, label + ": and differs from " + vtkName + " undoubled there");
  }
}

// f = a x + b y + c z in world coordinates: the gradient is (a, b, c) everywhere, at the
// faces too (one-sided differences of a linear field are exact), so every N is the same, every
// N_m equals it and N' = N whatever eps and k.
void TestLinearField()
{
  const int n[3] = { 7, 6, 5 };
  const double spacing[3] = { 0.5, 1.25, 2.0 }, origin[3] = { -1.0, 2.0, 0.5 };
  const double a = 0.7, b = -1.3, c = 0.4;
  const Volume v = MakeVolume(
    n, spacing, origin, [&](double x, double y, double z) { return a * x + b * y + c * z; });
  const Vec expected = Unit(Vec{ a, b, c });
  const std::vector<Vec> all(v.Size(), expected);
  for (bool sobel : { false, true })
  {
    for (double eps : { 1.0, 3.0 })
    {
      const std::vector<Vec> got = Run(ToImage(v),
        sobel ? vtkGradientExaggeration::SOBEL : vtkGradientExaggeration::CENTRAL_DIFFERENCE,
        eps,
        5);
      Check(Worst(got, all) < 1e-6,
        std::string("linear field, ") + (sobel ? "Sobel" : "central") + ", eps " + Str(eps) +
          ": every normal is (a, b, c) / |(a, b, c)|, faces included (worst " +
          Str(Worst(got, all)) + ")");
    }
  }
  // A 1-voxel-thick slab of the same field: nothing along z, so the z component is 0.
  const int slab[3] = { 6, 5, 1 };
  const Volume s = MakeVolume(
    slab, spacing, origin, [&](double x, double y, double z) { return a * x + b * y + c * z; });
  const std::vector<Vec> flat(s.Size(), Unit(Vec{ a, b, 0.0 }));
  for (bool sobel : { false, true })
  {
    const std::vector<Vec> got = Run(ToImage(s),
      sobel ? vtkGradientExaggeration::SOBEL : vtkGradientExaggeration::CENTRAL_DIFFERENCE,
      1.0,
      5);
    Check(Worst(got, flat) < 1e-6,
      std::string("6 x 5 x 1 slab, ") + (sobel ? "Sobel" : "central") +
        ": normals (a, b, 0) / |(a, b)| (worst " + Str(Worst(got, flat)) + ")");
  }
  // A line and a single voxel.
  const int line[3] = { 1, 1, 9 };
  const Volume l = MakeVolume(
    line, spacing, origin, [&](double x, double y, double z) { return a * x + b * y + c * z; });
  Check(Worst(Run(ToImage(l), 0, 1.0, 5), std::vector<Vec>(9, Vec{ 0, 0, 1 })) < 1e-6,
    "1 x 1 x 9 line: normals along z (c > 0)");
  const int one[3] = { 1, 1, 1 };
  const Volume o = MakeVolume(one, spacing, origin, [](double, double, double) { return 3.0; });
  const std::vector<Vec> single = Run(ToImage(o), 0, 1.0, 5);
  Check(single.size() == 1 && Norm(single[0]) == 0.0, "a single voxel has a zero normal");
}

// The crease f = |x| + y, spacing 1, crease on the column x = 0 (index 6 of 13). Central
// differences give three normals, the same in every row and slice (the one-sided differences
// at the faces of this piecewise-linear field are exact):
//   left  (x < 0): N_L = (-1, 1, 0) / sqrt 2      (at -45 degrees from +y, towards -x)
//   crease (x = 0): N_C = (0, 1, 0)                ((f(1) - f(-1)) / 2 = 0 along x)
//   right (x > 0): N_R = (1, 1, 0) / sqrt 2        (at +45 degrees)
// The 5^3 box of a voxel spans 5 columns; truncation in y and z removes whole rows of every
// column alike, so only the column counts matter.
// - x = 1 (next to the crease): columns -1 .. 3 = 1 left, 1 crease, 3 right:
//     M ~ N_L + N_C + 3 N_R = (2 / sqrt 2, 4 / sqrt 2 + 1, 0) = (sqrt 2, 2 sqrt 2 + 1, 0),
//     N_m at theta_m = atan(sqrt 2 / (1 + 2 sqrt 2)) = 20.274 degrees from +y; N at 45 degrees,
//     so N is delta = 45 - theta_m = 24.726 degrees from N_m. In N_m's frame N = (cos delta,
//     sin delta) and N' = N + eps (N - N_m) = ((1 + eps) cos delta - eps, (1 + eps) sin delta):
//     for eps = 1 the angle between N' and N_m is atan2(2 sin delta, 2 cos delta - 1)
//     = 45.690 degrees: the deviation from the mean grows from 24.7 to 45.7 degrees.
// - x = 2: columns 0 .. 4 = 1 crease, 4 right: M ~ (2 sqrt 2, 2 sqrt 2 + 1, 0), theta_m =
//   atan(2 sqrt 2 / (1 + 2 sqrt 2)) = 36.45 degrees, delta = 8.55 degrees -> 16.8 degrees.
// - x = 0: columns -2 .. 2 = 2 left, 1 crease, 2 right: M along +y = N_C, so N' = N_C.
// - x = 4 and beyond: all 5 columns right: N_m = N_R, N' = N_R.
// Mirrored on the left.
void TestCrease()
{
  const int n[3] = { 13, 7, 6 };
  const double spacing[3] = { 1, 1, 1 }, origin[3] = { -6, 0, 0 };
  const Volume v =
    MakeVolume(n, spacing, origin, [](double x, double y, double) { return std::abs(x) + y; });
  const std::vector<Vec> got = Run(ToImage(v), 0, 1.0, 5);
  if (!Check(got.size() == static_cast<size_t>(v.Size()), "crease: one normal per point"))
  {
    return;
  }
  const double pi = 3.14159265358979323846, s2 = std::sqrt(2.0);
  const Vec right = Unit(Vec{ 1, 1, 0 }), crease{ 0, 1, 0 };
  struct Case
  {
    int Column;   // x
    Vec MeanSum;  // M up to a factor, from the column counts above
    double Angle; // expected angle between N' and N_m, degrees, from the comment above
  };
  const double delta1 = pi / 4 - std::atan(s2 / (1 + 2 * s2));
  const double delta2 = pi / 4 - std::atan(2 * s2 / (1 + 2 * s2));
  const Case cases[] = {
    { 1,
      Vec{ s2, 2 * s2 + 1, 0 },
      std::atan2(2 * std::sin(delta1), 2 * std::cos(delta1) - 1) * 180 / pi },
    { 2,
      Vec{ 2 * s2, 2 * s2 + 1, 0 },
      std::atan2(2 * std::sin(delta2), 2 * std::cos(delta2) - 1) * 180 / pi },
  };
  // The hand-computed value, so that a slip in the formula above shows.
  Check(
    std::abs(cases[0].Angle - 45.690192625) < 1e-6, "crease: the derived angle is 45.6902 degrees");
  for (const Case& c : cases)
  {
    const Vec mean = Unit(c.MeanSum);
    double worstAngle = 0.0, worstDirection = 0.0;
    for (int side : { 1, -1 })
    {
      for (int k = 0; k < n[2]; ++k)
      {
        for (int j = 0; j < n[1]; ++j)
        {
          const Vec& out = got[v.Id(6 + side * c.Column, j, k)];
          const Vec m{ side * mean[0], mean[1], mean[2] };
          const Vec nn{ side * right[0], right[1], right[2] };
          worstAngle = std::max(worstAngle, std::abs(Angle(out, m) * 180 / pi - c.Angle));
          const Vec expected = Unit(Vec{ 2 * nn[0] - m[0], 2 * nn[1] - m[1], 2 * nn[2] - m[2] });
          worstDirection = std::max(worstDirection, Distance(out, expected));
        }
      }
    }
    const double before = Angle(right, mean) * 180 / pi;
    Check(worstAngle < 1e-4,
      "crease, x = +-" + std::to_string(c.Column) + ": angle between N' and N_m is " +
        Str(c.Angle) + " degrees (was " + Str(before) + "), worst deviation " + Str(worstAngle) +
        " degrees");
    Check(worstDirection < 1e-6, "crease, x = +-" + std::to_string(c.Column) + ": N' = 2 N - N_m");
    Check(c.Angle > before, "crease, x = +-" + std::to_string(c.Column) + ": sharper than before");
  }
  double worstCentre = 0.0, worstFar = 0.0;
  for (int k = 0; k < n[2]; ++k)
  {
    for (int j = 0; j < n[1]; ++j)
    {
      worstCentre = std::max(worstCentre, Distance(got[v.Id(6, j, k)], crease));
      for (int x = 4; x <= 6; ++x)
      {
        worstFar = std::max(worstFar, Distance(got[v.Id(6 + x, j, k)], right));
        worstFar =
          std::max(worstFar, Distance(got[v.Id(6 - x, j, k)], Vec{ -right[0], right[1], 0 }));
      }
    }
  }
  Check(worstCentre < 1e-6, "crease, x = 0: symmetric box, N' = N_C = (0, 1, 0)");
  Check(worstFar < 1e-6, "crease, |x| >= 4: the box holds one side only, N' = N");
}

// Zero gradients stay zero; huge eps still gives unit vectors.
void TestZeroAndHuge()
{
  const int n[3] = { 8, 6, 5 };
  const double spacing[3] = { 1, 1, 1 }, origin[3] = { 0, 0, 0 };
  const Volume constant =
    MakeVolume(n, spacing, origin, [](double, double, double) { return 2.5; });
  const std::vector<Vec> zeros(constant.Size(), Vec{ 0, 0, 0 });
  for (int method : { 0, 1 })
  {
    Check(Worst(Run(ToImage(constant), method, 1.0, 5), zeros) == 0.0,
      "constant volume: all normals zero (method " + std::to_string(method) + ")");
  }
  // A plateau (x <= 4) then a ramp: the central difference is 0 up to x = 3 (f(4) - f(2) = 0)
  // although the box there (x = 1 .. 5) reaches the ramp; without the zero mask it would get
  // -eps N_m.
  const Volume plateau =
    MakeVolume(n, spacing, origin, [](double x, double, double) { return std::max(x - 4.0, 0.0); });
  const std::vector<Vec> got = Run(ToImage(plateau), 0, 1.0, 5);
  bool zeroOnPlateau = got.size() == static_cast<size_t>(plateau.Size());
  bool unitOnRamp = zeroOnPlateau;
  for (int k = 0; zeroOnPlateau && k < n[2]; ++k)
  {
    for (int j = 0; j < n[1]; ++j)
    {
      for (int i = 0; i < n[0]; ++i)
      {
        const double length = Norm(got[plateau.Id(i, j, k)]);
        zeroOnPlateau = zeroOnPlateau && (i > 3 || length == 0.0);
        unitOnRamp = unitOnRamp && (i <= 3 || std::abs(length - 1.0) < 1e-6);
      }
    }
  }
  Check(zeroOnPlateau, "zero-gradient voxels beside the ramp stay exactly zero");
  Check(unitOnRamp, "voxels on the ramp have unit normals");

  // k = 1: N_m = N, so N' = N exactly, however large eps (no rounding of a box sum for eps to
  // multiply).
  const Volume noisy = RandomVolume(n, spacing, 8);
  Check(Worst(Run(ToImage(noisy), 0, 1e6, 1), Run(ToImage(noisy), 0, 0.0, 5)) == 0.0,
    "k = 1, eps 1e6: exactly the normalised gradients");

  // Huge eps: N' is dominated by N - N_m, still a unit vector wherever N is not zero; 1e300
  // overflows eps (N - N_m) and takes its limit.
  const Volume rough = RandomVolume(n, spacing, 3);
  for (double eps : { 1e6, 1e300 })
  {
    for (int method : { 0, 1 })
    {
      const std::vector<Vec> big = Run(ToImage(rough), method, eps, 5);
      const std::vector<Vec> plain = Run(ToImage(rough), method, 0.0, 5);
      bool ok = big.size() == plain.size() && !big.empty();
      for (size_t p = 0; ok && p < big.size(); ++p)
      {
        ok = Norm(plain[p]) == 0.0 ? Norm(big[p]) == 0.0 : std::abs(Norm(big[p]) - 1.0) < 1e-6;
      }
      Check(ok, "eps " + Str(eps) + ", method " + std::to_string(method) + ": unit-length output");
      // And it has turned normals: far from eps = 0.
      Check(Worst(big, plain) > 0.5, "eps " + Str(eps) + ": the normals turned");
    }
  }
}

// NaN and Inf voxels: zero normals, and their neighbours take one-sided differences, so on a
// linear field every other voxel keeps the exact normal (a zero normal adds nothing to a box).
void TestNonFinite()
{
  const int n[3] = { 7, 6, 5 };
  const double spacing[3] = { 0.5, 1.25, 2.0 }, origin[3] = { 0, 0, 0 };
  const double a = 0.7, b = -1.3, c = 0.4;
  const Volume linear = MakeVolume(
    n, spacing, origin, [&](double x, double y, double z) { return a * x + b * y + c * z; });
  const Vec expected = Unit(Vec{ a, b, c });
  for (double bad : { NaN, std::numeric_limits<double>::infinity() })
  {
    for (int method : { 0, 1 })
    {
      Volume v = linear;
      // Every other voxel keeps a finite neighbour along each axis (one without any gets 0
      // for that component, which would change the field's normal).
      const vtkIdType holes[] = { v.Id(3, 2, 2), v.Id(0, 0, 0), v.Id(6, 5, 2), v.Id(3, 3, 2) };
      for (vtkIdType h : holes)
      {
        v.Values[h] = bad;
      }
      const std::vector<Vec> got = Run(ToImage(v), method, 1.0, 5);
      bool ok = got.size() == static_cast<size_t>(v.Size());
      double worst = 0.0;
      for (vtkIdType p = 0; ok && p < v.Size(); ++p)
      {
        const bool hole = std::find(std::begin(holes), std::end(holes), p) != std::end(holes);
        const double d = Distance(got[p], hole ? Vec{ 0, 0, 0 } : expected);
        worst = std::max(worst, std::isfinite(d) ? d : 1e300);
      }
      Check(ok && worst < 1e-6,
        std::string(std::isnan(bad) ? "NaN" : "Inf") + " voxels, method " + std::to_string(method) +
          ": zero there, the exact linear normal everywhere else (worst " + Str(worst) + ")");
    }
  }
  // Against the brute force on a rough volume with holes (central differences).
  const int m[3] = { 8, 7, 6 };
  Volume rough = RandomVolume(m, spacing, 11);
  for (vtkIdType p = 0; p < rough.Size(); p += 13)
  {
    rough.Values[p] = NaN;
  }
  CheckAgainstBruteForce(rough, false, 1.0, 5, "rough volume with NaN holes");
  // All NaN: all zero, not an error.
  Volume empty = linear;
  std::fill(empty.Values.begin(), empty.Values.end(), NaN);
  vtkNew<vtkGradientExaggeration> filter;
  vtkNew<vtkTest::ErrorObserver> errors;
  filter->AddObserver(vtkCommand::ErrorEvent, errors);
  filter->SetInputData(ToImage(empty));
  filter->Update();
  Check(!errors->GetError() &&
      Worst(Normals(filter->GetOutput()), std::vector<Vec>(empty.Size(), Vec{ 0, 0, 0 })) == 0.0,
    "an all-NaN volume gives zero normals without an error");
}

// Values at the ends of double's range and far below 1: the threshold is relative, the
// arithmetic does not overflow.
void TestExtremeValues()
{
  const int n[3] = { 6, 5, 4 };
  const double spacing[3] = { 1e-300, 1.0, 1e300 }, origin[3] = { 0, 0, 0 };
  for (double scale : { 1e-30, 1e300 })
  {
    const int method = scale > 1.0 ? 1 : 0;
    const double unit[3] = { 1, 1, 1 };
    const Volume v = MakeVolume(
      n, unit, origin, [&](double x, double y, double z) { return scale * (x + 2 * y + 3 * z); });
    const std::vector<Vec> got = Run(ToImage(v), method, 1.0, 5);
    Check(Worst(got, std::vector<Vec>(v.Size(), Unit(Vec{ 1, 2, 3 }))) < 1e-6,
      "values scaled by " + Str(scale) + ": the linear normal (the threshold is relative)");
  }
  // +-1e308 alternating along x (differences beyond double's range) and spacings 1e-300 and
  // 1e300 (gradients beyond it): finite normals, unit (on the x faces) or zero (inside, where
  // the central difference of the alternation is 0).
  const Volume wild = MakeVolume(n,
    spacing,
    origin,
    [&](double x, double, double) { return (std::lround(x / 1e-300) % 2 ? 1e308 : -1e308); });
  const std::vector<Vec> got = Run(ToImage(wild), 0, 1.0, 5);
  bool ok = !got.empty();
  int units = 0;
  for (const Vec& g : got)
  {
    ok = ok && std::isfinite(Norm(g)) && (Norm(g) == 0.0 || std::abs(Norm(g) - 1.0) < 1e-6);
    units += Norm(g) > 0.5;
  }
  Check(ok && units == 2 * n[1] * n[2],
    "1e308 values and 1e-300 / 1e300 spacings: finite unit normals on the two x faces, zero "
    "elsewhere (" +
      std::to_string(units) + " unit normals)");
}

// Every input type, an SOA array (through the generic path when not dispatched) and an input
// array other than the active scalars.
void TestInputTypes()
{
  const int n[3] = { 7, 6, 5 };
  const double spacing[3] = { 0.5, 1.25, 2.0 }, origin[3] = { 0, 0, 0 };
  const Volume v = MakeVolume(n,
    spacing,
    origin,
    [](double x, double y, double z)
    { return std::round(20 + 10 * std::sin(2 * x) + 7 * std::cos(y) + 3 * z); });
  const std::vector<Vec> reference = Run(ToImage<vtkDoubleArray>(v), 0, 1.0, 5);
  Check(Worst(reference, BruteForce(v, false, 1.0, 5).Output) < 1e-5,
    "integer-valued field: reference");
  const std::vector<Vec> uchar = Run(ToImage<vtkUnsignedCharArray>(v), 0, 1.0, 5);
  const std::vector<Vec> shorts = Run(ToImage<vtkShortArray>(v), 0, 1.0, 5);
  const std::vector<Vec> floats = Run(ToImage<vtkFloatArray>(v), 0, 1.0, 5);
  const std::vector<Vec> soa = Run(ToImage<vtkSOADataArrayTemplate<float>>(v), 0, 1.0, 5);
  Check(Worst(uchar, reference) == 0.0, "unsigned char input: the same normals as double");
  Check(Worst(shorts, reference) == 0.0, "short input: the same normals as double");
  Check(Worst(floats, reference) == 0.0, "float input: the same normals as double");
  Check(Worst(soa, reference) == 0.0, "SOA float input: the same normals as double");

  // Two point arrays: the one selected by name, not the active scalars.
  auto image = ToImage(v, "active");
  const double a = 0.7, b = -1.3, c = 0.4;
  const Volume linear = MakeVolume(
    n, spacing, origin, [&](double x, double y, double z) { return a * x + b * y + c * z; });
  vtkSmartPointer<vtkImageData> other = ToImage(linear, "other");
  image->GetPointData()->AddArray(other->GetPointData()->GetArray("other"));
  vtkNew<vtkGradientExaggeration> filter;
  filter->SetInputData(image);
  filter->SetInputArrayToProcess(0, 0, 0, vtkDataObject::FIELD_ASSOCIATION_POINTS, "other");
  filter->SetOutputArrayName("Exaggerated");
  filter->Update();
  vtkImageData* out = filter->GetOutput();
  Check(Worst(Normals(out, "Exaggerated"), std::vector<Vec>(v.Size(), Unit(Vec{ a, b, c }))) < 1e-6,
    "the array selected by name is the one processed, under OutputArrayName");
  vtkDataArray* normals = out->GetPointData()->GetArray("Exaggerated");
  Check(normals && normals->GetDataType() == VTK_FLOAT && normals->GetNumberOfComponents() == 3,
    "the normals are a 3-component float array");
  Check(out->GetPointData()->GetScalars() == image->GetPointData()->GetScalars() &&
      out->GetPointData()->GetArray("other") == image->GetPointData()->GetArray("other"),
    "the input arrays are passed through (shallow copy)");
  Check(out->GetSpacing()[2] == 2.0 && out->GetNumberOfPoints() == image->GetNumberOfPoints(),
    "the geometry is the input's");
}

// A piece (as an MPI rank asks for, with or without ghost levels) and a sub-extent equal the
// whole volume's normals there: the filter asks for enough more input to compute them.
void TestPieces()
{
  vtkNew<vtkMarschnerLobbSource> source;
  source->SetDimensions(21, 19, 17);
  vtkNew<vtkGradientExaggeration> filter;
  filter->SetInputConnection(source->GetOutputPort());
  filter->Update();
  vtkNew<vtkImageData> whole;
  whole->DeepCopy(filter->GetOutput());
  const std::vector<Vec> all = Normals(whole);
  auto compare = [&](vtkImageData* out, const std::string& label)
  {
    int extent[6];
    out->GetExtent(extent);
    const std::vector<Vec> part = Normals(out);
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
            worst, Distance(part[out->ComputePointId(ijk)], all[whole->ComputePointId(ijk)]));
        }
      }
    }
    // Box sums are running sums started at other rows, so they may round differently.
    Check(ok && worst < 1e-6,
      label + ": a part of the grid with the whole volume's normals (" +
        std::to_string(out->GetNumberOfPoints()) + " points, worst " + Str(worst) + ")");
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
  // A new filter: the piece request above stays in the first one's pipeline information.
  vtkNew<vtkGradientExaggeration> sub;
  sub->SetInputConnection(source->GetOutputPort());
  int extent[6] = { 3, 10, 0, 9, 4, 12 };
  sub->UpdateExtent(extent);
  int got[6];
  sub->GetOutput()->GetExtent(got);
  Check(std::equal(got, got + 6, extent), "a sub-extent request gives that extent");
  compare(sub->GetOutput(), "extent 3..10 x 0..9 x 4..12");
}

void TestProgressAndAbort()
{
  vtkNew<vtkMarschnerLobbSource> source;
  source->SetDimensions(24, 24, 24);
  vtkNew<vtkGradientExaggeration> filter;
  filter->SetInputConnection(source->GetOutputPort());
  vtkNew<ProgressRecorder> progress;
  filter->AddObserver(vtkCommand::ProgressEvent, progress);
  filter->Update();
  const std::vector<double>& p = progress->Values;
  Check(p.size() >= 10 && std::is_sorted(p.begin(), p.end()) && p.back() == 1.0,
    "progress events rise to 1 (" + std::to_string(p.size()) + " events)");
  Check(
    filter->GetOutput()->GetPointData()->GetArray("ExaggeratedNormals") != nullptr, "normals made");

  progress->Values.clear();
  progress->AbortOnFirst = true;
  filter->Modified();
  filter->Update();
  Check(progress->Values.size() <= 3 &&
      filter->GetOutput()->GetPointData()->GetArray("ExaggeratedNormals") == nullptr,
    "an abort request stops the filter at the next chunk, without normals");
  progress->AbortOnFirst = false;
  filter->Modified();
  filter->Update();
  Check(filter->GetOutput()->GetPointData()->GetArray("ExaggeratedNormals") != nullptr,
    "the next update runs in full");
}

// Each bad input or setting: an error through the observers, an empty output, no crash; and
// a good input afterwards works again.
void TestBadInput()
{
  const int n[3] = { 5, 4, 3 };
  const double spacing[3] = { 1, 1, 1 }, origin[3] = { 0, 0, 0 };
  const Volume good =
    MakeVolume(n, spacing, origin, [](double x, double y, double z) { return x + y * z; });

  struct Case
  {
    std::string What;
    std::string Message; // a part of the expected error
    std::function<vtkSmartPointer<vtkImageData>()> Input;
    std::function<void(vtkGradientExaggeration*)> Settings;
  };
  auto goodImage = [&]() { return ToImage(good); };
  auto none = [](vtkGradientExaggeration*) {};
  std::vector<Case> cases = {
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
        auto image = ToImage(good);
        vtkNew<vtkDoubleArray> rgb;
        rgb->SetNumberOfComponents(3);
        rgb->SetNumberOfTuples(good.Size());
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
        auto image = ToImage(good);
        vtkNew<vtkDoubleArray> cells;
        cells->SetName("cells");
        cells->SetNumberOfTuples(image->GetNumberOfCells());
        cells->Fill(1.0);
        image->GetCellData()->AddArray(cells);
        return image;
      },
      [](vtkGradientExaggeration* f)
      { f->SetInputArrayToProcess(0, 0, 0, vtkDataObject::FIELD_ASSOCIATION_CELLS, "cells"); } },
    { "a missing array name",
      "no point array",
      goodImage,
      [](vtkGradientExaggeration* f)
      { f->SetInputArrayToProcess(0, 0, 0, vtkDataObject::FIELD_ASSOCIATION_POINTS, "nothing"); } },
    { "too few values",
      "values for the",
      [&]()
      {
        auto image = ToImage(good);
        image->GetPointData()->GetScalars()->SetNumberOfTuples(good.Size() - 7);
        return image;
      },
      none },
    { "zero spacing",
      "spacing",
      [&]()
      {
        auto image = ToImage(good);
        image->SetSpacing(1, 0, 1);
        return image;
      },
      none },
    { "NaN spacing",
      "spacing",
      [&]()
      {
        auto image = ToImage(good);
        image->SetSpacing(1, 1, NaN);
        return image;
      },
      none },
    { "infinite spacing",
      "spacing",
      [&]()
      {
        auto image = ToImage(good);
        image->SetSpacing(std::numeric_limits<double>::infinity(), 1, 1);
        return image;
      },
      none },
    { "NeighborhoodSize 4",
      "odd",
      goodImage,
      [](vtkGradientExaggeration* f) { f->SetNeighborhoodSize(4); } },
    { "NeighborhoodSize 0",
      "odd",
      goodImage,
      [](vtkGradientExaggeration* f) { f->SetNeighborhoodSize(0); } },
    { "NeighborhoodSize -3",
      "odd",
      goodImage,
      [](vtkGradientExaggeration* f) { f->SetNeighborhoodSize(-3); } },
    { "Epsilon -0.5",
      "Epsilon",
      goodImage,
      [](vtkGradientExaggeration* f) { f->SetEpsilon(-0.5); } },
    { "Epsilon NaN", "Epsilon", goodImage, [](vtkGradientExaggeration* f) { f->SetEpsilon(NaN); } },
    { "Epsilon Inf",
      "Epsilon",
      goodImage,
      [](vtkGradientExaggeration* f) { f->SetEpsilon(std::numeric_limits<double>::infinity()); } },
    { "empty OutputArrayName",
      "OutputArrayName",
      goodImage,
      [](vtkGradientExaggeration* f) { f->SetOutputArrayName(""); } },
    { "null OutputArrayName",
      "OutputArrayName",
      goodImage,
      [](vtkGradientExaggeration* f) { f->SetOutputArrayName(nullptr); } },
    { "OutputArrayName = the input's name",
      "input array's name",
      goodImage,
      [](vtkGradientExaggeration* f) { f->SetOutputArrayName("scalars"); } },
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
    vtkNew<vtkGradientExaggeration> filter;
    vtkNew<vtkTest::ErrorObserver> errors;
    filter->AddObserver(vtkCommand::ErrorEvent, errors);
    filter->GetExecutive()->AddObserver(vtkCommand::ErrorEvent, errors);
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
    filter->SetInputData(ToImage(good));
    filter->SetInputArrayToProcess(
      0, 0, 0, vtkDataObject::FIELD_ASSOCIATION_POINTS, vtkDataSetAttributes::SCALARS);
    filter->SetNeighborhoodSize(5);
    filter->SetEpsilon(1.0);
    filter->SetOutputArrayName("ExaggeratedNormals");
    filter->Update();
    Check(!errors->GetError() &&
        Normals(filter->GetOutput()).size() == static_cast<size_t>(good.Size()),
      c.What + ": the next good update works");
  }
}
}

int TestGradientExaggeration(int, char*[])
{
  TestDefaults();
  TestBruteForce();
  TestNoExaggeration();
  TestLinearField();
  TestCrease();
  TestZeroAndHuge();
  TestNonFinite();
  TestExtremeValues();
  TestInputTypes();
  TestPieces();
  TestProgressAndAbort();
  TestBadInput();
  if (failures)
  {
    std::cerr << "TestGradientExaggeration: " << failures << " checks failed\n";
    return 1;
  }
  return 0;
}
