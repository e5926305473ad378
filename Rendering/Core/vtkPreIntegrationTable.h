// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
/**
 * @class   vtkPreIntegrationTable
 * @brief   abstract base of the pre-integration tables: what they share and when they rebuild
 *
 * A pre-integration table stores, for ray segments of a fixed length SegmentLength whose
 * scalar follows a prescribed shape between table entries, the segment's premultiplied colour
 * and opacity (RGBA, float) with self-attenuation inside the segment. The table axes sample
 * ScalarRange at TableSize equispaced scalars, entry 0 at ScalarRange[0] and entry
 * TableSize - 1 at ScalarRange[1]; a shader looks a scalar s up at texture coordinate
 * ((s - r0) / (r1 - r0) (N - 1) + 1/2) / N so that entries sit at texel centres.
 *
 * Subclasses define the dimension and the segment model (first order: 2D over front and back
 * scalar; second order: 3D over front, middle and back) by implementing BuildTable().
 * Update() rebuilds only when the transfer functions, the unit distance, the segment length,
 * the scalar range or the table size changed; GetBuildCount() counts the rebuilds.
 */
#ifndef vtkPreIntegrationTable_h
#define vtkPreIntegrationTable_h

#include "hovrRenderingCoreModule.h" // For export macro
#include "vtkObject.h"

#include <functional> // For ForInParts
#include <vector>     // For the build key

class vtkDataArray;
class vtkFloatArray;
class vtkVolumeProperty;
class vtkVolumeTransferFunctionSampler;

class HOVRRENDERINGCORE_EXPORT vtkPreIntegrationTable : public vtkObject
{
public:
  vtkTypeMacro(vtkPreIntegrationTable, vtkObject);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  /**
   * The transfer functions and unit distance the table integrates (owned by the table).
   */
  vtkVolumeTransferFunctionSampler* GetSampler() { return this->Sampler; }

  /**
   * Take the transfer functions and unit distance of component 0 of a volume property.
   * Does not mark the table modified unless something the table depends on changed.
   */
  void SetVolumeProperty(vtkVolumeProperty* property);

  ///@{
  /**
   * Length of a ray segment in world units; must be positive and at most 1e30 (tables are
   * integrated in float). Initial value is 1.0.
   */
  vtkSetMacro(SegmentLength, double);
  vtkGetMacro(SegmentLength, double);
  ///@}

  ///@{
  /**
   * Scalar range spanned by the table axes. Initial value is [0, 255].
   */
  vtkSetVector2Macro(ScalarRange, double);
  vtkGetVector2Macro(ScalarRange, double);
  ///@}

  ///@{
  /**
   * Number of entries along each scalar axis, at least 2. Initial value is 256.
   */
  vtkSetClampMacro(TableSize, int, 2, 65536);
  vtkGetMacro(TableSize, int);
  ///@}

  ///@{
  /**
   * Whether Update() computes the entries. When false it still tracks changes, counts builds
   * and prepares what the entries are computed from (empty runs, and what a subclass needs),
   * leaving the entries to another builder such as a GPU pass; GetTable() is then empty.
   * Initial value is true.
   */
  vtkSetMacro(ComputeEntries, bool);
  vtkGetMacro(ComputeEntries, bool);
  vtkBooleanMacro(ComputeEntries, bool);
  ///@}

  /**
   * Rebuild the table if anything it depends on changed. Returns false and reports an error
   * for invalid settings (missing transfer function, non-positive lengths, empty range) and
   * when memory runs out for the table (16 bytes per entry, GetNumberOfEntries() of them),
   * which is then empty.
   */
  bool Update();

  /**
   * The table, RGBA float, entries along the first axis fastest; valid after Update().
   */
  vtkFloatArray* GetTable() { return this->Table; }

  /**
   * Zero-opacity runs, for skipping empty segments: value b (b = 0 .. TableSize - 2) belongs to
   * the table spacing [entry b, entry b + 1]; it is -1 when the opacity is positive somewhere
   * in that spacing, otherwise the index of the run of consecutive zero-opacity spacings it
   * belongs to. A segment whose end scalars both lie in spacings of the same run has zero
   * opacity everywhere (the scalar stays between them) and contributes nothing. A table that
   * prefilters the transfer function counts opacity within its filter margin of the spacing.
   * Valid after Update().
   */
  vtkFloatArray* GetEmptyRuns() { return this->EmptyRuns; }

  /**
   * Number of table dimensions (2 or 3).
   */
  virtual int GetNumberOfDimensions() const = 0;

  /**
   * Number of entries of the table: TableSize^dimensions unless a subclass sizes its axes
   * otherwise.
   */
  virtual vtkIdType GetNumberOfEntries() const;

  ///@{
  /**
   * Build in threads of low priority (vtkLowPriorityThreads) instead of vtkSMPTools': a
   * build in the background that must not slow rendering. Initial value is false.
   */
  vtkSetMacro(LowPriority, bool);
  vtkGetMacro(LowPriority, bool);
  vtkBooleanMacro(LowPriority, bool);
  ///@}

  ///@{
  /**
   * Set during a build (from a ProgressEvent observer, or another thread) to stop it: Update()
   * then reports an error, leaves the table empty and returns false; the flag is cleared when
   * the next build starts. Builds fire ProgressEvent (a double in [0, 1]) as they go.
   * Initial value is false.
   */
  vtkSetMacro(AbortBuild, bool);
  vtkGetMacro(AbortBuild, bool);
  vtkBooleanMacro(AbortBuild, bool);
  ///@}

  /**
   * Take the entries of built, a table of the same class and the same settings (sizes,
   * ranges, segment length and what a subclass adds) whose transfer functions equal this
   * one's, built by Update() elsewhere (in a worker thread, say): this table then counts as
   * built for its current settings, as after an Update() that built them, and built is left
   * empty. The transfer functions are the caller's to match; the other settings are checked.
   * Returns false, both tables untouched, when they differ or built was never built.
   */
  virtual bool AdoptBuild(vtkPreIntegrationTable* built);

  ///@{
  /**
   * Statistics: rebuilds so far, wall time of the last build in seconds, table size in bytes.
   */
  vtkGetMacro(BuildCount, int);
  vtkGetMacro(LastBuildTime, double);
  vtkIdType GetMemorySize() const;
  ///@}

  /**
   * A table size matched to the data and the transfer function. Integer data: one entry per
   * integer value of the range (lookups at voxel values are then exact), subdivided when a
   * transfer-function feature is narrower than one unit or to reach MinimumSize. Float data,
   * or integer data whose range needs more than MaximumSize entries: EntriesPerFeature
   * entries across the narrowest feature. Clamped to [MinimumSize, MaximumSize]. With
   * opacityFeatures, only opacity nodes define features and the integer rule is not used
   * (tables of integrated slabs need no entry per value). The sampler must be prepared.
   */
  static int SuggestTableSize(int scalarType,
    const double range[2],
    vtkVolumeTransferFunctionSampler* sampler,
    int minimumSize,
    int maximumSize,
    double entriesPerFeature = 4.0,
    bool opacityFeatures = false);

  /**
   * The scalar range a table spans for component 0 of scalars: dataRange receives their finite
   * range (NaN and infinite values left out), tableRange the same widened by
   * max(1, 1e-6 |value|) when the data is flat, so that its one value maps into a non-empty
   * range (1 alone vanishes next to 1e20). With `cover`, a finite range that is not empty
   * (low <= high), both span it too: the whole volume's range, when scalars are one piece of it
   * (a rank's, under MPI), so that every piece gets the same tables. False, both ranges
   * untouched, when the scalars hold no finite value (empty or all NaN).
   */
  static bool ComputeScalarRange(vtkDataArray* scalars,
    double dataRange[2],
    double tableRange[2],
    const double* cover = nullptr);

protected:
  vtkPreIntegrationTable();
  ~vtkPreIntegrationTable() override;

  /**
   * Fill this->Table (already sized to TableSize^dimensions RGBA tuples, or empty when
   * ComputeEntries is false) from the prepared sampler. Called by Update() only when needed.
   */
  virtual void BuildTable() = 0;

  // Called when Update() empties the table (an aborted build, no memory): a subclass that
  // keeps what the entries were built from forgets it.
  virtual void TableReleased() {}

  // Whether an aborted BuildTable() left entries worth keeping (a subclass that knows which of
  // them the next build must integrate again): Update() then keeps the table.
  virtual bool KeepsAbortedBuild() const { return false; }

  // Appends everything the entries depend on (the transfer functions by content, the range,
  // the size, the segment length, ...) to key: a table whose key is the last build's needs no
  // build. Subclasses append their own settings.
  virtual void AppendBuildKey(std::vector<double>& key) const;
  std::vector<double> BuildKey; // of the last complete build

  // Fills EmptyRuns from the prepared sampler.
  void BuildEmptyRuns();

  // Runs body(begin, end) over [0, n) in parts with vtkSMPTools, firing ProgressEvent after
  // each; false (and the rest skipped) once AbortBuild is set.
  bool ForInParts(vtkIdType n, const std::function<void(vtkIdType, vtkIdType)>& body);

  // Whether the last BuildTable() stopped on AbortBuild.
  bool BuildAborted = false;
  // Set by a BuildTable() that found every entry, and what else the table holds, as the last
  // build left them: the build is not counted (GetBuildCount), so nothing is uploaded again.
  bool EntriesUnchanged = false;
  bool AbortBuild = false;

  // Scalar margin around each spacing within which opacity makes it non-empty: a table that
  // filters the transfer function spreads opacity that far.
  virtual double GetEmptyRunMargin() const { return 0.0; }

  vtkVolumeTransferFunctionSampler* Sampler;
  vtkFloatArray* Table;
  vtkFloatArray* EmptyRuns;
  double SegmentLength = 1.0;
  double ScalarRange[2] = { 0.0, 255.0 };
  int TableSize = 256;
  int BuildCount = 0;
  double LastBuildTime = 0.0;
  bool ComputeEntries = true;
  bool LowPriority = false;
  vtkMTimeType BuildMTime = 0;

private:
  vtkPreIntegrationTable(const vtkPreIntegrationTable&) = delete;
  void operator=(const vtkPreIntegrationTable&) = delete;
};

#endif
