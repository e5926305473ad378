// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
/**
 * @class   vtkObjectOrderRayCaster
 * @brief   object-order ray casting on the CPU (Mora, Jessel and Caubet)
 *
 * Composite volume rendering of the trilinear field for parallel projection, walking the
 * volume instead of the rays (Mora, Jessel and Caubet, "Interactive volume rendering of large
 * datasets... object-order ray-casting"):
 *   - a vtkMinMaxOctree over the cells, built once per volume, is traversed front to back
 *     (children ordered by the view direction, valid for any parallel view); a node is skipped
 *     when the current opacity transfer function is zero over its range (section 4.1), so
 *     editing the transfer function costs no rebuild;
 *   - hidden volume removal (section 4.2): a node whose screen rectangle is opaque in the
 *     vtkHierarchicalOcclusionMap is skipped; a pixel becomes opaque, and its ray stops
 *     (the paper's opacity test for every treated ray), when its alpha reaches
 *     OpacityThreshold;
 *   - the octree's leaves are nodes of LeafSize^3 cells (1: the paper's single cells); each
 *     leaf that is neither transparent nor hidden is rendered while its points are in cache
 *     (a leaf lies in one brick, below): every pixel ray through the box of its visible
 *     cells (section 3.1: the pixels of the box's projected rectangle, an exact slab test for
 *     each ray's segment in the leaf, clipped to the box) is sampled where a sample position
 *     falls in a cell whose corner range is not transparent, interpolating that cell's 8
 *     corners; transparent cells take no sample. Samples lie at t = phase + k SampleDistance
 *     along each ray, t the world distance from the camera plane, and belong to the leaf and
 *     the cell where t falls (section 3.2's depth indicator, kept as the exact t); with
 *     InterleavedSampling the phase is SampleDistance / 2 on every other pixel in a
 *     checkerboard (section 3.3), trading staircase artifacts for noise;
 *   - classification after interpolation, chosen by Classification: PREINTEGRATED (default)
 *     composites the segment between consecutive samples of a ray from the first-order
 *     pre-integration table (vtkFirstOrderPreIntegrationTable, Engel et al.; the ray's ends
 *     are point-sampled pieces); POINT_SAMPLED is the paper's: colour and extinction of each
 *     sample from a table over the data range (vtkPreIntegrationTable::SuggestTableSize),
 *     weighted alpha = 1 - exp(-tau length) for the part of the ray nearest to it;
 *   - the volume is copied once into float bricks of 8^3 cells that keep their far faces
 *     (9^3 points, 1.42 times a plain float copy; the paper's section 4.3.4 bricks for cache
 *     locality), so a leaf's points lie at fixed strides, and each brick's visible cells are
 *     found once per transfer function (not per frame);
 *   - the image is cut into tiles of TileSize pixels rendered in parallel with vtkSMPTools,
 *     each with its own occlusion map: the image does not depend on the number of threads.
 * Shading (when the volume property's Shade is on): a white headlight along the view, with
 * the property's ambient, diffuse, specular and specular power, two-sided (|n.l|), normals
 * from central differences of the data; a sample's colour is the transfer function's times
 * (ambient + diffuse |n.l|) plus specular |n.l|^power (ambient only where the gradient
 * vanishes). ShadingMode chooses where: POST_SHADING interpolates the 8 corner gradients at
 * every sample and shades it; PRE_SHADING is the paper's (section 4.3.2): every point's
 * normal is quantized once per volume to one of 8100 directions, a reflectance map of those
 * directions is computed per frame, and the samples interpolate the shading of their cell's
 * 8 vertices. Perspective cameras are an error (the paper's method needs every cell to project
 * to the same shape); vtkObjectOrderVolumeMapper falls back to VTK's own ray caster for them.
 *
 * Counters of the last update (the paper's Table 1): non-transparent cells rendered (sampled
 * by a ray whose pixel was not yet opaque: the cells whose data were used), octree nodes
 * visited (summed over tiles), samples. ComputeNonTransparentCells() counts the
 * non-transparent cells in view, for the occluded ratio: the cells that hidden volume
 * removal (node tests and the rays' opacity test) kept out of the work.
 */
#ifndef vtkObjectOrderRayCaster_h
#define vtkObjectOrderRayCaster_h

#include "hovrRenderingCoreModule.h" // For export macro
#include "vtkVolumeImageAlgorithm.h"

class vtkFirstOrderPreIntegrationTable;
class vtkMatrix4x4;
class vtkMinMaxOctree;

class HOVRRENDERINGCORE_EXPORT vtkObjectOrderRayCaster : public vtkVolumeImageAlgorithm
{
public:
  static vtkObjectOrderRayCaster* New();
  vtkTypeMacro(vtkObjectOrderRayCaster, vtkVolumeImageAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /**
   * Distance between samples along each ray, in world units; must be positive. Initial
   * value is 1.
   */
  vtkSetMacro(SampleDistance, double);
  vtkGetMacro(SampleDistance, double);
  ///@}

  ///@{
  /**
   * Shift the samples of every other pixel (checkerboard) by half a sample distance.
   * Initial value is on.
   */
  vtkSetMacro(InterleavedSampling, bool);
  vtkGetMacro(InterleavedSampling, bool);
  vtkBooleanMacro(InterleavedSampling, bool);
  ///@}

  ///@{
  /**
   * Skip octree nodes whose pixels are all opaque. The image is the same either way.
   * Initial value is on.
   */
  vtkSetMacro(HiddenVolumeRemoval, bool);
  vtkGetMacro(HiddenVolumeRemoval, bool);
  vtkBooleanMacro(HiddenVolumeRemoval, bool);
  ///@}

  ///@{
  /**
   * A pixel whose alpha reaches this value takes no more samples (early ray termination,
   * object-order). Initial value is 0.996: the rest of the ray can then add at most 0.4% of
   * full intensity, about one 8-bit display level, as where VTK's GPU ray caster stops
   * (1 - 1/255; vtkFixedPointVolumeRayCastMapper stops at about 0.992): nearly opaque rays
   * skip the samples that could change an 8-bit image by one level at most. Raise it towards
   * 1 where float images must follow rays further.
   */
  vtkSetClampMacro(OpacityThreshold, double, 1e-3, 1.0);
  vtkGetMacro(OpacityThreshold, double);
  ///@}

  ///@{
  /**
   * The most samples a ray may take across the volume's diagonal at the sample distance; a
   * finer sample distance is an error (empty image) instead of a frame of hours. Frames
   * expected to take more than about 2^28 samples are walked in parts, with a progress event
   * after each; AbortExecute stops a frame at the next tile, leaving the tiles not walked
   * transparent. Initial value is 100000.
   */
  vtkSetClampMacro(MaximumSamplesPerRay, double, 1.0, 1e9);
  vtkGetMacro(MaximumSamplesPerRay, double);
  ///@}

  enum Classifications
  {
    POINT_SAMPLED = 0, ///< each sample's colour and opacity (the paper's)
    PREINTEGRATED = 1  ///< each segment between samples from a pre-integration table
  };

  ///@{
  /**
   * How samples are classified (see the class description). Pre-integration costs a 2D table
   * (256^2 to 512^2 entries, 1 to 4 MiB) rebuilt when the transfer function or the step
   * changes, and is far more accurate for narrow transfer-function features. Initial value
   * is PREINTEGRATED.
   */
  vtkSetClampMacro(Classification, int, POINT_SAMPLED, PREINTEGRATED);
  vtkGetMacro(Classification, int);
  ///@}

  enum ShadingModes
  {
    POST_SHADING = 0, ///< gradient interpolated and shaded at every sample
    PRE_SHADING = 1   ///< quantized normals, vertices shaded, shading interpolated
  };

  ///@{
  /**
   * How shading is computed when the volume property shades (see the class description).
   * Pre-shading keeps 2 bytes per point of quantized normals. Initial value is POST_SHADING.
   */
  vtkSetClampMacro(ShadingMode, int, POST_SHADING, PRE_SHADING);
  vtkGetMacro(ShadingMode, int);
  void SetShadingModeToPostShading() { this->SetShadingMode(POST_SHADING); }
  void SetShadingModeToPreShading() { this->SetShadingMode(PRE_SHADING); }
  ///@}

  ///@{
  /**
   * Placement of the volume in the world (a vtkVolume's matrix, from data to world
   * coordinates). Initial value is nullptr: the identity.
   */
  virtual void SetVolumeMatrix(vtkMatrix4x4*);
  vtkGetObjectMacro(VolumeMatrix, vtkMatrix4x4);
  ///@}

  ///@{
  /**
   * Edge of the image tiles rendered in parallel, in pixels. The image does not depend on
   * it. Initial value is 32.
   */
  vtkSetClampMacro(TileSize, int, 4, 4096);
  vtkGetMacro(TileSize, int);
  ///@}

  ///@{
  /**
   * Cells per edge of the octree's leaves, the nodes rendered as a whole: 1 (the paper's
   * per-cell rendering), 2, 4 or 8 (rounded down to a power of two). Larger leaves pay less
   * traversal, fewer screen tests and fewer ray segments per sample; smaller ones skip
   * transparent and hidden space more finely, but each leaf's rays are clipped to the box of
   * its visible cells, which recovers most of that, so the largest leaves usually cost the
   * least. The image depends on it only by float rounding (leaf-local
   * coordinates: a sample within rounding of a cell face may fall in the cell on its other
   * side). Initial value is 8.
   */
  vtkSetClampMacro(LeafSize, int, 1, 8);
  vtkGetMacro(LeafSize, int);
  ///@}

  ///@{
  /**
   * A scalar range the classification spans besides the range of the volume's scalars: the
   * whole volume's, when the input is one piece of it (a rank's under MPI), so that every
   * piece is classified alike. An empty range (low > high) or a non-finite one spans the
   * volume's scalars alone. Initial value is (1, 0).
   */
  vtkSetVector2Macro(ScalarRange, double);
  vtkGetVector2Macro(ScalarRange, double);
  ///@}

  ///@{
  /**
   * Bounds (dataset coordinates) of the whole volume when the input is one piece of it (a
   * rank's under MPI, as the ParaView plugin sets them); used with OwnedExtent. Empty bounds
   * (a minimum above its maximum) are the input's own. Initial value is (1, 0, 1, 0, 1, 0).
   */
  vtkSetVector6Macro(WholeBounds, double);
  vtkGetVector6Macro(WholeBounds, double);
  ///@}

  ///@{
  /**
   * The points of the input (its structured extent) that the caster draws as its own, when
   * the input is one piece of the volume with ghost points around it: the piece without them.
   * Each ray is then walked through the whole volume's box (WholeBounds), its samples taken
   * wherever the input has points, and a sample's step composited only when the sample lies in
   * the owned points (half-open: a sample on a face two pieces share goes to the piece behind
   * it), so that the pieces composited front to back give the whole volume's image; the ghost
   * points must reach two sample distances and two points past the owned ones. An empty extent
   * (a minimum above its maximum) owns the whole input. Initial value is (0, -1, 0, -1, 0, -1).
   */
  vtkSetVector6Macro(OwnedExtent, int);
  vtkGetVector6Macro(OwnedExtent, int);
  ///@}

  enum InstructionSets
  {
    INSTRUCTIONS_AUTOMATIC = 0, ///< AVX2 with FMA where the processor has them, else SSE2
    INSTRUCTIONS_SSE2 = 1,      ///< the loop every x86-64 processor runs
    INSTRUCTIONS_AVX2 = 2       ///< AVX2 with FMA (GCC and Clang builds on x86-64)
  };

  ///@{
  /**
   * Which compiled copy of the tiles' sample loop runs: INSTRUCTIONS_AUTOMATIC takes the AVX2
   * one where the processor has AVX2 and FMA and the build has that copy (GCC or Clang on
   * x86-64), the SSE2 one otherwise; INSTRUCTIONS_AVX2 falls back to SSE2, with a warning,
   * where it cannot run. Fused multiply-adds round differently, so the two images differ by
   * float rounding (on a few pixels where a sample lies on a cell face, by more); each is the
   * same for any number of threads. The AVX2 copy also samples the unshaded rays of a leaf
   * eight at a time, one vector lane each (positions, cells, corners and scalars as vectors;
   * the same image as its one-ray loop), so that eight rays share each instruction.
   * Initial value is INSTRUCTIONS_AUTOMATIC.
   */
  vtkSetClampMacro(InstructionSet, int, INSTRUCTIONS_AUTOMATIC, INSTRUCTIONS_AVX2);
  vtkGetMacro(InstructionSet, int);
  ///@}

  /**
   * The copy of the sample loop the last update ran: INSTRUCTIONS_SSE2 or
   * INSTRUCTIONS_AVX2 (INSTRUCTIONS_AUTOMATIC before the first update).
   */
  vtkGetMacro(LastInstructionSet, int);

  /**
   * The pixels of the last update's image that rays through the volume's box can reach,
   * [rect[0], rect[1]] x [rect[2], rect[3]] (rect[1] < rect[0] when none, or before a
   * successful update): the image is transparent (zero) outside them, so a mapper need only
   * draw these.
   */
  void GetLastVolumePixels(int rect[4]) const;

  ///@{
  /**
   * Counters of the last update: non-transparent cells rendered (sampled by a ray not yet
   * opaque; each cell once, however many tiles and rays sample it), octree nodes visited
   * (summed over tiles, leaves included), samples taken.
   */
  vtkGetMacro(NumberOfNonTransparentCells, vtkIdType);
  vtkGetMacro(NumberOfNodesVisited, vtkIdType);
  vtkGetMacro(NumberOfSamples, vtkIdType);
  ///@}

  /**
   * Non-transparent cells of the last update's volume and transfer function whose screen
   * rectangle meets the image: the denominator of the occluded-cell ratio (the cells that
   * hidden volume removal kept out of the work are this minus the cells rendered). Walks the
   * octree down to the cells without sampling; -1 before a successful update.
   */
  vtkIdType ComputeNonTransparentCells();

  /**
   * The octree of the current volume (built on the first update).
   */
  vtkMinMaxOctree* GetOctree() { return this->Octree; }

  /**
   * Bytes of the bricked float copy of the volume (bricks of 8^3 cells with their far faces:
   * 1.42 times a plain float copy), the quantized normals (pre-shading), the bricks' cell bits
   * (visible, sampled) and the octree.
   */
  vtkIdType GetMemorySize() const;

  /**
   * Whether the last update ran out of memory: the float bricks and octree of the volume (about
   * 7 bytes per point) or, with pre-shading, the quantized normals (3 more) could not be
   * allocated. An error says how much the bricks take, the image is empty (transparent), and
   * the copies are freed; as after any error, the next update after a change (Modified(),
   * new scalars) tries again. vtkObjectOrderVolumeMapper then draws with
   * vtkFixedPointVolumeRayCastMapper.
   */
  vtkGetMacro(LastUpdateOutOfMemory, bool);

  /**
   * Entries of the classification table of the last update.
   */
  vtkGetMacro(TableSize, int);

  vtkMTimeType GetMTime() override;

protected:
  vtkObjectOrderRayCaster();
  ~vtkObjectOrderRayCaster() override;

  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  // An allocation for `what` failed: the copies freed, the error reported.
  void OutOfMemory(const int dims[3], const char* what);

  double SampleDistance = 1.0;
  bool InterleavedSampling = true;
  bool HiddenVolumeRemoval = true;
  double OpacityThreshold = 0.996;
  double MaximumSamplesPerRay = 1e5;
  int TileSize = 32;
  int LeafSize = 8;
  double ScalarRange[2] = { 1.0, 0.0 };
  double WholeBounds[6] = { 1.0, 0.0, 1.0, 0.0, 1.0, 0.0 };
  int OwnedExtent[6] = { 0, -1, 0, -1, 0, -1 };
  int InstructionSet = INSTRUCTIONS_AUTOMATIC;
  int LastInstructionSet = INSTRUCTIONS_AUTOMATIC;
  int ShadingMode = POST_SHADING;
  int Classification = PREINTEGRATED;
  vtkFirstOrderPreIntegrationTable* SegmentTable;
  vtkIdType NumberOfNonTransparentCells = 0;
  vtkIdType NumberOfNodesVisited = 0;
  vtkIdType NumberOfSamples = 0;
  int TableSize = 0;
  bool LastUpdateOutOfMemory = false;
  vtkMinMaxOctree* Octree;
  vtkMatrix4x4* VolumeMatrix = nullptr;

private:
  vtkObjectOrderRayCaster(const vtkObjectOrderRayCaster&) = delete;
  void operator=(const vtkObjectOrderRayCaster&) = delete;

  class vtkInternals;
  vtkInternals* Internals;
};

#endif
