// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
// Example: render the Marschner-Lobb volume with first- and second-order pre-integration,
// measure their errors against the reference integrator next to VTK's stock mapper, and save
// a PNG of the second-order image.
//
//   PreIntegratedVolume [output.png] [step in voxels]
#include "vtkCamera.h"
#include "vtkColorTransferFunction.h"
#include "vtkFirstOrderPreIntegrationTable.h"
#include "vtkFloatRGBARenderCapture.h"
#include "vtkImageData.h"
#include "vtkMarschnerLobbSource.h"
#include "vtkNew.h"
#include "vtkOpenGLGPUVolumeRayCastMapper.h"
#include "vtkPNGWriter.h"
#include "vtkPiecewiseFunction.h"
#include "vtkPreIntegrationVolumeMapper.h"
#include "vtkRGBAErrorMetrics.h"
#include "vtkRenderWindow.h"
#include "vtkRenderer.h"
#include "vtkSecondOrderPreIntegrationTable.h"
#include "vtkVolume.h"
#include "vtkVolumeProperty.h"
#include "vtkVolumeReferenceIntegrator.h"
#include "vtkWindowToImageFilter.h"

#include <cstdlib>
#include <iostream>
#include <string>

namespace
{
// Renders the scene with one mapper and returns its RMSE against the reference.
double RenderAndMeasure(vtkGPUVolumeRayCastMapper* mapper,
  vtkMarschnerLobbSource* source,
  vtkVolumeProperty* property,
  vtkRenderer* renderer,
  vtkRenderWindow* window,
  vtkFloatRGBARenderCapture* capture,
  vtkVolumeReferenceIntegrator* reference,
  double step)
{
  mapper->SetInputConnection(source->GetOutputPort());
  mapper->SetAutoAdjustSampleDistances(0);
  mapper->SetSampleDistance(step * 2.0 / 40.0);
  vtkNew<vtkVolume> volume;
  volume->SetMapper(mapper);
  volume->SetProperty(property);
  renderer->RemoveAllViewProps();
  renderer->AddVolume(volume);
  renderer->ResetCameraClippingRange();
  window->Render();
  vtkNew<vtkImageData> image;
  capture->Capture(image);
  vtkNew<vtkRGBAErrorMetrics> metrics;
  metrics->SetInputData(image);
  metrics->SetReferenceConnection(reference->GetOutputPort());
  metrics->Update();
  return metrics->GetRMSE();
}
}

int main(int argc, char* argv[])
{
  const std::string output = argc > 1 ? argv[1] : "PreIntegratedVolume.png";
  const double step = argc > 2 ? std::atof(argv[2]) : 1.0;
  if (!(step > 0.0))
  {
    std::cerr << "The step must be positive.\n";
    return EXIT_FAILURE;
  }

  vtkNew<vtkMarschnerLobbSource> source;
  source->SetDimensions(41, 41, 41);

  // Three narrow opacity spikes: point sampling misses them between samples.
  vtkNew<vtkColorTransferFunction> color;
  color->AddRGBPoint(0.0, 0.2, 0.3, 1.0);
  color->AddRGBPoint(0.5, 0.1, 0.9, 0.3);
  color->AddRGBPoint(1.0, 1.0, 0.1, 0.1);
  vtkNew<vtkPiecewiseFunction> opacity;
  const double centres[3] = { 0.25, 0.5, 0.75 }, peaks[3] = { 0.5, 0.7, 0.9 };
  for (int i = 0; i < 3; ++i)
  {
    opacity->AddPoint(centres[i] - 0.02, 0.0);
    opacity->AddPoint(centres[i], peaks[i]);
    opacity->AddPoint(centres[i] + 0.02, 0.0);
  }
  vtkNew<vtkVolumeProperty> property;
  property->SetColor(color);
  property->SetScalarOpacity(opacity);
  property->SetScalarOpacityUnitDistance(0.05);
  property->SetInterpolationTypeToLinear();

  vtkNew<vtkRenderWindow> window;
  window->SetOffScreenRendering(1);
  window->SetMultiSamples(0);
  window->SetSize(320, 320);
  vtkNew<vtkRenderer> renderer;
  renderer->SetBackground(0, 0, 0);
  renderer->SetBackgroundAlpha(0);
  window->AddRenderer(renderer);
  vtkCamera* camera = renderer->GetActiveCamera();
  camera->SetPosition(2.5, -4.0, 2.2);
  camera->SetFocalPoint(0, 0, 0);
  camera->SetViewUp(0, 0, 1);
  camera->SetViewAngle(30);

  vtkNew<vtkFloatRGBARenderCapture> capture;
  if (!capture->Attach(window))
  {
    return EXIT_FAILURE;
  }
  vtkNew<vtkVolumeReferenceIntegrator> reference;
  reference->SetInputConnection(source->GetOutputPort());
  reference->SetVolumeProperty(property);
  reference->SetCamera(camera);
  reference->SetImageSize(320, 320);
  reference->Update();

  vtkNew<vtkOpenGLGPUVolumeRayCastMapper> stock;
  const double stockRMSE =
    RenderAndMeasure(stock, source, property, renderer, window, capture, reference, step);
  vtkNew<vtkPreIntegrationVolumeMapper> preint;
  const double preintRMSE =
    RenderAndMeasure(preint, source, property, renderer, window, capture, reference, step);
  vtkNew<vtkPreIntegrationVolumeMapper> secondOrder;
  secondOrder->SetIntegrationToSecondOrder();
  const double secondRMSE =
    RenderAndMeasure(secondOrder, source, property, renderer, window, capture, reference, step);
  std::cout << "step " << step << " voxel: RMSE stock " << stockRMSE
            << ", first-order pre-integration " << preintRMSE << ", second-order pre-integration "
            << secondRMSE << "\n";
  std::cout << "tables: " << preint->GetFirstOrderTable()->GetTableSize() << "^2 built in "
            << 1000.0 * preint->GetLastTableBuildTime() << " ms, "
            << secondOrder->GetSecondOrderTable()->GetTableSize() << "^3 built in "
            << 1000.0 * secondOrder->GetLastTableBuildTime() << " ms on the "
            << (secondOrder->GetLastTableBuiltOnGPU() ? "GPU" : "CPU") << "\n";

  vtkNew<vtkWindowToImageFilter> grab;
  grab->SetInput(window);
  grab->ReadFrontBufferOff();
  vtkNew<vtkPNGWriter> writer;
  writer->SetFileName(output.c_str());
  writer->SetInputConnection(grab->GetOutputPort());
  writer->Write();
  std::cout << "wrote " << output << "\n";
  return preintRMSE < stockRMSE && secondRMSE < stockRMSE ? EXIT_SUCCESS : EXIT_FAILURE;
}
