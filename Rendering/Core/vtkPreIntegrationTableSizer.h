// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
/**
 * @class   vtkPreIntegrationTableSizer
 * @brief   chooses the sizes of a pre-integration table by measuring candidate tables
 *
 * A table's entries sample a function of the segment's scalars; between them the renderer
 * interpolates, and how many entries an image needs depends on the transfer function (how
 * narrow its features are), on the data (which scalars, chords and deviations the rays meet at
 * this step, and where they linger) and on the step. No rule fitted to a few transfer
 * functions holds for all of them, so the sizer measures instead:
 *   1. it casts NumberOfRays random rays through the volume (uniform directions, uniform over
 *      each direction's projected disc, from a fixed Seed: the choice does not depend on the
 *      camera, and repeats) and integrates them with vtkVolumeReferenceIntegrator;
 *   2. it marches them as the GLSL does (vtkPreIntegrationRayMarch) and keeps the pieces
 *      (segments or slabs: their table axes and length) of every ray, which depend on the
 *      volume, the order and the step but not on the transfer functions; the largest chord
 *      |back - front| and deviation |middle - centre| they meet (times 1.25) are the extents
 *      the table's ChordRange and DeviationRange must cover;
 *   3. it composites the kept pieces with candidate tables (vtkSecondOrderPreIntegrationTable:
 *      TableSize entries on the centre axis, 2^k + 1; chord and deviation spacings 1, 2, 4 or
 *      8 times the centre spacing, over whole spacings that cover the measured extents),
 *      computing only the entries the rays read (vtkSecondOrderPreIntegrationTableKernel, the
 *      builders' own integration) and each once for all the candidates of a centre size
 *      (vtkPreIntegrationCandidateEntries: their entries lie on the finest one's grid; with
 *      KeepEntries they outlive the Choose(), and an edit of the transfer functions
 *      integrates again only the entries that read what changed), and with the exact segment
 *      model (each piece integrated along its model path, no table). A piece whose
 *      entries, for every candidate of a centre size, lie inside one zero-opacity run of the
 *      transfer functions adds exactly nothing and is left out of that size's compositing,
 *      and the exact model skips such paths too. Each candidate is
 *      measured on the first ScreeningFraction of the rays first; those rays drop, with
 *      confidence, the candidates out of twice the Tolerance of the best so far, and the
 *      others are measured on all the rays;
 *   4. it keeps the candidate (not dropped) with the least memory whose error against the
 *      reference (RMSE of premultiplied RGBA over the rays) is, with confidence, within
 *      Tolerance of the least error measured, on all the rays and on each half of them: the
 *      per-ray differences to the best candidate must stay below the allowance by two of
 *      their standard errors. The per-ray errors are heavy-tailed (rays grazing a sharp
 *      feature carry most of the error), and a table good only by the luck of a few rays
 *      should not be chosen. When the halves' bests differ by more than their rays resolve,
 *      so that no candidate is good on both, it keeps the least memory good on all the rays
 *      and one half (else the best). The table's own sizes (an earlier Choose()'s) stay when
 *      they are good on all the rays and one half at least and take at most twice the least
 *      memory: near-equal candidates would otherwise trade places from edit to edit, each
 *      trade rebuilding the table.
 * Every candidate within MaximumMemory (at BytesPerEntry) and MaximumAxisSize is measured (on
 * the screening rays at least), centre size by centre size from the coarsest: a coarse axis
 * can measure better than a finer one on one axis and not another, so a search that skips
 * candidates misses the best. Finer
 * centre sizes converge to the exact segment model, so with StopAtConvergence the search stops
 * after the first centre size whose best is, with confidence, within half the Tolerance of that
 * model's error (or better), or after two centre sizes in a row whose best improves on the
 * coarser sizes' best by less than half the Tolerance (one is not enough: a size too coarse
 * for a narrow feature can stall before the next resolves it). The rays are
 * quasi-random (a shifted Halton sequence), whose error estimates vary less between seeds than
 * independent random rays'. A coarse table can measure better than finer ones (its interpolation
 * can offset the segment model's own error); the sizer then keeps it, as it measures.
 */
#ifndef vtkPreIntegrationTableSizer_h
#define vtkPreIntegrationTableSizer_h

#include "hovrRenderingCoreModule.h" // For export macro
#include "vtkObject.h"

#include <memory> // For std::unique_ptr

class vtkDataArray;
class vtkDoubleArray;
class vtkImageData;
class vtkPreIntegrationCandidateEntries;
class vtkSecondOrderPreIntegrationTable;

class HOVRRENDERINGCORE_EXPORT vtkPreIntegrationTableSizer : public vtkObject
{
public:
  static vtkPreIntegrationTableSizer* New();
  vtkTypeMacro(vtkPreIntegrationTableSizer, vtkObject);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /**
   * Random rays the candidates are measured on. Initial value is 2048.
   */
  vtkSetClampMacro(NumberOfRays, int, 8, 1 << 20);
  vtkGetMacro(NumberOfRays, int);
  ///@}

  ///@{
  /**
   * Seed of the random rays. Initial value is 1.
   */
  vtkSetMacro(Seed, int);
  vtkGetMacro(Seed, int);
  ///@}

  ///@{
  /**
   * A candidate whose error is, with confidence, at most (1 + Tolerance) times the least error
   * measured counts as good. Initial value is 0.02.
   */
  vtkSetClampMacro(Tolerance, double, 0.0, 10.0);
  vtkGetMacro(Tolerance, double);
  ///@}

  ///@{
  /**
   * Largest table considered, in bytes at BytesPerEntry. Initial value is 64 MiB.
   */
  vtkSetClampMacro(MaximumMemory, double, 1024.0, 1e12);
  vtkGetMacro(MaximumMemory, double);
  ///@}

  ///@{
  /**
   * Bytes of one entry where the table is stored (8: RGBA half floats). Initial value is 8.
   */
  vtkSetClampMacro(BytesPerEntry, int, 1, 64);
  vtkGetMacro(BytesPerEntry, int);
  ///@}

  ///@{
  /**
   * Most entries along one axis (a texture size limit). Initial value is 4097.
   */
  vtkSetClampMacro(MaximumAxisSize, int, 3, 65536);
  vtkGetMacro(MaximumAxisSize, int);
  ///@}

  ///@{
  /**
   * The reference integrator's ScalarTolerance for the ground truth along the rays: its
   * error is a floor under every error measured. Initial value is the integrator's, 1/64.
   */
  vtkSetClampMacro(ReferenceTolerance, double, 1e-4, 1.0);
  vtkGetMacro(ReferenceTolerance, double);
  ///@}

  ///@{
  /**
   * Also integrate the exact segment model (each segment's or slab's model path, no table)
   * along the rays when StopAtConvergence is off, for GetExactError() (with StopAtConvergence
   * it is always integrated: the search stops against it); it costs about as much as the
   * reference. Initial value is false.
   */
  vtkSetMacro(MeasureExactModel, bool);
  vtkGetMacro(MeasureExactModel, bool);
  vtkBooleanMacro(MeasureExactModel, bool);
  ///@}

  ///@{
  /**
   * Measure every candidate size both with and without the prefilter
   * (vtkSecondOrderPreIntegrationTable::Prefilter) and let Choose() set the table's Prefilter
   * to the chosen candidate's; otherwise the table's own Prefilter is kept and measured. The
   * prefilter keeps a narrow feature's integral over scalar values and blurs it along rays that
   * linger near it: which of the two matters more depends on the transfer function and the
   * data, so it is measured like a size. It doubles the measuring time. Initial value is false.
   */
  vtkSetMacro(MeasurePrefilter, bool);
  vtkGetMacro(MeasurePrefilter, bool);
  vtkBooleanMacro(MeasurePrefilter, bool);
  ///@}

  ///@{
  /**
   * Stop measuring finer centre sizes once they stop improving the best error (see the class
   * documentation); off measures every candidate that fits. Initial value is true.
   */
  vtkSetMacro(StopAtConvergence, bool);
  vtkGetMacro(StopAtConvergence, bool);
  vtkBooleanMacro(StopAtConvergence, bool);
  ///@}

  ///@{
  /**
   * The fraction of the rays each candidate is measured on first (the first of the
   * quasi-random rays, which spread evenly). A candidate that these rays tell, with
   * confidence, is out of twice the Tolerance of the best candidate measured so far is
   * dropped (GetCandidateDropped(): its error is then over these rays alone, and it is not
   * chosen); the others are measured on all the rays, and the search's rules and the choice
   * use all the rays. 1 measures every candidate on all the rays. Initial value is 0.25.
   */
  vtkSetClampMacro(ScreeningFraction, double, 0.01, 1.0);
  vtkGetMacro(ScreeningFraction, double);
  ///@}

  ///@{
  /**
   * Keep the entries the candidates of the last centre size measured shared (see class
   * documentation; the largest, where most entries are integrated) from one Choose() to the
   * next: after an edit of the transfer functions, that grid measured again integrates only
   * the entries whose paths read a changed sample (a narrow edit changes few), the others
   * keep their values bit for bit. They take up to 17 bytes per entry of the grid (at most
   * twice MaximumMemory's entries), reserved but touched only where rays read, held between
   * measurements; a Choose() holds them beside the centre size it measures until it reaches
   * their grid. Initial value is true.
   */
  vtkSetMacro(KeepEntries, bool);
  vtkGetMacro(KeepEntries, bool);
  vtkBooleanMacro(KeepEntries, bool);
  ///@}

  ///@{
  /**
   * Rays stop once their opacity exceeds this value, as the renderer's. Initial value is
   * 1 - 1/255.
   */
  vtkSetClampMacro(OpacityThreshold, double, 0.0, 1.0);
  vtkGetMacro(OpacityThreshold, double);
  ///@}

  /**
   * Choose and set the sizes and ranges of table (TableSize, ChordSize, ChordRange,
   * DeviationSize, DeviationRange) for rendering the point scalars of volume with samples
   * sampleDistance (world units) apart, composited in order 1 (segments: the table gets
   * DeviationSize 1) or 2 (slabs): Prepare(), then the search. The table must have its
   * transfer functions, scalar range and segment length set (sampleDistance, or twice it for
   * order 2); its Iterations are kept, and its Prefilter unless MeasurePrefilter. Returns false and
   * reports an error on bad input; the table is then unchanged.
   */
  bool Choose(vtkImageData* volume,
    vtkDataArray* scalars,
    vtkSecondOrderPreIntegrationTable* table,
    int order,
    double sampleDistance);

  /**
   * The measuring part of Choose(): casts the random rays, keeps their pieces, integrates
   * the reference and the exact segment model along them, and measures the largest chord and
   * deviation (GetMeasuredChordRange(), GetMeasuredDeviationRange()). What depends on less is
   * kept from the last Prepare() (compared by pointer and modification time): the rays while
   * the volume, its scalars, Seed and NumberOfRays stay the same; their pieces while the order
   * and the sample distance also do; their reference while the table's transfer functions (by
   * content, vtkVolumeTransferFunctionSampler::GetContentHash) and
   * scalar range and ReferenceTolerance also do. After an edit of the transfer functions,
   * the reference integrates again only the cells of the rays whose integration reads a
   * scalar the edit changed (vtkVolumeReferenceIntegrator::RayCells,
   * vtkVolumeTransferFunctionSampler::GetChangedRange), none for an edit of the colours alone
   * where the colours interpolate linearly between at most 8 nodes (kept as node weights,
   * vtkVolumeTransferFunctionSampler::IsColorEditOf); the exact model's value of each piece is
   * kept likewise. So an edit of the transfer functions costs the cells and pieces near what
   * it changed and the candidates, and a change of order or sample distance the pieces, the
   * exact model and the candidates. The kept values take a byte per cell crossed and 4 to 9
   * floats per cell that meets opacity, and 4 doubles per piece. The table is not changed;
   * it must stay alive while Measure() is used.
   */
  bool Prepare(vtkImageData* volume,
    vtkDataArray* scalars,
    vtkSecondOrderPreIntegrationTable* table,
    int order,
    double sampleDistance);

  /**
   * The error (RMSE of premultiplied RGBA against the reference over the prepared rays) of a
   * table of the prepared one's transfer functions, range, segment length, iterations and
   * prefilter with these sizes and ranges (a range of 0 or less: the scalar range's width).
   * Only the entries the rays read are integrated. Returns -1 when no table was prepared or
   * memory runs out.
   */
  double Measure(int tableSize,
    int chordSize,
    int deviationSize,
    double chordRange,
    double deviationRange);

  /**
   * The squared error of each prepared ray in the last Measure() (mean over the four
   * channels), for statistics over the rays: paired comparisons of two tables on the same
   * rays.
   */
  void GetLastMeasurePerRay(vtkDoubleArray* errors);

  ///@{
  /**
   * Measure in threads of low priority (vtkLowPriorityThreads) instead of vtkSMPTools': a
   * measurement in the background that must not slow rendering. Not copied by
   * CopySettings(). Initial value is false.
   */
  virtual void SetLowPriority(bool low);
  virtual bool GetLowPriority();
  vtkBooleanMacro(LowPriority, bool);
  ///@}

  /**
   * Take the settings of other (NumberOfRays, Seed, Tolerance, MaximumMemory, BytesPerEntry,
   * MaximumAxisSize, ReferenceTolerance, MeasureExactModel, MeasurePrefilter,
   * StopAtConvergence, ScreeningFraction, KeepEntries, OpacityThreshold).
   */
  void CopySettings(vtkPreIntegrationTableSizer* other);

  /**
   * Take what other's last Choose() measured (candidates, chosen candidate, exact error, rays
   * in the volume, levels, time, measured ranges), for statistics; not its rays or reference.
   */
  void CopyStatistics(vtkPreIntegrationTableSizer* other);

  /**
   * How far the running (or last) Prepare() and Choose() are, in [0, 1]: 0.25 once the
   * reference is integrated, 0.35 with the pieces, 0.45 with the exact model, then half the
   * rest with each centre size measured, 1 when the sizes are chosen. ProgressEvent carries
   * the same value (a double) at each of those points. Thread-safe.
   */
  double GetProgress() const;

  ///@{
  /**
   * Stop a Choose() or Prepare() that runs in another thread at its next check (between
   * candidates, between chunks of rays, inside the reference's rays): it returns false without
   * an error message and leaves the table unchanged; the rays, pieces and reference it had
   * completed are kept for the next call. The request stays until ClearAbort(), so that an
   * Abort() just before a call is not lost: whoever starts a measurement clears it first.
   * GetAborted() tells whether the last Prepare() or Choose() stopped so. Thread-safe.
   */
  void Abort();
  void ClearAbort();
  bool GetAborted() const;
  ///@}

  ///@{
  /**
   * The largest chord |back - front| and deviation |middle - centre| that the prepared rays
   * met, in data units.
   */
  vtkGetMacro(MeasuredChordRange, double);
  vtkGetMacro(MeasuredDeviationRange, double);
  ///@}

  ///@{
  /**
   * What the last Choose() measured: the candidates in the order they were evaluated (their
   * TableSize, ChordSize and DeviationSize, ChordRange and DeviationRange, prefilter, error,
   * memory in bytes and whether the screening rays dropped it: its error is then over those
   * rays alone), the one chosen (-1 if none), the error of the exact segment model (no table; -1
   * when neither MeasureExactModel nor StopAtConvergence is on), the rays that met the volume, the
   * centre sizes measured, and the wall time in seconds.
   */
  int GetNumberOfCandidates() const;
  void GetCandidateSizes(int candidate, int sizes[3]) const;
  void GetCandidateRanges(int candidate, double ranges[2]) const;
  double GetCandidateError(int candidate) const;
  double GetCandidateMemory(int candidate) const;
  bool GetCandidatePrefilter(int candidate) const;
  bool GetCandidateDropped(int candidate) const;
  vtkGetMacro(ChosenCandidate, int);
  vtkGetMacro(ExactError, double);
  vtkGetMacro(NumberOfRaysInVolume, int);
  vtkGetMacro(NumberOfLevels, int);
  vtkGetMacro(LastChooseTime, double);
  ///@}

protected:
  vtkPreIntegrationTableSizer();
  ~vtkPreIntegrationTableSizer() override;

  int NumberOfRays = 2048;
  int Seed = 1;
  double Tolerance = 0.02;
  double MaximumMemory = 64.0 * 1024.0 * 1024.0;
  int BytesPerEntry = 8;
  int MaximumAxisSize = 4097;
  double OpacityThreshold = 1.0 - 1.0 / 255.0;
  bool MeasureExactModel = false;
  bool MeasurePrefilter = false;
  bool StopAtConvergence = true;
  bool KeepEntries = true;
  double ScreeningFraction = 0.25;
  int NumberOfLevels = 0;
  double ReferenceTolerance = 1.0 / 64.0;
  int ChosenCandidate = -1;
  double ExactError = 0.0;
  int NumberOfRaysInVolume = 0;
  double LastChooseTime = 0.0;
  double MeasuredChordRange = 0.0;
  double MeasuredDeviationRange = 0.0;

private:
  // Ends a Prepare() or Choose() on Abort(): forgets the candidates, returns false.
  bool Stop();
  // Sets GetProgress() and fires ProgressEvent.
  void ReportProgress(double progress);
  // Measure() with an explicit prefilter, reading the entries of shared (when given) where
  // they lie on its grid, on the rays [begin, end) (end < 0: to the last).
  double MeasureCandidate(int tableSize,
    int chordSize,
    int deviationSize,
    double chordRange,
    double deviationRange,
    bool prefilter,
    const vtkPreIntegrationCandidateEntries* shared = nullptr,
    vtkIdType begin = 0,
    vtkIdType end = -1);
  // The rays each candidate is screened on: the first ScreeningFraction of those in the
  // volume, at least 256 of them (all when fewer).
  vtkIdType GetScreeningRays() const;

  vtkPreIntegrationTableSizer(const vtkPreIntegrationTableSizer&) = delete;
  void operator=(const vtkPreIntegrationTableSizer&) = delete;

  struct vtkInternals;
  std::unique_ptr<vtkInternals> Internals;
};

#endif
