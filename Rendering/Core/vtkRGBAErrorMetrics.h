// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
/**
 * @class   vtkRGBAErrorMetrics
 * @brief   error of a rendered RGBA image against a reference: RMSE, maximum, difference image
 *
 * Input 0 is the image under test, input 1 the reference (connect it with
 * SetReferenceConnection or SetReferenceData). Both need the same dimensions and a 4-component
 * point array named ArrayName holding premultiplied RGBA. The output is the difference image:
 * its "Difference" array holds |test - reference| per channel (float, 4 components).
 *
 * After an update, GetRMSE() is the root mean square over all pixels and the 4 channels,
 * GetMaximumError() the largest absolute difference, and the per-channel variants the same for
 * one channel (0 = red ... 3 = alpha). Reference pixels holding NaN were not computed (a
 * reference integrated on a sample of the pixels, vtkVolumeReferenceIntegrator::PixelFraction):
 * they are left out of the metrics, and their difference is NaN. One implementation used by
 * the tests, the benchmark and the demo. Mismatched inputs give an error and metrics of -1.
 */
#ifndef vtkRGBAErrorMetrics_h
#define vtkRGBAErrorMetrics_h

#include "hovrRenderingCoreModule.h" // For export macro
#include "vtkImageAlgorithm.h"

class HOVRRENDERINGCORE_EXPORT vtkRGBAErrorMetrics : public vtkImageAlgorithm
{
public:
  static vtkRGBAErrorMetrics* New();
  vtkTypeMacro(vtkRGBAErrorMetrics, vtkImageAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /**
   * The reference image (input 1).
   */
  void SetReferenceConnection(vtkAlgorithmOutput* output) { this->SetInputConnection(1, output); }
  void SetReferenceData(vtkDataObject* image) { this->SetInputData(1, image); }
  ///@}

  ///@{
  /**
   * Name of the RGBA point array in both images. Initial value is "RGBA".
   */
  vtkSetStringMacro(ArrayName);
  vtkGetStringMacro(ArrayName);
  ///@}

  ///@{
  /**
   * Metrics of the last update; -1 when it failed.
   */
  vtkGetMacro(RMSE, double);
  vtkGetMacro(MaximumError, double);
  double GetChannelRMSE(int channel) const;
  double GetChannelMaximumError(int channel) const;
  ///@}

  /**
   * Pixels the last update measured: those whose reference holds no NaN.
   */
  vtkGetMacro(NumberOfMeasuredPixels, vtkIdType);

protected:
  vtkRGBAErrorMetrics();
  ~vtkRGBAErrorMetrics() override;

  int FillInputPortInformation(int port, vtkInformation* info) override;
  int RequestInformation(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  int RequestUpdateExtent(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  char* ArrayName = nullptr;
  double RMSE = -1.0;
  double MaximumError = -1.0;
  double ChannelRMSE[4] = { -1, -1, -1, -1 };
  double ChannelMaximumError[4] = { -1, -1, -1, -1 };
  vtkIdType NumberOfMeasuredPixels = 0;

private:
  vtkRGBAErrorMetrics(const vtkRGBAErrorMetrics&) = delete;
  void operator=(const vtkRGBAErrorMetrics&) = delete;
};

#endif
