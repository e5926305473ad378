// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
/**
 * @class   vtkAdaptiveSamplingRayCaster
 * @brief   the GL-free core of adaptive sampling in three dimensions with an oracle
 *
 * "Adaptive Sampling in Three Dimensions for Volume Rendering on GPUs", on the CPU, in double,
 * counting its operations:
 *   - view-aligned slices spaced by Delta, the distance between neighbouring view rays
 *     (line 68): 2 ParallelScale / image height. Slice 0 passes through the box corner of the
 *     volume's points nearest to the camera, and the last slice index i_max is the first
 *     multiple of 2^MaximumLevel at or behind the farthest corner (line 78; padding to that
 *     multiple instead of Fig. 6's next power of two). Parallel projection only: a
 *     perspective camera is an error (shells are the paper's future work, line 250);
 *   - a pyramid of levels 0..MaximumLevel over the image plane (Sec. 3.2): level l has
 *     (W / 2^l) x (H / 2^l) pixels, its pixel (x, y) samples the ray through level-0 pixel
 *     (2^l (x + 1/2) - 1/2, 2^l (y + 1/2) - 1/2) (Fig. 5, lines 137-138); W and H must be
 *     divisible by 2^MaximumLevel (an error otherwise);
 *   - per slice i, l_slice = SliceLevel(i) (Table 1, line 76), levels l_slice down to 0 with
 *     the pseudo code of Fig. 7 (ALGORITHM_FIG7, initial: synthesis of every pixel below
 *     l_slice, then sample iff d < 2^(l+1) or l = MaximumLevel, accumulate iff
 *     d < 2^(l_slice+1) or l_slice = MaximumLevel, both decided on d before it is resampled) or
 *     of Fig. 3 (ALGORITHM_FIG3: synthesis only where the stored d asks for accumulation,
 *     accumulation decided after resampling). They differ: Fig. 3 keeps stale values of
 *     skipped pixels, and can sample a pixel whose new d then fails the accumulation test;
 *   - SYNTHESIZE (Fig. 5) as bilinear interpolation of level l + 1 at the fine pixel's centre,
 *     clamped to the edge (the GL_LINEAR + GL_CLAMP_TO_EDGE lookup of line 127);
 *   - ACCUMULATECOLOR (Fig. 6): front-to-back compositing of the part of the segment from the
 *     ray's previous accumulated slice i_prev to this one i that lies inside the box of the
 *     volume's points, [max(i_prev, t_in), min(i, t_out)] with t_in <= t_out the slice
 *     coordinates where the level-0 ray enters and leaves the box (ClipSlices). An end inside
 *     the box takes the slice's value (stored or just sampled or synthesised); an end on a face
 *     takes the scalar fetched at the entry or exit point. A piece of length L (slice spacings,
 *     0 < L <= 2^MaximumLevel) comes from the ceil(L)-th of 2^MaximumLevel first-order tables
 *     (vtkFirstOrderPreIntegrationTable, segment length ceil(L) Delta), read as
 *     vtkPreIntegrationRayCaster reads a first-order table (bilinear, entries at texel centres,
 *     clamped to the edge), in double, with its optical depth scaled to L
 *     (vtkPreIntegrationRayMarch::Scale, as first-order pre-integration composites its last
 *     piece: exact for a constant scalar). Slice 0 touches the box's nearest corner and slice
 *     i_max, at or behind its farthest, is accumulated by every pixel (l_slice = MaximumLevel
 *     there), so no piece of a ray inside the box is left out. A ray that misses the box or
 *     grazes an edge adds nothing.
 *
 * Samples outside the box of the volume's points (line 68 asks for "a default value mapped to
 * transparent") are NaN, as are NaN scalars: a segment with a NaN end contributes nothing (a
 * ramp from an invented default value would add colour that is not in the data; the entry and
 * exit pieces above take the data's value on the face instead). A synthesised value with a NaN
 * among its four coarse neighbours is NaN too; on a slice where it accumulates, a pixel whose
 * own point on the slice is inside the box samples then, instead of keeping the NaN (so that
 * NaN does not spread inwards from the silhouette, dropping segments of rays inside; on other
 * slices its synthesised values are stale and unused). Outside the box the oracle is the distance
 * to the box in slice spacings, clamped to [1, 2^MaximumLevel], so that rays approach the entry
 * face with shrinking steps.
 *
 * The oracle: the point array OracleArrayName (world units, as vtkAdaptiveSamplingOracle
 * produces it), trilinearly interpolated, divided by Delta and clamped to
 * [1, 2^MaximumLevel]; or, with OracleMode MINIMUM, d = 1 everywhere (the paper's "min." oracle,
 * line 231) without any array. NaN or infinite oracle values are an error.
 *
 * Counters of the last update (one SAMPLE = one volume fetch at a point inside the box;
 * the oracle is fetched with it; points outside the box are not fetched and not counted):
 * GetNumberOfSampleOperations(), GetNumberOfOracleOperations() (equal to the samples; 0 with
 * MINIMUM, which reads no array),
 * GetNumberOfSynthesisOperations() (one per pixel synthesised, s and d together; a pixel
 * that samples because its synthesised value is NaN counts one synthesis and one sample),
 * GetNumberOfAccumulateOperations() (ACCUMULATECOLOR calls on slices after the first),
 * GetNumberOfBoundarySampleOperations() (volume fetches at the points where level-0 rays enter
 * or leave the box, for the pieces of ACCUMULATECOLOR that end on a face: not slice samples,
 * so the sample counts and their ratio to the full rate keep the paper's meaning) and
 * GetFullRateSampleOperations(): level-0 pixels times the slices whose point is inside the box,
 * what a full-rate ray caster takes on the same slice grid. With MINIMUM, level l samples all
 * its pixels on every 2^l-th slice, so the samples exceed the full rate by about
 * sum_{l=1..L} 1/8^l (14.26% for L = 3: the paper's Tables 2 and 3, 49 M -> 56 M and
 * 37 M -> 42 M); coarse rays pass through block centres, so the ratio is not exact.
 *
 * Levels are processed one after the other; the pixels of one level run in vtkSMPTools
 * threads (they are independent, line 100). No early ray termination (not in the paper).
 * Errors leave a transparent image and zero counters.
 */
#ifndef vtkAdaptiveSamplingRayCaster_h
#define vtkAdaptiveSamplingRayCaster_h

#include "hovrRenderingCoreModule.h" // For export macro
#include "vtkVolumeImageAlgorithm.h"

#include <memory> // For std::unique_ptr

class vtkMatrix4x4;

class HOVRRENDERINGCORE_EXPORT vtkAdaptiveSamplingRayCaster : public vtkVolumeImageAlgorithm
{
public:
  static vtkAdaptiveSamplingRayCaster* New();
  vtkTypeMacro(vtkAdaptiveSamplingRayCaster, vtkVolumeImageAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /**
   * The top level l_max of the pyramid: sampling distances reach 2^MaximumLevel slice spacings
   * (line 78; the paper uses 3, line 236). 0 is full-rate first-order pre-integration on the
   * slice grid. Values outside [0, 8] are an error on update. Initial value is 3.
   */
  vtkSetMacro(MaximumLevel, int);
  vtkGetMacro(MaximumLevel, int);
  ///@}

  enum Algorithms
  {
    ALGORITHM_FIG7 = 0, ///< the depth-test variant the paper measured (Fig. 7)
    ALGORITHM_FIG3 = 1  ///< the reference pseudo code (Fig. 3)
  };

  ///@{
  /**
   * Which pseudo code runs each slice. Initial value is ALGORITHM_FIG7.
   */
  vtkSetClampMacro(Algorithm, int, ALGORITHM_FIG7, ALGORITHM_FIG3);
  vtkGetMacro(Algorithm, int);
  void SetAlgorithmToFig7() { this->SetAlgorithm(ALGORITHM_FIG7); }
  void SetAlgorithmToFig3() { this->SetAlgorithm(ALGORITHM_FIG3); }
  ///@}

  enum OracleModes
  {
    ORACLE_ARRAY = 0,  ///< the point array OracleArrayName
    ORACLE_MINIMUM = 1 ///< d = 1 everywhere (the paper's "min." oracle)
  };

  ///@{
  /**
   * Where the oracle distance comes from. Initial value is ORACLE_ARRAY.
   */
  vtkSetClampMacro(OracleMode, int, ORACLE_ARRAY, ORACLE_MINIMUM);
  vtkGetMacro(OracleMode, int);
  void SetOracleModeToArray() { this->SetOracleMode(ORACLE_ARRAY); }
  void SetOracleModeToMinimum() { this->SetOracleMode(ORACLE_MINIMUM); }
  ///@}

  ///@{
  /**
   * The point array of oracle distances in world units (1 component). Initial value is
   * "OracleDistance".
   */
  vtkSetStringMacro(OracleArrayName);
  vtkGetStringMacro(OracleArrayName);
  ///@}

  ///@{
  /**
   * Entries per axis of each first-order table. Initial value is 256.
   */
  vtkSetClampMacro(TableSize, int, 2, 4096);
  vtkGetMacro(TableSize, int);
  ///@}

  ///@{
  /**
   * The most slices across the volume's diagonal; more is an error (empty image) instead of
   * a frame of hours. Initial value is 100000.
   */
  vtkSetClampMacro(MaximumSamplesPerRay, double, 1.0, 1e9);
  vtkGetMacro(MaximumSamplesPerRay, double);
  ///@}

  ///@{
  /**
   * Counters of the last update (see the class description); 0 after an error.
   */
  vtkGetMacro(NumberOfSampleOperations, vtkIdType);
  vtkGetMacro(NumberOfOracleOperations, vtkIdType);
  vtkGetMacro(NumberOfSynthesisOperations, vtkIdType);
  vtkGetMacro(NumberOfAccumulateOperations, vtkIdType);
  vtkGetMacro(NumberOfBoundarySampleOperations, vtkIdType);
  vtkGetMacro(FullRateSampleOperations, vtkIdType);
  vtkGetMacro(NumberOfSlices, vtkIdType);
  vtkGetMacro(SliceSpacing, double);
  ///@}

  /**
   * l_slice of Table 1 (line 76): the largest l <= maximumLevel with sliceIndex mod 2^l = 0,
   * maximumLevel for slice 0. sliceIndex >= 0, maximumLevel in [0, 62].
   */
  static int SliceLevel(vtkIdType sliceIndex, int maximumLevel);

  /**
   * Skipping along one ray with a constant oracle distance d >= 1 (Sec. 3.1):
   * the next slice after sliceIndex that is not skipped, (floor(i / 2^q) + 1) 2^q with
   * q = min(floor(log2 d), maximumLevel).
   */
  static vtkIdType NextSampleSlice(vtkIdType sliceIndex, double d, int maximumLevel);

  /**
   * The slice grid of a parallel view of a grid of dims points whose 0-based index maps to
   * world coordinates by gridToWorld, seen along the unit direction forward from the plane
   * through eye: slice 0 passes through the box corner nearest to that plane (line 57), its
   * depth is returned in nearest, and the result is i_max, the first multiple of
   * 2^maximumLevel at or behind the farthest corner at the slice spacing delta (line 78).
   * axisLength receives the world length of one index step along each grid axis.
   */
  static vtkIdType ComputeSliceGrid(vtkMatrix4x4* gridToWorld,
    const int dims[3],
    const double eye[3],
    const double forward[3],
    double delta,
    int maximumLevel,
    double& nearest,
    double axisLength[3]);

  /**
   * The slice coordinates where the ray origin + t step (0-based continuous grid index, t in
   * slice spacings) enters and leaves the closed box [0, boxMax], clipped to [0, lastSlice]
   * (the slab method, per axis). exit < entry when the ray misses the box; exit == entry when
   * it grazes an edge or corner.
   */
  static void ClipSlices(const double origin[3],
    const double step[3],
    const double boxMax[3],
    double lastSlice,
    double& entry,
    double& exit);

  /**
   * SYNTHESIZE of Fig. 5 at fine pixel (x, y) from a coarse level of coarseWidth x
   * coarseHeight values (row-major): the bilinear lookup of the coarse level at the fine pixel's
   * centre, (x / 2 - 1/4, y / 2 - 1/4) in coarse pixels, clamped to the edge (line 127).
   */
  static double Synthesize(const double* coarse, int coarseWidth, int coarseHeight, int x, int y);

protected:
  vtkAdaptiveSamplingRayCaster();
  ~vtkAdaptiveSamplingRayCaster() override;

  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  int MaximumLevel = 3;
  int Algorithm = ALGORITHM_FIG7;
  int OracleMode = ORACLE_ARRAY;
  char* OracleArrayName = nullptr;
  int TableSize = 256;
  double MaximumSamplesPerRay = 1e5;

  vtkIdType NumberOfSampleOperations = 0;
  vtkIdType NumberOfOracleOperations = 0;
  vtkIdType NumberOfSynthesisOperations = 0;
  vtkIdType NumberOfAccumulateOperations = 0;
  vtkIdType NumberOfBoundarySampleOperations = 0;
  vtkIdType FullRateSampleOperations = 0;
  vtkIdType NumberOfSlices = 0;
  double SliceSpacing = 0.0;

private:
  vtkAdaptiveSamplingRayCaster(const vtkAdaptiveSamplingRayCaster&) = delete;
  void operator=(const vtkAdaptiveSamplingRayCaster&) = delete;

  struct Tables;
  std::unique_ptr<Tables> SegmentTables; // one first-order table per segment length, kept
};

#endif
