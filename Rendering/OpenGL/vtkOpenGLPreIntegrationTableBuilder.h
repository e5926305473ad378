// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
/**
 * @class   vtkOpenGLPreIntegrationTableBuilder
 * @brief   builds a second-order pre-integration table on the GPU, into a 3D texture
 *
 * The GPU counterpart of vtkSecondOrderPreIntegrationTable's CPU build (El Hajjar, Marchesin,
 * Dischler and Mongenet 2008, section 6.2): each z slice of the N^3 table (back scalar k) is
 * one full-screen pass into that slice of the target texture, whose fragment (i, j)
 * integrates the slab (front i, middle j, back k). The fragment shader
 * (shaders/hovrPreIntegration2Build.glsl) repeats the CPU integration operation for operation
 * in 32-bit floats: midpoint steps along the quadratic of Eq. 2 by Horner's rule, each step's
 * colour and opacity interpolated linearly in the table's iteration table, front-to-back
 * compositing, entry (i, j, k) with i >= k integrated as the reversed path of (k, j, i).
 * Like the CPU it sets slabs whose scalar stays in one zero-opacity run to zero without
 * integrating (the test is exact here, in integers) and gives the diagonal (constant scalar)
 * the exact exponential, computed on the CPU. Both builds agree to float rounding (bit for
 * bit where OpenGL neither fuses multiply-adds nor rounds exp() otherwise than the C++
 * library). Unlike the paper it integrates front to back, skips empty slabs and renders into
 * the 3D texture directly instead of copying the framebuffer.
 *
 * Speed: it is meant for hardware GPUs. A software renderer such as Mesa's llvmpipe runs the
 * shader on the CPU without the CPU builder's sharing of lookups between (i, j, k) and
 * (k, j, i), so there the CPU build is faster.
 *
 * The table prepares the inputs without computing its entries on the CPU:
 * @code
 * table->SetComputeEntries(false);
 * table->Update();
 * builder->Build(renderWindow, table, texture, GL_RGBA16F);
 * @endcode
 * The builder holds no OpenGL resources between builds (the shader program is kept by the
 * window's shader cache), so it needs no ReleaseGraphicsResources. Build() restores the
 * framebuffer bindings, viewport, colour mask and the blend, depth, scissor, stencil and
 * face-culling switches it changes.
 */
#ifndef vtkOpenGLPreIntegrationTableBuilder_h
#define vtkOpenGLPreIntegrationTableBuilder_h

#include "hovrRenderingOpenGLModule.h" // For export macro
#include "vtkObject.h"

class vtkFloatArray;
class vtkOpenGLRenderWindow;
class vtkSecondOrderPreIntegrationTable;
class vtkTextureObject;

class HOVRRENDERINGOPENGL_EXPORT vtkOpenGLPreIntegrationTableBuilder : public vtkObject
{
public:
  static vtkOpenGLPreIntegrationTableBuilder* New();
  vtkTypeMacro(vtkOpenGLPreIntegrationTableBuilder, vtkObject);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  /**
   * Integrate the entries of table into target, an N^3 RGBA 3D texture (N = TableSize, entry
   * (i, j, k) at texel (i, j, k)) with internal format GL_RGBA8, GL_RGBA16F or GL_RGBA32F.
   * target is (re)created in context when its context, size or format differ, and left with
   * linear filtering and clamp-to-edge wrapping on S, T and R. The table must have been
   * Update()d since its last change (with ComputeEntries false to skip the CPU
   * integration); its iteration table, empty runs and transfer functions are used. Returns
   * false and reports an error on invalid input or OpenGL failure.
   */
  bool Build(vtkOpenGLRenderWindow* context,
    vtkSecondOrderPreIntegrationTable* table,
    vtkTextureObject* target,
    unsigned int internalFormat);

  /**
   * Wall time of the last successful Build() in seconds, from the first OpenGL call to the
   * completion of the GPU work (glFinish): input upload, texture allocation and all passes.
   * The first build in a context also compiles the shader. Initial value is 0.
   */
  vtkGetMacro(LastBuildTime, double);

  /**
   * Read a 3D RGBA texture back into table (4 float components, x fastest, then y, then z),
   * slice by slice through a framebuffer, e.g. to compare a GPU-built table with the CPU's
   * GetTable(). Returns false and reports an error when texture is not an allocated 3D
   * texture.
   */
  bool DownloadTable(vtkTextureObject* texture, vtkFloatArray* table);

protected:
  vtkOpenGLPreIntegrationTableBuilder();
  ~vtkOpenGLPreIntegrationTableBuilder() override;

  double LastBuildTime = 0.0;

private:
  vtkOpenGLPreIntegrationTableBuilder(const vtkOpenGLPreIntegrationTableBuilder&) = delete;
  void operator=(const vtkOpenGLPreIntegrationTableBuilder&) = delete;
};

#endif
