// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
/**
 * @class   vtkAdaptiveSamplingVolumeMapper
 * @brief   adaptive sampling in three dimensions on the GPU: the slice pyramid of Fig. 7
 *
 * "Adaptive Sampling in Three Dimensions for Volume Rendering on GPUs" as a volume mapper with
 * its own multi-pass loop of OpenGL passes. It draws what vtkAdaptiveSamplingRayCaster (the
 * GL-free specification) computes for the same camera, viewport and settings, to float
 * rounding, with the same operation counts:
 *   - view-aligned slices Delta = 2 ParallelScale / viewport height apart (one level-0 pixel
 *     is one ray, line 68); slice 0 through the box corner nearest to the camera, the last
 *     slice the first multiple of 2^MaximumLevel at or behind the farthest corner (line 78);
 *   - a pyramid of MaximumLevel + 1 levels over the viewport (Sec. 3.2), padded on the right
 *     and at the top to a multiple of 2^MaximumLevel (the padding's rays continue the
 *     viewport's pixel grid and are cropped when the image is drawn);
 *   - per slice i, for l = l_slice down to 0 (Table 1), one pass over level l
 *     (vtkAdaptiveSamplingPyramid) that runs Fig. 7 for every pixel: synthesis from level
 *     l + 1 below l_slice (Fig. 5, the bilinear lookup at the fine pixel's centre, clamped to
 *     the edge), the sample and oracle decision on the stored d, and on level 0 the
 *     front-to-back compositing of the part inside the box of the segment since the ray's
 *     previous accumulated slice, from the ceil(L)-th of 2^MaximumLevel first-order tables
 *     with its optical depth scaled to its length L in slice spacings (Fig. 6; an end where
 *     the ray enters or leaves the box takes the scalar fetched there, so no piece inside
 *     the box is lost: vtkAdaptiveSamplingRayCaster's rule). Level l + 1 is read while
 *     level l is written (separate textures); each level's state (s, d), the level-0
 *     accumulation (C, alpha) and (s_prev, i_prev) are float32 textures written through
 *     multiple render targets and swapped after each pass;
 *   - samples outside the box of the volume's points are NaN (a segment with a NaN end adds
 *     nothing; the entry and exit pieces above replace such ends by the value on the face);
 *     there the oracle is the distance to the box; on a slice a pixel accumulates, a NaN
 *     synthesised from a coarse neighbour outside the box at a point inside it is sampled
 *     instead; positions, the entry and exit slice coordinates, the oracle and d are
 *     evaluated in double (GL_ARB_gpu_shader_fp64) so that the decisions, and hence the
 *     counts, are those of the CPU core.
 *
 * A piece of a volume with ghost points (OwnedExtent with WholeBounds, as the ParaView plugin
 * sets them on several ranks) is drawn on the whole volume's slices, and each pixel composites
 * only between the slices of 2^MaximumLevel that start and end its walk in the owned points:
 * every level samples there and the pyramid holds nothing older, so the pieces' images
 * composited front to back give the whole volume's (GetLastFrameJoinedPieces).
 *
 * Early ray termination (the paper's future work, line 250): a level-0 pixel whose opacity
 * reached 1 - 1/255 stops sampling and accumulating, and a coarser pixel skips its sample once
 * every level-0 pixel its synthesis footprint reaches has stopped (a "terminated" flag per
 * level, the AND over the 4 x 4 finer pixels whose synthesis reads it). What a skipped sample
 * would have changed only reaches stopped pixels, so the image differs from the one without
 * termination by at most the 1/255 of opacity the stopped rays leave out.
 *
 * Limitations: each is an error and nothing is drawn (never a silently wrong image), unless
 * said otherwise:
 *   - a perspective camera (slices of constant spacing need a parallel projection; shells are
 *     the paper's future work), reported once until a parallel frame is drawn;
 *   - blend modes other than composite, single-component point scalars only, no cropping or
 *     clipping planes;
 *   - no shading (the paper composites unshaded emission and absorption): a shaded property
 *     is drawn unshaded after a warning;
 *   - the volume's prop matrix moves the rays, but the oracle distances are taken in the
 *     volume's own coordinates;
 *   - the image is composited over what is drawn, without a depth test against opaque
 *     geometry;
 *   - the volume (in its own type, 64-bit types as floats) and the oracle (floats) are read
 *     from bricks packed into the pages of an atlas each (vtkOpenGLVolumeBricks in atlas
 *     mode: an axis may be longer than GL_MAX_3D_TEXTURE_SIZE, the volume larger than one
 *     texture, and the split does not change the image), at most 8 textures of
 *     MaximumTextureBytes each.
 *
 * @sa vtkAdaptiveSamplingRayCaster vtkAdaptiveSamplingOracle vtkFirstOrderPreIntegrationTable
 */
#ifndef vtkAdaptiveSamplingVolumeMapper_h
#define vtkAdaptiveSamplingVolumeMapper_h

#include "hovrRenderingOpenGLModule.h" // For export macro
#include "vtkExtensibleGPUVolumeRayCastMapper.h"

#include <memory> // For std::unique_ptr

class HOVRRENDERINGOPENGL_EXPORT vtkAdaptiveSamplingVolumeMapper
  : public vtkExtensibleGPUVolumeRayCastMapper
{
public:
  static vtkAdaptiveSamplingVolumeMapper* New();
  vtkTypeMacro(vtkAdaptiveSamplingVolumeMapper, vtkExtensibleGPUVolumeRayCastMapper);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /**
   * The top level l_max of the pyramid: sampling distances reach 2^MaximumLevel slice spacings
   * (line 78; the paper uses 3, line 236). 0 is full-rate first-order pre-integration on the
   * slice grid. Values outside [0, 8] are an error when rendering (nothing is drawn). Initial
   * value is 3.
   */
  vtkSetMacro(MaximumLevel, int);
  vtkGetMacro(MaximumLevel, int);
  ///@}

  enum OracleModes
  {
    ORACLE_ARRAY = 0,  ///< the point array OracleArrayName
    ORACLE_MINIMUM = 1 ///< d = 1 everywhere (the paper's "min." oracle, line 231)
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
   * The point array of oracle distances in world units, one component, finite (as
   * vtkAdaptiveSamplingOracle produces it). A missing or non-finite array is an error and
   * nothing is drawn. Initial value is "OracleDistance".
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
   * Whether rays stop once their opacity reaches 1 - 1/255 (see the class description).
   * Initial value is true.
   */
  vtkSetMacro(EarlyRayTermination, bool);
  vtkGetMacro(EarlyRayTermination, bool);
  vtkBooleanMacro(EarlyRayTermination, bool);
  ///@}

  ///@{
  /**
   * Whether each frame counts its operations: every pass then covers its whole level (as the
   * CPU core counts every pixel, even those whose rays miss the volume), keeps per-pixel
   * counters in an extra render target, and the frame ends with one read of every level's
   * counters. Without counting, each level's pass covers only the pixels that can affect the
   * image (the rays that meet the volume, widened by the reach of synthesis); the image is the
   * same. Initial value is false.
   */
  vtkSetMacro(CountOperations, bool);
  vtkGetMacro(CountOperations, bool);
  vtkBooleanMacro(CountOperations, bool);
  ///@}

  ///@{
  /**
   * Operation counts of the last frame drawn, as vtkAdaptiveSamplingRayCaster counts them
   * (one SAMPLE = one volume fetch at a point inside the box, the oracle fetched with it; one
   * SYNTHESIS per pixel synthesised; one ACCUMULATE per ACCUMULATECOLOR call on a slice after
   * the ray's first; one BOUNDARY fetch per scalar fetched where a level-0 ray enters or
   * leaves the box, not a slice sample), and the full-rate count (level-0 pixels of the viewport's
   * padded image times the slices whose point is inside the box). -1 when CountOperations is off or
   * the last frame drew nothing.
   */
  vtkGetMacro(LastFrameSampleOperations, vtkIdType);
  vtkGetMacro(LastFrameSynthesisOperations, vtkIdType);
  vtkGetMacro(LastFrameAccumulateOperations, vtkIdType);
  vtkGetMacro(LastFrameBoundarySampleOperations, vtkIdType);
  vtkGetMacro(LastFrameFullRateSampleOperations, vtkIdType);
  ///@}

  ///@{
  /**
   * The slice grid of the last frame drawn: the number of slices i_max + 1, their spacing
   * Delta in world units, and the number of level passes drawn (one per level per slice);
   * 0 when the last frame drew nothing.
   */
  vtkGetMacro(NumberOfSlices, vtkIdType);
  vtkGetMacro(SliceSpacing, double);
  vtkGetMacro(LastFramePasses, vtkIdType);
  ///@}

  /**
   * Whether the last frame drew its input as a piece whose walks join its neighbours' (see
   * OwnedExtent): false without OwnedExtent, and when the ghost points are fewer than the
   * frame's slice spacing needs (the owned points are then drawn as a volume of their own).
   */
  vtkGetMacro(LastFrameJoinedPieces, bool);

  /**
   * Bytes of GPU memory held by the oracle's bricks (the volume's are the base class's
   * GetBrickTextureMemorySize).
   */
  vtkIdType GetOracleTextureMemorySize();

  /**
   * Number of rebuilds of the 2^MaximumLevel segment tables so far (they are rebuilt when the
   * transfer functions, the unit distance, Delta, the scalar range, TableSize or MaximumLevel
   * change).
   */
  vtkGetMacro(TableBuildCount, int);

protected:
  vtkAdaptiveSamplingVolumeMapper();
  ~vtkAdaptiveSamplingVolumeMapper() override;

  void GPURender(vtkRenderer* ren, vtkVolume* vol) override;

  // A float 3D texture of `components` (1 or 4) channels read with texelFetch, through
  // CreateTexture3D(); false after an error naming `what`.
  bool UploadFloatTexture(vtkTextureObject* texture,
    vtkOpenGLRenderWindow* context,
    const int size[3],
    int components,
    float* data,
    const char* what);

  // The superclass's shader hook is not used: this mapper draws with its own passes.
  FramePlan PrepareExtension(vtkRenderer*, vtkVolume*) override { return DrawNothing; }
  bool ReplaceExtensionShaderValues(std::string&, std::string&, vtkVolume*) override
  {
    return true;
  }
  void SetExtensionShaderParameters(vtkShaderProgram*, vtkVolume*) override {}
  void ReleaseExtensionResources(vtkWindow* window) override;

  // The box a frame's rays end on (grid index of the input) and whether the input, a piece
  // with ghost points, joins its walks to its neighbours' (its owned points in grid index);
  // from OwnedExtent, WholeBounds, the slice spacing delta (world), l_max and the world
  // length of one index unit along each axis.
  struct PieceFrame
  {
    bool Joined = false;
    double WholeMin[3] = { 0, 0, 0 }, WholeMax[3] = { 0, 0, 0 };
    int OwnedLo[3] = { 0, 0, 0 }, OwnedHi[3] = { 0, 0, 0 };
  };
  PieceFrame FindPieceFrame(vtkImageData* input,
    double delta,
    int lmax,
    const double axisLength[3]);

  int MaximumLevel = 3;
  int OracleMode = ORACLE_ARRAY;
  char* OracleArrayName = nullptr;
  int TableSize = 256;
  bool EarlyRayTermination = true;
  bool CountOperations = false;

  vtkIdType LastFrameSampleOperations = -1;
  vtkIdType LastFrameSynthesisOperations = -1;
  vtkIdType LastFrameAccumulateOperations = -1;
  vtkIdType LastFrameBoundarySampleOperations = -1;
  vtkIdType LastFrameFullRateSampleOperations = -1;
  vtkIdType NumberOfSlices = 0;
  double SliceSpacing = 0.0;
  vtkIdType LastFramePasses = 0;
  bool LastFrameJoinedPieces = false;
  int TableBuildCount = 0;
  bool PerspectiveReported = false;

private:
  vtkAdaptiveSamplingVolumeMapper(const vtkAdaptiveSamplingVolumeMapper&) = delete;
  void operator=(const vtkAdaptiveSamplingVolumeMapper&) = delete;

  struct Internals;
  std::unique_ptr<Internals> Internal;
};

#endif
