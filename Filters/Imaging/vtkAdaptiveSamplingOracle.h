// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
/**
 * @class   vtkAdaptiveSamplingOracle
 * @brief   distance to the nearest change of opacity, for adaptive sampling of a volume
 *
 * The oracle volume of "Adaptive Sampling in Three Dimensions for Volume Rendering on GPUs":
 * an oracle returns a preferred sampling distance d
 * for any point (line 49), and the renderer skips the samples closer than d. The paper's own
 * oracle is "pre-computed and stored with the data set" and "estimates the distance to the
 * nearest voxel that features a gradient magnitude of the opacity greater than some
 * threshold" (lines 231-236). This filter computes that volume: at each point, the Euclidean
 * distance in world units (spacing respected) to the nearest feature point, capped at the
 * maximum distance; the renderer converts it to its own units (slice spacing) per frame.
 *
 * Feature points, per Mode, with alpha = the ScalarOpacity function at the point's scalar (the
 * transfer function's opacity, not corrected for any step length):
 * - OPACITY_GRADIENT, the paper's test: |grad alpha| > Epsilon, the gradient by central
 *   differences (alpha[i+1] - alpha[i-1]) / 2 in per-voxel units (so that Epsilon is a change
 *   of opacity per voxel, whatever the spacing), one-sided alpha[1] - alpha[0] on the faces, 0
 *   along an axis with a single point. (vtkImageGradientMagnitude with HandleBoundaries on
 *   repeats the edge value instead, which halves the face-normal component.)
 * - OPACITY_RANGE (initial): max - min of alpha over the scalar interval [smin, smax] exceeds
 *   Epsilon, smin and smax the least and greatest scalar over the point's 3 x 3 x 3
 *   neighbourhood (truncated at the faces): the values of every trilinear cell touching the
 *   point. The paper's test looks at alpha at the points only, so a transfer-function spike
 *   between two neighbouring values (10 and 20, spike at 15) is not seen, and the renderer
 *   would skip what it should draw; this test sees it. Away from the faces it never finds
 *   fewer features than OPACITY_GRADIENT with the same Epsilon: there |grad alpha| is at most
 *   sqrt(3)/2 times the opacity range of the neighbourhood (on the faces the one-sided
 *   differences can exceed it). The range of alpha over an interval is exact for any
 *   vtkPiecewiseFunction: between two nodes the function is monotonic (linear, a step, or
 *   VTK's Hermite curve whose tangents are at most the nodes' difference; to rounding), so its
 *   extremes over [a, b] are among alpha(a), alpha(b) and the nodes' values inside. A point whose
 * neighbourhood has a single value (smin = smax) is never a feature. The smin and smax volumes do
 * not depend on the transfer function and are kept between updates: an update where only the
 * transfer function or a setting changed recomputes only the feature mask and the distances (see
 *   GetLastRecomputedRanges). They are recomputed when the input array, its values (its
 *   modification time) or the input image change, and released in the other modes.
 * - MIN: 0 everywhere (the paper's "min." oracle, full-rate sampling, line 231).
 * - MAX: the maximum distance everywhere.
 * Without any feature point every point gets the maximum distance.
 *
 * NaN scalars are transparent: alpha = 0 there (OPACITY_GRADIENT), and a NaN in a
 * neighbourhood adds opacity 0 to its range (OPACITY_RANGE), since the renderer draws nothing
 * there. An opacity the function evaluates to NaN (a log-scale function at values <= 0) counts
 * as 0. Infinite scalars take the function's value beyond its last node (or 0 without
 * Clamping), as vtkPiecewiseFunction::GetValue gives.
 *
 * The distance transform is exact (up to float rounding): the squared distance to the nearest
 * feature along x by two scans of each row, then along y and along z the lower envelope of
 * parabolas of Felzenszwalb and Huttenlocher ("Distance transforms of sampled functions",
 * Theory of Computing 8, 2012), each weighted by its axis's squared spacing. Distances beyond
 * the cap are dropped after each pass (a later pass only adds to them). It is also available
 * alone (DistanceTransform). The result is vtkImageEuclideanDistance's (squared distances,
 * ConsiderAnisotropy on) square-rooted and capped, where that filter is right: VTK 9.1's
 * applies the spacing of its last pass (z) only, so it agrees for spacings (1, 1, s), and for
 * any spacing when run one axis at a time (as the test does).
 *
 * Output: the input image (a shallow copy, every array passed through) with a 1-component
 * float point array named OutputArrayName. The image's direction matrix is not applied
 * (distances along the axes use the spacing), as vtkImageEuclideanDistance does. The filter
 * needs the whole extent (a distance can reach across the volume): it asks for it and crops
 * its output to the requested extent.
 *
 * Cost: O(number of points) for every step, in vtkSMPTools threads: the range volumes (two
 * values of the input's type per point, kept), a one-byte feature mask and the output array.
 * Progress events come between chunks of work on the calling thread, and AbortExecute is
 * honoured there (the output then has no distance array, and half-computed ranges are dropped).
 *
 * Answer first, refine after (RefineInBackground): an interactive application that edits the
 * opacity function, or steps through time, gets each update's output at once with the
 * distances it last output (when they are on the same grid, with the same settings), and the
 * new distances are computed in a worker thread of low priority (vtkBackgroundWorker,
 * vtkLowPriorityThreads), a newer update stopping an older computation; during a drag (updates
 * less than a second apart) a computation waits one and a half times the time since the last
 * update before it starts, so that it does not slow the drag's frames. The stale distances
 * may skip a feature the edit made: the renderer's frame is an interim one, and
 * CheckRefinement() (from the application's event loop) fires OracleRefinedEvent and marks the
 * filter modified when the new distances are ready, so that the next update outputs them.
 * Batch use keeps it off: every update computes its own distances.
 *
 * Bad input or settings are reported through vtkErrorMacro with an empty output: no
 * ScalarOpacity (or one without points) in the opacity modes, no input array, a cell array,
 * more than one component, a point count that does not match the grid, an empty image, a zero
 * or non-finite spacing, spacings so unequal that a squared distance across the grid in
 * smallest spacings overflows a float (ratios near 10^19), a negative or non-finite Epsilon, a
 * maximum distance that is not positive and finite as a float, an empty OutputArrayName or one
 * equal to the input array's name.
 *
 * @sa vtkImageEuclideanDistance vtkImageGradientMagnitude vtkPiecewiseFunction
 */
#ifndef vtkAdaptiveSamplingOracle_h
#define vtkAdaptiveSamplingOracle_h

#include "hovrFiltersImagingModule.h" // For export macro
#include "vtkCommand.h"               // For OracleRefinedEvent
#include "vtkImageAlgorithm.h"

#include <memory> // For std::unique_ptr

class vtkDataArray;
class vtkFloatArray;
class vtkPiecewiseFunction;

class HOVRFILTERSIMAGING_EXPORT vtkAdaptiveSamplingOracle : public vtkImageAlgorithm
{
public:
  static vtkAdaptiveSamplingOracle* New();
  vtkTypeMacro(vtkAdaptiveSamplingOracle, vtkImageAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  enum Modes
  {
    OPACITY_GRADIENT = 0,
    OPACITY_RANGE = 1,
    MIN = 2,
    MAX = 3
  };

  ///@{
  /**
   * Which points are features (see the class description): OPACITY_GRADIENT (the paper's
   * test), OPACITY_RANGE, MIN (distance 0 everywhere) or MAX (the maximum distance
   * everywhere). Initial value is OPACITY_RANGE.
   */
  vtkSetClampMacro(Mode, int, OPACITY_GRADIENT, MAX);
  vtkGetMacro(Mode, int);
  void SetModeToOpacityGradient() { this->SetMode(OPACITY_GRADIENT); }
  void SetModeToOpacityRange() { this->SetMode(OPACITY_RANGE); }
  void SetModeToMin() { this->SetMode(MIN); }
  void SetModeToMax() { this->SetMode(MAX); }
  const char* GetModeAsString();
  ///@}

  ///@{
  /**
   * The opacity transfer function alpha(scalar), as given to the volume property (not
   * corrected for the step length). Required in the two opacity modes; MIN and MAX do not read
   * it. Editing it (or replacing it) makes the next update recompute the feature mask and the
   * distances. Initial value is nullptr.
   */
  virtual void SetScalarOpacity(vtkPiecewiseFunction*);
  vtkGetObjectMacro(ScalarOpacity, vtkPiecewiseFunction);
  ///@}

  ///@{
  /**
   * Convenience for the transfer function as a list of (scalar, opacity) pairs (ParaView's
   * property): AddOpacityPoint adds a linear node to ScalarOpacity, creating a function first
   * when there is none; RemoveAllOpacityPoints removes every node of ScalarOpacity (if any).
   * Both edit the function that is set, which may be shared with a volume property.
   */
  void AddOpacityPoint(double scalar, double opacity);
  void RemoveAllOpacityPoints();
  ///@}

  ///@{
  /**
   * The feature threshold: a change of opacity per voxel (OPACITY_GRADIENT) or over a
   * neighbourhood (OPACITY_RANGE) that makes a feature when exceeded; finite and >= 0. Initial
   * value is 0.002, about half an 8-bit opacity level (the paper gives no value).
   */
  vtkSetMacro(Epsilon, double);
  vtkGetMacro(Epsilon, double);
  ///@}

  ///@{
  /**
   * Whether the cap of the distances is 8 times the input's smallest spacing (l_max = 3 of the
   * paper, line 236, at one sample per voxel) rather than MaximumDistance. Initial value is on.
   */
  vtkSetMacro(AutomaticMaximumDistance, vtkTypeBool);
  vtkGetMacro(AutomaticMaximumDistance, vtkTypeBool);
  vtkBooleanMacro(AutomaticMaximumDistance, vtkTypeBool);
  ///@}

  ///@{
  /**
   * The cap of the distances in world units, > 0 and finite as a float, used when
   * AutomaticMaximumDistance is off (setting it does not turn that off). Points farther from
   * every feature, and every point when there is none, get the cap. Initial value is 1.0.
   */
  vtkSetMacro(MaximumDistance, double);
  vtkGetMacro(MaximumDistance, double);
  ///@}

  ///@{
  /**
   * Name of the output distance array. Initial value is "OracleDistance".
   */
  vtkSetStringMacro(OutputArrayName);
  vtkGetStringMacro(OutputArrayName);
  ///@}

  ///@{
  /**
   * What the last update did: whether it computed the smin/smax volumes of OPACITY_RANGE
   * (false when it reused them, and in the other modes), how many feature points it found (0
   * in MIN and MAX), and the cap it used (0 before the first successful update).
   */
  vtkGetMacro(LastRecomputedRanges, bool);
  vtkGetMacro(LastNumberOfFeaturePoints, vtkIdType);
  vtkGetMacro(LastMaximumDistance, double);
  ///@}

  /**
   * The distance transform of the filter on its own: for a feature mask of dims[0] x dims[1] x
   * dims[2] points (x fastest; a non-zero value is a feature, any array type, one component),
   * distances receives min(Euclidean distance in world units to the nearest feature point,
   * maximumDistance) per point, maximumDistance where there is no feature. spacing: finite and
   * non-zero (its sign is ignored), its ratios within the class's limit; maximumDistance:
   * > 0 and finite as a float. Returns false, leaving distances untouched, on bad arguments.
   */
  static bool DistanceTransform(vtkDataArray* mask,
    const int dims[3],
    const double spacing[3],
    double maximumDistance,
    vtkFloatArray* distances);

  /**
   * Includes the modification time of ScalarOpacity.
   */
  vtkMTimeType GetMTime() override;

  /**
   * Fired by CheckRefinement() when distances computed in the background wait to be output:
   * update (render) again to get them.
   */
  enum RefinementEvents
  {
    OracleRefinedEvent = vtkCommand::UserEvent + 7302
  };

  ///@{
  /**
   * Answer first, refine after (see the class description): an update that needs new
   * distances outputs the last ones at once when they are on the same grid with the same
   * settings, and computes the new ones in a worker thread. Otherwise (the first update, a new
   * grid, a new setting, an input that fails its checks) the update computes them itself.
   * Turning it off stops the computation in the background. Initial value is false.
   */
  virtual void SetRefineInBackground(bool refine);
  vtkGetMacro(RefineInBackground, bool);
  vtkBooleanMacro(RefineInBackground, bool);
  ///@}

  /**
   * Whether the last output holds interim distances whose own are not output yet (being
   * computed, or waiting for the next update).
   */
  bool GetRefining();

  /**
   * Whether distances computed in the background wait for the next update.
   */
  bool GetRefinementReady();

  /**
   * How far the computation in the background is, in [0, 1] (1: none runs).
   */
  double GetRefinementProgress();

  /**
   * Fires OracleRefinedEvent, marks the filter modified and returns true when the background
   * computation of the last output's distances has ended (with distances, or with an error
   * the next update reports); call it from the application's event loop.
   */
  bool CheckRefinement();

  /**
   * Block until the background computation of the last output's distances has ended, and
   * mark the filter modified so that the next update outputs them.
   */
  void WaitForRefinement();

  /**
   * Whether the passes run in threads of low priority (vtkLowPriorityThreads) rather than
   * vtkSMPTools': on for the instance that computes in the background. Initial value is false.
   */
  bool GetLowPriority() { return this->LowPriority; }

protected:
  vtkAdaptiveSamplingOracle();
  ~vtkAdaptiveSamplingOracle() override;

  int RequestInformation(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  int RequestUpdateExtent(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  int Mode = OPACITY_RANGE;
  vtkPiecewiseFunction* ScalarOpacity = nullptr;
  double Epsilon = 0.002;
  vtkTypeBool AutomaticMaximumDistance = 1;
  double MaximumDistance = 1.0;
  char* OutputArrayName = nullptr;

  bool LastRecomputedRanges = false;
  vtkIdType LastNumberOfFeaturePoints = 0;
  double LastMaximumDistance = 0.0;
  bool RefineInBackground = false;
  bool LowPriority = false;

private:
  vtkAdaptiveSamplingOracle(const vtkAdaptiveSamplingOracle&) = delete;
  void operator=(const vtkAdaptiveSamplingOracle&) = delete;

  struct RangeCache;
  std::unique_ptr<RangeCache> Cache; // the smin/smax volumes of OPACITY_RANGE
  struct vtkBackground;
  std::unique_ptr<vtkBackground> Background; // the worker and what it computes
  // The update of RefineInBackground: interim distances and a job, or the distances at once.
  int RequestDataInBackground(vtkImageData* input,
    vtkDataArray* scalars,
    int association,
    vtkImageData* output,
    vtkInformation* outInfo);
};

#endif
