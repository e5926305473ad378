// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
/**
 * @class   vtkHovrRefinementStatus
 * @brief   where a "hovr Volume"'s background refinement stands, read where it draws
 *
 * ParaView reads a proxy's information properties from the client's own object when the proxy
 * lives on the client too, as every representation does: connected to a pvserver, the
 * client's twin of a vtkHovrVolumeRepresentation draws no volume and never refines, so its
 * HovrRefinementState says nothing of the server's. This object lives on the render server
 * only (the "HovrRefinementStatus" proxy, processes="renderserver"), is given the
 * representation's proxy (Representation, the "hovr Volume" subproxy or its composite
 * representation), and answers for the representation object on the server (the root rank
 * under MPI): the GUI's behaviour and scripts ask it, in every kind of session.
 */
#ifndef vtkHovrRefinementStatus_h
#define vtkHovrRefinementStatus_h

#include "hovrParaViewRepresentationModule.h" // For export macro
#include "vtkObject.h"
#include "vtkWeakPointer.h" // For ivar

class vtkHovrVolumeRepresentation;
class vtkPVDataRepresentation;

class HOVRPARAVIEWREPRESENTATION_EXPORT vtkHovrRefinementStatus : public vtkObject
{
public:
  static vtkHovrRefinementStatus* New();
  vtkTypeMacro(vtkHovrRefinementStatus, vtkObject);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  /**
   * The representation to answer for: a vtkHovrVolumeRepresentation, or a composite
   * representation whose active one is (held weakly; initially none).
   */
  void SetRepresentation(vtkPVDataRepresentation* representation);

  /**
   * vtkHovrVolumeRepresentation::GetRefinementState, GetRefinementProgress and
   * GetRefinementCount of the representation: 0, 1 and 0 without one.
   */
  int GetState();
  double GetProgress();
  int GetCount();

protected:
  vtkHovrRefinementStatus();
  ~vtkHovrRefinementStatus() override;

private:
  vtkHovrRefinementStatus(const vtkHovrRefinementStatus&) = delete;
  void operator=(const vtkHovrRefinementStatus&) = delete;
  vtkHovrVolumeRepresentation* GetHovr();

  vtkWeakPointer<vtkPVDataRepresentation> Representation;
};

#endif
