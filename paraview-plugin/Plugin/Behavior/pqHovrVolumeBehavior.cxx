// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
#include "pqHovrVolumeBehavior.h"

#include "pqApplicationCore.h"
#include "pqCoreUtilities.h"
#include "pqProgressManager.h"
#include "pqRepresentation.h"
#include "pqServerManagerModel.h"
#include "pqView.h"
#include "vtkCallbackCommand.h"
#include "vtkCommand.h"
#include "vtkDataObject.h"
#include "vtkNew.h"
#include "vtkPVXMLElement.h"
#include "vtkSMArrayListDomain.h"
#include "vtkSMPVRepresentationProxy.h"
#include "vtkSMProperty.h"
#include "vtkSMPropertyGroup.h"
#include "vtkSMPropertyHelper.h"
#include "vtkSMPropertyIterator.h"
#include "vtkSMProxy.h"
#include "vtkSMSessionProxyManager.h"

#include <QLabel>
#include <QMainWindow>
#include <QStatusBar>

#include <algorithm>
#include <cstring>
#include <string>

namespace
{
// The representation type hovr adds, and the one ParaView's hints name.
constexpr const char* HovrVolume = "hovr Volume";
constexpr const char* StockVolume = "Volume";

bool IsVolumeDecorator(vtkPVXMLElement* element)
{
  const char* name = element->GetName();
  return name && std::strcmp(name, "PropertyWidgetDecorator") == 0 &&
    std::strcmp(element->GetAttributeOrEmpty("type"), "GenericDecorator") == 0 &&
    std::strcmp(element->GetAttributeOrEmpty("property"), "Representation") == 0 &&
    std::strcmp(element->GetAttributeOrEmpty("value"), StockVolume) == 0 &&
    !element->GetAttribute("hovr");
}

// A GenericDecorator like original but on value, marked as hovr's.
vtkPVXMLElement* CopyDecorator(vtkPVXMLElement* original, const char* value)
{
  vtkPVXMLElement* copy = vtkPVXMLElement::New();
  copy->SetName("PropertyWidgetDecorator");
  for (const char* attribute : { "type", "mode", "property", "inverse", "index" })
  {
    if (const char* v = original->GetAttribute(attribute))
    {
      copy->AddAttribute(attribute, v);
    }
  }
  copy->SetAttribute("value", value);
  copy->AddAttribute("hovr", "1");
  return copy;
}

// Turns element (a decorator on Representation == "Volume") into the same test on "Volume" or
// "hovr Volume" (inverse: on neither): an Expression where the parent is one, else a
// CompositeDecorator holding one.
void Widen(vtkPVXMLElement* element, bool insideExpression)
{
  const bool inverse = std::strcmp(element->GetAttributeOrEmpty("inverse"), "1") == 0;
  vtkPVXMLElement* stock = CopyDecorator(element, StockVolume);
  vtkPVXMLElement* hovr = CopyDecorator(element, HovrVolume);
  vtkPVXMLElement* expression = element;
  if (insideExpression)
  {
    element->SetName("Expression");
  }
  else
  {
    element->SetAttribute("type", "CompositeDecorator");
    expression = vtkPVXMLElement::New();
    expression->SetName("Expression");
    element->AddNestedElement(expression);
    expression->Delete();
  }
  expression->SetAttribute("type", inverse ? "and" : "or");
  element->SetAttribute("hovr", "1");
  expression->AddNestedElement(stock);
  expression->AddNestedElement(hovr);
  stock->Delete();
  hovr->Delete();
}

int WidenRecursively(vtkPVXMLElement* element, bool insideExpression)
{
  int changed = 0;
  // The nested elements are read before any is changed: Widen adds children.
  const unsigned int count = element->GetNumberOfNestedElements();
  for (unsigned int i = 0; i < count; ++i)
  {
    vtkPVXMLElement* child = element->GetNestedElement(i);
    if (IsVolumeDecorator(child))
    {
      Widen(child, insideExpression);
      ++changed;
    }
    else if (!child->GetAttribute("hovr"))
    {
      const char* name = child->GetName();
      changed += WidenRecursively(child, name && std::strcmp(name, "Expression") == 0);
    }
  }
  return changed;
}

// Colours a representation switched to "hovr Volume" by its first point array, as ParaView's
// vtkSMPVRepresentationProxy::SetRepresentationType does for "Volume".
void OnRepresentationModified(vtkObject*, unsigned long, void* clientData, void*)
{
  auto* proxy = static_cast<vtkSMPVRepresentationProxy*>(clientData);
  const char* type = vtkSMPropertyHelper(proxy, "Representation").GetAsString();
  if (!type || std::strcmp(type, HovrVolume) != 0 || proxy->GetUsingScalarColoring())
  {
    return;
  }
  vtkSMProperty* colorArrayName = proxy->GetProperty("ColorArrayName");
  auto* arrays = colorArrayName ? colorArrayName->FindDomain<vtkSMArrayListDomain>() : nullptr;
  if (!arrays)
  {
    return;
  }
  for (unsigned int i = 0; i < arrays->GetNumberOfStrings(); ++i)
  {
    if (arrays->GetFieldAssociation(i) == vtkDataObject::POINT)
    {
      if (proxy->SetScalarColoring(arrays->GetString(i), vtkDataObject::POINT))
      {
        proxy->RescaleTransferFunctionToDataRange(true);
        proxy->UpdateVTKObjects();
      }
      return;
    }
  }
}
}

//------------------------------------------------------------------------------
pqHovrVolumeBehavior::pqHovrVolumeBehavior(QObject* parent)
  : Superclass(parent)
{
  this->Poll.setInterval(100);
  QObject::connect(&this->Poll, &QTimer::timeout, this, &pqHovrVolumeBehavior::onPoll);
}

//------------------------------------------------------------------------------
pqHovrVolumeBehavior::~pqHovrVolumeBehavior() = default;

//------------------------------------------------------------------------------
void pqHovrVolumeBehavior::onStartup()
{
  pqServerManagerModel* model = pqApplicationCore::instance()->getServerManagerModel();
  QObject::connect(model,
    &pqServerManagerModel::representationAdded,
    this,
    &pqHovrVolumeBehavior::onRepresentationAdded);
  QObject::connect(
    model, &pqServerManagerModel::viewAdded, this, &pqHovrVolumeBehavior::onViewAdded);
  for (pqRepresentation* representation : model->findItems<pqRepresentation*>())
  {
    this->onRepresentationAdded(representation);
  }
  for (pqView* view : model->findItems<pqView*>())
  {
    this->onViewAdded(view);
  }
}

//------------------------------------------------------------------------------
void pqHovrVolumeBehavior::onViewAdded(pqView* view)
{
  QObject::connect(view, &pqView::endRender, this, &pqHovrVolumeBehavior::onViewRendered);
}

//------------------------------------------------------------------------------
vtkSMProxy* pqHovrVolumeBehavior::StatusOf(pqRepresentation* representation)
{
  vtkSMProxy* proxy = representation->getProxy();
  // The "hovr Volume" subproxy: the owner of its exposed property.
  vtkSMProperty* property = proxy ? proxy->GetProperty("HovrRefinementState") : nullptr;
  vtkSMProxy* hovr = property ? property->GetParent() : nullptr;
  if (!hovr || !representation->isVisible())
  {
    return nullptr;
  }
  auto found = this->Statuses.find(representation);
  if (found == this->Statuses.end())
  {
    vtkSmartPointer<vtkSMProxy> status;
    status.TakeReference(
      hovr->GetSessionProxyManager()->NewProxy("hovr_misc", "HovrRefinementStatus"));
    if (!status)
    {
      return nullptr;
    }
    vtkSMPropertyHelper(status, "Representation").Set(hovr);
    status->UpdateVTKObjects();
    found = this->Statuses.emplace(representation, status).first;
    QObject::connect(representation,
      &QObject::destroyed,
      this,
      [this, representation]() { this->Statuses.erase(representation); });
  }
  return found->second;
}

//------------------------------------------------------------------------------
int pqHovrVolumeBehavior::RefinementState(pqView* view)
{
  int state = 0;
  for (pqRepresentation* representation : view->getRepresentations())
  {
    if (vtkSMProxy* status = this->StatusOf(representation))
    {
      status->UpdatePropertyInformation(); // one request for state, progress and count
      state = std::max(state, vtkSMPropertyHelper(status, "State").GetAsInt());
    }
  }
  return state;
}

//------------------------------------------------------------------------------
double pqHovrVolumeBehavior::RefinementProgress(pqView* view)
{
  double progress = 1.0;
  for (pqRepresentation* representation : view->getRepresentations())
  {
    if (vtkSMProxy* status = this->StatusOf(representation))
    {
      progress = std::min(progress, vtkSMPropertyHelper(status, "Progress").GetAsDouble());
    }
  }
  return progress;
}

//------------------------------------------------------------------------------
void pqHovrVolumeBehavior::onViewRendered()
{
  auto* view = qobject_cast<pqView*>(this->sender());
  const int state = view ? RefinementState(view) : 0;
  // A render of a refined table (or oracle) that leaves nothing refining ends a refinement (a
  // provisional table is followed by the measured one).
  if (view && this->Finishing.removeAll(view) > 0 && state == 0)
  {
    this->CountRefinement();
  }
  if (!view || this->Refining.contains(view) || state == 0)
  {
    return;
  }
  this->Refining.push_back(view);
  this->ShowStatus(tr("hovr: refining in the background"));
  this->ShowProgress(0);
  if (!this->Poll.isActive())
  {
    this->Poll.start();
  }
}

//------------------------------------------------------------------------------
void pqHovrVolumeBehavior::CountRefinement()
{
  ++this->Refinements;
  if (this->Status)
  {
    this->Status->setToolTip(tr("hovr: %1 refinements completed").arg(this->Refinements));
  }
}

//------------------------------------------------------------------------------
void pqHovrVolumeBehavior::ShowStatus(const QString& text)
{
  if (!this->Status)
  {
    auto* window = qobject_cast<QMainWindow*>(pqCoreUtilities::mainWidget());
    if (!window)
    {
      return;
    }
    this->Status = new QLabel(window->statusBar());
    this->Status->setObjectName("hovrRefinementStatus");
    window->statusBar()->addPermanentWidget(this->Status);
  }
  this->Status->setText(text);
}

//------------------------------------------------------------------------------
void pqHovrVolumeBehavior::onPoll()
{
  QVector<QPointer<pqView>> still;
  for (const QPointer<pqView>& view : this->Refining)
  {
    if (!view)
    {
      continue;
    }
    const int state = RefinementState(view);
    if (state == 2)
    {
      // Its end re-enters onViewRendered, which polls again if another change is refining.
      this->ShowStatus(tr("hovr: refined"));
      this->Finishing.push_back(view);
      view->render();
    }
    else if (state == 0)
    {
      // Ended without a render: the measurement confirmed the table the view draws.
      this->ShowStatus(tr("hovr: refined"));
      this->CountRefinement();
    }
    else
    {
      still.push_back(view);
      const int percent = static_cast<int>(100.0 * RefinementProgress(view));
      this->ShowStatus(tr("hovr: refining in the background (%1%)").arg(percent));
      this->ShowProgress(percent);
    }
  }
  this->Refining = still;
  if (this->Refining.isEmpty())
  {
    this->Poll.stop();
    this->HideProgress();
  }
}

//------------------------------------------------------------------------------
void pqHovrVolumeBehavior::ShowProgress(int percent)
{
  pqProgressManager* manager = pqApplicationCore::instance()->getProgressManager();
  if (!manager)
  {
    return;
  }
  if (!this->ProgressShown)
  {
    // An enabled progress bar blocks mouse and key input, which must go on while refining.
    this->ProgressUnblocked = manager->unblockEvents(true);
    manager->setEnableProgress(true);
    this->ProgressShown = true;
  }
  manager->setProgress(tr("hovr: refining"), percent);
}

//------------------------------------------------------------------------------
void pqHovrVolumeBehavior::HideProgress()
{
  pqProgressManager* manager = pqApplicationCore::instance()->getProgressManager();
  if (!manager || !this->ProgressShown)
  {
    return;
  }
  manager->setEnableProgress(false);
  manager->unblockEvents(this->ProgressUnblocked);
  this->ProgressShown = false;
}

//------------------------------------------------------------------------------
void pqHovrVolumeBehavior::onShutdown()
{
  this->Statuses.clear();
}

//------------------------------------------------------------------------------
int pqHovrVolumeBehavior::WidenVolumeDecorators(vtkPVXMLElement* hints)
{
  return hints ? WidenRecursively(hints, false) : 0;
}

//------------------------------------------------------------------------------
void pqHovrVolumeBehavior::onRepresentationAdded(pqRepresentation* representation)
{
  auto* proxy = vtkSMPVRepresentationProxy::SafeDownCast(representation->getProxy());
  // Only the representations that offer "hovr Volume" (image data) change.
  if (!proxy || !proxy->GetProperty("HovrIntegration"))
  {
    return;
  }
  for (size_t i = 0; i < proxy->GetNumberOfPropertyGroups(); ++i)
  {
    WidenVolumeDecorators(proxy->GetPropertyGroup(i)->GetHints());
  }
  vtkNew<vtkSMPropertyIterator> properties;
  properties->SetProxy(proxy);
  for (properties->Begin(); !properties->IsAtEnd(); properties->Next())
  {
    WidenVolumeDecorators(properties->GetProperty()->GetHints());
  }
  // The GUI answers every edit at once and refines after; pvbatch and pvpython keep the
  // default (frames wait for their measured tables).
  if (vtkSMProperty* refine = proxy->GetProperty("HovrRefineInBackground"))
  {
    vtkSMPropertyHelper(refine).Set(1);
    proxy->UpdateVTKObjects();
  }
  if (vtkSMProperty* type = proxy->GetProperty("Representation"))
  {
    vtkNew<vtkCallbackCommand> callback;
    callback->SetCallback(&OnRepresentationModified);
    callback->SetClientData(proxy);
    type->AddObserver(vtkCommand::ModifiedEvent, callback);
  }
}
