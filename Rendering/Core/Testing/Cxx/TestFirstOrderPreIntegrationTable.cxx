// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
// vtkFirstOrderPreIntegrationTable against closed forms of the segment integral
//   alpha = 1 - exp(-int_0^d tau), C = int_0^d c tau exp(-int_0^t tau) dt,
// its symmetries, its rebuild bookkeeping, its error handling and SuggestTableSize.
#include "vtkColorTransferFunction.h"
#include "vtkFirstOrderPreIntegrationTable.h"
#include "vtkFloatArray.h"
#include "vtkMinimalStandardRandomSequence.h"
#include "vtkNew.h"
#include "vtkPiecewiseFunction.h"
#include "vtkVolumeProperty.h"
#include "vtkVolumeTransferFunctionSampler.h"

#include "hovrTestUtilities.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <string>

namespace
{
// The table is float: every value is a double result rounded once to float (relative error
// 2^-24) and all values lie in [0, 1], so 2^-23 ~ 1.2e-7 absolute covers that rounding plus
// the double-precision accumulation over at most a few thousand pieces (< 1e-12).
constexpr double FloatTolerance = 1.2e-7;

hovrTest::Checker check;

// Scalar of table entry i, as documented: entry 0 at range[0], entry N - 1 at range[1].
double EntryScalar(vtkPreIntegrationTable* table, int i)
{
  const double* r = table->GetScalarRange();
  return r[0] + (r[1] - r[0]) * i / (table->GetTableSize() - 1.0);
}

// Every entry must be the constant-medium segment: alpha = 1 - exp(-tau d), C = c alpha.
void CheckConstantMedium(vtkFirstOrderPreIntegrationTable* table,
  const double c[3],
  double tau,
  const char* label)
{
  const double alpha = -std::expm1(-tau * table->GetSegmentLength());
  const int n = table->GetTableSize();
  double worst = 0.0;
  for (int j = 0; j < n; ++j)
  {
    for (int i = 0; i < n; ++i)
    {
      double rgba[4];
      table->GetEntry(i, j, rgba);
      worst = std::max(worst, std::abs(rgba[3] - alpha));
      for (int k = 0; k < 3; ++k)
      {
        worst = std::max(worst, std::abs(rgba[k] - c[k] * alpha));
      }
    }
  }
  check.Near(worst,
    0.0,
    FloatTolerance,
    std::string(label) + ": largest deviation from alpha = 1 - exp(-tau d), C = c alpha");
}
}

int TestFirstOrderPreIntegrationTable(int, char*[])
{
  hovrTest::MessageCapture messages;

  //----------------------------------------------------------------------------
  // 1. Constant transfer function, single nodes: alpha = 1 - exp(-tau d), C = c alpha for
  //    every (front, back), whatever the number of pieces the segment is cut into.
  const double c[3] = { 0.2, 0.5, 0.9 };
  const double unit = 2.0;
  const double tau = -std::log(1.0 - 0.3) / unit;
  {
    vtkNew<vtkColorTransferFunction> color;
    color->AddRGBPoint(3.0, c[0], c[1], c[2]);
    vtkNew<vtkPiecewiseFunction> opacity;
    opacity->AddPoint(3.0, 0.3);
    vtkNew<vtkVolumeProperty> property;
    property->SetColor(color);
    property->SetScalarOpacity(opacity);
    property->SetScalarOpacityUnitDistance(unit);
    vtkNew<vtkFirstOrderPreIntegrationTable> table;
    table->SetVolumeProperty(property);
    table->SetScalarRange(0.0, 10.0);
    table->SetTableSize(33);
    table->SetSegmentLength(1.5);
    table->SetSubSamples(3);
    check(table->Update(), "Update with a constant transfer function");
    check(table->GetTable()->GetNumberOfTuples() == 33 * 33, "table has N^2 entries");
    check(table->GetTable()->GetNumberOfComponents() == 4, "table is RGBA");
    check(table->GetNumberOfDimensions() == 2, "first-order table is 2D");
    check(table->GetMemorySize() == 33 * 33 * 4 * static_cast<vtkIdType>(sizeof(float)),
      "memory size is N^2 RGBA floats");
    CheckConstantMedium(table, c, tau, "single-node transfer function");
  }
  {
    // Several nodes, all equal, with midpoints and sharpness: still a constant medium.
    vtkNew<vtkColorTransferFunction> color;
    color->AddRGBPoint(0.0, c[0], c[1], c[2], 0.3, 0.0);
    color->AddRGBPoint(4.0, c[0], c[1], c[2], 0.7, 0.6);
    color->AddRGBPoint(7.0, c[0], c[1], c[2], 0.5, 1.0);
    vtkNew<vtkPiecewiseFunction> opacity;
    opacity->AddPoint(1.0, 0.3, 0.3, 0.5);
    opacity->AddPoint(5.0, 0.3, 0.8, 0.0);
    opacity->AddPoint(9.0, 0.3, 0.5, 1.0);
    vtkNew<vtkVolumeProperty> property;
    property->SetColor(color);
    property->SetScalarOpacity(opacity);
    property->SetScalarOpacityUnitDistance(unit);
    vtkNew<vtkFirstOrderPreIntegrationTable> table;
    table->SetVolumeProperty(property);
    table->SetScalarRange(-1.0, 11.0);
    table->SetTableSize(25);
    table->SetSegmentLength(0.75);
    check(table->Update(), "Update with equal nodes");
    CheckConstantMedium(table, c, tau, "equal-node transfer function");
  }

  //----------------------------------------------------------------------------
  // 2. Any transfer function: the diagonal s_f = s_b is the exact constant segment at that
  //    scalar, with colour and opacity taken from VTK's own functions (independent of the
  //    sampler); off the diagonal alpha is symmetric, since the same pieces are attenuated in
  //    the opposite order.
  {
    vtkNew<vtkMinimalStandardRandomSequence> random;
    random->SetSeed(11);
    auto next = [&]()
    {
      random->Next();
      return random->GetValue();
    };
    vtkNew<vtkColorTransferFunction> color;
    vtkNew<vtkPiecewiseFunction> opacity;
    double x = 0.0;
    for (int node = 0; node < 6; ++node)
    {
      x += 0.5 + 3.0 * next();
      const double sharpness = node % 2 ? 0.0 : next();
      color->AddRGBPoint(x, next(), next(), next(), 0.1 + 0.8 * next(), sharpness);
      opacity->AddPoint(x + 0.4, 0.95 * next(), 0.1 + 0.8 * next(), 1.0 - sharpness);
    }
    vtkNew<vtkVolumeProperty> property;
    property->SetColor(color);
    property->SetScalarOpacity(opacity);
    property->SetScalarOpacityUnitDistance(0.8);
    vtkNew<vtkFirstOrderPreIntegrationTable> table;
    table->SetVolumeProperty(property);
    table->SetScalarRange(-1.0, x + 1.0);
    table->SetTableSize(64);
    table->SetSegmentLength(1.3);
    table->SetSubSamples(2);
    check(table->Update(), "Update with a random transfer function");
    const int n = table->GetTableSize();
    // VTK's functions and the sampler agree to 1e-12 in opacity (TestVolumeTransferFunction-
    // Sampler), i.e. < 1e-10 in tau for opacities <= 0.95; the rest is float rounding.
    const double diagonalTolerance = FloatTolerance + 1e-10;
    double worstDiagonal = 0.0, worstSymmetry = 0.0, largestColourAsymmetry = 0.0;
    for (int i = 0; i < n; ++i)
    {
      const double s = EntryScalar(table, i);
      double rgb[3], rgba[4];
      color->GetColor(s, rgb);
      const double t = -std::log(1.0 - opacity->GetValue(s)) / 0.8;
      const double alpha = -std::expm1(-t * 1.3);
      table->GetEntry(i, i, rgba);
      worstDiagonal = std::max(worstDiagonal, std::abs(rgba[3] - alpha));
      for (int k = 0; k < 3; ++k)
      {
        worstDiagonal = std::max(worstDiagonal, std::abs(rgba[k] - rgb[k] * alpha));
      }
      for (int j = i + 1; j < n; ++j)
      {
        double forward[4], backward[4];
        table->GetEntry(i, j, forward);
        table->GetEntry(j, i, backward);
        worstSymmetry = std::max(worstSymmetry, std::abs(forward[3] - backward[3]));
        for (int k = 0; k < 3; ++k)
        {
          largestColourAsymmetry =
            std::max(largestColourAsymmetry, std::abs(forward[k] - backward[k]));
        }
      }
    }
    check.Near(worstDiagonal,
      0.0,
      diagonalTolerance,
      "diagonal entries equal the exact constant segment (largest deviation)");
    check.Near(worstSymmetry, 0.0, FloatTolerance, "alpha(s_f, s_b) == alpha(s_b, s_f)");
    // Colour depends on the order (what is in front attenuates what is behind).
    check(largestColourAsymmetry > 0.05, "colour is not symmetric in (s_f, s_b)");
  }

  //----------------------------------------------------------------------------
  // 3. Linear scalar, constant opacity (tau), linear colour ramp. Along the segment
  //    s(t) = s_f + (s_b - s_f) t / d, so c(t) = c0 + c1 t with c0 = c(s_f) and
  //    c1 = (c(s_b) - c(s_f)) / d, and the transmittance is exp(-tau t). Then
  //      C = int_0^d (c0 + c1 t) tau e^{-tau t} dt
  //        = c0 (1 - e^{-tau d}) + c1 int_0^d t tau e^{-tau t} dt,
  //    and by parts, int_0^d t tau e^{-tau t} dt = [-t e^{-tau t}]_0^d + int_0^d e^{-tau t} dt
  //        = -d e^{-tau d} + (1 - e^{-tau d}) / tau = (1 - e^{-tau d} (1 + tau d)) / tau.
  //    Error of the table's scheme: P = |j - i| SubSamples pieces of length h = d / P, each
  //    with the midpoint colour and the exact attenuation. Per piece, with x = tau h, the
  //    exact integral minus the midpoint value is c1 T_start (h/2 (1 - e^{-x})
  //    - (1 - e^{-x} (1 + x)) / tau) = c1 T_start (x^3/12 - x^4/24 + ...) / tau, at most
  //    |c1| tau^2 h^3 / 12, so |error| <= P |c1| tau^2 h^3 / 12 = |dc| tau^2 d^2 / (12 P^2)
  //    with dc = c(s_b) - c(s_f): second order in 1 / SubSamples.
  //    Sum rule, exact for the scheme: the reversed segment visits the same midpoints in the
  //    opposite order with the same weights, and a linear colour at mirrored midpoints sums
  //    to c(s_f) + c(s_b), so C(s_f, s_b) + C(s_b, s_f) = (c(s_f) + c(s_b)) alpha.
  {
    vtkNew<vtkColorTransferFunction> color;
    color->AddRGBPoint(0.0, 0.0, 0.3, 1.0);
    color->AddRGBPoint(1.0, 1.0, 0.3, 0.0);
    vtkNew<vtkPiecewiseFunction> opacity;
    opacity->AddPoint(0.5, 0.5);
    vtkNew<vtkVolumeProperty> property;
    property->SetColor(color);
    property->SetScalarOpacity(opacity);
    property->SetScalarOpacityUnitDistance(1.0);
    const double t = std::log(2.0); // -ln(1 - 0.5) / 1
    const double d = 3.0;
    const double e = std::exp(-t * d);
    const double alpha = 1.0 - e;
    const double ramp = (1.0 - e * (1.0 + t * d)) / t;
    vtkNew<vtkFirstOrderPreIntegrationTable> table;
    table->SetVolumeProperty(property);
    table->SetScalarRange(0.0, 1.0);
    table->SetTableSize(9);
    table->SetSegmentLength(d);
    const int n = table->GetTableSize();
    double previousError = 0.0;
    for (int k : { 1, 2, 4, 8 })
    {
      table->SetSubSamples(k);
      check(table->Update(), "Update for the linear-ramp case");
      double worstExcess = 0.0, worstSum = 0.0;
      for (int j = 0; j < n; ++j)
      {
        for (int i = 0; i < n; ++i)
        {
          const double sf = EntryScalar(table, i), sb = EntryScalar(table, j);
          // Red ramps 0 -> 1, blue 1 -> 0, green is constant 0.3.
          const double cf[3] = { sf, 0.3, 1.0 - sf }, cb[3] = { sb, 0.3, 1.0 - sb };
          double rgba[4], reverse[4];
          table->GetEntry(i, j, rgba);
          table->GetEntry(j, i, reverse);
          const int pieces = std::abs(j - i) * k;
          for (int ch = 0; ch < 3; ++ch)
          {
            const double dc = cb[ch] - cf[ch];
            const double exact = cf[ch] * alpha + dc / d * ramp;
            const double bound =
              pieces ? std::abs(dc) * t * t * d * d / (12.0 * pieces * pieces) : 0.0;
            worstExcess = std::max(worstExcess, std::abs(rgba[ch] - exact) - bound);
            worstSum =
              std::max(worstSum, std::abs(rgba[ch] + reverse[ch] - (cf[ch] + cb[ch]) * alpha));
          }
          worstExcess = std::max(worstExcess, std::abs(rgba[3] - alpha));
        }
      }
      // worstExcess: largest amount by which an entry exceeds its error bound (negative when
      // every entry is strictly within it; the diagonal and alpha make it >= 0 here).
      std::ostringstream label;
      label << "SubSamples " << k
            << ": C within |dc| tau^2 d^2 / (12 P^2) + float rounding of the closed form"
            << " (largest excess " << worstExcess << ")";
      check(worstExcess <= FloatTolerance, label.str());
      // Two float-rounded entries are added.
      check.Near(
        worstSum, 0.0, 2.0 * FloatTolerance, "C(s_f, s_b) + C(s_b, s_f) = (c_f + c_b) alpha");

      // Convergence on the full-range segment (P = 8 k pieces): the error falls by ~4 per
      // doubling of SubSamples. The leading term is c1 tau^2 h^2 (1 - e^{-tau d}) / 12, the
      // next one relatively -x/2 with x = tau h <= 0.26, hence ratios between 3.5 and 4.5.
      double rgba[4];
      table->GetEntry(0, n - 1, rgba);
      const double error = std::abs(rgba[0] - ramp / d);
      if (k > 1)
      {
        const double ratio = previousError / error;
        std::ostringstream what;
        what << "error ratio SubSamples " << k / 2 << " -> " << k << " is about 4 (got " << ratio
             << ")";
        std::cout << "Linear ramp: " << what.str() << "\n";
        check(ratio > 3.5 && ratio < 4.5, what.str());
      }
      previousError = error;
      // The colour is not symmetric: red front-to-back differs from back-to-front by
      // 2 (1/d) ramp - alpha (both closed forms, red goes 0 -> 1 over the segment).
      double back[4];
      table->GetEntry(n - 1, 0, back);
      check.Near(rgba[0] - back[0],
        2.0 * ramp / d - alpha,
        2.0 * t * t * d * d / (12.0 * 64.0 * k * k) + 2.0 * FloatTolerance,
        "red asymmetry C(0, 1) - C(1, 0) of the linear ramp");
    }
    std::cout << "Linear ramp: red error of the full-range entry with SubSamples 8: "
              << previousError << "\n";
  }

  //----------------------------------------------------------------------------
  // 4. Rebuilds: only when something the table depends on changed, exactly once per change.
  {
    vtkNew<vtkColorTransferFunction> color;
    color->AddRGBPoint(0.0, 0.0, 0.3, 1.0);
    color->AddRGBPoint(1.0, 1.0, 0.3, 0.0);
    vtkNew<vtkPiecewiseFunction> opacity;
    opacity->AddPoint(0.0, 0.1);
    opacity->AddPoint(1.0, 0.6);
    vtkNew<vtkVolumeProperty> property;
    property->SetColor(color);
    property->SetScalarOpacity(opacity);
    vtkNew<vtkFirstOrderPreIntegrationTable> table;
    table->SetVolumeProperty(property);
    table->SetScalarRange(0.0, 1.0);
    table->SetTableSize(16);
    check(table->GetBuildCount() == 0, "no build before Update()");
    check(table->Update() && table->Update(), "Update twice");
    check(table->GetBuildCount() == 1, "Update() twice without change builds once");
    table->SetVolumeProperty(property);
    table->SetSegmentLength(table->GetSegmentLength());
    table->SetScalarRange(0.0, 1.0);
    table->SetTableSize(16);
    check(table->Update(), "Update after setting unchanged values");
    check(table->GetBuildCount() == 1, "setting unchanged values does not rebuild");

    int expected = 1;
    auto expectOneRebuild = [&](const char* what)
    {
      ++expected;
      const bool ok = table->Update() && table->Update();
      check(ok && table->GetBuildCount() == expected,
        std::string(what) + " triggers exactly one rebuild (build count " +
          std::to_string(table->GetBuildCount()) + ", expected " + std::to_string(expected) + ")");
    };
    opacity->AddPoint(0.5, 0.2);
    expectOneRebuild("scalar opacity AddPoint");
    color->AddRGBPoint(0.5, 1.0, 1.0, 1.0);
    expectOneRebuild("colour AddRGBPoint");
    property->SetScalarOpacityUnitDistance(0.5);
    table->SetVolumeProperty(property);
    expectOneRebuild("unit distance through the volume property");
    table->GetSampler()->SetScalarOpacityUnitDistance(0.25);
    expectOneRebuild("unit distance on the sampler");
    table->SetSegmentLength(2.0);
    expectOneRebuild("segment length");
    table->SetScalarRange(0.0, 2.0);
    expectOneRebuild("scalar range");
    table->SetTableSize(17);
    expectOneRebuild("table size");
    check(table->GetTable()->GetNumberOfTuples() == 17 * 17, "table resized to 17^2 entries");
    table->SetSubSamples(2);
    expectOneRebuild("SubSamples");
    check(table->GetLastBuildTime() >= 0.0, "build time is measured");
  }

  //----------------------------------------------------------------------------
  // 5. Invalid settings: Update() returns false with an error, and nothing is built.
  messages.ExpectNone(check, "before the invalid-settings checks");
  {
    vtkNew<vtkColorTransferFunction> color;
    color->AddRGBPoint(0.0, 1.0, 1.0, 1.0);
    vtkNew<vtkPiecewiseFunction> opacity;
    opacity->AddPoint(0.0, 0.5);
    vtkNew<vtkVolumeProperty> property;
    property->SetColor(color);
    property->SetScalarOpacity(opacity);
    vtkNew<vtkFirstOrderPreIntegrationTable> table;
    table->SetTableSize(8);
    hovrTest::CheckInvalidTableSettings(
      check, messages, table.GetPointer(), property.GetPointer(), color.GetPointer(), 1.0);
  }

  //----------------------------------------------------------------------------
  // 6. SuggestTableSize, from the documented rules.
  {
    vtkNew<vtkColorTransferFunction> color;
    vtkNew<vtkPiecewiseFunction> opacity;
    vtkNew<vtkVolumeTransferFunctionSampler> sampler;
    sampler->SetColor(color);
    sampler->SetScalarOpacity(opacity);
    auto suggest = [&](int type, double r0, double r1, int minimum, int maximum)
    {
      check(sampler->Prepare(), "sampler prepared for SuggestTableSize");
      const double range[2] = { r0, r1 };
      return vtkPreIntegrationTable::SuggestTableSize(type, range, sampler, minimum, maximum);
    };
    // Integer data, features of 64 units: one entry per integer value.
    color->AddRGBPoint(0.0, 0.0, 0.0, 0.0);
    color->AddRGBPoint(64.0, 1.0, 0.0, 0.0);
    color->AddRGBPoint(255.0, 1.0, 1.0, 1.0);
    opacity->AddPoint(0.0, 0.0);
    opacity->AddPoint(128.0, 0.5);
    opacity->AddPoint(255.0, 1.0);
    int size = suggest(VTK_UNSIGNED_CHAR, 0.0, 255.0, 2, 4096);
    check(size == 256, "uint8 0..255 gives 256 entries, got " + std::to_string(size));
    // A minimum above 256: subdivide each unit evenly (entries stay on integers).
    size = suggest(VTK_UNSIGNED_CHAR, 0.0, 255.0, 600, 4096);
    check(
      size == 3 * 255 + 1, "uint8 with minimum 600 gives 766 entries, got " + std::to_string(size));
    // A feature of a quarter unit: 4 entries per unit.
    opacity->AddPoint(100.0, 0.1);
    opacity->AddPoint(100.25, 0.9);
    size = suggest(VTK_UNSIGNED_CHAR, 0.0, 255.0, 2, 4096);
    check(size == 4 * 255 + 1,
      "uint8 with a 0.25 feature gives 1021 entries, got " + std::to_string(size));
    // Integer data whose range needs too many entries: 4 entries across the narrowest feature.
    color->RemoveAllPoints();
    opacity->RemoveAllPoints();
    color->AddRGBPoint(0.0, 0.0, 0.0, 0.0);
    color->AddRGBPoint(65535.0, 1.0, 1.0, 1.0);
    opacity->AddPoint(0.0, 0.0);
    opacity->AddPoint(1000.0, 0.5);
    size = suggest(VTK_UNSIGNED_SHORT, 0.0, 65535.0, 2, 4096);
    check(size >= 2 && 65535.0 / (size - 1) <= 1000.0 / 4.0 && size <= 4096,
      "uint16: spacing at most a quarter of the 1000-unit feature, got " + std::to_string(size));
    check(
      size == 264, "uint16: ceil(4 65535 / 1000) + 1 = 264 entries, got " + std::to_string(size));

    // Float data with a feature of 0.01 over [0, 1]: spacing <= 0.01 / 4.
    color->RemoveAllPoints();
    opacity->RemoveAllPoints();
    color->AddRGBPoint(0.0, 0.0, 0.0, 0.0);
    color->AddRGBPoint(1.0, 1.0, 1.0, 1.0);
    opacity->AddPoint(0.5, 0.0);
    opacity->AddPoint(0.51, 1.0);
    size = suggest(VTK_FLOAT, 0.0, 1.0, 2, 4096);
    check(size >= 401 && size <= 402,
      "float with a 0.01 feature gives 401 entries (4 per feature), got " + std::to_string(size));
    size = suggest(VTK_FLOAT, 0.0, 1.0, 2, 256);
    check(size == 256, "clamped to the maximum 256, got " + std::to_string(size));
    // Wide features only: 4 entries per feature would be 5, clamped up to the minimum.
    opacity->RemoveAllPoints();
    opacity->AddPoint(0.0, 0.0);
    opacity->AddPoint(1.0, 1.0);
    size = suggest(VTK_DOUBLE, 0.0, 1.0, 64, 4096);
    check(size == 64, "clamped to the minimum 64, got " + std::to_string(size));
    size = suggest(VTK_FLOAT, 0.0, 1.0, 2, 4096);
    check(
      size == 5, "float with only a feature of 1 over [0, 1] gives 5, got " + std::to_string(size));
    size = suggest(VTK_FLOAT, 1.0, 1.0, 16, 4096);
    check(size == 16, "an empty data range gives the minimum, got " + std::to_string(size));
  }

  //----------------------------------------------------------------------------
  // Empty runs: spacings with opacity are -1, zero-opacity spacings are numbered by run, and
  // a segment with both ends in one run is exactly empty in the table.
  {
    vtkNew<vtkColorTransferFunction> color;
    color->AddRGBPoint(0.0, 1.0, 1.0, 1.0);
    vtkNew<vtkPiecewiseFunction> opacity;
    opacity->AddPoint(0.0, 0.0);
    opacity->AddPoint(3.5, 0.0);
    opacity->AddPoint(4.0, 0.8); // spacings [3, 4] and [4, 5] have opacity
    opacity->AddPoint(4.5, 0.0);
    opacity->AddPoint(7.0, 0.0);
    opacity->AddPoint(8.0, 0.5); // from 7 on: spacings [7, 8], [8, 9], [9, 10]
    vtkNew<vtkVolumeProperty> property;
    property->SetColor(color);
    property->SetScalarOpacity(opacity);
    vtkNew<vtkFirstOrderPreIntegrationTable> table;
    table->SetVolumeProperty(property);
    table->SetScalarRange(0.0, 10.0);
    table->SetTableSize(11);
    check(table->Update(), "Update for empty runs");
    const float expected[10] = { 0, 0, 0, -1, -1, 1, 1, -1, -1, -1 };
    vtkFloatArray* runs = table->GetEmptyRuns();
    check(runs->GetNumberOfTuples() == 10, "one run value per table spacing");
    for (int b = 0; b < 10 && runs->GetNumberOfTuples() == 10; ++b)
    {
      check(runs->GetValue(b) == expected[b],
        "run of spacing " + std::to_string(b) + " is " + std::to_string(expected[b]) + ", got " +
          std::to_string(runs->GetValue(b)));
    }
    for (int i = 0; i < 11; ++i)
    {
      for (int j = 0; j < 11; ++j)
      {
        const int bi = std::min(i, 9), bj = std::min(j, 9);
        if (expected[bi] >= 0 && expected[bi] == expected[bj])
        {
          double rgba[4];
          table->GetEntry(i, j, rgba);
          check(rgba[3] == 0.0 && rgba[0] == 0.0, "a segment inside one empty run is empty");
        }
      }
    }
  }

  //----------------------------------------------------------------------------
  // 7. ComputeScalarRange: the finite range, widened only for flat data.
  {
    vtkNew<vtkFloatArray> scalars;
    double dataRange[2] = { -7.0, -7.0 }, tableRange[2] = { -7.0, -7.0 };
    check(!vtkPreIntegrationTable::ComputeScalarRange(scalars, dataRange, tableRange) &&
        dataRange[0] == -7.0 && tableRange[1] == -7.0,
      "no scalars: no range, both untouched");
    const float nan = std::numeric_limits<float>::quiet_NaN();
    scalars->InsertNextValue(nan);
    scalars->Modified();
    check(!vtkPreIntegrationTable::ComputeScalarRange(scalars, dataRange, tableRange),
      "all NaN: no range");
    scalars->InsertNextValue(3.0f);
    scalars->InsertNextValue(std::numeric_limits<float>::infinity());
    scalars->Modified(); // inserting does not invalidate the cached range
    check(vtkPreIntegrationTable::ComputeScalarRange(scalars, dataRange, tableRange) &&
        dataRange[0] == 3.0 && dataRange[1] == 3.0 && tableRange[0] == 3.0 && tableRange[1] == 4.0,
      "flat finite data 3 (with NaN and inf): data [3, 3], table [3, 4]");
    scalars->Reset();
    scalars->InsertNextValue(1e20f);
    scalars->Modified();
    check(vtkPreIntegrationTable::ComputeScalarRange(scalars, dataRange, tableRange) &&
        tableRange[1] > tableRange[0] &&
        std::abs(tableRange[1] - tableRange[0] - 1e-6 * tableRange[0]) <= 1e-9 * tableRange[0],
      "flat data 1e20: the table range widens by 1e-6 of the value");
    scalars->InsertNextValue(-2.0f);
    scalars->Modified();
    check(vtkPreIntegrationTable::ComputeScalarRange(scalars, dataRange, tableRange) &&
        dataRange[0] == -2.0 && tableRange[0] == -2.0 && dataRange[1] == tableRange[1] &&
        dataRange[1] == static_cast<double>(1e20f),
      "varying data: both ranges are the finite range");
  }

  messages.ExpectNone(check, "at the end of the test");
  return check.Result("TestFirstOrderPreIntegrationTable");
}
