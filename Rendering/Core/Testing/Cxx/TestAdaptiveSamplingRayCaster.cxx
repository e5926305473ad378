// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
// vtkAdaptiveSamplingRayCaster ("Adaptive Sampling in Three Dimensions for Volume Rendering on
// GPUs"):
//   1. the "min." oracle draws first-order pre-integration on the same slice grid (an
//      independent full-rate composite in this test, and the caster with MaximumLevel 0), and
//      its samples exceed the full rate by the pyramid's levels (about sum 1/8^l, 14.26% at
//      l_max = 3, Tables 2 and 3);
//   2. Table 1 (l_slice of slices 0..8) and the closed-form next sample against a per-slice loop;
//   3. Gaussian blobs in empty space with a distance-to-features oracle: few samples, an error
//      against vtkVolumeReferenceIntegrator close to the full-rate image's;
//   4. Fig. 3 and Fig. 7 count differently and both stay close to the reference;
//   5. bad input: clear errors and an empty image;
//   6. entry and exit pieces: a constant volume gives exactly 1 - exp(-sigma chord) per pixel
//      (oblique and axis-aligned views, every oracle, Fig. 7 and Fig. 3), a linear ramp the
//      error of first-order pre-integration at the same step.
#include "vtkAdaptiveSamplingRayCaster.h"
#include "vtkCamera.h"
#include "vtkCameraRayModel.h"
#include "vtkColorTransferFunction.h"
#include "vtkFirstOrderPreIntegrationTable.h"
#include "vtkFloatArray.h"
#include "vtkImageData.h"
#include "vtkMinimalStandardRandomSequence.h"
#include "vtkNew.h"
#include "vtkPiecewiseFunction.h"
#include "vtkPointData.h"
#include "vtkPreIntegrationRayCaster.h"
#include "vtkPreIntegrationRayMarch.h"
#include "vtkRGBAErrorMetrics.h"
#include "vtkVolumeProperty.h"
#include "vtkVolumeReferenceIntegrator.h"

#include "hovrAdaptiveTestScenes.h"
#include "hovrTestUtilities.h"

#include <algorithm>
#include <cmath>
#include <iostream>
#include <limits>
#include <string>
#include <vector>

namespace
{
hovrTest::Checker check;

constexpr int N = hovrTest::BlobPoints;

vtkFloatArray* RGBA(vtkImageData* image)
{
  return vtkFloatArray::SafeDownCast(image->GetPointData()->GetArray("RGBA"));
}

double MaxDifference(vtkImageData* a, vtkImageData* b)
{
  vtkFloatArray* x = RGBA(a);
  vtkFloatArray* y = RGBA(b);
  if (!x || !y || x->GetNumberOfValues() != y->GetNumberOfValues())
  {
    return 1e30;
  }
  double worst = 0.0;
  for (vtkIdType i = 0; i < x->GetNumberOfValues(); ++i)
  {
    worst = std::max(worst, std::abs(static_cast<double>(x->GetValue(i)) - y->GetValue(i)));
  }
  return worst;
}

double RMSE(vtkImageData* image, vtkImageData* reference)
{
  vtkNew<vtkRGBAErrorMetrics> metrics;
  metrics->SetInputData(image);
  metrics->SetReferenceData(reference);
  metrics->Update();
  return metrics->GetRMSE();
}

bool AllZero(vtkImageData* image)
{
  vtkFloatArray* rgba = RGBA(image);
  if (!rgba)
  {
    return true;
  }
  for (vtkIdType i = 0; i < rgba->GetNumberOfValues(); ++i)
  {
    if (rgba->GetValue(i) != 0.0f)
    {
      return false;
    }
  }
  return true;
}

// The full-rate first-order composite of the slice grid, written here from the paper's
// definition (slices from the nearest box corner, one Delta apart; segments between
// consecutive slices, from a table of length Delta), cut to the ray's chord through the box:
// a segment that the box's entry or exit splits keeps its part inside, with the scalar taken
// on the face and its optical depth scaled to its length. boundary counts those face values.
void FullRate(vtkImageData* volume,
  vtkVolumeProperty* property,
  vtkCamera* camera,
  int size,
  std::vector<double>& image,
  vtkIdType& samples,
  vtkIdType& boundary)
{
  vtkNew<vtkCameraRayModel> rays;
  rays->SetCamera(camera);
  rays->SetImageSize(size, size);
  rays->Prepare();
  const double delta = 2.0 * camera->GetParallelScale() / size;
  double eye[3], forward[3];
  rays->GetRay(0, 0, eye, forward);
  double nearest = 1e300, farthest = -1e300;
  for (int c = 0; c < 8; ++c)
  {
    const double p[3] = {
      (c & 1) ? N - 1.0 : 0.0, (c & 2) ? N - 1.0 : 0.0, (c & 4) ? N - 1.0 : 0.0
    };
    double depth = 0.0;
    for (int a = 0; a < 3; ++a)
    {
      depth += (p[a] - eye[a]) * forward[a];
    }
    nearest = std::min(nearest, depth);
    farthest = std::max(farthest, depth);
  }
  const int slices = static_cast<int>(std::ceil((farthest - nearest) / delta)) + 1;
  vtkNew<vtkFirstOrderPreIntegrationTable> table;
  table->SetVolumeProperty(property);
  table->SetSegmentLength(delta);
  double range[2];
  volume->GetPointData()->GetScalars()->GetRange(range);
  table->SetScalarRange(range);
  table->Update();
  vtkPreIntegrationRayMarch::TablePieces pieces;
  pieces.Table = vtkPreIntegrationRayMarch::TableView::Of(table);
  std::vector<double> values(static_cast<size_t>(N) * N * N);
  for (size_t i = 0; i < values.size(); ++i)
  {
    values[i] = volume->GetPointData()->GetScalars()->GetComponent(static_cast<vtkIdType>(i), 0);
  }
  vtkPreIntegrationRayMarch::Grid grid;
  grid.Values.SetValues(values.data(), static_cast<vtkIdType>(values.size()));
  grid.Dims[0] = grid.Dims[1] = grid.Dims[2] = N;
  image.assign(4 * static_cast<size_t>(size) * size, 0.0);
  samples = 0;
  boundary = 0;
  for (int j = 0; j < size; ++j)
  {
    for (int i = 0; i < size; ++i)
    {
      double o[3], v[3];
      rays->GetPixelRay(i, j, o, v);
      double* c = &image[4 * (static_cast<size_t>(j) * size + i)];
      double t0, t1; // the chord (world distance from o)
      if (!grid.Clip(o, v, t0, t1))
      {
        continue;
      }
      auto at = [&](double t)
      {
        const double p[3] = { o[0] + t * v[0], o[1] + t * v[1], o[2] + t * v[2] };
        return grid.Sample(p);
      };
      double previous = std::numeric_limits<double>::quiet_NaN();
      for (int k = 0; k < slices; ++k)
      {
        const double t = nearest + k * delta;
        const double p[3] = { o[0] + t * v[0], o[1] + t * v[1], o[2] + t * v[2] };
        const bool inside =
          p[0] >= 0 && p[1] >= 0 && p[2] >= 0 && p[0] <= N - 1 && p[1] <= N - 1 && p[2] <= N - 1;
        const double s = inside ? grid.Sample(p) : std::numeric_limits<double>::quiet_NaN();
        samples += inside;
        const double front = std::max(t - delta, t0), back = std::min(t, t1);
        if (k > 0 && back > front)
        {
          const double sf = std::isnan(previous) ? at(front) : previous;
          const double sb = inside ? s : at(back);
          boundary += std::isnan(previous) + !inside;
          double segment[4];
          pieces.Segment(sf, sb, (back - front) / delta, delta, segment);
          const double transmittance = 1.0 - c[3];
          for (int q = 0; q < 4; ++q)
          {
            c[q] += transmittance * segment[q];
          }
        }
        previous = s;
      }
    }
  }
}
}

int TestAdaptiveSamplingRayCaster(int, char*[])
{
  hovrTest::MessageCapture messages;
  const int size = 96;
  auto volume = hovrTest::MakeBlobVolume();
  auto property = hovrTest::MakeBlobProperty(2.0);
  vtkNew<vtkCamera> camera;
  hovrTest::MakeBlobCamera(camera);

  vtkNew<vtkAdaptiveSamplingRayCaster> caster;
  caster->SetInputData(volume);
  caster->SetVolumeProperty(property);
  caster->SetCamera(camera);
  caster->SetImageSize(size, size);
  check(caster->GetMaximumLevel() == 3 && caster->GetAlgorithm() == 0 &&
      std::string(caster->GetOracleArrayName()) == "OracleDistance",
    "initial values: MaximumLevel 3, Fig. 7, OracleDistance");

  //----------------------------------------------------------------------------
  // 2. Table 1 (l_max = infinity; slice 0 takes l_max) and the closed-form skip.
  {
    const int table1[9] = { 40, 0, 1, 0, 2, 0, 1, 0, 3 };
    bool same = true;
    for (int i = 0; i < 9; ++i)
    {
      same = same && vtkAdaptiveSamplingRayCaster::SliceLevel(i, 40) == table1[i];
    }
    check(same, "Table 1: l_slice of slices 0..8 = inf 0 1 0 2 0 1 0 3");
    check(vtkAdaptiveSamplingRayCaster::SliceLevel(8, 2) == 2 &&
        vtkAdaptiveSamplingRayCaster::SliceLevel(0, 2) == 2,
      "l_slice is capped at l_max");
    vtkNew<vtkMinimalStandardRandomSequence> random;
    random->SetSeed(7);
    int mismatches = 0;
    for (int trial = 0; trial < 20000; ++trial)
    {
      const int lmax = static_cast<int>(random->GetNextRangeValue(0, 5));
      const vtkIdType i = static_cast<vtkIdType>(random->GetNextRangeValue(0, 1000));
      const double d = random->GetNextRangeValue(1.0, 40.0);
      // Per-slice loop: skip j iff d >= 2^(l_slice(j) + 1), never when l_slice(j) = l_max.
      vtkIdType j = i + 1;
      for (;; ++j)
      {
        const int lj = vtkAdaptiveSamplingRayCaster::SliceLevel(j, lmax);
        if (lj == lmax || d < std::ldexp(1.0, lj + 1))
        {
          break;
        }
      }
      mismatches += j != vtkAdaptiveSamplingRayCaster::NextSampleSlice(i, d, lmax);
    }
    check(mismatches == 0,
      "closed-form next sample = per-slice loop (" + std::to_string(mismatches) +
        " of 20000 differ)");

    // SYNTHESIZE (Fig. 5) reproduces Fig. 4: s_0[4,1] = 3/16 s_1[1,0] + 9/16 s_1[2,0] +
    // 1/16 s_1[1,1] + 3/16 s_1[2,1], read as the weight of each coarse pixel (a unit impulse
    // there); at the level's edge the missing neighbour's weight goes to the edge pixel.
    const int cw = 4, ch = 3;
    const double fig4[4][3] = {
      { 1, 0, 3.0 / 16 }, { 2, 0, 9.0 / 16 }, { 1, 1, 1.0 / 16 }, { 2, 1, 3.0 / 16 }
    };
    double total = 0.0;
    bool weights = true;
    for (int cy = 0; cy < ch; ++cy)
    {
      for (int cx = 0; cx < cw; ++cx)
      {
        std::vector<double> impulse(cw * ch, 0.0);
        impulse[cy * cw + cx] = 1.0;
        const double w = vtkAdaptiveSamplingRayCaster::Synthesize(impulse.data(), cw, ch, 4, 1);
        double expected = 0.0;
        for (const auto& e : fig4)
        {
          expected += (e[0] == cx && e[1] == cy) ? e[2] : 0.0;
        }
        weights = weights && w == expected;
        total += w;
      }
    }
    check(weights && total == 1.0, "SYNTHESIZE weights of fine pixel (4, 1) are Fig. 4's");
    std::vector<double> ramp(cw * ch);
    for (int q = 0; q < cw * ch; ++q)
    {
      ramp[q] = q % cw;
    }
    check(vtkAdaptiveSamplingRayCaster::Synthesize(ramp.data(), cw, ch, 0, 0) == 0.0 &&
        vtkAdaptiveSamplingRayCaster::Synthesize(ramp.data(), cw, ch, 7, 5) == 3.0 &&
        vtkAdaptiveSamplingRayCaster::Synthesize(ramp.data(), cw, ch, 3, 2) == 1.25,
      "SYNTHESIZE clamps to the edge and interpolates at the fine pixel's centre");
  }

  //----------------------------------------------------------------------------
  // 1. The min. oracle: full-rate first-order pre-integration, plus the pyramid's samples.
  std::vector<double> independent;
  vtkIdType independentSamples = 0, independentBoundary = 0;
  FullRate(volume, property, camera, size, independent, independentSamples, independentBoundary);
  caster->SetOracleModeToMinimum();
  vtkNew<vtkImageData> fullRate;
  {
    double expectedOverhead = 0.0;
    for (int lmax = 0; lmax <= 3; ++lmax)
    {
      if (lmax > 0)
      {
        expectedOverhead += std::ldexp(1.0, -3 * lmax);
      }
      caster->SetMaximumLevel(lmax);
      caster->Update();
      vtkImageData* image = caster->GetOutput();
      if (lmax == 0)
      {
        fullRate->DeepCopy(image);
      }
      vtkFloatArray* rgba = RGBA(image);
      double worst = 0.0;
      for (vtkIdType v = 0; v < rgba->GetNumberOfValues(); ++v)
      {
        worst = std::max(worst, std::abs(rgba->GetValue(v) - independent[v]));
      }
      const double overhead = static_cast<double>(caster->GetNumberOfSampleOperations()) /
          caster->GetFullRateSampleOperations() -
        1.0;
      std::cout << "min. oracle, l_max " << lmax << ": samples "
                << caster->GetNumberOfSampleOperations() << ", full rate "
                << caster->GetFullRateSampleOperations() << ", overhead " << 100.0 * overhead
                << "% (sum 1/8^l: " << 100.0 * expectedOverhead << "%), synthesis "
                << caster->GetNumberOfSynthesisOperations() << ", largest difference from the "
                << "independent full-rate composite " << worst << "\n";
      check.Near(worst,
        0.0,
        1e-6,
        "min. oracle, l_max " + std::to_string(lmax) +
          ": image = full-rate first-order pre-integration on the slice grid");
      check(caster->GetFullRateSampleOperations() == independentSamples,
        "full-rate count = the independent composite's inside samples (" +
          std::to_string(caster->GetFullRateSampleOperations()) + " vs " +
          std::to_string(independentSamples) + ")");
      // Every level-0 ray accumulates on every slice: one fetch where it enters the box and
      // one where it leaves, unless it does so on a slice.
      check(caster->GetNumberOfBoundarySampleOperations() == independentBoundary,
        "min. oracle: boundary fetches = the independent composite's (" +
          std::to_string(caster->GetNumberOfBoundarySampleOperations()) + " vs " +
          std::to_string(independentBoundary) + ")");
      // Coarse rays pass through block centres, so the inside counts of a level are those of
      // its pixels' central rays, not exactly 1/8^l of level 0's: a tolerance of 0.5%.
      check.Near(overhead,
        expectedOverhead,
        0.005,
        "min. oracle, l_max " + std::to_string(lmax) + ": sample overhead over the full rate");
      check(caster->GetNumberOfOracleOperations() == 0, "the min. oracle reads no array");
    }
  }
  messages.ExpectNone(check, "rendering with the min. oracle");

  //----------------------------------------------------------------------------
  // 3. and 4. The real oracle, Fig. 7 and Fig. 3, against the reference integrator.
  vtkNew<vtkVolumeReferenceIntegrator> reference;
  reference->SetInputData(volume);
  reference->SetVolumeProperty(property);
  reference->SetCamera(camera);
  reference->SetImageSize(size, size);
  reference->Update();
  const double fullRMSE = RMSE(fullRate, reference->GetOutput());
  std::cout << "full rate (l_max 0): RMSE against the reference " << fullRMSE << "\n";
  caster->SetOracleModeToArray();
  caster->SetMaximumLevel(3);
  vtkIdType counts[2][2];
  for (int algorithm = 0; algorithm < 2; ++algorithm)
  {
    caster->SetAlgorithm(algorithm);
    caster->Update();
    const double rmse = RMSE(caster->GetOutput(), reference->GetOutput());
    const double ratio = static_cast<double>(caster->GetNumberOfSampleOperations()) /
      caster->GetFullRateSampleOperations();
    counts[algorithm][0] = caster->GetNumberOfSampleOperations();
    counts[algorithm][1] = caster->GetNumberOfSynthesisOperations();
    const std::string name = algorithm ? "Fig. 3" : "Fig. 7";
    std::cout << "blobs, oracle, " << name << ", l_max 3: samples "
              << caster->GetNumberOfSampleOperations() << " (" << ratio
              << " x full rate), synthesis " << caster->GetNumberOfSynthesisOperations()
              << ", accumulate " << caster->GetNumberOfAccumulateOperations()
              << ", RMSE against the reference " << rmse << " (" << rmse / fullRMSE
              << " x full rate's), against full rate " << RMSE(caster->GetOutput(), fullRate)
              << "\n";
    // About 0.085 x full rate are the oracle's; the rest are samples that replace a NaN
    // synthesised at a point inside the box near the outline of each slice's cross-section,
    // a band of a few pixels per level along an outline that is long for a 96 x 96 image.
    check(
      ratio <= 0.125, name + ": samples at most 0.125 x full rate, got " + std::to_string(ratio));
    check(rmse <= 1.5 * fullRMSE,
      name + ": RMSE at most 1.5 x the full-rate image's, got " + std::to_string(rmse / fullRMSE));
    check(caster->GetNumberOfOracleOperations() == caster->GetNumberOfSampleOperations(),
      "the oracle is fetched with every sample");
  }
  check(counts[0][0] != counts[1][0] || counts[0][1] != counts[1][1],
    "Fig. 3 and Fig. 7 count differently");
  check(counts[1][1] < counts[0][1], "Fig. 3 synthesises fewer pixels than Fig. 7");
  messages.ExpectNone(check, "rendering the blobs");
  caster->SetAlgorithmToFig7();

  // An oracle that asks for 2^l_max everywhere inside: inside the box only
  // the top level samples, on every 2^l_max-th slice, 1/8^3 of the full rate; outside, the
  // oracle is the distance to the box, so rays reach the entry face with shrinking steps on
  // finer levels, which adds samples near the faces (a few times 1/512 on this small volume),
  // and on every 2^l_max-th slice the finer levels sample where a NaN from a coarse
  // neighbour outside the box meets a point inside (a band along each cross-section's
  // outline: about 1/25 of the full rate here).
  // The blobs are then undersampled and the error bound above fails: it measures the oracle.
  {
    vtkNew<vtkImageData> coarse;
    coarse->DeepCopy(volume);
    vtkFloatArray::SafeDownCast(coarse->GetPointData()->GetArray("OracleDistance"))
      ->FillValue(1000.0f);
    caster->SetInputData(coarse);
    caster->Update();
    const double rmse = RMSE(caster->GetOutput(), reference->GetOutput());
    const double ratio = static_cast<double>(caster->GetNumberOfSampleOperations()) /
      caster->GetFullRateSampleOperations();
    std::cout << "blobs, d = 2^l_max everywhere: samples " << caster->GetNumberOfSampleOperations()
              << " (" << ratio << " x full rate, 1/512 = " << 1.0 / 512 << "), RMSE " << rmse
              << " (" << rmse / fullRMSE << " x full rate's)\n";
    check(ratio >= 1.0 / 512.0 && ratio <= 0.05,
      "d = 2^l_max: samples between full rate / 512 and 5% of it, got " + std::to_string(ratio));
    check(rmse > 1.5 * fullRMSE, "d = 2^l_max: the undersampled image fails the error bound");
    caster->SetInputData(volume);
  }

  //----------------------------------------------------------------------------
  // 6. Entry and exit pieces: a constant scalar gives, per pixel, exactly the exponential of
  // its chord through the box, whatever the oracle, the algorithm and the view (oblique, where
  // rays enter and leave between slices, and along an axis, where slice 0 lies on the entry
  // face). Every piece comes from the table of a constant (its diagonal entry, exact up to its
  // float32 rounding) with the optical depth scaled to its length, which is exact for a
  // constant; the float32 entries and image leave ~1e-7 per piece, a few dozen pieces per ray:
  // a tolerance of 2e-6. A segment dropped at a face (a quarter of a slice spacing at least
  // where it matters) or a NaN from the silhouette misses 1e-3 or more.
  {
    vtkNew<vtkVolumeProperty> flat;
    hovrTest::MakeConstantProperty(flat);
    const int constantSize = 64;
    const double centre[3] = { hovrTest::ConstantOrigin[0] +
        0.5 * (hovrTest::ConstantDims[0] - 1) * hovrTest::ConstantSpacing[0],
      hovrTest::ConstantOrigin[1] +
        0.5 * (hovrTest::ConstantDims[1] - 1) * hovrTest::ConstantSpacing[1],
      hovrTest::ConstantOrigin[2] +
        0.5 * (hovrTest::ConstantDims[2] - 1) * hovrTest::ConstantSpacing[2] };
    struct View
    {
      const char* Name;
      double Direction[3], Up[3];
    };
    const View views[3] = { { "oblique", { 100.0, 60.0, 80.0 }, { 0, 0, 1 } },
      { "along -z", { 0.0, 0.0, 100.0 }, { 0, 1, 0 } },
      { "along +x", { -100.0, 0.0, 0.0 }, { 0, 0, 1 } } };
    vtkNew<vtkCamera> view;
    view->SetFocalPoint(centre[0], centre[1], centre[2]);
    view->SetParallelProjection(true);
    view->SetParallelScale(31.0);
    vtkNew<vtkAdaptiveSamplingRayCaster> flatCaster;
    flatCaster->SetVolumeProperty(flat);
    flatCaster->SetCamera(view);
    flatCaster->SetImageSize(constantSize, constantSize);
    for (const View& v : views)
    {
      view->SetPosition(
        centre[0] + v.Direction[0], centre[1] + v.Direction[1], centre[2] + v.Direction[2]);
      view->SetViewUp(v.Up[0], v.Up[1], v.Up[2]);
      for (int oracle = 0; oracle < 3; ++oracle)
      {
        auto constant = hovrTest::MakeConstantVolume(oracle == 2);
        flatCaster->SetInputData(constant);
        flatCaster->SetOracleMode(oracle == 0 ? vtkAdaptiveSamplingRayCaster::ORACLE_MINIMUM
                                              : vtkAdaptiveSamplingRayCaster::ORACLE_ARRAY);
        for (int algorithm = 0; algorithm < 2; ++algorithm)
        {
          flatCaster->SetAlgorithm(algorithm);
          flatCaster->SetMaximumLevel(3);
          flatCaster->Update();
          const double error = hovrTest::ConstantVolumeError(
            flatCaster->GetOutput(), constant, flat, view, constantSize);
          const std::string name = std::string("constant volume, ") + v.Name +
            (oracle == 0      ? ", min. oracle"
                : oracle == 1 ? ", oracle 2^l_max"
                              : ", varying oracle") +
            (algorithm ? ", Fig. 3" : ", Fig. 7");
          std::cout << name << ": samples " << flatCaster->GetNumberOfSampleOperations()
                    << ", boundary fetches " << flatCaster->GetNumberOfBoundarySampleOperations()
                    << ", full rate " << flatCaster->GetFullRateSampleOperations()
                    << ", largest difference from 1 - exp(-sigma chord) " << error << "\n";
          check.Near(error, 0.0, 2e-6, name + ": exact for a constant scalar");
        }
      }
    }
    messages.ExpectNone(check, "rendering the constant volume");

    // A linear ramp (along x) on the oblique view: the pyramid against the reference
    // integrator, next to first-order pre-integration from the box entry at the same step
    // (vtkPreIntegrationRayCaster, the twin of the mapper whose entry and exit pieces the
    // pyramid's follow). Both are exact on whole segments of a linear scalar but for the
    // table's bilinear lookup, and approximate on partial pieces (the depth scaling is exact
    // for a constant only); a piece dropped at a face costs far more (the bound fails then).
    view->SetPosition(centre[0] + 100.0, centre[1] + 60.0, centre[2] + 80.0);
    view->SetViewUp(0, 0, 1);
    auto ramp = hovrTest::MakeConstantVolume(false, true);
    vtkNew<vtkVolumeReferenceIntegrator> rampReference;
    rampReference->SetInputData(ramp);
    rampReference->SetVolumeProperty(flat);
    rampReference->SetCamera(view);
    rampReference->SetImageSize(constantSize, constantSize);
    rampReference->Update();
    vtkNew<vtkFirstOrderPreIntegrationTable> rampTable;
    vtkNew<vtkPreIntegrationRayCaster> preint;
    preint->SetInputData(ramp);
    preint->SetVolumeProperty(flat);
    preint->SetCamera(view);
    preint->SetImageSize(constantSize, constantSize);
    preint->SetTable(rampTable);
    preint->SetSampleDistance(2.0 * view->GetParallelScale() / constantSize);
    preint->SetOpacityThreshold(1.0);
    preint->Update();
    const double preintRMSE = RMSE(preint->GetOutput(), rampReference->GetOutput());
    const double preintWorst = MaxDifference(preint->GetOutput(), rampReference->GetOutput());
    flatCaster->SetInputData(ramp);
    flatCaster->SetAlgorithmToFig7();
    for (int oracle = 0; oracle < 2; ++oracle)
    {
      flatCaster->SetOracleMode(oracle == 0 ? vtkAdaptiveSamplingRayCaster::ORACLE_MINIMUM
                                            : vtkAdaptiveSamplingRayCaster::ORACLE_ARRAY);
      flatCaster->Update();
      const double rmse = RMSE(flatCaster->GetOutput(), rampReference->GetOutput());
      const double worst = MaxDifference(flatCaster->GetOutput(), rampReference->GetOutput());
      const std::string name =
        std::string("linear ramp, ") + (oracle == 0 ? "min. oracle" : "oracle 2^l_max");
      std::cout << name << ": RMSE against the reference " << rmse << ", largest difference "
                << worst << "; first-order pre-integration at the same step: " << preintRMSE << ", "
                << preintWorst << "\n";
      check(rmse <= 1.25 * preintRMSE && worst <= 1.25 * preintWorst,
        name + ": error at most 1.25 x first-order pre-integration's");
    }
  }

  //----------------------------------------------------------------------------
  // 5. Bad input: an error naming the problem, a transparent image, zero counters.
  auto expectError = [&](const std::string& fragment, const std::string& what)
  {
    caster->Update();
    check(messages.TakeError(fragment), what + ": an error mentioning \"" + fragment + "\"");
    check(AllZero(caster->GetOutput()), what + ": a transparent image");
    check(caster->GetNumberOfSampleOperations() == 0, what + ": no samples counted");
  };
  camera->SetParallelProjection(false);
  expectError("parallel projection", "perspective camera");
  camera->SetParallelProjection(true);
  caster->SetImageSize(100, 100);
  expectError("not divisible", "image size 100 with l_max 3");
  caster->SetImageSize(size, size);
  caster->SetMaximumLevel(9);
  expectError("MaximumLevel", "l_max 9");
  caster->SetMaximumLevel(-1);
  expectError("MaximumLevel", "l_max -1");
  caster->SetMaximumLevel(3);
  caster->SetOracleArrayName("NoSuchArray");
  expectError("NoSuchArray", "missing oracle array");
  caster->SetOracleArrayName("OracleDistance");
  {
    vtkNew<vtkImageData> bad;
    bad->DeepCopy(volume);
    vtkFloatArray::SafeDownCast(bad->GetPointData()->GetArray("OracleDistance"))
      ->SetValue(1234, std::numeric_limits<float>::quiet_NaN());
    caster->SetInputData(bad);
    expectError("not finite", "NaN oracle value");
    caster->SetInputData(volume);
  }
  caster->Update();
  check(!AllZero(caster->GetOutput()), "valid settings render again");
  messages.ExpectNone(check, "after the bad input");

  return check.Result("TestAdaptiveSamplingRayCaster");
}
