// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
/**
 * @class   vtkErrorForwarder
 * @brief   reports the errors and warnings of an internal helper object as its owner's
 *
 * hovr classes delegate to helpers they own (a mapper to its table, a table to its
 * transfer-function sampler). A user observing errors on the public object would otherwise
 * miss the helpers' messages. Forward(helper, owner) makes the owner fire the helper's
 * ErrorEvent and WarningEvent (or print them when the owner has no observer). Not wrapped.
 */
#ifndef vtkErrorForwarder_h
#define vtkErrorForwarder_h

#include "hovrRenderingCoreModule.h" // For export macro

class vtkObject;

class HOVRRENDERINGCORE_EXPORT vtkErrorForwarder
{
public:
  /**
   * Forward the helper's error and warning events to owner, which must outlive the helper's
   * use (typically: the owner owns the helper).
   */
  static void Forward(vtkObject* helper, vtkObject* owner);
};

#endif
