// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
#include "vtkErrorForwarder.h"

#include "vtkCallbackCommand.h"
#include "vtkCommand.h"
#include "vtkNew.h"
#include "vtkObject.h"
#include "vtkOutputWindow.h"

namespace
{
void ForwardEvent(vtkObject*, unsigned long event, void* owner, void* message)
{
  auto* self = static_cast<vtkObject*>(owner);
  if (self->HasObserver(event))
  {
    self->InvokeEvent(event, message);
  }
  else if (event == vtkCommand::ErrorEvent)
  {
    vtkOutputWindowDisplayErrorText(static_cast<const char*>(message));
  }
  else
  {
    vtkOutputWindowDisplayWarningText(static_cast<const char*>(message));
  }
}
}

//------------------------------------------------------------------------------
void vtkErrorForwarder::Forward(vtkObject* helper, vtkObject* owner)
{
  vtkNew<vtkCallbackCommand> command;
  command->SetCallback(ForwardEvent);
  command->SetClientData(owner);
  helper->AddObserver(vtkCommand::ErrorEvent, command);
  helper->AddObserver(vtkCommand::WarningEvent, command);
}
