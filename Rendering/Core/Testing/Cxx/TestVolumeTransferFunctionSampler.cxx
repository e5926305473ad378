// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
// vtkVolumeTransferFunctionSampler reproduces VTK's transfer-function semantics exactly and
// turns opacity per unit distance into extinction.
#include "vtkColorTransferFunction.h"
#include "vtkMinimalStandardRandomSequence.h"
#include "vtkNew.h"
#include "vtkPiecewiseFunction.h"
#include "vtkVolumeProperty.h"
#include "vtkVolumeTransferFunctionSampler.h"

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

  if (failures)
  {
    std::cerr << failures << " checks failed\n";
    return 1;
  }
  return 0;
}
