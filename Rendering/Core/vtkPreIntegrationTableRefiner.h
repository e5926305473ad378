// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
/**
 * @class   vtkPreIntegrationTableRefiner
 * @brief   measures and builds pre-integration tables in a worker thread, the newest request
 *          winning
 *
 * A renderer that answers an edit (of the transfer functions, the data, the sample distance
 * or the order) at once draws with a table that is cheap to get, and asks the refiner for the
 * measured one:
 *   - Request() takes a snapshot of what the table depends on: the volume and its scalars
 *     (held by reference), copies of the transfer functions (made only when they changed
 *     since the last request), the table's settings and the settings of GetSizerSettings();
 *     it stops the work of any earlier request at its next check
 *     (vtkPreIntegrationTableSizer::Abort, the table's AbortBuild), so that a drag of edits
 *     measures only its last;
 *   - the worker chooses the sizes with one vtkPreIntegrationTableSizer kept across requests,
 *     so that what an edit does not change is not measured again (the rays' pieces across
 *     edits of the transfer functions, their reference across changes of step or order),
 *     and builds the table on the CPU unless asked not to;
 *   - IsReady() tells when a request's result waits, and TakeResult() gives it to the
 *     caller's table: the sizes, ranges and prefilter it chose and, when built, the entries
 *     (vtkPreIntegrationTable::AdoptBuild). Only the newest request's result is kept.
 * Wait() blocks until the newest request is done (batch use). Results are polled, never
 * called back: the worker touches nothing but its snapshot, and whatever renders stays on the
 * thread that renders. The volume's scalars must not be changed in place while a request is
 * measured (a changed array is a new request: its modification time changes).
 *
 * The worker fires no VTK events. Statistics: GetNumberOfRequests(), GetNumberOfCompleted(),
 * GetNumberOfStopped(), GetLastRefinementTime() and the sizer's figures of the last completed
 * request (GetLastSizer()).
 *
 * @sa vtkPreIntegrationTableSizer vtkSecondOrderPreIntegrationTable
 */
#ifndef vtkPreIntegrationTableRefiner_h
#define vtkPreIntegrationTableRefiner_h

#include "hovrRenderingCoreModule.h" // For export macro
#include "vtkObject.h"

#include <memory> // For std::unique_ptr
#include <string> // For GetFailure

class vtkDataArray;
class vtkImageData;
class vtkPreIntegrationTableSizer;
class vtkSecondOrderPreIntegrationTable;

class HOVRRENDERINGCORE_EXPORT vtkPreIntegrationTableRefiner : public vtkObject
{
public:
  static vtkPreIntegrationTableRefiner* New();
  vtkTypeMacro(vtkPreIntegrationTableRefiner, vtkObject);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /**
   * Work in threads of low priority (vtkLowPriorityThreads: nice 10 on Linux; elsewhere
   * normal priority): rendering, on the CPU with a software OpenGL as on a GPU, is barely
   * slowed by a measurement, which still goes on beside other busy programs. Off:
   * vtkSMPTools' threads at normal priority. Read at each Request(). Initial value is true.
   */
  vtkSetMacro(LowPriority, bool);
  vtkGetMacro(LowPriority, bool);
  vtkBooleanMacro(LowPriority, bool);
  ///@}

  /**
   * The sizer settings every request copies (vtkPreIntegrationTableSizer::CopySettings): set
   * them here. Its measurements are not the worker's (see GetLastSizer()).
   */
  vtkPreIntegrationTableSizer* GetSizerSettings() { return this->SizerSettings; }

  /**
   * Ask for the table like `table` (its transfer functions, scalar range, segment length,
   * iterations, prefilter and moment layers) with sizes measured for the scalars of volume
   * at this order (1 or 2) and sample distance, its deviation axis at most deviationLimit
   * entries, built on the CPU when buildEntries. With provisional (and buildEntries), a table
   * of table's present sizes, ranges and prefilter is built first and given as a provisional
   * result (IsProvisional); when table holds a complete build at those settings, its entries
   * move to the worker (vtkSecondOrderPreIntegrationTable::TakeEntries: table is left without
   * them, as the caller draws other sizes meanwhile), and only those that read what the change
   * reached are integrated again, as they are from a stopped request's provisional table
   * during a drag. With drawn, the caller draws table's present sizes itself (it
   * builds them for the change): when the measurement finds them, the result is a
   * confirmation (IsConfirmation) and nothing is built. Stops earlier requests. Returns the
   * request's number (positive), or 0 after an error (bad arguments, or the worker could not
   * start).
   */
  vtkIdType Request(vtkImageData* volume,
    vtkDataArray* scalars,
    vtkSecondOrderPreIntegrationTable* table,
    int order,
    double sampleDistance,
    int deviationLimit,
    bool buildEntries,
    bool provisional = false,
    bool drawn = false);

  /**
   * Stop the current request and drop any result.
   */
  void Cancel();

  /**
   * Whether the worker is measuring or building (a request not yet done).
   */
  bool IsBusy();

  /**
   * Whether a result of request `request` waits (it is the newest, and not taken): its
   * provisional table, or its measured one.
   */
  bool IsReady(vtkIdType request);

  /**
   * Whether the result of request `request` that waits is provisional: with `provisional` set,
   * a request whose table's sizes were measured before first builds a table of those sizes
   * for the new transfer functions, data or step (what a small edit most often measures again),
   * gives it as a provisional result, and then measures. When the measured sizes are the same,
   * its final result is that table again (TakeResult then changes nothing); otherwise it is the
   * measured table. Only with buildEntries.
   */
  bool IsProvisional(vtkIdType request);

  /**
   * Whether the final result of request `request` is the provisional table already taken:
   * TakeResult() then only ends the request, and a frame would draw the same image.
   */
  bool IsConfirmation(vtkIdType request);

  /**
   * Give the result of request `request` to table: its sizes, ranges and prefilter, and its
   * entries when they were built and table takes them (AdoptBuild; otherwise table's next
   * Update() builds them). The table must have the settings the request was made with. False
   * when no such result waits, or the request failed (its table is then left unchanged).
   */
  bool TakeResult(vtkIdType request, vtkSecondOrderPreIntegrationTable* table);

  /**
   * Whether request `request` ended without a result (an error of the sizer or the build).
   */
  bool Failed(vtkIdType request);

  /**
   * The error message of request `request` when it Failed() (the worker's messages are kept,
   * not printed from its thread), else empty.
   */
  std::string GetFailure(vtkIdType request);

  /**
   * Block until no request is being worked on (a request held by Paused is not).
   */
  void Wait();

  ///@{
  /**
   * Hold requests without starting them (the one being worked on goes on): an application
   * that refines only when it is idle, or a test that checks that nothing waits for the
   * worker. Initial value is false.
   */
  virtual void SetPaused(bool paused);
  virtual bool GetPaused();
  vtkBooleanMacro(Paused, bool);
  ///@}

  ///@{
  /**
   * Requests made, completed with a result, and stopped (superseded or cancelled).
   */
  vtkIdType GetNumberOfRequests();
  vtkIdType GetNumberOfCompleted();
  vtkIdType GetNumberOfStopped();
  ///@}

  /**
   * How far the request being worked on is, in [0, 1]: the sizer's progress
   * (vtkPreIntegrationTableSizer::GetProgress) for nine tenths, then the build; 1 when idle.
   */
  double GetProgress();

  /**
   * Wall time in seconds of the last completed request, from its start in the worker to its
   * result (the sizer and the build).
   */
  double GetLastRefinementTime();

  /**
   * Copy into `into` what the worker's sizer measured for the last completed request
   * (vtkPreIntegrationTableSizer::CopyStatistics: candidates, chosen candidate, errors, time).
   */
  void GetLastSizer(vtkPreIntegrationTableSizer* into);

protected:
  vtkPreIntegrationTableRefiner();
  ~vtkPreIntegrationTableRefiner() override;

  vtkPreIntegrationTableSizer* SizerSettings;
  bool LowPriority = true;

private:
  vtkPreIntegrationTableRefiner(const vtkPreIntegrationTableRefiner&) = delete;
  void operator=(const vtkPreIntegrationTableRefiner&) = delete;

  struct vtkInternals;
  std::unique_ptr<vtkInternals> Internals;
};

#endif
