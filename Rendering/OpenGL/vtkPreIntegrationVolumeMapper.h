// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
/**
 * @class   vtkPreIntegrationVolumeMapper
 * @brief   GPU ray casting with pre-integrated classification
 *
 * A vtkOpenGLGPUVolumeRayCastMapper whose compositing integrates the transfer functions
 * between samples instead of point-sampling them, so that narrow transfer-function features
 * are not missed between samples:
 *   - Integration = STOCK: VTK's own compositing, unchanged (for comparison);
 *   - Integration = FIRST_ORDER: first-order pre-integration (Engel et al. 2001): each segment
 *     between consecutive samples, its scalar taken linear, from a 2D table for the sample
 *     distance;
 *   - Integration = SECOND_ORDER: second-order pre-integration (El Hajjar et al. 2008), slabs
 *     of two sample distances whose three samples fix a quadratic profile, from a 3D table:
 *     one volume fetch per sample, one table fetch per slab.
 * Both tables are vtkSecondOrderPreIntegrationTable, whose axes are the chord's centre
 * (front + back) / 2, the chord back - front and (second order) the deviation of the middle
 * sample from the chord: a ray whose scalar lingers gives segments near chord 0, so the fine
 * resolution the transfer function needs goes to the centre axis only, while the chord and
 * deviation axes span what the data produce at this step. The first-order table is the same
 * table with deviation 0.
 *
 * Only the table of the active order is built, on the CPU (or for second order on the GPU,
 * see TableBuilder), and uploaded only when the transfer functions, the opacity unit
 * distance, the sample distance, the data or the table's sizes change. Its sizes are measured
 * (vtkPreIntegrationTableSizer: candidate tables against the reference integrator on random
 * rays through the volume, the least memory within 2% of the best error) unless TableSize is
 * set, and its storage precision follows its order unless TablePrecision is set.
 *
 * Shading (the volume property's Shade on) is pre-integrated too: Guetat et al. 2010's shaded
 * pre-integration, Blinn-Phong with the paper's cone for the specular term or Gooch shading,
 * from moment layers of the table and the normals at the samples, interpolated as
 * GradientInterpolation says; the lighting model is vtkVolumeShadingModel, with the
 * renderer's directional lights (several are summed) and its two-sided lighting flag. Normals
 * are VTK's: the normalised central-difference gradient of the scalar texture.
 *   - First order: the moment layers of the first-order table (vtkSecondOrderPreIntegration-
 *     Table::Moments) and the normals at both ends of each segment.
 *   - Second order: the slab moment layers of the 3D table (vtkSecondOrderPreIntegrationTable::
 *     SlabMoments: the moments of each half slab, the scalar on the slab's quadratic) and the
 *     normals at the slab's three samples; each half is shaded between the normals at its
 *     ends (front and middle, middle and back), so the normal follows the same arcs as first
 *     order at the same sample distance while the scalar follows the quadratic. The table
 *     holds twice first order's layers per entry (4 for constant and linear interpolation, 8
 *     for non-linear), counted in TableMemoryLimit and in the 3D
 *     texture's depth, and is built on the CPU.
 *
 * The volume is drawn brick by brick from textures of its own (vtkOpenGLVolumeBricks, with
 * the ghost points a segment or slab reaching past a brick's face reads), and the shader walks
 * each ray itself: samples lie on the ray's own grid (t = k times the sample distance from the
 * camera's plane or eye, jittered by VTK's noise when UseJittering is on), and a brick
 * composites the pieces whose front lies in it, so that the bricks give the image of one piece
 * (up to early ray termination, which each brick applies to its own pieces). Cropping (a piece
 * whose back lies in a region not drawn is skipped), clipping planes and opaque geometry (the
 * ray ends at VTK's termination point) keep working. Composite blending of one-component scalars
 * (RGB or grey colour) without enabled gradient opacity or 2D transfer functions is
 * pre-integrated, shaded or not, with directional lights only, for point scalars and
 * cameras that vtkCameraRayModel describes; anything else is drawn by VTK's stock path after a
 * warning. The sample
 * distance is fixed (automatic adjustment is off) and must be positive: otherwise an error is
 * reported and nothing is drawn.
 */
#ifndef vtkPreIntegrationVolumeMapper_h
#define vtkPreIntegrationVolumeMapper_h

#include "hovrRenderingOpenGLModule.h" // For export macro
#include "vtkCommand.h"                // For TablesRefinedEvent
#include "vtkExtensibleGPUVolumeRayCastMapper.h"
#include "vtkWeakPointer.h" // For the watched interactor

#include <string> // For std::string
#include <vector> // For std::vector

class vtkImageData;
class vtkOpenGLPreIntegrationTableBuilder;
class vtkOpenGLRenderWindow;
class vtkOpenGLVolumeBricks;
class vtkPreIntegrationTableSizer;
class vtkPreIntegrationTableSizing;
class vtkRenderWindowInteractor;
class vtkSecondOrderPreIntegrationTable;
class vtkTextureObject;
class vtkVolumeShadingModel;
class vtkVolumeTransferFunctionSampler;

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

  enum TablePrefilters
  {
    PREFILTER_OFF = 0,      ///< the transfer function as it is
    PREFILTER_ON = 1,       ///< box-averaged over one centre spacing
    PREFILTER_AUTOMATIC = 2 ///< measured by the sizer for first order; off otherwise
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
   * Entries along every axis of the table, over every chord (and deviation) the scalar range
   * allows: N^2 entries for first order, N^3 for second order, as tables over (front, back)
   * and (front, middle, back) of that size. 0 measures the sizes instead
   * (vtkPreIntegrationTableSizer, within TableMemoryLimit): the chord and deviation axes then
   * span only what the data produce at this step, and each axis gets the entries the image
   * needs. Values above the OpenGL texture limits or 4097 are clamped with a warning (shaded
   * second order: the deviation axis to what its moment layers leave of the 3D texture
   * depth). Initial value is 0.
   */
  vtkSetClampMacro(TableSize, int, 0, 65536);
  vtkGetMacro(TableSize, int);
  ///@}

  ///@{
  /**
   * The largest table the automatic sizes consider, in bytes of GPU memory at the table's
   * precision, every moment layer of a shaded table included (shaded second order stores 4 or
   * 8 layers per entry, and needs a larger limit than unshaded second order for the same
   * sizes). Initial value is 64 MiB.
   */
  vtkSetClampMacro(TableMemoryLimit, double, 1024.0, 1e12);
  vtkGetMacro(TableMemoryLimit, double);
  ///@}

  ///@{
  /**
   * The volume the automatic sizes are measured on instead of the input (its point scalars,
   * one component, in the same world coordinates): when the input is one piece of a volume
   * drawn in pieces (ParaView's ranks), the whole volume, or every few points of it
   * (vtkWholeVolumeAssembler), so that every piece draws the table the whole volume gets. Its
   * scalars must span the input's values or ScalarRange. nullptr measures on the input.
   * Initial value is nullptr.
   */
  virtual void SetSizingVolume(vtkImageData* volume);
  vtkGetObjectMacro(SizingVolume, vtkImageData);
  ///@}

  /**
   * What the automatic sizes measured last (candidates, errors, the exact segment model's
   * error, time): the statistics of the measured table in use.
   */
  vtkPreIntegrationTableSizer* GetTableSizer();

  /**
   * When the automatic sizes are measured (at once, or in the background after interim
   * sizes), and its statistics.
   */
  vtkPreIntegrationTableSizing* GetTableSizing() { return this->TableSizing; }

  /**
   * Fired by CheckRefinement() (and the watch of WatchRefinement()) when a table measured in
   * the background waits to be drawn: render again to draw it.
   */
  enum RefinementEvents
  {
    TablesRefinedEvent = vtkCommand::UserEvent + 7301
  };

  ///@{
  /**
   * Answer first, refine after: when the automatic sizes must be measured (the transfer
   * functions, the data, the sample distance, the order or the shading changed), draw that
   * frame at once with interim sizes (the last measured ones, or a small table over every
   * chord; vtkPreIntegrationTableSizing) and measure and build the table in a worker thread;
   * a newer change stops an older measurement. When the measured table is ready,
   * CheckRefinement() fires TablesRefinedEvent, and the next render draws it. Off (batch
   * use: pvbatch, hovr render, the bench, tests), every frame waits for its measured table
   * and is deterministic. No effect with a fixed TableSize. Initial value is false.
   */
  virtual void SetRefineInBackground(bool refine);
  virtual bool GetRefineInBackground();
  vtkBooleanMacro(RefineInBackground, bool);
  ///@}

  /**
   * Whether the last frame was drawn with interim sizes whose measured table is not drawn
   * yet (being measured, or waiting for the next render).
   */
  bool GetRefining();

  /**
   * Whether a table measured in the background waits for the next render.
   */
  bool GetRefinementReady();

  /**
   * How far the background measurement is, in [0, 1] (1: none runs). Measurements made
   * before a frame fire ProgressEvent on the mapper instead (the sizer's and the table
   * build's).
   */
  double GetRefinementProgress();

  /**
   * Fires TablesRefinedEvent and returns true when a table measured in the background waits
   * for the next render; call it from the application's event loop (a timer), or let
   * WatchRefinement() do so.
   */
  bool CheckRefinement();

  /**
   * Block until the background measurement of the last frame's table is done (the next
   * render then draws it).
   */
  void WaitForRefinement();

  /**
   * Watch for refined tables from a repeating timer of this interactor (every 50 ms):
   * CheckRefinement() then fires TablesRefinedEvent in its event loop, where an observer can
   * render. nullptr stops watching. The interactor is not kept alive.
   */
  void WatchRefinement(vtkRenderWindowInteractor* interactor);

  ///@{
  /**
   * Storage of the table on the GPU. Initial value is PRECISION_AUTOMATIC.
   */
  vtkSetClampMacro(TablePrecision, int, PRECISION_AUTOMATIC, PRECISION_FLOAT32);
  vtkGetMacro(TablePrecision, int);
  ///@}

  ///@{
  /**
   * Where the second-order table is built (the first-order table and shaded tables always on
   * the CPU). A
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
   * GPU), and costs time where they are cheap, as on software renderers such as Mesa's
   * llvmpipe. Initial value is false.
   */
  virtual void SetSkipEmptySegments(bool skip);
  vtkGetMacro(SkipEmptySegments, bool);
  vtkBooleanMacro(SkipEmptySegments, bool);
  ///@}

  ///@{
  /**
   * The most integration steps along a table entry's segment or slab: an entry takes one step
   * per sample of the transfer function that its scalar sweeps (vtkSecondOrderPreIntegration-
   * Table::Iterations), up to this many (the paper takes 64 evenly spaced steps for every
   * entry). Initial value is 64.
   */
  virtual void SetIterations(int iterations);
  virtual int GetIterations();
  ///@}

  ///@{
  /**
   * Box-average the transfer function over one entry spacing of the table's centre axis before
   * integrating (vtkSecondOrderPreIntegrationTable::Prefilter). It keeps the integral over
   * scalar values of features narrower than a spacing, but a ray whose scalar lingers next to
   * such a feature collects opacity the transfer function does not give it. PREFILTER_OFF (or
   * false) and PREFILTER_ON (or true) hold for both orders and every table size;
   * PREFILTER_AUTOMATIC lets the sizer measure each candidate of a first-order table with and
   * without it (vtkPreIntegrationTableSizer::MeasurePrefilter) when TableSize is 0, and leaves
   * it off otherwise: for second order the measured gain is rarely worth the doubled measuring
   * time. GetActiveTable()->GetPrefilter() tells what was used. Initial value is
   * PREFILTER_AUTOMATIC.
   */
  vtkSetClampMacro(TablePrefilter, int, PREFILTER_OFF, PREFILTER_AUTOMATIC);
  vtkGetMacro(TablePrefilter, int);
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
   * How the volume is stored on the GPU (its bricks, vtkOpenGLVolumeBricks) while it is
   * pre-integrated. Texture units may interpolate an 8-bit texture at 8-bit precision (Mesa's
   * llvmpipe does), which rounds every sample to about a whole data value and puts a floor
   * under the error of every step and table size. VOLUME_PRECISION_16BIT (the automatic
   * choice) stores 8-bit data as 16-bit values, the same values in twice the memory, whose
   * texels llvmpipe converts to float before interpolating; VOLUME_PRECISION_FLOAT32 stores
   * every type as floats (four bytes per value), interpolated in float wherever float textures
   * are filtered in float; VOLUME_PRECISION_NATIVE keeps 8-bit data in 8 bits. 16-bit data is
   * stored in 16 bits, 32-bit integers and doubles as floats. The textures are filled from the
   * array itself, slice by slice: no copy of the volume is made on the CPU. Initial value is
   * VOLUME_PRECISION_AUTOMATIC.
   */
  vtkSetClampMacro(VolumePrecision, int, VOLUME_PRECISION_AUTOMATIC, VOLUME_PRECISION_FLOAT32);
  vtkGetMacro(VolumePrecision, int);
  ///@}

  /**
   * Bytes of the volume's textures of the last pre-integrated frame (its bricks, ghost points
   * included), and of a CPU copy made for them (none: 0).
   */
  vtkIdType GetVolumeTextureMemorySize() { return this->GetBrickTextureMemorySize(); }
  vtkIdType GetVolumeCopyMemorySize() { return 0; }

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
  vtkSecondOrderPreIntegrationTable* GetFirstOrderTable() { return this->FirstOrderTable; }
  vtkSecondOrderPreIntegrationTable* GetSecondOrderTable() { return this->SecondOrderTable; }
  vtkSecondOrderPreIntegrationTable* GetActiveTable();
  ///@}

  ///@{
  /**
   * Shading: how the normal is interpolated between the two samples of a segment (or half slab)
   * (vtkVolumeShadingModel::GradientInterpolations: CONSTANT, LINEAR as Lum et al., NONLINEAR
   * as Guetat et al.). Initial value is NONLINEAR.
   */
  virtual void SetGradientInterpolation(int mode);
  virtual int GetGradientInterpolation();
  ///@}

  ///@{
  /**
   * Shading: Gooch shading (Guetat et al.'s Eq. 11, tones and weights of
   * GetShadingModel()) instead of Blinn-Phong. Initial value is false.
   */
  virtual void SetGooch(bool gooch);
  virtual bool GetGooch();
  vtkBooleanMacro(Gooch, bool);
  ///@}

  ///@{
  /**
   * Shading: the point array of 3-component vectors to take as the normals
   * (interpolated trilinearly and normalised), such as the output of vtkGradientExaggeration;
   * nullptr or empty: the gradient of the trilinear field (the differences one point either
   * side, clamped to the volume, as vtkVolumeReferenceIntegrator's). The vectors are in the
   * data's coordinates (as vtkImageGradient's) and uploaded, in the volume's bricks, as float
   * textures (12 bytes per point) when the array changes. A name the input lacks, or an array that
   * is not 3 components per point, is an error: nothing is drawn. Initial value is nullptr.
   */
  vtkSetStringMacro(NormalArrayName);
  vtkGetStringMacro(NormalArrayName);
  ///@}

  /**
   * Bytes of GPU memory held by the normal texture (0 without NormalArrayName).
   */
  vtkGetMacro(NormalTextureMemorySize, vtkIdType);

  /**
   * The lighting model of shaded frames: its coefficients and lights are taken from the volume
   * property and the renderer at every frame; the other settings (Gooch tones, the bound of
   * the non-linear normalisation) are the caller's.
   */
  vtkVolumeShadingModel* GetShadingModel() { return this->ShadingModel; }

  /**
   * Whether the last frame was drawn with shaded pre-integration.
   */
  vtkGetMacro(LastFrameShaded, bool);

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

  // Warns once when the opacity is zero over the data range (no sampler: nothing to say).
  void WarnIfTransparent(vtkVolumeTransferFunctionSampler* sampler, const double range[2]);

  // Returns a reason why this input and property cannot be pre-integrated, or nullptr.
  const char* GetStockFallbackReason(vtkRenderer* ren, vtkVolume* vol, vtkDataArray* scalars);
  std::string FallbackReason; // what GetStockFallbackReason() last returned, when composed
  bool UploadTable(vtkRenderer* ren);
  // Takes the lighting of a shaded frame (lights from the renderer, coefficients
  // from the property) and sets the GLSL's shading switches: the moment layers the table
  // needs (0 unshaded), or -1 after an error (nothing can be drawn).
  int PrepareShading(vtkRenderer* ren, vtkVolume* vol);
  void SetShadingParameters(vtkShaderProgram* program);
  // Uploads the NormalArrayName array in the volume's bricks if it changed; false after an
  // error.
  bool UploadNormals(vtkRenderer* ren, const int dims[3]);
  // The frame's geometry for the shader: grid index to world and to the data's coordinates,
  // the camera's near plane and view direction, cropping and clipping in grid index.
  void PrepareRayGeometry(vtkRenderer* ren, vtkVolume* vol);
  // Sets the active table's sizes: TableSize, or measured by the sizer when the data, the
  // transfer functions or the step changed. False after an error.
  bool SizeTable(vtkOpenGLRenderWindow* context,
    vtkDataArray* scalars,
    int cellFlag,
    const double range[2]);
  bool BuildOnGPU(vtkOpenGLRenderWindow* context);

  int Integration = FIRST_ORDER;
  int TableSize = 0;
  int TablePrecision = PRECISION_AUTOMATIC;
  int TablePrefilter = PREFILTER_AUTOMATIC;
  int TableBuilder = BUILD_AUTOMATIC;
  bool SkipEmptySegments = false;
  bool LastTableBuiltOnGPU = false;
  double LastTableBuildTime = 0.0;
  double OpacityThreshold = 1.0 - 1.0 / 255.0;
  double MaximumSamplesPerRay = 1e5;
  int VolumePrecision = VOLUME_PRECISION_AUTOMATIC;

  vtkSecondOrderPreIntegrationTable* FirstOrderTable; // deviation 0
  vtkVolumeShadingModel* ShadingModel;
  bool LastFrameShaded = false;
  char* NormalArrayName = nullptr;
  vtkOpenGLVolumeBricks* NormalBricks;
  vtkIdType NormalTextureMemorySize = 0;
  vtkDataArray* UploadedNormals = nullptr; // the array in NormalBricks, nullptr when none

  // The frame's geometry (PrepareRayGeometry).
  float IndexToWorld[9] = {};
  float IndexToObject[9] = {};
  float GradientToObject[9] = {};
  float ViewDirection[3] = { 0.0f, 0.0f, -1.0f };
  float Near = 0.0f;
  float PlaneT = 0.0f;
  float CroppingPlanes[6] = {};
  int CroppingRegions = 0;
  int ClippingCount = 0;
  float ClippingPlanes[6][4] = {};
  std::string RaySwitches; // HOVR_JITTER, HOVR_CLIPPING, HOVR_CROPPING as inserted
  // The shading switches of the GLSL last inserted (empty: unshaded).
  std::string ShadingSwitches;
  vtkSecondOrderPreIntegrationTable* SecondOrderTable;
  vtkPreIntegrationTableSizing* TableSizing;
  double TableMemoryLimit = 64.0 * 1024.0 * 1024.0;
  vtkImageData* SizingVolume = nullptr;
  // Fires the mapper's ProgressEvent for the sizer's and the tables' (measurements and builds
  // made before a frame).
  static void ForwardProgress(vtkObject*, unsigned long, void* clientData, void* callData);
  // WatchRefinement(): the interactor, its timer (0: none) and the observer's tag.
  vtkWeakPointer<vtkRenderWindowInteractor> WatchedInteractor;
  int WatchTimer = 0;
  unsigned long WatchObserver = 0;
  void StopWatching();
  static void OnWatchTimer(vtkObject*, unsigned long, void* clientData, void* callData);
  vtkOpenGLPreIntegrationTableBuilder* GPUBuilder;
  vtkTextureObject* TableTexture;
  vtkTextureObject* EmptyRunsTexture;
  // What the textures hold: table, its build and precision.
  vtkSecondOrderPreIntegrationTable* UploadedTable = nullptr;
  int UploadedBuildCount = -1;
  int UploadedPrecision = -1;
  vtkIdType TableTextureMemorySize = 0;
  float RawToTable[2] = { 1.0f, 0.0f };
  // Centre-axis coordinate differences -> chord and deviation coordinates.
  float ChordScale = 0.0f;
  float DeviationScale = 0.0f;

private:
  vtkPreIntegrationVolumeMapper(const vtkPreIntegrationVolumeMapper&) = delete;
  void operator=(const vtkPreIntegrationVolumeMapper&) = delete;
};

#endif
