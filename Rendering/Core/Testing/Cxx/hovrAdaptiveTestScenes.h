// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
// Shared by the adaptive-sampling tests (CPU core and GPU pyramid): Gaussian blobs in empty
// space with an exact oracle, their transfer functions and view; and a volume whose image is
// known exactly, a constant scalar on a box of points with non-unit spacing and an offset
// origin, its transfer functions and the largest difference of an image from the exact one.
#ifndef hovrAdaptiveTestScenes_h
#define hovrAdaptiveTestScenes_h

#include "vtkCamera.h"
#include "vtkCameraRayModel.h"
#include "vtkColorTransferFunction.h"
#include "vtkFloatArray.h"
#include "vtkImageData.h"
#include "vtkNew.h"
#include "vtkPiecewiseFunction.h"
#include "vtkPointData.h"
#include "vtkSmartPointer.h"
#include "vtkVolumeProperty.h"

#include <algorithm>
#include <cmath>

namespace hovrTest
{
constexpr int BlobPoints = 64;     // points per axis
constexpr double BlobSigma = 2.5;  // blob width in voxels
constexpr double BlobOnset = 0.05; // scalar where opacity starts
constexpr double BlobCentres[4][3] = { { 18, 20, 22 },
  { 44, 30, 40 },
  { 28, 46, 34 },
  { 40, 14, 48 } };

// Gaussian blobs in empty space, spacing 1, and an exact oracle: the distance (world units) to
// the balls where the opacity varies, plus a voxel and a half for the cells touching them.
// nz points along z from z = z0 (the blobs stay where they are).
inline vtkSmartPointer<vtkImageData> MakeBlobVolume(int nz = BlobPoints, int z0 = 0)
{
  auto image = vtkSmartPointer<vtkImageData>::New();
  image->SetDimensions(BlobPoints, BlobPoints, nz);
  vtkNew<vtkFloatArray> scalars;
  scalars->SetName("Scalars");
  scalars->SetNumberOfTuples(static_cast<vtkIdType>(BlobPoints) * BlobPoints * nz);
  vtkNew<vtkFloatArray> oracle;
  oracle->SetName("OracleDistance");
  oracle->SetNumberOfTuples(scalars->GetNumberOfTuples());
  const double radius = BlobSigma * std::sqrt(2.0 * std::log(1.0 / BlobOnset)) + 1.5;
  vtkIdType id = 0;
  for (int z = z0; z < z0 + nz; ++z)
  {
    for (int y = 0; y < BlobPoints; ++y)
    {
      for (int x = 0; x < BlobPoints; ++x, ++id)
      {
        double value = 0.0, distance = 1e30;
        for (const auto& c : BlobCentres)
        {
          const double r2 =
            (x - c[0]) * (x - c[0]) + (y - c[1]) * (y - c[1]) + (z - c[2]) * (z - c[2]);
          value += std::exp(-r2 / (2.0 * BlobSigma * BlobSigma));
          distance = std::min(distance, std::max(0.0, std::sqrt(r2) - radius));
        }
        scalars->SetValue(id, static_cast<float>(value));
        oracle->SetValue(id, static_cast<float>(distance));
      }
    }
  }
  image->GetPointData()->SetScalars(scalars);
  image->GetPointData()->AddArray(oracle);
  return image;
}

// The blobs' transfer functions: opaque from BlobOnset up, colours from blue to red.
inline vtkSmartPointer<vtkVolumeProperty> MakeBlobProperty(double unitDistance)
{
  vtkNew<vtkColorTransferFunction> color;
  color->AddRGBPoint(0.0, 0.1, 0.2, 0.9);
  color->AddRGBPoint(0.5, 0.9, 0.8, 0.2);
  color->AddRGBPoint(1.0, 1.0, 0.2, 0.1);
  vtkNew<vtkPiecewiseFunction> opacity;
  opacity->AddPoint(0.0, 0.0);
  opacity->AddPoint(BlobOnset, 0.0);
  opacity->AddPoint(1.0, 0.6);
  auto property = vtkSmartPointer<vtkVolumeProperty>::New();
  property->SetColor(color);
  property->SetScalarOpacity(opacity);
  property->SetScalarOpacityUnitDistance(unitDistance);
  property->SetInterpolationTypeToLinear();
  return property;
}

// An oblique parallel view of the blob volume.
inline void MakeBlobCamera(vtkCamera* camera, double scale = 48.0)
{
  camera->SetFocalPoint(31.5, 31.5, 31.5);
  camera->SetPosition(31.5 + 100.0, 31.5 + 60.0, 31.5 + 80.0);
  camera->SetViewUp(0, 0, 1);
  camera->SetParallelProjection(true);
  camera->SetParallelScale(scale);
}

constexpr double ConstantValue = 0.5;
constexpr int ConstantDims[3] = { 40, 33, 27 };
constexpr double ConstantSpacing[3] = { 1.0, 1.25, 0.8 };
constexpr double ConstantOrigin[3] = { -5.0, 2.0, 10.0 };

// The constant volume ("Scalars", ConstantValue everywhere; with ramp, linear along x from 0
// to 1 instead) with an oracle array "OracleDistance": a constant (every pixel asks for
// 2^l_max) or a field that varies through the whole range of d, so that all levels sample.
inline vtkSmartPointer<vtkImageData> MakeConstantVolume(bool varyingOracle, bool ramp = false)
{
  auto image = vtkSmartPointer<vtkImageData>::New();
  image->SetDimensions(ConstantDims[0], ConstantDims[1], ConstantDims[2]);
  image->SetSpacing(ConstantSpacing[0], ConstantSpacing[1], ConstantSpacing[2]);
  image->SetOrigin(ConstantOrigin[0], ConstantOrigin[1], ConstantOrigin[2]);
  const vtkIdType n = image->GetNumberOfPoints();
  vtkNew<vtkFloatArray> scalars;
  scalars->SetName("Scalars");
  scalars->SetNumberOfTuples(n);
  scalars->FillValue(static_cast<float>(ConstantValue));
  if (ramp)
  {
    for (vtkIdType id = 0; id < n; ++id)
    {
      scalars->SetValue(id, static_cast<float>((id % ConstantDims[0]) / (ConstantDims[0] - 1.0)));
    }
  }
  vtkNew<vtkFloatArray> oracle;
  oracle->SetName("OracleDistance");
  oracle->SetNumberOfTuples(n);
  for (vtkIdType id = 0; id < n; ++id)
  {
    double p[3];
    image->GetPoint(id, p);
    oracle->SetValue(id,
      varyingOracle
        ? static_cast<float>(std::fmod(0.37 * p[0] + 0.23 * p[1] + 0.11 * p[2] + 50.0, 7.0))
        : 1000.0f);
  }
  image->GetPointData()->SetScalars(scalars);
  image->GetPointData()->AddArray(oracle);
  return image;
}

// The constant volume's transfer functions: one colour, opacity 0.2 at ConstantValue (0.4 at
// 1), unit distance 15.
inline void MakeConstantProperty(vtkVolumeProperty* flat)
{
  vtkNew<vtkColorTransferFunction> color;
  color->AddRGBPoint(0.0, 0.9, 0.6, 0.3);
  color->AddRGBPoint(1.0, 0.9, 0.6, 0.3);
  vtkNew<vtkPiecewiseFunction> opacity;
  opacity->AddPoint(0.0, 0.0);
  opacity->AddPoint(1.0, 0.4);
  flat->SetColor(color);
  flat->SetScalarOpacity(opacity);
  flat->SetScalarOpacityUnitDistance(15.0);
}

// Largest difference, over the pixels and channels of the size x size float "RGBA" image,
// from the constant volume's exact image: opacity 1 - exp(-sigma chord), with the chord of the
// pixel's ray through the box of points and sigma = -ln(1 - alpha(c)) / U, colour rgb(c) times
// that opacity. A missing image or a value that is not finite counts as 1e30.
inline double ConstantVolumeError(vtkImageData* image,
  vtkImageData* volume,
  vtkVolumeProperty* property,
  vtkCamera* camera,
  int size)
{
  vtkNew<vtkCameraRayModel> rays;
  rays->SetCamera(camera);
  rays->SetImageSize(size, size);
  rays->Prepare();
  double bounds[6];
  volume->GetBounds(bounds);
  const double alpha = property->GetScalarOpacity()->GetValue(ConstantValue);
  const double sigma = -std::log(1.0 - alpha) / property->GetScalarOpacityUnitDistance();
  double rgb[3];
  property->GetRGBTransferFunction()->GetColor(ConstantValue, rgb);
  vtkFloatArray* rgba =
    image ? vtkFloatArray::SafeDownCast(image->GetPointData()->GetArray("RGBA")) : nullptr;
  if (!rgba || rgba->GetNumberOfTuples() != static_cast<vtkIdType>(size) * size)
  {
    return 1e30;
  }
  double worst = 0.0;
  for (int j = 0; j < size; ++j)
  {
    for (int i = 0; i < size; ++i)
    {
      double o[3], v[3];
      rays->GetPixelRay(i, j, o, v);
      double t0 = -1e300, t1 = 1e300;
      for (int a = 0; a < 3; ++a)
      {
        if (v[a] == 0.0)
        {
          t1 = o[a] < bounds[2 * a] || o[a] > bounds[2 * a + 1] ? -1e300 : t1;
          continue;
        }
        const double ta = (bounds[2 * a] - o[a]) / v[a], tb = (bounds[2 * a + 1] - o[a]) / v[a];
        t0 = std::max(t0, std::min(ta, tb));
        t1 = std::min(t1, std::max(ta, tb));
      }
      const double opacity = -std::expm1(-sigma * std::max(t1 - t0, 0.0));
      const double expected[4] = { rgb[0] * opacity, rgb[1] * opacity, rgb[2] * opacity, opacity };
      for (int c = 0; c < 4; ++c)
      {
        const double value = rgba->GetComponent(static_cast<vtkIdType>(j) * size + i, c);
        worst = std::max(worst, std::isfinite(value) ? std::abs(value - expected[c]) : 1e30);
      }
    }
  }
  return worst;
}
}

#endif // hovrAdaptiveTestScenes_h
