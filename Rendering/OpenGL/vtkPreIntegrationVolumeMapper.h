// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
/**
 * @class   vtkPreIntegrationVolumeMapper
 * @brief   GPU ray casting with pre-integrated classification
 *
 * A vtkOpenGLGPUVolumeRayCastMapper whose compositing integrates the transfer functions
 * between samples instead of point-sampling them, so that narrow transfer-function features
 * are not missed between samples:
 *   - Integration = STOCK: VTK's own compositing, unchanged (for comparison);
 *   - Integration = FIRST_ORDER: first-order pre-integration (Engel et al. 2001), a 2D table
 *     over (front, back) scalar for the sample distance (vtkFirstOrderPreIntegrationTable);
 *   - Integration = SECOND_ORDER: second-order pre-integration (El Hajjar et al. 2008), slabs
 *     of two sample distances whose three samples fix a quadratic profile, a 3D table over
 *     (front, middle, back) scalar (vtkSecondOrderPreIntegrationTable): one volume fetch per
 *     sample, one table fetch per slab.
 *
 * Only the table of the active order is built, on the CPU, and uploaded only when the
 * transfer functions, the opacity unit distance, the sample distance or the scalar range
 * change. Its size is chosen from the data (one entry per integer value for 8-bit data) and
 * the transfer function (enough entries across its narrowest feature) unless TableSize is
 * set, and its storage precision from its dimension unless TablePrecision is set.
 *
 * Cropping, clipping planes and jittering keep working: segments honour the cropping skip
 * flag and start and end where VTK's ray does. Composite blending of one-component scalars
 * (RGB or grey colour) without shading, enabled gradient opacity or 2D transfer functions is
 * pre-integrated; anything else is drawn by VTK's stock path after a warning. The sample
 * distance is fixed (automatic adjustment is off) and must be positive: otherwise an error is
 * reported and nothing is drawn.
 */
#ifndef vtkPreIntegrationVolumeMapper_h
#define vtkPreIntegrationVolumeMapper_h

#include "hovrRenderingOpenGLModule.h" // For export macro
#include "vtkExtensibleGPUVolumeRayCastMapper.h"

class vtkFirstOrderPreIntegrationTable;
class vtkOpenGLPreIntegrationTableBuilder;
class vtkOpenGLRenderWindow;
class vtkPreIntegrationTable;
class vtkSecondOrderPreIntegrationTable;
class vtkTextureObject;

class HOVRRENDERINGOPENGL_EXPORT vtkPreIntegrationVolumeMapper
  : public vtkExtensibleGPUVolumeRayCastMapper
{
public:
  static vtkPreIntegrationVolumeMapper* New();
  vtkTypeMacro(vtkPreIntegrationVolumeMapper, vtkExtensibleGPUVolumeRayCastMapper);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  enum IntegrationModes
  {
    STOCK = 0,
    FIRST_ORDER = 1,
    SECOND_ORDER = 2
  };

  enum TableBuilders
  {
    BUILD_AUTOMATIC = 0, ///< on the GPU, unless OpenGL is a software renderer (llvmpipe...)
    BUILD_ON_CPU = 1,    ///< vtkSMPTools, then uploaded
    BUILD_ON_GPU = 2 ///< a render pass writes the 3D texture (vtkOpenGLPreIntegrationTableBuilder)
  };

  enum TablePrecisions
  {
    PRECISION_AUTOMATIC = 0, ///< 32-bit floats for the 2D table, 16-bit for the 3D table
    PRECISION_UNORM8 = 1,    ///< 8 bits per channel, as in the second-order paper
    PRECISION_FLOAT16 = 2,
    PRECISION_FLOAT32 = 3
  };

  enum VolumePrecisions
  {
    VOLUME_PRECISION_AUTOMATIC = 0, ///< 8-bit integers in 16 bits, other types as VTK uploads them
    VOLUME_PRECISION_NATIVE = 1,    ///< as VTK uploads them: 8-bit textures for 8-bit data
    VOLUME_PRECISION_16BIT = 2,     ///< 8-bit integers copied to 16-bit ones (automatic)
    VOLUME_PRECISION_FLOAT32 = 3    ///< 8- and 16-bit integers as 32-bit floats
  };

  ///@{
  /**
   * How samples are composited. Initial value is FIRST_ORDER.
   */
  virtual void SetIntegration(int mode);
  vtkGetMacro(Integration, int);
  void SetIntegrationToStock() { this->SetIntegration(STOCK); }
  void SetIntegrationToFirstOrder() { this->SetIntegration(FIRST_ORDER); }
  void SetIntegrationToSecondOrder() { this->SetIntegration(SECOND_ORDER); }
  ///@}

  ///@{
  /**
   * Entries of the table along each scalar axis; 0 chooses from the data and the transfer
   * function (vtkPreIntegrationTable::SuggestTableSize): one entry per integer value of 8-bit
   * data; otherwise, for the 2D table, 8 entries across the narrowest transfer-function
   * feature, between 256 and 1024. The 3D table interpolates integrated slabs, which vary
   * more slowly than the transfer function, the more so the longer the slab: 1.5 / step
   * entries per narrowest opacity feature (step in voxels), between 48 and 256. Measured on
   * neghip, fuel, bucky and Marschner-Lobb with narrow spikes, this is within a few percent
   * of the best size for steps of 0.25 to 2 voxels; a 256^3 table at a 2-voxel step is 3-10%
   * less accurate and slower than a 64^3 one. Values above the OpenGL texture limits, or above
   * 512 for the 3D table (1 GiB in half floats), are clamped with a warning. Initial value
   * is 0.
   */
  vtkSetClampMacro(TableSize, int, 0, 65536);
  vtkGetMacro(TableSize, int);
  ///@}

  ///@{
  /**
   * Storage of the table on the GPU. Initial value is PRECISION_AUTOMATIC.
   */
  vtkSetClampMacro(TablePrecision, int, PRECISION_AUTOMATIC, PRECISION_FLOAT32);
  vtkGetMacro(TablePrecision, int);
  ///@}

  ///@{
  /**
   * Where the second-order table is built (the first-order table always on the CPU). A
   * software OpenGL renderer runs the GPU pass on the CPU, slower than the CPU builder.
   * Initial value is BUILD_AUTOMATIC.
   */
  vtkSetClampMacro(TableBuilder, int, BUILD_AUTOMATIC, BUILD_ON_GPU);
  vtkGetMacro(TableBuilder, int);
  ///@}

  /**
   * Whether the last second-order table was built on the GPU.
   */
  vtkGetMacro(LastTableBuiltOnGPU, bool);

  /**
   * Wall time in seconds of the last table build, on the CPU or the GPU (including the
   * upload or the render passes).
   */
  vtkGetMacro(LastTableBuildTime, double);

  ///@{
  /**
   * Skip the table fetch of segments (first order) or slabs (second order) whose scalar stays
   * in one zero-opacity run of the transfer function; the result is the same. The test costs
   * a texel fetch per sample: it pays where table fetches are expensive (large tables on a
   * GPU); with Mesa llvmpipe it was measured 5-20% slower than fetching. Initial value is
   * false.
   */
  virtual void SetSkipEmptySegments(bool skip);
  vtkGetMacro(SkipEmptySegments, bool);
  vtkBooleanMacro(SkipEmptySegments, bool);
  ///@}

  ///@{
  /**
   * Integration steps per entry of the second-order table (the paper: 64 are enough, 256
   * satisfy Nyquist). Initial value is 64.
   */
  virtual void SetIterations(int iterations);
  virtual int GetIterations();
  ///@}

  ///@{
  /**
   * Box-average the transfer function over one entry spacing of the second-order table before
   * integrating (vtkSecondOrderPreIntegrationTable::Prefilter), so that opacity features
   * narrower than a spacing keep their integral wherever they fall between entries. Data
   * exactly at the ends of the scalar range keeps the exact transfer function. Initial value
   * is true.
   */
  virtual void SetTablePrefilter(bool prefilter);
  virtual bool GetTablePrefilter();
  vtkBooleanMacro(TablePrefilter, bool);
  ///@}

  ///@{
  /**
   * Early ray termination: a ray stops once its opacity exceeds this value. The missed light
   * is at most 1 - threshold. Initial value is VTK's, 1 - 1/255.
   */
  vtkSetClampMacro(OpacityThreshold, double, 0.5, 1.0);
  vtkGetMacro(OpacityThreshold, double);
  ///@}

  ///@{
  /**
   * How the volume is stored on the GPU while it is pre-integrated. Texture units may
   * interpolate an 8-bit texture at 8-bit precision (Mesa's llvmpipe does), which rounds every
   * sample to about a whole data value and puts a floor under the error of every step and
   * table size. VOLUME_PRECISION_16BIT (the automatic choice) uploads a 16-bit integer copy of
   * 8-bit data instead, the same values in twice the memory, whose texels llvmpipe converts to
   * float before interpolating; VOLUME_PRECISION_FLOAT32 a float copy of 8- and 16-bit data
   * (four bytes per value), interpolated in float wherever float textures are filtered in
   * float. VTK uploads 16-bit data in 16-bit textures already, 32-bit integers and doubles as
   * floats. The copy is made on the CPU once per scalar array and holds as many bytes as the
   * texture; as it holds the data's values, VTK's scalar range and lookup tables are unchanged.
   * Frames drawn by VTK's stock path use the data as VTK uploads it. Initial value is
   * VOLUME_PRECISION_AUTOMATIC.
   */
  vtkSetClampMacro(VolumePrecision, int, VOLUME_PRECISION_AUTOMATIC, VOLUME_PRECISION_FLOAT32);
  vtkGetMacro(VolumePrecision, int);
  ///@}

  /**
   * Bytes of the volume texture of the last pre-integrated frame as uploaded (the data's
   * points or cells times 1, 2 or 4 bytes, VolumePrecision resolved), and of the CPU copy
   * made for it (0 when VTK uploads the input's own array).
   */
  vtkGetMacro(VolumeTextureMemorySize, vtkIdType);
  vtkGetMacro(VolumeCopyMemorySize, vtkIdType);

  ///@{
  /**
   * The most samples a ray may take across the volume's diagonal at the sample distance. A
   * sample distance finer than that is an error and nothing is drawn: the shader advances
   * the ray in float texture coordinates, whose rounding (about 6e-8 of the volume) must
   * stay far below one step, and the frame would take minutes. Initial value is 100000.
   */
  vtkSetClampMacro(MaximumSamplesPerRay, double, 1.0, 1e9);
  vtkGetMacro(MaximumSamplesPerRay, double);
  ///@}

  ///@{
  /**
   * The tables (for statistics: GetBuildCount, GetLastBuildTime, GetMemorySize); only the one
   * of the active order is built.
   */
  vtkFirstOrderPreIntegrationTable* GetFirstOrderTable() { return this->FirstOrderTable; }
  vtkSecondOrderPreIntegrationTable* GetSecondOrderTable() { return this->SecondOrderTable; }
  vtkPreIntegrationTable* GetActiveTable();
  ///@}

  /**
   * Bytes of GPU memory held by the current table textures.
   */
  vtkGetMacro(TableTextureMemorySize, vtkIdType);

  /**
   * The precision the table is stored with (PRECISION_AUTOMATIC resolved).
   */
  int GetEffectiveTablePrecision();

protected:
  vtkPreIntegrationVolumeMapper();
  ~vtkPreIntegrationVolumeMapper() override;

  FramePlan PrepareExtension(vtkRenderer* ren, vtkVolume* vol) override;
  void ActivateExtensionTextures() override;
  void DeactivateExtensionTextures() override;
  bool ReplaceExtensionShaderValues(std::string& vertexShader,
    std::string& fragmentShader,
    vtkVolume* vol) override;
  void SetExtensionShaderParameters(vtkShaderProgram* program, vtkVolume* vol) override;
  void ReleaseExtensionResources(vtkWindow* window) override;

  // Returns a reason why this input and property cannot be pre-integrated, or nullptr.
  const char* GetStockFallbackReason(vtkVolume* vol, vtkDataArray* scalars);
  bool UploadTable(vtkRenderer* ren);
  // The array for VTK to upload as the volume texture under VolumePrecision: the input's own
  // or a cached copy of its values in a wider type.
  vtkDataArray* ChooseTextureScalars(vtkDataArray* scalars);
  bool BuildOnGPU(vtkOpenGLRenderWindow* context);

  int Integration = FIRST_ORDER;
  int TableSize = 0;
  int TablePrecision = PRECISION_AUTOMATIC;
  int TableBuilder = BUILD_AUTOMATIC;
  bool SkipEmptySegments = false;
  bool LastTableBuiltOnGPU = false;
  double LastTableBuildTime = 0.0;
  double OpacityThreshold = 1.0 - 1.0 / 255.0;
  double MaximumSamplesPerRay = 1e5;
  int VolumePrecision = VOLUME_PRECISION_AUTOMATIC;
  vtkIdType VolumeTextureMemorySize = 0;
  vtkIdType VolumeCopyMemorySize = 0;
  // The copy of the scalars for the volume texture, and what it was made from.
  vtkDataArray* ScalarsCopy = nullptr;
  vtkDataArray* ScalarsCopySource = nullptr;
  vtkMTimeType ScalarsCopyTime = 0;

  vtkFirstOrderPreIntegrationTable* FirstOrderTable;
  vtkSecondOrderPreIntegrationTable* SecondOrderTable;
  vtkOpenGLPreIntegrationTableBuilder* GPUBuilder;
  vtkTextureObject* TableTexture;
  vtkTextureObject* EmptyRunsTexture;
  // What the textures hold: table, its build and precision.
  vtkPreIntegrationTable* UploadedTable = nullptr;
  int UploadedBuildCount = -1;
  int UploadedPrecision = -1;
  vtkIdType TableTextureMemorySize = 0;
  float RawToTable[2] = { 1.0f, 0.0f };

private:
  vtkPreIntegrationVolumeMapper(const vtkPreIntegrationVolumeMapper&) = delete;
  void operator=(const vtkPreIntegrationVolumeMapper&) = delete;
};

#endif
