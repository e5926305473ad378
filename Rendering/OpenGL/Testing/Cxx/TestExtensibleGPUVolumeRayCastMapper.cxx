// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
// Proves the extension hook of vtkExtensibleGPUVolumeRayCastMapper with a test-local subclass
// whose GLSL paints every ray with a colour uniform set only from
// SetExtensionShaderParameters: the uniform reaches the first frame (where VTK builds the
// program and fires no UpdateShaderEvent) and every later frame; the program is built once and
// rebuilt only after ExtensionShaderModified(); a DrawStock plan gives exactly the image of a
// plain vtkOpenGLGPUVolumeRayCastMapper and DrawNothing leaves the background; switching
// between plans never reuses the other plan's program; other information keys and render
// passes on the volume are called and survive the draw, and the hook is never left behind.
#include "hovrRenderTestUtilities.h"

#include "vtkDataObject.h"
#include "vtkExtensibleGPUVolumeRayCastMapper.h"
#include "vtkInformation.h"
#include "vtkInformationIntegerKey.h"
#include "vtkInformationObjectBaseVectorKey.h"
#include "vtkObjectFactory.h"
#include "vtkOpenGLRenderPass.h"
#include "vtkShaderProgram.h"
#include "vtkVolume.h"

#include <iostream>
#include <sstream>

namespace
{
// Paints each ray's pixel with the uniform hovrTest_colour (or its .bgra swizzle).
class vtkUniformColourMapper : public vtkExtensibleGPUVolumeRayCastMapper
{
public:
  static vtkUniformColourMapper* New();
  vtkTypeMacro(vtkUniformColourMapper, vtkExtensibleGPUVolumeRayCastMapper);

  // What PrepareExtension answers (FramePlan is protected).
  enum TestPlan
  {
    Extension,
    Stock,
    Nothing
  };
  TestPlan Plan = Extension;
  float Colour[4] = { 0.0f, 0.0f, 0.0f, 0.0f };
  bool SwapRedBlue = false; // GLSL variant; takes effect after MarkShaderModified()
  int ShaderBuilds = 0;     // ReplaceExtensionShaderValues calls
  int ParameterCalls = 0;   // SetExtensionShaderParameters calls
  int Activations = 0;
  int Deactivations = 0;

  void MarkShaderModified() { this->ExtensionShaderModified(); }

protected:
  vtkUniformColourMapper() = default;
  ~vtkUniformColourMapper() override = default;

  FramePlan PrepareExtension(vtkRenderer*, vtkVolume*) override
  {
    return this->Plan == Extension ? DrawWithExtension
                                   : (this->Plan == Stock ? DrawStock : DrawNothing);
  }
  void ActivateExtensionTextures() override { this->Activations++; }
  void DeactivateExtensionTextures() override { this->Deactivations++; }
  bool ReplaceExtensionShaderValues(std::string&, std::string& fragmentShader, vtkVolume*) override
  {
    this->ShaderBuilds++;
    bool ok = ReplaceShaderTag(
      fragmentShader, "//VTK::Shading::Dec", "uniform vec4 hovrTest_colour;", BeforeTag);
    ok = ok &&
      ReplaceShaderTag(fragmentShader,
        "//VTK::Shading::Impl",
        this->SwapRedBlue ? "g_fragColor = hovrTest_colour.bgra;"
                          : "g_fragColor = hovrTest_colour;",
        ReplaceTag);
    return ok;
  }
  void SetExtensionShaderParameters(vtkShaderProgram* program, vtkVolume*) override
  {
    this->ParameterCalls++;
    program->SetUniform4f("hovrTest_colour", this->Colour);
  }

private:
  vtkUniformColourMapper(const vtkUniformColourMapper&) = delete;
  void operator=(const vtkUniformColourMapper&) = delete;
};
vtkStandardNewMacro(vtkUniformColourMapper);

// Somebody else's render pass on the volume: counts the ray caster's calls, changes nothing.
class vtkCountingPass : public vtkOpenGLRenderPass
{
public:
  static vtkCountingPass* New();
  vtkTypeMacro(vtkCountingPass, vtkOpenGLRenderPass);
  void Render(const vtkRenderState*) override {}
  bool PreReplaceShaderValues(std::string&,
    std::string&,
    std::string&,
    vtkAbstractMapper*,
    vtkProp*) override
  {
    this->ShaderBuilds++;
    return true;
  }
  bool SetShaderParameters(vtkShaderProgram*,
    vtkAbstractMapper*,
    vtkProp*,
    vtkOpenGLVertexArrayObject*) override
  {
    this->ParameterCalls++;
    return true;
  }
  int ShaderBuilds = 0;
  int ParameterCalls = 0;

protected:
  vtkCountingPass() { this->ActiveDrawBuffers = 1; }
  ~vtkCountingPass() override = default;
};
vtkStandardNewMacro(vtkCountingPass);

void SetColour(vtkUniformColourMapper* mapper, float r, float g, float b, float a)
{
  mapper->Colour[0] = r;
  mapper->Colour[1] = g;
  mapper->Colour[2] = b;
  mapper->Colour[3] = a;
}

// Checks that every pixel is either transparent black or exactly colour, and that at least
// minimumCovered pixels (the volume's box) are colour.
void CheckPainted(hovrTest::Checker& check,
  vtkImageData* image,
  const float colour[4],
  vtkIdType minimumCovered,
  const std::string& what)
{
  vtkFloatArray* rgba = hovrTest::GetRGBA(image);
  if (!check(rgba != nullptr, what + ": image captured"))
  {
    return;
  }
  vtkIdType painted = 0, other = 0;
  for (vtkIdType i = 0; i < rgba->GetNumberOfTuples(); ++i)
  {
    const float* p = rgba->GetPointer(4 * i);
    if (p[0] == colour[0] && p[1] == colour[1] && p[2] == colour[2] && p[3] == colour[3])
    {
      painted++;
    }
    else if (p[0] != 0.0f || p[1] != 0.0f || p[2] != 0.0f || p[3] != 0.0f)
    {
      other++;
    }
  }
  std::ostringstream label;
  label << what << ": " << painted << " pixels of colour (" << colour[0] << ", " << colour[1]
        << ", " << colour[2] << ", " << colour[3] << "), " << other << " of another colour";
  std::cout << label.str() << "\n";
  check(painted >= minimumCovered && other == 0, label.str());
}
}

int TestExtensibleGPUVolumeRayCastMapper(int, char*[])
{
  hovrTest::Checker check;
  const int size = 128;
  auto data = hovrTest::MakeMarschnerLobb(41, VTK_FLOAT);
  auto property = hovrTest::MakeSpikeProperty();

  hovrTest::FloatRenderView view;
  if (!check(view.Initialize(size, size), "float colour buffer attached"))
  {
    return check.Result("TestExtensibleGPUVolumeRayCastMapper");
  }
  hovrTest::SetObliqueCamera(view.GetCamera(), data->GetBounds());

  vtkNew<vtkUniformColourMapper> mapper;
  vtkNew<vtkTest::ErrorObserver> errors;
  hovrTest::Observe(mapper, errors);
  mapper->SetInputData(data);
  mapper->SetSampleDistance(0.05);
  vtkNew<vtkVolume> volume;
  volume->SetMapper(mapper);
  volume->SetProperty(property);
  view.GetRenderer()->AddVolume(volume);
  // The volume's box covers about half of the view; a third is a safe floor.
  const vtkIdType boxPixels = size * size / 3;

  // Exactly representable colours, so that equality is exact.
  const float colourA[4] = { 0.125f, 0.25f, 0.375f, 0.5f };
  const float colourB[4] = { 0.5f, 0.25f, 0.0625f, 0.75f };
  const float colourBSwapped[4] = { 0.0625f, 0.25f, 0.5f, 0.75f };
  const float colourASwapped[4] = { 0.375f, 0.25f, 0.125f, 0.5f };

  // First frame: the program is built in this frame and the uniform is already set.
  SetColour(mapper, 0.125f, 0.25f, 0.375f, 0.5f);
  auto image = view.Render();
  CheckPainted(check, image, colourA, boxPixels, "first frame");
  check(mapper->ShaderBuilds == 1, "program built once on the first frame");
  const std::string& source = mapper->GetFragmentShaderSource();
  check(source.find("uniform vec4 hovrTest_colour;") != std::string::npos &&
      source.find("g_fragColor = hovrTest_colour") != std::string::npos &&
      source.find("//VTK::Shading::Impl") == std::string::npos,
    "GetFragmentShaderSource() is the program after every replacement");
  check(mapper->ParameterCalls >= 1, "parameters set on the first frame");
  check(mapper->GetExtensionFrameCount() == 1, "one extension frame");
  check(mapper->Activations == 1 && mapper->Deactivations == 1, "textures activated around it");
  vtkInformation* keys = volume->GetPropertyKeys();
  check(!keys || !keys->Has(vtkOpenGLRenderPass::RenderPasses()),
    "the hook is not left on a volume that had no passes");

  // A later frame: the new uniform value without any Modified() and without a rebuild.
  SetColour(mapper, 0.5f, 0.25f, 0.0625f, 0.75f);
  image = view.Render();
  CheckPainted(check, image, colourB, boxPixels, "second frame, new uniform");
  check(mapper->ShaderBuilds == 1, "no rebuild for a new uniform value");

  // A GLSL change is not picked up until the extension says so...
  mapper->SwapRedBlue = true;
  image = view.Render();
  CheckPainted(check, image, colourB, boxPixels, "GLSL changed without ExtensionShaderModified");
  check(mapper->ShaderBuilds == 1, "no rebuild without ExtensionShaderModified");
  // ...and is after ExtensionShaderModified(), once.
  mapper->MarkShaderModified();
  image = view.Render();
  CheckPainted(check, image, colourBSwapped, boxPixels, "after ExtensionShaderModified");
  check(mapper->ShaderBuilds == 2, "one rebuild after ExtensionShaderModified");
  image = view.Render();
  check(mapper->ShaderBuilds == 2, "no further rebuild");
  check(mapper->GetExtensionFrameCount() == 5, "five extension frames");

  // DrawStock: exactly what VTK's own mapper draws with the same settings.
  mapper->Plan = vtkUniformColourMapper::Stock;
  auto drawStock = view.Render();
  check(mapper->GetExtensionFrameCount() == 5, "a stock frame is not an extension frame");
  check(mapper->Activations == 5, "no extension textures activated for a stock frame");
  vtkNew<vtkOpenGLGPUVolumeRayCastMapper> stock;
  stock->SetInputData(data);
  stock->SetAutoAdjustSampleDistances(0);
  stock->SetSampleDistance(0.05);
  volume->SetMapper(stock);
  auto stockImage = view.Render();
  volume->SetMapper(mapper);
  double maxDifference = -1.0;
  hovrTest::RMSE(drawStock, stockImage, &maxDifference);
  check(maxDifference == 0.0, "DrawStock image identical to vtkOpenGLGPUVolumeRayCastMapper's");
  check(hovrTest::CountCovered(drawStock) > boxPixels / 2, "the stock image shows the volume");

  // Back to the extension: its program again, not the stock one.
  mapper->Plan = vtkUniformColourMapper::Extension;
  image = view.Render();
  CheckPainted(check, image, colourBSwapped, boxPixels, "extension after a stock frame");

  // DrawNothing: the background only.
  mapper->Plan = vtkUniformColourMapper::Nothing;
  image = view.Render();
  check(hovrTest::MaximumValue(image) == 0.0, "DrawNothing leaves the transparent background");
  check(mapper->GetExtensionFrameCount() == 6, "a DrawNothing frame is not an extension frame");

  // Another pass and another key on the volume: called on every frame, and still there after.
  vtkNew<vtkInformation> ownKeys;
  vtkNew<vtkCountingPass> pass;
  vtkOpenGLRenderPass::RenderPasses()->Append(ownKeys, pass);
  vtkDataObject::FIELD_ASSOCIATION()->Set(ownKeys, 42);
  volume->SetPropertyKeys(ownKeys);
  mapper->Plan = vtkUniformColourMapper::Extension;
  SetColour(mapper, 0.125f, 0.25f, 0.375f, 0.5f);
  const int buildsBefore = mapper->ShaderBuilds;
  image = view.Render();
  // The GLSL still swaps red and blue.
  CheckPainted(check, image, colourASwapped, boxPixels, "with another pass (first frame)");
  check(mapper->ShaderBuilds == buildsBefore + 1, "rebuilt once when another pass appears");
  check(pass->ShaderBuilds == 1 && pass->ParameterCalls >= 1, "the other pass is called too");
  SetColour(mapper, 0.5f, 0.25f, 0.0625f, 0.75f);
  mapper->SwapRedBlue = false;
  mapper->MarkShaderModified();
  image = view.Render();
  CheckPainted(check, image, colourB, boxPixels, "with another pass, after a GLSL change");
  check(pass->ShaderBuilds == 2, "the other pass sees the rebuild");
  const int passCalls = pass->ParameterCalls;
  mapper->Plan = vtkUniformColourMapper::Stock;
  image = view.Render();
  check(pass->ParameterCalls > passCalls, "the other pass is called on stock frames");
  check(volume->GetPropertyKeys() == ownKeys, "the volume keeps its information object");
  check(vtkOpenGLRenderPass::RenderPasses()->Length(ownKeys) == 1 &&
      vtkOpenGLRenderPass::RenderPasses()->Get(ownKeys, 0) == pass.Get(),
    "only the other pass is left on the volume");
  check(ownKeys->Has(vtkDataObject::FIELD_ASSOCIATION()) &&
      vtkDataObject::FIELD_ASSOCIATION()->Get(ownKeys) == 42,
    "other keys survive");
  // The pass is the test's own: taken off again, so that no information object keeps it.
  vtkOpenGLRenderPass::RenderPasses()->Remove(ownKeys, pass);
  volume->SetPropertyKeys(nullptr);
  hovrTest::ExpectQuiet(check, errors, "the whole test");

  return check.Result("TestExtensibleGPUVolumeRayCastMapper");
}
