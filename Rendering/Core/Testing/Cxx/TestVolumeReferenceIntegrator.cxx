// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
// vtkVolumeReferenceIntegrator, the ground truth, against closed forms of the emission-
// absorption integral: homogeneous media (slab, oblique chords, eye inside), a linear scalar
// with a linear colour ramp, a linear opacity ramp; rays that miss; second-order convergence
// in ScalarTolerance on the Marschner-Lobb volume; perspective against parallel; NaN scalars;
// bad inputs; progress events.
// One file, beyond the usual length: every closed form shares the volume and camera fixtures.
#include "vtkCallbackCommand.h"
#include "vtkCamera.h"
#include "vtkCameraRayModel.h"
#include "vtkColorTransferFunction.h"
#include "vtkContourValues.h"
#include "vtkDoubleArray.h"
#include "vtkFloatArray.h"
#include "vtkImageData.h"
#include "vtkMarschnerLobbSource.h"
#include "vtkMath.h"
#include "vtkMinimalStandardRandomSequence.h"
#include "vtkNew.h"
#include "vtkPiecewiseFunction.h"
#include "vtkPointData.h"
#include "vtkSmartPointer.h"
#include "vtkVolumeProperty.h"
#include "vtkVolumeReferenceIntegrator.h"

#include "hovrTestUtilities.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <functional>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

namespace
{
hovrTest::Checker check;

// The integrator works in double and stores float: a result x is exact to 1e-9 (the budget
// for the double computation, whose rounding is ~1e-15) plus the float rounding 2^-24 |x|.
double OutputTolerance(double x)
{
  return 1e-9 + std::ldexp(std::abs(x), -24);
}

// A volume with point scalars f(world point), extent starting at extentStart.
vtkSmartPointer<vtkImageData> MakeVolume(const int dims[3],
  const double spacing[3],
  const double origin[3],
  const std::function<double(const double*)>& f,
  const int extentStart[3] = nullptr,
  int type = VTK_DOUBLE)
{
  auto image = vtkSmartPointer<vtkImageData>::New();
  const int e[3] = { extentStart ? extentStart[0] : 0,
    extentStart ? extentStart[1] : 0,
    extentStart ? extentStart[2] : 0 };
  image->SetExtent(e[0], e[0] + dims[0] - 1, e[1], e[1] + dims[1] - 1, e[2], e[2] + dims[2] - 1);
  image->SetSpacing(spacing[0], spacing[1], spacing[2]);
  image->SetOrigin(origin[0], origin[1], origin[2]);
  image->AllocateScalars(type, 1);
  vtkDataArray* scalars = image->GetPointData()->GetScalars();
  scalars->SetName("Scalars");
  for (vtkIdType id = 0; id < image->GetNumberOfPoints(); ++id)
  {
    double p[3];
    image->GetPoint(id, p);
    scalars->SetComponent(id, 0, f(p));
  }
  return image;
}

// Volume property from colour nodes (s, r, g, b) and opacity nodes (s, alpha).
vtkSmartPointer<vtkVolumeProperty> MakeProperty(const std::vector<std::array<double, 4>>& colours,
  const std::vector<std::array<double, 2>>& opacities,
  double unitDistance)
{
  vtkNew<vtkColorTransferFunction> color;
  for (const auto& c : colours)
  {
    color->AddRGBPoint(c[0], c[1], c[2], c[3]);
  }
  vtkNew<vtkPiecewiseFunction> opacity;
  for (const auto& o : opacities)
  {
    opacity->AddPoint(o[0], o[1]);
  }
  auto property = vtkSmartPointer<vtkVolumeProperty>::New();
  property->SetColor(color);
  property->SetScalarOpacity(opacity);
  property->SetScalarOpacityUnitDistance(unitDistance);
  return property;
}

void SetupCamera(vtkCamera* camera,
  const double position[3],
  const double focal[3],
  const double up[3],
  bool parallel,
  double scaleOrAngle)
{
  camera->SetPosition(position[0], position[1], position[2]);
  camera->SetFocalPoint(focal[0], focal[1], focal[2]);
  camera->SetViewUp(up[0], up[1], up[2]);
  camera->SetParallelProjection(parallel);
  if (parallel)
  {
    camera->SetParallelScale(scaleOrAngle);
  }
  else
  {
    camera->SetViewAngle(scaleOrAngle);
  }
}

vtkFloatArray* RGBA(vtkImageData* image)
{
  return vtkFloatArray::SafeDownCast(image->GetPointData()->GetArray("RGBA"));
}

// Copy of the output pixels (double), so that several renders can be compared.
std::vector<double> Pixels(vtkVolumeReferenceIntegrator* integrator)
{
  integrator->Update();
  vtkFloatArray* rgba = RGBA(integrator->GetOutput());
  std::vector<double> out;
  if (rgba)
  {
    out.assign(rgba->GetPointer(0), rgba->GetPointer(0) + rgba->GetNumberOfValues());
  }
  return out;
}

double RMSE(const std::vector<double>& a, const std::vector<double>& b)
{
  if (a.size() != b.size() || a.empty())
  {
    return std::numeric_limits<double>::infinity();
  }
  double sum = 0.0;
  for (size_t i = 0; i < a.size(); ++i)
  {
    sum += (a[i] - b[i]) * (a[i] - b[i]);
  }
  return std::sqrt(sum / a.size());
}

// Independent chord: the length of {t >= 0 : o + t d in [lo, hi]} for a unit direction d.
double Chord(const double lo[3], const double hi[3], const double o[3], const double d[3])
{
  double t0 = 0.0, t1 = std::numeric_limits<double>::infinity();
  for (int a = 0; a < 3; ++a)
  {
    if (d[a] == 0.0)
    {
      if (o[a] < lo[a] || o[a] > hi[a])
      {
        return 0.0;
      }
      continue;
    }
    const double ta = (lo[a] - o[a]) / d[a], tb = (hi[a] - o[a]) / d[a];
    t0 = std::max(t0, std::min(ta, tb));
    t1 = std::min(t1, std::max(ta, tb));
  }
  return std::max(0.0, t1 - t0);
}

// Independent brute force for an axis-aligned volume: steps of length <= delta from the box
// entry (or the ray origin) to the exit, each sampled at its midpoint with a trilinear
// interpolation written here and VTK's own transfer functions, attenuating exactly for that
// sample. Cells with a NaN corner are transparent.
void BruteForce(vtkImageData* volume,
  vtkVolumeProperty* property,
  const double o[3],
  const double d[3],
  double delta,
  double rgba[4])
{
  rgba[0] = rgba[1] = rgba[2] = rgba[3] = 0.0;
  const double* b = volume->GetBounds();
  const double lo[3] = { b[0], b[2], b[4] }, hi[3] = { b[1], b[3], b[5] };
  double t0 = 0.0, t1 = std::numeric_limits<double>::infinity();
  for (int a = 0; a < 3; ++a)
  {
    if (d[a] == 0.0)
    {
      if (o[a] < lo[a] || o[a] > hi[a])
      {
        return;
      }
      continue;
    }
    const double ta = (lo[a] - o[a]) / d[a], tb = (hi[a] - o[a]) / d[a];
    t0 = std::max(t0, std::min(ta, tb));
    t1 = std::min(t1, std::max(ta, tb));
  }
  if (!(t1 > t0))
  {
    return;
  }
  int dims[3];
  volume->GetDimensions(dims);
  const double* spacing = volume->GetSpacing();
  vtkDataArray* scalars = volume->GetPointData()->GetScalars();
  vtkPiecewiseFunction* opacity = property->GetScalarOpacity();
  vtkColorTransferFunction* color = property->GetRGBTransferFunction();
  const double unit = property->GetScalarOpacityUnitDistance();
  const int n = static_cast<int>(std::ceil((t1 - t0) / delta));
  const double h = (t1 - t0) / n;
  double transmittance = 1.0;
  for (int k = 0; k < n; ++k)
  {
    const double t = t0 + (k + 0.5) * h;
    int cell[3];
    double f[3];
    for (int a = 0; a < 3; ++a)
    {
      const double u = (o[a] + t * d[a] - lo[a]) / spacing[a];
      cell[a] = std::min(std::max(static_cast<int>(std::floor(u)), 0), dims[a] - 2);
      f[a] = u - cell[a];
    }
    double s = 0.0;
    for (int corner = 0; corner < 8; ++corner)
    {
      const int di = corner & 1, dj = (corner >> 1) & 1, dk = (corner >> 2) & 1;
      const vtkIdType id = (cell[0] + di) +
        dims[0] * ((cell[1] + dj) + static_cast<vtkIdType>(dims[1]) * (cell[2] + dk));
      s += (di ? f[0] : 1.0 - f[0]) * (dj ? f[1] : 1.0 - f[1]) * (dk ? f[2] : 1.0 - f[2]) *
        scalars->GetComponent(id, 0);
    }
    if (std::isnan(s))
    {
      continue;
    }
    double rgb[3];
    color->GetColor(s, rgb);
    const double alpha = -std::expm1(std::log1p(-opacity->GetValue(s)) / unit * h);
    for (int c = 0; c < 3; ++c)
    {
      rgba[c] += transmittance * alpha * rgb[c];
    }
    transmittance *= 1.0 - alpha;
  }
  rgba[3] = 1.0 - transmittance;
}

// Compares every pixel with expected(i, j, rgba) within tolerance(expected value); returns
// the largest absolute deviation.
double CheckPixels(vtkVolumeReferenceIntegrator* integrator,
  const std::function<void(int, int, double*)>& expected,
  const std::function<double(double)>& tolerance,
  const std::string& label)
{
  integrator->Update();
  vtkImageData* image = integrator->GetOutput();
  vtkFloatArray* rgba = RGBA(image);
  const int* size = integrator->GetImageSize();
  int dims[3];
  image->GetDimensions(dims);
  if (!check(rgba && dims[0] == size[0] && dims[1] == size[1] && dims[2] == 1 &&
          rgba->GetNumberOfComponents() == 4,
        label + ": a W x H x 1 image with an RGBA float array"))
  {
    return std::numeric_limits<double>::infinity();
  }
  int bad = 0;
  double worst = 0.0;
  for (int j = 0; j < size[1]; ++j)
  {
    for (int i = 0; i < size[0]; ++i)
    {
      double want[4];
      expected(i, j, want);
      const float* got = rgba->GetPointer(4 * (i + static_cast<vtkIdType>(size[0]) * j));
      for (int c = 0; c < 4; ++c)
      {
        worst = std::max(worst, std::abs(got[c] - want[c]));
        if (!(std::abs(got[c] - want[c]) <= tolerance(want[c])))
        {
          if (++bad <= 4)
          {
            std::cerr << label << ": pixel (" << i << ", " << j << ") channel " << c << " is "
                      << got[c] << ", expected " << want[c] << " (difference " << got[c] - want[c]
                      << ", tolerance " << tolerance(want[c]) << ")\n";
          }
        }
      }
    }
  }
  check(bad == 0,
    label + ": every pixel matches the closed form (" + std::to_string(bad) + " mismatches)");
  return worst;
}

// A transparent image of the requested size, no samples: what a failed update leaves.
void CheckTransparent(vtkVolumeReferenceIntegrator* integrator, const std::string& label)
{
  const int* size = integrator->GetImageSize();
  vtkImageData* image = integrator->GetOutput();
  vtkFloatArray* rgba = RGBA(image);
  int dims[3];
  image->GetDimensions(dims);
  bool ok = rgba && dims[0] == size[0] && dims[1] == size[1] && dims[2] == 1 &&
    rgba->GetNumberOfTuples() == static_cast<vtkIdType>(size[0]) * size[1];
  for (vtkIdType v = 0; ok && v < rgba->GetNumberOfValues(); ++v)
  {
    ok = rgba->GetValue(v) == 0.0f;
  }
  check(ok, label + ": output is a transparent image of the requested size");
  check(integrator->GetNumberOfSamples() == 0, label + ": no samples");
}
}

int TestVolumeReferenceIntegrator(int, char*[])
{
  hovrTest::MessageCapture messages;
  const double up[3] = { 0, 1, 0 };

  //----------------------------------------------------------------------------
  // 1. Homogeneous slab. The box [0, 2]^3 (non-zero extent start, origin and anisotropic
  //    spacing on purpose), seen along -z by a parallel camera: every ray that enters crosses
  //    L = 2, so alpha = 1 - exp(-tau L) and C = c alpha, with tau = -ln(1 - 0.4) / 0.7.
  //    The 40 x 40 pixel centres sit at x, y = (2i + 1) / 32 - 1/4: never on a face or a grid
  //    plane, 32 x 32 of them inside the box; the others miss and must be exactly 0.
  const int slabDims[3] = { 9, 9, 5 };
  const double slabSpacing[3] = { 0.25, 0.25, 0.5 };
  const int slabExtent[3] = { 2, 0, 3 };
  const double slabOrigin[3] = { -0.5, 0.0, -1.5 };
  auto constant = MakeVolume(
    slabDims, slabSpacing, slabOrigin, [](const double*) { return 5.0; }, slabExtent);
  const double* bounds = constant->GetBounds();
  check(bounds[0] == 0 && bounds[1] == 2 && bounds[2] == 0 && bounds[3] == 2 && bounds[4] == 0 &&
      bounds[5] == 2,
    "test volume spans [0, 2]^3");
  const double lo[3] = { 0, 0, 0 }, hi[3] = { 2, 2, 2 };
  const double c[3] = { 0.9, 0.5, 0.2 };
  const double tau = -std::log(1.0 - 0.4) / 0.7;
  auto homogeneous = MakeProperty({ { 5.0, c[0], c[1], c[2] } }, { { 5.0, 0.4 } }, 0.7);
  vtkNew<vtkCamera> camera;
  const double above[3] = { 1, 1, 10 }, centre[3] = { 1, 1, 1 };
  SetupCamera(camera, above, centre, up, true, 1.25);
  vtkNew<vtkVolumeReferenceIntegrator> integrator;
  integrator->SetInputData(constant);
  integrator->SetVolumeProperty(homogeneous);
  integrator->SetCamera(camera);
  integrator->SetImageSize(40, 40);
  auto pixelX = [](int i) { return (2 * i + 1) / 32.0 - 0.25; };
  auto inside = [&](int i, int j)
  { return pixelX(i) > 0.0 && pixelX(i) < 2.0 && pixelX(j) > 0.0 && pixelX(j) < 2.0; };
  auto homogeneousPixel = [&](double chord, double* rgba)
  {
    const double alpha = -std::expm1(-tau * chord);
    for (int k = 0; k < 3; ++k)
    {
      rgba[k] = c[k] * alpha;
    }
    rgba[3] = alpha;
  };
  CheckPixels(
    integrator,
    [&](int i, int j, double* rgba) { homogeneousPixel(inside(i, j) ? 2.0 : 0.0, rgba); },
    [](double x) { return x == 0.0 ? 0.0 : OutputTolerance(x); },
    "homogeneous slab");
  // One piece per cell crossed (a constant field needs no subdivision): 32^2 rays x 4 cells.
  check(integrator->GetNumberOfSamples() == 32 * 32 * 4,
    "homogeneous slab: one sample per cell crossed (" +
      std::to_string(integrator->GetNumberOfSamples()) + ", expected 4096)");
  // The output follows the transfer functions through the volume property: an opacity of 0.6
  // (AddPoint at an existing node replaces it) re-executes with the new closed form.
  {
    homogeneous->GetScalarOpacity()->AddPoint(5.0, 0.6);
    const double alpha = -std::expm1(2.0 * std::log(1.0 - 0.6) / 0.7);
    const std::vector<double> image = Pixels(integrator);
    const int pixel = 4 * (20 + 40 * 20);
    check.Near(image[pixel + 3],
      alpha,
      OutputTolerance(alpha),
      "a transfer-function change re-executes the integrator");
    homogeneous->GetScalarOpacity()->AddPoint(5.0, 0.4);
  }
  // A pixel sample (PixelFraction): exactly that many pixels, each as in the full image, the
  // others NaN; another seed draws other pixels; the smallest fraction still draws one.
  {
    check(integrator->GetPixelFraction() == 1.0 && integrator->GetPixelSeed() == 1,
      "every pixel, seed 1, by default");
    const std::vector<double> full = Pixels(integrator);
    auto sampled = [&](double fraction, int seed, int& computed, int& cells)
    {
      integrator->SetPixelFraction(fraction);
      integrator->SetPixelSeed(seed);
      const std::vector<double> image = Pixels(integrator);
      computed = 0;
      cells = static_cast<int>(integrator->GetNumberOfSamples());
      std::vector<int> which;
      bool same = image.size() == full.size();
      for (size_t p = 0; same && p < image.size() / 4; ++p)
      {
        const bool nan = std::isnan(image[4 * p]);
        for (int k = 0; k < 4; ++k)
        {
          same = same && (nan ? std::isnan(image[4 * p + k]) : image[4 * p + k] == full[4 * p + k]);
        }
        computed += nan ? 0 : 1;
      }
      return same;
    };
    int computed = 0, cells = 0, other = 0, otherCells = 0;
    check(sampled(0.25, 7, computed, cells) && computed == 400,
      "PixelFraction 0.25: 400 of the 1600 pixels, each as in the full image, NaN elsewhere");
    check(cells % 4 == 0 && cells <= 4 * 400, "the samples count the sampled pixels only");
    const std::vector<double> first = Pixels(integrator);
    integrator->SetPixelSeed(8);
    const std::vector<double> second = Pixels(integrator);
    int differ = 0;
    for (size_t p = 0; p < first.size() / 4; ++p)
    {
      differ += std::isnan(first[4 * p]) != std::isnan(second[4 * p]) ? 1 : 0;
    }
    check(differ > 0, "another seed samples other pixels");
    check(sampled(0.0, 7, other, otherCells) && other == 1, "PixelFraction 0: one pixel");
    integrator->SetPixelFraction(1.0);
    integrator->SetPixelSeed(1);
  }

  //----------------------------------------------------------------------------
  // 2. Oblique rays through the same homogeneous volume: 1 - exp(-tau chord) with the chord
  //    from an independent box clip of the camera model's rays (vtkCameraRayModel is checked
  //    against VTK's projection in TestCameraRayModel). Perspective from outside, parallel
  //    oblique, and a perspective eye inside the volume (chord from the eye to the exit).
  {
    struct View
    {
      const char* Name;
      double Position[3];
      double Focal[3];
      bool Parallel;
      double ScaleOrAngle;
    };
    const View views[] = {
      { "oblique perspective", { 3.1, 2.3, 4.2 }, { 1.0, 0.9, 1.1 }, false, 40.0 },
      { "oblique parallel", { -6.0, 5.0, 7.0 }, { 1.1, 1.0, 0.9 }, true, 1.3 },
      { "perspective from inside", { 1.2, 0.7, 1.3 }, { 2.0, 1.5, -0.5 }, false, 100.0 }
    };
    for (const View& view : views)
    {
      const double tilted[3] = { 0.2, 1.0, 0.3 };
      SetupCamera(camera, view.Position, view.Focal, tilted, view.Parallel, view.ScaleOrAngle);
      integrator->SetImageSize(33, 29);
      vtkNew<vtkCameraRayModel> rays;
      rays->SetCamera(camera);
      rays->SetImageSize(33, 29);
      check(rays->Prepare(), "ray model for the oblique views");
      int hits = 0;
      CheckPixels(
        integrator,
        [&](int i, int j, double* rgba)
        {
          double o[3], d[3];
          rays->GetPixelRay(i, j, o, d);
          const double chord = Chord(lo, hi, o, d);
          hits += chord > 0.0 ? 1 : 0;
          homogeneousPixel(chord, rgba);
        },
        OutputTolerance,
        view.Name);
      check(hits > 100, std::string(view.Name) + ": enough rays hit the box");
    }

    // A rotated, shifted volume (direction matrix: 30 degrees about z): the chord is measured
    // in the volume's own frame, local = R^T (world - origin), where the box is [0, 2]^3.
    const double cs = std::cos(vtkMath::RadiansFromDegrees(30.0));
    const double sn = std::sin(vtkMath::RadiansFromDegrees(30.0));
    const double shift[3] = { 0.5, -0.2, 0.1 };
    auto rotated = MakeVolume(slabDims, slabSpacing, shift, [](const double*) { return 5.0; });
    rotated->SetDirectionMatrix(cs, -sn, 0.0, sn, cs, 0.0, 0.0, 0.0, 1.0);
    integrator->SetInputData(rotated);
    const double rotatedCentre[3] = { shift[0] + cs - sn, shift[1] + sn + cs, shift[2] + 1.0 };
    const double eye[3] = { 4.0, -3.0, 3.5 }, tilted[3] = { 0.2, 1.0, 0.3 };
    SetupCamera(camera, eye, rotatedCentre, tilted, false, 45.0);
    vtkNew<vtkCameraRayModel> rays;
    rays->SetCamera(camera);
    rays->SetImageSize(33, 29);
    check(rays->Prepare(), "ray model for the rotated volume");
    int hits = 0;
    CheckPixels(
      integrator,
      [&](int i, int j, double* rgba)
      {
        double o[3], d[3], ol[3], dl[3];
        rays->GetPixelRay(i, j, o, d);
        const double p[3] = { o[0] - shift[0], o[1] - shift[1], o[2] - shift[2] };
        ol[0] = cs * p[0] + sn * p[1];
        ol[1] = -sn * p[0] + cs * p[1];
        ol[2] = p[2];
        dl[0] = cs * d[0] + sn * d[1];
        dl[1] = -sn * d[0] + cs * d[1];
        dl[2] = d[2];
        const double chord = Chord(lo, hi, ol, dl);
        hits += chord > 0.0 ? 1 : 0;
        homogeneousPixel(chord, rgba);
      },
      OutputTolerance,
      "rotated volume (direction matrix)");
    check(hits > 100, "rotated volume: enough rays hit the box");
    integrator->SetInputData(constant);
    SetupCamera(camera, above, centre, up, true, 1.25);
    integrator->SetImageSize(40, 40);
  }

  //----------------------------------------------------------------------------
  // 3. Linear scalar s = z on [0, 2]^3 (trilinear interpolation reproduces it exactly), seen
  //    along -z: s(t) = 2 - t over L = 2. Constant opacity 0.5 (tau = ln 2), colour ramp from
  //    (0, 0.3, 1) at s = 0 to (1, 0.3, 0) at s = 2, i.e. along the ray c(t) = c0 + c1 t with
  //    red c0 = 1, c1 = -1/2, green 0.3, blue c0 = 0, c1 = 1/2. As derived in
  //    TestFirstOrderPreIntegrationTable:
  //      C = c0 (1 - e^{-tau L}) + c1 (1 - e^{-tau L} (1 + tau L)) / tau.
  //    The integrator uses pieces of scalar change <= ScalarTolerance * feature (feature = 2,
  //    the node spacing, here also the data range), i.e. of length h <= 2 ScalarTolerance,
  //    each with the midpoint colour and exact attenuation; per piece the error is at most
  //    |c1| tau^2 h^3 / 12, in total |dc| tau^2 h^2 / 12 with dc = c1 L (same derivation).
  {
    const int dims[3] = { 5, 5, 9 };
    const double spacing[3] = { 0.5, 0.5, 0.25 }, origin[3] = { 0, 0, 0 };
    auto ramp = MakeVolume(dims, spacing, origin, [](const double* p) { return p[2]; });
    auto property =
      MakeProperty({ { 0.0, 0.0, 0.3, 1.0 }, { 2.0, 1.0, 0.3, 0.0 } }, { { 0.0, 0.5 } }, 1.0);
    integrator->SetInputData(ramp);
    integrator->SetVolumeProperty(property);
    const double t = std::log(2.0), L = 2.0;
    const double alpha = -std::expm1(-t * L);
    const double R = (1.0 - std::exp(-t * L) * (1.0 + t * L)) / t;
    const double c0[3] = { 1.0, 0.3, 0.0 }, c1[3] = { -0.5, 0.0, 0.5 };
    double previous = 0.0;
    for (double tolerance : { 1.0 / 32.0, 1.0 / 64.0, 1.0 / 128.0 })
    {
      integrator->SetScalarTolerance(tolerance);
      const double h = 2.0 * tolerance;
      std::ostringstream label;
      label << "linear colour ramp, ScalarTolerance 1/" << 1.0 / tolerance;
      CheckPixels(
        integrator,
        [&](int i, int j, double* rgba)
        {
          for (int k = 0; k < 3; ++k)
          {
            rgba[k] = inside(i, j) ? c0[k] * alpha + c1[k] * R : 0.0;
          }
          rgba[3] = inside(i, j) ? alpha : 0.0;
        },
        [&](double) { return 1.0 * t * t * h * h / 12.0 + OutputTolerance(1.0); },
        label.str());
      // Convergence: the red error of a hit pixel falls by ~4 per halving (x = tau h <= 0.05,
      // so the next term changes the ratio by < 3%).
      std::vector<double> image = Pixels(integrator);
      const int pixel = 20 + 40 * 20;
      const double error = std::abs(image[4 * pixel] - (c0[0] * alpha + c1[0] * R));
      if (previous > 0.0)
      {
        const double ratio = previous / error;
        std::cout << label.str() << ": red error " << error << ", ratio " << ratio << "\n";
        check(ratio > 3.5 && ratio < 4.5, label.str() + ": error falls ~4x per halving");
      }
      previous = error;
    }
    integrator->SetScalarTolerance(1.0 / 64.0);
  }

  //----------------------------------------------------------------------------
  // 4. Linear opacity alpha(s) = a + b s (nodes (0, a) and (2, a + 2b)), U = 1, constant
  //    colour, s = z along the ray. tau(s) = -ln(1 - a - b s); with u = 1 - a - b s,
  //    int_0^2 tau ds = (1/b) [u ln u - u]_{u(0)}^{u(2)}, and |ds/dt| = 1, so
  //    T = exp(-(F(u(2)) - F(u(0))) / b), F(u) = u ln u - u, alpha = 1 - T, C = c alpha.
  //    Midpoint error of int tau over pieces of length h: <= L h^2 max|tau''| / 24 with
  //    tau'' = b^2 / u^2 (largest at s = 2), giving |d alpha| <= T L h^2 max|tau''| / 24. The
  //    feature is 1 here (nodes at 0, 1, 2), so h <= ScalarTolerance.
  {
    const int dims[3] = { 5, 5, 9 };
    const double spacing[3] = { 0.5, 0.5, 0.25 }, origin[3] = { 0, 0, 0 };
    auto ramp = MakeVolume(dims, spacing, origin, [](const double* p) { return p[2]; });
    const double a = 0.1, b = 0.35;
    auto property =
      MakeProperty({ { 1.0, c[0], c[1], c[2] } }, { { 0.0, a }, { 2.0, a + 2 * b } }, 1.0);
    integrator->SetInputData(ramp);
    integrator->SetVolumeProperty(property);
    auto F = [](double u) { return u * std::log(u) - u; };
    const double u0 = 1.0 - a, u2 = 1.0 - a - 2.0 * b;
    const double T = std::exp(-(F(u2) - F(u0)) / b);
    const double h = integrator->GetScalarTolerance() * 1.0;
    const double bound = T * 2.0 * h * h * (b * b / (u2 * u2)) / 24.0;
    CheckPixels(
      integrator,
      [&](int i, int j, double* rgba)
      {
        const double alpha = inside(i, j) ? 1.0 - T : 0.0;
        for (int k = 0; k < 3; ++k)
        {
          rgba[k] = c[k] * alpha;
        }
        rgba[3] = alpha;
      },
      [&](double x) { return x == 0.0 ? 0.0 : bound + OutputTolerance(x); },
      "linear opacity ramp");
  }

  //----------------------------------------------------------------------------
  // 5. NaN scalars: the 8 cells around the NaN point (1, 1, 1) are transparent, so rays with
  //    x, y in (0.75, 1.25) cross 1.5 of medium instead of 2; no NaN anywhere in the output.
  {
    const int dims[3] = { 9, 9, 9 };
    const double spacing[3] = { 0.25, 0.25, 0.25 }, origin[3] = { 0, 0, 0 };
    auto holed = MakeVolume(
      dims,
      spacing,
      origin,
      [](const double* p)
      { return p[0] == 1.0 && p[1] == 1.0 && p[2] == 1.0 ? std::nan("") : 5.0; },
      nullptr,
      VTK_FLOAT);
    integrator->SetInputData(holed);
    integrator->SetVolumeProperty(homogeneous);
    auto inHole = [&](int i, int j)
    { return pixelX(i) > 0.75 && pixelX(i) < 1.25 && pixelX(j) > 0.75 && pixelX(j) < 1.25; };
    CheckPixels(
      integrator,
      [&](int i, int j, double* rgba)
      { homogeneousPixel(inside(i, j) ? (inHole(i, j) ? 1.5 : 2.0) : 0.0, rgba); },
      OutputTolerance,
      "NaN point in a float volume");
    std::vector<double> image = Pixels(integrator);
    check(std::none_of(image.begin(), image.end(), [](double v) { return std::isnan(v); }),
      "no NaN in the output");
    // NaN cells are skipped, not integrated: 32^2 rays x 8 cells, less 2 cells for each of
    // the 8 x 8 rays through the hole.
    check(integrator->GetNumberOfSamples() == 32 * 32 * 8 - 8 * 8 * 2,
      "NaN cells take no samples (" + std::to_string(integrator->GetNumberOfSamples()) +
        ", expected 8064)");
  }
  messages.ExpectNone(check, "for the closed-form cases");

  //----------------------------------------------------------------------------
  // 5b. Against the independent brute force: (a) one hot voxel in a zero volume with an
  //     opacity that is zero below s = 0.5, seen obliquely, so that only the 8 cells around
  //     the voxel contribute, each through a small region (this catches any wrong skipping of
  //     empty cells); (b) random scalars on an anisotropic, offset grid with a smooth transfer
  //     function, perspective from outside.
  //     Error budget: the brute force's midpoint steps of 2.5e-4 err by O(delta^2); halving
  //     them changes the differences below by < 1e-8, so its error is negligible. The
  //     integrator's own O(h^2) error dominates: with ScalarTolerance 1/256 the largest
  //     difference is 8.6e-6 (hot voxel: steep extinction, tau up to 11.5 with tau'' ~ 1e3)
  //     and 3.7e-7 (random volume), falling to 7.2e-7 and 4e-8 at 1/1024. 2e-5 is twice the
  //     largest, and far below the O(1e-2 .. 1) errors of a wrong cell, sample or skip.
  {
    const double bruteStep = 2.5e-4;
    const double bruteTolerance = 2e-5;
    integrator->SetScalarTolerance(1.0 / 256.0);
    const int hotDims[3] = { 7, 7, 7 };
    const double unitSpacing[3] = { 1, 1, 1 }, zero[3] = { 0, 0, 0 };
    auto hot = MakeVolume(hotDims,
      unitSpacing,
      zero,
      [](const double* p) { return p[0] == 3.0 && p[1] == 3.0 && p[2] == 3.0 ? 1.0 : 0.0; });
    auto hotProperty = MakeProperty({ { 0.0, 0.0, 0.0, 1.0 }, { 1.0, 1.0, 0.5, 0.0 } },
      { { 0.0, 0.0 }, { 0.5, 0.0 }, { 1.0, 0.9 } },
      0.2);
    const double hotEye[3] = { 7.0, 5.5, 8.0 }, hotCentre[3] = { 3.0, 3.0, 3.0 };
    const double tilted[3] = { 0.1, 1.0, 0.2 };
    SetupCamera(camera, hotEye, hotCentre, tilted, false, 14.0);

    const int randomDims[3] = { 6, 5, 4 };
    const double randomSpacing[3] = { 0.4, 0.5, 0.7 }, randomOrigin[3] = { -1.0, 0.5, 2.0 };
    vtkNew<vtkMinimalStandardRandomSequence> random;
    random->SetSeed(5);
    auto noise = MakeVolume(randomDims,
      randomSpacing,
      randomOrigin,
      [&](const double*)
      {
        random->Next();
        return random->GetValue();
      });
    auto smooth =
      MakeProperty({ { 0.0, 0.1, 0.2, 0.9 }, { 0.5, 0.9, 0.8, 0.1 }, { 1.0, 0.8, 0.1, 0.1 } },
        { { 0.0, 0.05 }, { 0.6, 0.5 }, { 1.0, 0.2 } },
        0.5);
    vtkNew<vtkCamera> outside;
    const double noiseEye[3] = { 2.5, -2.0, 5.5 }, noiseCentre[3] = { 0.0, 1.5, 3.0 };
    SetupCamera(outside, noiseEye, noiseCentre, tilted, false, 30.0);

    struct Case
    {
      const char* Name;
      vtkImageData* Volume;
      vtkVolumeProperty* Property;
      vtkCamera* Camera;
    };
    for (const Case& test : { Case{ "hot voxel", hot, hotProperty, camera },
           Case{ "random volume", noise, smooth, outside } })
    {
      integrator->SetInputData(test.Volume);
      integrator->SetVolumeProperty(test.Property);
      integrator->SetCamera(test.Camera);
      integrator->SetImageSize(12, 12);
      vtkNew<vtkCameraRayModel> rays;
      rays->SetCamera(test.Camera);
      rays->SetImageSize(12, 12);
      check(rays->Prepare(), "ray model for the brute-force comparison");
      double largest = 0.0;
      const double worst = CheckPixels(
        integrator,
        [&](int i, int j, double* rgba)
        {
          double o[3], d[3];
          rays->GetPixelRay(i, j, o, d);
          BruteForce(test.Volume, test.Property, o, d, bruteStep, rgba);
          largest = std::max(largest, rgba[3]);
        },
        [&](double) { return bruteTolerance; },
        std::string(test.Name) + " against brute force");
      std::cout << test.Name << ": largest difference to brute force " << worst
                << " (largest alpha " << largest << ")\n";
      check(largest > 0.2, std::string(test.Name) + ": the image is not empty");
    }
    integrator->SetCamera(camera);
    integrator->SetScalarTolerance(1.0 / 64.0);
  }
  messages.ExpectNone(check, "for the brute-force comparisons");

  //----------------------------------------------------------------------------
  // 6. Marschner-Lobb 41^3 with a narrow opacity spike: second-order convergence in
  //    ScalarTolerance. The differences between successive halvings must fall by ~4 (asserted
  //    > 2.5: kinks of the piecewise-linear transfer function and the per-cell rounding of the
  //    piece count make the ratio noisy) and the finest difference must be below 1e-4.
  vtkNew<vtkMarschnerLobbSource> marschnerLobb;
  marschnerLobb->Update();
  auto spike =
    MakeProperty({ { 0.0, 0.1, 0.2, 1.0 }, { 0.5, 1.0, 0.9, 0.3 }, { 1.0, 1.0, 0.1, 0.1 } },
      { { 0.0, 0.0 }, { 0.45, 0.0 }, { 0.5, 0.8 }, { 0.55, 0.0 }, { 1.0, 0.0 } },
      0.05);
  integrator->SetInputData(marschnerLobb->GetOutput());
  integrator->SetVolumeProperty(spike);
  const double eye[3] = { 2.2, -3.0, 1.8 }, origin[3] = { 0, 0, 0 };
  const double zUp[3] = { 0, 0, 1 };
  SetupCamera(camera, eye, origin, zUp, false, 38.0);
  integrator->SetImageSize(48, 48);
  {
    std::vector<std::vector<double>> images;
    std::vector<vtkIdType> samples;
    const auto start = std::chrono::steady_clock::now();
    for (double tolerance : { 1.0 / 8.0, 1.0 / 16.0, 1.0 / 32.0, 1.0 / 64.0 })
    {
      integrator->SetScalarTolerance(tolerance);
      images.push_back(Pixels(integrator));
      samples.push_back(integrator->GetNumberOfSamples());
    }
    const std::chrono::duration<double> elapsed = std::chrono::steady_clock::now() - start;
    double coverage = 0.0;
    for (size_t p = 3; p < images.back().size(); p += 4)
    {
      coverage = std::max(coverage, images.back()[p]);
    }
    check(coverage > 0.5,
      "the spike is visible in the Marschner-Lobb image (largest alpha " +
        std::to_string(coverage) + ")");
    std::cout << "Marschner-Lobb 41^3, 48 x 48, 4 renders in " << elapsed.count() << " s; samples";
    for (vtkIdType s : samples)
    {
      std::cout << " " << s;
    }
    std::cout << "\n";
    double previous = 0.0;
    for (size_t k = 1; k < images.size(); ++k)
    {
      const double difference = RMSE(images[k - 1], images[k]);
      std::cout << "RMSE(1/" << (4 << k) << " vs 1/" << (8 << k) << ") = " << difference;
      if (k > 1)
      {
        std::cout << ", ratio " << previous / difference;
        check(previous / difference > 2.5,
          "Marschner-Lobb: the difference falls by more than 2.5 per halving of ScalarTolerance");
      }
      std::cout << "\n";
      check(samples[k] > samples[k - 1], "Marschner-Lobb: more samples for a finer tolerance");
      previous = difference;
    }
    check(previous < 1e-4, "Marschner-Lobb: the finest difference is below 1e-4");
    check(previous > 0.0, "Marschner-Lobb: successive tolerances do change the image");
    check(samples[0] > 0, "Marschner-Lobb: NumberOfSamples > 0");
  }
  integrator->SetScalarTolerance(1.0 / 64.0);

  //----------------------------------------------------------------------------
  // 7. Perspective against parallel, same position and direction, far away (D = 1000) with
  //    the view angle matching the parallel scale: rays differ by < 1.5 / 1000 in position
  //    across the volume, so the images nearly agree; the centre pixel ray is the very same
  //    ray, so that pixel agrees exactly. A perspective with the angle taken horizontally
  //    (a wrong convention for a 41 x 25 image) must be far off.
  {
    const double far[3] = { 0.0, -1000.0, 0.0 };
    const double scale = 1.2;
    integrator->SetImageSize(41, 25);
    integrator->SetScalarTolerance(1.0 / 16.0);
    SetupCamera(camera, far, origin, zUp, true, scale);
    const std::vector<double> parallel = Pixels(integrator);
    const double angle = 2.0 * std::atan(scale / 1000.0) * 180.0 / 3.14159265358979323846;
    SetupCamera(camera, far, origin, zUp, false, angle);
    const std::vector<double> perspective = Pixels(integrator);
    SetupCamera(camera, far, origin, zUp, false, angle * 41.0 / 25.0);
    const std::vector<double> wrong = Pixels(integrator);
    const double near = RMSE(parallel, perspective), off = RMSE(parallel, wrong);
    std::cout << "RMSE parallel vs distant perspective " << near << ", vs mismatched angle " << off
              << "\n";
    check(near < 1e-3, "distant perspective nearly equals parallel (measured 1.6e-4)");
    check(off > 10.0 * near, "a mismatched view angle is clearly detected");
    const int centrePixel = 4 * (20 + 41 * 12);
    bool same = true;
    for (int k = 0; k < 4; ++k)
    {
      same = same && parallel[centrePixel + k] == perspective[centrePixel + k];
    }
    check(same, "the centre pixel is the same ray in both projections");
    integrator->SetScalarTolerance(1.0 / 64.0);
  }
  messages.ExpectNone(check, "for the Marschner-Lobb renders");

  //----------------------------------------------------------------------------
  // 8. Progress events and early ray termination.
  {
    std::vector<double> progress;
    vtkNew<vtkCallbackCommand> observer;
    observer->SetClientData(&progress);
    observer->SetCallback([](vtkObject*, unsigned long, void* client, void* data)
      { static_cast<std::vector<double>*>(client)->push_back(*static_cast<double*>(data)); });
    integrator->AddObserver(vtkCommand::ProgressEvent, observer);
    integrator->SetInputData(constant);
    integrator->SetVolumeProperty(homogeneous);
    SetupCamera(camera, above, centre, up, true, 1.25);
    integrator->SetImageSize(40, 40);
    integrator->Update();
    // The executive alone reports 0 and 1; the integrator reports after each chunk of rows.
    const auto intermediate =
      std::count_if(progress.begin(), progress.end(), [](double p) { return p > 0.0 && p < 1.0; });
    check(intermediate >= 2,
      "progress events are fired during the integration (" + std::to_string(intermediate) +
        " between 0 and 1)");
    check(std::is_sorted(progress.begin(), progress.end()), "progress never goes back");
    check(!progress.empty() && progress.back() == 1.0, "progress ends at 1");
    integrator->RemoveObserver(observer);

    // A nearly opaque medium: the transmittance falls below the cutoff in the first cell, so
    // each ray stops after one sample.
    auto opaque = MakeProperty({ { 5.0, c[0], c[1], c[2] } }, { { 5.0, 0.999 } }, 0.01);
    integrator->SetVolumeProperty(opaque);
    integrator->Update();
    check(integrator->GetNumberOfSamples() == 32 * 32,
      "opaque medium: rays stop after one cell (" +
        std::to_string(integrator->GetNumberOfSamples()) + " samples)");
    integrator->SetVolumeProperty(homogeneous);
  }
  messages.ExpectNone(check, "for the progress checks");

  //----------------------------------------------------------------------------
  // 9. Bad inputs: an error, a transparent image of the requested size, no crash.
  {
    auto expectFailure = [&](vtkImageData* input,
                           vtkVolumeProperty* property,
                           vtkCamera* cam,
                           const char* fragment,
                           const std::string& label)
    {
      vtkNew<vtkVolumeReferenceIntegrator> bad;
      bad->SetInputData(input);
      bad->SetVolumeProperty(property);
      bad->SetCamera(cam);
      bad->SetImageSize(12, 10);
      bad->Update();
      check(messages.TakeError(fragment), label + ": error mentioning '" + fragment + "'");
      CheckTransparent(bad, label);
    };
    vtkNew<vtkImageData> multi;
    multi->SetDimensions(4, 4, 4);
    multi->AllocateScalars(VTK_DOUBLE, 3);
    expectFailure(multi, homogeneous, camera, "single-component", "3-component scalars");
    vtkNew<vtkImageData> bare;
    bare->SetDimensions(4, 4, 4);
    expectFailure(bare, homogeneous, camera, "scalars", "no scalars");
    const int flatDims[3] = { 5, 5, 1 };
    auto flat = MakeVolume(flatDims, slabSpacing, lo, [](const double*) { return 5.0; });
    expectFailure(flat, homogeneous, camera, "2 points", "one voxel thick");
    vtkNew<vtkImageData> empty;
    expectFailure(empty, homogeneous, camera, "scalars", "empty image");
    expectFailure(constant, nullptr, camera, "volume property", "missing volume property");
    expectFailure(constant, homogeneous, nullptr, "camera", "missing camera");
  }

  //----------------------------------------------------------------------------
  // DepthSpread: how far the first hit moves when the isovalues move by +-IsoPerturbation of
  // the data range. One parallel ray along +x through y = z = 0.5 of a 3 x 2 x 2 grid
  // (spacing 2 along x) whose values along x are 0, 1, 0.5:
  //   - isovalue 0.5: a clean crossing at x = 1 (world), where the field rises 1/2 per world
  //     unit, so the hit moves by 1e-6 * range / (1/2) = 2e-6;
  //   - isovalue 1: the field touches it at its maximum: a shift up makes the ray miss, so
  //     the spread is infinite;
  //   - isovalue 2: a miss either way, spread 0.
  {
    const int dims[3] = { 3, 2, 2 };
    const double spacing[3] = { 2.0, 1.0, 1.0 }, zero[3] = { 0.0, 0.0, 0.0 };
    auto peak = MakeVolume(dims,
      spacing,
      zero,
      [](const double* x) { return x[0] < 1.0 ? 0.0 : (x[0] < 3.0 ? 1.0 : 0.5); });
    auto surface = MakeProperty({ { 0.0, 1.0, 1.0, 1.0 } }, { { 0.0, 1.0 } }, 1.0);
    vtkNew<vtkCamera> along;
    const double from[3] = { -5.0, 0.5, 0.5 }, to[3] = { 0.0, 0.5, 0.5 }, zUp[3] = { 0, 0, 1 };
    SetupCamera(along, from, to, zUp, true, 0.1);
    vtkNew<vtkVolumeReferenceIntegrator> spread;
    spread->SetInputData(peak);
    spread->SetVolumeProperty(surface);
    spread->SetCamera(along);
    spread->SetImageSize(1, 1);
    spread->SetBlendModeToIsoSurface();
    check(spread->GetIsoPerturbation() == 1e-6, "IsoPerturbation is 1e-6 by default");
    auto run = [&](double isovalue, double& depth)
    {
      surface->GetIsoSurfaceValues()->SetValue(0, isovalue);
      spread->Modified();
      spread->Update();
      vtkPointData* pd = spread->GetOutput()->GetPointData();
      depth = pd->GetArray("Depth")->GetComponent(0, 0);
      return pd->GetArray("DepthSpread")->GetComponent(0, 0);
    };
    double depth;
    const double crossing = run(0.5, depth);
    check.Near(depth, 6.0, 1e-6, "the ray meets isovalue 0.5 at x = 1, 6 from the camera plane");
    check.Near(crossing, 2e-6, 1e-9, "clean crossing: DepthSpread = shift / slope");
    const double touch = run(1.0, depth);
    check(std::isinf(touch) && std::abs(depth - 7.0) < 1e-6,
      "touching the maximum: a hit at x = 2 with an infinite spread (got spread " +
        std::to_string(touch) + ", depth " + std::to_string(depth) + ")");
    const double miss = run(2.0, depth);
    check(miss == 0.0 && std::isnan(depth), "a miss either way: spread 0, depth NaN");
    check(messages.Take().find("The image is transparent") != std::string::npos,
      "an image without a hit comes with a warning");
    spread->SetIsoPerturbation(0.0);
    check(run(1.0, depth) == 0.0, "IsoPerturbation 0 turns the measure off");
  }

  messages.ExpectNone(check, "at the end of the test");
  return check.Result("TestVolumeReferenceIntegrator");
}
