// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
// Proves that vtkFloatRGBARenderCapture reads what VTK drew at float precision: an unlit
// polygon of colour (0.3, 0.6, 0.9) comes back to 1e-6 (an 8-bit buffer is off by up to
// 1/510), a translucent one as the exact blend result, the background as transparent
// black, pixel (i, j) counted from left and bottom; that the window's own 8-bit image agrees
// within 1/255; and that misuse (multisampled window, no window, capture before attach) fails
// with an error instead of returning garbage.
#include "hovrRenderTestUtilities.h"

#include "vtkActor.h"
#include "vtkCellArray.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkPolyDataMapper.h"
#include "vtkProperty.h"
#include "vtkUnsignedCharArray.h"
#include "vtkWindowToImageFilter.h"

#include <iostream>
#include <sstream>

namespace
{
// An unlit quad of colour (0.3, 0.6, 0.9) spanning [x0, x0 + 1] x [y0, y0 + 1] at z = 0.
vtkSmartPointer<vtkActor> MakeQuad(double x0, double y0, double opacity)
{
  vtkNew<vtkPoints> points;
  points->InsertNextPoint(x0, y0, 0.0);
  points->InsertNextPoint(x0 + 1.0, y0, 0.0);
  points->InsertNextPoint(x0 + 1.0, y0 + 1.0, 0.0);
  points->InsertNextPoint(x0, y0 + 1.0, 0.0);
  vtkNew<vtkCellArray> polygons;
  const vtkIdType corners[4] = { 0, 1, 2, 3 };
  polygons->InsertNextCell(4, corners);
  vtkNew<vtkPolyData> quad;
  quad->SetPoints(points);
  quad->SetPolys(polygons);
  vtkNew<vtkPolyDataMapper> mapper;
  mapper->SetInputData(quad);
  auto actor = vtkSmartPointer<vtkActor>::New();
  actor->SetMapper(mapper);
  actor->GetProperty()->LightingOff();
  actor->GetProperty()->SetColor(0.3, 0.6, 0.9);
  actor->GetProperty()->SetOpacity(opacity);
  return actor;
}

void GetPixel(vtkImageData* image, int i, int j, double rgba[4])
{
  int dims[3];
  image->GetDimensions(dims);
  hovrTest::GetRGBA(image)->GetTuple(static_cast<vtkIdType>(j) * dims[0] + i, rgba);
}

// Checks every channel of pixel (i, j) against expected within tolerance.
void CheckPixel(hovrTest::Checker& check,
  vtkImageData* image,
  int i,
  int j,
  const double expected[4],
  double tolerance,
  const std::string& what)
{
  double rgba[4];
  GetPixel(image, i, j, rgba);
  for (int c = 0; c < 4; ++c)
  {
    std::ostringstream label;
    label << what << ", pixel (" << i << ", " << j << ") channel " << c;
    check.Near(rgba[c], expected[c], tolerance, label.str());
  }
}
}

int TestFloatRGBARenderCapture(int, char*[])
{
  hovrTest::Checker check;
  const int size = 128;
  hovrTest::FloatRenderView view;
  vtkNew<vtkTest::ErrorObserver> errors;
  hovrTest::Observe(view.GetCapture(), errors);
  check(view.Initialize(size, size), "Attach on a single-sampled window");
  hovrTest::ExpectQuiet(check, errors, "Attach");

  // World [-1, 1]^2 fills the window: pixel i covers x in [-1 + 2i/128, -1 + 2(i+1)/128].
  vtkCamera* camera = view.GetCamera();
  camera->ParallelProjectionOn();
  camera->SetParallelScale(1.0);
  camera->SetPosition(0.0, 0.0, 5.0);
  camera->SetFocalPoint(0.0, 0.0, 0.0);
  camera->SetViewUp(0.0, 1.0, 0.0);
  // Opaque quad in the lower left quarter, half-transparent one in the upper right quarter.
  view.GetRenderer()->AddActor(MakeQuad(-1.0, -1.0, 1.0));
  view.GetRenderer()->AddActor(MakeQuad(0.0, 0.0, 0.5));

  auto image = view.Render();
  hovrTest::ExpectQuiet(check, errors, "Capture");
  if (!check(image != nullptr, "Capture succeeds after Attach"))
  {
    return check.Result("TestFloatRGBARenderCapture");
  }
  int dims[3];
  image->GetDimensions(dims);
  check(dims[0] == size && dims[1] == size && dims[2] == 1, "image has the window's size");
  vtkFloatArray* rgba = hovrTest::GetRGBA(image);
  check(rgba && rgba->GetNumberOfComponents() == 4, "float RGBA array named \"RGBA\"");

  // Float precision: 1e-6 is a few float ulps; the nearest 8-bit value of 0.3 is 0.00196 off.
  const double opaque[4] = { 0.3, 0.6, 0.9, 1.0 };
  // Opacity 0.5 over transparent black: colour 0.5 * (0.3, 0.6, 0.9). VTK blends the alpha
  // of translucent polygons with the source-alpha factor too, leaving 0.5 * 0.5 (volume
  // mappers leave 1 - transmittance instead).
  const double translucent[4] = { 0.15, 0.3, 0.45, 0.25 };
  const double background[4] = { 0.0, 0.0, 0.0, 0.0 };
  CheckPixel(check, image, 32, 32, opaque, 1e-6, "opaque quad (lower left)");
  CheckPixel(check, image, 1, 1, opaque, 1e-6, "opaque quad, corner pixel (lower left)");
  CheckPixel(check, image, 96, 96, translucent, 1e-6, "translucent quad (upper right)");
  CheckPixel(check, image, 96, 32, background, 0.0, "background (lower right)");
  CheckPixel(check, image, 32, 96, background, 0.0, "background (upper left)");

  // The window's 8-bit image of the same frame agrees within one 8-bit step everywhere.
  vtkNew<vtkWindowToImageFilter> grab;
  grab->SetInput(view.GetWindow());
  grab->SetInputBufferTypeToRGBA();
  grab->ReadFrontBufferOff();
  grab->ShouldRerenderOff();
  grab->Update();
  vtkDataArray* bytes = grab->GetOutput()->GetPointData()->GetScalars();
  double worst = -1.0;
  if (check(bytes && bytes->GetNumberOfTuples() == rgba->GetNumberOfTuples() &&
          bytes->GetNumberOfComponents() == 4,
        "8-bit RGBA window image of the same size"))
  {
    worst = 0.0;
    for (vtkIdType v = 0; v < rgba->GetNumberOfValues(); ++v)
    {
      worst =
        std::max(worst, std::abs(bytes->GetComponent(v / 4, v % 4) / 255.0 - rgba->GetValue(v)));
    }
    // The 8-bit image cannot hold 0.3: proof that the float capture does not read it.
    check(std::abs(bytes->GetComponent(32 * size + 32, 0) / 255.0 - 0.3) > 1e-3,
      "the 8-bit red of 0.3 is more than 1e-3 off");
  }
  std::cout << "largest float - 8-bit difference: " << worst << " (" << worst * 255.0
            << " 8-bit steps)\n";
  check(worst >= 0.0 && worst <= 1.0 / 255.0, "8-bit window image within 1/255 of the float one");

  // A resized window: the float attachment follows the size.
  view.GetWindow()->SetSize(96, 64);
  auto resized = view.Render();
  errors->Clear();
  if (check(resized != nullptr, "Capture after a resize"))
  {
    resized->GetDimensions(dims);
    check(dims[0] == 96 && dims[1] == 64, "captured image follows the new window size");
  }

  // Misuse reports errors and returns false.
  vtkNew<vtkRenderWindow> multisampled;
  multisampled->SetOffScreenRendering(1);
  multisampled->SetMultiSamples(4);
  vtkNew<vtkFloatRGBARenderCapture> msCapture;
  hovrTest::Observe(msCapture, errors);
  check(!msCapture->Attach(multisampled), "Attach on a multisampled window fails");
  hovrTest::ExpectError(check, errors, "SetMultiSamples(0)", "Attach on a multisampled window");
  check(!msCapture->Attach(nullptr), "Attach without a window fails");
  hovrTest::ExpectError(check, errors, "OpenGL render window", "Attach(nullptr)");

  vtkNew<vtkFloatRGBARenderCapture> unattached;
  hovrTest::Observe(unattached, errors);
  vtkNew<vtkImageData> nothing;
  check(!unattached->Capture(nothing), "Capture before Attach fails");
  hovrTest::ExpectError(check, errors, "call Attach()", "Capture before Attach");
  check(nothing->GetNumberOfPoints() == 0, "a failed Capture leaves the image empty");
  check(!view.GetCapture()->Capture(nullptr), "Capture into nullptr fails");
  hovrTest::ExpectError(check, errors, "call Attach()", "Capture(nullptr)");

  return check.Result("TestFloatRGBARenderCapture");
}
