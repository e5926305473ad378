// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
/**
 * @class   vtkPreIntegrationTableSizing
 * @brief   the sizes a pre-integration table is drawn with, frame by frame: measured at once,
 *          or cheap at once and measured in the background
 *
 * A renderer calls Update() before each frame with a key of everything its table's sizes
 * depend on (the data, the transfer functions, the order, the sample distance, the limits).
 * While the key stays the same nothing is done. When it changes:
 *   - by default the sizes are measured at once (vtkPreIntegrationTableSizer::Choose): the
 *     frame waits for them and every frame is the measured one (batch use: deterministic);
 *   - with RefineInBackground the frame is drawn at once with interim sizes, and a
 *     vtkPreIntegrationTableRefiner measures and builds the table in a worker thread (a newer
 *     key stops an older measurement). The interim sizes are the table's own when it was
 *     measured for the same order (a new transfer function, time step or sample distance keeps
 *     the last measured sizes and ranges), else TableSize 129 (first order; 65 for second
 *     order) over every chord and deviation; either is cut to at most InterimEntries entries
 *     by halving its axes, so that it builds in a few milliseconds. With ProvisionalTables,
 *     a table measured before is drawn at its full measured sizes as a provisional table (a
 *     small edit most often measures the same sizes again): at once when their rebuild for
 *     the change integrates at most InterimEntries entries on the CPU
 *     (vtkSecondOrderPreIntegrationTable::GetNumberOfEntriesToBuild: a narrow edit of the
 *     transfer functions, the table last built at those sizes) or, incremental, is predicted
 *     at the table's last build rate to take at most ImmediateBuildFraction of FrameTime (or
 *     ImmediateBuildTime while the frame time is unknown); else built in the worker and given
 *     before the measurement ends. IsRefinementReady() tells when the provisional
 * or the measured table waits, and the next Update() with the same key gives it to the table (sizes
 * and entries). A measurement that confirms the provisional table already drawn ends the refinement
 * by itself (IsRefining() and IsRefinementReady() turn false): a frame would draw the same image. A
 * failed measurement is reported once and the interim table stays. GetSizer() holds the sizer
 * settings both ways use, and the statistics of the last measured sizes in use (after a background
 * measurement, copied from the worker's sizer).
 *
 * @sa vtkPreIntegrationTableSizer vtkPreIntegrationTableRefiner
 */
#ifndef vtkPreIntegrationTableSizing_h
#define vtkPreIntegrationTableSizing_h

#include "hovrRenderingCoreModule.h" // For export macro
#include "vtkObject.h"

#include <vector> // For the key

class vtkDataArray;
class vtkDoubleArray;
class vtkImageData;
class vtkPreIntegrationTableRefiner;
class vtkPreIntegrationTableSizer;
class vtkSecondOrderPreIntegrationTable;

class HOVRRENDERINGCORE_EXPORT vtkPreIntegrationTableSizing : public vtkObject
{
public:
  static vtkPreIntegrationTableSizing* New();
  vtkTypeMacro(vtkPreIntegrationTableSizing, vtkObject);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /**
   * Draw at once with interim sizes and measure in the background (see the class
   * description); off measures before the frame. Initial value is false.
   */
  vtkSetMacro(RefineInBackground, bool);
  vtkGetMacro(RefineInBackground, bool);
  vtkBooleanMacro(RefineInBackground, bool);
  ///@}

  ///@{
  /**
   * With RefineInBackground, draw a table measured before at its full measured sizes before
   * the measurement ends: at once when its rebuild is cheap, else built in the worker first
   * (see the class description). Initial value is true.
   */
  vtkSetMacro(ProvisionalTables, bool);
  vtkGetMacro(ProvisionalTables, bool);
  vtkBooleanMacro(ProvisionalTables, bool);
  ///@}

  ///@{
  /**
   * The most entries of an interim table (every moment layer counted once), and of the
   * rebuild of a provisional table drawn at once. Initial value is 131072.
   */
  vtkSetClampMacro(InterimEntries, double, 1024.0, 1e9);
  vtkGetMacro(InterimEntries, double);
  ///@}

  ///@{
  /**
   * The longest incremental rebuild (predicted from the table's last build: its time over its
   * entries) of a provisional table drawn at once after a change, as a fraction of FrameTime,
   * so that the frame after the change stays close to a camera move's; 0 leaves only the
   * InterimEntries rule. Initial value is 0.25.
   */
  vtkSetClampMacro(ImmediateBuildFraction, double, 0.0, 10.0);
  vtkGetMacro(ImmediateBuildFraction, double);
  ///@}

  ///@{
  /**
   * The renderer's time for a frame of the table's volume (seconds; its last draw, which the
   * renderer sets before each Update()), and the longest incremental rebuild of a
   * provisional table drawn at once while it is unknown (0 or less). Initial values are 0 and
   * 0.05.
   */
  vtkSetMacro(FrameTime, double);
  vtkGetMacro(FrameTime, double);
  vtkSetClampMacro(ImmediateBuildTime, double, 0.0, 10.0);
  vtkGetMacro(ImmediateBuildTime, double);
  ///@}

  /**
   * The sizer settings both ways use, and the statistics of the measured sizes in use.
   */
  vtkPreIntegrationTableSizer* GetSizer() { return this->Sizer; }

  /**
   * The worker of background measurements (statistics: requests, completed, stopped).
   */
  vtkPreIntegrationTableRefiner* GetRefiner() { return this->Refiner; }

  /**
   * Give table its sizes for the next frame (see the class description): key holds what they
   * depend on but the data, dataKey what they depend on in the data (the scalars, their
   * modification time, the range); volume and scalars are what is drawn, at this order (1 or 2) and
   * sample distance; the deviation axis gets at most deviationLimit entries; buildEntries tells
   * whether the table's entries are built on the CPU (false: another builder, such as a GPU
   * pass, builds them, and a background measurement chooses sizes only). The table must
   * hold its transfer functions, scalar range, segment length, iterations and moment layers.
   * Returns false after an error (reported): nothing can be drawn.
   */
  bool Update(const std::vector<double>& key,
    const std::vector<double>& dataKey,
    vtkImageData* volume,
    vtkDataArray* scalars,
    vtkSecondOrderPreIntegrationTable* table,
    int order,
    double sampleDistance,
    int deviationLimit,
    bool buildEntries);

  /**
   * What the measured sizes depend on in a volume's scalars, for deciding whether a new time
   * step needs them measured again: [range low, range high, chord, h_0 .. h_63], the
   * histogram h of the values over the range (fractions summing to 1) and the 99th
   * percentile of the differences between neighbouring points along x, as a fraction of the
   * range's width (what the chords of segments at a step of one voxel span), from at most
   * about a million points of a regular subsample of the dims[0] x dims[1] x dims[2] grid.
   * NaN values are left out.
   */
  static void ComputeSignature(vtkDataArray* scalars,
    const int dims[3],
    const double range[2],
    vtkDoubleArray* signature);

  /**
   * How far the distribution of signature b is from a's: the earth mover's distance between
   * their histograms (the mean shift of the values) as a fraction of a's range's width.
   */
  static double DistributionShift(vtkDoubleArray* a, vtkDoubleArray* b);

  /**
   * How far the chords of b are from a's: |log(chord b / chord a)| (0.1 is about 10%).
   */
  static double ChordChange(vtkDoubleArray* a, vtkDoubleArray* b);

  /**
   * Forget the key: the next Update() sizes the table anew (and stops a background
   * measurement).
   */
  void Reset();

  /**
   * Whether the table holds interim sizes while a background measurement runs or waits.
   */
  bool IsRefining();

  /**
   * Whether the provisional or measured table waits for the next Update() (the frame that
   * draws it). Both this and IsRefining() first end a refinement whose measurement confirmed
   * the provisional table already drawn.
   */
  bool IsRefinementReady();

  /**
   * Block until the background measurement of the current key is done (nothing to wait for
   * when sizes are measured at once).
   */
  void WaitForRefinement();

  /**
   * Interim tables drawn so far (frames that answered a change before its measurement), and
   * provisional tables given so far (see ProvisionalTables).
   */
  vtkGetMacro(NumberOfInterimTables, int);
  vtkGetMacro(NumberOfProvisionalTables, int);

  ///@{
  /**
   * New data alone (a new time step: dataKey changed, nothing else) keeps the measured sizes,
   * and the table's scalar range they were measured over (which then replaces the range
   * given; values beyond it extend it by whole centre spacings, TableSize growing with it, by
   * at most a quarter of it), when the signature of its scalars (ComputeSignature, over that
   * range) is within MaximumDistributionShift
   * (the mean shift of the values, as a fraction of the range) and MaximumChordChange (of the
   * chords, as |log| of their ratio) of the signature of the data they were measured on;
   * otherwise they are measured again. Initial values: true, 0.01 and 0.05.
   */
  vtkSetMacro(ReuseForNewData, bool);
  vtkGetMacro(ReuseForNewData, bool);
  vtkBooleanMacro(ReuseForNewData, bool);
  vtkSetClampMacro(MaximumDistributionShift, double, 0.0, 1e9);
  vtkGetMacro(MaximumDistributionShift, double);
  vtkSetClampMacro(MaximumChordChange, double, 0.0, 1e9);
  vtkGetMacro(MaximumChordChange, double);
  ///@}

  /**
   * New data that kept the measured sizes so far, and the distances of the last new data
   * compared (VTK_DOUBLE_MAX: not comparable).
   */
  vtkGetMacro(NumberOfKeptSizes, int);
  vtkGetMacro(LastDistributionShift, double);
  vtkGetMacro(LastChordChange, double);

protected:
  vtkPreIntegrationTableSizing();
  ~vtkPreIntegrationTableSizing() override;

  // Interim sizes for table (order 1 or 2), at most InterimEntries entries.
  void SetInterimSizes(vtkSecondOrderPreIntegrationTable* table, int order, int deviationLimit);
  // Records that table holds measured sizes.
  void MarkMeasured(vtkSecondOrderPreIntegrationTable* table);
  // Takes the measured sizes into the sizer's statistics and the table's record: the
  // refinement of the request's table ends.
  void FinishRefinement(vtkSecondOrderPreIntegrationTable* table);
  // Ends the refinement when its measurement confirmed the provisional table already drawn.
  void FinishConfirmation();

  bool RefineInBackground = false;
  double InterimEntries = 131072.0;
  double ImmediateBuildTime = 0.05;
  double ImmediateBuildFraction = 0.25;
  double FrameTime = 0.0;
  int NumberOfInterimTables = 0;
  bool ProvisionalTables = true;
  int NumberOfProvisionalTables = 0;
  vtkPreIntegrationTableSizer* Sizer;
  vtkPreIntegrationTableRefiner* Refiner;
  std::vector<double> Key;     // what the table's sizes are for, the data aside
  std::vector<double> DataKey; // the data they are for
  bool ReuseForNewData = true;
  double MaximumDistributionShift = 0.01;
  double MaximumChordChange = 0.05;
  int NumberOfKeptSizes = 0;
  double LastDistributionShift = 0.0;
  double LastChordChange = 0.0;
  // The signature of the data the sizes were last measured on, and the table's range then.
  vtkDoubleArray* MeasuredSignature;
  double MeasuredRange[2] = { 0.0, 1.0 };
  int MeasuredSize = 0; // its centre size
  // Kept sizes for new data: the range and centre size the table keeps while the key and the
  // data stay the same.
  bool RangeKept = false;
  double KeptRange[2] = { 0.0, 1.0 };
  int KeptTableSize = 0;
  bool Interim = false;  // the sizes for Key are interim (a request runs or waits)
  vtkIdType Request = 0; // the background request for Key
  vtkSecondOrderPreIntegrationTable* RequestTable = nullptr; // the table it refines
  // The tables whose sizes were measured once (the interim sizes keep them).
  std::vector<const void*> MeasuredTables;
  // Their last measured TableSize, ChordSize, ChordRange, DeviationSize, DeviationRange and
  // prefilter (a provisional table's sizes).
  std::vector<std::vector<double>> MeasuredSizes;

private:
  vtkPreIntegrationTableSizing(const vtkPreIntegrationTableSizing&) = delete;
  void operator=(const vtkPreIntegrationTableSizing&) = delete;
};

#endif
