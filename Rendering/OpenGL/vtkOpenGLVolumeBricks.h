// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
/**
 * @class   vtkOpenGLVolumeBricks
 * @brief   a volume's scalars as one 3D texture per brick (vtkVolumeBrickLayout)
 *
 * The textures hovr's GPU methods sample instead of VTK's single volume texture: one per
 * brick, holding the brick's owned points and its ghosts, so that volumes with an axis beyond
 * the GPU's 3D texture size, or larger than a texture should be, are drawn brick by brick.
 * Each texture is filled slice by slice from the scalar array itself, so no copy of the volume
 * is made on the CPU.
 *
 * Formats (Precision): float scalars as they are (R32F); 8-bit scalars as they are (R8,
 * NATIVE) or as 16-bit normalised values (R16, WIDE: linear filtering of 8-bit textures
 * interpolates at 8-bit precision on common GPUs and llvmpipe); 16-bit scalars as R16; other
 * types as R32F values rescaled to [0, 1] over the finite range; with FLOAT32 every type as
 * R32F values (integers as they are). GetValueMapping() gives data = raw * scale + shift for
 * the raw value a sampler returns; a signed integer type is offset to unsigned first. NaN
 * reaches the texture only through R32F. Arrays of 3 components (normals) are uploaded as
 * RGB32F, as they are.
 *
 * With Atlas on, the bricks are packed into a few 3D textures instead (the atlas's pages, each
 * within GL_MAX_3D_TEXTURE_SIZE and the layout's MaximumBrickBytes), tile b of a page's grid of
 * tiles holding the page's brick b: a renderer whose rays cross the whole volume in one pass
 * reads the brick that owns the cell a sample lies in (hovrVolumeAtlas.glsl), so that every
 * trilinear sample is the volume's own (neighbouring bricks share their face points; the
 * layout needs no ghosts). That lifts the limits on an axis and on the bytes of one texture;
 * the pages are at most MaximumAtlasPages.
 *
 * A value class of hovr's mappers (a vtkObject for reference counting), not wrapped.
 */
#ifndef vtkOpenGLVolumeBricks_h
#define vtkOpenGLVolumeBricks_h

#include "hovrRenderingOpenGLModule.h" // For export macro
#include "vtkNew.h"                    // For ivar
#include "vtkObject.h"
#include "vtkSmartPointer.h" // For ivar

#include <functional> // For std::function
#include <string>     // For std::string
#include <vector>     // For std::vector

class vtkDataArray;
class vtkOpenGLRenderWindow;
class vtkShaderProgram;
class vtkTextureObject;
class vtkVolumeBrickLayout;
class vtkWindow;

class HOVRRENDERINGOPENGL_EXPORT vtkOpenGLVolumeBricks : public vtkObject
{
public:
  static vtkOpenGLVolumeBricks* New();
  vtkTypeMacro(vtkOpenGLVolumeBricks, vtkObject);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  enum Precisions
  {
    NATIVE = 0, ///< 8- and 16-bit integers in their own size
    WIDE = 1,   ///< 8-bit integers in 16 bits
    FLOAT32 = 2 ///< every type as 32-bit floats
  };

  ///@{
  /**
   * Texel precision (see the class documentation). Initial value is WIDE.
   */
  vtkSetClampMacro(Precision, int, NATIVE, FLOAT32);
  vtkGetMacro(Precision, int);
  ///@}

  ///@{
  /**
   * Whether the texture unit interpolates (linear filtering) or reads texels (nearest).
   * Initial value is true.
   */
  vtkSetMacro(Filtered, bool);
  vtkGetMacro(Filtered, bool);
  ///@}

  ///@{
  /**
   * Pack the bricks into one texture (see the class documentation). Initial value is false.
   */
  vtkSetMacro(Atlas, bool);
  vtkGetMacro(Atlas, bool);
  ///@}

  ///@{
  /**
   * The layout plans bricks for at least this many bytes per point, so that arrays of other
   * formats (normals) can be uploaded in the same bricks. Initial value is 0.
   */
  vtkSetClampMacro(MinimumBytesPerPoint, int, 0, 64);
  vtkGetMacro(MinimumBytesPerPoint, int);
  ///@}

  /**
   * The layout; set its GhostPoints, MaximumBrickPoints and MaximumBrickBytes before Update()
   * (its Dimensions and BytesPerPoint are set by Update()).
   */
  vtkVolumeBrickLayout* GetLayout() { return this->Layout; }

  /**
   * Lay out and upload the bricks of these scalars (component 0, or all 3 of a 3-component
   * array; point data) on a grid of dims points, unless they, the layout settings and the
   * format are those of the last upload. With a layout, its bricks instead of the own
   * layout's (another array of the same volume). False, with the reason in why and no
   * textures, when a brick cannot be created.
   */
  bool Update(vtkOpenGLRenderWindow* context,
    vtkDataArray* scalars,
    const int dims[3],
    std::string& why,
    vtkVolumeBrickLayout* layout = nullptr);

  /**
   * Write slices of a 3D texture: the region of `size` texels at `offset`, of `components`
   * values of vtkType each (VTK_UNSIGNED_CHAR, VTK_UNSIGNED_SHORT or VTK_FLOAT).
   * fillSlice(z, out) writes slice z (0 <= z < size[2]) of the region, x fastest, to out. The
   * slices are filled in threads, a slab at a time into a buffer of at most a few MiB (or one
   * slice), and each slab is uploaded with glTexSubImage3D, so no copy of the whole region
   * exists in CPU memory. False when the buffer cannot be allocated; GL errors are the
   * caller's to check.
   */
#ifndef __VTK_WRAP__
  static bool WriteSlices(vtkTextureObject* texture,
    const int offset[3],
    const int size[3],
    int components,
    int vtkType,
    const std::function<void(int, void*)>& fillSlice);
#endif

  /**
   * Whether `texture` already holds dims texels of `components` values of vtkType in
   * `context`, so that new values can be written into it instead of creating it again (a new
   * time step reuses its GPU memory).
   */
  static bool HasTexture3D(vtkTextureObject* texture,
    vtkOpenGLRenderWindow* context,
    const int dims[3],
    int components,
    int vtkType);

  /**
   * Bricks of the last upload (0 without one), and brick b's texture (in atlas mode, the page
   * that holds it).
   */
  int GetNumberOfBricks() const
  {
    return this->Textures.empty() ? 0 : this->BrickCount;
  }
  vtkTextureObject* GetTexture(int brick) const;

  /**
   * Atlas mode: the most textures (pages) the bricks may take, each sampler of a shader taking
   * one texture unit per page.
   */
  static constexpr int MaximumAtlasPages = 8;

  /**
   * Textures of the last upload: one per brick, or the atlas's pages.
   */
  int GetNumberOfTextures() const
  {
    return static_cast<int>(this->Textures.size());
  }

  /**
   * Activate (bind to texture units) the textures a draw of brick b reads: in atlas mode every
   * page; Deactivate releases them.
   */
  void Activate(int brick);
  void Deactivate(int brick);

  /**
   * After Activate(brick): point the shader's sampler `name` at them (in atlas mode an array
   * of one sampler per page, as GetAtlasSamplerCode declares it).
   */
  void SetSamplerUniform(vtkShaderProgram* program, const char* name, int brick) const;

  /**
   * Atlas mode: the most cuts along an axis (pieces + 1) that the GLSL's cut array holds and
   * the pages, as "#define HOVR_ATLAS_CUTS n" and "#define HOVR_ATLAS_PAGES p"
   * (hovrVolumeAtlas.glsl needs them before it), and the uniforms that place the bricks
   * (hovr_atlas*; the samplers themselves are the caller's, SetSamplerUniform).
   */
  std::string GetAtlasDefines() const;
  void SetAtlasUniforms(vtkShaderProgram* program) const;

  /**
   * Atlas mode: GLSL declaring the sampler array `name` (one per page) and its readers
   * name_texture(int page, vec3 coordinate) and name_texelFetch(int page, ivec3 texel), which
   * read the page that hovr_atlasCoord or hovr_atlasTexel gave.
   */
  std::string GetAtlasSamplerCode(const std::string& name) const;

  /**
   * data value = raw texture value * scale + shift, for every brick.
   */
  void GetValueMapping(double& scale, double& shift) const
  {
    scale = this->Scale;
    shift = this->Shift;
  }

  /**
   * Bytes of GPU memory the textures hold.
   */
  vtkIdType GetMemorySize() const
  {
    return this->MemorySize;
  }

  /**
   * Number of uploads so far (each brick counts).
   */
  vtkGetMacro(UploadCount, int);

  /**
   * Number of textures created so far: an upload of new values in the same layout and format
   * (a time step) writes into the textures already made and creates none.
   */
  vtkGetMacro(CreateCount, int);

  void ReleaseGraphicsResources(vtkWindow* window);

protected:
  vtkOpenGLVolumeBricks();
  ~vtkOpenGLVolumeBricks() override;

private:
  vtkOpenGLVolumeBricks(const vtkOpenGLVolumeBricks&) = delete;
  // Atlas mode: the tiles for the layout's bricks, false with why when they do not fit.
  bool PlanAtlas(vtkOpenGLRenderWindow* context,
    vtkVolumeBrickLayout* layout,
    int bytesPerTexel,
    std::string& why);
  void operator=(const vtkOpenGLVolumeBricks&) = delete;
  // The textures a draw of brick b reads: every page in atlas mode, else the brick's.
  std::vector<vtkTextureObject*> GetTexturesOf(int brick) const;

  int Precision = WIDE;
  bool Filtered = true;
  bool Atlas = false;
  int BrickCount = 0;
  int AtlasTiles[3] = { 1, 1, 1 };    // tiles along the atlas's axes
  int AtlasTileSize[3] = { 1, 1, 1 }; // texels of a tile
  int AtlasSize[3] = { 1, 1, 1 };     // texels of a page
  int AtlasPages = 1;
  std::vector<int> AtlasCuts; // the layout's cuts, HOVR_ATLAS_CUTS per axis
  int AtlasPieces[3] = { 1, 1, 1 };
  int AtlasDimensions[3] = { 2, 2, 2 };
  int MinimumBytesPerPoint = 0;
  vtkNew<vtkVolumeBrickLayout> Layout;
  std::vector<vtkSmartPointer<vtkTextureObject>> Textures;
  double Scale = 1.0;
  double Shift = 0.0;
  vtkIdType MemorySize = 0;
  int UploadCount = 0;
  int CreateCount = 0;
  // What the textures were made from: the array, its time, the settings.
  vtkDataArray* Scalars = nullptr; // not referenced: only compared
  vtkMTimeType ScalarsTime = 0;
  std::string Key;
};

#endif
