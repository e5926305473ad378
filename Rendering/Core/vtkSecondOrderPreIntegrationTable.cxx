// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
#include "vtkSecondOrderPreIntegrationTable.h"

#include "vtkFloatArray.h"
#include "vtkObjectFactory.h"
#include "vtkSMPTools.h"
#include "vtkVolumeTransferFunctionSampler.h"

#include <algorithm>
#include <cmath>
#include <vector>

vtkStandardNewMacro(vtkSecondOrderPreIntegrationTable);

//------------------------------------------------------------------------------
vtkSecondOrderPreIntegrationTable::vtkSecondOrderPreIntegrationTable()
  : IterationTable(vtkFloatArray::New())
  , IterationEmptyRuns(vtkFloatArray::New())
  , DiagonalTable(vtkFloatArray::New())
{
  this->DiagonalTable->SetNumberOfComponents(4);
  this->IterationTable->SetNumberOfComponents(4);
  this->SegmentLength = 2.0;
}

//------------------------------------------------------------------------------
vtkSecondOrderPreIntegrationTable::~vtkSecondOrderPreIntegrationTable()
{
  this->IterationTable->Delete();
  this->IterationEmptyRuns->Delete();
  this->DiagonalTable->Delete();
}

//------------------------------------------------------------------------------
void vtkSecondOrderPreIntegrationTable::BuildIterationTable()
{
  const int n = this->TableSize;
  const double width = this->ScalarRange[1] - this->ScalarRange[0];
  const double tableSpacing = width / (n - 1);
  const double feature = this->Sampler->GetSmallestFeature();
  const double wanted = std::ceil(16.0 * tableSpacing / feature);
  // Even, so that the prefilter's box ends fall on samples; Fine - 1 <= 65536.
  this->IterationSamplesPerSpacing = 2 *
    static_cast<int>(
      std::max(4.0, std::min(std::ceil(0.5 * wanted), std::floor(32768.0 / (n - 1)))));
  const int p = this->IterationSamplesPerSpacing;
  const int fine = p * (n - 1) + 1; // entry i at sample p i
  const double s0 = this->ScalarRange[0];
  const double spacing = width / (fine - 1);
  // The last sample exactly at ScalarRange[1]: s0 + (fine - 1) spacing can miss it by a
  // rounding error, which matters for a transfer-function step at the range end.
  const double s1 = this->ScalarRange[1];
  const double top = fine - 1.0;
  auto scalar = [&](double x) { return x >= top ? s1 : s0 + x * spacing; };

  // Extinction and extinction-weighted colour at the samples, and (prefiltered) their box
  // averages over one local entry spacing.
  std::vector<double> point(4 * static_cast<size_t>(fine));
  for (int q = 0; q < fine; ++q)
  {
    double rgbTau[4];
    this->Sampler->Evaluate(scalar(q), rgbTau);
    for (int c = 0; c < 3; ++c)
    {
      point[4 * q + c] = rgbTau[c] * rgbTau[3];
    }
    point[4 * q + 3] = rgbTau[3];
  }
  // Half an entry spacing, in samples: the half-width of the box filter.
  const int halfWidth = this->Prefilter ? p / 2 : 0;
  std::vector<double> filtered;
  if (this->Prefilter)
  {
    // Integral from sample 0 to each sample, by Simpson's rule on Panels panels per spacing:
    // the extinction curves sharply where the opacity nears 1 and kinks at the transfer
    // function's nodes, which the samples alone would integrate coarsely. p is even, so the
    // box ends q +- p / 2 fall on samples.
    constexpr int Panels = 4;
    std::vector<double> integral(4 * static_cast<size_t>(fine), 0.0);
    for (int q = 1; q < fine; ++q)
    {
      double sum[4] = { 0.0, 0.0, 0.0, 0.0 };
      for (int m = 0; m <= 2 * Panels; ++m)
      {
        const double weight = m == 0 || m == 2 * Panels ? 1.0 : m % 2 ? 4.0 : 2.0;
        const double* v = nullptr;
        double rgbTau[4], inner[4];
        if (m == 0 || m == 2 * Panels)
        {
          v = &point[4 * (m == 0 ? q - 1 : q)];
        }
        else
        {
          this->Sampler->Evaluate(scalar(q - 1 + 0.5 * m / Panels), rgbTau);
          for (int c = 0; c < 3; ++c)
          {
            inner[c] = rgbTau[c] * rgbTau[3];
          }
          inner[3] = rgbTau[3];
          v = inner;
        }
        for (int c = 0; c < 4; ++c)
        {
          sum[c] += weight * v[c];
        }
      }
      for (int c = 0; c < 4; ++c)
      {
        integral[4 * q + c] = integral[4 * (q - 1) + c] + sum[c] / (6.0 * Panels);
      }
    }
    filtered.resize(point.size());
    for (int q = 0; q < fine; ++q)
    {
      // Centred, and narrowing to nothing at the range ends: data exactly at an end (often
      // saturated or clamped values) keeps that end's exact transfer function.
      const int h = std::min(halfWidth, std::min(q, fine - 1 - q));
      for (int c = 0; c < 4; ++c)
      {
        filtered[4 * q + c] = h > 0
          ? (integral[4 * (q + h) + c] - integral[4 * (q - h) + c]) / (2.0 * h)
          : point[4 * q + c];
      }
    }
  }
  const std::vector<double>& values = this->Prefilter ? filtered : point;

  // One integration step, and a whole slab of constant scalar (the exact exponential).
  auto slab = [&](const double* v, double length, float* out)
  {
    const double alpha = -std::expm1(-v[3] * length);
    const double scale = v[3] > 0.0 ? alpha / v[3] : 0.0; // colour = v[c] / tau
    for (int c = 0; c < 3; ++c)
    {
      out[c] = static_cast<float>(v[c] * scale);
    }
    out[3] = static_cast<float>(alpha);
  };
  const double step = this->SegmentLength / this->Iterations;
  this->IterationTable->SetNumberOfTuples(fine);
  float* steps = this->IterationTable->GetPointer(0);
  for (int q = 0; q < fine; ++q)
  {
    slab(&values[4 * q], step, steps + 4 * q);
  }
  this->DiagonalTable->SetNumberOfTuples(n);
  for (int i = 0; i < n; ++i)
  {
    double v[4];
    if (this->Prefilter)
    {
      std::copy(&filtered[4 * p * i], &filtered[4 * p * i] + 4, v);
    }
    else
    {
      // The exact scalar of the entry, the last one exactly at the range end.
      double rgbTau[4];
      this->Sampler->Evaluate(scalar(static_cast<double>(p) * i), rgbTau);
      for (int c = 0; c < 3; ++c)
      {
        v[c] = rgbTau[c] * rgbTau[3];
      }
      v[3] = rgbTau[3];
    }
    slab(v, this->SegmentLength, this->DiagonalTable->GetPointer(4 * i));
  }

  // Zero-opacity runs of the (filtered) iteration table: a spacing is empty when the transfer
  // function has no opacity within half an entry spacing of it.
  this->IterationEmptyRuns->SetNumberOfTuples(fine - 1);
  int run = -1;
  bool inRun = false;
  for (int q = 0; q < fine - 1; ++q)
  {
    const bool empty = this->Sampler->GetMaximumOpacity(scalar(std::max(q - halfWidth, 0)),
                         scalar(std::min(q + 1 + halfWidth, fine - 1))) <= 0.0;
    run += empty && !inRun ? 1 : 0;
    inRun = empty;
    this->IterationEmptyRuns->SetValue(q, empty ? static_cast<float>(run) : -1.0f);
  }
}

//------------------------------------------------------------------------------
namespace
{
// Integrates the slabs (front, middle, back) and (back, middle, front) of one table. The two
// follow the same scalar path in opposite directions: they share the iteration-table lookups
// (the costly part) and differ only in the order of compositing.
class SlabIntegrator
{
public:
  int N;
  int PerSpacing; // iteration-table samples per entry spacing: entry i at sample PerSpacing i
  const float* Diagonal; // constant-scalar slab of each entry
  int Fine;
  int Iterations;
  const float* Steps;
  const float* Runs;
  float* Table;

  float* Entry(int front, int middle, int back) const
  {
    return this->Table + 4 * (front + static_cast<vtkIdType>(this->N) * (middle + this->N * back));
  }

  static constexpr int Lanes = 4;

  // Scratch memory of one task.
  struct Scratch
  {
    std::vector<float> X, W, Steps;
    std::vector<int> Q;
  };

  // Integrates, both ways, the slabs of up to Lanes fronts sharing middle j and back k. The
  // compositing loops carry one multiplication chain per lane and direction; interleaving them
  // keeps the processor busy instead of waiting on one chain.
  void IntegrateBatch(const int* fronts, int count, int j, int k, Scratch& scratch) const
  {
    const int n = this->Iterations;
    const float h = 1.0f / n;
    const float top = static_cast<float>(this->Fine - 1);
    for (int lane = 0; lane < count; ++lane)
    {
      // Eq. 2 in units of iteration-table samples; P(t) by Horner's rule in float, as the
      // GPU builder does. The loops are split so that the first two vectorise.
      const float xf = static_cast<float>(this->PerSpacing * fronts[lane]);
      const float xm = static_cast<float>(this->PerSpacing * j);
      const float xb = static_cast<float>(this->PerSpacing * k);
      const float a = 2.0f * xf - 4.0f * xm + 2.0f * xb;
      const float b = -3.0f * xf + 4.0f * xm - xb;
      float* x = scratch.X.data();
      float* w = scratch.W.data();
      int* q = scratch.Q.data();
      for (int it = 0; it < n; ++it)
      {
        const float t = (it + 0.5f) * h;
        x[it] = std::min(std::max(xf + t * (b + a * t), 0.0f), top);
      }
      for (int it = 0; it < n; ++it)
      {
        const int qi = static_cast<int>(x[it]);
        q[it] = qi < this->Fine - 2 ? qi : this->Fine - 2;
        w[it] = x[it] - static_cast<float>(q[it]);
      }
      float* step = scratch.Steps.data() + 4 * n * lane;
      for (int it = 0; it < n; ++it)
      {
        const float* v = this->Steps + 4 * q[it];
        for (int c = 0; c < 4; ++c)
        {
          step[4 * it + c] = v[c] + w[it] * (v[c + 4] - v[c]);
        }
      }
    }
    // Front to back: RGBA += T (c a, a), T *= 1 - a. Alpha is accumulated like the colour,
    // not taken as 1 - T: in float 1 - a is a multiple of 2^-24, so T would drop steps with
    // a below 3e-8 and distort those below ~1e-5 (thin media, short slabs) while their colour
    // still counted.
    float f[Lanes][4], g[Lanes][4], tf[Lanes], tg[Lanes];
    for (int lane = 0; lane < Lanes; ++lane)
    {
      std::fill(f[lane], f[lane] + 4, 0.0f);
      std::fill(g[lane], g[lane] + 4, 0.0f);
      tf[lane] = tg[lane] = 1.0f;
    }
    const float* steps = scratch.Steps.data();
    for (int it = 0; it < n; ++it)
    {
      for (int lane = 0; lane < count; ++lane)
      {
        const float* u = steps + 4 * (n * lane + it);
        const float* v = steps + 4 * (n * lane + n - 1 - it);
        for (int c = 0; c < 4; ++c)
        {
          f[lane][c] += tf[lane] * u[c];
          g[lane][c] += tg[lane] * v[c];
        }
        tf[lane] *= 1.0f - u[3];
        tg[lane] *= 1.0f - v[3];
      }
    }
    for (int lane = 0; lane < count; ++lane)
    {
      float* forward = this->Entry(fronts[lane], j, k);
      float* backward = this->Entry(k, j, fronts[lane]);
      for (int c = 0; c < 3; ++c)
      {
        forward[c] = f[lane][c];
        backward[c] = g[lane][c];
      }
      forward[3] = std::min(f[lane][3], 1.0f); // sum of T a: 1 at most, up to rounding
      backward[3] = std::min(g[lane][3], 1.0f);
    }
  }

  void operator()(vtkIdType kBegin, vtkIdType kEnd) const
  {
    Scratch scratch;
    scratch.X.resize(this->Iterations);
    scratch.W.resize(this->Iterations);
    scratch.Q.resize(this->Iterations);
    scratch.Steps.resize(4 * this->Iterations * Lanes);
    for (vtkIdType kk = kBegin; kk < kEnd; ++kk)
    {
      const int k = static_cast<int>(kk);
      for (int j = 0; j < this->N; ++j)
      {
        int batch[Lanes];
        int pending = 0;
        for (int i = 0; i <= k; ++i)
        {
          float* forward = this->Entry(i, j, k);
          float* backward = this->Entry(k, j, i);
          // The range of P over [0, 1]: its ends, and its extremum when inside.
          const double xf = this->PerSpacing * i, xm = this->PerSpacing * j;
          const double xb = this->PerSpacing * k;
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
          hi = std::min(hi, this->Fine - 1.0);
          if (hi == lo)
          {
            // Constant scalar (the table diagonal, or clamped to a range end): the exact
            // exponential.
            const float* v = this->Diagonal +
              4 *
                (lo <= 0.0                   ? 0
                    : lo >= this->Fine - 1.0 ? this->N - 1
                                             : i);
            std::copy(v, v + 4, forward);
            std::copy(v, v + 4, backward);
            continue;
          }
          const int qlo = std::min(static_cast<int>(lo), this->Fine - 2);
          const int qhi = std::min(static_cast<int>(hi), this->Fine - 2);
          if (this->Runs[qlo] >= 0.0f && this->Runs[qlo] == this->Runs[qhi])
          {
            std::fill(forward, forward + 4, 0.0f); // inside one zero-opacity run
            std::fill(backward, backward + 4, 0.0f);
            continue;
          }
          batch[pending++] = i;
          if (pending == Lanes)
          {
            this->IntegrateBatch(batch, pending, j, k, scratch);
            pending = 0;
          }
        }
        if (pending > 0)
        {
          this->IntegrateBatch(batch, pending, j, k, scratch);
        }
      }
    }
  }
};
}

//------------------------------------------------------------------------------
void vtkSecondOrderPreIntegrationTable::BuildTable()
{
  this->BuildIterationTable();
  if (!this->ComputeEntries)
  {
    return; // another builder (the GPU) integrates from the iteration table
  }
  SlabIntegrator integrator;
  integrator.N = this->TableSize;
  integrator.PerSpacing = this->IterationSamplesPerSpacing;
  integrator.Diagonal = this->DiagonalTable->GetPointer(0);
  integrator.Fine = this->IterationTable->GetNumberOfTuples();
  integrator.Iterations = this->Iterations;
  integrator.Steps = this->IterationTable->GetPointer(0);
  integrator.Runs = this->IterationEmptyRuns->GetPointer(0);
  integrator.Table = this->Table->GetPointer(0);
  // Slice k integrates k + 1 pairs: many small tasks keep both cores busy.
  vtkSMPTools::For(0, this->TableSize, 1, integrator);
}

//------------------------------------------------------------------------------
double vtkSecondOrderPreIntegrationTable::GetEmptyRunMargin() const
{
  return this->Prefilter
    ? 0.5 * (this->ScalarRange[1] - this->ScalarRange[0]) / (this->TableSize - 1)
    : 0.0;
}

//------------------------------------------------------------------------------
void vtkSecondOrderPreIntegrationTable::GetEntry(int front, int middle, int back, double rgba[4])
{
  const vtkIdType n = this->TableSize;
  const vtkIdType index = front + n * (middle + n * back);
  for (int c = 0; c < 4; ++c)
  {
    rgba[c] = this->Table->GetTypedComponent(index, c);
  }
}

//------------------------------------------------------------------------------
void vtkSecondOrderPreIntegrationTable::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Iterations: " << this->Iterations << "\n";
  os << indent << "Prefilter: " << (this->Prefilter ? "On" : "Off") << "\n";
}
