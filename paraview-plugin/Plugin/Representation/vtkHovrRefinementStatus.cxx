// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
#include "vtkHovrRefinementStatus.h"

#include "vtkHovrVolumeRepresentation.h"
#include "vtkObjectFactory.h"
#include "vtkPVCompositeRepresentation.h"

vtkStandardNewMacro(vtkHovrRefinementStatus);

//------------------------------------------------------------------------------
vtkHovrRefinementStatus::vtkHovrRefinementStatus() = default;

//------------------------------------------------------------------------------
vtkHovrRefinementStatus::~vtkHovrRefinementStatus() = default;

//------------------------------------------------------------------------------
void vtkHovrRefinementStatus::SetRepresentation(vtkPVDataRepresentation* representation)
{
  if (this->Representation != representation)
  {
    this->Representation = representation;
    this->Modified();
  }
}

//------------------------------------------------------------------------------
vtkHovrVolumeRepresentation* vtkHovrRefinementStatus::GetHovr()
{
  vtkPVDataRepresentation* representation = this->Representation;
  if (auto* composite = vtkPVCompositeRepresentation::SafeDownCast(representation))
  {
    representation = composite->GetActiveRepresentation();
  }
  return vtkHovrVolumeRepresentation::SafeDownCast(representation);
}

//------------------------------------------------------------------------------
int vtkHovrRefinementStatus::GetState()
{
  vtkHovrVolumeRepresentation* hovr = this->GetHovr();
  return hovr ? hovr->GetRefinementState() : 0;
}

//------------------------------------------------------------------------------
double vtkHovrRefinementStatus::GetProgress()
{
  vtkHovrVolumeRepresentation* hovr = this->GetHovr();
  return hovr ? hovr->GetRefinementProgress() : 1.0;
}

//------------------------------------------------------------------------------
int vtkHovrRefinementStatus::GetCount()
{
  vtkHovrVolumeRepresentation* hovr = this->GetHovr();
  return hovr ? hovr->GetRefinementCount() : 0;
}

//------------------------------------------------------------------------------
void vtkHovrRefinementStatus::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Representation: " << this->Representation.GetPointer() << "\n";
}
