// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
/**
 * @class   vtkMarschnerLobbSource
 * @brief   the Marschner-Lobb test signal sampled on a regular grid
 *
 * Marschner and Lobb (1994): on [-1, 1]^3,
 *   rho(x, y, z) = (1 - sin(pi z / 2) + alpha (1 + cos(2 pi f_M cos(pi r / 2)))) / (2 (1 + alpha)),
 * r = sqrt(x^2 + y^2), values in [0, 1]. A band-limited signal with much of its energy near
 * the Nyquist rate of the classic 41^3 sampling: the standard test of how a renderer
 * reconstructs and integrates. The grid spans [-1, 1]^3 with Dimensions points per axis
 * (spacing 2 / (n - 1), origin -1).
 *
 * The output scalar "MarschnerLobb" is float by default; with OutputScalarType set to
 * VTK_UNSIGNED_CHAR or VTK_UNSIGNED_SHORT the values are scaled to the full integer range and
 * rounded, to test integer data paths. Any sub-extent can be requested (a piece of a parallel
 * pipeline computes only its own points, the same values as in the whole volume).
 */
#ifndef vtkMarschnerLobbSource_h
#define vtkMarschnerLobbSource_h

#include "hovrFiltersSourcesModule.h" // For export macro
#include "vtkImageAlgorithm.h"

class HOVRFILTERSSOURCES_EXPORT vtkMarschnerLobbSource : public vtkImageAlgorithm
{
public:
  static vtkMarschnerLobbSource* New();
  vtkTypeMacro(vtkMarschnerLobbSource, vtkImageAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /**
   * Points along each axis, at least 2. Initial value is 41 x 41 x 41.
   */
  vtkSetVector3Macro(Dimensions, int);
  vtkGetVector3Macro(Dimensions, int);
  ///@}

  ///@{
  /**
   * Modulation frequency f_M. Initial value is 6.
   */
  vtkSetMacro(Frequency, double);
  vtkGetMacro(Frequency, double);
  ///@}

  ///@{
  /**
   * Modulation amplitude alpha. Initial value is 0.25.
   */
  vtkSetMacro(Alpha, double);
  vtkGetMacro(Alpha, double);
  ///@}

  ///@{
  /**
   * Scalar type of the output: VTK_FLOAT, VTK_DOUBLE, VTK_UNSIGNED_CHAR or
   * VTK_UNSIGNED_SHORT. Initial value is VTK_FLOAT.
   */
  vtkSetMacro(OutputScalarType, int);
  vtkGetMacro(OutputScalarType, int);
  ///@}

  /**
   * The signal itself at (x, y, z).
   */
  static double Evaluate(double x, double y, double z, double frequency, double alpha);

protected:
  vtkMarschnerLobbSource();
  ~vtkMarschnerLobbSource() override = default;

  int RequestInformation(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  void ExecuteDataWithInformation(vtkDataObject* output, vtkInformation* outInfo) override;

  int Dimensions[3] = { 41, 41, 41 };
  double Frequency = 6.0;
  double Alpha = 0.25;
  int OutputScalarType = VTK_FLOAT;

private:
  vtkMarschnerLobbSource(const vtkMarschnerLobbSource&) = delete;
  void operator=(const vtkMarschnerLobbSource&) = delete;
};

#endif
