// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
// Proves that vtkPreIntegrationVolumeMapper builds its first-order table exactly when it must:
// once on the first frame; not again for re-renders, camera moves, window resizes, data edits
// that keep the scalar range, or released graphics resources; exactly once after a change of
// the colour function, the opacity function, the opacity unit distance, the sample distance or
// the scalar range. Switching Integration STOCK <-> FIRST_ORDER changes the program (the
// images are VTK's stock image and the pre-integrated one again, exactly) but not the table.
// The table has a fixed size here; with measured sizes (TableSize 0) a camera move still
// rebuilds nothing, and a change of the transfer function measures and rebuilds once.
#include "hovrRenderTestUtilities.h"

#include "vtkOpenGLGPUVolumeRayCastMapper.h"
#include "vtkPreIntegrationTableSizer.h"
#include "vtkPreIntegrationVolumeMapper.h"
#include "vtkSecondOrderPreIntegrationTable.h"
#include "vtkVolume.h"

#include <iostream>

namespace
{
// Largest absolute difference between two captures; -1 if they cannot be compared.
double MaxDifference(vtkImageData* a, vtkImageData* b)
{
  double maximum = -1.0;
  hovrTest::RMSE(a, b, &maximum);
  return maximum;
}
}

int TestPreIntegrationTableRebuilds(int, char*[])
{
  hovrTest::Checker check;
  const int size = 128;
  auto data = hovrTest::MakeMarschnerLobb(41, VTK_FLOAT);
  auto property = hovrTest::MakeSpikeProperty();

  hovrTest::FloatRenderView view;
  if (!check(view.Initialize(size, size), "float colour buffer attached"))
  {
    return check.Result("TestPreIntegrationTableRebuilds");
  }
  hovrTest::SetObliqueCamera(view.GetCamera(), data->GetBounds());

  vtkNew<vtkPreIntegrationVolumeMapper> mapper;
  vtkNew<vtkTest::ErrorObserver> errors;
  hovrTest::Observe(mapper, errors);
  mapper->SetInputData(data);
  mapper->SetSampleDistance(0.05);
  vtkNew<vtkVolume> volume;
  volume->SetMapper(mapper);
  volume->SetProperty(property);
  view.GetRenderer()->AddVolume(volume);
  mapper->SetTableSize(256); // the rebuild logic alone, without measured sizes
  vtkSecondOrderPreIntegrationTable* table = mapper->GetFirstOrderTable();

  // Renders twice: the change must rebuild the table on the first frame and not on the second.
  // Returns the first frame's image.
  int expected = 0;
  auto renderExpecting = [&](bool rebuild, const std::string& what)
  {
    expected += rebuild ? 1 : 0;
    auto image = view.Render();
    check(table->GetBuildCount() == expected,
      what + ": " + std::to_string(expected) + " builds, got " +
        std::to_string(table->GetBuildCount()));
    view.Render();
    check(table->GetBuildCount() == expected, what + ": no build on the next frame");
    return image;
  };

  auto first = renderExpecting(true, "first render");
  check(hovrTest::CountCovered(first) > size * size / 10, "the volume is drawn");
  check(table->GetTableSize() >= 64 && mapper->GetTableTextureMemorySize() > 0, "table uploaded");

  auto again = renderExpecting(false, "re-render");
  check(MaxDifference(first, again) == 0.0, "re-render gives the same image");

  view.GetCamera()->Azimuth(25.0);
  auto moved = renderExpecting(false, "camera moved");
  check(MaxDifference(first, moved) > 0.1, "moving the camera changes the image");
  view.GetCamera()->Azimuth(-25.0);

  view.GetWindow()->SetSize(160, 144);
  renderExpecting(false, "window resized");
  view.GetWindow()->SetSize(size, size);
  auto resizedBack = renderExpecting(false, "window resized back");
  check(MaxDifference(first, resizedBack) == 0.0, "same image after resizing back");

  mapper->ReleaseGraphicsResources(view.GetWindow());
  auto released = renderExpecting(false, "graphics resources released");
  check(MaxDifference(first, released) == 0.0, "same image after re-uploading the table");

  property->GetRGBTransferFunction(0)->AddRGBPoint(0.5, 1.0, 0.0, 1.0);
  auto recoloured = renderExpecting(true, "colour function changed");
  check(MaxDifference(first, recoloured) > 0.05, "the colour change shows");

  property->GetScalarOpacity(0)->AddPoint(0.5, 0.2); // the middle spike: 0.7 -> 0.2
  auto fainter = renderExpecting(true, "opacity function changed");
  check(MaxDifference(recoloured, fainter) > 0.05, "the opacity change shows");

  property->SetScalarOpacityUnitDistance(0.1);
  auto thinner = renderExpecting(true, "unit distance changed");
  check(MaxDifference(fainter, thinner) > 0.05, "the unit distance change shows");

  mapper->SetSampleDistance(0.025);
  auto finer = renderExpecting(true, "sample distance changed");
  check(MaxDifference(thinner, finer) > 0.0, "the sample distance change shows");

  // A data edit inside the range re-uploads the volume but keeps the table.
  vtkDataArray* scalars = data->GetPointData()->GetScalars();
  scalars->SetComponent(0, 0, 0.5);
  scalars->Modified();
  renderExpecting(false, "data edited within its range");
  // One voxel (a corner) above the old maximum widens the range.
  scalars->SetComponent(0, 0, 1.5);
  scalars->Modified();
  auto widened = renderExpecting(true, "scalar range widened");
  check(table->GetScalarRange()[1] == 1.5, "the table spans the new range");

  // STOCK: VTK's program and image, table untouched.
  const int frames = mapper->GetExtensionFrameCount();
  mapper->SetIntegrationToStock();
  auto stockMode = renderExpecting(false, "Integration STOCK");
  check(mapper->GetExtensionFrameCount() == frames, "STOCK frames bypass the extension");
  vtkNew<vtkOpenGLGPUVolumeRayCastMapper> stock;
  stock->SetInputData(data);
  stock->SetAutoAdjustSampleDistances(0);
  stock->SetSampleDistance(0.025);
  volume->SetMapper(stock);
  auto stockImage = view.Render();
  volume->SetMapper(mapper);
  check(MaxDifference(stockMode, stockImage) == 0.0, "STOCK draws VTK's stock image");
  check(MaxDifference(stockMode, widened) > 0.01, "STOCK differs from FIRST_ORDER");

  mapper->SetIntegrationToFirstOrder();
  auto backToFirstOrder = renderExpecting(false, "Integration FIRST_ORDER again");
  check(mapper->GetExtensionFrameCount() == frames + 2, "FIRST_ORDER frames use the extension");
  check(MaxDifference(backToFirstOrder, widened) == 0.0, "FIRST_ORDER image is back, exactly");

  // Measured sizes: measured and built once, kept while only the camera moves.
  mapper->SetTableSize(0);
  auto measured = renderExpecting(true, "measured table sizes");
  check(
    mapper->GetTableSizer()->GetChosenCandidate() >= 0 &&
      table->GetTableSize() ==
        [&]()
        {
          int sizes[3];
          mapper->GetTableSizer()->GetCandidateSizes(
            mapper->GetTableSizer()->GetChosenCandidate(), sizes);
          return sizes[0];
        }(),
    "the table has the measured size");
  check(hovrTest::CountCovered(measured) > size * size / 10, "measured sizes: the volume is drawn");
  view.GetCamera()->Azimuth(25.0);
  renderExpecting(false, "measured sizes, camera moved");
  property->GetScalarOpacity(0)->AddPoint(0.5, 0.6);
  renderExpecting(true, "measured sizes, opacity function changed");

  hovrTest::ExpectQuiet(check, errors, "the whole test");
  return check.Result("TestPreIntegrationTableRebuilds");
}
