// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
// vtkSecondOrderPreIntegrationTable against the slab integral of El Hajjar et al., Eq. 2:
//   alpha = 1 - exp(-int_0^1 tau(P(t)) L dt),
//   C     = int_0^1 c(P(t)) tau(P(t)) L exp(-int_0^t tau(P(t')) L dt') dt,
//   P(t)  = A t^2 + B t + C, A = 2 s_f - 4 s_m + 2 s_b, B = -3 s_f + 4 s_m - s_b, C = s_f,
// with P clamped to the scalar range. References: closed forms (constant scalar, constant
// colour, saturation, thin media) and an independent brute-force integration in double.
// Also: symmetry, range ends, empty-slab skipping, rebuild bookkeeping and error handling.
#include "vtkColorTransferFunction.h"
#include "vtkFloatArray.h"
#include "vtkMinimalStandardRandomSequence.h"
#include "vtkNew.h"
#include "vtkPiecewiseFunction.h"
#include "vtkSecondOrderPreIntegrationTable.h"
#include "vtkSmartPointer.h"
#include "vtkVolumeProperty.h"
#include "vtkVolumeTransferFunctionSampler.h"

#include "hovrTestUtilities.h"

#include <algorithm>
#include <cmath>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

namespace
{
// Table values are floats in [0, 1] computed in double and rounded once (2^-24 relative), so
// 2^-23 ~ 1.2e-7 absolute covers a closed form evaluated in double and stored.
constexpr double FloatTolerance = 1.2e-7;
// Unit roundoff of float. A slab composites Iterations steps in float, each step rounding
// values <= 1 once or twice, so chains that are equal in exact arithmetic (colour against
// alpha, forward against backward) differ by at most a few Iterations 2^-24.
constexpr double FloatEpsilon = 1.0 / 16777216.0;
// The sampler's default opacity cap (the extinction of opacity 1 stays finite).
constexpr double MaximumOpacity = 1.0 - 1e-9;
// Steps of the brute-force reference. Its midpoint error is second order like the table's, so
// at 20000 steps it is (256 / 20000)^2 = 1.6e-4 times the table's error at 256 iterations.
constexpr int ReferenceSteps = 20000;

hovrTest::Checker check;

// Indices (front, middle, back) of a table entry.
struct Entry
{
  int I, J, K;
};

std::string Where(const std::string& what, const Entry& e)
{
  std::ostringstream os;
  os << what << " at entry (" << e.I << ", " << e.J << ", " << e.K << ")";
  return os.str();
}

// Scalar of table entry i: entry 0 at range[0], entry n - 1 exactly at range[1].
double EntryScalar(const double range[2], int n, int i)
{
  return i == n - 1 ? range[1] : range[0] + (range[1] - range[0]) * i / (n - 1.0);
}

// P(t) of Eq. 2 through (s_f, s_m, s_b) at t = 0, 1/2, 1.
struct Quadratic
{
  double A, B, C;
  Quadratic(double sf, double sm, double sb)
    : A(2.0 * sf - 4.0 * sm + 2.0 * sb)
    , B(-3.0 * sf + 4.0 * sm - sb)
    , C(sf)
  {
  }
  double operator()(double t) const { return this->C + t * (this->B + this->A * t); }
  double Slope(double t) const { return this->B + 2.0 * this->A * t; }
  // Range of P over [0, 1]: the ends, and the extremum when it lies inside.
  void Range(double& lo, double& hi) const
  {
    lo = std::min(this->C, (*this)(1.0));
    hi = std::max(this->C, (*this)(1.0));
    if (this->A != 0.0)
    {
      const double vertex = -this->B / (2.0 * this->A);
      if (vertex > 0.0 && vertex < 1.0)
      {
        lo = std::min(lo, (*this)(vertex));
        hi = std::max(hi, (*this)(vertex));
      }
    }
  }
};

Quadratic EntryQuadratic(vtkSecondOrderPreIntegrationTable* table, const Entry& e)
{
  const double* r = table->GetScalarRange();
  const int n = table->GetTableSize();
  return Quadratic(EntryScalar(r, n, e.I), EntryScalar(r, n, e.J), EntryScalar(r, n, e.K));
}

// Premultiplied RGBA of a slab and its optical depth int_0^1 tau(P(t)) L dt.
struct Reference
{
  double RGBA[4];
  double Depth;
};

// Brute-force Eq. 2 in double, independent of the table: `steps` midpoint steps along t, each
// a constant medium with the exact exponential, P clamped to [clamp[0], clamp[1]] unless
// clamp is null, the transfer function evaluated exactly by the sampler at every step.

Reference Integrate(const vtkVolumeTransferFunctionSampler* sampler,
  const Quadratic& p,
  double length,
  const double* clamp,
  int steps = ReferenceSteps)
{
  Reference out = { { 0.0, 0.0, 0.0, 0.0 }, 0.0 };
  const double h = length / steps;
  for (int m = 0; m < steps; ++m)
  {
    double s = p((m + 0.5) / steps);
    if (clamp)
    {
      s = std::min(std::max(s, clamp[0]), clamp[1]);
    }
    double rgbTau[4];
    sampler->Evaluate(s, rgbTau);
    const double weight = std::exp(-out.Depth) * -std::expm1(-rgbTau[3] * h);
    for (int c = 0; c < 3; ++c)
    {
      out.RGBA[c] += weight * rgbTau[c];
    }
    out.Depth += rgbTau[3] * h;
  }
  out.RGBA[3] = -std::expm1(-out.Depth);
  return out;
}

// A transfer function with VTK's own evaluation (independent of the sampler) and a prepared
// sampler for the brute-force references.
struct TransferFunction
{
  vtkNew<vtkColorTransferFunction> Color;
  vtkNew<vtkPiecewiseFunction> Opacity;
  vtkNew<vtkVolumeProperty> Property;
  vtkNew<vtkVolumeTransferFunctionSampler> Sampler;
  double Unit = 1.0;

  void SetUnit(double unit)
  {
    this->Unit = unit;
    this->Property->SetColor(this->Color);
    this->Property->SetScalarOpacity(this->Opacity);
    this->Property->SetScalarOpacityUnitDistance(unit);
    this->Sampler->SetFromVolumeProperty(this->Property);
    check(this->Sampler->Prepare(), "reference sampler prepared");
  }

  // Colour and extinction through vtkColorTransferFunction and vtkPiecewiseFunction.
  void Exact(double s, double rgbTau[4])
  {
    this->Color->GetColor(s, rgbTau);
    const double opacity = std::min(std::max(this->Opacity->GetValue(s), 0.0), MaximumOpacity);
    rgbTau[3] = -std::log1p(-opacity) / this->Unit;
  }

  // Largest value of each colour channel (interpolation stays between node values).
  void MaximumColor(double rgb[3])
  {
    rgb[0] = rgb[1] = rgb[2] = 0.0;
    for (int i = 0; i < this->Color->GetSize(); ++i)
    {
      double v[6];
      this->Color->GetNodeValue(i, v);
      for (int c = 0; c < 3; ++c)
      {
        rgb[c] = std::max(rgb[c], v[c + 1]);
      }
    }
  }
};

// Every entry finite, 0 <= alpha <= 1, 0 <= colour <= alpha max(c) (premultiplied). The
// colour and alpha chains round differently: 4 Iterations 2^-24 allowance.
void CheckValid(vtkSecondOrderPreIntegrationTable* table,
  TransferFunction& tf,
  const std::string& label)
{
  double cmax[3];
  tf.MaximumColor(cmax);
  const double allowance = 4.0 * table->GetIterations() * FloatEpsilon;
  const float* v = table->GetTable()->GetPointer(0);
  const vtkIdType count = table->GetTable()->GetNumberOfTuples();
  const int n = table->GetTableSize();
  vtkIdType bad = 0, firstBad = -1;
  for (vtkIdType e = 0; e < count; ++e)
  {
    const float* rgba = v + 4 * e;
    bool ok = std::isfinite(rgba[3]) && rgba[3] >= 0.0f && rgba[3] <= 1.0f;
    for (int c = 0; c < 3; ++c)
    {
      ok =
        ok && std::isfinite(rgba[c]) && rgba[c] >= 0.0f && rgba[c] <= rgba[3] * cmax[c] + allowance;
    }
    if (!ok)
    {
      firstBad = firstBad < 0 ? e : firstBad;
      ++bad;
    }
  }
  std::ostringstream what;
  what << label << ": every entry finite with 0 <= alpha <= 1 and 0 <= C <= alpha max(c) (" << bad
       << " bad entries";
  if (bad)
  {
    const float* rgba = v + 4 * firstBad;
    what << ", first (" << firstBad % n << ", " << (firstBad / n) % n << ", " << firstBad / n / n
         << ") = " << rgba[0] << " " << rgba[1] << " " << rgba[2] << " " << rgba[3];
  }
  what << ")";
  check(count == static_cast<vtkIdType>(n) * n * n && bad == 0, what.str());
}

vtkSmartPointer<vtkSecondOrderPreIntegrationTable> Build(TransferFunction& tf,
  double r0,
  double r1,
  int n,
  double length,
  int iterations,
  const std::string& label,
  bool prefilter = false)
{
  auto table = vtkSmartPointer<vtkSecondOrderPreIntegrationTable>::New();
  // The integral of Eq. 2 itself; section 9 tests the prefilter.
  table->SetPrefilter(prefilter);
  table->SetVolumeProperty(tf.Property);
  table->SetScalarRange(r0, r1);
  table->SetTableSize(n);
  table->SetSegmentLength(length);
  table->SetIterations(iterations);
  check(table->Update(), "Update: " + label);
  CheckValid(table, tf, label);
  return table;
}

std::vector<Entry> RandomEntries(int n, int count, int seed)
{
  vtkNew<vtkMinimalStandardRandomSequence> random;
  random->SetSeed(seed);
  std::vector<Entry> entries;
  auto next = [&]()
  {
    random->Next();
    return std::min(static_cast<int>(random->GetValue() * n), n - 1);
  };
  for (int e = 0; e < count; ++e)
  {
    const int i = next(), j = next(), k = next();
    entries.push_back({ i, j, k });
  }
  return entries;
}

// Largest absolute difference over the entries and the four channels.
double LargestError(vtkSecondOrderPreIntegrationTable* table,
  const std::vector<Entry>& entries,
  const std::vector<Reference>& references)
{
  double worst = 0.0;
  for (size_t e = 0; e < entries.size(); ++e)
  {
    double rgba[4];
    table->GetEntry(entries[e].I, entries[e].J, entries[e].K, rgba);
    for (int c = 0; c < 4; ++c)
    {
      worst = std::max(worst, std::abs(rgba[c] - references[e].RGBA[c]));
    }
  }
  return worst;
}

std::vector<Reference> References(vtkSecondOrderPreIntegrationTable* table,
  TransferFunction& tf,
  const std::vector<Entry>& entries)
{
  std::vector<Reference> references;
  for (const Entry& e : entries)
  {
    references.push_back(Integrate(
      tf.Sampler, EntryQuadratic(table, e), table->GetSegmentLength(), table->GetScalarRange()));
  }
  return references;
}

// Random nodes 0.5 to 3.5 apart, mixed sharpness and midpoints, opacity up to 0.95, plus two
// opacity spikes 0 -> 0.95 -> 0 only 0.08 wide: features much narrower than a table spacing.
double MakeSpikyTransferFunction(TransferFunction& tf, int seed)
{
  vtkNew<vtkMinimalStandardRandomSequence> random;
  random->SetSeed(seed);
  auto next = [&]()
  {
    random->Next();
    return random->GetValue();
  };
  double x = 0.0;
  for (int node = 0; node < 6; ++node)
  {
    x += 0.5 + 3.0 * next();
    const double sharpness = node % 2 ? 0.0 : next();
    tf.Color->AddRGBPoint(x, next(), next(), next(), 0.1 + 0.8 * next(), sharpness);
    tf.Opacity->AddPoint(x + 0.4, 0.95 * next(), 0.1 + 0.8 * next(), 1.0 - sharpness);
  }
  for (double spike : { 0.35 * x, 0.8 * x })
  {
    tf.Opacity->AddPoint(spike - 0.04, 0.0);
    tf.Opacity->AddPoint(spike, 0.95);
    tf.Opacity->AddPoint(spike + 0.04, 0.0);
  }
  return x;
}

// Smooth on [0, 1]: colour and opacity linear between nodes at 0 and 1 only, opacity 0.1 to
// 0.5. Inside the range tau(s) = -ln(1 - alpha(s)) / U is analytic with (U = 1)
//   tau >= 0.105, |tau'| <= 0.4 / 0.5 = 0.8, |tau''| <= 0.4^2 / 0.5^2 = 0.64,
// and for P inside the range (|P'| <= 4, |P''| <= 8) g(t) = tau(P(t)) has
//   |g''| <= |tau''| P'^2 + |tau'| |P''| <= 0.64 * 16 + 0.8 * 8 = 16.6, |g''| / g <= 158.
void MakeSmoothTransferFunction(TransferFunction& tf)
{
  tf.Color->AddRGBPoint(0.0, 0.9, 0.2, 0.1);
  tf.Color->AddRGBPoint(1.0, 0.1, 0.6, 1.0);
  tf.Opacity->AddPoint(0.0, 0.1);
  tf.Opacity->AddPoint(1.0, 0.5);
}

// Box average of (c tau, tau) over [s - h, s + h] (h > 0) by the midpoint rule in double.
void BoxAverage(const vtkVolumeTransferFunctionSampler* sampler, double s, double h, double out[4])
{
  const int steps = 20000;
  std::fill(out, out + 4, 0.0);
  for (int m = 0; m < steps; ++m)
  {
    double rgbTau[4];
    sampler->Evaluate(s - h + 2.0 * h * (m + 0.5) / steps, rgbTau);
    for (int c = 0; c < 3; ++c)
    {
      out[c] += rgbTau[c] * rgbTau[3] / steps;
    }
    out[3] += rgbTau[3] / steps;
  }
}

// Zero opacity on [0, 34] and [38, 50], a spike on (34, 38), 0.6 from 52 on (range [0, 63]).
void MakeRunsTransferFunction(TransferFunction& runs)
{
  runs.Color->AddRGBPoint(0.0, 1.0, 1.0, 1.0);
  runs.Color->AddRGBPoint(63.0, 1.0, 0.5, 0.0);
  runs.Opacity->AddPoint(0.0, 0.0);
  runs.Opacity->AddPoint(34.0, 0.0);
  runs.Opacity->AddPoint(36.0, 0.8);
  runs.Opacity->AddPoint(38.0, 0.0);
  runs.Opacity->AddPoint(50.0, 0.0);
  runs.Opacity->AddPoint(52.0, 0.6);
  runs.Opacity->AddPoint(63.0, 0.6);
  runs.SetUnit(1.0);
}

// Entries whose quadratic stays inside the scalar range (no clamping kink).
std::vector<Entry> InsideEntries(vtkSecondOrderPreIntegrationTable* table,
  const std::vector<Entry>& all)
{
  std::vector<Entry> inside;
  const double* r = table->GetScalarRange();
  for (const Entry& e : all)
  {
    double lo, hi;
    EntryQuadratic(table, e).Range(lo, hi);
    if (lo >= r[0] && hi <= r[1])
    {
      inside.push_back(e);
    }
  }
  return inside;
}
}

int TestSecondOrderPreIntegrationTable(int, char*[])
{
  hovrTest::MessageCapture messages;
  const int iterationCounts[3] = { 16, 64, 256 };

  //----------------------------------------------------------------------------
  // 1. The diagonal s_f = s_m = s_b is a constant medium: alpha = 1 - exp(-tau(s) L),
  //    C = c(s) alpha, with colour and opacity from VTK's own functions; and the iteration
  //    table holds (c a, a), a = 1 - exp(-tau L / Iterations), at equispaced scalars.
  TransferFunction spiky;
  const double spikyEnd = MakeSpikyTransferFunction(spiky, 11);
  spiky.SetUnit(0.8);
  const double spikyRange[2] = { -1.0, spikyEnd + 1.0 };
  {
    auto table = Build(spiky, spikyRange[0], spikyRange[1], 48, 1.3, 64, "spiky transfer function");
    const int n = table->GetTableSize();
    // VTK's functions and the sampler agree to 1e-12 in opacity (TestVolumeTransferFunction-
    // Sampler), i.e. < 1e-10 in tau for opacities <= 0.95; the rest is float rounding.
    const double tolerance = FloatTolerance + 1e-10;
    double worst = 0.0;
    for (int i = 0; i < n; ++i)
    {
      double f[4], rgba[4];
      spiky.Exact(EntryScalar(spikyRange, n, i), f);
      const double alpha = -std::expm1(-f[3] * 1.3);
      table->GetEntry(i, i, i, rgba);
      worst = std::max(worst, std::abs(rgba[3] - alpha));
      for (int c = 0; c < 3; ++c)
      {
        worst = std::max(worst, std::abs(rgba[c] - f[c] * alpha));
      }
    }
    std::cout << "Diagonal: largest deviation from the exact exponential " << worst << "\n";
    check.Near(worst, 0.0, tolerance, "diagonal entries equal 1 - exp(-tau L), c alpha");

    // Iteration table: 16 samples across the narrowest feature (0.04), at least 8 per
    // table spacing.
    const int per = table->GetIterationSamplesPerSpacing();
    const double spacing = (spikyRange[1] - spikyRange[0]) / (n - 1);
    check(per >= 8 && spacing / per <= 0.04 / 16.0 + 1e-12,
      "iteration table resolves the narrowest feature with 16 samples (" + std::to_string(per) +
        " per spacing)");
    vtkFloatArray* steps = table->GetIterationTable();
    const int fine = per * (n - 1) + 1;
    check(steps->GetNumberOfTuples() == fine && steps->GetNumberOfComponents() == 4,
      "iteration table has IterationSamplesPerSpacing (N - 1) + 1 RGBA samples");
    check(table->GetIterationEmptyRuns()->GetNumberOfTuples() == fine - 1,
      "one iteration empty-run value per iteration-table spacing");
    double worstStep = 0.0;
    for (int q = 0; q < fine && steps->GetNumberOfTuples() == fine; ++q)
    {
      double f[4];
      spiky.Exact(EntryScalar(spikyRange, fine, q), f);
      const double a = -std::expm1(-f[3] * 1.3 / 64);
      worstStep = std::max(worstStep, std::abs(steps->GetComponent(q, 3) - a));
      for (int c = 0; c < 3; ++c)
      {
        worstStep = std::max(worstStep, std::abs(steps->GetComponent(q, c) - f[c] * a));
      }
    }
    check.Near(worstStep,
      0.0,
      FloatTolerance,
      "iteration table holds (c a, a) with a = 1 - exp(-tau L / Iterations)");
  }

  //----------------------------------------------------------------------------
  // 2. Against the brute-force Eq. 2 for random entries, Iterations 16, 64, 256.
  //    Smooth transfer function, entries inside the range: the midpoint rule is second order,
  //    so the error falls by 16 per factor 4 in Iterations. Two parts do not depend on
  //    Iterations: the iteration table's linear interpolation (spacing 1/512 of the range
  //    with N = 65: ds^2 / 8 |tau''| / tau <= 3e-6 relative) and float compositing; measured
  //    together ~2e-6 at 1024 iterations, they are up to ~15% of the error at 256, hence a
  //    ratio of 16 within [12, 21].
  TransferFunction smooth;
  MakeSmoothTransferFunction(smooth);
  smooth.SetUnit(0.5);
  {
    double errors[3];
    std::vector<Entry> entries;
    std::vector<Reference> references;
    for (int c = 0; c < 3; ++c)
    {
      auto table = Build(smooth, 0.0, 1.0, 65, 2.0, iterationCounts[c], "smooth transfer function");
      if (c == 0)
      {
        entries = InsideEntries(table, RandomEntries(65, 400, 5));
        references = References(table, smooth, entries);
      }
      errors[c] = LargestError(table, entries, references);
      std::cout << "Smooth transfer function, " << entries.size() << " entries, Iterations "
                << iterationCounts[c] << ": largest error " << errors[c] << "\n";
    }
    check(entries.size() >= 150, "enough random entries inside the range");
    for (int c = 1; c < 3; ++c)
    {
      const double ratio = errors[c - 1] / errors[c];
      std::ostringstream what;
      what << "smooth transfer function: error ratio Iterations " << iterationCounts[c - 1]
           << " -> " << iterationCounts[c] << " is about 16 (second order), got " << ratio;
      std::cout << "Smooth transfer function: error ratio " << iterationCounts[c - 1] << " -> "
                << iterationCounts[c] << ": " << ratio << "\n";
      check(ratio > 12.0 && ratio < 21.0, what.str());
    }
  }
  {
    // Spiky transfer function on [-1, 10.95]: a spike 0.08 wide is crossed in as little as
    // 1/600 of the slab (|P'| up to 4 x 12), less than one step even at 256 iterations, and a
    // step then hits or misses it: the error is first order, bounded by the optical depth of
    // one step at the spike's peak, tau_peak L / Iterations (4.9 / Iterations here).
    const double peakDepth = -std::log1p(-0.95) / 0.8 * 1.3;
    double errors[3];
    std::vector<Entry> entries = RandomEntries(48, 300, 7);
    std::vector<Reference> references;
    for (int c = 0; c < 3; ++c)
    {
      auto table = Build(spiky,
        spikyRange[0],
        spikyRange[1],
        48,
        1.3,
        iterationCounts[c],
        "spiky transfer function");
      if (c == 0)
      {
        references = References(table, spiky, entries);
      }
      errors[c] = LargestError(table, entries, references);
      std::cout << "Spiky transfer function, " << entries.size() << " entries, Iterations "
                << iterationCounts[c] << ": largest error " << errors[c] << "\n";
      check.Near(errors[c],
        0.0,
        peakDepth / iterationCounts[c],
        "spiky transfer function: largest error at " + std::to_string(iterationCounts[c]) +
          " iterations");
    }
    check(errors[1] < errors[0] && errors[2] < errors[1],
      "spiky transfer function: error decreases with Iterations");
  }

  //----------------------------------------------------------------------------
  // 3. Symmetry: (s_f, s_m, s_b) and (s_b, s_m, s_f) follow the same path in opposite
  //    directions, so alpha = 1 - exp(-int tau) is the same; colour depends on the order. With
  //    a constant colour c, C = c int tau exp(-...) = c alpha for every entry.
  {
    auto table = Build(spiky, spikyRange[0], spikyRange[1], 48, 1.3, 64, "spiky transfer function");
    const int n = table->GetTableSize();
    // Two float chains of 64 steps, each step rounding twice: 4 Iterations 2^-24 = 1.5e-5.
    const double tolerance = 4.0 * 64 * FloatEpsilon;
    double worstAlpha = 0.0, largestColour = 0.0;
    for (int k = 0; k < n; ++k)
    {
      for (int j = 0; j < n; ++j)
      {
        for (int i = 0; i < k; ++i)
        {
          double forward[4], backward[4];
          table->GetEntry(i, j, k, forward);
          table->GetEntry(k, j, i, backward);
          worstAlpha = std::max(worstAlpha, std::abs(forward[3] - backward[3]));
          for (int c = 0; c < 3; ++c)
          {
            largestColour = std::max(largestColour, std::abs(forward[c] - backward[c]));
          }
        }
      }
    }
    std::cout << "Symmetry: largest |alpha(f, m, b) - alpha(b, m, f)| " << worstAlpha
              << ", largest colour asymmetry " << largestColour << "\n";
    check.Near(worstAlpha, 0.0, tolerance, "alpha(s_f, s_m, s_b) == alpha(s_b, s_m, s_f)");
    check(largestColour > 0.05, "colour is not symmetric in (s_f, s_b)");
  }
  {
    TransferFunction constant;
    const double c[3] = { 0.3, 0.6, 0.9 };
    constant.Color->AddRGBPoint(0.0, c[0], c[1], c[2]);
    constant.Opacity->DeepCopy(spiky.Opacity);
    constant.SetUnit(0.8);
    auto table = Build(constant, spikyRange[0], spikyRange[1], 40, 1.3, 64, "constant colour");
    const float* v = table->GetTable()->GetPointer(0);
    double worst = 0.0;
    for (vtkIdType e = 0; e < table->GetTable()->GetNumberOfTuples(); ++e)
    {
      for (int ch = 0; ch < 3; ++ch)
      {
        worst = std::max(worst, std::abs(v[4 * e + ch] - c[ch] * v[4 * e + 3]));
      }
    }
    std::cout << "Constant colour: largest |C - c alpha| " << worst << "\n";
    // Same allowance as CheckValid: the colour and alpha chains round differently.
    check.Near(worst, 0.0, 4.0 * 64 * FloatEpsilon, "constant colour: C = c alpha for every entry");
  }

  //----------------------------------------------------------------------------
  // 4. Quadratic overshoot: P leaves the range by up to 1/8 of the spread (f = min, m = b =
  //    max peaks at 9/8 at t = 3/4) and is clamped. The transfer function keeps changing
  //    beyond the range, so the clamped and unclamped integrals differ by ~0.1.
  {
    TransferFunction beyond;
    beyond.Color->AddRGBPoint(-0.25, 0.0, 0.0, 1.0);
    beyond.Color->AddRGBPoint(0.0, 1.0, 0.0, 0.0);
    beyond.Color->AddRGBPoint(1.0, 0.0, 1.0, 0.0);
    beyond.Color->AddRGBPoint(1.25, 1.0, 1.0, 1.0);
    beyond.Opacity->AddPoint(-0.25, 0.9);
    beyond.Opacity->AddPoint(0.0, 0.2);
    beyond.Opacity->AddPoint(0.5, 0.6);
    beyond.Opacity->AddPoint(1.0, 0.3);
    beyond.Opacity->AddPoint(1.25, 0.95);
    beyond.SetUnit(1.0);
    const int n = 17;
    auto table = Build(beyond, 0.0, 1.0, n, 2.0, 256, "transfer function beyond the range");
    const std::vector<Entry> corners = {
      { 0, n - 1, n - 1 }, { n - 1, 0, 0 }, { n - 1, n - 1, 0 }, { 0, 0, n - 1 }
    };
    std::vector<Entry> entries = corners;
    for (const Entry& e : RandomEntries(n, 400, 3))
    {
      double lo, hi;
      EntryQuadratic(table, e).Range(lo, hi);
      if (lo < -0.01 || hi > 1.01)
      {
        entries.push_back(e);
      }
    }
    const std::vector<Reference> references = References(table, beyond, entries);
    const double error = LargestError(table, entries, references);
    std::cout << "Overshoot: " << entries.size() << " entries leaving the range, largest error "
              << error << " against the clamped brute force\n";
    // Still second order: a kink of the integrand g = tau(P) L inside a step costs at most
    // h^2 |jump of g'| / 8 (h = 1/256). The clamped P meets the range ends at most twice,
    // |jump| <= |tau'| |P'| L <= 2 * 4 * 2 = 16: 3.1e-5 each; P crosses the opacity node at
    // 0.5 at most twice, where tau' jumps by <= 2 + 1.5: 5.3e-5 each. With the smooth part
    // (1e-5 in part 2): 1.8e-4, below 2e-4.
    check.Near(error, 0.0, 2e-4, "overshooting entries equal the clamped integral");
    double smallestUnclamped = 1.0;
    for (const Entry& e : corners)
    {
      const Reference free = Integrate(beyond.Sampler, EntryQuadratic(table, e), 2.0, nullptr);
      double rgba[4], difference = 0.0;
      table->GetEntry(e.I, e.J, e.K, rgba);
      for (int c = 0; c < 4; ++c)
      {
        difference = std::max(difference, std::abs(rgba[c] - free.RGBA[c]));
      }
      smallestUnclamped = std::min(smallestUnclamped, difference);
    }
    std::cout << "Overshoot: the corner entries differ from the unclamped integral by at least "
              << smallestUnclamped << "\n";
    check(smallestUnclamped > 0.02, "corner entries differ from the unclamped integral");
  }

  //----------------------------------------------------------------------------
  // 5. Saturation inside one slab. Opacity 0 below 0.5 - w, a ramp to 1 at 0.5, 1 above;
  //    colour red -> green (at 0.5) -> blue, linear, |dc/ds| <= 2 per channel.
  {
    const double w = 1e-3;
    const double slope = 2.0;
    TransferFunction opaque;
    opaque.Color->AddRGBPoint(0.0, 1.0, 0.0, 0.0);
    opaque.Color->AddRGBPoint(0.5, 0.0, 1.0, 0.0);
    opaque.Color->AddRGBPoint(1.0, 0.0, 0.0, 1.0);
    opaque.Opacity->AddPoint(0.0, 0.0);
    opaque.Opacity->AddPoint(0.5 - w, 0.0);
    opaque.Opacity->AddPoint(0.5, 1.0);
    opaque.Opacity->AddPoint(1.0, 1.0);
    const int n = 33; // entry 16 at 0.5
    const double range[2] = { 0.0, 1.0 };
    {
      // U = 1: opacity 1 is capped at 1 - 1e-9, tau L = 41.4 over the slab: finite, and the
      // diagonal is the exact exponential (1 in float).
      opaque.SetUnit(1.0);
      auto table = Build(opaque, 0.0, 1.0, n, 2.0, 256, "opacity 1 nodes");
      double worst = 0.0;
      for (int i = 0; i < n; ++i)
      {
        double f[4], rgba[4];
        opaque.Exact(EntryScalar(range, n, i), f);
        const double alpha = -std::expm1(-f[3] * 2.0);
        table->GetEntry(i, i, i, rgba);
        worst = std::max(worst, std::abs(rgba[3] - alpha));
      }
      check.Near(worst, 0.0, FloatTolerance, "opacity 1: diagonal alpha = 1 - exp(-tau_max L)");
      vtkFloatArray* steps = table->GetIterationTable();
      bool finite = true;
      for (vtkIdType v = 0; v < steps->GetNumberOfValues(); ++v)
      {
        finite = finite && std::isfinite(steps->GetValue(v)) && steps->GetValue(v) <= 1.0f;
      }
      check(finite, "opacity 1: iteration table finite and <= 1");
    }
    // U = 1e-3: tau L = 4.1e4 over the slab, 160 per step: a step in the opaque part has
    // a = 1 and hides everything behind. Expected: alpha = 1, colour = c at the first opaque
    // point, within the scalars visited by the steps that see the ramp: those lie within w
    // and one step (|P'| / Iterations) of it.
    opaque.SetUnit(1e-3);
    const int iterations = 256;
    auto table = Build(opaque, 0.0, 1.0, n, 2.0, iterations, "opacity 1 nodes, U = 1e-3");
    double worstExcess = -1.0, worstAlpha = 0.0;
    int saturated = 0, empty = 0;
    bool emptyOk = true;
    for (int k = 0; k < n; ++k)
    {
      for (int j = 0; j < n; ++j)
      {
        for (int i = 0; i < n; ++i)
        {
          const Entry e = { i, j, k };
          const Quadratic p = EntryQuadratic(table, e);
          double rgba[4];
          table->GetEntry(i, j, k, rgba);
          double lo, hi;
          p.Range(lo, hi);
          if (hi < 0.5 - w)
          {
            ++empty; // never reaches opacity
            emptyOk =
              emptyOk && rgba[0] == 0.0 && rgba[1] == 0.0 && rgba[2] == 0.0 && rgba[3] == 0.0;
            continue;
          }
          double first, tolerance;
          const double t0 = 0.5 / iterations;
          if (p(t0) >= 0.5)
          {
            // The first step is opaque: the colour at the front within half a step.
            first = p.C;
            tolerance = slope * std::abs(std::min(std::max(p(t0), 0.0), 1.0) - first);
          }
          else if (p.C < 0.5 - w && p(0.5) >= 0.5 && p(1.0) >= 0.5)
          {
            // Crossing once upwards at t* in (0, 1/2] (a quadratic crosses a level at most
            // twice, so P >= 0.5 on [t*, 1]); t* by bisection.
            double below = 0.0, above = 0.5;
            for (int b = 0; b < 60; ++b)
            {
              const double mid = 0.5 * (below + above);
              (p(mid) < 0.5 ? below : above) = mid;
            }
            first = 0.5;
            const double steep =
              std::max(std::abs(p.Slope(above)), std::abs(p.Slope(above + 1.0 / iterations)));
            tolerance = slope * std::max(w, steep / iterations);
          }
          else
          {
            continue;
          }
          ++saturated;
          double f[4];
          opaque.Exact(first, f);
          worstAlpha = std::max(worstAlpha, 1.0 - rgba[3]);
          for (int c = 0; c < 3; ++c)
          {
            worstExcess =
              std::max(worstExcess, std::abs(rgba[c] - f[c]) - tolerance - 3.0 * FloatTolerance);
          }
        }
      }
    }
    std::cout << "Saturation: " << saturated << " saturated entries, largest 1 - alpha "
              << worstAlpha << ", largest colour excess over its bound " << worstExcess << "\n";
    check(saturated > 1000, "enough saturated entries");
    check.Near(worstAlpha, 0.0, FloatTolerance, "saturated entries have alpha = 1");
    check(worstExcess <= 0.0, "saturated entries have the colour of the first opaque point");
    check(empty > 1000 && emptyOk, "entries below the ramp are empty");
  }

  //----------------------------------------------------------------------------
  // 6. Extreme unit distances and slab lengths, smooth transfer function.
  {
    // (a) U = 1e-6 L: every step is opaque (tau L / Iterations >= 1.6e3), alpha = 1 and the
    //     colour is that of the front, within the half step P moves before the first
    //     midpoint (the colour is linear, |dc/ds| = 0.8, 0.4, 0.9).
    const double dc[3] = { 0.8, 0.4, 0.9 };
    const double range[2] = { 0.0, 1.0 };
    smooth.SetUnit(2e-6);
    const int n = 33;
    auto table = Build(smooth, 0.0, 1.0, n, 2.0, 64, "U = 1e-6 L");
    double worstAlpha = 0.0, worstExcess = -1.0;
    for (int k = 0; k < n; ++k)
    {
      for (int j = 0; j < n; ++j)
      {
        for (int i = 0; i < n; ++i)
        {
          const Quadratic p(
            EntryScalar(range, n, i), EntryScalar(range, n, j), EntryScalar(range, n, k));
          double rgba[4], f[4];
          table->GetEntry(i, j, k, rgba);
          smooth.Exact(p.C, f);
          const double moved = std::abs(std::min(std::max(p(0.5 / 64), 0.0), 1.0) - p.C);
          worstAlpha = std::max(worstAlpha, 1.0 - rgba[3]);
          for (int c = 0; c < 3; ++c)
          {
            worstExcess = std::max(
              worstExcess, std::abs(rgba[c] - f[c]) - dc[c] * moved - 3.0 * FloatTolerance);
          }
        }
      }
    }
    std::cout << "U = 1e-6 L: largest 1 - alpha " << worstAlpha
              << ", largest colour excess over c(s_f) +- |c'| |P(1/2n) - s_f| " << worstExcess
              << "\n";
    check.Near(worstAlpha, 0.0, FloatTolerance, "U = 1e-6 L: alpha = 1 everywhere");
    check(worstExcess <= 0.0, "U = 1e-6 L: colour is the colour at the front");
  }
  {
    // (b) U = 1e6 L: alpha ~ L int tau ~ 1e-6 and C / alpha is the tau-weighted mean colour.
    //     Relative errors: midpoint rule h^2 / 24 max|g''| / g <= 158 / (24 256^2) = 1e-4 for
    //     alpha (bounds of MakeSmoothTransferFunction), 2.7e-4 for int c g (|(c g)''| <= 45);
    //     iteration-table interpolation 1.2e-5, float compositing 2 Iterations 2^-24 = 3e-5.
    //     Hence 2e-4 relative on alpha and 5e-4 absolute on C / alpha (values <= 1).
    smooth.SetUnit(2e6);
    auto table = Build(smooth, 0.0, 1.0, 33, 2.0, 256, "U = 1e6 L");
    const std::vector<Entry> entries = InsideEntries(table, RandomEntries(33, 300, 9));
    const std::vector<Reference> references = References(table, smooth, entries);
    double worstAlpha = 0.0, worstColour = 0.0;
    for (size_t e = 0; e < entries.size(); ++e)
    {
      double rgba[4];
      table->GetEntry(entries[e].I, entries[e].J, entries[e].K, rgba);
      const double* ref = references[e].RGBA;
      worstAlpha = std::max(worstAlpha, std::abs(rgba[3] / ref[3] - 1.0));
      for (int c = 0; c < 3; ++c)
      {
        worstColour = std::max(
          worstColour, rgba[3] > 0.0 ? std::abs(rgba[c] / rgba[3] - ref[c] / ref[3]) : 1.0);
      }
    }
    std::cout << "U = 1e6 L: " << entries.size() << " entries, alpha ~ " << references[0].RGBA[3]
              << ", largest relative alpha error " << worstAlpha << ", largest C / alpha error "
              << worstColour << "\n";
    check.Near(worstAlpha, 0.0, 2e-4, "U = 1e6 L: relative alpha error");
    check.Near(worstColour, 0.0, 5e-4, "U = 1e6 L: C / alpha is the mean colour");
  }
  {
    // (c) L = 1e-3 (U = 1): alpha = L int tau - (L int tau)^2 / 2 + ..., so |alpha - D| <=
    //     D^2 / 2 with D the optical depth, up to the relative 2e-4 of (b).
    smooth.SetUnit(1.0);
    auto table = Build(smooth, 0.0, 1.0, 33, 1e-3, 256, "L = 1e-3");
    const std::vector<Entry> entries = InsideEntries(table, RandomEntries(33, 300, 13));
    const std::vector<Reference> references = References(table, smooth, entries);
    double worstExcess = -1.0, largestDepth = 0.0;
    for (size_t e = 0; e < entries.size(); ++e)
    {
      double rgba[4];
      table->GetEntry(entries[e].I, entries[e].J, entries[e].K, rgba);
      const double d = references[e].Depth;
      largestDepth = std::max(largestDepth, d);
      worstExcess = std::max(worstExcess, std::abs(rgba[3] - d) - d * d / 2.0 - 2e-4 * d);
    }
    std::cout << "L = 1e-3: optical depths up to " << largestDepth
              << ", largest excess of |alpha - tau L| over its bound " << worstExcess << "\n";
    check(worstExcess <= 0.0, "L = 1e-3: alpha = tau L to first order");
  }

  //----------------------------------------------------------------------------
  // 7. Range ends: entry 0 is ScalarRange[0] and entry N - 1 exactly ScalarRange[1], so
  //    are the first and last iteration-table samples. Transfer functions with a step 1e-12
  //    of the range wide exactly at each end, inside or outside the range: evaluating one
  //    rounding error (1e-16 relative) beyond an end changes the opacity by 1e-4. The ranges
  //    and sizes are ones where r0 + (N - 1) ((r1 - r0) / (N - 1)) != r1 in double.
  {
    const double ranges[3][3] = { { 0.0, 255.0, 32 }, { 0.0, 1.0, 50 }, { 0.1, 0.7, 38 } };
    for (const auto& r : ranges)
    {
      const int n = static_cast<int>(r[2]);
      for (bool inside : { true, false })
      {
        const double w = 1e-12 * (r[1] - r[0]);
        TransferFunction ends;
        ends.Color->AddRGBPoint(r[0] - w, 0.0, 1.0, 0.0);
        ends.Color->AddRGBPoint(r[0], 1.0, 0.5, 0.25);
        ends.Color->AddRGBPoint(r[1], 0.25, 0.5, 1.0);
        ends.Color->AddRGBPoint(r[1] + w, 0.0, 1.0, 0.0);
        if (inside)
        {
          ends.Opacity->AddPoint(r[0], 0.9);
          ends.Opacity->AddPoint(r[0] + w, 0.0);
          ends.Opacity->AddPoint(r[1] - w, 0.0);
          ends.Opacity->AddPoint(r[1], 0.9);
        }
        else
        {
          ends.Opacity->AddPoint(r[0] - w, 0.9);
          ends.Opacity->AddPoint(r[0], 0.0);
          ends.Opacity->AddPoint(r[1], 0.0);
          ends.Opacity->AddPoint(r[1] + w, 0.9);
        }
        ends.SetUnit(1.0);
        std::ostringstream label;
        label << "range [" << r[0] << ", " << r[1] << "], N = " << n << ", steps "
              << (inside ? "inside" : "outside");
        auto table = Build(ends, r[0], r[1], n, 2.0, 16, label.str());
        vtkFloatArray* steps = table->GetIterationTable();
        const vtkIdType last = steps->GetNumberOfTuples() - 1;
        for (int end = 0; end < 2; ++end)
        {
          double f[4], rgba[4];
          ends.Exact(r[end], f);
          const double alpha = -std::expm1(-f[3] * 2.0);
          const double a = -std::expm1(-f[3] * 2.0 / 16);
          const int i = end ? n - 1 : 0;
          table->GetEntry(i, i, i, rgba);
          double worst = std::abs(rgba[3] - alpha);
          for (int c = 0; c < 3; ++c)
          {
            worst = std::max(worst, std::abs(rgba[c] - f[c] * alpha));
          }
          check.Near(worst,
            0.0,
            FloatTolerance,
            label.str() + ": diagonal entry " + std::to_string(i) +
              " is the exact exponential at " + (end ? "ScalarRange[1]" : "ScalarRange[0]"));
          const vtkIdType q = end ? last : 0;
          worst = std::abs(steps->GetComponent(q, 3) - a);
          for (int c = 0; c < 3; ++c)
          {
            worst = std::max(worst, std::abs(steps->GetComponent(q, c) - f[c] * a));
          }
          check.Near(worst,
            0.0,
            FloatTolerance,
            label.str() + ": iteration-table sample " + std::to_string(q) + " is at " +
              (end ? "ScalarRange[1]" : "ScalarRange[0]"));
        }
      }
    }
  }

  //----------------------------------------------------------------------------
  // 8. Empty runs. Opacity 0 on [0, 34] and [38, 50], a spike on (34, 38), 0.6 from 52 on;
  //    range [0, 63], N = 64 (entry i at scalar i). An entry whose scalar stays in [0, 34]
  //    or [38, 50] is exactly zero; one whose ends and middle lie in [0, 34] but whose
  //    extremum enters the spike is not (the empty test must use the extremum).
  {
    TransferFunction runs;
    MakeRunsTransferFunction(runs);
    const int n = 64;
    auto table = Build(runs, 0.0, 63.0, n, 2.0, 256, "empty runs");
    vtkFloatArray* coarse = table->GetEmptyRuns();
    bool runsOk = coarse->GetNumberOfTuples() == n - 1;
    for (int b = 0; b < n - 1 && runsOk; ++b)
    {
      const float expected = b < 34 ? 0.0f : b < 38 ? -1.0f : b < 50 ? 1.0f : -1.0f;
      runsOk = coarse->GetValue(b) == expected;
    }
    check(runsOk, "empty runs: spacings [0, 34] are run 0, [38, 50] run 1, the others -1");
    vtkFloatArray* fine = table->GetIterationEmptyRuns();
    const int per = table->GetIterationSamplesPerSpacing();
    bool fineOk = fine->GetNumberOfTuples() == per * (n - 1);
    for (vtkIdType q = 0; q < fine->GetNumberOfTuples() && fineOk; ++q)
    {
      fineOk = fine->GetValue(q) == coarse->GetValue(q / per);
    }
    check(fineOk, "iteration empty runs refine the table's empty runs");

    int zeros = 0, touching = 0;
    bool zerosOk = true, touchingOk = true;
    for (int k = 0; k < n; ++k)
    {
      for (int j = 0; j < n; ++j)
      {
        for (int i = 0; i < n; ++i)
        {
          double lo, hi, rgba[4];
          const Quadratic p(i, j, k);
          p.Range(lo, hi);
          lo = std::max(lo, 0.0);
          hi = std::min(hi, 63.0);
          table->GetEntry(i, j, k, rgba);
          if (hi <= 34.0 || (lo >= 38.0 && hi <= 50.0))
          {
            ++zeros;
            zerosOk =
              zerosOk && rgba[0] == 0.0 && rgba[1] == 0.0 && rgba[2] == 0.0 && rgba[3] == 0.0;
          }
          else if (std::max({ i, j, k }) <= 34 && hi >= 35.0)
          {
            // The step nearest the extremum has P >= 34.999 (P drops by at most
            // |A| / (2 Iterations)^2 = 252 / 512^2 within half a step), opacity >= 0.399,
            // so alpha >= 1 - 0.601^(L / Iterations) = 4e-3.
            ++touching;
            touchingOk = touchingOk && rgba[3] > 1e-3;
          }
        }
      }
    }
    std::cout << "Empty runs: " << zeros << " entries inside a zero-opacity run, " << touching
              << " entries reaching the spike only through their extremum\n";
    check(zeros > 10000 && zerosOk, "entries inside a zero-opacity run are exactly zero");
    check(touching > 100 && touchingOk, "entries whose extremum enters the spike are not zero");
    // Two of them against the brute force: (0, 32, 32) peaks at 36 for t = 3/4, and
    // (49, 39, 39) dips to 37.75 inside the spike from the run [38, 50]. Error budget at 256
    // iterations (h = 1/256) for (0, 32, 32), the worse one. Midpoint rule: h^2 / 24 int |g''|
    // with |g''| <= L (|tau''| P'^2 + |tau'| |P''|) <= 2 (4 * 22.6^2 + 2 * 128) = 4.6e3 over
    // the 0.35 of the slab inside the spike, plus two kinks where P enters and leaves it,
    // h^2 / 8 |tau'| |P'| L each: 1.1e-3. Linear interpolation of the iteration table (samples
    // ds = 1/8 apart): ds^2 / 8 L int |tau''(P)| dt <= 1/512 * 2 * 4 * 0.35 = 5.5e-3.
    for (const Entry& e : { Entry{ 0, 32, 32 }, Entry{ 49, 39, 39 } })
    {
      const Reference ref =
        Integrate(runs.Sampler, EntryQuadratic(table, e), 2.0, table->GetScalarRange());
      double rgba[4], worst = 0.0;
      table->GetEntry(e.I, e.J, e.K, rgba);
      for (int c = 0; c < 4; ++c)
      {
        worst = std::max(worst, std::abs(rgba[c] - ref.RGBA[c]));
      }
      std::cout << Where("Empty runs: alpha " + std::to_string(rgba[3]) + ", error", e) << " "
                << worst << "\n";
      check(ref.RGBA[3] > 0.01, Where("the reference is not empty", e));
      check.Near(worst, 0.0, 6.6e-3, Where("extremum-only entry equals the brute force", e));
    }
  }

  //----------------------------------------------------------------------------
  // 9. Prefilter (the default): every entry integrates the transfer function box-averaged
  //    over one entry spacing, the box narrowing to nothing at the range ends.
  {
    // (a) The diagonal is the exact exponential of the box average, computed here
    //     independently; the end entries that of the exact transfer function.
    auto table = Build(spiky,
      spikyRange[0],
      spikyRange[1],
      48,
      1.3,
      64,
      "prefiltered spiky transfer function",
      true);
    const int n = table->GetTableSize();
    const double spacing = (spikyRange[1] - spikyRange[0]) / (n - 1);
    double worst = 0.0, worstEnd = 0.0;
    for (int i = 0; i < n; ++i)
    {
      double v[4];
      const double s = EntryScalar(spikyRange, n, i);
      if (i == 0 || i == n - 1)
      {
        double rgbTau[4];
        spiky.Exact(s, rgbTau);
        for (int c = 0; c < 3; ++c)
        {
          v[c] = rgbTau[c] * rgbTau[3];
        }
        v[3] = rgbTau[3];
      }
      else
      {
        BoxAverage(spiky.Sampler, s, 0.5 * spacing, v);
      }
      const double alpha = -std::expm1(-v[3] * 1.3);
      double rgba[4];
      table->GetEntry(i, i, i, rgba);
      for (int c = 0; c < 4; ++c)
      {
        const double expected = c < 3 ? (v[3] > 0.0 ? v[c] / v[3] * alpha : 0.0) : alpha;
        (i == 0 || i == n - 1 ? worstEnd : worst) =
          std::max(i == 0 || i == n - 1 ? worstEnd : worst, std::abs(rgba[c] - expected));
      }
    }
    std::cout << "Prefilter: diagonal against the box-averaged transfer function, largest error "
              << worst << " (ends " << worstEnd << ")\n";
    // The table averages linear interpolation between its iteration-table samples (16 per
    // narrowest feature): the spikes' curvature in tau costs about 1e-4.
    check.Near(worst, 0.0, 5e-4, "prefiltered diagonal is exp(-L box average of tau)");
    check.Near(worstEnd, 0.0, 1e-10 + FloatTolerance, "prefiltered end entries are exact");

    // (b) A feature narrower than the spacing keeps its integral wherever it lies: the sum
    //     over the diagonal of tau_i spacing (tau_i = -ln(1 - alpha_i) / L) equals the integral
    //     of tau. Without the prefilter that sum depends on where the entries fall.
    const double offsets[4] = { 0.0, 0.25, 0.5, 0.8 };
    double worstLoss = 0.0, leastRaw = 1e300, mostRaw = 0.0;
    for (double offset : offsets)
    {
      TransferFunction narrow;
      const double centre = 20.0 + offset; // range [0, 40], N = 41: entry i at scalar i
      narrow.Color->AddRGBPoint(0.0, 1.0, 0.8, 0.2);
      narrow.Color->AddRGBPoint(40.0, 0.2, 0.4, 1.0);
      narrow.Opacity->AddPoint(centre - 0.1, 0.0);
      narrow.Opacity->AddPoint(centre, 0.6);
      narrow.Opacity->AddPoint(centre + 0.1, 0.0);
      narrow.SetUnit(1.0);
      double integral[4];
      BoxAverage(narrow.Sampler, 20.0, 20.0, integral); // mean over [0, 40]
      integral[3] *= 40.0;
      double sums[2] = { 0.0, 0.0 };
      for (bool prefilter : { true, false })
      {
        auto t = Build(narrow, 0.0, 40.0, 41, 2.0, 16, "narrow feature", prefilter);
        for (int i = 0; i < 41; ++i)
        {
          double rgba[4];
          t->GetEntry(i, i, i, rgba);
          sums[prefilter ? 0 : 1] += -std::log1p(-rgba[3]) / 2.0;
        }
      }
      std::cout << "Prefilter: feature at " << centre << ", integral of tau " << integral[3]
                << ", sum over the diagonal " << sums[0] << " (without the prefilter " << sums[1]
                << ")\n";
      worstLoss = std::max(worstLoss, std::abs(sums[0] / integral[3] - 1.0));
      leastRaw = std::min(leastRaw, sums[1] / integral[3]);
      mostRaw = std::max(mostRaw, sums[1] / integral[3]);
    }
    check.Near(worstLoss, 0.0, 0.01, "prefiltered: a narrow feature keeps its integral");
    check(leastRaw < 0.5 && mostRaw > 2.0,
      "without the prefilter the narrow feature is lost or magnified by the entry placement");

    // (c) Empty runs widen by half a spacing: the opacity spread by the filter is never
    //     skipped. The transfer function of section 8 (spike on (34, 38), opacity from 50 on),
    //     range [0, 63], N = 64: spacing b is empty when [b - 1/2, b + 3/2] has no opacity.
    TransferFunction runs;
    MakeRunsTransferFunction(runs);
    auto t = Build(runs, 0.0, 63.0, 64, 2.0, 64, "prefiltered empty runs", true);
    vtkFloatArray* coarse = t->GetEmptyRuns();
    bool runsOk = coarse->GetNumberOfTuples() == 63;
    for (int b = 0; b < 63 && runsOk; ++b)
    {
      const float expected = b < 33 ? 0.0f : b < 39 ? -1.0f : b < 49 ? 1.0f : -1.0f;
      runsOk = coarse->GetValue(b) == expected;
    }
    check(runsOk, "prefiltered empty runs: spacings [0, 33] are run 0, [39, 49] run 1");
    int zeros = 0;
    bool zerosOk = true;
    for (int k = 0; k < 64; ++k)
    {
      for (int j = 0; j < 64; ++j)
      {
        for (int i = 0; i < 64; ++i)
        {
          double lo, hi, rgba[4];
          Quadratic(i, j, k).Range(lo, hi);
          if (hi <= 33.0 || (lo >= 39.0 && hi <= 49.0))
          {
            ++zeros;
            t->GetEntry(i, j, k, rgba);
            zerosOk =
              zerosOk && rgba[0] == 0.0 && rgba[1] == 0.0 && rgba[2] == 0.0 && rgba[3] == 0.0;
          }
        }
      }
    }
    check(zeros > 10000 && zerosOk, "prefiltered: entries inside an empty run are exactly zero");
  }

  //----------------------------------------------------------------------------
  // 10. Rebuilds: exactly one per change of something the table depends on, none otherwise.
  //    ComputeEntries off still counts a build and prepares the iteration table and the
  //    empty runs (for the GPU builder), leaving GetTable() empty.
  {
    TransferFunction tf;
    tf.Color->AddRGBPoint(0.0, 0.0, 0.3, 1.0);
    tf.Color->AddRGBPoint(1.0, 1.0, 0.3, 0.0);
    tf.Opacity->AddPoint(0.0, 0.1);
    tf.Opacity->AddPoint(1.0, 0.6);
    tf.SetUnit(1.0);
    vtkNew<vtkSecondOrderPreIntegrationTable> table;
    table->SetVolumeProperty(tf.Property);
    table->SetScalarRange(0.0, 1.0);
    table->SetTableSize(16);
    table->SetIterations(16);
    check(table->GetBuildCount() == 0, "no build before Update()");
    check(table->GetNumberOfDimensions() == 3, "second-order table is 3D");
    check(table->Update() && table->Update(), "Update twice");
    check(table->GetBuildCount() == 1, "Update() twice without change builds once");
    check(table->GetTable()->GetNumberOfTuples() == 16 * 16 * 16, "table has N^3 entries");
    check(table->GetMemorySize() == 16 * 16 * 16 * 4 * static_cast<vtkIdType>(sizeof(float)),
      "memory size is N^3 RGBA floats");
    table->SetVolumeProperty(tf.Property);
    table->SetSegmentLength(table->GetSegmentLength());
    table->SetScalarRange(0.0, 1.0);
    table->SetTableSize(16);
    table->SetIterations(16);
    table->SetComputeEntries(true);
    check(
      table->Update() && table->GetBuildCount() == 1, "setting unchanged values does not rebuild");

    int expected = 1;
    auto expectOneRebuild = [&](const char* what)
    {
      ++expected;
      const bool ok = table->Update() && table->Update();
      check(ok && table->GetBuildCount() == expected,
        std::string(what) + " triggers exactly one rebuild (build count " +
          std::to_string(table->GetBuildCount()) + ", expected " + std::to_string(expected) + ")");
    };
    tf.Opacity->AddPoint(0.5, 0.2);
    expectOneRebuild("scalar opacity AddPoint");
    tf.Color->AddRGBPoint(0.5, 1.0, 1.0, 1.0);
    expectOneRebuild("colour AddRGBPoint");
    tf.Property->SetScalarOpacityUnitDistance(0.5);
    table->SetVolumeProperty(tf.Property);
    expectOneRebuild("unit distance through the volume property");
    table->GetSampler()->SetScalarOpacityUnitDistance(0.25);
    expectOneRebuild("unit distance on the sampler");
    table->SetSegmentLength(1.0);
    expectOneRebuild("segment length");
    table->SetScalarRange(0.0, 2.0);
    expectOneRebuild("scalar range");
    table->SetTableSize(17);
    expectOneRebuild("table size");
    check(table->GetTable()->GetNumberOfTuples() == 17 * 17 * 17, "table resized to 17^3 entries");
    double before[4], after[4];
    table->GetEntry(0, 8, 16, before);
    table->SetIterations(32);
    expectOneRebuild("Iterations");
    table->GetEntry(0, 8, 16, after);
    check(before[3] != after[3], "a change of Iterations changes the entries");
    check(table->GetPrefilter(), "the prefilter is on by default");
    table->SetPrefilter(false);
    expectOneRebuild("Prefilter");

    table->SetComputeEntries(false);
    expectOneRebuild("ComputeEntries off");
    const int fine = table->GetIterationSamplesPerSpacing() * 16 + 1;
    check(table->GetTable()->GetNumberOfTuples() == 0 && table->GetMemorySize() == 0,
      "ComputeEntries off leaves GetTable() empty");
    check(table->GetIterationTable()->GetNumberOfTuples() == fine &&
        table->GetIterationEmptyRuns()->GetNumberOfTuples() == fine - 1 &&
        table->GetEmptyRuns()->GetNumberOfTuples() == 16,
      "ComputeEntries off builds the iteration table and the empty runs");
    // The iteration table is that of the current settings (Iterations 32, L = 1, U = 0.25).
    double f[4];
    tf.Sampler->SetScalarOpacityUnitDistance(0.25);
    check(tf.Sampler->Prepare(), "reference sampler prepared");
    tf.Sampler->Evaluate(2.0, f);
    const double a = -std::expm1(-f[3] * 1.0 / 32);
    check.Near(table->GetIterationTable()->GetComponent(fine - 1, 3),
      a,
      FloatTolerance,
      "ComputeEntries off: iteration table of the current settings");
    table->SetComputeEntries(true);
    expectOneRebuild("ComputeEntries back on");
    check(table->GetTable()->GetNumberOfTuples() == 17 * 17 * 17, "entries computed again");
    check(table->GetLastBuildTime() >= 0.0, "build time is measured");
  }

  //----------------------------------------------------------------------------
  // 11. Invalid settings: Update() returns false with an error, and nothing is built.
  messages.ExpectNone(check, "before the invalid-settings checks");
  {
    TransferFunction tf;
    tf.Color->AddRGBPoint(0.0, 1.0, 1.0, 1.0);
    tf.Opacity->AddPoint(0.0, 0.5);
    tf.SetUnit(1.0);
    vtkNew<vtkSecondOrderPreIntegrationTable> table;
    table->SetTableSize(8);
    table->SetIterations(8);
    hovrTest::CheckInvalidTableSettings(
      check, messages, table.GetPointer(), tf.Property.GetPointer(), tf.Color.GetPointer(), 2.0);
  }

  messages.ExpectNone(check, "at the end of the test");
  return check.Result("TestSecondOrderPreIntegrationTable");
}
