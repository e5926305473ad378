// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
// vtkSecondOrderPreIntegrationTable against the slab integral of El Hajjar et al., Eq. 2:
//   alpha = 1 - exp(-int_0^1 tau(P(t)) L dt),
//   C     = int_0^1 c(P(t)) tau(P(t)) L exp(-int_0^t tau(P(t')) L dt') dt,
// with P the quadratic of the entry in the table's axes (chord centre c, chord b, deviation
// d): P(t) = c - b/2 + (b + 4d) t - 4d t^2, clamped to the scalar range. References: closed
// forms (constant scalar, constant colour, saturation, thin media) and an independent
// brute-force integration in double. Also: the axes and paths, symmetry, range ends, clamping,
// empty-slab skipping, the kernel that evaluates single entries (as the sizer does), the
// prefilter, rebuild bookkeeping and error handling.
// One file, beyond the usual length: every check shares the slab-integral reference above.
#include "vtkCallbackCommand.h"
#include "vtkColorTransferFunction.h"
#include "vtkCommand.h"
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
// Table values are floats computed in float (the GPU builder's arithmetic): a slab of n
// steps rounds each step's colour and alpha a few times. 2^-24 per operation.
constexpr double FloatEpsilon = 1.0 / 16777216.0;
// The sampler's default opacity cap (the extinction of opacity 1 stays finite).
constexpr double MaximumOpacity = 1.0 - 1e-9;
// Steps of the brute-force reference: its midpoint error is (steps of the table / 20000)^2
// of the table's.
constexpr int ReferenceSteps = 20000;

hovrTest::Checker check;

struct Entry
{
  int I, J, K; // centre, chord, deviation
};

std::string Where(const std::string& what, const Entry& e)
{
  std::ostringstream os;
  os << what << " at entry (" << e.I << ", " << e.J << ", " << e.K << ")";
  return os.str();
}

// P(t) = C + B t + A t^2.
struct Quadratic
{
  double C, B, A;
  double operator()(double t) const { return this->C + t * (this->B + this->A * t); }
  double Slope(double t) const { return this->B + 2.0 * this->A * t; }
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
  double path[3];
  table->GetEntryPath(e.I, e.J, e.K, path);
  return Quadratic{ path[0], path[1], path[2] };
}

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

  void SetUnit(double unit)
  {
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
    rgbTau[3] = -std::log1p(-opacity) / this->Property->GetScalarOpacityUnitDistance();
  }

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

struct Sizes
{
  int Centre, Chord, Deviation;
  double ChordRange, DeviationRange; // 0: the range's width
};

// Every entry finite, 0 <= alpha <= 1, 0 <= colour <= alpha max(c) (premultiplied), with the
// rounding allowance of float compositing over the most steps a slab takes.
void CheckValid(vtkSecondOrderPreIntegrationTable* table,
  TransferFunction& tf,
  const std::string& label)
{
  double cmax[3];
  tf.MaximumColor(cmax);
  const double allowance = 8.0 * table->GetIterations() * FloatEpsilon;
  const float* v = table->GetTable()->GetPointer(0);
  const vtkIdType count = table->GetTable()->GetNumberOfTuples();
  vtkIdType bad = 0;
  for (vtkIdType e = 0; e < count; ++e)
  {
    const float* rgba = v + 4 * e;
    bool ok = std::isfinite(rgba[3]) && rgba[3] >= 0.0f && rgba[3] <= 1.0f;
    for (int c = 0; c < 3; ++c)
    {
      ok =
        ok && std::isfinite(rgba[c]) && rgba[c] >= 0.0f && rgba[c] <= rgba[3] * cmax[c] + allowance;
    }
    bad += ok ? 0 : 1;
  }
  check(count == table->GetNumberOfEntries() && bad == 0,
    label + ": every entry finite with 0 <= alpha <= 1 and 0 <= C <= alpha max(c) (" +
      std::to_string(bad) + " bad entries)");
}

vtkSmartPointer<vtkSecondOrderPreIntegrationTable> Build(TransferFunction& tf,
  double r0,
  double r1,
  const Sizes& sizes,
  double length,
  int iterations,
  const std::string& label,
  bool prefilter = false)
{
  auto table = vtkSmartPointer<vtkSecondOrderPreIntegrationTable>::New();
  table->SetPrefilter(prefilter);
  table->SetVolumeProperty(tf.Property);
  table->SetScalarRange(r0, r1);
  table->SetTableSize(sizes.Centre);
  table->SetChordSize(sizes.Chord);
  table->SetDeviationSize(sizes.Deviation);
  table->SetChordRange(sizes.ChordRange);
  table->SetDeviationRange(sizes.DeviationRange);
  table->SetSegmentLength(length);
  table->SetIterations(iterations);
  check(table->Update(), "Update: " + label);
  CheckValid(table, tf, label);
  return table;
}

std::vector<Entry> RandomEntries(const Sizes& s, int count, int seed)
{
  vtkNew<vtkMinimalStandardRandomSequence> random;
  random->SetSeed(seed);
  auto next = [&](int n)
  {
    random->Next();
    return std::min(static_cast<int>(random->GetValue() * n), n - 1);
  };
  std::vector<Entry> entries;
  for (int e = 0; e < count; ++e)
  {
    const int i = next(s.Centre), j = next(s.Chord), k = next(s.Deviation);
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

// Random nodes 0.5 to 3.5 apart, mixed sharpness and midpoints, opacity up to 0.95, plus two
// opacity spikes 0 -> 0.95 -> 0 only 0.08 wide.
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
// 0.5; tau = -ln(1 - alpha) / U is analytic inside the range.
void MakeSmoothTransferFunction(TransferFunction& tf)
{
  tf.Color->AddRGBPoint(0.0, 0.9, 0.2, 0.1);
  tf.Color->AddRGBPoint(1.0, 0.1, 0.6, 1.0);
  tf.Opacity->AddPoint(0.0, 0.1);
  tf.Opacity->AddPoint(1.0, 0.5);
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
}

int TestSecondOrderPreIntegrationTable(int, char*[])
{
  hovrTest::MessageCapture messages;

  TransferFunction spiky;
  const double spikyEnd = MakeSpikyTransferFunction(spiky, 11);
  spiky.SetUnit(0.8);
  const double spikyRange[2] = { -1.0, spikyEnd + 1.0 };
  const double spikyWidth = spikyRange[1] - spikyRange[0];

  //----------------------------------------------------------------------------
  // 1. Axes and paths. Entry (i, j, k): centre r0 + i (r1 - r0) / (N - 1), chord
  //    -R + 2 R j / (ChordSize - 1), deviation likewise; P(0) = front = c - b/2, P(1) = back,
  //    P(1/2) = middle = c + d. The chord and deviation grids are symmetric about 0, so
  //    entry ChordSize - 1 - j holds the reversed chord.
  {
    const Sizes sizes{ 9, 7, 5, 3.0, 1.5 };
    auto table = Build(spiky, spikyRange[0], spikyRange[1], sizes, 1.3, 64, "axes");
    check(table->GetNumberOfEntries() == 9 * 7 * 5 &&
        table->GetTable()->GetNumberOfTuples() == 9 * 7 * 5,
      "the table has TableSize x ChordSize x DeviationSize entries");
    check(table->GetMemorySize() == 9 * 7 * 5 * 4 * static_cast<vtkIdType>(sizeof(float)),
      "memory size is the entries' RGBA floats");
    double worst = 0.0;
    for (int i = 0; i < 9; ++i)
    {
      for (int j = 0; j < 7; ++j)
      {
        for (int k = 0; k < 5; ++k)
        {
          const Quadratic p = EntryQuadratic(table, { i, j, k });
          const double c = spikyRange[0] + spikyWidth * i / 8.0;
          const double b = 3.0 * (2.0 * j - 6.0) / 6.0, d = 1.5 * (2.0 * k - 4.0) / 4.0;
          worst = std::max({ worst,
            std::abs(p(0.0) - (c - 0.5 * b)),
            std::abs(p(1.0) - (c + 0.5 * b)),
            std::abs(p(0.5) - (c + d)) });
        }
      }
    }
    check.Near(worst, 0.0, 1e-12, "entry paths: P(0) = c - b/2, P(1) = c + b/2, P(1/2) = c + d");
    double last[3], mirror[3];
    table->GetEntryPath(8, 1, 2, last);
    table->GetEntryPath(8, 5, 2, mirror);
    check(last[0] + last[1] + last[2] == mirror[0] && mirror[0] + mirror[1] + mirror[2] == last[0],
      "chord entry j and ChordSize - 1 - j are the same path reversed");
    check(table->GetEffectiveChordRange() == 3.0 && table->GetEffectiveDeviationRange() == 1.5,
      "effective ranges are the ranges set");
    table->SetChordRange(0.0);
    table->SetDeviationRange(-1.0);
    check(table->GetEffectiveChordRange() == spikyWidth &&
        table->GetEffectiveDeviationRange() == spikyWidth,
      "ranges of 0 or less are the scalar range's width");
    table->SetDeviationSize(1);
    check(table->GetEffectiveDeviationRange() == 0.0, "one deviation entry: deviation 0 only");
  }

  //----------------------------------------------------------------------------
  // 2. Chord 0, deviation 0 is a constant medium: one step, the exact exponential
  //    alpha = 1 - exp(-tau(s) L), C = c(s) alpha, colour and opacity from VTK's own functions.
  {
    const Sizes sizes{ 48, 5, 3, 2.0, 1.0 };
    auto table = Build(spiky, spikyRange[0], spikyRange[1], sizes, 1.3, 64, "constant slabs");
    double worst = 0.0;
    for (int i = 0; i < 48; ++i)
    {
      double f[4], rgba[4];
      spiky.Exact(i == 47 ? spikyRange[1] : spikyRange[0] + spikyWidth * i / 47.0, f);
      const double alpha = -std::expm1(-f[3] * 1.3);
      table->GetEntry(i, 2, 1, rgba);
      worst = std::max(worst, std::abs(rgba[3] - alpha));
      for (int c = 0; c < 3; ++c)
      {
        worst = std::max(worst, std::abs(rgba[c] - f[c] * alpha));
      }
    }
    std::cout << "Constant slabs: largest deviation from the exact exponential " << worst << "\n";
    // One step in float: exp and a few products, 1e-6 relative; VTK's functions and the
    // sampler agree to 1e-10 in tau.
    check.Near(worst, 0.0, 2e-6, "chord 0, deviation 0: 1 - exp(-tau L), c alpha");
    // The iteration table: (c tau, tau) at equispaced scalars, 16 across the narrowest
    // feature (0.04), an even number per centre spacing.
    const int per = table->GetIterationSamplesPerSpacing();
    const int fine = table->GetNumberOfIterationSamples();
    check(per % 2 == 0 && fine == per * 47 + 1 && spikyWidth / (fine - 1) <= 0.04 / 16.0 + 1e-12,
      "iteration table resolves the narrowest feature with 16 samples");
    vtkFloatArray* samples = table->GetIterationTable();
    double worstSample = 0.0;
    for (int q = 0; q < fine; q += 7)
    {
      double f[4];
      spiky.Exact(q == fine - 1 ? spikyRange[1] : spikyRange[0] + spikyWidth * q / (fine - 1), f);
      for (int c = 0; c < 4; ++c)
      {
        const double expected = c < 3 ? f[c] * f[3] : f[3];
        worstSample = std::max(worstSample,
          std::abs(samples->GetComponent(q, c) - expected) / std::max(1.0, std::abs(expected)));
      }
    }
    check.Near(worstSample, 0.0, 1e-6, "iteration table holds (c tau, tau)");
  }

  //----------------------------------------------------------------------------
  // 3. Against the brute-force Eq. 2 for random entries. The table takes one midpoint step per
  //    iteration-table sample the path sweeps (at least 1), so on a smooth transfer function
  //    the error is second order in that spacing; capping the steps (Iterations) raises it
  //    for long paths, by 16 per factor 4 of the cap when the cap binds.
  TransferFunction smooth;
  MakeSmoothTransferFunction(smooth);
  smooth.SetUnit(0.5);
  {
    const Sizes sizes{ 65, 33, 17, 0.0, 0.0 };
    const int caps[3] = { 8, 32, 128 };
    double errors[3];
    std::vector<Entry> entries;
    std::vector<Reference> references;
    for (int c = 0; c < 3; ++c)
    {
      auto table = Build(smooth, 0.0, 1.0, sizes, 2.0, caps[c], "smooth transfer function");
      if (c == 0)
      {
        // Paths sweeping more than 128 samples (|b| + 4|d| > 128 / 512 of the range): the
        // cap binds at every value tried.
        for (const Entry& e : InsideEntries(table, RandomEntries(sizes, 3000, 5)))
        {
          const Quadratic p = EntryQuadratic(table, e);
          if (std::max(std::abs(p.B), std::abs(2.0 * p.A + p.B)) * 512.0 > 130.0)
          {
            entries.push_back(e);
          }
        }
        references = References(table, smooth, entries);
      }
      errors[c] = LargestError(table, entries, references);
      std::cout << "Smooth transfer function, " << entries.size() << " long entries, at most "
                << caps[c] << " steps: largest error " << errors[c] << "\n";
    }
    check(entries.size() >= 100, "enough long random entries inside the range");
    for (int c = 1; c < 3; ++c)
    {
      const double ratio = errors[c - 1] / errors[c];
      // Second order: 16, within [10, 22] (float compositing and the iteration table's
      // linear interpolation add a part that does not shrink; at 128 steps it is below 1e-5).
      check(ratio > 10.0 && ratio < 22.0,
        "smooth transfer function: error ratio from cap " + std::to_string(caps[c - 1]) + " to " +
          std::to_string(caps[c]) + " is about 16, got " + std::to_string(ratio));
    }
    // Uncapped (every entry sweeps fewer samples than 4096): the midpoint rule at one step per
    // sample (ds = 1/512: ds^2 / 24 |g''| / g, 1e-5 relative) and float compositing of up to
    // 1500 steps (a rounding of 2^-24 or two per step: 1e-4).
    auto table = Build(smooth, 0.0, 1.0, sizes, 2.0, 4096, "smooth transfer function, uncapped");
    const std::vector<Entry> all = InsideEntries(table, RandomEntries(sizes, 400, 6));
    const double error = LargestError(table, all, References(table, smooth, all));
    std::cout << "Smooth transfer function, " << all.size() << " entries, uncapped: largest error "
              << error << "\n";
    check.Near(error, 0.0, 2e-4, "uncapped entries equal the brute force");
  }
  {
    // Spiky transfer function: a step of the path is at most one iteration-table sample (1/16
    // of the narrowest feature) wide, so a spike is integrated by 16 steps or more: errors of
    // the midpoint rule on the spike's kinks, bounded by the peak's optical depth over 16
    // steps times the kink share, measured here below 2e-3 for the whole range of entries.
    const Sizes sizes{ 48, 25, 13, 0.0, 0.0 };
    auto table = Build(spiky, spikyRange[0], spikyRange[1], sizes, 1.3, 65536, "spiky, uncapped");
    const std::vector<Entry> entries = InsideEntries(table, RandomEntries(sizes, 300, 7));
    const double error = LargestError(table, entries, References(table, spiky, entries));
    std::cout << "Spiky transfer function, " << entries.size()
              << " entries, uncapped: largest error " << error << "\n";
    check.Near(error, 0.0, 2e-3, "spiky transfer function: entries equal the brute force");
  }

  //----------------------------------------------------------------------------
  // 4. Symmetry: chords j and ChordSize - 1 - j are one path in opposite directions, so alpha
  //    is the same and the colour depends on the order; with a constant colour c, C = c alpha.
  {
    const Sizes sizes{ 48, 21, 9, 0.0, 0.0 };
    auto table = Build(spiky, spikyRange[0], spikyRange[1], sizes, 1.3, 64, "symmetry");
    double worstAlpha = 0.0, largestColour = 0.0;
    for (int k = 0; k < 9; ++k)
    {
      for (int j = 0; j < 10; ++j)
      {
        for (int i = 0; i < 48; ++i)
        {
          double forward[4], backward[4];
          table->GetEntry(i, j, k, forward);
          table->GetEntry(i, 20 - j, k, backward);
          worstAlpha = std::max(worstAlpha, std::abs(forward[3] - backward[3]));
          for (int c = 0; c < 3; ++c)
          {
            largestColour = std::max(largestColour, std::abs(forward[c] - backward[c]));
          }
        }
      }
    }
    std::cout << "Symmetry: largest |alpha forward - alpha backward| " << worstAlpha
              << ", largest colour asymmetry " << largestColour << "\n";
    // Two float chains of at most 64 steps, each rounding twice a step.
    check.Near(worstAlpha, 0.0, 4.0 * 64 * FloatEpsilon, "alpha is the same both ways");
    check(largestColour > 0.05, "colour depends on the direction");
  }
  {
    TransferFunction constant;
    const double c[3] = { 0.3, 0.6, 0.9 };
    constant.Color->AddRGBPoint(0.0, c[0], c[1], c[2]);
    constant.Opacity->DeepCopy(spiky.Opacity);
    constant.SetUnit(0.8);
    auto table = Build(
      constant, spikyRange[0], spikyRange[1], { 40, 21, 9, 0.0, 0.0 }, 1.3, 64, "constant colour");
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
    check.Near(worst, 0.0, 8.0 * 64 * FloatEpsilon, "constant colour: C = c alpha for every entry");
  }

  //----------------------------------------------------------------------------
  // 5. Clamping: paths that leave the range are clamped to it (the trilinear field never
  //    leaves the data range). The transfer function keeps changing beyond the range, so the
  //    clamped and unclamped integrals differ.
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
    const Sizes sizes{ 17, 17, 9, 0.0, 0.0 };
    auto table = Build(beyond, 0.0, 1.0, sizes, 2.0, 65536, "transfer function beyond the range");
    std::vector<Entry> entries;
    for (const Entry& e : RandomEntries(sizes, 600, 3))
    {
      double lo, hi;
      EntryQuadratic(table, e).Range(lo, hi);
      if (lo < -0.05 || hi > 1.05)
      {
        entries.push_back(e);
      }
    }
    const std::vector<Reference> references = References(table, beyond, entries);
    const double error = LargestError(table, entries, references);
    double smallestUnclamped = 1.0;
    for (size_t e = 0; e < entries.size(); ++e)
    {
      const Reference free =
        Integrate(beyond.Sampler, EntryQuadratic(table, entries[e]), 2.0, nullptr, 2000);
      double difference = 0.0;
      for (int c = 0; c < 4; ++c)
      {
        difference = std::max(difference, std::abs(free.RGBA[c] - references[e].RGBA[c]));
      }
      smallestUnclamped = std::min(smallestUnclamped, difference);
    }
    std::cout << "Clamping: " << entries.size() << " entries leaving the range, largest error "
              << error << " against the clamped brute force; the unclamped integrals differ by "
              << "at least " << smallestUnclamped << "\n";
    // Second order but with kinks where the clamped path meets the range ends: measured 1e-4.
    check(entries.size() > 100, "enough entries leaving the range");
    check.Near(error, 0.0, 5e-4, "entries leaving the range equal the clamped integral");
    check(smallestUnclamped > 1e-3, "clamping matters for these entries");
  }

  //----------------------------------------------------------------------------
  // 6. Saturation and extreme unit distances. Opacity 1 (capped at 1 - 1e-9) keeps every
  //    entry finite; U = 1e-6 L makes every step opaque, so alpha = 1 and the colour is that at
  //    the front within the first half step; U = 1e6 L makes the slab thin, alpha ~ tau L.
  {
    TransferFunction opaque;
    opaque.Color->AddRGBPoint(0.0, 1.0, 0.0, 0.0);
    opaque.Color->AddRGBPoint(1.0, 0.0, 0.0, 1.0);
    opaque.Opacity->AddPoint(0.0, 1.0);
    opaque.Opacity->AddPoint(1.0, 1.0);
    opaque.SetUnit(1e-6);
    const Sizes sizes{ 33, 17, 9, 0.0, 0.0 };
    auto table = Build(opaque, 0.0, 1.0, sizes, 2.0, 64, "opacity 1, U = 1e-6 L");
    double worstAlpha = 0.0, worstExcess = -1.0;
    for (const Entry& e : RandomEntries(sizes, 500, 17))
    {
      const Quadratic p = EntryQuadratic(table, e);
      double rgba[4], f[4];
      table->GetEntry(e.I, e.J, e.K, rgba);
      const double front = std::min(std::max(p.C, 0.0), 1.0);
      opaque.Exact(front, f);
      // The first step's midpoint lies at most half a step (1/(2 steps) <= 1/2) along P.
      double lo, hi;
      Quadratic{ p.C, p.B, p.A }.Range(lo, hi);
      const int steps = std::max(1,
        std::min(64,
          static_cast<int>(std::ceil(std::max(std::abs(p.B), std::abs(2 * p.A + p.B)) *
            (table->GetNumberOfIterationSamples() - 1)))));
      const double moved = std::abs(std::min(std::max(p(0.5 / steps), 0.0), 1.0) - front);
      worstAlpha = std::max(worstAlpha, 1.0 - rgba[3]);
      worstExcess = std::max(worstExcess, std::abs(rgba[0] - f[0]) - moved - 1e-5);
    }
    check.Near(worstAlpha, 0.0, 1e-6, "U = 1e-6 L: alpha = 1");
    check(worstExcess <= 0.0, "U = 1e-6 L: the colour of the first step");
  }
  {
    smooth.SetUnit(2e6);
    const Sizes sizes{ 33, 17, 9, 0.0, 0.0 };
    auto table = Build(smooth, 0.0, 1.0, sizes, 2.0, 65536, "U = 1e6 L");
    const std::vector<Entry> entries = InsideEntries(table, RandomEntries(sizes, 300, 9));
    const std::vector<Reference> references = References(table, smooth, entries);
    double worstAlpha = 0.0;
    for (size_t e = 0; e < entries.size(); ++e)
    {
      double rgba[4];
      table->GetEntry(entries[e].I, entries[e].J, entries[e].K, rgba);
      worstAlpha = std::max(worstAlpha, std::abs(rgba[3] / references[e].RGBA[3] - 1.0));
    }
    std::cout << "U = 1e6 L: alpha ~ " << references[0].RGBA[3] << ", largest relative error "
              << worstAlpha << "\n";
    // The series of 1 - exp for thin steps keeps float's relative precision: 1e-4 relative
    // (the midpoint rule on the smooth function, 1e-5, and float compositing).
    check.Near(worstAlpha, 0.0, 1e-4, "U = 1e6 L: thin slabs keep their relative precision");
    smooth.SetUnit(0.5);
  }

  //----------------------------------------------------------------------------
  // 7. Range ends: the first and last iteration-table samples are exactly ScalarRange[0] and
  //    [1]. Steps 1e-12 of the range wide at each end: one rounding error beyond an end
  //    changes the opacity there. Ranges where r0 + (N - 1) ((r1 - r0) / (N - 1)) != r1.
  {
    const double ranges[3][3] = { { 0.0, 255.0, 32 }, { 0.0, 1.0, 50 }, { 0.1, 0.7, 38 } };
    for (const auto& r : ranges)
    {
      const int n = static_cast<int>(r[2]);
      const double w = 1e-12 * (r[1] - r[0]);
      TransferFunction ends;
      ends.Color->AddRGBPoint(r[0], 1.0, 0.5, 0.25);
      ends.Color->AddRGBPoint(r[1], 0.25, 0.5, 1.0);
      ends.Opacity->AddPoint(r[0], 0.9);
      ends.Opacity->AddPoint(r[0] + w, 0.0);
      ends.Opacity->AddPoint(r[1] - w, 0.0);
      ends.Opacity->AddPoint(r[1], 0.9);
      ends.SetUnit(1.0);
      auto table = Build(ends, r[0], r[1], { n, 5, 3, 0.0, 0.0 }, 2.0, 16, "range ends");
      for (int end = 0; end < 2; ++end)
      {
        double f[4], rgba[4];
        ends.Exact(r[end], f);
        const double alpha = -std::expm1(-f[3] * 2.0);
        table->GetEntry(end ? n - 1 : 0, 2, 1, rgba);
        check.Near(rgba[3],
          alpha,
          2e-6,
          "range [" + std::to_string(r[0]) + ", " + std::to_string(r[1]) + "]: the constant slab " +
            (end ? "at ScalarRange[1]" : "at ScalarRange[0]") + " is the exact exponential");
      }
    }
  }

  //----------------------------------------------------------------------------
  // 8. Empty runs: a path that stays inside a zero-opacity run is exactly zero; one whose ends
  //    and middle lie in a run but whose extremum enters the spike is not.
  {
    TransferFunction runs;
    MakeRunsTransferFunction(runs);
    const Sizes sizes{ 64, 33, 17, 0.0, 0.0 };
    auto table = Build(runs, 0.0, 63.0, sizes, 2.0, 256, "empty runs");
    vtkFloatArray* coarse = table->GetEmptyRuns();
    bool runsOk = coarse->GetNumberOfTuples() == 63;
    for (int b = 0; b < 63 && runsOk; ++b)
    {
      const float expected = b < 34 ? 0.0f : b < 38 ? -1.0f : b < 50 ? 1.0f : -1.0f;
      runsOk = coarse->GetValue(b) == expected;
    }
    check(runsOk, "empty runs: spacings [0, 34] are run 0, [38, 50] run 1, the others -1");
    int zeros = 0, touching = 0;
    bool zerosOk = true, touchingOk = true;
    for (int k = 0; k < 17; ++k)
    {
      for (int j = 0; j < 33; ++j)
      {
        for (int i = 0; i < 64; ++i)
        {
          double lo, hi, rgba[4];
          const Quadratic p = EntryQuadratic(table, { i, j, k });
          p.Range(lo, hi);
          lo = std::max(lo, 0.0);
          hi = std::min(hi, 63.0);
          table->GetEntry(i, j, k, rgba);
          const double ends = std::max({ p(0.0), p(0.5), p(1.0) });
          if (hi <= 34.0 || (lo >= 38.0 && hi <= 50.0))
          {
            ++zeros;
            zerosOk =
              zerosOk && rgba[0] == 0.0 && rgba[1] == 0.0 && rgba[2] == 0.0 && rgba[3] == 0.0;
          }
          else if (ends <= 34.0 && lo >= 0.0 && hi >= 35.5)
          {
            ++touching;
            touchingOk = touchingOk && rgba[3] > 1e-4;
          }
        }
      }
    }
    std::cout << "Empty runs: " << zeros << " entries inside a zero-opacity run, " << touching
              << " reaching the spike only through their extremum\n";
    check(zeros > 1000 && zerosOk, "entries inside a zero-opacity run are exactly zero");
    check(touching > 10 && touchingOk, "entries whose extremum enters the spike are not zero");
  }

  //----------------------------------------------------------------------------
  // 9. The kernel integrates single entries exactly as the build does (bit for bit), the
  //    mirrored chords as the reversed path of their mirror: what the sizer measures is what
  //    the renderer reads.
  {
    const Sizes sizes{ 48, 21, 9, 0.0, 0.0 };
    auto table = Build(spiky, spikyRange[0], spikyRange[1], sizes, 1.3, 64, "kernel");
    const vtkSecondOrderPreIntegrationTableKernel kernel = table->GetKernel();
    const float* samples = table->GetIterationTable()->GetPointer(0);
    const float* runs = table->GetIterationEmptyRuns()->GetPointer(0);
    std::vector<float> steps;
    int mismatches = 0;
    for (const Entry& e : RandomEntries(sizes, 500, 21))
    {
      const int mirror = sizes.Chord - 1 - e.J;
      float forward[4], backward[4], entry[4];
      if (e.J <= mirror)
      {
        kernel.Integrate(e.I, e.J, e.K, samples, runs, steps, entry, nullptr);
      }
      else
      {
        kernel.Integrate(e.I, mirror, e.K, samples, runs, steps, forward, backward);
        std::copy(backward, backward + 4, entry);
      }
      double built[4];
      table->GetEntry(e.I, e.J, e.K, built);
      for (int c = 0; c < 4; ++c)
      {
        mismatches += static_cast<float>(built[c]) == entry[c] ? 0 : 1;
      }
    }
    check(mismatches == 0,
      "kernel entries equal the built ones bit for bit (" + std::to_string(mismatches) +
        " mismatches)");
  }

  //----------------------------------------------------------------------------
  // 10. First order: DeviationSize 1 holds linear paths (deviation 0), the first-order
  //     integral of a segment (front, back) over L.
  {
    const Sizes sizes{ 48, 31, 1, 0.0, 0.0 };
    auto table = Build(spiky, spikyRange[0], spikyRange[1], sizes, 1.3, 65536, "first order");
    double worstLinear = 0.0;
    std::vector<Entry> entries = RandomEntries(sizes, 300, 23);
    for (const Entry& e : entries)
    {
      worstLinear = std::max(worstLinear, std::abs(EntryQuadratic(table, e).A));
    }
    check(worstLinear == 0.0, "deviation 0: every path is linear");
    entries = InsideEntries(table, entries);
    const double error = LargestError(table, entries, References(table, spiky, entries));
    check.Near(error, 0.0, 2e-3, "first-order entries equal the brute force");
  }

  //----------------------------------------------------------------------------
  // 11. Prefilter (off by default): every entry integrates the transfer function box-averaged
  //     over one centre spacing, narrowing to nothing at the range ends. A narrow feature keeps
  //     its integral over scalar values (the sum of the constant slabs' optical depths).
  {
    const Sizes sizes{ 48, 5, 3, 0.0, 0.0 };
    auto table = Build(spiky,
      spikyRange[0],
      spikyRange[1],
      sizes,
      1.3,
      64,
      "prefiltered spiky transfer function",
      true);
    const double spacing = spikyWidth / 47.0;
    double worst = 0.0;
    for (int i = 1; i < 47; ++i)
    {
      double v[4], rgba[4];
      BoxAverage(spiky.Sampler, spikyRange[0] + spacing * i, 0.5 * spacing, v);
      const double alpha = -std::expm1(-v[3] * 1.3);
      table->GetEntry(i, 2, 1, rgba);
      worst = std::max(worst, std::abs(rgba[3] - alpha));
    }
    std::cout << "Prefilter: constant slabs against the box-averaged transfer function, largest "
              << "error " << worst << "\n";
    // Linear interpolation between iteration-table samples (16 per narrowest feature) under
    // the average: about 1e-4.
    check.Near(worst, 0.0, 5e-4, "prefiltered constant slab is exp(-L box average of tau)");
    vtkNew<vtkSecondOrderPreIntegrationTable> fresh;
    check(!fresh->GetPrefilter(), "the prefilter is off by default");
    const double offsets[3] = { 0.0, 0.25, 0.5 };
    double worstLoss = 0.0;
    for (double offset : offsets)
    {
      TransferFunction narrow;
      const double centre = 20.0 + offset; // range [0, 40], 41 centres: entry i at scalar i
      narrow.Color->AddRGBPoint(0.0, 1.0, 0.8, 0.2);
      narrow.Color->AddRGBPoint(40.0, 0.2, 0.4, 1.0);
      narrow.Opacity->AddPoint(centre - 0.1, 0.0);
      narrow.Opacity->AddPoint(centre, 0.6);
      narrow.Opacity->AddPoint(centre + 0.1, 0.0);
      narrow.SetUnit(1.0);
      double integral[4];
      BoxAverage(narrow.Sampler, 20.0, 20.0, integral);
      integral[3] *= 40.0;
      auto t = Build(narrow, 0.0, 40.0, { 41, 3, 3, 0.0, 0.0 }, 2.0, 16, "narrow feature", true);
      double sum = 0.0;
      for (int i = 0; i < 41; ++i)
      {
        double rgba[4];
        t->GetEntry(i, 1, 1, rgba);
        sum += -std::log1p(-rgba[3]) / 2.0;
      }
      worstLoss = std::max(worstLoss, std::abs(sum / integral[3] - 1.0));
    }
    check.Near(worstLoss, 0.0, 0.01, "prefiltered: a narrow feature keeps its integral");
  }

  //----------------------------------------------------------------------------
  // 12. Rebuilds: exactly one per change of something the table depends on, none otherwise.
  //     ComputeEntries off still counts a build and prepares the iteration table and the
  //     empty runs (for the GPU builder), leaving GetTable() empty.
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
    table->SetChordSize(9);
    table->SetDeviationSize(5);
    table->SetIterations(16);
    check(table->GetBuildCount() == 0, "no build before Update()");
    check(table->GetNumberOfDimensions() == 3, "second-order table is 3D");
    check(table->Update() && table->Update() && table->GetBuildCount() == 1,
      "Update() twice without change builds once");
    table->SetVolumeProperty(tf.Property);
    table->SetSegmentLength(table->GetSegmentLength());
    table->SetScalarRange(0.0, 1.0);
    table->SetTableSize(16);
    table->SetIterations(16);
    check(table->Update() && table->GetBuildCount() == 1, "unchanged values do not rebuild");
    int expected = 1;
    auto expectOneRebuild = [&](const char* what)
    {
      ++expected;
      const bool ok = table->Update() && table->Update();
      check(ok && table->GetBuildCount() == expected,
        std::string(what) + " triggers exactly one rebuild");
    };
    tf.Opacity->AddPoint(0.5, 0.2);
    expectOneRebuild("scalar opacity AddPoint");
    tf.Color->AddRGBPoint(0.5, 1.0, 1.0, 1.0);
    expectOneRebuild("colour AddRGBPoint");
    table->GetSampler()->SetScalarOpacityUnitDistance(0.25);
    expectOneRebuild("unit distance on the sampler");
    table->SetSegmentLength(1.0);
    expectOneRebuild("segment length");
    table->SetScalarRange(0.0, 2.0);
    expectOneRebuild("scalar range");
    table->SetTableSize(17);
    expectOneRebuild("table size");
    table->SetChordSize(11);
    expectOneRebuild("chord size");
    table->SetChordRange(0.5);
    expectOneRebuild("chord range");
    table->SetDeviationSize(7);
    expectOneRebuild("deviation size");
    table->SetDeviationRange(0.25);
    expectOneRebuild("deviation range");
    check(table->GetTable()->GetNumberOfTuples() == 17 * 11 * 7, "table resized");
    table->SetIterations(32);
    expectOneRebuild("Iterations");
    table->SetPrefilter(true);
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
    table->SetComputeEntries(true);
    expectOneRebuild("ComputeEntries back on");
    check(table->GetTable()->GetNumberOfTuples() == 17 * 11 * 7, "entries computed again");
  }

  //----------------------------------------------------------------------------
  // 12b. Incremental rebuilds: after an edit of the opacity at one node (the same iteration
  //      samples elsewhere), only the entries whose paths read a changed sample are
  //      integrated, and every entry equals, bit for bit, a table built from scratch; with
  //      shading moments and the prefilter too. A change of size, length or sampling density
  //      rebuilds every entry; so does a build after an aborted whole one.
  for (int variant = 0; variant < 3; ++variant)
  {
    const std::string name = variant == 0 ? "plain" : variant == 1 ? "slab moments" : "prefilter";
    TransferFunction tf;
    tf.Color->AddRGBPoint(0.0, 0.9, 0.2, 0.1);
    tf.Color->AddRGBPoint(63.0, 0.1, 0.6, 1.0);
    for (double x : { 0.0, 10.0, 20.0, 30.0, 40.0, 50.0, 63.0 })
    {
      tf.Opacity->AddPoint(x, x == 30.0 ? 0.8 : 0.2);
    }
    tf.SetUnit(1.0);
    const Sizes sizes{ 33, 17, 9, 20.0, 8.0 };
    auto table = Build(tf, 0.0, 63.0, sizes, 2.0, 64, "incremental " + name, variant == 2);
    if (variant == 1)
    {
      table->SetSlabMoments(2);
      check(table->Update(), "incremental " + name + ": moments built");
    }
    const vtkIdType all = table->GetNumberOfEntries();
    check(table->GetLastBuildEntries() == all, "incremental " + name + ": a first build is full");
    tf.Opacity->AddPoint(30.0, 0.4);
    check(table->Update(), "incremental " + name + ": rebuilt after the edit");
    const vtkIdType some = table->GetLastBuildEntries();
    check(some > 0 && some < all,
      "incremental " + name + ": an edit at one node integrates only the entries it reaches (" +
        std::to_string(some) + " of " + std::to_string(all) + ")");
    auto fresh = vtkSmartPointer<vtkSecondOrderPreIntegrationTable>::New();
    fresh->SetPrefilter(variant == 2);
    fresh->SetVolumeProperty(tf.Property);
    fresh->SetScalarRange(0.0, 63.0);
    fresh->SetTableSize(sizes.Centre);
    fresh->SetChordSize(sizes.Chord);
    fresh->SetDeviationSize(sizes.Deviation);
    fresh->SetChordRange(sizes.ChordRange);
    fresh->SetDeviationRange(sizes.DeviationRange);
    fresh->SetSegmentLength(2.0);
    fresh->SetIterations(64);
    fresh->SetSlabMoments(variant == 1 ? 2 : 0);
    check(fresh->Update(), "incremental " + name + ": the table from scratch");
    bool same = fresh->GetTable()->GetNumberOfValues() == table->GetTable()->GetNumberOfValues();
    for (vtkIdType v = 0; same && v < fresh->GetTable()->GetNumberOfValues(); ++v)
    {
      same = fresh->GetTable()->GetValue(v) == table->GetTable()->GetValue(v);
    }
    check(same, "incremental " + name + ": every entry equals the table from scratch");
    table->SetSegmentLength(2.5);
    check(table->Update() && table->GetLastBuildEntries() == all,
      "incremental " + name + ": a new length rebuilds every entry");
    table->SetChordSize(19);
    check(table->Update() && table->GetLastBuildEntries() == table->GetNumberOfEntries(),
      "incremental " + name + ": a new size rebuilds every entry");
  }
  {
    // An aborted build: a whole one leaves nothing to keep (the next build is full); an
    // incremental one keeps its entries, and the next build, after an edit that sets the
    // aborted one's change back and changes another node, integrates the entries either
    // reaches and equals a table from scratch (without the aborted build's samples it would
    // keep values of a transfer function no longer in use). TakeEntries() moves the entries to
    // another table of the same settings, whose next build is incremental in the same way.
    TransferFunction tf;
    tf.Color->AddRGBPoint(0.0, 0.9, 0.2, 0.1);
    tf.Color->AddRGBPoint(63.0, 0.1, 0.6, 1.0);
    for (double x : { 0.0, 10.0, 20.0, 30.0, 40.0, 50.0, 63.0 })
    {
      tf.Opacity->AddPoint(x, 0.3);
    }
    tf.SetUnit(1.0);
    const Sizes sizes{ 33, 17, 9, 20.0, 8.0 };
    auto configured = [&](vtkSecondOrderPreIntegrationTable* table)
    {
      table->SetVolumeProperty(tf.Property);
      table->SetScalarRange(0.0, 63.0);
      table->SetTableSize(sizes.Centre);
      table->SetChordSize(sizes.Chord);
      table->SetDeviationSize(sizes.Deviation);
      table->SetChordRange(sizes.ChordRange);
      table->SetDeviationRange(sizes.DeviationRange);
      table->SetSegmentLength(2.0);
      table->SetIterations(64);
    };
    auto sameAsFresh = [&](vtkSecondOrderPreIntegrationTable* table, const std::string& label)
    {
      vtkNew<vtkSecondOrderPreIntegrationTable> fresh;
      configured(fresh);
      check(fresh->Update(), label + ": the table from scratch");
      bool same = fresh->GetTable()->GetNumberOfValues() == table->GetTable()->GetNumberOfValues();
      for (vtkIdType v = 0; same && v < fresh->GetTable()->GetNumberOfValues(); ++v)
      {
        same = fresh->GetTable()->GetValue(v) == table->GetTable()->GetValue(v);
      }
      check(same, label + ": every entry equals the table from scratch");
    };
    vtkNew<vtkCallbackCommand> abort;
    abort->SetCallback([](vtkObject* caller, unsigned long, void*, void*)
      { static_cast<vtkPreIntegrationTable*>(caller)->SetAbortBuild(true); });
    auto abortedUpdate = [&](vtkSecondOrderPreIntegrationTable* table, const std::string& label)
    {
      const unsigned long tag = table->AddObserver(vtkCommand::ProgressEvent, abort);
      check(!table->Update(), label + ": the build is stopped");
      messages.TakeError("aborted");
      table->RemoveObserver(tag);
    };
    vtkNew<vtkSecondOrderPreIntegrationTable> table;
    configured(table);
    check(table->Update(), "abort: first build");
    const vtkIdType all = table->GetNumberOfEntries();
    tf.Opacity->AddPoint(20.0, 0.9);
    abortedUpdate(table, "abort, incremental");
    check(table->GetTable()->GetNumberOfTuples() == all, "abort, incremental: entries kept");
    tf.Opacity->AddPoint(20.0, 0.3);
    tf.Opacity->AddPoint(50.0, 0.6);
    check(table->Update(), "abort, incremental: rebuilt after a second edit");
    const vtkIdType some = table->GetLastBuildEntries();
    check(some > 0 && some < all,
      "abort, incremental: the next build integrates only what either edit reaches (" +
        std::to_string(some) + " of " + std::to_string(all) + ")");
    sameAsFresh(table, "abort, incremental");

    tf.Opacity->AddPoint(40.0, 0.5);
    vtkNew<vtkSecondOrderPreIntegrationTable> taker;
    configured(taker);
    check(taker->TakeEntries(table), "TakeEntries: a complete build at its settings is taken");
    check(table->GetTable()->GetNumberOfTuples() == 0, "TakeEntries: the other keeps none");
    check(taker->Update() && taker->GetLastBuildEntries() > 0 && taker->GetLastBuildEntries() < all,
      "TakeEntries: the taker's build integrates only what the edit reaches (" +
        std::to_string(taker->GetLastBuildEntries()) + " of " + std::to_string(all) + ")");
    sameAsFresh(taker, "TakeEntries");
    check(table->Update() && table->GetLastBuildEntries() == all,
      "TakeEntries: the other's next build integrates every entry");
    table->SetChordSize(19);
    check(!taker->TakeEntries(table) && table->GetTable()->GetNumberOfTuples() > 0,
      "TakeEntries: a build at other settings is not taken, and stays");
    messages.ExpectNone(check, "after TakeEntries");

    table->SetSegmentLength(2.5);
    abortedUpdate(table, "abort, whole");
    check(table->GetTable()->GetNumberOfTuples() == 0, "abort, whole: nothing kept");
    check(table->Update() && table->GetLastBuildEntries() == table->GetNumberOfEntries(),
      "abort, whole: the next build integrates every entry");
  }

  //----------------------------------------------------------------------------
  // 13. Invalid settings: Update() returns false with an error, and nothing is built.
  messages.ExpectNone(check, "before the invalid-settings checks");
  {
    TransferFunction tf;
    tf.Color->AddRGBPoint(0.0, 1.0, 1.0, 1.0);
    tf.Opacity->AddPoint(0.0, 0.5);
    tf.SetUnit(1.0);
    vtkNew<vtkSecondOrderPreIntegrationTable> table;
    table->SetTableSize(8);
    table->SetChordSize(5);
    table->SetDeviationSize(3);
    table->SetIterations(8);
    hovrTest::CheckInvalidTableSettings(
      check, messages, table.GetPointer(), tf.Property.GetPointer(), tf.Color.GetPointer(), 2.0);
  }

  messages.ExpectNone(check, "at the end of the test");
  return check.Result("TestSecondOrderPreIntegrationTable");
}
