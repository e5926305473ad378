// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
/**
 * @class   vtkFirstOrderPreIntegrationTable
 * @brief   classic pre-integration: a 2D table over (front scalar, back scalar)
 *
 * Engel, Kraus and Ertl (2001), in the notation of El Hajjar et al. (second-order paper,
 * section 3.2.2): within a segment of length d the scalar is taken linear from s_f to s_b,
 * and the table stores
 *   alpha(s_f, s_b) = 1 - exp(-int_0^d tau(s(t)) dt),
 *   C(s_f, s_b)     = int_0^d c(s(t)) tau(s(t)) exp(-int_0^t tau) dt,
 * colour premultiplied and self-attenuated inside the segment. Entry (i, j) holds
 * s_f = scalar of entry i (first axis, fastest) and s_b = scalar of entry j.
 *
 * The integral is evaluated with SubSamples pieces per table spacing crossed (midpoint rule,
 * exact for constant pieces), so the pieces' midpoints lie on one fixed grid of scalars where
 * the transfer function is evaluated once; a segment with s_f = s_b is exact. Built on the
 * CPU with vtkSMPTools, one scalar difference |j - i| per task: its entries are windows of the
 * same number of pieces sliding over the pieces, each composited from two runs kept per piece
 * (compositing is associative), so a table costs O(TableSize^2 SubSamples).
 */
#ifndef vtkFirstOrderPreIntegrationTable_h
#define vtkFirstOrderPreIntegrationTable_h

#include "hovrRenderingCoreModule.h" // For export macro
#include "vtkPreIntegrationTable.h"

class HOVRRENDERINGCORE_EXPORT vtkFirstOrderPreIntegrationTable : public vtkPreIntegrationTable
{
public:
  static vtkFirstOrderPreIntegrationTable* New();
  vtkTypeMacro(vtkFirstOrderPreIntegrationTable, vtkPreIntegrationTable);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  int GetNumberOfDimensions() const override { return 2; }

  ///@{
  /**
   * Integration pieces per table spacing that the segment's scalar crosses; 0 chooses
   * max(1, min(4, 1024 / TableSize)), which keeps large tables quick to build (the cost grows
   * as TableSize^2 SubSamples). Initial value is 0.
   */
  vtkSetClampMacro(SubSamples, int, 0, 256);
  vtkGetMacro(SubSamples, int);
  ///@}

  /**
   * The pieces per table spacing the next build uses (SubSamples, or its automatic value).
   */
  int GetEffectiveSubSamples() const;

  /**
   * RGBA of entry (front, back) after Update().
   */
  void GetEntry(int front, int back, double rgba[4]);

protected:
  vtkFirstOrderPreIntegrationTable();
  ~vtkFirstOrderPreIntegrationTable() override;

  void BuildTable() override;
  void AppendBuildKey(std::vector<double>& key) const override;

  int SubSamples = 0;

private:
  vtkFirstOrderPreIntegrationTable(const vtkFirstOrderPreIntegrationTable&) = delete;
  void operator=(const vtkFirstOrderPreIntegrationTable&) = delete;
};

#endif
