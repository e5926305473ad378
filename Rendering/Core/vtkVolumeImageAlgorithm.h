// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
/**
 * @class   vtkVolumeImageAlgorithm
 * @brief   base of hovr's CPU volume renderers: a volume in, a W x H RGBA image out
 *
 * What the CPU renderers share (vtkVolumeReferenceIntegrator, vtkObjectOrderRayCaster): the
 * volume property and its transfer functions (through vtkVolumeTransferFunctionSampler), the
 * camera and the pixel rays (vtkCameraRayModel), the output image size, and the checks of the
 * input. The output is a W x H x 1 image with point data "RGBA" (float, premultiplied colour,
 * alpha = 1 - transmittance), pixel (i, j) counted from left and bottom, over transparent
 * black; on an error it stays transparent.
 */
#ifndef vtkVolumeImageAlgorithm_h
#define vtkVolumeImageAlgorithm_h

#include "hovrRenderingCoreModule.h" // For export macro
#include "vtkImageAlgorithm.h"

#include <string> // For CheckVolume
#include <vector> // For ReadNormalArray

class vtkCamera;
class vtkCameraRayModel;
class vtkDataArray;
class vtkFloatArray;
class vtkVolumeProperty;
class vtkVolumeTransferFunctionSampler;

class HOVRRENDERINGCORE_EXPORT vtkVolumeImageAlgorithm : public vtkImageAlgorithm
{
public:
  vtkTypeMacro(vtkVolumeImageAlgorithm, vtkImageAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /**
   * Transfer functions and opacity unit distance (component 0). Initial value is nullptr.
   */
  virtual void SetVolumeProperty(vtkVolumeProperty*);
  vtkGetObjectMacro(VolumeProperty, vtkVolumeProperty);
  ///@}

  ///@{
  /**
   * The camera. Initial value is nullptr.
   */
  virtual void SetCamera(vtkCamera*);
  vtkCamera* GetCamera();
  ///@}

  ///@{
  /**
   * Output image size in pixels. Initial value is 256 x 256.
   */
  virtual void SetImageSize(int w, int h);
  virtual void SetImageSize(const int size[2]) { this->SetImageSize(size[0], size[1]); }
  int* GetImageSize() VTK_SIZEHINT(2);
  ///@}

  vtkMTimeType GetMTime() override;

  /**
   * Why scalars cannot be rendered as the point scalars of input, or an empty string when they
   * can: a missing input or array, several components, fewer than 2 points along an axis, a
   * tuple count other than the number of points, an origin, spacing or direction matrix that
   * is not finite or is singular, bounds beyond double range, scalars with no finite value,
   * with infinite values or with a range wider than the largest double. Every hovr renderer
   * checks its input with it before reading the scalars.
   */
  static std::string CheckVolume(vtkImageData* input, vtkDataArray* scalars);

  /**
   * The part of CheckVolume() about the grid alone: why input's origin, spacing, direction
   * matrix or bounds cannot be rendered, or an empty string.
   */
  static std::string CheckGeometry(vtkImageData* input);

  /**
   * For mappers, from GetBounds(): reports CheckGeometry()'s reason as an error of reporter,
   * once per modification time of input (kept in reported). VTK and ParaView may skip drawing
   * after a look at the bounds, so that the mapper never gets to say why.
   */
  static void ReportGeometry(vtkObject* reporter, vtkImageData* input, vtkMTimeType& reported);

  /**
   * For a piece of a volume (a rank's under MPI): the whole volume's box, wholeBounds' corners
   * (dataset coordinates, which hold the input's bounds; empty or non-finite bounds: the
   * input's own), and the points the input owns, ownedExtent (structured extent) within the
   * input's (an empty extent, a minimum above its maximum: all of them), in input's grid index
   * counted from its extent's first point. Pieces share their origin, spacing and direction, so
   * every piece finds the same box, shifted by its extent's first point.
   */
  static void ComputeWholeIndexBox(vtkImageData* input,
    const double wholeBounds[6],
    double lo[3],
    double hi[3]);
  static void ComputeOwnedIndexBox(vtkImageData* input,
    const int ownedExtent[6],
    int lo[3],
    int hi[3]);

protected:
  vtkVolumeImageAlgorithm();
  ~vtkVolumeImageAlgorithm() override;

  int FillInputPortInformation(int port, vtkInformation* info) override;
  int RequestInformation(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  int RequestUpdateExtent(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  /**
   * Size the output to the image size with a transparent "RGBA" array, and return that array.
   * With clear false its values are left uninitialized, for the caller to write every one.
   * extraFloats more floats per pixel are counted in the memory the image needs: an image that
   * would not fit in the machine's physical memory, or whose allocation fails, is an error
   * and an empty output (no points), and nullptr is returned.
   */
  vtkFloatArray* InitializeOutput(vtkImageData* output, bool clear = true, int extraFloats = 0);

  /**
   * The input's scalars to render, after checking them and preparing the sampler and the
   * rays: nullptr after an error (CheckVolume(), no volume property, bad transfer functions
   * or camera). dims gets the grid's point dimensions.
   */
  vtkDataArray* PrepareFrame(vtkImageData* input, vtkInformationVector** inputVector, int dims[3]);

  /**
   * Whether step (world units) is positive, at most the diagonal of input's bounds, and takes
   * at most maximumSamples samples along it; an error otherwise, rather than a frame of hours
   * or a volume stepped over.
   */
  bool CheckSampleDistance(vtkImageData* input, double step, double maximumSamples);

  /**
   * A warning when every pixel of rgba is transparent and this frame has warned of nothing
   * yet, so that an empty image never comes without a message.
   */
  void WarnIfTransparent(vtkFloatArray* rgba);

  /**
   * The point array name of input as n 3-component vectors, in double, into normals: false
   * and an error when it names no such array (the caller leaves the image empty).
   */
  bool ReadNormalArray(vtkImageData* input,
    const char* name,
    vtkIdType n,
    std::vector<double>& normals);

  // Whether this frame has warned already (PrepareFrame resets it).
  bool FrameWarned = false;

  vtkVolumeProperty* VolumeProperty = nullptr;
  vtkCameraRayModel* RayModel;
  vtkVolumeTransferFunctionSampler* Sampler;

private:
  vtkVolumeImageAlgorithm(const vtkVolumeImageAlgorithm&) = delete;
  void operator=(const vtkVolumeImageAlgorithm&) = delete;
};

#endif
