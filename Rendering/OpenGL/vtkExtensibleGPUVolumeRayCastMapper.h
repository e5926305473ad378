// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
/**
 * @class   vtkExtensibleGPUVolumeRayCastMapper
 * @brief   VTK's GPU ray caster with a per-frame hook for own GLSL, textures and uniforms
 *
 * The base of every hovr mapper. vtkOpenGLGPUVolumeRayCastMapper builds its fragment shader
 * from a template with //VTK:: tags but does not let subclasses edit it (the replacement
 * methods are not virtual) and fires UpdateShaderEvent only on frames that reuse a cached
 * shader. This class attaches a private vtkOpenGLRenderPass to the volume's
 * vtkOpenGLRenderPass::RenderPasses() key around each draw: the ray caster then calls it when
 * it builds the shader (to edit the template) and on every draw, including the first one (to
 * set uniforms). Subclasses implement:
 *   - PrepareExtension(): per frame, on the CPU: validate input, build tables, upload textures;
 *     decide whether to draw with the extension, with VTK's stock shader, or not at all;
 *   - ActivateExtensionTextures() / DeactivateExtensionTextures(): bind their textures around
 *     the superclass draw;
 *   - ReplaceExtensionShaderValues(): edit the shader template (tags still present);
 *   - SetExtensionShaderParameters(): uniforms and sampler units, every draw.
 * A subclass calls ExtensionShaderModified() when its GLSL must change; the hook reports that
 * time so the ray caster rebuilds the program.
 *
 * Automatic sample distance adjustment is off by default: hovr methods tabulate integrals for
 * the sample distance, and measuring accuracy needs a fixed step.
 */
#ifndef vtkExtensibleGPUVolumeRayCastMapper_h
#define vtkExtensibleGPUVolumeRayCastMapper_h

#include "hovrRenderingOpenGLModule.h" // For export macro
#include "vtkOpenGLGPUVolumeRayCastMapper.h"
#include "vtkSmartPointer.h" // For ivar
#include "vtkTimeStamp.h"    // For ivar

#include <memory> // For std::unique_ptr
#include <string> // For std::string

class vtkCameraRayModel;
class vtkGPURayCastShaderHook;
class vtkImageData;
class vtkOpenGLVolumeBricks;
class vtkOpenGLRenderTimer;
class vtkOpenGLRenderWindow;
class vtkPiecewiseFunction;
class vtkShaderProgram;
class vtkTextureObject;

class HOVRRENDERINGOPENGL_EXPORT vtkExtensibleGPUVolumeRayCastMapper
  : public vtkOpenGLGPUVolumeRayCastMapper
{
public:
  vtkTypeMacro(vtkExtensibleGPUVolumeRayCastMapper, vtkOpenGLGPUVolumeRayCastMapper);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  void ReleaseGraphicsResources(vtkWindow* window) override;

  /**
   * Number of frames drawn with the extension's shader so far.
   */
  vtkGetMacro(ExtensionFrameCount, int);

  /**
   * The time the OpenGL implementation took for the last draw whose timer query has
   * completed (seconds; a draw's own query completes a frame or two later), measured with
   * vtkOpenGLRenderTimer around each draw; 0 until one has, or where timer queries are not
   * supported.
   */
  vtkGetMacro(LastDrawTime, double);

  /**
   * Where ReplaceShaderTag() puts code: instead of the tag, or before or after it (the tag
   * stays, so VTK still substitutes its own code there).
   */
  enum TagPlacement
  {
    ReplaceTag = 0,
    BeforeTag,
    AfterTag
  };

  /**
   * Put code at one //VTK:: tag of a shader source. Returns false when the tag is absent or
   * the code itself contains a //VTK:: tag (a later replacement would hit that copy).
   */
  static bool ReplaceShaderTag(std::string& source,
    const std::string& tag,
    const std::string& code,
    TagPlacement placement);

  /**
   * Affine map from the raw value VTK's volume texture returns for an array of this type to
   * the data value: value = raw * scale + shift. Depends on how vtkVolumeTexture uploads each
   * scalar type (normalised integer formats, or a float copy rescaled to the range). With
   * `cover` (a ScalarRange), the range is the scalars' widened to cover it, as the proxy VTK
   * draws bricks from holds it.
   */
  static void GetTextureValueMapping(vtkDataArray* scalars,
    double& scale,
    double& shift,
    const double* cover = nullptr);

  /**
   * The fragment shader of the last program built with the extension, after every
   * replacement: the code that runs, for inspection and tests. Empty before the first build.
   */
  const std::string& GetFragmentShaderSource() const { return this->FragmentShaderSource; }

  /**
   * The input's bounds; an error when they are not finite (a NaN origin, an infinite
   * spacing), since the renderer then culls the volume and never asks for a frame.
   */
  double* GetBounds() VTK_SIZEHINT(6) override;
  using vtkAbstractMapper3D::GetBounds;

  ///@{
  /**
   * The largest 3D texture, in bytes, that the mapper creates, or lets VTK create, for the
   * volume and its copies (the volume texture, packed corners, normals, the oracle). OpenGL
   * implementations may accept a larger texture and then read it wrongly without reporting an
   * error, so every such texture is checked against this limit and against the context's
   * GL_MAX_3D_TEXTURE_SIZE before it is created, and OpenGL's error state is checked after.
   * Initial value is 1 GiB.
   */
  vtkSetClampMacro(MaximumTextureBytes, vtkIdType, 1024, VTK_ID_MAX);
  vtkGetMacro(MaximumTextureBytes, vtkIdType);
  ///@}

  ///@{
  /**
   * The most points along an axis of one brick, for the methods that draw a volume brick by
   * brick from textures of their own (a volume with an axis beyond the GPU's
   * GL_MAX_3D_TEXTURE_SIZE or over MaximumTextureBytes is split into bricks, each drawn over its
   * own box and composited back to front, with the image of one piece). 0 leaves it to the GPU's
   * limit. Initial value is 0 (a subclass may set another, see its documentation).
   */
  vtkSetClampMacro(MaximumBrickSize, int, 0, 1 << 20);
  vtkGetMacro(MaximumBrickSize, int);
  ///@}

  ///@{
  /**
   * A scalar range the mapper's tables, transfer-function textures and sampling span besides
   * the range of the scalars drawn: the whole volume's, when the input is one piece of it (a
   * rank's under MPI, as the ParaView plugin sets it), so that every piece is drawn with the
   * same tables and its image is the whole volume's image of that piece. An empty range
   * (low > high) or a non-finite one spans the scalars drawn alone. Initial value is (1, 0).
   */
  vtkSetVector2Macro(ScalarRange, double);
  vtkGetVector2Macro(ScalarRange, double);
  ///@}

  ///@{
  /**
   * Bounds (dataset coordinates, xmin, xmax, ymin, ymax, zmin, zmax) that the mapper's sampling
   * grid is anchored to besides its input's: the whole volume's, when the input is one piece of
   * it (a rank's under MPI, as the ParaView plugin sets them), so that every piece samples on the
   * grid of the whole. Empty bounds (a minimum above its maximum) anchor to the input's own.
   * The methods whose grid is anchored to the volume (the adaptive methods' slices) read them;
   * the others sample on a grid anchored to the camera. Initial value is (1, 0, 1, 0, 1, 0).
   */
  vtkSetVector6Macro(WholeBounds, double);
  vtkGetVector6Macro(WholeBounds, double);
  ///@}

  ///@{
  /**
   * The points of the input (its structured extent) the mapper draws as its own, when the
   * input is one piece of a volume that carries ghost points around it (a rank's under MPI,
   * as the ParaView plugin sets it): the piece without them. With WholeBounds, pre-integration
   * then walks each ray as the whole volume does, and a segment or slab that starts in the
   * owned points is drawn whole, reading the ghost points past them, so that the pieces
   * composited front to back give the whole volume's image; its ghost points must reach two
   * sample distances and two points past the owned ones. The adaptive ray walks from and to
   * the slices every walk samples (multiples of 2^MaximumLevel), so that its pieces' walks join
   * into the whole volume's; its ghost points, and those its oracle was computed with, must
   * reach 2^(MaximumLevel + 1) sample distances and two points. The slice pyramid
   * (vtkAdaptiveSamplingVolumeMapper) joins its walks likewise, from the first slice of
   * 2^MaximumLevel where a pixel's ray enters the owned points from another piece's; its ghost
   * points, and its oracle's, must reach 2^(MaximumLevel + 2) slice spacings (pixels) and two
   * points, else the owned points are drawn as a volume of their own. A frame drawn by VTK's
   * own path (Stock, or a fallback) is cropped to the owned points' box (with the user's
   * cropping, when that is a sub-volume). An empty extent (a
   * minimum above its maximum) owns the whole input. Initial value is (0, -1, 0, -1, 0, -1).
   */
  vtkSetVector6Macro(OwnedExtent, int);
  vtkGetVector6Macro(OwnedExtent, int);
  ///@}

  /**
   * Bricks of the last frame drawn brick by brick, and the bytes of GPU memory their textures
   * hold (0 for methods that draw from VTK's volume texture).
   */
  int GetNumberOfBricks();
  vtkIdType GetBrickTextureMemorySize();

  /**
   * Textures the last bricked frame's bricks took: one per brick, or, for the methods that pack
   * them into an atlas, its pages (each within MaximumTextureBytes).
   */
  int GetNumberOfBrickTextures();

  /**
   * Bricks uploaded since the mapper was made: each brick once per new or changed volume or
   * brick layout, none for a frame that only moves the camera or edits the transfer function.
   */
  int GetBrickUploadCount();

  /**
   * Brick textures created since the mapper was made: a new volume in the same layout and
   * format (a time step) is written into the textures already made, so this stays while
   * GetBrickUploadCount() grows.
   */
  int GetBrickTextureCreateCount();

  /**
   * The first point (0-based grid index) of brick b's texture in the last bricked frame: a
   * position in the brick's own grid index plus this is one in the volume's.
   */
  void GetBrickOrigin(int brick, int origin[3]);

protected:
  vtkExtensibleGPUVolumeRayCastMapper();
  ~vtkExtensibleGPUVolumeRayCastMapper() override;

  /**
   * What PrepareExtension() asks for this frame.
   */
  enum FramePlan
  {
    DrawWithExtension = 0, ///< hook attached, own GLSL
    DrawStock,             ///< plain vtkOpenGLGPUVolumeRayCastMapper
    DrawNothing            ///< an error was reported; the volume is not drawn
  };

  virtual FramePlan PrepareExtension(vtkRenderer* ren, vtkVolume* vol) = 0;
  virtual void ActivateExtensionTextures() {}
  virtual void DeactivateExtensionTextures() {}
  virtual bool ReplaceExtensionShaderValues(std::string& vertexShader,
    std::string& fragmentShader,
    vtkVolume* vol) = 0;
  virtual void SetExtensionShaderParameters(vtkShaderProgram* program, vtkVolume* vol) = 0;
  virtual void ReleaseExtensionResources(vtkWindow* window) { (void)window; }

  /**
   * The input's point scalars for this frame, with the grid dimensions and whether they are
   * cell scalars. Returns nullptr and sets plan when the frame cannot use the extension:
   * DrawStock without input or scalars (VTK reports that itself), DrawNothing after an error
   * when the volume has fewer than 2 points along an axis (no cell to render).
   */
  vtkDataArray* GetFrameScalars(int dims[3], int& cellFlag, FramePlan& plan);

  ///@{
  /**
   * Warn that this frame falls back to VTK's stock shader, once per distinct reason; clear
   * when the extension draws again.
   */
  void WarnFallbackOnce(const char* reason);
  void ClearFallbackWarning() { this->LastFallbackWarning.clear(); }
  ///@}

  ///@{
  /**
   * Warn that this frame's image is empty for a reason the mapper can tell (a transparent
   * transfer function over the data, no isovalue in the data), once per distinct message;
   * clear when a frame has no such reason. An empty image never comes without a message.
   */
  void WarnEmptyOnce(const std::string& message);
  void ClearEmptyWarning() { this->LastEmptyWarning.clear(); }
  ///@}

  /**
   * Scalars for VTK to upload as the volume texture instead of the input's own, from this
   * frame's PrepareExtension() on (nullptr, the initial value: the input's own). They must
   * have the input scalars' tuples and name; only the texture changes (for example a 16-bit
   * copy of 8-bit data for more interpolation precision), and it is uploaded again only when
   * this array changes. Frames drawn by the stock path always upload the input's own.
   */
  void SetTextureScalars(vtkDataArray* scalars);
  vtkDataArray* GetTextureScalars() { return this->TextureScalars; }

  /**
   * A copy of 8-bit scalars in 16 bits for VTK to upload as the volume texture (pass it to
   * SetTextureScalars()), or nullptr when the scalars need none: OpenGL implementations such
   * as Mesa's llvmpipe interpolate 8-bit textures at 8-bit precision, so the trilinear samples
   * between two values are quantised to 1/255 of the range, which a 16-bit texture of the same
   * values avoids. The copy holds the same values (unsigned char becomes unsigned short,
   * signed char and char become short), so the data range, VTK's lookup tables and
   * GetTextureValueMapping() of the copy stay right. With wideType VTK_FLOAT, 8- and 16-bit
   * scalars are copied to 32-bit floats instead. Only single-component arrays in standard
   * memory layout are copied; nullptr for any other array, for other types, for nullptr, and
   * (after a warning) when the copy does not fit in memory. The copy is cached and made again
   * only when the array, its modification time or wideType changes; a nullptr result releases
   * it.
   */
  vtkDataArray* WidenedTextureScalars(vtkDataArray* scalars, int wideType = VTK_VOID);

  /**
   * Why a frame of `method` (a subject for the message, e.g. "pre-integration") cannot be
   * drawn by the extension and goes to VTK's stock path, for what every hovr composite method
   * leaves out: a blend mode other than composite, scalars of several components, a 2D
   * transfer function, an enabled gradient opacity that is not constant one. Empty when none
   * applies.
   */
  std::string GetCompositeFallbackReason(vtkVolume* vol, vtkDataArray* scalars, const char* method);

  /**
   * Whether the sample distance is positive, finite and takes at most maximumSamples samples
   * along the input's diagonal; otherwise an error says so (the frame is then not drawn).
   */
  bool CheckFrameSampleDistance(double distance, double maximumSamples);

  /**
   * Whether a piecewise function is 1 at every node, so everywhere (VTK clamps outside the
   * nodes); false for nullptr or a function without nodes. A gradient opacity that is
   * constant one does not change the image.
   */
  static bool IsConstantOne(vtkPiecewiseFunction* function);

  /**
   * Why a 3D texture of dims texels of bytesPerTexel bytes, named `what` in the message,
   * cannot be created in this context: an axis beyond GL_MAX_3D_TEXTURE_SIZE, or more than
   * MaximumTextureBytes. Empty when it can.
   */
  std::string CheckTexture3D(vtkOpenGLRenderWindow* context,
    const int dims[3],
    double bytesPerTexel,
    const char* what);

  /**
   * Create3DFromRaw() after CheckTexture3D(), with the texture's formats already set, then
   * OpenGL's error state: false, the texture released and why set, on any failure.
   */
  bool CreateTexture3D(vtkTextureObject* texture,
    vtkOpenGLRenderWindow* context,
    const int dims[3],
    int components,
    int vtkType,
    void* data,
    const char* what,
    std::string& why);

  /**
   * Why VTK's volume texture of the input cannot be created (CheckTexture3D() for the
   * array VTK uploads, the texture scalars when set), empty when it can. VTK itself would draw
   * nothing then, with no error but its log lines.
   */
  std::string CheckVolumeTexture(vtkRenderer* ren, vtkDataArray* uploaded, const int dims[3]);

  // CheckVolumeTexture() for this frame's input and `uploaded` (nullptr: the input's own
  // scalars); false after an error when VTK could not create the texture.
  bool CheckFrameVolumeTexture(vtkRenderer* ren, vtkDataArray* uploaded);

  /**
   * For methods that draw from hovr's brick textures (vtkOpenGLVolumeBricks) instead of VTK's
   * volume texture: lay out and upload the bricks of the frame's scalars, ghostPoints beyond
   * each brick's own cells, at a vtkOpenGLVolumeBricks precision, filtered (linear
   * interpolation) or not, planned for at least minimumBytes per point (for other arrays in the
   * same bricks), with at most maximumPoints points an axis when positive (besides
   * MaximumBrickSize and the GPU's limits). The frame is then drawn brick by brick in
   * visibility order, VTK drawing each
   * brick's box; while a brick is drawn, GetBrickCells(), GetBrickPoints() and
   * GetBrickTexture() describe it and its texture is active. With atlas, the bricks are packed
   * into one texture (vtkOpenGLVolumeBricks' atlas mode) and VTK draws the whole volume's box
   * once, over it. False after an error (nothing is drawn).
   */
  bool PrepareBricks(vtkRenderer* ren,
    vtkDataArray* scalars,
    const int dims[3],
    int ghostPoints,
    int precision,
    bool filtered,
    int minimumBytes = 0,
    int maximumPoints = 0,
    bool atlas = false);
  void GetBrickCells(int cells[6]);
  void GetBrickPoints(int points[6]);

  /**
   * Draw a bricked frame: by default one round of DrawBrickRound(). A method whose results do
   * not composite by "over" (a maximum) draws several rounds into targets of its own.
   */
  virtual void DrawBrickedFrame(vtkRenderer* ren, vtkVolume* vol);

  /**
   * Draw every brick once, back to front, each over its own box.
   */
  void DrawBrickRound(vtkRenderer* ren, vtkVolume* vol);
  vtkTextureObject* GetBrickTexture();
  int GetCurrentBrick() const { return this->CurrentBrick; }
  vtkOpenGLVolumeBricks* GetBricks() { return this->Bricks; }
  bool GetBrickedThisFrame() const { return this->BrickedThisFrame; }

  /**
   * The rays of this frame as an affine frame in the volume's grid index (vtkCameraRayModel's
   * GetGridRayFrame, in double), when the model describes the camera (RayFrameInUse); cameras
   * it does not (window centre, view shear, explicit projection) leave RayFrameInUse 0.
   */
  void UpdateRayFrame(vtkRenderer* ren, vtkVolume* vol);

  /**
   * The rays' uniforms: hovr_rayFrameInUse; the volume's frame, the same for every brick
   * (hovr_rayCentre, hovr_rayEye, hovr_rayPixelCentre, grid index of the volume); the brick
   * drawn's (hovr_localCentre, hovr_localEye, hovr_localPixelCentre: its texture's grid index,
   * centred on the pixel nearest to the brick's centre, so that float positions round at the
   * brick's scale); hovr_rayDx, hovr_rayDy, hovr_rayForward and hovr_rayPerspective; and the
   * pixel grid moved to the plane through the brick's centre (hovr_brickCentre, hovr_brickDx,
   * hovr_brickDy, in the brick's grid index), where positions near the brick round finest.
   */
  void SetRayFrameUniforms(vtkShaderProgram* program);

  vtkCameraRayModel* RayModel;
  int RayFrameInUse = 0;
  double RayFrame[5][3] = {}; // centre, dx, dy, eye, forward (see GetGridRayFrame)
  double RayPixelCentre[2] = { 0.0, 0.0 };
  int RayPerspective = 0;

  /**
   * Mark the extension's GLSL as changed: the program is rebuilt on the next draw.
   */
  void ExtensionShaderModified() { this->ExtensionShaderTime.Modified(); }

  void GPURender(vtkRenderer* ren, vtkVolume* vol) override;

  // Puts `scalars` (nullptr: the input's own) where VTK's ray caster reads the array to
  // upload: in its copy of the input, GetTransformedInput().
  void PlaceTextureScalars(vtkDataArray* scalars);

  vtkTimeStamp ExtensionShaderTime;
  int ExtensionFrameCount = 0;
  double LastDrawTime = 0.0;
  std::unique_ptr<vtkOpenGLRenderTimer> DrawTimer; // a reusable timer query around each draw
  vtkIdType MaximumTextureBytes = vtkIdType(1) << 30;
  int MaximumBrickSize = 0;
  vtkMTimeType ReportedBoundsTime = 0; // the input time whose bounds GetBounds reported
  std::string FragmentShaderSource;
  std::string LastFallbackWarning;
  std::string LastEmptyWarning;

  double ScalarRange[2] = { 1.0, 0.0 };
  double WholeBounds[6] = { 1.0, 0.0, 1.0, 0.0, 1.0, 0.0 };
  int OwnedExtent[6] = { 0, -1, 0, -1, 0, -1 };

  // bounds widened to cover WholeBounds when those are not empty.
  void CoverWholeBounds(double bounds[6]) const;

  // The whole volume's box (WholeBounds' corners, else the input's own) and the points the
  // input owns (OwnedExtent within the input, else all of them), in the input's grid index
  // (0 at its first point).
  void GetWholeIndexBox(double lo[3], double hi[3]);

  // VTK's own path (DrawStock), for a piece with ghost points cropped to its owned points.
  void DrawStockOwned(vtkRenderer* ren, vtkVolume* vol);
  bool StockCroppedToOwned = false;
  void GetOwnedIndexBox(int lo[3], int hi[3]);

private:
  vtkExtensibleGPUVolumeRayCastMapper(const vtkExtensibleGPUVolumeRayCastMapper&) = delete;
  void operator=(const vtkExtensibleGPUVolumeRayCastMapper&) = delete;

  friend class vtkGPURayCastShaderHook;
  vtkGPURayCastShaderHook* Hook;

  vtkOpenGLVolumeBricks* Bricks;
  vtkImageData* Proxy;
  vtkSmartPointer<vtkDataArray> ProxyScalars;
  bool BrickedThisFrame = false;
  int CurrentBrick = 0;
  vtkDataArray* TextureScalars = nullptr;
  // WidenedTextureScalars()' cached copy and what it was made from.
  vtkDataArray* WidenedScalars = nullptr;
  vtkDataArray* WidenedSource = nullptr;
  vtkMTimeType WidenedSourceTime = 0;
};

#endif
