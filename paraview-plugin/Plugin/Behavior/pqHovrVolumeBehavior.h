// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
/**
 * @class   pqHovrVolumeBehavior
 * @brief   makes "hovr Volume" behave like ParaView's "Volume" in the GUI
 *
 * ParaView's panel and representation switch treat the representation named "Volume"
 * specially: the "Volume Rendering" group (blend mode, opacity unit distance, shading,
 * isovalues, cropping) is shown only for it, surface-only properties (point size, line width,
 * textures, backface styling) are hidden for it, and switching to it colours by the active
 * point scalars. This behaviour, started with the GUI, gives "hovr Volume" the same:
 *   - every panel decorator of an image representation that tests Representation == "Volume"
 *     is widened to "Volume" or "hovr Volume" (and "not Volume" to "neither"), in the proxy's
 *     hints, before its panel is built;
 *   - switching a representation to "hovr Volume" colours it by its first point array, with
 *     the transfer functions rescaled to the data range, as ParaView does for "Volume";
 *   - every new "hovr Volume" refines its tables in the background (HovrRefineInBackground:
 *     an edit is drawn at once with interim table sizes), and after each render of a view
 *     that draws interim tables the behaviour asks the representations, every 100 ms, where
 *     their measurement stands (a "HovrRefinementStatus" proxy each, which answers where the
 *     volume is drawn, the server in client-server) and renders the view again when a
 *     measured table (or oracle) waits; a label in the main window's status bar says so
 *     ("hovrRefinementStatus": refining, with how far the measurement is, then refined; its
 *     tool tip counts the refinements completed in the session), and
 *     ParaView's progress bar shows how far it is, without blocking the user's input (the
 *     work is in the background: the view stays interactive).
 */
#ifndef pqHovrVolumeBehavior_h
#define pqHovrVolumeBehavior_h

#include <QObject>
#include <QPointer>
#include <QTimer>
#include <QVector>

#include "vtkSmartPointer.h" // For ivar

#include <map> // For ivar

class QLabel;
class pqRepresentation;
class pqView;
class vtkPVXMLElement;
class vtkSMProxy;

class pqHovrVolumeBehavior : public QObject
{
  Q_OBJECT
  using Superclass = QObject;

public:
  pqHovrVolumeBehavior(QObject* parent = nullptr);
  ~pqHovrVolumeBehavior() override;

  void onStartup();
  void onShutdown();

  /**
   * Widens the decorators on Representation == "Volume" found in hints (recursively) to
   * include "hovr Volume"; returns how many it changed. Elements it made are marked and left
   * alone on a second pass.
   */
  static int WidenVolumeDecorators(vtkPVXMLElement* hints);

private Q_SLOTS:
  void onRepresentationAdded(pqRepresentation* representation);
  void onViewAdded(pqView* view);
  // After a view's render: poll it while its hovr representations draw interim tables.
  void onViewRendered();
  void onPoll();

private:
  // Where the hovr representations of a view stand: the largest refinement state, asked of
  // their status proxies.
  int RefinementState(pqView* view);
  // How far their measurements are (the least), in [0, 1], as the last RefinementState heard.
  double RefinementProgress(pqView* view);
  // The "HovrRefinementStatus" proxy of a visible "hovr Volume" representation (made on first
  // use, released with the representation); null for other representations. It answers where
  // the volume is drawn: the server, when there is one.
  vtkSMProxy* StatusOf(pqRepresentation* representation);
  std::map<pqRepresentation*, vtkSmartPointer<vtkSMProxy>> Statuses;
  // Shows what the refinement does in the status bar (made on first use).
  void ShowStatus(const QString& text);
  // One more refinement completed, in the status label's tooltip.
  void CountRefinement();
  QVector<QPointer<pqView>> Refining;
  QTimer Poll;
  QPointer<QLabel> Status;
  // Views rendered for a refined table or oracle, and the refinements completed (in the
  // label's tool tip).
  QVector<QPointer<pqView>> Finishing;
  int Refinements = 0;
  // Whether the progress bar is ours, and the progress manager's input blocking before.
  bool ProgressShown = false;
  bool ProgressUnblocked = false;
  void ShowProgress(int percent);
  void HideProgress();
  Q_DISABLE_COPY(pqHovrVolumeBehavior)
};

#endif
