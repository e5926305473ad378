// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
// Shared by the hovr OpenGL tests: the test scene (Marschner-Lobb volume, narrow-spike
// transfer function, oblique camera), an offscreen window that renders into float RGBA the way
// hovr.methods.Renderer does, the CPU reference and the error metrics. The check counter and
// the message capture come from the GL-free tests (Rendering/Core/Testing/Cxx).
#ifndef hovrRenderTestUtilities_h
#define hovrRenderTestUtilities_h

#include "hovrTestUtilities.h"

#include "vtkCamera.h"
#include "vtkColorTransferFunction.h"
#include "vtkDataArray.h"
#include "vtkFloatArray.h"
#include "vtkFloatRGBARenderCapture.h"
#include "vtkImageData.h"
#include "vtkMarschnerLobbSource.h"
#include "vtkMath.h"
#include "vtkNew.h"
#include "vtkPiecewiseFunction.h"
#include "vtkPointData.h"
#include "vtkRGBAErrorMetrics.h"
#include "vtkRenderWindow.h"
#include "vtkRenderer.h"
#include "vtkSmartPointer.h"
#include "vtkTestErrorObserver.h"
#include "vtkVolumeProperty.h"
#include "vtkVolumeReferenceIntegrator.h"

#include <algorithm>
#include <cmath>
#include <string>

namespace hovrTest
{
// Checks that observer caught an error containing fragment since its last Clear(); clears it.
inline bool ExpectError(Checker& check,
  vtkTest::ErrorObserver* observer,
  const std::string& fragment,
  const std::string& what)
{
  const std::string message = observer->GetErrorMessage();
  const bool ok = observer->GetError() && message.find(fragment) != std::string::npos;
  observer->Clear();
  return check(ok, what + ": an error containing \"" + fragment + "\", got [" + message + "]");
}

// Checks that observer caught a warning containing fragment and no error; clears it.
inline bool ExpectWarning(Checker& check,
  vtkTest::ErrorObserver* observer,
  const std::string& fragment,
  const std::string& what)
{
  const std::string message = observer->GetWarningMessage();
  const bool ok =
    observer->GetWarning() && !observer->GetError() && message.find(fragment) != std::string::npos;
  const std::string error = observer->GetErrorMessage();
  observer->Clear();
  return check(ok,
    what + ": a warning containing \"" + fragment + "\", got [" + message + "], errors [" + error +
      "]");
}

// Checks that observer caught neither error nor warning; clears it.
inline bool ExpectQuiet(Checker& check, vtkTest::ErrorObserver* observer, const std::string& what)
{
  const std::string message = observer->GetErrorMessage() + observer->GetWarningMessage();
  const bool ok = !observer->GetError() && !observer->GetWarning();
  observer->Clear();
  return check(ok, what + ": no error or warning, got [" + message + "]");
}

// Observes errors and warnings of object (they are then not printed).
inline void Observe(vtkObject* object, vtkTest::ErrorObserver* observer)
{
  object->AddObserver(vtkCommand::ErrorEvent, observer);
  object->AddObserver(vtkCommand::WarningEvent, observer);
}

// The transfer function of presets/transfer-functions/marschner-lobb-spikes.json (opacity
// spikes at 0.25, 0.5, 0.75 of half width 0.02), its scalar axis mapped from [0, 1] to
// [lo, hi]. Linear interpolation, no shading, as hovr.io.make_volume_property.
inline vtkSmartPointer<vtkVolumeProperty> MakeSpikeProperty(double lo = 0.0,
  double hi = 1.0,
  double unitDistance = 0.05)
{
  auto at = [lo, hi](double x) { return lo + x * (hi - lo); };
  vtkNew<vtkColorTransferFunction> color;
  color->SetColorSpaceToRGB();
  color->AddRGBPoint(at(0.0), 0.2, 0.3, 1.0);
  color->AddRGBPoint(at(0.35), 0.1, 0.9, 0.3);
  color->AddRGBPoint(at(0.7), 1.0, 0.8, 0.1);
  color->AddRGBPoint(at(1.0), 1.0, 0.1, 0.1);
  vtkNew<vtkPiecewiseFunction> opacity;
  const double nodes[][2] = { { 0.0, 0.0 },
    { 0.23, 0.0 },
    { 0.25, 0.5 },
    { 0.27, 0.0 },
    { 0.48, 0.0 },
    { 0.5, 0.7 },
    { 0.52, 0.0 },
    { 0.73, 0.0 },
    { 0.75, 0.9 },
    { 0.77, 0.0 },
    { 1.0, 0.0 } };
  for (const auto& node : nodes)
  {
    opacity->AddPoint(at(node[0]), node[1]);
  }
  auto property = vtkSmartPointer<vtkVolumeProperty>::New();
  property->SetColor(color);
  property->SetScalarOpacity(opacity);
  property->SetScalarOpacityUnitDistance(unitDistance);
  property->SetInterpolationTypeToLinear();
  property->ShadeOff();
  return property;
}

// The Marschner-Lobb volume on [-1, 1]^3 (values in [0, 1] for float and double).
inline vtkSmartPointer<vtkImageData> MakeMarschnerLobb(int n = 41, int scalarType = VTK_FLOAT)
{
  vtkNew<vtkMarschnerLobbSource> source;
  source->SetDimensions(n, n, n);
  source->SetOutputScalarType(scalarType);
  source->Update();
  auto image = vtkSmartPointer<vtkImageData>::New();
  image->DeepCopy(source->GetOutput());
  return image;
}

// A copy of image whose scalars are of scalarType, holding round(value * scale + shift) for
// integer types and value * scale + shift for floating-point ones.
inline vtkSmartPointer<vtkImageData> ConvertScalars(vtkImageData* image,
  int scalarType,
  double scale,
  double shift)
{
  vtkDataArray* in = image->GetPointData()->GetScalars();
  auto out = vtkSmartPointer<vtkDataArray>::Take(vtkDataArray::CreateDataArray(scalarType));
  out->SetName(in->GetName());
  out->SetNumberOfComponents(1);
  out->SetNumberOfTuples(in->GetNumberOfTuples());
  const bool integer = scalarType != VTK_FLOAT && scalarType != VTK_DOUBLE;
  for (vtkIdType i = 0; i < in->GetNumberOfTuples(); ++i)
  {
    const double value = in->GetComponent(i, 0) * scale + shift;
    out->SetComponent(i, 0, integer ? std::round(value) : value);
  }
  auto result = vtkSmartPointer<vtkImageData>::New();
  result->CopyStructure(image);
  result->GetPointData()->SetScalars(out);
  return result;
}

// hovr.io.default_camera: an oblique perspective camera (view angle 30 degrees) that frames
// the bounding sphere of bounds.
inline void SetObliqueCamera(vtkCamera* camera, const double bounds[6])
{
  const double direction[3] = { 1.0, -1.6, 0.9 };
  const double norm = vtkMath::Norm(direction);
  double center[3];
  double radius = 0.0;
  for (int a = 0; a < 3; ++a)
  {
    center[a] = 0.5 * (bounds[2 * a] + bounds[2 * a + 1]);
    radius += (bounds[2 * a + 1] - bounds[2 * a]) * (bounds[2 * a + 1] - bounds[2 * a]);
  }
  radius = 0.5 * std::sqrt(radius);
  const double angle = 30.0;
  const double distance = radius / std::sin(vtkMath::RadiansFromDegrees(angle) / 2.0) * 1.02;
  camera->SetFocalPoint(center);
  camera->SetPosition(center[0] + distance * direction[0] / norm,
    center[1] + distance * direction[1] / norm,
    center[2] + distance * direction[2] / norm);
  camera->SetViewUp(0.0, 0.0, 1.0);
  camera->SetViewAngle(angle);
  camera->SetParallelProjection(false);
}

// An offscreen window that draws into float RGBA over a transparent black background, set up
// as hovr.methods.Renderer does for GPU methods.
class FloatRenderView
{
public:
  // Returns false when the float colour buffer could not be attached.
  bool Initialize(int width, int height)
  {
    this->Window->SetOffScreenRendering(1);
    this->Window->SetMultiSamples(0);
    this->Window->SetAlphaBitPlanes(1);
    this->Window->SetSize(width, height);
    this->Renderer->SetBackground(0.0, 0.0, 0.0);
    this->Renderer->SetBackgroundAlpha(0.0);
    this->Window->AddRenderer(this->Renderer);
    return this->Capture->Attach(this->Window);
  }

  vtkRenderWindow* GetWindow() { return this->Window; }
  vtkRenderer* GetRenderer() { return this->Renderer; }
  vtkCamera* GetCamera() { return this->Renderer->GetActiveCamera(); }
  vtkFloatRGBARenderCapture* GetCapture() { return this->Capture; }

  // Renders one frame and returns its float RGBA ("RGBA" point data), nullptr on failure.
  vtkSmartPointer<vtkImageData> Render()
  {
    this->Renderer->ResetCameraClippingRange();
    this->Window->Render();
    this->Window->WaitForCompletion();
    auto image = vtkSmartPointer<vtkImageData>::New();
    if (!this->Capture->Capture(image))
    {
      return nullptr;
    }
    return image;
  }

private:
  vtkNew<vtkRenderWindow> Window;
  vtkNew<vtkRenderer> Renderer;
  vtkNew<vtkFloatRGBARenderCapture> Capture;
};

// The CPU ground truth for the same scene.
// Its ScalarTolerance is 1/16 instead of 1/64: a quarter of the integration pieces, and it
// moves the ML spike image by an RMSE of about 5e-5, 100x below the errors the tests bound.
inline vtkSmartPointer<vtkImageData> RenderReference(vtkImageData* volume,
  vtkVolumeProperty* property,
  vtkCamera* camera,
  int width,
  int height)
{
  vtkNew<vtkVolumeReferenceIntegrator> integrator;
  integrator->SetInputData(volume);
  integrator->SetVolumeProperty(property);
  integrator->SetCamera(camera);
  integrator->SetImageSize(width, height);
  integrator->SetScalarTolerance(1.0 / 16.0);
  integrator->Update();
  auto image = vtkSmartPointer<vtkImageData>::New();
  image->DeepCopy(integrator->GetOutput());
  return image;
}

// RMSE over all pixels and channels (vtkRGBAErrorMetrics); -1 when the images do not match
// in size or lack "RGBA". With maximum, also the largest absolute difference.
inline double RMSE(vtkImageData* test, vtkImageData* reference, double* maximum = nullptr)
{
  if (!test || !reference)
  {
    return -1.0;
  }
  vtkNew<vtkRGBAErrorMetrics> metrics;
  metrics->SetInputData(test);
  metrics->SetReferenceData(reference);
  metrics->Update();
  if (maximum)
  {
    *maximum = metrics->GetMaximumError();
  }
  return metrics->GetRMSE();
}

inline vtkFloatArray* GetRGBA(vtkImageData* image)
{
  return image ? vtkFloatArray::SafeDownCast(image->GetPointData()->GetArray("RGBA")) : nullptr;
}

// Pixels whose alpha exceeds threshold (the volume is drawn there).
inline vtkIdType CountCovered(vtkImageData* image, double threshold = 1e-3)
{
  vtkFloatArray* rgba = GetRGBA(image);
  vtkIdType count = 0;
  for (vtkIdType i = 0; rgba && i < rgba->GetNumberOfTuples(); ++i)
  {
    count += rgba->GetValue(4 * i + 3) > threshold ? 1 : 0;
  }
  return count;
}

// Largest absolute channel value; 0 for an image left at the transparent black background.
inline double MaximumValue(vtkImageData* image)
{
  vtkFloatArray* rgba = GetRGBA(image);
  double maximum = rgba ? 0.0 : -1.0;
  for (vtkIdType i = 0; rgba && i < rgba->GetNumberOfValues(); ++i)
  {
    maximum = std::max(maximum, static_cast<double>(std::abs(rgba->GetValue(i))));
  }
  return maximum;
}

// True if every channel of every pixel is finite.
inline bool AllFinite(vtkImageData* image)
{
  vtkFloatArray* rgba = GetRGBA(image);
  for (vtkIdType i = 0; rgba && i < rgba->GetNumberOfValues(); ++i)
  {
    if (!std::isfinite(rgba->GetValue(i)))
    {
      return false;
    }
  }
  return rgba != nullptr;
}
}

#endif
