// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
/**
 * @class   vtkAdaptiveRayVolumeMapper
 * @brief   GPU ray casting whose sampling distance along each ray follows an oracle
 *
 * Skipping along rays of "Adaptive Sampling in Three Dimensions for Volume Rendering on GPUs"
 * (Sec. 3.1), composited with first-order pre-integration (Sec. 3.3, Fig. 6), inside VTK's
 * GPU ray caster; no pyramid over the image plane (Sec. 3.2). It is the cheap companion of the
 * full method and works for parallel and perspective cameras:
 *   - samples lie on a global grid of slices i = 0, 1, 2, ... spaced Delta = SampleDistance
 *     (the volume's data coordinates, where VTK measures its step), shared by all rays. With a
 *     parallel camera the slices are planes perpendicular to the view direction, slice 0
 *     through the corner of the volume's box nearest to the camera; with a perspective camera
 *     they are spheres around the eye (the shells the paper names as future work, line 250),
 *     slice 0 through the point of the box nearest to the eye (radius 0 when the eye is
 *     inside). The box is the input's, widened to WholeBounds when the input is a piece of a
 *     larger volume, so that every piece samples the whole volume's slices;
 *   - at each sample the oracle gives a preferred distance d = clamp(oracle / Delta, 1,
 *     2^MaximumLevel) in slices: the point array OracleArrayName (world units, as
 *     vtkAdaptiveSamplingOracle produces it), uploaded as float texels and interpolated
 *     trilinearly; with OracleMode MINIMUM, d = 1 everywhere (every slice is sampled: the
 *     paper's "min." oracle, line 231);
 *   - the next sample is slice j = (floor(i / 2^q) + 1) 2^q, q = min(floor(log2 d),
 *     MaximumLevel) (vtkAdaptiveSamplingRayCaster::NextSampleSlice, the closed form of the skip
 *     condition of line 74): one iteration of VTK's loop per sample, skipped slices cost
 *     nothing. With MaximumLevel 0 every slice is sampled and the oracle is not read;
 *   - the segment between consecutive samples spans k = j - i slices (1 <= k <=
 *     2^MaximumLevel) and is composited from the k-th of 2^MaximumLevel first-order tables
 *     (vtkFirstOrderPreIntegrationTable for segment length k Delta, Fig. 6's C_lut and
 *     alpha_lut), tiles of one 2D texture (bilinear lookups). The partial segments from the
 *     ray's entry to its first slice and from its last sample to its exit or termination point
 *     take the table of the next whole number of slices and rescale its optical depth to their
 *     length (exact for a constant scalar), as vtkPreIntegrationVolumeMapper does.
 * The scalar field sampled along the rays is chosen by Reconstruction: trilinear
 * interpolation (one texture fetch a sample), or the cubic B-spline approximation of the data
 * (Sigg and Hadwiger, "Fast Third-Order Texture Filtering", GPU Gems 2, chapter 20: eight
 * trilinear fetches a sample), an expensive sampler with which each skipped sample saves
 * more. The B-spline's values are convex combinations of the data, so they stay within the
 * data range and the tables are those of the trilinear field; it does not interpolate the
 * data (it smooths them) but reproduces linear functions exactly. At the borders the fetches
 * clamp to the edge: the data continue as the values of the outermost points, so
 * within one voxel of a face the B-spline blends in those copies (and a linear function is
 * reproduced only farther inside). The oracle is always read with one trilinear fetch.
 *
 * The volume and the oracle are read from bricks packed into the pages of an atlas each
 * (vtkOpenGLVolumeBricks in atlas mode, hovrVolumeAtlas.glsl; up to 8 textures of at most
 * MaximumTextureBytes): a sample reads the brick that owns its cell, so the image does not
 * depend on the split, an axis may be longer than GL_MAX_3D_TEXTURE_SIZE and the volume larger
 * than one texture; VTK draws the volume's box from a 2 x 2 x 2 proxy. 8-bit scalars go up as
 * 16-bit texels of the same values, since some OpenGL implementations interpolate 8-bit
 * textures at 8-bit precision. No copy of the volume or the oracle is made on the CPU.
 *
 * Early ray termination is VTK's (opacity above 1 - 1/255). With OracleMode MINIMUM the image
 * is first-order pre-integration at step Delta on the slice grid: the same as
 * vtkPreIntegrationVolumeMapper's where VTK's samples fall on the slices (a parallel camera
 * whose rays enter through a face perpendicular to the view).
 *
 * The tables are built on the CPU (vtkSMPTools) and uploaded only when the transfer
 * functions, the opacity unit distance, Delta, the scalar range, the table size or
 * MaximumLevel change; GetTableBuildCount() counts those uploads. MINIMUM needs only the
 * table of one slice.
 *
 * With CountSamples on, an atomic counter (GL_ARB_shader_atomic_counters) counts the slice
 * samples of each frame (a volume sample each, and an oracle fetch unless d = 1 everywhere; the
 * entry and end points of each ray are not counted) and GetLastFrameSampleCount() reports it.
 *
 * Limitations and fallbacks:
 *   - composite blending of one-component scalars with a 1D transfer function, no gradient
 *     opacity, no shading, no cropping and no clipping planes: anything else is drawn by VTK's
 *     stock path after a warning;
 *   - point scalars only (cell scalars go to VTK's stock path after a warning);
 *   - the volume (and the oracle, in the same bricks) must fit 8 textures of
 *     MaximumTextureBytes: otherwise an error is reported and nothing is drawn;
 *   - the oracle must be a point array of one finite value per point (any numeric type);
 *     otherwise (a missing array, another number of
 *     components or values, NaN or infinite values, too large) a warning says so and the
 *     frame is drawn at the full rate (d = 1, as MINIMUM);
 *   - the sample distance is fixed (automatic adjustment is off) and must be positive and
 *     finite, and take at most MaximumSamplesPerRay samples along the volume's diagonal:
 *     otherwise an error is reported and nothing is drawn; so is a volume with fewer than
 *     2 points along an axis;
 *   - jittering has no effect: samples lie on the slices. Opaque geometry in the depth
 *     buffer ends the rays as in VTK.
 *
 * @sa vtkPreIntegrationVolumeMapper vtkAdaptiveSamplingRayCaster vtkAdaptiveSamplingOracle
 */
#ifndef vtkAdaptiveRayVolumeMapper_h
#define vtkAdaptiveRayVolumeMapper_h

#include "hovrRenderingOpenGLModule.h" // For export macro
#include "vtkExtensibleGPUVolumeRayCastMapper.h"

#include <memory> // For std::unique_ptr

class HOVRRENDERINGOPENGL_EXPORT vtkAdaptiveRayVolumeMapper
  : public vtkExtensibleGPUVolumeRayCastMapper
{
public:
  static vtkAdaptiveRayVolumeMapper* New();
  vtkTypeMacro(vtkAdaptiveRayVolumeMapper, vtkExtensibleGPUVolumeRayCastMapper);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  enum OracleModes
  {
    ORACLE_ARRAY = 0,  ///< the point array OracleArrayName
    ORACLE_MINIMUM = 1 ///< d = 1 everywhere (the paper's "min." oracle)
  };

  enum Reconstructions
  {
    RECONSTRUCTION_TRILINEAR = 0,       ///< VTK's trilinear interpolation, one fetch a sample
    RECONSTRUCTION_TRICUBIC_BSPLINE = 1 ///< the cubic B-spline approximation, eight fetches
  };

  ///@{
  /**
   * The reconstruction of the scalar field from the data points at each sample (the volume's
   * samples only: the oracle is trilinear). An unknown value gives a warning and
   * RECONSTRUCTION_TRILINEAR. Initial value is RECONSTRUCTION_TRILINEAR.
   */
  virtual void SetReconstruction(int reconstruction);
  vtkGetMacro(Reconstruction, int);
  void SetReconstructionToTrilinear() { this->SetReconstruction(RECONSTRUCTION_TRILINEAR); }
  void SetReconstructionToTricubicBSpline()
  {
    this->SetReconstruction(RECONSTRUCTION_TRICUBIC_BSPLINE);
  }
  ///@}

  ///@{
  /**
   * The largest level l_max: sampling distances reach 2^MaximumLevel slices (line 78; the
   * paper uses 3, line 236). 0 samples every slice. Values outside [0, 8] are clamped with a
   * warning. Initial value is 3.
   */
  virtual void SetMaximumLevel(int level);
  vtkGetMacro(MaximumLevel, int);
  ///@}

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
   * The point array of oracle distances in world units, one component. Initial value is
   * "OracleDistance".
   */
  vtkSetStringMacro(OracleArrayName);
  vtkGetStringMacro(OracleArrayName);
  ///@}

  ///@{
  /**
   * Entries per scalar axis of each table. 0 chooses 256 (one entry per value of 8-bit data;
   * the build time grows as the cube of the size, times the number of tables). Tables whose
   * layers would exceed 64 MiB in 32-bit floats are stored in 16-bit floats, and their size
   * is reduced with a warning beyond 256 MiB or the OpenGL texture limit. Initial value is 0.
   */
  vtkSetClampMacro(TableSize, int, 0, 4096);
  vtkGetMacro(TableSize, int);
  ///@}

  ///@{
  /**
   * The most samples a ray may take across the volume's diagonal at the sample distance; a
   * finer sample distance is an error and nothing is drawn (float ray positions stop
   * resolving the step). Initial value is 100000.
   */
  vtkSetClampMacro(MaximumSamplesPerRay, double, 1.0, 1e9);
  vtkGetMacro(MaximumSamplesPerRay, double);
  ///@}

  ///@{
  /**
   * Count the slice samples of each frame on the GPU (an atomic counter read back after the
   * draw, which waits for the frame to finish). Initial value is false.
   */
  virtual void SetCountSamples(bool count);
  vtkGetMacro(CountSamples, bool);
  vtkBooleanMacro(CountSamples, bool);
  ///@}

  /**
   * Slice samples of the last frame drawn with the extension; -1 when CountSamples is off,
   * when the OpenGL lacks atomic counters, or when the last frame was drawn otherwise.
   */
  vtkGetMacro(LastFrameSampleCount, vtkIdType);

  /**
   * Number of times the table texture was made (a table was rebuilt, or the number of layers
   * or their storage changed), and the wall time in seconds of the last time (the builds of
   * the tables that changed, and the upload).
   */
  vtkGetMacro(TableBuildCount, int);
  vtkGetMacro(LastTableBuildTime, double);

  /**
   * Entries per scalar axis and number of layers of the current tables (after a frame).
   */
  vtkGetMacro(EffectiveTableSize, int);
  vtkGetMacro(NumberOfTables, int);

  /**
   * Bytes of GPU memory held by the table and oracle textures.
   */
  vtkGetMacro(TableTextureMemorySize, vtkIdType);
  vtkGetMacro(OracleTextureMemorySize, vtkIdType);

  /**
   * Whether the last frame used the oracle array (false: d = 1, by OracleMode MINIMUM, with
   * MaximumLevel 0, which samples every slice without reading the oracle, or after a warning
   * about the array).
   */
  vtkGetMacro(LastFrameUsedOracle, bool);

protected:
  vtkAdaptiveRayVolumeMapper();
  ~vtkAdaptiveRayVolumeMapper() override;

  FramePlan PrepareExtension(vtkRenderer* ren, vtkVolume* vol) override;
  void ActivateExtensionTextures() override;
  void DeactivateExtensionTextures() override;
  bool ReplaceExtensionShaderValues(std::string& vertexShader,
    std::string& fragmentShader,
    vtkVolume* vol) override;
  void SetExtensionShaderParameters(vtkShaderProgram* program, vtkVolume* vol) override;
  void ReleaseExtensionResources(vtkWindow* window) override;

  int MaximumLevel = 3;
  int OracleMode = ORACLE_ARRAY;
  int Reconstruction = RECONSTRUCTION_TRILINEAR;
  char* OracleArrayName = nullptr;
  int TableSize = 0;
  double MaximumSamplesPerRay = 1e5;
  bool CountSamples = false;
  vtkIdType LastFrameSampleCount = -1;
  int TableBuildCount = 0;
  double LastTableBuildTime = 0.0;
  int EffectiveTableSize = 0;
  int NumberOfTables = 0;
  vtkIdType TableTextureMemorySize = 0;
  vtkIdType OracleTextureMemorySize = 0;
  bool LastFrameUsedOracle = false;

private:
  vtkAdaptiveRayVolumeMapper(const vtkAdaptiveRayVolumeMapper&) = delete;
  void operator=(const vtkAdaptiveRayVolumeMapper&) = delete;

  struct Internals;
  std::unique_ptr<Internals> Internal;
};

#endif
