// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
/**
 * @class   vtkAnalyticVolumeMapper
 * @brief   exact first-hit isosurfaces and exact maximum/minimum intensity projection on the GPU
 *
 * VTK's GPU ray caster with the analytic ray profiles of Jozsa, Toth and Csebfalvi
 * ("Analytic isosurface rendering and maximum intensity projection on the GPU"). Each ray
 * visits every cell it crosses, with the integer-based traversal of their section 7, and
 * treats the trilinear field along the ray in a cell as the cubic it is: the isosurface is the
 * exact first crossing of the trilinear field, the projections the exact extremum, with no
 * sample distance to choose. The blend mode is the mapper's (SetBlendMode):
 *   - ISOSURFACE_BLEND: an opaque surface at the first crossing of any of the volume
 *     property's isosurface values (vtkVolumeProperty::GetIsoSurfaceValues()), coloured by the
 *     colour transfer function at its isovalue; when the property shades, lit by a white
 *     headlight along the ray with the exact gradient of the trilinear field (ambient +
 *     diffuse |n.v| + specular |n.v|^power, two-sided). Opacity and gradient opacity
 *     functions do not apply: the surface is opaque.
 *   - MAXIMUM_INTENSITY_BLEND / MINIMUM_INTENSITY_BLEND: the exact extremum along the ray,
 *     shown through the colour and opacity transfer functions as VTK's projections are.
 *   - other blend modes are drawn by VTK's stock shader, with a warning.
 * vtkVolumeReferenceIntegrator computes the same quantities in double precision.
 *
 * Method STOCK draws with VTK's own shader (its sampled isosurface and projections), so the
 * two can be compared through the same OutputQuantity.
 *
 * Rays: each pixel's ray comes from vtkCameraRayModel in double precision, as a point near
 * the volume and a direction in grid index (the frame of GetGridRayFrame), so float rounding
 * stays at the scale of the volume rather than of the camera's distance; the reference
 * integrator casts the same rays. Cameras the model does not describe (window centre, view
 * shear, explicit projection or model transforms) are reached through VTK's float matrices
 * instead, as the stock shader does; PrintSelf reports which (RayFrameInUse).
 *
 * Limits (each reported once, then VTK's stock shader draws): single-component point scalars
 * (no cell data), no cropping, 1D transfer functions. Volumes whose texture the GPU cannot
 * hold in one piece (CheckVolumeTexture), empty volumes and volumes with fewer than 2 points
 * along an axis are not drawn, with an error.
 */
#ifndef vtkAnalyticVolumeMapper_h
#define vtkAnalyticVolumeMapper_h

#include "hovrRenderingOpenGLModule.h" // For export macro
#include "vtkExtensibleGPUVolumeRayCastMapper.h"

#include "vtkSmartPointer.h" // For ivar
#include "vtkTimeStamp.h"    // For ivar

#include <memory> // For std::unique_ptr
#include <string> // For std::string
#include <vector> // For std::vector

class vtkOpenGLFramebufferObject;
class vtkOpenGLQuadHelper;
class vtkOpenGLRenderWindow;
class vtkTextureObject;

class HOVRRENDERINGOPENGL_EXPORT vtkAnalyticVolumeMapper
  : public vtkExtensibleGPUVolumeRayCastMapper
{
public:
  static vtkAnalyticVolumeMapper* New();
  vtkTypeMacro(vtkAnalyticVolumeMapper, vtkExtensibleGPUVolumeRayCastMapper);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  enum Methods
  {
    STOCK = 0,   ///< VTK's sampled isosurface and projections, at the sample distance
    ANALYTIC = 1 ///< exact first hit and extrema of the trilinear field
  };

  enum OutputQuantities
  {
    OUTPUT_COLOR = 0,    ///< the image
    OUTPUT_POSITION = 1, ///< RGBA = (grid index of the surface hit, 1); 0 on a miss
                         ///< (ANALYTIC: the grid index is brick b's, w = 1 + b, see
                         ///< GetBrickOrigin)
    OUTPUT_SCALAR = 2    ///< RGBA = (extremum in data units, 0, 0, 1); 0 where the ray misses
  };

  ///@{
  /**
   * How the blend mode is computed. Initial value is ANALYTIC.
   */
  vtkSetClampMacro(Method, int, STOCK, ANALYTIC);
  vtkGetMacro(Method, int);
  void SetMethodToStock() { this->SetMethod(STOCK); }
  void SetMethodToAnalytic() { this->SetMethod(ANALYTIC); }
  ///@}

  ///@{
  /**
   * What the fragments write: the colour, or, for measurements (hovr render's Depth and
   * MaxScalar/MinScalar arrays, read back with vtkFloatRGBARenderCapture), the surface hit
   * position (isosurface) or the extremum (projections). With Method STOCK the position is
   * the first sample past VTK's detected crossing, the extremum VTK's sampled one. Initial
   * value is OUTPUT_COLOR.
   */
  vtkSetClampMacro(OutputQuantity, int, OUTPUT_COLOR, OUTPUT_SCALAR);
  vtkGetMacro(OutputQuantity, int);
  ///@}

  ///@{
  /**
   * For the projections (MIP, MinIP) with Method ANALYTIC and OutputQuantity OUTPUT_COLOR:
   * write each pixel's depth from its extremum, nearer for a larger maximum (a smaller
   * minimum): 0.75 - 0.5 u for MIP, 0.25 + 0.5 u for MinIP, u the extremum's place in the
   * scalar range (ScalarRange, when set, else the data's). A compositor that keeps the nearest
   * fragment of several images (IceT's z-buffer compositing, ParaView's on several ranks
   * without ordered compositing) then keeps the pixel of the piece that holds the extremum:
   * the projection of the whole volume. Pixels no ray meets keep their depth. Initial value is
   * false.
   */
  vtkSetMacro(ExtremumDepth, bool);
  vtkGetMacro(ExtremumDepth, bool);
  vtkBooleanMacro(ExtremumDepth, bool);
  ///@}

  ///@{
  /**
   * Edge of the blocks, in cells, for empty-space skipping: a 3D texture holds the range of
   * the points of each block; a ray walks the blocks and enters only those that may hold an
   * isovalue (or, for the projections, beat the extremum found so far), cell by cell. The
   * image is the same with or without; 0 turns skipping off. Rebuilt when the data changes.
   * Initial value is 8 (a 256^3 volume gets a 32^3 texture of 256 KiB): larger blocks take
   * fewer block steps through dense data, smaller ones skip sparse data more finely.
   */
  vtkSetClampMacro(BlockSize, int, 0, 64);
  vtkGetMacro(BlockSize, int);
  ///@}

  /**
   * Bytes of GPU memory of the block-range texture (0 when skipping is off).
   */
  vtkGetMacro(BlockTextureMemorySize, vtkIdType);

  ///@{
  /**
   * Read each cell's 8 corners with 2 texture fetches instead of 8, from a second copy of the
   * volume holding 4 points per texel (the point and its neighbours in x, y and both). Costs
   * 4 values per point of GPU memory (in the data's type for 8- and 16-bit unsigned scalars,
   * else float: 4, 8 or 16 bytes per point) for a quarter of the fetches per cell, so it is
   * made only when it fits in CornerPackingMemoryLimit (and MaximumTextureBytes). The image
   * is the same either way. When the copy cannot be made (not enough memory, or the GPU
   * refuses the texture), the cells are read from VTK's volume texture after one warning,
   * until the scalars change. Initial value is on.
   */
  vtkSetMacro(CornerPacking, bool);
  vtkGetMacro(CornerPacking, bool);
  vtkBooleanMacro(CornerPacking, bool);
  ///@}

  ///@{
  /**
   * The largest packed-corner copy (CornerPacking), in bytes of GPU memory; a volume whose
   * copy would be larger reads its cells from VTK's volume texture, with the same image.
   * Initial value is 256 MiB: the copy of a float volume of up to 256^3 points, a 16-bit one
   * of 323^3 or an 8-bit one of 407^3.
   */
  vtkSetClampMacro(CornerPackingMemoryLimit, double, 0.0, 1e15);
  vtkGetMacro(CornerPackingMemoryLimit, double);
  ///@}

  /**
   * Bytes of GPU memory of the packed-corner texture (0 when CornerPacking is off).
   */
  vtkGetMacro(CornerTextureMemorySize, vtkIdType);

protected:
  vtkAnalyticVolumeMapper();
  ~vtkAnalyticVolumeMapper() override;

  FramePlan PrepareExtension(vtkRenderer* ren, vtkVolume* vol) override;
  bool ReplaceExtensionShaderValues(std::string& vertexShader,
    std::string& fragmentShader,
    vtkVolume* vol) override;
  void SetExtensionShaderParameters(vtkShaderProgram* program, vtkVolume* vol) override;
  void ActivateExtensionTextures() override;
  void DeactivateExtensionTextures() override;
  void ReleaseExtensionResources(vtkWindow* window) override;
  void DrawBrickedFrame(vtkRenderer* ren, vtkVolume* vol) override;
  // The colour target over the frame, with each pixel's depth from its extremum.
  void DrawWithExtremumDepth(vtkRenderer* ren, bool maximum);

  // Build and upload each brick's block ranges (BlockSize) and, when PackedThisFrame, packed
  // corners, unless they are current; false when a texture could not be made.
  bool UpdateBrickTextures(vtkRenderer* ren,
    vtkDataArray* scalars,
    const int dims[3],
    double scale,
    double shift);

  // The texture of the brick drawn, of a per-brick list.
  vtkTextureObject* GetCurrentBrickTexture(
    std::vector<vtkSmartPointer<vtkTextureObject>>& textures);

  // Why the analytic shader cannot draw this frame, or nullptr.
  const char* GetStockFallbackReason(vtkVolume* vol, vtkDataArray* scalars, int cellFlag);

  int Method = ANALYTIC;
  int OutputQuantity = OUTPUT_COLOR;
  bool ExtremumDepth = false;
  double DepthRange[2] = { 0.0, 1.0 }; // the scalar range the depth maps (data units)
  int BlockSize = 8;
  vtkIdType BlockTextureMemorySize = 0;
  std::vector<vtkSmartPointer<vtkTextureObject>> BlockTextures; // per brick
  std::string BlockKey;                                         // what they were built from

  // Per frame: what the shader is built for and the values it needs.
  bool StockThisFrame = false;
  std::string ShaderKey;
  std::vector<float> IsoRaw;
  float RawToData[2] = { 1.0f, 0.0f };
  float RawExtreme = 0.0f;
  float RawRange[2] = { 0.0f, 1.0f };    // the data's finite range in texture values
  float RawToVtkRaw[2] = { 1.0f, 0.0f }; // raw value -> VTK's texture's raw value

  // Whether the scalars hold NaN, kept for the scalars and their modification time.
  bool HasNaN(vtkDataArray* scalars);
  vtkDataArray* NaNScalars = nullptr; // not referenced: only compared
  vtkMTimeType NaNTime = 0;
  bool ScalarsHaveNaN = false;
  bool CornerPacking = true;
  double CornerPackingMemoryLimit = 256.0 * 1048576.0;
  bool PackedThisFrame = false; // CornerPacking within the limit, unless the copy failed
  vtkDataArray* UnpackableScalars = nullptr; // not referenced: only compared
  vtkMTimeType UnpackableTime = 0;
  std::vector<vtkSmartPointer<vtkTextureObject>> CornerTextures; // per brick
  vtkIdType CornerTextureMemorySize = 0;
  std::string CornerKey; // what they were built from

  // Projections over several bricks (DrawBrickedFrame): the round drawn (0: one brick), each
  // pixel's extremum, the colour, their framebuffer, and the extremum's copy for measurements.
  bool Rounds = false; // whether this frame's projection is drawn in rounds
  int Round = 0;
  vtkOpenGLRenderWindow* Context = nullptr; // of the frame
  vtkTextureObject* ExtremeTexture;
  vtkTextureObject* ColourTexture;
  vtkOpenGLFramebufferObject* Targets;
  std::unique_ptr<vtkOpenGLQuadHelper> ExtremeCopy;
  std::unique_ptr<vtkOpenGLQuadHelper> DepthCopy; // the colour, with depth from the extremum

private:
  vtkAnalyticVolumeMapper(const vtkAnalyticVolumeMapper&) = delete;
  void operator=(const vtkAnalyticVolumeMapper&) = delete;
};

#endif
