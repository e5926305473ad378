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
 *     over (front, back) scalar for the sample distance (vtkFirstOrderPreIntegrationTable).
 *
 * The table is built on the CPU and uploaded only when the transfer functions, the opacity
 * unit distance, the sample distance or the scalar range change. Its size is chosen from the
 * data (one entry per integer value for 8-bit data) and the transfer function (enough entries
 * across its narrowest feature) unless TableSize is set.
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
    FIRST_ORDER = 1
  };

  ///@{
  /**
   * How samples are composited. Initial value is FIRST_ORDER.
   */
  virtual void SetIntegration(int mode);
  vtkGetMacro(Integration, int);
  void SetIntegrationToStock() { this->SetIntegration(STOCK); }
  void SetIntegrationToFirstOrder() { this->SetIntegration(FIRST_ORDER); }
  ///@}

  ///@{
  /**
   * Entries of the table along each scalar axis; 0 chooses from the data and the transfer
   * function: one entry per integer value of 8-bit data, otherwise 8 entries across the
   * narrowest transfer-function feature, at least 256 and at most 1024
   * (vtkPreIntegrationTable::SuggestTableSize). Values above the OpenGL texture
   * limit are clamped to it with a warning. Initial value is 0.
   */
  vtkSetClampMacro(TableSize, int, 0, 65536);
  vtkGetMacro(TableSize, int);
  ///@}

  ///@{
  /**
   * Store the table as 16-bit floats on the GPU (half the memory) instead of 32-bit floats.
   * Initial value is false.
   */
  vtkSetMacro(HalfFloatTable, bool);
  vtkGetMacro(HalfFloatTable, bool);
  vtkBooleanMacro(HalfFloatTable, bool);
  ///@}

  ///@{
  /**
   * Early ray termination: a ray stops once its opacity exceeds this value. The missed light
   * is at most 1 - threshold. Initial value is VTK's, 1 - 1/255.
   */
  vtkSetClampMacro(OpacityThreshold, double, 0.5, 1.0);
  vtkGetMacro(OpacityThreshold, double);
  ///@}

  /**
   * The first-order table (for statistics: GetBuildCount, GetLastBuildTime, GetMemorySize).
   */
  vtkFirstOrderPreIntegrationTable* GetFirstOrderTable() { return this->FirstOrderTable; }

  /**
   * Bytes of GPU memory held by the current table texture.
   */
  vtkGetMacro(TableTextureMemorySize, vtkIdType);

  /**
   * Affine map from the raw value VTK's volume texture returns for an array of this type to
   * the data value: value = raw * scale + shift. Depends on how vtkVolumeTexture uploads each
   * scalar type (normalised integer formats, or a float copy rescaled to the range).
   */
  static void GetTextureValueMapping(vtkDataArray* scalars, double& scale, double& shift);

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

  int Integration = FIRST_ORDER;
  int TableSize = 0;
  bool HalfFloatTable = false;
  double OpacityThreshold = 1.0 - 1.0 / 255.0;

  vtkFirstOrderPreIntegrationTable* FirstOrderTable;
  vtkTextureObject* TableTexture;
  vtkTextureObject* EmptyRunsTexture;
  int UploadedBuildCount = -1;
  bool UploadedHalfFloat = false;
  vtkIdType TableTextureMemorySize = 0;
  float RawToTable[2] = { 1.0f, 0.0f };
  std::string LastWarning;

private:
  vtkPreIntegrationVolumeMapper(const vtkPreIntegrationVolumeMapper&) = delete;
  void operator=(const vtkPreIntegrationVolumeMapper&) = delete;
};

#endif
