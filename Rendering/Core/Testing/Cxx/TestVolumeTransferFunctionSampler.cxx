// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
// vtkVolumeTransferFunctionSampler reproduces VTK's transfer-function semantics exactly and
// turns opacity per unit distance into extinction.
#include "vtkColorTransferFunction.h"
#include "vtkMinimalStandardRandomSequence.h"
#include "vtkNew.h"
#include "vtkPiecewiseFunction.h"
#include "vtkVolumeProperty.h"
#include "vtkVolumeTransferFunctionSampler.h"

#include <algorithm>
#include <cmath>
#include <iostream>
#include <vector>

namespace
{
int failures = 0;
void Check(bool ok, const char* what)
{
  if (!ok)
  {
    std::cerr << "Failed: " << what << "\n";
    ++failures;
  }
}
}

int TestVolumeTransferFunctionSampler(int, char*[])
{
  // Random functions with midpoints and sharpness: evaluation must match VTK's own to 1e-12.
  vtkNew<vtkMinimalStandardRandomSequence> random;
  random->SetSeed(7);
  auto next = [&]()
  {
    random->Next();
    return random->GetValue();
  };
  for (int trial = 0; trial < 20; ++trial)
  {
    vtkNew<vtkColorTransferFunction> color;
    vtkNew<vtkPiecewiseFunction> opacity;
    double x = 0.0;
    for (int n = 0; n < 6; ++n)
    {
      x += 0.5 + 10.0 * next();
      const double sharpness = trial % 3 == 0 ? 0.0 : next();
      const double midpoint = 0.05 + 0.9 * next();
      color->AddRGBPoint(x, next(), next(), next(), midpoint, sharpness);
      opacity->AddPoint(x + 0.3, 0.99 * next(), midpoint, sharpness);
    }
    vtkNew<vtkVolumeTransferFunctionSampler> sampler;
    sampler->SetColor(color);
    sampler->SetScalarOpacity(opacity);
    sampler->SetScalarOpacityUnitDistance(2.5);
    Check(sampler->Prepare(), "Prepare with valid functions");
    for (int i = 0; i <= 400; ++i)
    {
      const double s = -5.0 + (x + 10.0) * i / 400.0;
      double rgbTau[4], rgb[3];
      sampler->Evaluate(s, rgbTau);
      color->GetColor(s, rgb);
      const double alpha = opacity->GetValue(s);
      Check(std::abs(rgbTau[0] - rgb[0]) < 1e-12 && std::abs(rgbTau[1] - rgb[1]) < 1e-12 &&
          std::abs(rgbTau[2] - rgb[2]) < 1e-12,
        "colour equals vtkColorTransferFunction::GetColor");
      Check(std::abs(sampler->EvaluateOpacity(s) - alpha) < 1e-12,
        "opacity equals vtkPiecewiseFunction::GetValue");
      Check(std::abs(rgbTau[3] - (-std::log(1.0 - alpha) / 2.5)) < 1e-9,
        "extinction is -ln(1 - alpha) / U");
    }
    // The maximum over an interval is attained at an end or a node.
    for (int i = 0; i < 50; ++i)
    {
      const double a = x * next(), b = x * next();
      double brute = 0.0;
      for (int k = 0; k <= 2000; ++k)
      {
        brute =
          std::max(brute, sampler->EvaluateOpacity(std::min(a, b) + std::abs(b - a) * k / 2000.0));
      }
      Check(sampler->GetMaximumOpacity(a, b) >= brute - 1e-15, "maximum opacity bounds samples");
    }
  }

  // Colour spaces other than RGB (random nodes, midpoints and sharpness): the colour follows
  // vtkColorTransferFunction's table everywhere, and the smallest feature stays that of the
  // function's own nodes.
  for (int space = VTK_CTF_HSV; space <= VTK_CTF_STEP; ++space)
  {
    for (int trial = 0; trial < 5; ++trial)
    {
      vtkNew<vtkColorTransferFunction> color;
      color->SetColorSpace(space);
      double x = 0.0;
      for (int n = 0; n < 5; ++n)
      {
        x += 0.5 + 10.0 * next();
        const double sharpness = trial % 2 == 0 ? 0.0 : 0.8 * next();
        color->AddRGBPoint(x, next(), next(), next(), 0.1 + 0.8 * next(), sharpness);
      }
      vtkNew<vtkPiecewiseFunction> opacity;
      double first[6];
      color->GetNodeValue(0, first);
      opacity->AddPoint(first[0], 0.5); // adds no gap of its own
      vtkNew<vtkVolumeTransferFunctionSampler> sampler;
      sampler->SetColor(color);
      sampler->SetScalarOpacity(opacity);
      Check(sampler->Prepare(), "Prepare in another colour space");
      // VTK's colours in one call over the nodes' range (CIEDE2000 computes its path once
      // per call, for the range asked for).
      const int samples = 16385;
      std::vector<double> table(3 * samples);
      double range[2];
      color->GetRange(range);
      color->GetTable(range[0], range[1], samples, table.data());
      double worst = 0.0;
      for (int i = 0; i < samples; ++i)
      {
        const double s = range[0] + (range[1] - range[0]) * i / (samples - 1.0);
        double rgbTau[4];
        sampler->Evaluate(s, rgbTau);
        for (int c = 0; c < 3; ++c)
        {
          worst = std::max(worst, std::abs(rgbTau[c] - table[3 * i + c]));
        }
      }
      // A tenth of a 1/255 colour level: the curve's pieces meet VTK's colours at their
      // ends and midpoints, and stray a little where clamping to [0, 1] bends the curve.
      // CIEDE2000's path is computed per table, of steps finer than the curve's pieces: there
      // the curve is followed to 0.03.
      const double tolerance =
        space == VTK_CTF_STEP ? 1e-12 : (space == VTK_CTF_LAB_CIEDE2000 ? 0.03 : 4e-4);
      if (!(worst < tolerance))
      {
        std::cerr << "colour space " << space << ", trial " << trial << ": " << worst << "\n";
      }
      Check(worst < tolerance, "colour follows VTK's in its colour space");
      double smallest = VTK_DOUBLE_MAX;
      for (int n = 1; n < color->GetSize(); ++n)
      {
        double a[6], b[6];
        color->GetNodeValue(n - 1, a);
        color->GetNodeValue(n, b);
        smallest = std::min(smallest, b[0] - a[0]);
      }
      Check(std::abs(sampler->GetSmallestFeature() - smallest) < 1e-12,
        "the smallest feature is that of the nodes, not of the refined curve");
    }
  }

  // Opacity 1 stays finite, NaN is transparent, errors are reported.
  vtkNew<vtkColorTransferFunction> color;
  color->AddRGBPoint(0.0, 1.0, 0.5, 0.25);
  vtkNew<vtkPiecewiseFunction> opacity;
  opacity->AddPoint(0.0, 1.0);
  vtkNew<vtkVolumeProperty> property;
  property->SetColor(color);
  property->SetScalarOpacity(opacity);
  property->SetScalarOpacityUnitDistance(0.5);
  vtkNew<vtkVolumeTransferFunctionSampler> sampler;
  sampler->SetFromVolumeProperty(property);
  Check(sampler->Prepare(), "Prepare from a volume property");
  double rgbTau[4];
  sampler->Evaluate(3.0, rgbTau);
  Check(std::isfinite(rgbTau[3]) && std::abs(rgbTau[3] - (-std::log(1e-9) / 0.5)) < 1e-6,
    "opacity 1 gives the capped finite extinction");
  sampler->Evaluate(std::nan(""), rgbTau);
  Check(rgbTau[0] == 0 && rgbTau[1] == 0 && rgbTau[2] == 0 && rgbTau[3] == 0,
    "NaN scalar is transparent black");
  Check(sampler->GetSmallestFeature() == VTK_DOUBLE_MAX, "no feature with single nodes");

  // A grey colour function gives grey colours with VTK's values; errors of the sampler reach
  // observers of the object that owns it (here: a pre-integration table).
  vtkNew<vtkPiecewiseFunction> gray;
  gray->AddPoint(0.0, 0.2);
  gray->AddPoint(10.0, 0.9, 0.3, 0.4);
  vtkNew<vtkVolumeProperty> grayProperty;
  grayProperty->SetColor(gray);
  grayProperty->SetScalarOpacity(opacity);
  sampler->SetFromVolumeProperty(grayProperty);
  Check(sampler->Prepare(), "Prepare with a grey colour function");
  for (double s = -1.0; s <= 11.0; s += 0.37)
  {
    sampler->Evaluate(s, rgbTau);
    const double g = gray->GetValue(s);
    Check(std::abs(rgbTau[0] - g) < 1e-12 && rgbTau[1] == rgbTau[0] && rgbTau[2] == rgbTau[0],
      "grey colour equals vtkPiecewiseFunction::GetValue on all channels");
  }

  // Edits: outside GetChangedRange() every query answers as before the edit; a colour edit
  // leaves colours a weighting of the colour nodes.
  for (int trial = 0; trial < 20; ++trial)
  {
    vtkNew<vtkColorTransferFunction> color;
    vtkNew<vtkPiecewiseFunction> alpha;
    for (int k = 0; k < 6; ++k)
    {
      const double x = 10.0 * k + 8.0 * next();
      color->AddRGBPoint(x, next(), next(), next());
      alpha->AddPoint(x + 3.0 * next(), next(), 0.2 + 0.6 * next(), next() < 0.5 ? 0.0 : next());
    }
    vtkNew<vtkVolumeTransferFunctionSampler> edited, before;
    edited->SetColor(color);
    edited->SetScalarOpacity(alpha);
    edited->SetScalarOpacityUnitDistance(0.7);
    Check(edited->Prepare() && before->DeepCopy(edited), "a deep copy prepares");
    double changed[2];
    edited->GetChangedRange(before, changed);
    Check(changed[0] > changed[1], "nothing changed: an empty changed range");
    Check(edited->IsColorEditOf(before), "the same functions are a colour edit");
    // One opacity node's value (or its position, between its neighbours) changes.
    const int node = static_cast<int>(next() * 6) % 6;
    double values[4];
    alpha->GetNodeValue(node, values);
    const bool move = trial % 2 == 1 && node > 0 && node < 5;
    if (move)
    {
      double low[4], high[4];
      alpha->GetNodeValue(node - 1, low);
      alpha->GetNodeValue(node + 1, high);
      values[0] = low[0] + (high[0] - low[0]) * (0.1 + 0.8 * next());
    }
    else
    {
      values[1] = next();
    }
    alpha->SetNodeValue(node, values);
    Check(edited->Prepare(), "Prepare after an edit");
    edited->GetChangedRange(before, changed);
    Check(changed[0] <= values[0] && values[0] <= changed[1], "the edited node is changed");
    Check(!edited->IsColorEditOf(before), "an opacity edit is not a colour edit");
    int outside = 0;
    for (int q = 0; q < 400; ++q)
    {
      const double a = -10.0 + 80.0 * next(), b = a + 6.0 * next() * next();
      if (!(b < changed[0] || a > changed[1]))
      {
        continue;
      }
      ++outside;
      double e[4], f[4];
      edited->Evaluate(a, e);
      before->Evaluate(a, f);
      const double cap = b - a;
      const double s = a + 0.5 * cap;
      Check(e[0] == f[0] && e[1] == f[1] && e[2] == f[2] && e[3] == f[3] &&
          edited->GetMaximumOpacity(a, b) == before->GetMaximumOpacity(a, b) &&
          edited->GetSmallestFeature(a, b) == before->GetSmallestFeature(a, b) &&
          edited->GetLongestSweep(s, 1.0 / 64.0, 70.0, 0.5 * cap) ==
            before->GetLongestSweep(s, 1.0 / 64.0, 70.0, 0.5 * cap),
        "outside the changed range, queries answer as before the edit");
    }
    Check(outside > 0, "some queries lie outside the changed range");
    // A node more: everything changed.
    alpha->AddPoint(75.0, 0.5);
    edited->Prepare();
    edited->GetChangedRange(before, changed);
    Check(std::isinf(changed[0]) && std::isinf(changed[1]), "a new node changes everything");
    alpha->RemovePoint(75.0);
    alpha->GetNodeValue(node, values);
    // The opacity as before, a colour node's colour edited: a colour edit, whose colours are
    // the colour nodes weighted by GetColorWeights().
    double old[4];
    before->GetScalarOpacity()->GetNodeValue(node, old);
    alpha->SetNodeValue(node, old);
    double rgb[6];
    color->GetNodeValue(node, rgb);
    rgb[1] = next();
    rgb[3] = next();
    color->SetNodeValue(node, rgb);
    edited->Prepare();
    Check(edited->IsColorEditOf(before), "a colour edit is one");
    const int n = edited->GetNumberOfColorNodes();
    std::vector<double> weights(n);
    double worst = 0.0;
    for (int q = 0; q < 200; ++q)
    {
      const double s = -10.0 + 80.0 * next();
      double w[2], e[4], combined[3];
      std::fill(weights.begin(), weights.end(), 0.0);
      const int k = edited->GetColorWeights(s, w);
      weights[k] += w[0];
      weights[std::min(k + 1, n - 1)] += w[1];
      edited->CombineColors(weights.data(), combined);
      edited->Evaluate(s, e);
      for (int c = 0; c < 3; ++c)
      {
        worst = std::max(worst, std::abs(combined[c] - e[c]));
      }
    }
    Check(worst < 1e-12, "colours are their nodes weighted by GetColorWeights");
    // A colour node whose curve is not linear in the colours: no colour edit.
    color->GetNodeValue(node, rgb);
    rgb[5] = 0.5;
    color->SetNodeValue(node, rgb);
    edited->Prepare();
    Check(!edited->IsColorEditOf(before), "a sharpness of 0.5 is no colour edit");
  }

  if (failures)
  {
    std::cerr << failures << " checks failed\n";
    return 1;
  }
  return 0;
}
