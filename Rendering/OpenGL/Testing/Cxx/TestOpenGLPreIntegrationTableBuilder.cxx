// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
// Proves that vtkOpenGLPreIntegrationTableBuilder builds the second-order table the CPU builds:
// for the narrow spikes of presets/transfer-functions/neghip-spikes.json (unit distance 1,
// slabs of length 4, at most 64 steps) at 32 x 21 x 9 and 64 x 41 x 17 entries (centre, chord,
// deviation), the GPU table read back from an RGBA32F texture matches
// vtkSecondOrderPreIntegrationTable's to float rounding, RGBA16F and RGBA8 targets to their
// storage precision, with and without the prefilter; the constant slabs are the exact
// exponential; every slab the CPU finds empty is exactly zero on both; the target texture is
// re-created when the sizes or format change and reused otherwise, left with linear filtering
// and clamp-to-edge wrapping; an iteration table wider than a texture row (a needle spike) is
// read correctly; the caller's OpenGL state survives a build; misuse fails with an error.
// Prints the GPU and CPU build times for three sizes (not asserted).
#include "hovrRenderTestUtilities.h"

#include "vtkOpenGLPreIntegrationTableBuilder.h"
#include "vtkOpenGLRenderWindow.h"
#include "vtkOpenGLState.h"
#include "vtkSecondOrderPreIntegrationTable.h"
#include "vtkTextureObject.h"
#include "vtkVolumeTransferFunctionSampler.h"
#include "vtk_glew.h"

#include <algorithm>
#include <cmath>
#include <iostream>
#include <string>

namespace
{
// Float rounding. Both builders run the same float operations in the same order, but an
// OpenGL implementation may fuse a multiply and an add, and its exp() need not round as the
// C++ library's (GLSL allows 3 ulps). A fused position moves a step by the iteration table's
// steepest slope s (per sample) times an ulp of the largest position, Samples - 1 (allowed
// for four steps of a slab on a steep flank); each step's alpha may differ by a few ulps of
// itself, and compositing adds a few ulps of 1 per step: 4 s ulp + 64 steps * 8 2^-24
// (3e-5).
double FloatTolerance(vtkSecondOrderPreIntegrationTable* table)
{
  vtkFloatArray* steps = table->GetIterationTable();
  double slope = 0.0;
  for (vtkIdType v = 4; v < steps->GetNumberOfValues(); ++v)
  {
    slope =
      std::max(slope, std::abs(static_cast<double>(steps->GetValue(v)) - steps->GetValue(v - 4)));
  }
  // The samples hold extinction (c tau, tau): a step's alpha moves by slope h at most.
  slope *= table->GetSegmentLength();
  const float top = static_cast<float>(steps->GetNumberOfTuples() - 1);
  const double ulp = std::nextafter(top, 2.0f * top) - top;
  return 4.0 * slope * ulp + 64.0 * 8.0 / 16777216.0;
}

// Half floats keep 11 significant bits; the conversion may truncate: one ulp, 2^-10
// relative, plus 2^-24 (the subnormal spacing) absolute.
const double HalfRelativeTolerance = 1.0 / 1024.0;
const double HalfAbsoluteTolerance = 1.0 / 16777216.0;
// 8-bit storage: one of the two nearest of 255 levels.
const double UnormTolerance = 1.0 / 255.0;

// presets/transfer-functions/neghip-spikes.json: opacity spikes at 40, 100 and 180 of half
// width 3 over [0, 255]; linear interpolation, no shading.
vtkSmartPointer<vtkVolumeProperty> MakeNeghipSpikes()
{
  vtkNew<vtkColorTransferFunction> color;
  color->SetColorSpaceToRGB();
  color->AddRGBPoint(0.0, 0.2, 0.3, 1.0);
  color->AddRGBPoint(89.25, 0.1, 0.9, 0.3);
  color->AddRGBPoint(178.5, 1.0, 0.8, 0.1);
  color->AddRGBPoint(255.0, 1.0, 0.1, 0.1);
  vtkNew<vtkPiecewiseFunction> opacity;
  const double nodes[][2] = { { 0.0, 0.0 },
    { 37.0, 0.0 },
    { 40.0, 0.5 },
    { 43.0, 0.0 },
    { 97.0, 0.0 },
    { 100.0, 0.7 },
    { 103.0, 0.0 },
    { 177.0, 0.0 },
    { 180.0, 0.9 },
    { 183.0, 0.0 },
    { 255.0, 0.0 } };
  for (const auto& node : nodes)
  {
    opacity->AddPoint(node[0], node[1]);
  }
  auto property = vtkSmartPointer<vtkVolumeProperty>::New();
  property->SetColor(color);
  property->SetScalarOpacity(opacity);
  property->SetScalarOpacityUnitDistance(1.0);
  property->SetInterpolationTypeToLinear();
  property->ShadeOff();
  return property;
}

// One opacity spike at 100 of half width 0.01: the iteration table needs the maximum 65536
// spacings, more than a texture row holds.
vtkSmartPointer<vtkVolumeProperty> MakeNeedleSpike()
{
  auto property = MakeNeghipSpikes();
  vtkPiecewiseFunction* opacity = property->GetScalarOpacity();
  opacity->RemoveAllPoints();
  opacity->AddPoint(0.0, 0.0);
  opacity->AddPoint(99.99, 0.0);
  opacity->AddPoint(100.0, 0.8);
  opacity->AddPoint(100.01, 0.0);
  opacity->AddPoint(255.0, 0.0);
  return property;
}

struct Sizes
{
  int Centre, Chord, Deviation;
};

vtkSmartPointer<vtkSecondOrderPreIntegrationTable> MakeTable(vtkVolumeProperty* property,
  const Sizes& sizes,
  bool computeEntries,
  int iterations = 64,
  bool prefilter = false)
{
  auto table = vtkSmartPointer<vtkSecondOrderPreIntegrationTable>::New();
  table->SetPrefilter(prefilter);
  table->SetVolumeProperty(property);
  table->SetSegmentLength(4.0);
  table->SetScalarRange(0.0, 255.0);
  table->SetTableSize(sizes.Centre);
  table->SetChordSize(sizes.Chord);
  table->SetChordRange(120.0);
  table->SetDeviationSize(sizes.Deviation);
  table->SetDeviationRange(40.0);
  table->SetIterations(iterations);
  table->SetComputeEntries(computeEntries);
  table->Update();
  return table;
}

struct Agreement
{
  double MaxAbs = 0.0;     // largest |gpu - cpu| over entries and channels
  double MaxExcess = 0.0;  // largest |gpu - cpu| - tolerance(cpu); <= 0 passes
  vtkIdType Identical = 0; // entries equal in all four channels
  vtkIdType Entries = 0;
};

// Compares gpu with cpu entry by entry; the tolerance grows with |cpu| by relative.
Agreement Compare(vtkFloatArray* gpu, vtkFloatArray* cpu, double absolute, double relative)
{
  Agreement result;
  result.Entries = cpu->GetNumberOfTuples();
  const float* g = gpu->GetPointer(0);
  const float* c = cpu->GetPointer(0);
  for (vtkIdType e = 0; e < result.Entries; ++e)
  {
    bool identical = true;
    for (int ch = 0; ch < 4; ++ch)
    {
      const double difference = std::abs(static_cast<double>(g[4 * e + ch]) - c[4 * e + ch]);
      result.MaxAbs = std::max(result.MaxAbs, difference);
      result.MaxExcess =
        std::max(result.MaxExcess, difference - absolute - relative * std::abs(c[4 * e + ch]));
      identical = identical && g[4 * e + ch] == c[4 * e + ch];
    }
    result.Identical += identical ? 1 : 0;
  }
  return result;
}

// Checks gpu against cpu within the tolerance; prints the agreement.
void CheckAgreement(hovrTest::Checker& check,
  vtkFloatArray* gpu,
  vtkFloatArray* cpu,
  double absolute,
  double relative,
  const std::string& what)
{
  if (!check(gpu->GetNumberOfTuples() == cpu->GetNumberOfTuples(), what + ": same entry count"))
  {
    return;
  }
  const Agreement agreement = Compare(gpu, cpu, absolute, relative);
  std::cout << what << ": max |GPU - CPU| = " << agreement.MaxAbs << " (tolerance " << absolute
            << " + " << relative << " |CPU|), identical entries " << agreement.Identical << " of "
            << agreement.Entries << "\n";
  check(agreement.MaxExcess <= 0.0,
    what + ": within " + std::to_string(absolute) + " + " + std::to_string(relative) +
      " |cpu|, exceeded by " + std::to_string(agreement.MaxExcess));
}

// The constant slabs (chord 0, deviation 0) are the exact exponential; the slabs the kernel
// finds empty are exactly zero in both tables.
void CheckShortcuts(hovrTest::Checker& check,
  vtkSecondOrderPreIntegrationTable* table,
  vtkFloatArray* gpu,
  vtkFloatArray* cpu,
  const std::string& what)
{
  const int nc = table->GetTableSize(), nb = table->GetChordSize(), nd = table->GetDeviationSize();
  const double spacing = 255.0 / (nc - 1);
  double constantError = 0.0;
  for (int i = 0; i < nc; ++i)
  {
    double rgbTau[4];
    table->GetSampler()->Evaluate(i == nc - 1 ? 255.0 : i * spacing, rgbTau);
    const double alpha = -std::expm1(-rgbTau[3] * 4.0);
    const double exact[4] = { rgbTau[0] * alpha, rgbTau[1] * alpha, rgbTau[2] * alpha, alpha };
    const vtkIdType e =
      i + static_cast<vtkIdType>(nc) * (nb / 2 + static_cast<vtkIdType>(nb) * (nd / 2));
    for (int c = 0; c < 4; ++c)
    {
      constantError = std::max(constantError, std::abs(gpu->GetValue(4 * e + c) - exact[c]));
    }
  }
  // One step of float arithmetic: a few ulps of a value below 1.
  check(constantError <= 1e-6,
    what + ": constant slabs are the exact exponential, error " + std::to_string(constantError));

  const vtkSecondOrderPreIntegrationTableKernel kernel = table->GetKernel();
  const float* runs = table->GetIterationEmptyRuns()->GetPointer(0);
  vtkIdType empty = 0, nonZeroCPU = 0, nonZeroGPU = 0;
  for (int k = 0; k < nd; ++k)
  {
    for (int j = 0; j < nb; ++j)
    {
      for (int i = 0; i < nc; ++i)
      {
        float x0, b, a;
        kernel.Path(i, std::min(j, nb - 1 - j), k, x0, b, a);
        if (!kernel.IsEmpty(x0, b, a, runs))
        {
          continue;
        }
        ++empty;
        const vtkIdType e = i + static_cast<vtkIdType>(nc) * (j + static_cast<vtkIdType>(nb) * k);
        for (int c = 0; c < 4; ++c)
        {
          nonZeroGPU += gpu->GetValue(4 * e + c) != 0.0f ? 1 : 0;
          nonZeroCPU += cpu->GetValue(4 * e + c) != 0.0f ? 1 : 0;
        }
      }
    }
  }
  std::cout << what << ": " << empty << " empty slabs of " << table->GetNumberOfEntries() << "\n";
  check(empty > table->GetNumberOfEntries() / 50, what + ": many empty slabs");
  check(nonZeroCPU == 0, what + ": empty slabs are 0 on the CPU, " + std::to_string(nonZeroCPU));
  check(nonZeroGPU == 0, what + ": empty slabs are 0 on the GPU, " + std::to_string(nonZeroGPU));
}

// Builds table into texture and reads it back; nullptr on failure.
vtkSmartPointer<vtkFloatArray> BuildAndDownload(hovrTest::Checker& check,
  vtkOpenGLPreIntegrationTableBuilder* builder,
  vtkOpenGLRenderWindow* window,
  vtkSecondOrderPreIntegrationTable* table,
  vtkTextureObject* texture,
  unsigned int format,
  const std::string& what)
{
  auto entries = vtkSmartPointer<vtkFloatArray>::New();
  if (!check(builder->Build(window, table, texture, format), what + ": Build succeeds") ||
    !check(builder->DownloadTable(texture, entries), what + ": DownloadTable succeeds"))
  {
    return nullptr;
  }
  check(texture->GetWidth() == static_cast<unsigned int>(table->GetTableSize()) &&
      texture->GetHeight() == static_cast<unsigned int>(table->GetChordSize()) &&
      texture->GetDepth() == static_cast<unsigned int>(table->GetDeviationSize()) &&
      texture->GetInternalFormat(VTK_FLOAT, 4, false) == format,
    what + ": texture of the table's sizes and the requested format");
  check(texture->GetMinificationFilter() == vtkTextureObject::Linear &&
      texture->GetMagnificationFilter() == vtkTextureObject::Linear &&
      texture->GetWrapS() == vtkTextureObject::ClampToEdge &&
      texture->GetWrapT() == vtkTextureObject::ClampToEdge &&
      texture->GetWrapR() == vtkTextureObject::ClampToEdge,
    what + ": linear filtering, clamp-to-edge wrapping");
  return entries;
}
}

int TestOpenGLPreIntegrationTableBuilder(int, char*[])
{
  hovrTest::Checker check;
  vtkNew<vtkRenderWindow> renderWindow;
  vtkNew<vtkRenderer> renderer;
  renderWindow->SetOffScreenRendering(1);
  renderWindow->SetSize(16, 16);
  renderWindow->AddRenderer(renderer);
  renderWindow->Render(); // creates the context
  auto* window = vtkOpenGLRenderWindow::SafeDownCast(renderWindow);
  if (!check(window != nullptr, "an OpenGL render window"))
  {
    return check.Result("TestOpenGLPreIntegrationTableBuilder");
  }

  vtkNew<vtkOpenGLPreIntegrationTableBuilder> builder;
  vtkNew<vtkTest::ErrorObserver> errors;
  hovrTest::Observe(builder, errors);
  auto property = MakeNeghipSpikes();
  vtkNew<vtkTextureObject> texture;

  // 32 x 21 x 9, without the prefilter: every format into one texture, which is reused or
  // re-created as needed.
  const Sizes small{ 32, 21, 9 };
  {
    auto cpu = MakeTable(property, small, true);
    auto gpuTable = MakeTable(property, small, false);
    check(gpuTable->GetTable()->GetNumberOfTuples() == 0, "ComputeEntries off leaves no entries");
    auto gpu =
      BuildAndDownload(check, builder, window, gpuTable, texture, GL_RGBA32F, "32 x 21 x 9 f32");
    if (gpu)
    {
      CheckAgreement(check, gpu, cpu->GetTable(), FloatTolerance(cpu), 0.0, "32 x 21 x 9 RGBA32F");
      CheckShortcuts(check, gpuTable, gpu, cpu->GetTable(), "32 x 21 x 9 RGBA32F");
    }
    const unsigned int handle = texture->GetHandle();
    builder->Build(window, gpuTable, texture, GL_RGBA32F);
    check(texture->GetHandle() == handle, "same size and format: the texture is reused");

    // The caller's state survives: framebuffer bindings, viewport, blending (as VTK's state
    // cache sees them; it queries OpenGL for the bindings).
    vtkOpenGLState* state = window->GetState();
    state->vtkglEnable(GL_BLEND);
    GLint before[6], after[6];
    state->vtkglGetIntegerv(GL_VIEWPORT, before);
    state->vtkglGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, before + 4);
    state->vtkglGetIntegerv(GL_READ_FRAMEBUFFER_BINDING, before + 5);
    builder->Build(window, gpuTable, texture, GL_RGBA32F);
    state->vtkglGetIntegerv(GL_VIEWPORT, after);
    state->vtkglGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, after + 4);
    state->vtkglGetIntegerv(GL_READ_FRAMEBUFFER_BINDING, after + 5);
    GLboolean blend = GL_FALSE;
    state->vtkglGetBooleanv(GL_BLEND, &blend);
    check(std::equal(before, before + 6, after) && blend == GL_TRUE,
      "viewport, framebuffer bindings and blending restored");

    auto half =
      BuildAndDownload(check, builder, window, gpuTable, texture, GL_RGBA16F, "32 x 21 x 9 f16");
    if (half)
    {
      CheckAgreement(check,
        half,
        cpu->GetTable(),
        HalfAbsoluteTolerance + FloatTolerance(cpu),
        HalfRelativeTolerance,
        "32 x 21 x 9 RGBA16F");
    }
    auto unorm =
      BuildAndDownload(check, builder, window, gpuTable, texture, GL_RGBA8, "32 x 21 x 9 u8");
    if (unorm)
    {
      CheckAgreement(check,
        unorm,
        cpu->GetTable(),
        UnormTolerance + FloatTolerance(cpu),
        0.0,
        "32 x 21 x 9 RGBA8");
    }
  }

  // 64 x 41 x 17, with the prefilter: the texture grows.
  const Sizes larger{ 64, 41, 17 };
  {
    auto cpu = MakeTable(property, larger, true, 64, true);
    auto gpuTable = MakeTable(property, larger, false, 64, true);
    auto gpu =
      BuildAndDownload(check, builder, window, gpuTable, texture, GL_RGBA32F, "64 x 41 x 17 f32");
    if (gpu)
    {
      CheckAgreement(check, gpu, cpu->GetTable(), FloatTolerance(cpu), 0.0, "64 x 41 x 17 RGBA32F");
    }
    auto half =
      BuildAndDownload(check, builder, window, gpuTable, texture, GL_RGBA16F, "64 x 41 x 17 f16");
    if (half)
    {
      CheckAgreement(check,
        half,
        cpu->GetTable(),
        HalfAbsoluteTolerance + FloatTolerance(cpu),
        HalfRelativeTolerance,
        "64 x 41 x 17 RGBA16F");
    }
    // A 2D texture (as the mapper's first-order table) becomes the 3D table.
    vtkNew<vtkTextureObject> flat;
    flat->SetContext(window);
    flat->Allocate2D(8, 8, 4, VTK_FLOAT);
    auto fromFlat = BuildAndDownload(check, builder, window, gpuTable, flat, GL_RGBA32F, "2D->3D");
    check(flat->GetNumberOfDimensions() == 3, "a 2D texture is re-created as a 3D one");
    if (fromFlat)
    {
      CheckAgreement(check, fromFlat, gpu, 0.0, 0.0, "64 x 41 x 17 into a former 2D texture");
    }
  }
  // A needle spike: the iteration table spans several texture rows.
  {
    auto needle = MakeNeedleSpike();
    auto cpu = MakeTable(needle, small, true);
    auto gpuTable = MakeTable(needle, small, false);
    const int fine = gpuTable->GetNumberOfIterationSamples();
    check(fine > vtkTextureObject::GetMaximumTextureSize(window),
      "needle spike: the iteration table (" + std::to_string(fine) +
        " samples) is wider than a texture row");
    auto gpu = BuildAndDownload(check, builder, window, gpuTable, texture, GL_RGBA32F, "needle");
    if (gpu)
    {
      CheckAgreement(check, gpu, cpu->GetTable(), FloatTolerance(cpu), 0.0, "needle RGBA32F");
    }
  }
  hovrTest::ExpectQuiet(check, errors, "valid builds");

  // Misuse fails with an error and leaves the texture alone.
  {
    auto table = MakeTable(property, { 16, 9, 5 }, false);
    const unsigned int handle = texture->GetHandle();
    const unsigned int width = texture->GetWidth();
    check(!builder->Build(nullptr, table, texture, GL_RGBA32F), "no window: fails");
    hovrTest::ExpectError(check, errors, "needs a render window", "no window");
    check(!builder->Build(window, table, texture, GL_RGB8), "GL_RGB8: fails");
    hovrTest::ExpectError(check, errors, "Unsupported internal format 0x8051;", "GL_RGB8");
    table->SetTableSize(24); // not updated since
    check(!builder->Build(window, table, texture, GL_RGBA32F), "stale table: fails");
    hovrTest::ExpectError(check, errors, "call Update()", "stale table");
    auto fresh = vtkSmartPointer<vtkSecondOrderPreIntegrationTable>::New();
    check(!builder->Build(window, fresh, texture, GL_RGBA32F), "never updated: fails");
    hovrTest::ExpectError(check, errors, "call Update()", "never updated");
    check(texture->GetHandle() == handle && texture->GetWidth() == width,
      "failed builds leave the texture alone");
    vtkNew<vtkTextureObject> unallocated;
    vtkNew<vtkFloatArray> entries;
    check(!builder->DownloadTable(unallocated, entries), "download of no texture: fails");
    hovrTest::ExpectError(check, errors, "allocated 3D texture", "download of no texture");
  }

  // Timings for the report, not asserted (at most 64 steps; RGBA16F, as the mapper stores 3D
  // tables). The CPU time is the table's whole build, iteration table included.
  for (const Sizes& timedSizes :
    { Sizes{ 64, 65, 33 }, Sizes{ 128, 129, 65 }, Sizes{ 256, 257, 129 } })
  {
    auto gpuTable = MakeTable(property, timedSizes, false);
    vtkNew<vtkTextureObject> timed;
    builder->Build(window, gpuTable, timed, GL_RGBA16F);
    auto cpu = MakeTable(property, timedSizes, true);
    std::cout << timedSizes.Centre << " x " << timedSizes.Chord << " x " << timedSizes.Deviation
              << ", at most 64 steps: GPU " << builder->GetLastBuildTime() << " s, CPU "
              << cpu->GetLastBuildTime() << " s\n";
  }
  hovrTest::ExpectQuiet(check, errors, "timed builds");
  return check.Result("TestOpenGLPreIntegrationTableBuilder");
}
