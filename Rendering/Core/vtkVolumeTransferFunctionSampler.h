// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
/**
 * @class   vtkVolumeTransferFunctionSampler
 * @brief   exact evaluation and tabulation of a scalar volume's transfer functions
 *
 * Turns a colour transfer function and a scalar opacity function into the two quantities of
 * the volume-rendering integral C = int c(s) tau(s) exp(-int tau) dt:
 *   - colour c(s), between the colour nodes as vtkColorTransferFunction interpolates it in
 *     its colour space: RGB and Step exactly; Lab, Diverging and HSV through a
 *     piecewise-linear RGB curve through VTK's colours, within a tenth of a 1/255 level;
 *     Lab/CIEDE2000, whose path VTK computes per table, to about 0.03,
 *   - extinction tau(s) = -ln(1 - alpha(s)) / U, U being the scalar opacity unit distance,
 * which is VTK's meaning of opacity (an opacity alpha per unit distance U).
 *
 * Evaluation reproduces the node semantics of vtkPiecewiseFunction and
 * vtkColorTransferFunction (midpoint, sharpness, clamping to the end nodes) in double
 * precision, from a private copy of the nodes made by Prepare(); after that it is thread-safe
 * and does not touch the VTK functions. Values outside the nodes take the end values,
 * whatever the clamping flags say.
 *
 * Opacity is capped at MaximumOpacity so that the extinction stays finite: a transfer function
 * opacity of exactly 1 means "opaque within a tiny distance", never an infinite coefficient.
 *
 * Every consumer of transfer functions in hovr (pre-integration tables, the reference
 * integrator, the benchmark) goes through this class so that they agree on what the transfer
 * function means.
 */
#ifndef vtkVolumeTransferFunctionSampler_h
#define vtkVolumeTransferFunctionSampler_h

#include "hovrRenderingCoreModule.h" // For export macro
#include "vtkObject.h"

class vtkColorTransferFunction;
class vtkPiecewiseFunction;
class vtkVolumeProperty;

class HOVRRENDERINGCORE_EXPORT vtkVolumeTransferFunctionSampler : public vtkObject
{
public:
  static vtkVolumeTransferFunctionSampler* New();
  vtkTypeMacro(vtkVolumeTransferFunctionSampler, vtkObject);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /**
   * Colour transfer function. Initial value is nullptr.
   */
  virtual void SetColor(vtkColorTransferFunction*);
  vtkGetObjectMacro(Color, vtkColorTransferFunction);
  ///@}

  ///@{
  /**
   * Grey colour function, used when no colour transfer function is set (as
   * vtkVolumeProperty::SetColor(vtkPiecewiseFunction*)): colour (g, g, g). Initial value is
   * nullptr.
   */
  virtual void SetGrayColor(vtkPiecewiseFunction*);
  vtkGetObjectMacro(GrayColor, vtkPiecewiseFunction);
  ///@}

  ///@{
  /**
   * Scalar opacity function: opacity per ScalarOpacityUnitDistance. Initial value is nullptr.
   */
  virtual void SetScalarOpacity(vtkPiecewiseFunction*);
  vtkGetObjectMacro(ScalarOpacity, vtkPiecewiseFunction);
  ///@}

  ///@{
  /**
   * Distance in world units over which ScalarOpacity holds; must lie in [1e-30, 1e30] (an
   * error in Prepare() otherwise), where the extinction stays within float range.
   * Initial value is 1.0.
   */
  vtkSetMacro(ScalarOpacityUnitDistance, double);
  vtkGetMacro(ScalarOpacityUnitDistance, double);
  ///@}

  ///@{
  /**
   * Largest opacity honoured, in (0, 1). Initial value is 1 - 1e-9, so the largest extinction
   * is about 20.7 / ScalarOpacityUnitDistance.
   */
  vtkSetClampMacro(MaximumOpacity, double, 1e-6, 1.0 - 1e-15);
  vtkGetMacro(MaximumOpacity, double);
  ///@}

  /**
   * Take colour (RGB or grey), scalar opacity and unit distance of component 0 of a volume
   * property. Like VTK's mappers, a property without functions yields VTK's default ones.
   */
  void SetFromVolumeProperty(vtkVolumeProperty* property);

  /**
   * Take the functions, unit distance and opacity cap of another sampler (shared, not copied).
   */
  void SetFromSampler(vtkVolumeTransferFunctionSampler* other);

  /**
   * Take copies of the functions of another sampler (later edits of its functions do not
   * reach this one), its unit distance and opacity cap, and Prepare(). Returns Prepare()'s
   * result.
   */
  bool DeepCopy(vtkVolumeTransferFunctionSampler* other);

  /**
   * The closed scalar interval outside which this sampler evaluates as `before` did (both
   * prepared): Evaluate(), EvaluateOpacity(), GetMaximumOpacity(), GetSmallestFeature() and
   * GetLongestSweep() on values and intervals that do not meet [range[0], range[1]] give the
   * same results. A node that changed reaches to its neighbours (the node intervals it
   * bounds), and beyond the end nodes to infinity; the whole line when a function gained or
   * lost nodes or the unit distance or opacity cap differ; empty (range[0] > range[1]) when
   * nothing evaluates differently.
   */
  void GetChangedRange(vtkVolumeTransferFunctionSampler* before, double range[2]) const;

  /**
   * Whether this sampler differs from `before` (both prepared) in its colours alone: the same
   * opacity, unit distance, opacity cap and node positions, and colours that interpolate
   * linearly (or hold) between their nodes in both, at the same places (no node's sharpness
   * between 0.01 and 0.99, where VTK's curve is not linear in the colours). A colour of either
   * is then the same weighting of its colour nodes' values (GetColorWeights()).
   */
  bool IsColorEditOf(vtkVolumeTransferFunctionSampler* before) const;

  /**
   * Colour nodes as evaluated: the function's nodes in RGB, the piecewise-linear curve
   * followed in other colour spaces. Requires Prepare().
   */
  int GetNumberOfColorNodes() const;

  /**
   * The colour at scalar s as a weighting of two colour nodes, where colours interpolate
   * linearly or hold (see IsColorEditOf()): colour = weights[0] node[k] + weights[1] node[k + 1],
   * k returned (weights[1] is 0 outside the nodes). Requires Prepare().
   */
  int GetColorWeights(double s, double weights[2]) const;

  /**
   * The sum over the colour nodes of weights[k] times node k's colour, for
   * GetNumberOfColorNodes() weights. Requires Prepare().
   */
  void CombineColors(const double* weights, double rgb[3]) const;

  /**
   * Check the settings and copy the nodes for evaluation. Returns false and reports an error
   * if a function is missing or empty or the unit distance is not positive (or not finite). Cheap
   * when nothing changed since the last call.
   */
  bool Prepare();

  /**
   * A hash (53 bits, exact in a double) of everything evaluation reads, as of the last
   * Prepare(): the nodes as evaluated, the unit distance and the opacity cap. Two samplers, or
   * one before and after an edit that changed nothing (a function rebuilt with the same nodes,
   * a modification time bumped), evaluate alike where their hashes are equal: caches keyed by
   * it survive such edits, which keys of modification times do not. 0 before Prepare().
   */
  double GetContentHash() const;

  /**
   * Colour and extinction at scalar s: rgbTau = (r, g, b, tau). Requires Prepare().
   * A NaN scalar gives a transparent black sample.
   */
  void Evaluate(double s, double rgbTau[4]) const;

  /**
   * Opacity alpha(s) of the scalar opacity function, capped at MaximumOpacity.
   */
  double EvaluateOpacity(double s) const;

  /**
   * Extinction tau(s) = -ln(1 - alpha(s)) / U.
   */
  double EvaluateExtinction(double s) const;

  /**
   * Sample n >= 2 equispaced scalars over [s0, s1], both included, into rgbTau (4 n values).
   */
  void Sample(double s0, double s1, int n, double* rgbTau) const;

  /**
   * Largest opacity over the closed scalar interval [s0, s1]. Exact: VTK's interpolation is
   * monotone between nodes, so the maximum is at an end or a node.
   */
  double GetMaximumOpacity(double s0, double s1) const;

  /**
   * Smallest distance between two adjacent distinct nodes of either function: the width of
   * the narrowest transfer-function feature. Returns VTK_DOUBLE_MAX with fewer than 2 nodes.
   */
  double GetSmallestFeature() const;

  /**
   * The narrowest feature among those the scalar interval [s0, s1] overlaps: the smallest
   * distance between adjacent distinct nodes of either function whose interval meets
   * [s0, s1]. VTK_DOUBLE_MAX where both functions are constant over [s0, s1] (outside every
   * node interval). Requires Prepare().
   */
  double GetSmallestFeature(double s0, double s1) const;

  /**
   * The longest scalar sweep sigma <= cap of an integration piece that starts at s, such that
   * sigma <= tolerance * f, f being the narrowest feature (at most widest) that the values
   * within sigma of s meet (GetSmallestFeature(s - sigma, s + sigma)): a piece far from a
   * narrow feature needs no fine step. Requires Prepare().
   */
  double GetLongestSweep(double s, double tolerance, double widest, double cap) const;

  /**
   * The same for the nodes of the opacity function only: what integrated quantities (opacity,
   * and colour weighted by it) vary with fastest.
   */
  double GetSmallestOpacityFeature() const;

  /**
   * Scalar range spanned by the nodes of both functions.
   */
  void GetNodeRange(double range[2]) const;

  /**
   * Modification time including the transfer functions themselves.
   */
  vtkMTimeType GetMTime() override;

protected:
  vtkVolumeTransferFunctionSampler();
  ~vtkVolumeTransferFunctionSampler() override;

  vtkColorTransferFunction* Color = nullptr;
  vtkPiecewiseFunction* GrayColor = nullptr;
  vtkPiecewiseFunction* ScalarOpacity = nullptr;
  double ScalarOpacityUnitDistance = 1.0;
  double MaximumOpacity = 1.0 - 1e-9;

private:
  vtkVolumeTransferFunctionSampler(const vtkVolumeTransferFunctionSampler&) = delete;
  void operator=(const vtkVolumeTransferFunctionSampler&) = delete;

  class vtkInternals;
  vtkInternals* Internals;
};

#endif
