// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
#include "vtkPreIntegrationTableSizing.h"

#include "vtkDataArray.h"
#include "vtkImageData.h"
#include "vtkObjectFactory.h"
#include "vtkPreIntegrationTableRefiner.h"
#include "vtkPreIntegrationTableSizer.h"
#include "vtkSecondOrderPreIntegrationTable.h"

#include <algorithm>
#include <string>

vtkStandardNewMacro(vtkPreIntegrationTableSizing);

//------------------------------------------------------------------------------
vtkPreIntegrationTableSizing::vtkPreIntegrationTableSizing()
  : Sizer(vtkPreIntegrationTableSizer::New())
  , Refiner(vtkPreIntegrationTableRefiner::New())
{
}

//------------------------------------------------------------------------------
vtkPreIntegrationTableSizing::~vtkPreIntegrationTableSizing()
{
  this->Refiner->Delete();
  this->Sizer->Delete();
}

//------------------------------------------------------------------------------
void vtkPreIntegrationTableSizing::Reset()
{
  this->Key.clear();
  this->Interim = false;
  this->Request = 0;
  this->Refiner->Cancel();
}

//------------------------------------------------------------------------------
void vtkPreIntegrationTableSizing::MarkMeasured(vtkSecondOrderPreIntegrationTable* table)
{
  if (std::find(this->MeasuredTables.begin(), this->MeasuredTables.end(), table) ==
    this->MeasuredTables.end())
  {
    this->MeasuredTables.push_back(table);
  }
}

//------------------------------------------------------------------------------
bool vtkPreIntegrationTableSizing::Update(const std::vector<double>& key,
  vtkImageData* volume,
  vtkDataArray* scalars,
  vtkSecondOrderPreIntegrationTable* table,
  int order,
  double sampleDistance,
  int deviationLimit,
  bool buildEntries)
{
  if (!table)
  {
    return false;
  }
  if (key == this->Key && !this->Key.empty())
  {
    if (!this->Interim)
    {
      return true;
    }
    if (this->Refiner->TakeResult(this->Request, table))
    {
      this->Refiner->GetLastSizer(this->Sizer);
      this->Interim = false;
      this->MarkMeasured(table);
      return true;
    }
    if (this->Refiner->Failed(this->Request))
    {
      // The interim table stays: it is a table of the right transfer functions, only not
      // of measured sizes.
      vtkErrorMacro("The table sizes could not be measured in the background ("
        << this->Refiner->GetFailure(this->Request) << "); the interim table stays.");
      this->Interim = false;
    }
    return true;
  }

  this->Key = key;
  this->Interim = false;
  this->Request = 0;
  if (!this->RefineInBackground)
  {
    this->Refiner->Cancel();
    if (!this->Sizer->Choose(volume, scalars, table, order, sampleDistance))
    {
      this->Key.clear();
      return false;
    }
    if (order == 2)
    {
      table->SetDeviationSize(std::min(table->GetDeviationSize(), std::max(deviationLimit, 1)));
    }
    this->MarkMeasured(table);
    return true;
  }

  this->Refiner->GetSizerSettings()->CopySettings(this->Sizer);
  this->Request = this->Refiner->Request(
    volume, scalars, table, order, sampleDistance, deviationLimit, buildEntries);
  if (this->Request <= 0)
  {
    this->Key.clear();
    return false;
  }
  this->Interim = true;
  ++this->NumberOfInterimTables;
  this->SetInterimSizes(table, order, deviationLimit);
  return true;
}

//------------------------------------------------------------------------------
void vtkPreIntegrationTableSizing::SetInterimSizes(vtkSecondOrderPreIntegrationTable* table,
  int order,
  int deviationLimit)
{
  const bool measured =
    std::find(this->MeasuredTables.begin(), this->MeasuredTables.end(), table) !=
    this->MeasuredTables.end();
  int sizes[3];
  if (measured)
  {
    sizes[0] = table->GetTableSize();
    sizes[1] = table->GetChordSize();
    sizes[2] = order == 2 ? table->GetDeviationSize() : 1;
  }
  else
  {
    // Every chord and deviation the range allows: what any data produces at any step.
    const int n = order == 2 ? 65 : 129;
    sizes[0] = n;
    sizes[1] = n;
    sizes[2] = order == 2 ? n : 1;
    table->SetChordRange(0.0);
    table->SetDeviationRange(0.0);
  }
  sizes[2] = std::min(sizes[2], std::max(deviationLimit, 1));
  // Halve the axes (2^k + 1 entries stay so, odd chord and deviation axes stay odd) until
  // the table is within InterimEntries.
  auto entries = [&]() { return static_cast<double>(sizes[0]) * sizes[1] * sizes[2]; };
  while (entries() > this->InterimEntries && (sizes[0] > 3 || sizes[1] > 3 || sizes[2] > 3))
  {
    for (int& size : sizes)
    {
      if (size > 3)
      {
        size = (size - 1) / 2 + ((size - 1) / 2) % 2 + 1;
      }
    }
  }
  table->SetTableSize(std::max(sizes[0], 2));
  table->SetChordSize(sizes[1]);
  table->SetDeviationSize(sizes[2]);
}

//------------------------------------------------------------------------------
bool vtkPreIntegrationTableSizing::IsRefining()
{
  return this->Interim;
}

//------------------------------------------------------------------------------
bool vtkPreIntegrationTableSizing::IsRefinementReady()
{
  return this->Interim &&
    (this->Refiner->IsReady(this->Request) || this->Refiner->Failed(this->Request));
}

//------------------------------------------------------------------------------
void vtkPreIntegrationTableSizing::WaitForRefinement()
{
  if (this->Interim)
  {
    this->Refiner->Wait();
  }
}

//------------------------------------------------------------------------------
void vtkPreIntegrationTableSizing::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "RefineInBackground: " << this->RefineInBackground << "\n";
  os << indent << "InterimEntries: " << this->InterimEntries << "\n";
  os << indent << "NumberOfInterimTables: " << this->NumberOfInterimTables << "\n";
  os << indent << "Interim: " << this->Interim << "\n";
}
