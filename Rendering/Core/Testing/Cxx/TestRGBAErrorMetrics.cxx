// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
// vtkRGBAErrorMetrics on images with known differences (exact with dyadic values), the
// difference image, another array name and type, and the failure modes (metrics -1).
#include "vtkFloatArray.h"
#include "vtkImageData.h"
#include "vtkMinimalStandardRandomSequence.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkRGBAErrorMetrics.h"
#include "vtkUnsignedCharArray.h"

#include "hovrTestUtilities.h"

#include <cmath>
#include <string>

namespace
{
hovrTest::Checker check;

// Every value below is a multiple of 1/256 below 2, so differences, squares and sums of up to
// a few hundred squares are exact in double; only the final square root rounds. 1e-15 is a
// few ulps of the results.
constexpr double Exact = 1e-15;

vtkNew<vtkImageData> MakeImage(int w, int h, const char* name, int components = 4)
{
  vtkNew<vtkImageData> image;
  image->SetDimensions(w, h, 1);
  vtkNew<vtkFloatArray> rgba;
  rgba->SetName(name);
  rgba->SetNumberOfComponents(components);
  rgba->SetNumberOfTuples(static_cast<vtkIdType>(w) * h);
  rgba->FillValue(0.0f);
  image->GetPointData()->SetScalars(rgba);
  return image;
}

void CheckFailed(vtkRGBAErrorMetrics* metrics, const std::string& what)
{
  bool all = metrics->GetRMSE() == -1.0 && metrics->GetMaximumError() == -1.0;
  for (int c = 0; c < 4; ++c)
  {
    all = all && metrics->GetChannelRMSE(c) == -1.0 && metrics->GetChannelMaximumError(c) == -1.0;
  }
  check(all, what + ": every metric is -1");
}
}

int TestRGBAErrorMetrics(int, char*[])
{
  hovrTest::MessageCapture messages;
  const int w = 8, h = 6, n = w * h;
  auto test = MakeImage(w, h, "RGBA");
  auto reference = MakeImage(w, h, "RGBA");
  vtkDataArray* a = test->GetPointData()->GetScalars();
  vtkDataArray* b = reference->GetPointData()->GetScalars();
  vtkNew<vtkMinimalStandardRandomSequence> random;
  random->SetSeed(3);
  for (vtkIdType i = 0; i < n; ++i)
  {
    for (int c = 0; c < 4; ++c)
    {
      random->Next();
      const double v = std::floor(192.0 * random->GetValue()) / 256.0;
      a->SetComponent(i, c, v);
      b->SetComponent(i, c, v);
    }
  }

  vtkNew<vtkRGBAErrorMetrics> metrics;
  metrics->SetInputData(test);
  metrics->SetReferenceData(reference);
  CheckFailed(metrics, "before any update");

  // Identical images: all zero.
  metrics->Update();
  check(
    metrics->GetRMSE() == 0.0 && metrics->GetMaximumError() == 0.0, "identical images: 0 error");

  // A constant offset of 1/8 in red only: red RMSE and maximum 1/8, other channels 0, overall
  // RMSE sqrt((1/8)^2 / 4) = 1/16 (half the offset: one channel in four).
  const double offset = 0.125;
  for (vtkIdType i = 0; i < n; ++i)
  {
    b->SetComponent(i, 0, a->GetComponent(i, 0) + offset);
  }
  reference->Modified();
  metrics->Update();
  check.Near(metrics->GetChannelRMSE(0), offset, Exact, "red RMSE equals the offset");
  check.Near(metrics->GetChannelMaximumError(0), offset, Exact, "red maximum equals the offset");
  for (int c = 1; c < 4; ++c)
  {
    check(metrics->GetChannelRMSE(c) == 0.0 && metrics->GetChannelMaximumError(c) == 0.0,
      "untouched channel " + std::to_string(c) + " has 0 error");
  }
  check.Near(metrics->GetRMSE(), offset / 2.0, Exact, "overall RMSE is offset / 2");
  check.Near(metrics->GetMaximumError(), offset, Exact, "maximum error is the offset");
  check(metrics->GetChannelRMSE(4) == -1.0 && metrics->GetChannelRMSE(-1) == -1.0,
    "channel outside 0..3 gives -1");

  // Plus one green outlier of 1/2 at pixel (5, 1), and the reference brighter in blue by
  // 1/4 at pixel 0 while the test is brighter in alpha by 3/8 there (absolute differences).
  const vtkIdType outlier = 5 + 1 * w;
  b->SetComponent(outlier, 1, a->GetComponent(outlier, 1) + 0.5);
  b->SetComponent(0, 2, a->GetComponent(0, 2) + 0.25);
  b->SetComponent(0, 3, a->GetComponent(0, 3) - 0.375);
  reference->Modified();
  metrics->Update();
  check.Near(metrics->GetChannelRMSE(1), std::sqrt(0.25 / n), Exact, "green RMSE sqrt(0.5^2 / n)");
  check.Near(
    metrics->GetChannelRMSE(2), std::sqrt(0.0625 / n), Exact, "blue RMSE sqrt(0.25^2 / n)");
  check.Near(
    metrics->GetChannelRMSE(3), std::sqrt(0.140625 / n), Exact, "alpha RMSE sqrt(0.375^2 / n)");
  check.Near(metrics->GetChannelMaximumError(1), 0.5, Exact, "green maximum 0.5");
  check.Near(metrics->GetChannelMaximumError(3), 0.375, Exact, "alpha maximum 0.375");
  check.Near(metrics->GetMaximumError(), 0.5, Exact, "overall maximum 0.5");
  check.Near(metrics->GetRMSE(),
    std::sqrt((n * offset * offset + 0.25 + 0.0625 + 0.140625) / (4.0 * n)),
    Exact,
    "overall RMSE over all channels and pixels");

  // The difference image: same geometry, |test - reference| per channel.
  vtkImageData* diff = metrics->GetOutput();
  int dims[3];
  diff->GetDimensions(dims);
  check(dims[0] == w && dims[1] == h && dims[2] == 1, "difference image has the input size");
  vtkDataArray* d = diff->GetPointData()->GetArray("Difference");
  if (check(d && d->GetNumberOfComponents() == 4 && d->GetNumberOfTuples() == n,
        "difference image has a 4-component 'Difference' array of n tuples"))
  {
    check(diff->GetPointData()->GetScalars() == d, "'Difference' is the active scalar array");
    double worst = 0.0;
    for (vtkIdType i = 0; i < n; ++i)
    {
      const double expected[4] = {
        offset, i == outlier ? 0.5 : 0.0, i == 0 ? 0.25 : 0.0, i == 0 ? 0.375 : 0.0
      };
      for (int c = 0; c < 4; ++c)
      {
        worst = std::max(worst, std::abs(d->GetComponent(i, c) - expected[c]));
      }
    }
    check(worst == 0.0,
      "difference image values are exact (largest deviation " + std::to_string(worst) + ")");
  }
  check(metrics->GetNumberOfMeasuredPixels() == n, "every pixel measured");
  messages.ExpectNone(check, "for valid inputs");

  // Reference pixels with a NaN channel were not computed (a sampled reference): left out of
  // the metrics, NaN in the difference image. Leaving out the outlier and pixel 0 leaves the
  // red offset alone.
  {
    vtkNew<vtkImageData> sampled;
    sampled->DeepCopy(reference);
    vtkDataArray* s = sampled->GetPointData()->GetScalars();
    s->SetComponent(outlier, 2, std::nan(""));
    for (int c = 0; c < 4; ++c)
    {
      s->SetComponent(0, c, std::nan(""));
    }
    vtkNew<vtkRGBAErrorMetrics> partial;
    partial->SetInputData(test);
    partial->SetReferenceData(sampled);
    partial->Update();
    check(partial->GetNumberOfMeasuredPixels() == n - 2, "two pixels not measured");
    check.Near(partial->GetChannelRMSE(0), offset, Exact, "sampled: red RMSE is the offset");
    check(partial->GetChannelRMSE(1) == 0.0 && partial->GetChannelMaximumError(1) == 0.0 &&
        partial->GetChannelRMSE(3) == 0.0,
      "sampled: the outlier and pixel 0 are left out");
    check.Near(partial->GetRMSE(), offset / 2.0, Exact, "sampled: overall RMSE is offset / 2");
    vtkDataArray* pd = partial->GetOutput()->GetPointData()->GetArray("Difference");
    check(std::isnan(pd->GetComponent(outlier, 0)) && std::isnan(pd->GetComponent(0, 3)) &&
        pd->GetComponent(1, 0) == offset,
      "sampled: the difference is NaN where the reference is not computed");
  }
  messages.ExpectNone(check, "for a sampled reference");

  // Another array name and type: unsigned char colours, an alpha difference of 10.
  {
    auto makeColours = [&](unsigned char alpha)
    {
      vtkNew<vtkImageData> image;
      image->SetDimensions(3, 2, 1);
      vtkNew<vtkUnsignedCharArray> colours;
      colours->SetName("Colors");
      colours->SetNumberOfComponents(4);
      colours->SetNumberOfTuples(6);
      for (vtkIdType i = 0; i < 6; ++i)
      {
        const unsigned char rgba[4] = { 10, 20, 30, alpha };
        colours->SetTypedTuple(i, rgba);
      }
      image->GetPointData()->AddArray(colours);
      return image;
    };
    auto x = makeColours(200);
    auto y = makeColours(210);
    vtkNew<vtkRGBAErrorMetrics> bytes;
    bytes->SetArrayName("Colors");
    bytes->SetInputData(x);
    bytes->SetReferenceData(y);
    bytes->Update();
    check(bytes->GetChannelRMSE(3) == 10.0 && bytes->GetRMSE() == 5.0 &&
        bytes->GetMaximumError() == 10.0,
      "unsigned char 'Colors' (non-scalar array): alpha difference 10 gives RMSE 5, maximum 10");
  }
  messages.ExpectNone(check, "for the unsigned char images");

  //----------------------------------------------------------------------------
  // Failures: an error, every metric -1 (also after a successful update), no crash.
  auto smaller = MakeImage(w, h - 1, "RGBA");
  metrics->SetReferenceData(smaller);
  metrics->Update();
  check(messages.TakeError("sizes differ"), "mismatched sizes are reported");
  CheckFailed(metrics, "mismatched sizes");

  auto renamed = MakeImage(w, h, "Colour");
  metrics->SetReferenceData(renamed);
  metrics->Update();
  check(messages.TakeError("RGBA"), "a missing array is reported");
  CheckFailed(metrics, "missing array in the reference");

  auto rgb = MakeImage(w, h, "RGBA", 3);
  metrics->SetInputData(rgb);
  metrics->SetReferenceData(reference);
  metrics->Update();
  check(messages.TakeError("4-component"), "a 3-component array is reported");
  CheckFailed(metrics, "3-component test array");

  // Valid again, then without a reference at all.
  metrics->SetInputData(test);
  metrics->Update();
  check.Near(metrics->GetMaximumError(), 0.5, Exact, "valid again after the failures");
  messages.ExpectNone(check, "for valid inputs again");
  metrics->SetReferenceData(nullptr);
  metrics->Update();
  check(messages.TakeError("reference image"), "a missing reference is reported");
  CheckFailed(metrics, "missing reference");
  metrics->SetReferenceData(reference);
  metrics->Update();
  messages.ExpectNone(check, "with the reference back");
  metrics->SetInputData(nullptr);
  metrics->Update();
  check(messages.TakeError("test image"), "a missing test image is reported");
  CheckFailed(metrics, "missing test image");

  messages.ExpectNone(check, "at the end of the test");
  return check.Result("TestRGBAErrorMetrics");
}
