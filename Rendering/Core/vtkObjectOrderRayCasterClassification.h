// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
/**
 * @class   vtkObjectOrderRayCasterClassification
 * @brief   the classification tables of vtkObjectOrderRayCaster's sample loop
 *
 * The point-sampled table over the data range (RGB and the alpha of one step per entry,
 * entries at S0 + e / InvStep), the bins of that table where the opacity may be non-zero
 * (which decide the visible octree nodes and cells) and, for pre-integrated classification,
 * the first-order table over (front, back) scalar for one step, in float for the sample loop.
 * The tables are rebuilt only when the transfer functions, the data range, the size or the
 * step change.
 *
 * Part of vtkObjectOrderRayCaster's frame: a value class for its inner loops (not a
 * vtkObject, not wrapped, not installed).
 */
#ifndef vtkObjectOrderRayCasterClassification_h
#define vtkObjectOrderRayCasterClassification_h

#include <algorithm> // For std::min
#include <array>     // For std::array
#include <vector>    // For std::vector

class vtkFirstOrderPreIntegrationTable;
class vtkVolumeProperty;
class vtkVolumeTransferFunctionSampler;

class vtkObjectOrderRayCasterClassification
{
public:
  /**
   * The point-sampled table (Entries of them) for scalars of this data type over range (not
   * empty) and samples step apart; true when the tables were rebuilt (then the bricks'
   * visible cells are to be found again).
   */
  bool Update(vtkVolumeTransferFunctionSampler* sampler,
    int dataType,
    const double range[2],
    double step);

  /**
   * The pre-integrated segments of one step over range from the first-order table (updated
   * here); false when the table fails.
   */
  bool UpdateSegments(vtkFirstOrderPreIntegrationTable* table,
    vtkVolumeProperty* property,
    vtkVolumeTransferFunctionSampler* sampler,
    int dataType,
    const double range[2],
    double step);

  /**
   * Whether the opacity can be non-zero somewhere in [lo, hi] (conservative: whole bins).
   */
  bool Visible(double lo, double hi) const
  {
    if (!(lo <= hi) || this->Entries < 2)
    {
      return false;
    }
    // Clamped to [0, last] before the conversion, which then truncates like floor.
    const double last = this->Entries - 2;
    const int b0 = static_cast<int>(std::min(std::max((lo - this->S0) * this->InvStep, 0.0), last));
    const int b1 = static_cast<int>(std::min(std::max((hi - this->S0) * this->InvStep, 0.0), last));
    return this->VisiblePrefix[b1 + 1] - this->VisiblePrefix[b0] > 0;
  }

  // Point-sampled: RGBA per entry (alpha for one step), entries at S0 + e / InvStep.
  std::vector<float> Table;
  int Entries = 0;
  double S0 = 0.0, InvStep = 1.0;
  std::vector<int> VisiblePrefix;      // visible bins before bin b
  std::array<double, 5> TableKey = {}; // what the two tables above were built for
  // Pre-integrated: the first-order table over (front, back) scalar for one step (RGBA
  // premultiplied, front fastest), entries at S0 + e / SegmentInvStep.
  bool Preintegrated = false;
  const float* Segments = nullptr;
  int SegmentEntries = 0;
  double SegmentInvStep = 1.0;
};

#endif
