// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
// Proves that vtkOpenGLPreIntegrationTableBuilder builds the second-order table the CPU builds:
// for the narrow spikes of presets/transfer-functions/neghip-spikes.json (unit distance 1,
// slabs of length 4, 64 iterations) at N = 32 and 64, the GPU table read back from an RGBA32F
// texture matches vtkSecondOrderPreIntegrationTable's to float rounding, RGBA16F and RGBA8
// targets to their storage precision, with and without the prefilter; the diagonal is the
// exact exponential (of the box-averaged transfer function with the prefilter); every slab the
// CPU finds empty is exactly zero on both; the target texture is re-created when the size or
// format changes and reused otherwise, left with linear filtering and clamp-to-edge wrapping;
// an iteration table wider than a texture row (a needle spike) is read correctly; the
// caller's OpenGL state survives a build; misuse fails with an error. Prints the GPU and CPU
// build times for N = 64, 128 and 256 (not asserted).
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
// Float rounding. Both builders run the same float operations in the same order (the tables
// are identical bit for bit on llvmpipe), but an OpenGL implementation may fuse a multiply
// and an add. That moves a sample position by an ulp of the largest position, Fine - 1, which
// changes a step by the iteration table's steepest slope s (per position unit) times that ulp
// (allowed for four steps of a slab on a steep flank), and a composited value by a few ulps
// of 1 per step (four per step for 64 steps): 4 s ulp(Fine - 1) + 256 2^-24 (1.5e-5).
double FloatTolerance(vtkSecondOrderPreIntegrationTable* table)
{
  vtkFloatArray* steps = table->GetIterationTable();
  double slope = 0.0;
  for (vtkIdType v = 4; v < steps->GetNumberOfValues(); ++v)
  {
    slope =
      std::max(slope, std::abs(static_cast<double>(steps->GetValue(v)) - steps->GetValue(v - 4)));
  }
  const float top = static_cast<float>(steps->GetNumberOfTuples() - 1);
  const double ulp = std::nextafter(top, 2.0f * top) - top;
  return 4.0 * slope * ulp + 256.0 / 16777216.0;
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

vtkSmartPointer<vtkSecondOrderPreIntegrationTable> MakeTable(vtkVolumeProperty* property,
  int size,
  bool computeEntries,
  int iterations = 64,
  bool prefilter = true)
{
  auto table = vtkSmartPointer<vtkSecondOrderPreIntegrationTable>::New();
  table->SetPrefilter(prefilter);
  table->SetVolumeProperty(property);
  table->SetSegmentLength(4.0);
  table->SetScalarRange(0.0, 255.0);
  table->SetTableSize(size);
  table->SetIterations(iterations);
  table->SetComputeEntries(computeEntries);
  table->Update();
  return table;
}

// The CPU's empty-slab shortcut (vtkSecondOrderPreIntegrationTable::BuildTable), in its double
// arithmetic: the range of the quadratic over [0, 1] lies in one zero-opacity run of the
// iteration table. For the pair (i, j, k), (k, j, i) with i <= k.
bool CPUFindsEmpty(vtkSecondOrderPreIntegrationTable* table, int i, int j, int k)
{
  const double p = table->GetIterationSamplesPerSpacing();
  const int fine = table->GetIterationSamplesPerSpacing() * (table->GetTableSize() - 1) + 1;
  const float* runs = table->GetIterationEmptyRuns()->GetPointer(0);
  const double xf = p * i, xm = p * j, xb = p * k;
  const double a = 2.0 * xf - 4.0 * xm + 2.0 * xb;
  const double b = -3.0 * xf + 4.0 * xm - xb;
  double lo = std::min(xf, xb), hi = std::max(xf, xb);
  const double vertex = a != 0.0 ? -b / (2.0 * a) : -1.0;
  if (vertex > 0.0 && vertex < 1.0)
  {
    const double extremum = xf + vertex * (b + a * vertex);
    lo = std::min(lo, extremum);
    hi = std::max(hi, extremum);
  }
  lo = std::max(lo, 0.0);
  hi = std::min(hi, fine - 1.0);
  if (hi == lo)
  {
    return false; // constant: the exact exponential
  }
  const int qlo = std::min(static_cast<int>(lo), fine - 2);
  const int qhi = std::min(static_cast<int>(hi), fine - 2);
  return runs[qlo] >= 0.0f && runs[qlo] == runs[qhi];
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

// The diagonal is the exact exponential; the slabs the CPU finds empty are exactly zero in
// both tables.
void CheckShortcuts(hovrTest::Checker& check,
  vtkSecondOrderPreIntegrationTable* table,
  vtkFloatArray* gpu,
  vtkFloatArray* cpu,
  const std::string& what)
{
  const int n = table->GetTableSize();
  const double spacing = 255.0 / (n - 1);
  double diagonalError = 0.0;
  for (int i = 0; i < n; ++i)
  {
    // Without the prefilter the exact transfer function; with it, the box average that the
    // CPU computes (checked by TestSecondOrderPreIntegrationTable).
    double rgbTau[4];
    table->GetSampler()->Evaluate(i == n - 1 ? 255.0 : i * spacing, rgbTau);
    const double alpha = -std::expm1(-rgbTau[3] * 4.0);
    double exact[4] = { rgbTau[0] * alpha, rgbTau[1] * alpha, rgbTau[2] * alpha, alpha };
    if (table->GetPrefilter())
    {
      table->GetDiagonalTable()->GetTuple(i, exact);
    }
    const vtkIdType e = i + static_cast<vtkIdType>(n) * (i + static_cast<vtkIdType>(n) * i);
    for (int c = 0; c < 4; ++c)
    {
      diagonalError = std::max(diagonalError, std::abs(gpu->GetValue(4 * e + c) - exact[c]));
    }
  }
  // Rounding the exact value to float: half a unit in the last place of a value below 1.
  check(diagonalError <= 6e-8,
    what + ": diagonal is the exact exponential, error " + std::to_string(diagonalError));

  vtkIdType empty = 0, nonZeroCPU = 0, nonZeroGPU = 0, zeroGPU = 0;
  for (int k = 0; k < n; ++k)
  {
    for (int j = 0; j < n; ++j)
    {
      for (int i = 0; i < n; ++i)
      {
        const vtkIdType e = i + static_cast<vtkIdType>(n) * (j + static_cast<vtkIdType>(n) * k);
        bool gpuZero = true, cpuZero = true;
        for (int c = 0; c < 4; ++c)
        {
          gpuZero = gpuZero && gpu->GetValue(4 * e + c) == 0.0f;
          cpuZero = cpuZero && cpu->GetValue(4 * e + c) == 0.0f;
        }
        zeroGPU += gpuZero ? 1 : 0;
        if (CPUFindsEmpty(table, std::min(i, k), j, std::max(i, k)))
        {
          ++empty;
          nonZeroCPU += cpuZero ? 0 : 1;
          nonZeroGPU += gpuZero ? 0 : 1;
        }
      }
    }
  }
  std::cout << what << ": " << empty << " empty slabs of " << static_cast<vtkIdType>(n) * n * n
            << ", " << zeroGPU << " zero GPU entries\n";
  // The three spikes leave about 5% of the slabs empty: the check must see many.
  check(empty > static_cast<vtkIdType>(n) * n * n / 50, what + ": many empty slabs");
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
  const unsigned int n = table->GetTableSize();
  check(texture->GetWidth() == n && texture->GetHeight() == n && texture->GetDepth() == n &&
      texture->GetInternalFormat(VTK_FLOAT, 4, false) == format,
    what + ": texture is N^3 of the requested format");
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

  // N = 32, without the prefilter: every format into one texture, which is reused or
  // re-created as needed.
  {
    auto cpu = MakeTable(property, 32, true, 64, false);
    auto gpuTable = MakeTable(property, 32, false, 64, false);
    check(gpuTable->GetTable()->GetNumberOfTuples() == 0, "ComputeEntries off leaves no entries");
    auto gpu = BuildAndDownload(check, builder, window, gpuTable, texture, GL_RGBA32F, "32^3 f32");
    if (gpu)
    {
      CheckAgreement(check, gpu, cpu->GetTable(), FloatTolerance(cpu), 0.0, "32^3 RGBA32F");
      CheckShortcuts(check, gpuTable, gpu, cpu->GetTable(), "32^3 RGBA32F");
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

    auto half = BuildAndDownload(check, builder, window, gpuTable, texture, GL_RGBA16F, "32^3 f16");
    if (half)
    {
      CheckAgreement(check,
        half,
        cpu->GetTable(),
        HalfAbsoluteTolerance + FloatTolerance(cpu),
        HalfRelativeTolerance,
        "32^3 RGBA16F");
    }
    auto unorm = BuildAndDownload(check, builder, window, gpuTable, texture, GL_RGBA8, "32^3 u8");
    if (unorm)
    {
      CheckAgreement(
        check, unorm, cpu->GetTable(), UnormTolerance + FloatTolerance(cpu), 0.0, "32^3 RGBA8");
    }
  }

  // N = 64, with the prefilter: the texture grows.
  {
    auto cpu = MakeTable(property, 64, true);
    auto gpuTable = MakeTable(property, 64, false);
    auto gpu = BuildAndDownload(check, builder, window, gpuTable, texture, GL_RGBA32F, "64^3 f32");
    if (gpu)
    {
      CheckAgreement(check, gpu, cpu->GetTable(), FloatTolerance(cpu), 0.0, "64^3 RGBA32F");
      CheckShortcuts(check, gpuTable, gpu, cpu->GetTable(), "64^3 RGBA32F");
    }
    auto half = BuildAndDownload(check, builder, window, gpuTable, texture, GL_RGBA16F, "64^3 f16");
    if (half)
    {
      CheckAgreement(check,
        half,
        cpu->GetTable(),
        HalfAbsoluteTolerance + FloatTolerance(cpu),
        HalfRelativeTolerance,
        "64^3 RGBA16F");
    }
    // A 2D texture (as the mapper's first-order table) becomes the 3D table.
    vtkNew<vtkTextureObject> flat;
    flat->SetContext(window);
    flat->Allocate2D(8, 8, 4, VTK_FLOAT);
    auto fromFlat = BuildAndDownload(check, builder, window, gpuTable, flat, GL_RGBA32F, "2D->3D");
    check(flat->GetNumberOfDimensions() == 3, "a 2D texture is re-created as a 3D one");
    if (fromFlat)
    {
      CheckAgreement(check, fromFlat, gpu, 0.0, 0.0, "64^3 into a former 2D texture");
    }
  }
  // A needle spike: the iteration table spans several texture rows.
  {
    auto needle = MakeNeedleSpike();
    auto cpu = MakeTable(needle, 32, true);
    auto gpuTable = MakeTable(needle, 32, false);
    const int fine = gpuTable->GetIterationSamplesPerSpacing() * 31 + 1;
    check(fine > vtkTextureObject::GetMaximumTextureSize(window),
      "needle spike: the iteration table (" + std::to_string(fine) +
        " samples) is wider than a texture row");
    auto gpu = BuildAndDownload(check, builder, window, gpuTable, texture, GL_RGBA32F, "needle");
    if (gpu)
    {
      CheckAgreement(check, gpu, cpu->GetTable(), FloatTolerance(cpu), 0.0, "needle 32^3 RGBA32F");
    }
  }
  hovrTest::ExpectQuiet(check, errors, "valid builds");

  // Misuse fails with an error and leaves the texture alone.
  {
    auto table = MakeTable(property, 16, false);
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

  // Timings for the report, not asserted (64 iterations; RGBA16F, as the mapper stores 3D
  // tables). The CPU time is the table's whole build, iteration table included.
  for (int n : { 64, 128, 256 })
  {
    auto gpuTable = MakeTable(property, n, false);
    vtkNew<vtkTextureObject> timed;
    builder->Build(window, gpuTable, timed, GL_RGBA16F);
    auto cpu = MakeTable(property, n, true);
    std::cout << "N = " << n << ", 64 iterations: GPU " << builder->GetLastBuildTime() << " s, CPU "
              << cpu->GetLastBuildTime() << " s\n";
  }
  hovrTest::ExpectQuiet(check, errors, "timed builds");
  return check.Result("TestOpenGLPreIntegrationTableBuilder");
}
