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
 * Formats: float scalars as they are (R32F); 8-bit scalars as 16-bit normalised values
 * (R16; linear filtering of 8-bit textures interpolates at 8-bit precision on common GPUs and
 * llvmpipe) or, when the samples are read without filtering (Filtered off), as they are (R8);
 * 16-bit scalars as R16; other types as R32F values rescaled to [0, 1] over the finite range.
 * GetValueMapping() gives data = raw * scale + shift for the raw value a sampler returns; a
 * signed type is offset to unsigned first. NaN reaches the texture only through R32F.
 *
 * A value class of hovr's mappers (a vtkObject for reference counting), not wrapped.
 */
#ifndef vtkOpenGLVolumeBricks_h
#define vtkOpenGLVolumeBricks_h

#include "hovrRenderingOpenGLModule.h" // For export macro
#include "vtkObject.h"
#include "vtkNew.h"       // For ivar
#include "vtkSmartPointer.h" // For ivar

#include <string> // For std::string
#include <vector> // For std::vector

class vtkDataArray;
class vtkOpenGLRenderWindow;
class vtkTextureObject;
class vtkVolumeBrickLayout;
class vtkWindow;

class HOVRRENDERINGOPENGL_EXPORT vtkOpenGLVolumeBricks : public vtkObject
{
public:
  static vtkOpenGLVolumeBricks* New();
  vtkTypeMacro(vtkOpenGLVolumeBricks, vtkObject);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /**
   * Whether the samples are filtered (linear interpolation by the texture unit): 8-bit data
   * then go up as 16-bit. Initial value is true.
   */
  vtkSetMacro(Filtered, bool);
  vtkGetMacro(Filtered, bool);
  ///@}

  /**
   * The layout; set its GhostPoints, MaximumBrickPoints and MaximumBrickBytes before Update()
   * (its Dimensions and BytesPerPoint are set by Update()).
   */
  vtkVolumeBrickLayout* GetLayout() { return this->Layout; }

  /**
   * Lay out and upload the bricks of these scalars (component 0, point data) on a grid of dims
   * points, unless they, the layout settings and the format are those of the last upload.
   * False, with the reason in why and no textures, when a brick cannot be created.
   */
  bool Update(vtkOpenGLRenderWindow* context, vtkDataArray* scalars, const int dims[3],
    std::string& why);

  int GetNumberOfBricks() const { return static_cast<int>(this->Textures.size()); }
  vtkTextureObject* GetTexture(int brick) const;

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
  vtkIdType GetMemorySize() const { return this->MemorySize; }

  /**
   * Number of uploads so far (each brick counts).
   */
  vtkGetMacro(UploadCount, int);

  void ReleaseGraphicsResources(vtkWindow* window);

protected:
  vtkOpenGLVolumeBricks();
  ~vtkOpenGLVolumeBricks() override;

private:
  vtkOpenGLVolumeBricks(const vtkOpenGLVolumeBricks&) = delete;
  void operator=(const vtkOpenGLVolumeBricks&) = delete;

  bool Filtered = true;
  vtkNew<vtkVolumeBrickLayout> Layout;
  std::vector<vtkSmartPointer<vtkTextureObject>> Textures;
  double Scale = 1.0;
  double Shift = 0.0;
  vtkIdType MemorySize = 0;
  int UploadCount = 0;
  // What the textures were made from: the array, its time, the settings.
  vtkDataArray* Scalars = nullptr; // not referenced: only compared
  vtkMTimeType ScalarsTime = 0;
  std::string Key;
};

#endif
