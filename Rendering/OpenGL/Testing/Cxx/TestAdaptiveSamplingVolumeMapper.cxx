// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
// vtkAdaptiveSamplingVolumeMapper ("Adaptive Sampling in Three Dimensions for Volume Rendering
// on GPUs", Figs. 5-7 on the GPU) against its specification, the CPU core
// vtkAdaptiveSamplingRayCaster, for the same camera and image size:
//   1. the "min." oracle at l_max 3 and 0: the same image to float rounding and exactly the same
//      sample, synthesis and accumulate counts (the samples exceed the full rate by about
//      sum 1/8^l, 14.26% at l_max 3);
//   2. Gaussian blobs in empty space with a distance-to-features oracle: the same image and
//      counts without early ray termination; with it, fewer samples and an image within 1/255
//      of the one without; without counting (passes limited to the pixels that matter) the
//      same images; the tables rebuild only when Delta or the transfer function changes; after
//      ReleaseGraphicsResources the same image; a shaded property warns once;
//   3. a viewport not divisible by 2^l_max (padded: the CPU core with the padded size and a
//      camera shifted to the padded image's centre draws the same pixels and counts);
//   4. fewer slices than 2^l_max, and an oracle that asks for 2^l_max everywhere;
//   5. a perspective camera: one error, nothing drawn, until the camera is parallel again;
//   6. bad input: a missing oracle array, a NaN oracle, l_max outside [0, 8], a 1-voxel-thick
//      volume: an error each and nothing drawn;
//   7. entry and exit pieces: a constant volume (non-unit spacing, offset origin), oblique and
//      along an axis, with the min. oracle, an oracle of 2^l_max and a varying one: the CPU
//      core's image and counts (the boundary fetches too), and per pixel the exact
//      1 - exp(-sigma chord).
// Every comparison with the CPU core includes the boundary fetches (entry and exit scalars).
#include "hovrAdaptiveTestScenes.h"
#include "hovrRenderTestUtilities.h"

#include "vtkAdaptiveSamplingRayCaster.h"
#include "vtkAdaptiveSamplingVolumeMapper.h"
#include "vtkCameraRayModel.h"
#include "vtkColorTransferFunction.h"
#include "vtkPiecewiseFunction.h"
#include "vtkVolume.h"

#include <iostream>
#include <limits>

namespace
{
hovrTest::Checker check;

// The images are float32 composites of about a hundred segments from the same float tables;
// the CPU core sums in double from double samples, the GPU in float (scalars uploaded as float
// table indices): differences of a few float roundings per pixel (below 1e-6 here), well under
// the 1e-5 allowed, which a wrong ray, slice, segment length or table exceeds by orders of
// magnitude.
constexpr double ImageTolerance = 1e-5;

constexpr int N = hovrTest::BlobPoints;

struct Frame
{
  vtkSmartPointer<vtkImageData> Image;
  vtkIdType Samples = -1, Synthesis = -1, Accumulates = -1, Boundary = -1, FullRate = -1,
            Slices = 0;
};

struct Scene
{
  hovrTest::FloatRenderView View;
  vtkNew<vtkVolume> Volume;
  vtkNew<vtkAdaptiveSamplingVolumeMapper> Mapper;
  vtkNew<vtkTest::ErrorObserver> Errors;

  bool Initialize(int width, int height, vtkImageData* data, vtkVolumeProperty* property)
  {
    hovrTest::Observe(this->Mapper, this->Errors);
    this->Mapper->SetInputData(data);
    this->Mapper->CountOperationsOn();
    this->Volume->SetMapper(this->Mapper);
    this->Volume->SetProperty(property);
    this->View.GetRenderer()->AddVolume(this->Volume);
    hovrTest::MakeBlobCamera(
      this->View.GetCamera()); // before the first frame, which Initialize draws
    return this->View.Initialize(width, height);
  }

  Frame Render()
  {
    Frame frame;
    frame.Image = this->View.Render();
    frame.Samples = this->Mapper->GetLastFrameSampleOperations();
    frame.Synthesis = this->Mapper->GetLastFrameSynthesisOperations();
    frame.Accumulates = this->Mapper->GetLastFrameAccumulateOperations();
    frame.Boundary = this->Mapper->GetLastFrameBoundarySampleOperations();
    frame.FullRate = this->Mapper->GetLastFrameFullRateSampleOperations();
    frame.Slices = this->Mapper->GetNumberOfSlices();
    return frame;
  }
};

// The CPU core's frame for the mapper's settings, camera and image size.
Frame RenderCPU(vtkImageData* data,
  vtkVolumeProperty* property,
  vtkCamera* camera,
  int width,
  int height,
  vtkAdaptiveSamplingVolumeMapper* mapper)
{
  vtkNew<vtkAdaptiveSamplingRayCaster> caster;
  caster->SetInputData(data);
  caster->SetVolumeProperty(property);
  caster->SetCamera(camera);
  caster->SetImageSize(width, height);
  caster->SetMaximumLevel(mapper->GetMaximumLevel());
  caster->SetOracleMode(mapper->GetOracleMode());
  caster->SetOracleArrayName(mapper->GetOracleArrayName());
  caster->SetTableSize(mapper->GetTableSize());
  caster->Update();
  Frame frame;
  frame.Image = vtkSmartPointer<vtkImageData>::New();
  frame.Image->DeepCopy(caster->GetOutput());
  frame.Samples = caster->GetNumberOfSampleOperations();
  frame.Synthesis = caster->GetNumberOfSynthesisOperations();
  frame.Accumulates = caster->GetNumberOfAccumulateOperations();
  frame.Boundary = caster->GetNumberOfBoundarySampleOperations();
  frame.FullRate = caster->GetFullRateSampleOperations();
  frame.Slices = caster->GetNumberOfSlices();
  return frame;
}

// Largest difference over the pixels of gpu (w x h), against the pixels of cpu (cw wide) at the
// same position.
double MaxDifference(vtkImageData* gpu, vtkImageData* cpu, int w, int h, int cw)
{
  vtkFloatArray* a = hovrTest::GetRGBA(gpu);
  vtkFloatArray* b = hovrTest::GetRGBA(cpu);
  if (!a || !b)
  {
    return 1e30;
  }
  double worst = 0.0;
  for (int y = 0; y < h; ++y)
  {
    for (int x = 0; x < w; ++x)
    {
      for (int c = 0; c < 4; ++c)
      {
        const double u = a->GetValue(4 * (static_cast<vtkIdType>(y) * w + x) + c);
        const double v = b->GetValue(4 * (static_cast<vtkIdType>(y) * cw + x) + c);
        worst = std::max(worst, std::isfinite(u) ? std::abs(u - v) : 1e30);
      }
    }
  }
  return worst;
}

// Checks that the GPU frame equals the CPU frame: image to ImageTolerance, counts exactly.
void Compare(const Frame& gpu, const Frame& cpu, int w, int h, int cw, const std::string& what)
{
  const double worst = MaxDifference(gpu.Image, cpu.Image, w, h, cw);
  std::cout << what << ": samples " << gpu.Samples << " (CPU " << cpu.Samples << ", full rate "
            << cpu.FullRate << ", ratio " << static_cast<double>(cpu.Samples) / cpu.FullRate
            << "), synthesis " << gpu.Synthesis << " (CPU " << cpu.Synthesis << "), accumulate "
            << gpu.Accumulates << " (CPU " << cpu.Accumulates << "), boundary " << gpu.Boundary
            << " (CPU " << cpu.Boundary << "), slices " << gpu.Slices
            << ", largest image difference " << worst << "\n";
  check(worst <= ImageTolerance,
    what + ": image equals the CPU core's within " + std::to_string(ImageTolerance) + ", got " +
      std::to_string(worst));
  check(gpu.Samples == cpu.Samples,
    what + ": samples " + std::to_string(gpu.Samples) + " = CPU " + std::to_string(cpu.Samples));
  check(gpu.Synthesis == cpu.Synthesis,
    what + ": syntheses " + std::to_string(gpu.Synthesis) + " = CPU " +
      std::to_string(cpu.Synthesis));
  check(gpu.Accumulates == cpu.Accumulates,
    what + ": accumulates " + std::to_string(gpu.Accumulates) + " = CPU " +
      std::to_string(cpu.Accumulates));
  check(gpu.Boundary == cpu.Boundary,
    what + ": boundary fetches " + std::to_string(gpu.Boundary) + " = CPU " +
      std::to_string(cpu.Boundary));
  check(gpu.FullRate == cpu.FullRate,
    what + ": full rate " + std::to_string(gpu.FullRate) + " = CPU " +
      std::to_string(cpu.FullRate));
  check(gpu.Slices == cpu.Slices,
    what + ": slices " + std::to_string(gpu.Slices) + " = CPU " + std::to_string(cpu.Slices));
}

bool Empty(vtkImageData* image)
{
  return image && hovrTest::MaximumValue(image) == 0.0;
}
}

int TestAdaptiveSamplingVolumeMapper(int, char*[])
{
  hovrTest::MessageCapture messages;
  const int size = 96;
  auto volume = hovrTest::MakeBlobVolume();
  auto property = hovrTest::MakeBlobProperty(2.0);

  {
    Scene scene;
    if (!check(scene.Initialize(size, size, volume, property), "float capture attached"))
    {
      return check.Result("TestAdaptiveSamplingVolumeMapper");
    }
    vtkAdaptiveSamplingVolumeMapper* mapper = scene.Mapper;
    vtkCamera* camera = scene.View.GetCamera();
    check(mapper->GetMaximumLevel() == 3 && mapper->GetOracleMode() == 0 &&
        std::string(mapper->GetOracleArrayName()) == "OracleDistance" &&
        mapper->GetTableSize() == 256 && mapper->GetEarlyRayTermination(),
      "initial values: MaximumLevel 3, ORACLE_ARRAY, OracleDistance, TableSize 256, early "
      "termination on");

    //--------------------------------------------------------------------------
    // 1. The min. oracle (no early termination in the CPU core).
    mapper->SetOracleModeToMinimum();
    mapper->EarlyRayTerminationOff();
    for (int lmax : { 3, 0 })
    {
      mapper->SetMaximumLevel(lmax);
      const Frame gpu = scene.Render();
      const Frame cpu = RenderCPU(volume, property, camera, size, size, mapper);
      Compare(gpu, cpu, size, size, size, "min. oracle, l_max " + std::to_string(lmax));
      if (lmax == 3)
      {
        const double overhead = static_cast<double>(gpu.Samples) / gpu.FullRate - 1.0;
        // Coarse rays pass through block centres: not exactly 1/8^l of level 0's (0.5%).
        check.Near(overhead,
          1.0 / 8 + 1.0 / 64 + 1.0 / 512,
          0.005,
          "min. oracle, l_max 3: samples over the full rate");
      }
      else
      {
        check(gpu.Samples == gpu.FullRate && gpu.Synthesis == 0,
          "l_max 0 samples at the full rate and synthesises nothing");
      }
    }
    hovrTest::ExpectQuiet(check, scene.Errors, "the min. oracle");

    //--------------------------------------------------------------------------
    // 2. The distance oracle, without and with early ray termination (an opaque property, so
    // that rays through the blobs stop).
    mapper->SetOracleModeToArray();
    mapper->SetMaximumLevel(3);
    const Frame gpu = scene.Render();
    const Frame cpu = RenderCPU(volume, property, camera, size, size, mapper);
    Compare(gpu, cpu, size, size, size, "blobs, oracle, l_max 3");
    // The oracle's samples, plus those that replace a NaN synthesised near the outline of
    // each slice's cross-section (the CPU core's test measures both).
    check(gpu.Samples < gpu.FullRate / 8, "the oracle skips most samples");
    // Without counting, the passes cover only the pixels that can matter: the same image.
    mapper->CountOperationsOff();
    const Frame uncounted = scene.Render();
    check(
      MaxDifference(uncounted.Image, gpu.Image, size, size, size) == 0.0 && uncounted.Samples == -1,
      "without counting: the same image, counts -1");
    mapper->CountOperationsOn();

    auto opaque = hovrTest::MakeBlobProperty(0.1);
    scene.Volume->SetProperty(opaque);
    const Frame off = scene.Render();
    const Frame offCPU = RenderCPU(volume, opaque, camera, size, size, mapper);
    Compare(off, offCPU, size, size, size, "opaque blobs, no early termination");
    mapper->EarlyRayTerminationOn();
    const Frame on = scene.Render();
    const double worst = MaxDifference(on.Image, off.Image, size, size, size);
    std::cout << "early ray termination: samples " << on.Samples << " (without " << off.Samples
              << "), synthesis " << on.Synthesis << ", accumulate " << on.Accumulates
              << " (without " << off.Accumulates << "), largest difference " << worst << "\n";
    check(on.Samples < off.Samples && on.Accumulates < off.Accumulates,
      "early ray termination takes fewer samples and accumulates");
    check(worst <= 1.0 / 255.0 + 1e-6,
      "early ray termination changes the image by at most 1/255, got " + std::to_string(worst));
    check(hovrTest::CountCovered(on.Image, 1.0 - 1.0 / 255.0) > 50,
      "some rays are opaque enough to stop");
    mapper->CountOperationsOff();
    check(MaxDifference(scene.Render().Image, on.Image, size, size, size) == 0.0,
      "early ray termination without counting: the same image");
    mapper->CountOperationsOn();
    mapper->EarlyRayTerminationOff();
    scene.Volume->SetProperty(property);

    //--------------------------------------------------------------------------
    // 4. d >= 2^l_max everywhere: inside the box only the top level samples, every 8th slice.
    {
      auto far = vtkSmartPointer<vtkImageData>::New();
      far->DeepCopy(volume);
      vtkFloatArray::SafeDownCast(far->GetPointData()->GetArray("OracleDistance"))->Fill(1e6);
      mapper->SetInputData(far);
      const Frame g = scene.Render();
      const Frame c = RenderCPU(far, property, camera, size, size, mapper);
      Compare(g, c, size, size, size, "oracle 1e6 everywhere");
      // Inside, 1/512 of the full rate; outside, the distance to the box brings rays to the
      // entry face with shrinking steps on finer levels: a few times 1/512 on this volume;
      // and samples that replace a NaN synthesised near each cross-section's outline.
      check(g.Samples < g.FullRate / 20, "an oracle of 2^l_max samples a few percent");
      mapper->SetInputData(volume);
    }
    hovrTest::ExpectQuiet(check, scene.Errors, "the oracle frames");

    //--------------------------------------------------------------------------
    // The 2^l_max tables rebuild when Delta or the transfer function changes, not per frame;
    // after ReleaseGraphicsResources the next frame draws the same image again.
    {
      const int builds = mapper->GetTableBuildCount();
      const Frame again = scene.Render();
      check(mapper->GetTableBuildCount() == builds, "no table rebuild for an unchanged frame");
      camera->SetParallelScale(50.0);
      scene.Render();
      check(mapper->GetTableBuildCount() == builds + 8,
        "a new Delta rebuilds the 8 tables, got " +
          std::to_string(mapper->GetTableBuildCount() - builds));
      camera->SetParallelScale(48.0);
      property->GetScalarOpacity()->AddPoint(0.9, 0.5);
      scene.Render();
      property->GetScalarOpacity()->RemovePoint(0.9);
      scene.Render();
      check(mapper->GetTableBuildCount() == builds + 24,
        "Delta back with an opacity edit, then another edit: two more rebuilds of 8, got " +
          std::to_string(mapper->GetTableBuildCount() - builds));
      mapper->ReleaseGraphicsResources(scene.View.GetWindow());
      const Frame released = scene.Render();
      check(MaxDifference(released.Image, again.Image, size, size, size) == 0.0 &&
          released.Samples == again.Samples,
        "after ReleaseGraphicsResources: the same image and counts");
      property->ShadeOn();
      scene.Render();
      hovrTest::ExpectWarning(check, scene.Errors, "shading is not applied", "shading on");
      scene.Render();
      hovrTest::ExpectQuiet(check, scene.Errors, "shading on, second frame");
      property->ShadeOff();
    }
    hovrTest::ExpectQuiet(check, scene.Errors, "rebuilds and release");

    //--------------------------------------------------------------------------
    // The prop matrix moves the rays: a translated volume draws what the CPU core draws for
    // the data moved by the same offset.
    {
      scene.Volume->SetPosition(4.0, -3.0, 2.5);
      const Frame moved = scene.Render();
      auto shifted = vtkSmartPointer<vtkImageData>::New();
      shifted->DeepCopy(volume);
      shifted->SetOrigin(4.0, -3.0, 2.5);
      const Frame movedCPU = RenderCPU(shifted, property, camera, size, size, mapper);
      Compare(moved, movedCPU, size, size, size, "translated volume");
      scene.Volume->SetPosition(0.0, 0.0, 0.0);
    }

    //--------------------------------------------------------------------------
    // 5. A perspective camera: one error, nothing drawn; parallel again: drawn, no message.
    camera->SetParallelProjection(false);
    auto perspective = scene.Render();
    hovrTest::ExpectError(check, scene.Errors, "parallel projection", "perspective camera");
    check(Empty(perspective.Image), "perspective: nothing drawn");
    perspective = scene.Render();
    check(!scene.Errors->GetError(), "perspective: the error is reported once");
    check(
      Empty(perspective.Image) && perspective.Samples == -1, "perspective again: nothing drawn");
    camera->SetParallelProjection(true);
    check(!Empty(scene.Render().Image), "parallel again: drawn");
    hovrTest::ExpectQuiet(check, scene.Errors, "back to a parallel camera");

    //--------------------------------------------------------------------------
    // 6. Bad input.
    mapper->SetOracleArrayName("Missing");
    check(Empty(scene.Render().Image), "missing oracle array: nothing drawn");
    hovrTest::ExpectError(check, scene.Errors, "names no 1-component", "missing oracle array");
    mapper->SetOracleArrayName("OracleDistance");
    {
      auto nan = vtkSmartPointer<vtkImageData>::New();
      nan->DeepCopy(volume);
      vtkFloatArray::SafeDownCast(nan->GetPointData()->GetArray("OracleDistance"))
        ->SetValue(1234, std::numeric_limits<float>::quiet_NaN());
      mapper->SetInputData(nan);
      check(Empty(scene.Render().Image), "NaN oracle: nothing drawn");
      hovrTest::ExpectError(check, scene.Errors, "not finite", "NaN oracle");
      mapper->SetInputData(volume);
    }
    for (int lmax : { -1, 9 })
    {
      mapper->SetMaximumLevel(lmax);
      check(Empty(scene.Render().Image), "l_max " + std::to_string(lmax) + ": nothing drawn");
      hovrTest::ExpectError(check, scene.Errors, "outside [0, 8]", "l_max " + std::to_string(lmax));
    }
    mapper->SetMaximumLevel(3);
    {
      auto thin = hovrTest::MakeBlobVolume(1);
      mapper->SetInputData(thin);
      check(Empty(scene.Render().Image), "1-voxel-thick volume: nothing drawn");
      hovrTest::ExpectError(check, scene.Errors, "at least 2 points", "1-voxel-thick volume");
      mapper->SetInputData(volume);
    }
    mapper->CountOperationsOff();
    check(!Empty(scene.Render().Image) && mapper->GetLastFrameSampleOperations() == -1,
      "CountOperations off: drawn, counts -1");
    hovrTest::ExpectQuiet(check, scene.Errors, "valid input again");
  }

  //----------------------------------------------------------------------------
  // 3. A viewport not divisible by 2^l_max: the padded image continues the pixel grid to the
  // right and the top; the CPU core draws it with the padded size, the same Delta (parallel
  // scale times padded / real height) and the camera moved to the padded image's centre.
  {
    const int w = 100, h = 90, lmax = 3;
    const int pw = 104, ph = 96;
    Scene scene;
    scene.Initialize(w, h, volume, property);
    scene.Mapper->SetMaximumLevel(lmax);
    scene.Mapper->EarlyRayTerminationOff();
    const Frame gpu = scene.Render();
    vtkCamera* camera = scene.View.GetCamera();
    vtkNew<vtkCamera> padded;
    padded->DeepCopy(camera);
    const double delta = 2.0 * camera->GetParallelScale() / h;
    padded->SetParallelScale(camera->GetParallelScale() * ph / h);
    double right[3], up[3], forward[3];
    camera->GetViewUp(up);
    camera->GetDirectionOfProjection(forward);
    vtkMath::Cross(forward, up, right);
    vtkMath::Normalize(right);
    vtkMath::Cross(right, forward, up);
    double focal[3], position[3];
    camera->GetFocalPoint(focal);
    camera->GetPosition(position);
    for (int a = 0; a < 3; ++a)
    {
      const double shift = 0.5 * delta * ((pw - w) * right[a] + (ph - h) * up[a]);
      focal[a] += shift;
      position[a] += shift;
    }
    padded->SetFocalPoint(focal);
    padded->SetPosition(position);
    const Frame cpu = RenderCPU(volume, property, padded, pw, ph, scene.Mapper);
    Compare(gpu, cpu, w, h, pw, "viewport 100 x 90 (padded to 104 x 96)");
    hovrTest::ExpectQuiet(check, scene.Errors, "an odd viewport");
  }

  //----------------------------------------------------------------------------
  // 4. Fewer slices than 2^l_max: a slab 2 voxels thick through two blobs, seen nearly along
  // its normal.
  {
    auto slab = hovrTest::MakeBlobVolume(3, 21);
    Scene scene;
    scene.Initialize(size, size, slab, property);
    vtkCamera* camera = scene.View.GetCamera();
    camera->SetFocalPoint(31.5, 31.5, 1.0);
    camera->SetPosition(31.5 + 3.0, 31.5 + 2.0, 101.0);
    camera->SetViewUp(0, 1, 0);
    for (int lmax : { 3, 4 })
    {
      scene.Mapper->SetMaximumLevel(lmax);
      scene.Mapper->EarlyRayTerminationOff();
      const Frame gpu = scene.Render();
      const Frame cpu = RenderCPU(slab, property, camera, size, size, scene.Mapper);
      Compare(gpu, cpu, size, size, size, "slab, l_max " + std::to_string(lmax));
      check(gpu.Slices == (1 << lmax) + 1, "the slab takes 2^l_max + 1 slices");
      check(hovrTest::CountCovered(gpu.Image) > 100, "the slab is drawn");
    }
    hovrTest::ExpectQuiet(check, scene.Errors, "the slab");
  }

  //----------------------------------------------------------------------------
  // 7. Entry and exit pieces on a constant volume: every piece is exact for a constant (the
  // table's diagonal entry with its optical depth scaled to the piece's length). The GPU
  // composites in float32 (the scaling's pow too): a few float roundings per piece over a few
  // dozen pieces, below 1e-5; a piece dropped at a face, or a NaN spread from the silhouette,
  // misses by 1e-3 or more.
  {
    const int constantSize = 64;
    vtkNew<vtkVolumeProperty> flat;
    hovrTest::MakeConstantProperty(flat);
    auto constant = hovrTest::MakeConstantVolume(false);
    Scene scene;
    scene.Initialize(constantSize, constantSize, constant, flat);
    scene.Mapper->EarlyRayTerminationOff();
    vtkCamera* camera = scene.View.GetCamera();
    double centre[3];
    constant->GetCenter(centre);
    camera->SetFocalPoint(centre);
    camera->SetParallelScale(31.0);
    const double directions[2][3] = { { 100.0, 60.0, 80.0 }, { 0.0, 0.0, 100.0 } };
    const double ups[2][3] = { { 0, 0, 1 }, { 0, 1, 0 } };
    for (int view = 0; view < 2; ++view)
    {
      camera->SetPosition(centre[0] + directions[view][0],
        centre[1] + directions[view][1],
        centre[2] + directions[view][2]);
      camera->SetViewUp(ups[view][0], ups[view][1], ups[view][2]);
      for (int oracle = 0; oracle < 3; ++oracle)
      {
        auto data = hovrTest::MakeConstantVolume(oracle == 2);
        scene.Mapper->SetInputData(data);
        scene.Mapper->SetOracleMode(oracle == 0 ? vtkAdaptiveSamplingVolumeMapper::ORACLE_MINIMUM
                                                : vtkAdaptiveSamplingVolumeMapper::ORACLE_ARRAY);
        const std::string name = std::string("constant volume, ") +
          (view == 0 ? "oblique" : "along -z") +
          (oracle == 0      ? ", min. oracle"
              : oracle == 1 ? ", oracle 2^l_max"
                            : ", varying oracle");
        const Frame gpu = scene.Render();
        const Frame cpu = RenderCPU(data, flat, camera, constantSize, constantSize, scene.Mapper);
        Compare(gpu, cpu, constantSize, constantSize, constantSize, name);
        const double error =
          hovrTest::ConstantVolumeError(gpu.Image, data, flat, camera, constantSize);
        std::cout << name << ": largest difference from 1 - exp(-sigma chord) " << error << "\n";
        check(error <= 1e-5,
          name + ": exact for a constant scalar within 1e-5, got " + std::to_string(error));
        check(gpu.Boundary > 0, name + ": entry and exit fetches");
      }
    }
    hovrTest::ExpectQuiet(check, scene.Errors, "the constant volume");
  }

  messages.ExpectNone(check, "in the whole test");
  return check.Result("TestAdaptiveSamplingVolumeMapper");
}
