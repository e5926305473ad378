// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
// Proves that vtkPreIntegrationVolumeMapper handles bad and unusual input as documented:
// shading is pre-integrated by both orders and falls back for positional lights; a sample distance
// <= 0, a non-positive opacity unit distance, a 1-voxel-thick volume and an empty image report an
// error and draw nothing (no crash); multi-component scalars warn and draw exactly VTK's stock
// image; grey colour functions and disabled gradient opacity are pre-integrated; NaN scalars give
// no NaN or infinity in the image and the rest of the volume is still drawn as the reference
// integrator draws it; and every scalar type VTK uploads differently (8/16-bit normalised integers,
// signed and unsigned, 32-bit integers and doubles rescaled to floats, floats as they are) is
// mapped back to data values correctly: each agrees with its own CPU reference
// (GetTextureValueMapping).
#include "hovrRenderTestUtilities.h"

#include "vtkLight.h"
#include "vtkOpenGLGPUVolumeRayCastMapper.h"
#include "vtkPreIntegrationVolumeMapper.h"
#include "vtkSecondOrderPreIntegrationTable.h"
#include "vtkVolume.h"

#include <iostream>
#include <limits>

namespace
{
const int Size = 128;

struct Scene
{
  hovrTest::FloatRenderView View;
  vtkNew<vtkVolume> Volume;
  vtkNew<vtkPreIntegrationVolumeMapper> Mapper;
  vtkNew<vtkTest::ErrorObserver> Errors;

  bool Initialize(vtkImageData* data, vtkVolumeProperty* property)
  {
    hovrTest::Observe(this->Mapper, this->Errors);
    this->Mapper->SetInputData(data);
    this->Mapper->SetSampleDistance(0.05);
    this->Volume->SetMapper(this->Mapper);
    this->Volume->SetProperty(property);
    this->View.GetRenderer()->AddVolume(this->Volume);
    const bool ok = this->View.Initialize(Size, Size);
    const double bounds[6] = { -1, 1, -1, 1, -1, 1 };
    hovrTest::SetObliqueCamera(this->View.GetCamera(), bounds);
    return ok;
  }

  // The image VTK's own mapper draws for the same input, property and step.
  vtkSmartPointer<vtkImageData> RenderStock(vtkImageData* data)
  {
    vtkNew<vtkOpenGLGPUVolumeRayCastMapper> stock;
    stock->SetInputData(data);
    stock->SetAutoAdjustSampleDistances(0);
    stock->SetSampleDistance(this->Mapper->GetSampleDistance());
    stock->SetBlendMode(this->Mapper->GetBlendMode());
    this->Volume->SetMapper(stock);
    auto image = this->View.Render();
    this->Volume->SetMapper(this->Mapper);
    return image;
  }
};

// A 2- or 3-component copy of data: every component holds the scalar.
vtkSmartPointer<vtkImageData> Replicate(vtkImageData* data, int components)
{
  vtkDataArray* in = data->GetPointData()->GetScalars();
  vtkNew<vtkFloatArray> out;
  out->SetNumberOfComponents(components);
  out->SetNumberOfTuples(in->GetNumberOfTuples());
  for (vtkIdType i = 0; i < in->GetNumberOfTuples(); ++i)
  {
    for (int c = 0; c < components; ++c)
    {
      out->SetComponent(i, c, in->GetComponent(i, 0));
    }
  }
  auto result = vtkSmartPointer<vtkImageData>::New();
  result->CopyStructure(data);
  result->GetPointData()->SetScalars(out);
  return result;
}

// Renders with a bad setting: an error containing fragment, the background only.
void CheckNothingDrawn(hovrTest::Checker& check,
  Scene& scene,
  const std::string& fragment,
  const std::string& what)
{
  auto image = scene.View.Render();
  hovrTest::ExpectError(check, scene.Errors, fragment, what);
  check(image && hovrTest::MaximumValue(image) == 0.0, what + ": nothing drawn");
}

// Renders what pre-integration does not handle: one warning containing fragment (not repeated
// on the next frame), then exactly the stock mapper's image; then a pre-integrated frame again
// once undo() has restored the scene.
void CheckStockFallback(hovrTest::Checker& check,
  Scene& scene,
  vtkImageData* data,
  const std::string& fragment,
  const std::string& what)
{
  scene.Mapper->SetInputData(data);
  const int frames = scene.Mapper->GetExtensionFrameCount();
  scene.View.Render();
  hovrTest::ExpectWarning(check, scene.Errors, fragment, what);
  auto image = scene.View.Render();
  hovrTest::ExpectQuiet(check, scene.Errors, what + ", second frame");
  check(scene.Mapper->GetExtensionFrameCount() == frames, what + ": drawn by the stock path");
  auto stockImage = scene.RenderStock(data);
  hovrTest::ExpectQuiet(check, scene.Errors, what + " (stock mapper)");
  double maxDifference = -1.0;
  hovrTest::RMSE(image, stockImage, &maxDifference);
  check(maxDifference == 0.0, what + ": the stock mapper's image");
  check(hovrTest::CountCovered(image) > Size * Size / 10, what + ": the volume is drawn");
}

// After a fallback case is undone: pre-integrated again, quietly.
void CheckPreIntegratedAgain(hovrTest::Checker& check,
  Scene& scene,
  vtkImageData* data,
  const std::string& what)
{
  scene.Mapper->SetInputData(data);
  const int frames = scene.Mapper->GetExtensionFrameCount();
  scene.View.Render();
  hovrTest::ExpectQuiet(check, scene.Errors, what + " undone");
  check(scene.Mapper->GetExtensionFrameCount() == frames + 1, what + " undone: pre-integrated");
}
}

int TestPreIntegrationVolumeMapperBadInput(int, char*[])
{
  hovrTest::Checker check;
  auto data = hovrTest::MakeMarschnerLobb(41, VTK_FLOAT);
  auto property = hovrTest::MakeSpikeProperty();
  Scene scene;
  if (!check(scene.Initialize(data, property), "float colour buffer attached"))
  {
    return check.Result("TestPreIntegrationVolumeMapperBadInput");
  }
  vtkPreIntegrationVolumeMapper* mapper = scene.Mapper;
  auto good = scene.View.Render();
  hovrTest::ExpectQuiet(check, scene.Errors, "valid input");
  check(hovrTest::CountCovered(good) > Size * Size / 10, "valid input is drawn");

  // Sample distance: the error names the value; nothing drawn, every frame.
  mapper->SetSampleDistance(0.0);
  CheckNothingDrawn(check, scene, "sample distance must be positive", "sample distance 0");
  CheckNothingDrawn(check, scene, "sample distance must be positive", "sample distance 0 again");
  mapper->SetSampleDistance(-0.05);
  CheckNothingDrawn(check, scene, "sample distance must be positive", "sample distance < 0");
  // A sample distance so fine that float ray positions would stop advancing: more samples
  // along the diagonal (2 sqrt(3) here) than MaximumSamplesPerRay.
  mapper->SetSampleDistance(1e-9);
  CheckNothingDrawn(check, scene, "MaximumSamplesPerRay", "sample distance 1e-9");
  mapper->SetSampleDistance(0.05);
  mapper->SetMaximumSamplesPerRay(60.0); // 69 samples at 0.05
  CheckNothingDrawn(check, scene, "samples along the volume's diagonal", "69 samples, 60 allowed");
  mapper->SetMaximumSamplesPerRay(1e5);
  auto recovered = scene.View.Render();
  hovrTest::ExpectQuiet(check, scene.Errors, "valid sample distance again");
  double maxDifference = -1.0;
  hovrTest::RMSE(good, recovered, &maxDifference);
  check(maxDifference == 0.0, "the valid image comes back");

  // Opacity unit distance: vtkVolumeProperty stores any value; hovr's sampler rejects <= 0
  // (its error goes to the output window), the mapper reports that it cannot pre-integrate.
  for (double unitDistance : { 0.0, -0.05 })
  {
    hovrTest::MessageCapture messages;
    property->SetScalarOpacityUnitDistance(unitDistance);
    check(property->GetScalarOpacityUnitDistance() == unitDistance,
      "vtkVolumeProperty keeps the unit distance as given");
    const std::string what = "unit distance " + std::to_string(unitDistance);
    CheckNothingDrawn(check, scene, "cannot be pre-integrated", what);
    check(messages.TakeError("unit distance must lie in"),
      what + ": the sampler names the unit distance");
  }
  property->SetScalarOpacityUnitDistance(0.05);

  // Multi-component scalars: VTK's stock compositing after one warning.
  property->IndependentComponentsOff(); // 2 components: colour from the first, opacity second
  CheckStockFallback(
    check, scene, Replicate(data, 2), "single-component", "2 dependent components");
  property->IndependentComponentsOn();
  CheckPreIntegratedAgain(check, scene, data, "2 dependent components");
  for (int c = 1; c < 3; ++c)
  {
    property->SetColor(c, property->GetRGBTransferFunction(0));
    property->SetScalarOpacity(c, property->GetScalarOpacity(0));
    property->SetScalarOpacityUnitDistance(c, 0.05);
  }
  CheckStockFallback(
    check, scene, Replicate(data, 3), "single-component", "3 independent components");
  CheckPreIntegratedAgain(check, scene, data, "3 independent components");

  // A grey colour function is pre-integrated: exactly as the RGB function with equal channels.
  vtkSmartPointer<vtkColorTransferFunction> rgb = property->GetRGBTransferFunction(0);
  vtkNew<vtkPiecewiseFunction> grey;
  grey->AddPoint(0.0, 0.2);
  grey->AddPoint(1.0, 1.0);
  vtkNew<vtkColorTransferFunction> equalChannels;
  equalChannels->AddRGBPoint(0.0, 0.2, 0.2, 0.2);
  equalChannels->AddRGBPoint(1.0, 1.0, 1.0, 1.0);
  property->SetColor(equalChannels);
  auto rgbImage = scene.View.Render();
  property->SetColor(grey);
  const int greyFrames = mapper->GetExtensionFrameCount();
  auto greyImage = scene.View.Render();
  hovrTest::ExpectQuiet(check, scene.Errors, "grey colour function");
  check(mapper->GetExtensionFrameCount() == greyFrames + 1, "grey colour: pre-integrated");
  double greyDifference = -1.0;
  hovrTest::RMSE(greyImage, rgbImage, &greyDifference);
  check(greyDifference == 0.0, "grey colour: the image of the equal-channel RGB function");
  property->SetColor(rgb);

  // The other documented fallbacks: settings of the property or the mapper that the
  // first-order table cannot express.
  // Shading: first order shades its segments, second order its slabs; positional lights fall
  // back.
  property->ShadeOn();
  CheckPreIntegratedAgain(check, scene, data, "shading, first order");
  check(scene.Mapper->GetLastFrameShaded(), "shading, first order: a shaded frame");
  scene.Mapper->SetIntegrationToSecondOrder();
  CheckPreIntegratedAgain(check, scene, data, "shading, second order");
  check(scene.Mapper->GetLastFrameShaded(), "shading, second order: a shaded frame");
  scene.Mapper->SetIntegrationToFirstOrder();
  vtkNew<vtkLight> lamp;
  lamp->SetPositional(true);
  lamp->SetPosition(0.0, 0.0, 5.0);
  scene.View.GetRenderer()->AddLight(lamp);
  CheckStockFallback(check, scene, data, "positional light", "a positional light");
  scene.View.GetRenderer()->RemoveLight(lamp);
  CheckPreIntegratedAgain(check, scene, data, "a positional light");
  property->ShadeOff();
  CheckPreIntegratedAgain(check, scene, data, "shading");
  check(!scene.Mapper->GetLastFrameShaded(), "shading off: an unshaded frame");

  vtkNew<vtkPiecewiseFunction> gradientOpacity;
  gradientOpacity->AddPoint(0.0, 0.2);
  gradientOpacity->AddPoint(10.0, 1.0);
  property->SetGradientOpacity(gradientOpacity);
  CheckStockFallback(check, scene, data, "gradient opacity", "gradient opacity");
  // A disabled gradient opacity function is ignored, as VTK ignores it.
  property->DisableGradientOpacityOn();
  CheckPreIntegratedAgain(check, scene, data, "disabled gradient opacity");
  property->DisableGradientOpacityOff();
  property->SetGradientOpacity(static_cast<vtkPiecewiseFunction*>(nullptr));
  CheckPreIntegratedAgain(check, scene, data, "gradient opacity");
  // VTK's default gradient opacity (1 everywhere), which GetGradientOpacity() creates for
  // whoever asks, as vtkFixedPointVolumeRayCastMapper does: nothing to fall back for.
  property->GetGradientOpacity(0);
  check(property->HasGradientOpacity(0), "GetGradientOpacity() created VTK's default function");
  CheckPreIntegratedAgain(check, scene, data, "the default gradient opacity");
  property->SetGradientOpacity(static_cast<vtkPiecewiseFunction*>(nullptr));

  // Maximum intensity: the maxima along the rays are near 1, made visible for this case.
  property->GetScalarOpacity(0)->AddPoint(1.0, 0.8);
  mapper->SetBlendModeToMaximumIntensity();
  CheckStockFallback(check, scene, data, "composite blending only", "maximum intensity");
  mapper->SetBlendModeToComposite();
  property->GetScalarOpacity(0)->AddPoint(1.0, 0.0);
  CheckPreIntegratedAgain(check, scene, data, "maximum intensity");

  // A 1-voxel-thick volume has no cell: nothing to integrate.
  vtkNew<vtkImageData> slab;
  slab->SetDimensions(41, 41, 1);
  slab->SetOrigin(-1.0, -1.0, 0.0);
  slab->SetSpacing(0.05, 0.05, 0.05);
  slab->AllocateScalars(VTK_FLOAT, 1);
  slab->GetPointData()->GetScalars()->Fill(0.5);
  mapper->SetInputData(slab);
  CheckNothingDrawn(check, scene, "at least 2 points along each axis", "41 x 41 x 1 volume");

  // An empty image: VTK's own checks report it; nothing drawn, no crash.
  {
    hovrTest::MessageCapture messages;
    vtkNew<vtkImageData> empty;
    mapper->SetInputData(empty);
    auto image = scene.View.Render();
    const std::string text = messages.Take();
    hovrTest::ExpectError(check, scene.Errors, "No scalars", "empty image");
    check(text.empty(), "empty image: nothing else reported, got [" + text + "]");
    check(image && hovrTest::MaximumValue(image) == 0.0, "empty image: nothing drawn");
  }

  // Scalars without a finite value: nothing to draw, said once per frame.
  {
    auto allNaN = hovrTest::ConvertScalars(data, VTK_FLOAT, 1.0, 0.0);
    allNaN->GetPointData()->GetScalars()->Fill(std::numeric_limits<double>::quiet_NaN());
    mapper->SetInputData(allNaN);
    CheckNothingDrawn(check, scene, "no finite value", "all-NaN scalars");
  }
  // Flat data of a huge value: a range of one value that adding 1 cannot widen.
  {
    auto flat = hovrTest::ConvertScalars(data, VTK_FLOAT, 0.0, 1e20);
    mapper->SetInputData(flat);
    auto image = scene.View.Render();
    // The transfer function is transparent there: said, as every empty image is.
    hovrTest::ExpectWarning(
      check, scene.Errors, "opacity is zero over the data range", "flat data at 1e20");
    check(hovrTest::AllFinite(image), "flat data at 1e20: every pixel finite");
  }

  // NaN scalars: a block of NaN voxels and scattered single ones. Where the reference sees data
  // the volume is drawn; nowhere NaN or infinity.
  {
    auto withNaN = hovrTest::ConvertScalars(data, VTK_FLOAT, 1.0, 0.0);
    vtkDataArray* scalars = withNaN->GetPointData()->GetScalars();
    const double nan = std::numeric_limits<double>::quiet_NaN();
    for (int k = 30; k < 41; ++k)
    {
      for (int j = 0; j < 15; ++j)
      {
        for (int i = 0; i < 41; ++i)
        {
          scalars->SetComponent(i + 41 * (j + 41 * k), 0, nan);
        }
      }
    }
    for (vtkIdType v = 0; v < scalars->GetNumberOfTuples(); v += 97)
    {
      scalars->SetComponent(v, 0, nan);
    }
    mapper->SetInputData(withNaN);
    mapper->SetSampleDistance(0.0125); // a quarter voxel, so that the method error is small
    auto image = scene.View.Render();
    hovrTest::ExpectQuiet(check, scene.Errors, "NaN scalars");
    check(hovrTest::AllFinite(image), "NaN scalars: every pixel finite");
    auto reference =
      hovrTest::RenderReference(withNaN, property, scene.View.GetCamera(), Size, Size);
    const double rmse = hovrTest::RMSE(image, reference);
    std::cout << "NaN scalars: RMSE vs reference " << rmse << ", covered pixels "
              << hovrTest::CountCovered(image) << " (reference "
              << hovrTest::CountCovered(reference) << ")\n";
    check(hovrTest::CountCovered(image) > hovrTest::CountCovered(reference) * 9 / 10,
      "NaN scalars: the rest of the volume is drawn");
    // Above the error without NaN by where segments and cells touching NaN are cut
    // differently; NaN treated as a value or as the end of the ray is far off.
    check(rmse >= 0.0 && rmse < 0.015, "NaN scalars: close to the reference");
  }

  // Every scalar type against its own reference, at a quarter-voxel step where the method
  // error is small, and against the float data's image, for both orders (second order is as
  // accurate at this step, the same bounds hold). Typical values: RMSE vs reference
  // 0.0053-0.0074 for every type (the method error; 8-bit data is uploaded in 16 bits, which
  // llvmpipe interpolates at 16-bit precision: in its own 8-bit texture uint8 reaches 0.0092);
  // RMSE vs the float image 2e-7 (double), 4e-7 (int), 1.7e-5 (16-bit: quantisation),
  // 0.003 (8-bit: quantisation). A wrong raw-to-data mapping moves the spike shells: errors of
  // 1e-3 and more against the reference.
  struct TypeCase
  {
    int Type;
    double Scale, Shift;
    double ReferenceBound; // RMSE vs the CPU reference of the same typed data
    double FloatBound;     // RMSE vs the image of the float data
  };
  const TypeCase cases[] = {
    { VTK_FLOAT, 1.0, 0.0, 0.0085, 0.0 },
    { VTK_DOUBLE, 8.0, -3.0, 0.0085, 1e-4 },
    { VTK_UNSIGNED_CHAR, 255.0, 0.0, 0.0085, 0.01 },
    { VTK_SIGNED_CHAR, 250.0, -125.0, 0.0085, 0.01 },
    { VTK_UNSIGNED_SHORT, 60000.0, 0.0, 0.0085, 1e-4 },
    { VTK_SHORT, 40000.0, -20000.0, 0.0085, 1e-4 },
    { VTK_INT, 2000000.0, -1000000.0, 0.0085, 1e-4 },
  };
  mapper->SetSampleDistance(0.0125);
  for (int order :
    { vtkPreIntegrationVolumeMapper::FIRST_ORDER, vtkPreIntegrationVolumeMapper::SECOND_ORDER })
  {
    mapper->SetIntegration(order);
    const std::string label =
      order == vtkPreIntegrationVolumeMapper::FIRST_ORDER ? "first order, " : "second order, ";
    vtkSmartPointer<vtkImageData> floatImage;
    for (const TypeCase& c : cases)
    {
      auto typed = hovrTest::ConvertScalars(data, c.Type, c.Scale, c.Shift);
      auto typedProperty = hovrTest::MakeSpikeProperty(c.Shift, c.Shift + c.Scale, 0.05);
      scene.Volume->SetProperty(typedProperty);
      mapper->SetInputData(typed);
      auto image = scene.View.Render();
      hovrTest::ExpectQuiet(check, scene.Errors, label + typed->GetScalarTypeAsString());
      auto reference =
        hovrTest::RenderReference(typed, typedProperty, scene.View.GetCamera(), Size, Size);
      const double rmse = hovrTest::RMSE(image, reference);
      double scale, shift;
      vtkPreIntegrationVolumeMapper::GetTextureValueMapping(
        typed->GetPointData()->GetScalars(), scale, shift);
      if (!floatImage)
      {
        floatImage = image;
      }
      const double rmseFloat = hovrTest::RMSE(image, floatImage);
      std::cout << label << typed->GetScalarTypeAsString() << ": RMSE vs reference " << rmse
                << ", vs the float data's image " << rmseFloat << " (texture value mapping "
                << scale << " * raw + " << shift << ", table "
                << mapper->GetActiveTable()->GetTableSize() << ")\n";
      const std::string name = label + typed->GetScalarTypeAsString();
      check(rmse >= 0.0 && rmse < c.ReferenceBound, name + ": RMSE vs reference below bound");
      check(
        rmseFloat >= 0.0 && rmseFloat <= c.FloatBound, name + ": RMSE vs float image below bound");
    }
  }
  return check.Result("TestPreIntegrationVolumeMapperBadInput");
}
