// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
// vtkPreIntegrationTableRefiner and vtkLowPriorityThreads: the worker's table equals the one
// measured and built in the calling thread (sizes and entries), the newest of a burst of
// requests wins, Cancel(), Paused, a failure with its message, a refiner destroyed while it
// works, and the low-priority loop covering its range once. Threads under the sanitizers: the
// C++ side of TestPreIntegrationTableRefiner.py.
#include "vtkColorTransferFunction.h"
#include "vtkDataArray.h"
#include "vtkFloatArray.h"
#include "vtkImageData.h"
#include "vtkLowPriorityThreads.h"
#include "vtkNew.h"
#include "vtkPiecewiseFunction.h"
#include "vtkPointData.h"
#include "vtkPreIntegrationTableRefiner.h"
#include "vtkPreIntegrationTableSizer.h"
#include "vtkSecondOrderPreIntegrationTable.h"
#include "vtkSmartPointer.h"
#include "vtkVolumeProperty.h"

#include "hovrTestUtilities.h"

#include <atomic>
#include <cmath>
#include <vector>

namespace
{
hovrTest::Checker check;

// A smooth field on n^3 points, values in [0, 1].
vtkSmartPointer<vtkImageData> MakeVolume(int n)
{
  auto image = vtkSmartPointer<vtkImageData>::New();
  image->SetDimensions(n, n, n);
  image->AllocateScalars(VTK_FLOAT, 1);
  auto* values = static_cast<float*>(image->GetScalarPointer());
  for (int k = 0; k < n; ++k)
  {
    for (int j = 0; j < n; ++j)
    {
      for (int i = 0; i < n; ++i)
      {
        const double x = 2.0 * i / (n - 1) - 1, y = 2.0 * j / (n - 1) - 1,
                     z = 2.0 * k / (n - 1) - 1;
        values[i + n * (j + n * k)] =
          static_cast<float>(0.5 + 0.5 * std::sin(3.0 * x) * std::cos(2.0 * y + z));
      }
    }
  }
  return image;
}

vtkSmartPointer<vtkVolumeProperty> MakeProperty(double peak)
{
  vtkNew<vtkPiecewiseFunction> opacity;
  opacity->AddPoint(0.0, 0.0);
  opacity->AddPoint(0.45, 0.0);
  opacity->AddPoint(0.5, peak);
  opacity->AddPoint(0.55, 0.0);
  opacity->AddPoint(1.0, 0.0);
  vtkNew<vtkColorTransferFunction> color;
  color->AddRGBPoint(0.0, 0.1, 0.3, 1.0);
  color->AddRGBPoint(1.0, 1.0, 0.6, 0.1);
  auto property = vtkSmartPointer<vtkVolumeProperty>::New();
  property->SetScalarOpacity(opacity);
  property->SetColor(color);
  property->SetScalarOpacityUnitDistance(0.5);
  return property;
}

vtkSmartPointer<vtkSecondOrderPreIntegrationTable> MakeTable(vtkVolumeProperty* property,
  vtkImageData* image,
  int order)
{
  auto table = vtkSmartPointer<vtkSecondOrderPreIntegrationTable>::New();
  table->SetVolumeProperty(property);
  double range[2];
  image->GetPointData()->GetScalars()->GetRange(range);
  table->SetScalarRange(range);
  table->SetSegmentLength(order * 1.0);
  return table;
}

bool SameEntries(vtkSecondOrderPreIntegrationTable* a, vtkSecondOrderPreIntegrationTable* b)
{
  vtkFloatArray* x = a->GetTable();
  vtkFloatArray* y = b->GetTable();
  if (x->GetNumberOfValues() != y->GetNumberOfValues() || x->GetNumberOfValues() == 0)
  {
    return false;
  }
  for (vtkIdType v = 0; v < x->GetNumberOfValues(); ++v)
  {
    if (x->GetValue(v) != y->GetValue(v))
    {
      return false;
    }
  }
  return true;
}
}

int TestPreIntegrationTableRefiner(int, char*[])
{
  hovrTest::MessageCapture messages;
  vtkSmartPointer<vtkImageData> image = MakeVolume(32);
  vtkDataArray* scalars = image->GetPointData()->GetScalars();
  vtkSmartPointer<vtkVolumeProperty> property = MakeProperty(0.6);

  for (int order = 1; order <= 2; ++order)
  {
    const std::string name = "order " + std::to_string(order);
    vtkSmartPointer<vtkSecondOrderPreIntegrationTable> expected = MakeTable(property, image, order);
    vtkNew<vtkPreIntegrationTableSizer> sizer;
    check(sizer->Choose(image, scalars, expected, order, 1.0) && expected->Update(),
      name + ": measured and built in this thread");

    vtkNew<vtkPreIntegrationTableRefiner> refiner;
    vtkIdType request =
      refiner->Request(image, scalars, MakeTable(property, image, order), order, 1.0, 4097, true);
    refiner->Wait();
    vtkSmartPointer<vtkSecondOrderPreIntegrationTable> table = MakeTable(property, image, order);
    check(refiner->IsReady(request) && refiner->TakeResult(request, table),
      name + ": the worker's result is taken");
    check(table->GetTableSize() == expected->GetTableSize() &&
        table->GetChordSize() == expected->GetChordSize() &&
        table->GetDeviationSize() == expected->GetDeviationSize(),
      name + ": the worker's sizes are this thread's");
    check(table->GetBuildCount() == 1 && table->Update() && table->GetBuildCount() == 1,
      name + ": the taken table counts as built");
    check(SameEntries(table, expected), name + ": the worker's entries are this thread's");

    // A burst of 8 requests: only the newest is measured.
    const vtkIdType completed = refiner->GetNumberOfCompleted();
    std::vector<vtkIdType> burst;
    for (int k = 0; k < 8; ++k)
    {
      burst.push_back(refiner->Request(image,
        scalars,
        MakeTable(MakeProperty(0.2 + 0.1 * k), image, order),
        order,
        1.0,
        4097,
        true));
    }
    refiner->Wait();
    bool older = false;
    for (size_t k = 0; k + 1 < burst.size(); ++k)
    {
      older = older || refiner->IsReady(burst[k]);
    }
    check(
      refiner->IsReady(burst.back()) && !older && refiner->GetNumberOfCompleted() - completed >= 1,
      name + ": the newest of a burst wins");

    // Held, then cancelled.
    refiner->SetPaused(true);
    request =
      refiner->Request(image, scalars, MakeTable(property, image, order), order, 1.0, 4097, true);
    refiner->Wait();
    check(!refiner->IsReady(request) && refiner->IsBusy(), name + ": a held request waits");
    refiner->Cancel();
    refiner->SetPaused(false);
    refiner->Wait();
    check(!refiner->IsReady(request) && !refiner->IsBusy(), name + ": a cancelled request ends");

    // A transfer function without opacity nodes: a failure with its message.
    vtkNew<vtkVolumeProperty> empty;
    vtkNew<vtkPiecewiseFunction> none;
    empty->SetScalarOpacity(none);
    empty->SetColor(property->GetRGBTransferFunction());
    request =
      refiner->Request(image, scalars, MakeTable(empty, image, order), order, 1.0, 4097, true);
    refiner->Wait();
    check(refiner->Failed(request) && !refiner->GetFailure(request).empty(),
      name + ": a failed request says why");
  }

  // Destroyed while it works: the worker stops at its next check.
  {
    vtkSmartPointer<vtkImageData> big = MakeVolume(64);
    vtkNew<vtkPreIntegrationTableRefiner> refiner;
    refiner->Request(
      big, big->GetPointData()->GetScalars(), MakeTable(property, big, 2), 2, 0.5, 4097, true);
  }

  // The low-priority loop covers its range once, in chunks of at most the grain.
  std::vector<std::atomic<int>> hits(10007);
  std::atomic<int> largest{ 0 };
  vtkLowPriorityThreads::For(static_cast<vtkIdType>(hits.size()),
    64,
    [&](vtkIdType begin, vtkIdType end)
    {
      int size = static_cast<int>(end - begin);
      int seen = largest.load();
      while (size > seen && !largest.compare_exchange_weak(seen, size))
      {
      }
      for (vtkIdType i = begin; i < end; ++i)
      {
        hits[i]++;
      }
    });
  bool once = true;
  for (const auto& hit : hits)
  {
    once = once && hit.load() == 1;
  }
  check(once && largest.load() <= 64, "the low-priority loop visits every index once");

  // The worker's errors are kept for GetFailure(), never printed from its thread.
  messages.ExpectNone(check, "from the worker");
  return check.Result("TestPreIntegrationTableRefiner");
}
