// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
/**
 * @class   vtkSecondOrderPreIntegrationTable
 * @brief   second-order pre-integration: a 3D table over (front, middle, back) scalar
 *
 * El Hajjar, Marchesin, Dischler and Mongenet, "Second Order Pre-Integrated Volume
 * Rendering" (2008). Within a slab of length L = SegmentLength (twice the sample distance) the
 * scalar follows the quadratic through three equispaced samples (Eq. 2):
 *   P(t) = A t^2 + B t + C, A = 2 s_f - 4 s_m + 2 s_b, B = -3 s_f + 4 s_m - s_b, C = s_f,
 * t in [0, 1], and the table stores
 *   alpha = 1 - exp(-int_0^1 tau(P(t)) L dt),
 *   C     = int_0^1 c(P(t)) tau(P(t)) L exp(-int_0^t tau(P(t')) L dt') dt,
 * premultiplied and self-attenuated. Entry (i, j, k) holds s_f = scalar of entry i (fastest),
 * s_m of entry j and s_b of entry k.
 *
 * The integral takes Iterations midpoint steps in t (the paper: 64 are enough, 256 satisfy
 * Nyquist), with colour and opacity of each step read from the iteration table
 * (GetIterationTable), which also serves the GPU builder so that both integrate the same
 * function. P(t) is clamped to the scalar range: the quadratic overshoots its samples by up
 * to 1/8 of their spread, the trilinear field never leaves the data range. A slab whose
 * scalar stays inside one zero-opacity run is set to zero without integration, and one whose
 * scalar stays constant uses the exact exponential; both follow from the range of P over
 * [0, 1]. Built on the CPU with vtkSMPTools.
 */
#ifndef vtkSecondOrderPreIntegrationTable_h
#define vtkSecondOrderPreIntegrationTable_h

#include "hovrRenderingCoreModule.h" // For export macro
#include "vtkPreIntegrationTable.h"

class HOVRRENDERINGCORE_EXPORT vtkSecondOrderPreIntegrationTable : public vtkPreIntegrationTable
{
public:
  static vtkSecondOrderPreIntegrationTable* New();
  vtkTypeMacro(vtkSecondOrderPreIntegrationTable, vtkPreIntegrationTable);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  int GetNumberOfDimensions() const override { return 3; }

  ///@{
  /**
   * Integration steps along a slab. Initial value is 64.
   */
  vtkSetClampMacro(Iterations, int, 1, 4096);
  vtkGetMacro(Iterations, int);
  ///@}

  /**
   * Samples of the iteration table per table spacing in the last build: at least 8, and
   * enough for 16 samples across the narrowest transfer-function feature. With AdaptiveAxes
   * the entries are not equispaced and the iteration table may be finer still (16 samples
   * per narrowest feature over the whole range); GPU builders then do not apply. The iteration
   * table samples the transfer function densely over the scalar range; each step of the
   * integration reads it with linear interpolation.
   */
  vtkGetMacro(IterationSamplesPerSpacing, int);

  /**
   * The iteration table of the last build: for IterationSamplesPerSpacing (TableSize - 1) + 1
   * equispaced scalars over ScalarRange, RGBA = (c a, a) with a = 1 - exp(-tau L /
   * Iterations), the premultiplied colour and opacity of one integration step.
   */
  vtkFloatArray* GetIterationTable() { return this->IterationTable; }

  /**
   * Zero-opacity run of each spacing of the iteration table (-1 where there is opacity), the
   * fine counterpart of GetEmptyRuns() used to skip empty slabs during the build.
   */
  vtkFloatArray* GetIterationEmptyRuns() { return this->IterationEmptyRuns; }

  /**
   * RGBA of entry (front, middle, back) after Update().
   */
  void GetEntry(int front, int middle, int back, double rgba[4]);

  /**
   * Fill the iteration table and its empty runs for the current settings (done by Update();
   * public for builders that integrate elsewhere, e.g. on the GPU). The sampler must be
   * prepared.
   */
  void BuildIterationTable();

protected:
  vtkSecondOrderPreIntegrationTable();
  ~vtkSecondOrderPreIntegrationTable() override;

  void BuildTable() override;

  int Iterations = 64;
  int IterationSamplesPerSpacing = 8;
  std::vector<double> EntryPositions; // in iteration-table samples
  vtkFloatArray* IterationTable;
  vtkFloatArray* IterationEmptyRuns;

private:
  vtkSecondOrderPreIntegrationTable(const vtkSecondOrderPreIntegrationTable&) = delete;
  void operator=(const vtkSecondOrderPreIntegrationTable&) = delete;
};

#endif
