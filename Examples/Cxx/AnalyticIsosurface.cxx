// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
// Example: the exact first-hit isosurface of a volume with features thinner than a voxel
// (vtkAnalyticVolumeMapper), next to VTK's sampled isosurface at a quarter voxel; counts the
// surface pixels each misses against the reference integrator's float64 first hits and saves
// a PNG of the analytic image.
//
//   AnalyticIsosurface [output.png]
#include "vtkAnalyticVolumeMapper.h"
#include "vtkCamera.h"
#include "vtkColorTransferFunction.h"
#include "vtkContourValues.h"
#include "vtkDataArray.h"
#include "vtkFloatRGBARenderCapture.h"
#include "vtkImageData.h"
#include "vtkNew.h"
#include "vtkPNGWriter.h"
#include "vtkPiecewiseFunction.h"
#include "vtkPointData.h"
#include "vtkRenderWindow.h"
#include "vtkRenderer.h"
#include "vtkThinFeatureSource.h"
#include "vtkVolume.h"
#include "vtkVolumeProperty.h"
#include "vtkVolumeReferenceIntegrator.h"
#include "vtkWindowToImageFilter.h"

#include <cmath>
#include <cstdlib>
#include <iostream>
#include <string>

namespace
{
const int Size = 320;

// Draws the thin features with one mapper into the window.
void Draw(vtkAnalyticVolumeMapper* mapper,
  vtkThinFeatureSource* source,
  vtkVolumeProperty* property,
  vtkRenderer* renderer,
  vtkRenderWindow* window)
{
  mapper->SetInputConnection(source->GetOutputPort());
  mapper->SetBlendModeToIsoSurface();
  mapper->SetAutoAdjustSampleDistances(0);
  vtkNew<vtkVolume> volume;
  volume->SetMapper(mapper);
  volume->SetProperty(property);
  renderer->RemoveAllViewProps();
  renderer->AddVolume(volume);
  renderer->ResetCameraClippingRange();
  window->Render();
}

// Pixels the reference hits and the mapper does not (its hit positions have w = 0).
int CountMissed(vtkAnalyticVolumeMapper* mapper,
  vtkThinFeatureSource* source,
  vtkVolumeProperty* property,
  vtkRenderer* renderer,
  vtkRenderWindow* window,
  vtkFloatRGBARenderCapture* capture,
  vtkDataArray* depth)
{
  mapper->SetOutputQuantity(vtkAnalyticVolumeMapper::OUTPUT_POSITION);
  Draw(mapper, source, property, renderer, window);
  mapper->SetOutputQuantity(vtkAnalyticVolumeMapper::OUTPUT_COLOR);
  vtkNew<vtkImageData> image;
  capture->Capture(image);
  vtkDataArray* positions = image->GetPointData()->GetScalars();
  int missed = 0;
  for (vtkIdType p = 0; p < positions->GetNumberOfTuples(); ++p)
  {
    missed += !std::isnan(depth->GetComponent(p, 0)) && !(positions->GetComponent(p, 3) > 0);
  }
  return missed;
}
}

int main(int argc, char* argv[])
{
  const std::string output = argc > 1 ? argv[1] : "AnalyticIsosurface.png";

  // Sheets and tubes thinner than a voxel: the isosurface 0.5 forms films and threads.
  vtkNew<vtkThinFeatureSource> source;
  source->SetDimensions(64, 64, 64);
  vtkNew<vtkColorTransferFunction> color;
  color->AddRGBPoint(0.0, 0.95, 0.85, 0.65);
  color->AddRGBPoint(1.0, 0.95, 0.85, 0.65);
  vtkNew<vtkPiecewiseFunction> opacity; // VTK's isosurface shows crossings with this opacity
  opacity->AddPoint(0.0, 1.0);
  opacity->AddPoint(1.0, 1.0);
  vtkNew<vtkVolumeProperty> property;
  property->SetColor(color);
  property->SetScalarOpacity(opacity);
  property->SetInterpolationTypeToLinear();
  property->ShadeOn();
  property->GetIsoSurfaceValues()->SetValue(0, 0.5);

  vtkNew<vtkRenderWindow> window;
  window->SetOffScreenRendering(1);
  window->SetMultiSamples(0);
  window->SetSize(Size, Size);
  vtkNew<vtkRenderer> renderer;
  renderer->SetBackground(0, 0, 0);
  window->AddRenderer(renderer);
  vtkCamera* camera = renderer->GetActiveCamera();
  camera->SetPosition(150.0, -120.0, 140.0);
  camera->SetFocalPoint(31.5, 31.5, 31.5);
  camera->SetViewUp(0, 0, 1);
  camera->SetViewAngle(30);
  vtkNew<vtkFloatRGBARenderCapture> capture; // float buffer: positions, not 8-bit colours
  if (!capture->Attach(window))
  {
    return EXIT_FAILURE;
  }

  vtkNew<vtkVolumeReferenceIntegrator> reference;
  reference->SetInputConnection(source->GetOutputPort());
  reference->SetVolumeProperty(property);
  reference->SetCamera(camera);
  reference->SetImageSize(Size, Size);
  reference->SetBlendModeToIsoSurface();
  reference->Update();
  vtkDataArray* depth = reference->GetOutput()->GetPointData()->GetArray("Depth");
  int surface = 0;
  for (vtkIdType p = 0; p < depth->GetNumberOfTuples(); ++p)
  {
    surface += !std::isnan(depth->GetComponent(p, 0));
  }

  vtkNew<vtkAnalyticVolumeMapper> stock;
  stock->SetMethodToStock();      // VTK's own ISOSURFACE_BLEND shader, observed
  stock->SetSampleDistance(0.25); // a quarter voxel (spacing 1)
  vtkNew<vtkAnalyticVolumeMapper> analytic;
  const int stockMissed = CountMissed(stock, source, property, renderer, window, capture, depth);
  const int analyticMissed =
    CountMissed(analytic, source, property, renderer, window, capture, depth);
  std::cout << "reference surface pixels: " << surface << "; missed surface pixels: stock "
            << stockMissed << ", analytic " << analyticMissed << "\n";

  Draw(analytic, source, property, renderer, window);
  vtkNew<vtkWindowToImageFilter> grab;
  grab->SetInput(window);
  grab->ReadFrontBufferOff();
  vtkNew<vtkPNGWriter> writer;
  writer->SetFileName(output.c_str());
  writer->SetInputConnection(grab->GetOutputPort());
  writer->Write();
  std::cout << "wrote " << output << "\n";
  return analyticMissed < stockMissed ? EXIT_SUCCESS : EXIT_FAILURE;
}
