// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
#include "vtkObjectOrderRayCasterClassification.h"

#include "vtkFirstOrderPreIntegrationTable.h"
#include "vtkFloatArray.h"
#include "vtkPreIntegrationTable.h"
#include "vtkVolumeTransferFunctionSampler.h"

#include <cmath>

//------------------------------------------------------------------------------
bool vtkObjectOrderRayCasterClassification::Update(vtkVolumeTransferFunctionSampler* sampler,
  int dataType,
  const double range[2],
  double step)
{
  const int entries =
    vtkPreIntegrationTable::SuggestTableSize(dataType, range, sampler, 256, 65536);
  this->Entries = entries;
  this->S0 = range[0];
  this->InvStep = (entries - 1) / (range[1] - range[0]);
  const std::array<double, 5> tableKey = {
    static_cast<double>(sampler->GetMTime()), range[0], range[1], static_cast<double>(entries), step
  };
  if (tableKey == this->TableKey)
  {
    return false;
  }
  this->TableKey = tableKey;
  std::vector<double> rgbTau(4 * static_cast<size_t>(entries));
  sampler->Sample(range[0], range[1], entries, rgbTau.data());
  this->Table.resize(4 * static_cast<size_t>(entries));
  for (int e = 0; e < entries; ++e)
  {
    for (int ch = 0; ch < 3; ++ch)
    {
      this->Table[4 * e + ch] = static_cast<float>(rgbTau[4 * e + ch]);
    }
    this->Table[4 * e + 3] = static_cast<float>(-std::expm1(-rgbTau[4 * e + 3] * step));
  }
  this->VisiblePrefix.assign(entries, 0);
  for (int b = 0; b + 1 < entries; ++b)
  {
    const double lo = range[0] + b / this->InvStep, hi = range[0] + (b + 1) / this->InvStep;
    const bool visible = sampler->GetMaximumOpacity(lo, hi) > 0.0 ||
      this->Table[4 * b + 3] > 0.0f || this->Table[4 * b + 7] > 0.0f;
    this->VisiblePrefix[b + 1] = this->VisiblePrefix[b] + (visible ? 1 : 0);
  }
  return true;
}

//------------------------------------------------------------------------------
bool vtkObjectOrderRayCasterClassification::UpdateSegments(vtkFirstOrderPreIntegrationTable* table,
  vtkVolumeProperty* property,
  vtkVolumeTransferFunctionSampler* sampler,
  int dataType,
  const double range[2],
  double step)
{
  table->SetVolumeProperty(property);
  table->SetSegmentLength(step);
  table->SetScalarRange(range[0], range[1]);
  // At most 512^2 entries (4 MiB): a finer table falls out of the caches the sample loop
  // relies on, for little gain in accuracy.
  table->SetTableSize(
    vtkPreIntegrationTable::SuggestTableSize(dataType, range, sampler, 256, 512, 8.0));
  if (!table->Update())
  {
    return false;
  }
  this->Segments = table->GetTable()->GetPointer(0);
  this->SegmentEntries = table->GetTableSize();
  this->SegmentInvStep = (this->SegmentEntries - 1) / (range[1] - range[0]);
  return true;
}
