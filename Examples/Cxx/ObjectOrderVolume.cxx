// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
// Example: composite volume rendering on the CPU with object-order ray casting
// (vtkObjectOrderVolumeMapper) in a plain VTK pipeline, parallel projection; prints the
// paper's counters (non-transparent cells rendered and hidden, octree nodes, samples) and
// saves a PNG.
//
//   ObjectOrderVolume [output.png]
#include "vtkCamera.h"
#include "vtkColorTransferFunction.h"
#include "vtkImageData.h"
#include "vtkMarschnerLobbSource.h"
#include "vtkNew.h"
#include "vtkObjectOrderRayCaster.h"
#include "vtkObjectOrderVolumeMapper.h"
#include "vtkPNGWriter.h"
#include "vtkPiecewiseFunction.h"
#include "vtkRenderWindow.h"
#include "vtkRenderer.h"
#include "vtkVolume.h"
#include "vtkVolumeProperty.h"
#include "vtkWindowToImageFilter.h"

#include <iostream>

int main(int argc, char* argv[])
{
  const char* output = argc > 1 ? argv[1] : "object_order.png";
  vtkNew<vtkMarschnerLobbSource> source;
  source->SetDimensions(64, 64, 64);

  // An opaque shell: most of the volume lies behind it.
  vtkNew<vtkColorTransferFunction> color;
  color->AddRGBPoint(0.45, 0.55, 0.15, 0.10);
  color->AddRGBPoint(0.55, 0.95, 0.75, 0.55);
  color->AddRGBPoint(1.00, 1.00, 0.97, 0.90);
  vtkNew<vtkPiecewiseFunction> opacity;
  opacity->AddPoint(0.45, 0.0);
  opacity->AddPoint(0.55, 1.0);
  vtkNew<vtkVolumeProperty> property;
  property->SetColor(color);
  property->SetScalarOpacity(opacity);
  property->SetScalarOpacityUnitDistance(0.05);
  property->SetInterpolationTypeToLinear();

  vtkNew<vtkObjectOrderVolumeMapper> mapper; // instead of vtkFixedPointVolumeRayCastMapper
  mapper->SetInputConnection(source->GetOutputPort());
  mapper->SetSampleDistance(1.0 / 63.0); // half a voxel of the [-1, 1]^3 volume
  vtkNew<vtkVolume> volume;
  volume->SetMapper(mapper);
  volume->SetProperty(property);

  vtkNew<vtkRenderer> renderer;
  renderer->AddVolume(volume);
  vtkCamera* camera = renderer->GetActiveCamera();
  camera->SetPosition(3.0, -4.8, 2.7);
  camera->SetFocalPoint(0.0, 0.0, 0.0);
  camera->SetViewUp(0, 0, 1);
  camera->ParallelProjectionOn(); // object-order ray casting needs a parallel projection
  camera->SetParallelScale(1.8);
  renderer->ResetCameraClippingRange();
  vtkNew<vtkRenderWindow> window;
  window->SetOffScreenRendering(1);
  window->SetSize(320, 320);
  window->AddRenderer(renderer);
  window->Render();

  vtkObjectOrderRayCaster* caster = mapper->GetCaster();
  const vtkIdType inView = caster->ComputeNonTransparentCells();
  const vtkIdType rendered = caster->GetNumberOfNonTransparentCells();
  if (mapper->GetLastFrameFellBack() || inView <= 0)
  {
    std::cerr << "The object-order caster did not draw the volume.\n";
    return EXIT_FAILURE;
  }
  std::cout << "non-transparent cells: " << rendered << " rendered of " << inView << " in view ("
            << 100.0 * (1.0 - static_cast<double>(rendered) / inView)
            << "% hidden and skipped), octree nodes " << caster->GetNumberOfNodesVisited()
            << ", samples " << caster->GetNumberOfSamples() << "\n";

  vtkNew<vtkWindowToImageFilter> grab;
  grab->SetInput(window);
  vtkNew<vtkPNGWriter> writer;
  writer->SetFileName(output);
  writer->SetInputConnection(grab->GetOutputPort());
  writer->Write();
  return EXIT_SUCCESS;
}
