// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
/**
 * @class   vtkSecondOrderPreIntegrationTable
 * @brief   second-order pre-integration: a 3D table of slabs (front, middle, back scalar)
 *
 * El Hajjar, Marchesin, Dischler and Mongenet, "Second Order Pre-Integrated Volume
 * Rendering" (2008). Within a slab of length L = SegmentLength (twice the sample distance) the
 * scalar follows the quadratic through three equispaced samples (Eq. 2):
 *   P(t) = A t^2 + B t + C, A = 2 s_f - 4 s_m + 2 s_b, B = -3 s_f + 4 s_m - s_b, C = s_f,
 * t in [0, 1], and the table stores
 *   alpha = 1 - exp(-int_0^1 tau(P(t)) L dt),
 *   C     = int_0^1 c(P(t)) tau(P(t)) L exp(-int_0^t tau(P(t')) L dt') dt,
 * premultiplied and self-attenuated.
 *
 * The table's axes are not the three samples themselves but a linear change of them that puts
 * the entries where slabs fall:
 *   - the chord's centre c = (s_f + s_b) / 2, TableSize entries over ScalarRange;
 *   - the chord b = s_b - s_f, ChordSize entries over [-ChordRange, ChordRange];
 *   - the deviation d = s_m - c of the middle sample from the chord, DeviationSize entries
 *     over [-DeviationRange, DeviationRange],
 * so that P(t) = s_f + (b + 4 d) t - 4 d t^2 (Eq. 2 again). A ray whose scalar lingers near a
 * value (where the table must resolve the transfer function's narrowest features) gives slabs
 * near b = d = 0, whatever the step: the centre axis can be as fine as a first-order table's,
 * while the chord and deviation axes only span the differences the data produce at this step,
 * which shrink with the step (b about as the gradient, d as its change). A table over
 * (front, middle, back) instead spends its entries evenly on every combination of three
 * scalars, most of which no slab takes at small steps. Lookups beyond ChordRange or
 * DeviationRange are clamped to the edge. Entry (i, j, k) holds centre i (fastest), chord j
 * and deviation k. With DeviationSize 1 (deviation 0) the table is a first-order one
 * (linear scalar) over (centre, chord).
 *
 * The integral takes midpoint steps in t, one for every sample of the iteration table that
 * P(t) sweeps (at least 1, at most Iterations); each reads the extinction and the extinction-
 * weighted colour from the iteration table with linear interpolation and composites the step
 * with the exact exponential of its length, which is exact for a constant scalar. P(t) is
 * clamped to the scalar range: the quadratic overshoots its samples by up to 1/8 of their
 * spread, the trilinear field never leaves the data range. A slab whose scalar stays inside
 * one zero-opacity run is set to zero without integration. Built on the CPU with vtkSMPTools;
 * vtkOpenGLPreIntegrationTableBuilder builds the same table on the GPU from the same
 * iteration table. With Prefilter the transfer function is first box-averaged over one entry
 * spacing of the centre axis (off by default: see Prefilter).
 */
#ifndef vtkSecondOrderPreIntegrationTable_h
#define vtkSecondOrderPreIntegrationTable_h

#include "hovrRenderingCoreModule.h" // For export macro
#include "vtkPreIntegrationTable.h"
#include "vtkSecondOrderPreIntegrationTableKernel.h" // For GetKernel

class HOVRRENDERINGCORE_EXPORT vtkSecondOrderPreIntegrationTable : public vtkPreIntegrationTable
{
public:
  static vtkSecondOrderPreIntegrationTable* New();
  vtkTypeMacro(vtkSecondOrderPreIntegrationTable, vtkPreIntegrationTable);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  int GetNumberOfDimensions() const override { return 3; }

  /**
   * Also checks the chord and deviation axes, iterations, prefilter and moment layers, and
   * takes the iteration table with the entries.
   */
  bool AdoptBuild(vtkPreIntegrationTable* built) override;
  vtkIdType GetNumberOfEntries() const override;

  /**
   * Take other's entries with what they were built from, leaving other without entries (its
   * next Update() builds them all): this table's next Update(), at other's sizes, ranges and
   * settings, then integrates only the entries that read a transfer-function sample changed
   * since, as other's own would. A worker that builds the table for an edit so starts from
   * the entries the renderer holds instead of from nothing. False, and nothing taken, when
   * other holds no complete build at its present settings (prepares other's sampler and
   * builds its iteration table to tell).
   */
  bool TakeEntries(vtkSecondOrderPreIntegrationTable* other);

  ///@{
  /**
   * Entries along the chord axis (back - front); 1 holds chord 0 only. Initial value is 65.
   */
  vtkSetClampMacro(ChordSize, int, 1, 65536);
  vtkGetMacro(ChordSize, int);
  ///@}

  ///@{
  /**
   * Largest chord |back - front| the table holds, in data units; 0 or less: the width of the
   * scalar range (every chord). Initial value is 0.
   */
  vtkSetMacro(ChordRange, double);
  vtkGetMacro(ChordRange, double);
  ///@}

  ///@{
  /**
   * Entries along the deviation axis (middle - (front + back) / 2); 1 holds deviation 0 only,
   * a first-order table. Initial value is 33.
   */
  vtkSetClampMacro(DeviationSize, int, 1, 65536);
  vtkGetMacro(DeviationSize, int);
  ///@}

  ///@{
  /**
   * Largest deviation |middle - (front + back) / 2| the table holds, in data units; 0 or less:
   * the width of the scalar range (every deviation of three samples inside it). Initial
   * value is 0.
   */
  vtkSetMacro(DeviationRange, double);
  vtkGetMacro(DeviationRange, double);
  ///@}

  /**
   * ChordRange and DeviationRange as the table uses them (the range width where they are not
   * positive). The chord of entry j is -R + 2 R j / (ChordSize - 1), R the effective chord
   * range (0 when ChordSize is 1), and likewise for the deviation.
   */
  double GetEffectiveChordRange() const;
  double GetEffectiveDeviationRange() const;

  ///@{
  /**
   * The most integration steps along a slab: a slab takes one step per iteration-table sample
   * its scalar sweeps, up to this many (the paper integrates every slab in 64 steps). Long
   * chords vary smoothly with their ends, so capping their steps costs little. Initial value
   * is 64.
   */
  vtkSetClampMacro(Iterations, int, 1, 65536);
  vtkGetMacro(Iterations, int);
  ///@}

  ///@{
  /**
   * Average the transfer function over one entry spacing of the centre axis before
   * integrating. A feature narrower than the spacing then keeps its integral over scalar
   * values wherever the entries fall, but not the integral along a ray whose scalar lingers
   * near it: a ray that stays at a value next to a narrow opacity spike collects the spike's
   * averaged opacity, which the transfer function does not give it. A table whose centre
   * spacing resolves the transfer function needs no prefilter. Initial value is false.
   */
  vtkSetMacro(Prefilter, bool);
  vtkGetMacro(Prefilter, bool);
  vtkBooleanMacro(Prefilter, bool);
  ///@}

  ///@{
  /**
   * Moment layers for shaded pre-integration (vtkVolumeShadingModel::ShadeSegment), first
   * order only (DeviationSize 1): 0 stores the segment's RGBA; 1 to 4 store that many
   * layers of TableSize x ChordSize entries one after the other instead, layer l holding
   * (J_l.rgb, J'_l): the integrals of the colour-weighted and of the plain step
   * weights times (1 - u), u, u (1 - u)^2 and u^2 (1 - u) of the position u along the
   * segment (Guetat et al. 2010, Eq. 8 and 10 in a basis without cancellation; layers 0 and
   * 1 sum to the unshaded RGBA). Linear and constant interpolation read 2 layers, non-linear
   * 4. Ignored (one RGBA layer) unless DeviationSize is 1. Initial value is 0.
   */
  vtkSetClampMacro(Moments, int, 0, 4);
  vtkGetMacro(Moments, int);
  ///@}

  ///@{
  /**
   * Moment layers for shaded second-order slabs (vtkVolumeShadingModel::ShadeSegment once per
   * half slab), DeviationSize above 1 only: 0 stores the slab's RGBA; 1 to 4 store twice
   * that many layers of TableSize x ChordSize x DeviationSize entries one after the other
   * instead: layers 0..SlabMoments-1 hold the moments of Moments' layers for the slab's front
   * half, its position u' = 2u running over [0, 1/2] of the slab, and the next SlabMoments
   * layers those of its back half, u' = 2u - 1, both with the scalar on the slab's quadratic
   * (Eq. 2) and attenuated from the slab's front. Shading each half as a first-order segment
   * between its end normals (front and middle, middle and back) and adding the two gives the
   * slab: the arc passes through the middle normal. The four layers 0, 1, SlabMoments and
   * SlabMoments + 1 sum to the unshaded RGBA. Ignored (one RGBA layer) when DeviationSize is 1.
   * Initial value is 0.
   */
  vtkSetClampMacro(SlabMoments, int, 0, 4);
  vtkGetMacro(SlabMoments, int);
  ///@}

  /**
   * Layers of TableSize x ChordSize x DeviationSize RGBA entries the table stores: Moments
   * when DeviationSize is 1, twice SlabMoments otherwise, or 1.
   */
  int GetNumberOfLayers() const;

  /**
   * The iteration table of the last build: (c tau, tau), extinction-weighted colour and
   * extinction of the (prefiltered) transfer function at GetNumberOfIterationSamples()
   * equispaced scalars over ScalarRange, the first at ScalarRange[0] and the last exactly at
   * ScalarRange[1]. Their spacing is at most 1/16 of the narrowest transfer-function feature
   * and half the centre axis' entry spacing, and there are at most 65536 of them.
   */
  vtkFloatArray* GetIterationTable() { return this->IterationTable; }
  int GetNumberOfIterationSamples() const { return this->IterationSamples; }

  /**
   * Iteration-table samples per entry spacing of the centre axis (even, at least 2): entry i
   * lies at sample IterationSamplesPerSpacing i. Valid after Update().
   */
  vtkGetMacro(IterationSamplesPerSpacing, int);

  /**
   * Zero-opacity run of each spacing of the iteration table (-1 where there is opacity),
   * the fine counterpart of GetEmptyRuns() used to skip empty slabs during the build.
   */
  vtkFloatArray* GetIterationEmptyRuns() { return this->IterationEmptyRuns; }

  /**
   * The quadratic of entry (centre i, chord j, deviation k) in data units: P(t) = path[0] +
   * path[1] t + path[2] t^2 (before clamping to the scalar range). Valid after Update().
   */
  void GetEntryPath(int i, int j, int k, double path[3]) const;

  /**
   * RGBA of entry (centre i, chord j, deviation k) after Update().
   */
  void GetEntry(int i, int j, int k, double rgba[4]);

  /**
   * Fill the iteration table and its empty runs for the current settings (done by Update();
   * public for builders that integrate elsewhere, e.g. on the GPU). The sampler must be
   * prepared.
   */
  void BuildIterationTable();

  /**
   * Entries integrated by the last build: all of them, or after an edit of the transfer
   * functions that left everything else alone, only those whose paths read the scalars whose
   * transfer-function samples changed (the others keep their values, bit for bit).
   */
  vtkGetMacro(LastBuildEntries, vtkIdType);

  /**
   * The centre entries (first and last index along TableSize) whose entries the last build
   * integrated: all of them after a whole build (and after AdoptBuild()), the ones an
   * incremental build reached after an edit (last < first when none), so that an upload can
   * send that slab alone.
   */
  vtkGetVector2Macro(LastBuildCentres, int);

  /**
   * Entries the next Update() would integrate on the CPU: those that read a changed
   * transfer-function sample after an edit that left everything else alone since the last
   * build, else all of them (also when ComputeEntries is off: another builder integrates them
   * all). Builds the iteration table for the current settings (the sampler must be prepared)
   * and changes nothing else.
   */
  vtkIdType GetNumberOfEntriesToBuild();

#ifndef __VTK_WRAP__
  /**
   * The integration of single entries, for the current settings and iteration table (after
   * Update() or BuildIterationTable()).
   */
  vtkSecondOrderPreIntegrationTableKernel GetKernel() const;
#endif

protected:
  vtkSecondOrderPreIntegrationTable();
  ~vtkSecondOrderPreIntegrationTable() override;

  void BuildTable() override;

  void AppendBuildKey(std::vector<double>& key) const override;
  void TableReleased() override
  {
    this->BuiltValid = false;
  }
  // An incremental build stopped part way keeps its entries: those that read none of the
  // samples it changed are still the last build's, and the next build integrates the others.
  bool KeepsAbortedBuild() const override
  {
    return this->BuiltValid;
  }

#ifndef __VTK_WRAP__
  // Whether the current settings and iteration table differ from the last build's only in
  // samples (the same kernel, layers and entries): then [first, last] are the samples that
  // differ, and those an aborted build may have changed (last < first when none).
  bool ChangedSamples(const vtkSecondOrderPreIntegrationTableKernel& kernel,
    int& first,
    int& last) const;
#endif

  // The prefilter spreads opacity by half a centre spacing.
  double GetEmptyRunMargin() const override;

  int ChordSize = 65;
  double ChordRange = 0.0;
  int DeviationSize = 33;
  double DeviationRange = 0.0;
  int Iterations = 64;
  bool Prefilter = false;
  int Moments = 0;
  int SlabMoments = 0;
  int IterationSamples = 0;
  int IterationSamplesPerSpacing = 2;
  vtkFloatArray* IterationTable;
  vtkFloatArray* IterationEmptyRuns;
  // What the entries in the table were last built from, so that a rebuild after an edit of the
  // transfer functions integrates only the entries whose paths read samples that changed:
  // the iteration table, the kernel, the layers and the number of entries, and whether the
  // table still holds that build's entries.
  vtkFloatArray* BuiltIterationTable;
  vtkSecondOrderPreIntegrationTableKernel BuiltKernel;
  int BuiltLayers = -1;
  vtkIdType BuiltEntries = -1;
  bool BuiltValid = false;
  // Samples whose entries an aborted incremental build may have left at either build's values
  // (the entries that read them are integrated again); last < first when none.
  int DirtySamples[2] = { 0, -1 };
  vtkIdType LastBuildEntries = 0;
  int LastBuildCentres[2] = { 0, -1 };

private:
  vtkSecondOrderPreIntegrationTable(const vtkSecondOrderPreIntegrationTable&) = delete;
  void operator=(const vtkSecondOrderPreIntegrationTable&) = delete;
};

#endif
