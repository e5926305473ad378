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
 * [0, 1]. Built on the CPU with vtkSMPTools. With Prefilter (the default) the transfer
 * function is first box-averaged over one table spacing, so that features narrower than the
 * spacing keep their integral instead of being hit or missed by the entries.
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

  ///@{
  /**
   * Average the transfer function over one table spacing before integrating. A table can
   * only store its entries; between them the renderer interpolates. A feature narrower than
   * the entry spacing is then hit or missed depending on where the entries fall, and at
   * large steps or with 16-bit or float data whose range holds thousands of such features, a
   * table that resolves all of them would be too big. With Prefilter, every entry integrates
   * the transfer function box-averaged over one entry spacing, so each feature keeps
   * its integral wherever it lies and interpolation between entries is smooth; slabs whose
   * scalar sweeps across many spacings are unchanged, as is a transfer function that is
   * linear over each spacing. Initial value is true.
   */
  vtkSetMacro(Prefilter, bool);
  vtkGetMacro(Prefilter, bool);
  vtkBooleanMacro(Prefilter, bool);
  ///@}

  /**
   * Samples of the iteration table per table spacing in the last build: at least 8, and
   * enough for 16 samples across the narrowest transfer-function feature. The iteration
   * table samples the transfer function densely over the scalar range; each step of the
   * integration reads it with linear interpolation.
   */
  vtkGetMacro(IterationSamplesPerSpacing, int);

  /**
   * The iteration table of the last build: for IterationSamplesPerSpacing (TableSize - 1) + 1
   * equispaced scalars over ScalarRange, RGBA = (c a, a) with a = 1 - exp(-tau L /
   * Iterations), the premultiplied colour and opacity of one integration step (c and tau of
   * the prefiltered transfer function when Prefilter is on).
   */
  vtkFloatArray* GetIterationTable() { return this->IterationTable; }

  /**
   * The constant-scalar slab of each entry (the table diagonal), RGBA = (c alpha, alpha) with
   * alpha = 1 - exp(-tau SegmentLength), tau and c of the (prefiltered) transfer function at
   * the entry's scalar. Filled by BuildIterationTable().
   */
  vtkFloatArray* GetDiagonalTable() { return this->DiagonalTable; }

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

  // The prefilter spreads opacity by half a spacing; the quadratic between entries of one
  // spacing overshoots them by at most an eighth of it, also within that margin.
  double GetEmptyRunMargin() const override;

  int Iterations = 64;
  int IterationSamplesPerSpacing = 8;
  bool Prefilter = true;
  vtkFloatArray* IterationTable;
  vtkFloatArray* IterationEmptyRuns;
  vtkFloatArray* DiagonalTable;

private:
  vtkSecondOrderPreIntegrationTable(const vtkSecondOrderPreIntegrationTable&) = delete;
  void operator=(const vtkSecondOrderPreIntegrationTable&) = delete;
};

#endif
