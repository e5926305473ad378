// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
/**
 * @class   vtkCubeFieldSource
 * @brief   base of the generated volumes that sample a field over [-1, 1]^3
 *
 * The grid spans [-1, 1]^3 with Dimensions points per axis (spacing 2 / (n - 1), origin -1);
 * the output holds the subclass's field as float point scalars named by GetFieldName().
 * Dimensions below 2 are an error and give an empty output, as are settings the subclass's
 * CheckFieldSettings() refuses; an impossible size is an error and an empty output, not an
 * allocation that overcommits. Any sub-extent can be requested (a piece of a parallel
 * pipeline computes only its own points, the same values as in the whole volume); the points
 * are computed in vtkSMPTools threads, one range of slices each.
 */
#ifndef vtkCubeFieldSource_h
#define vtkCubeFieldSource_h

#include "hovrFiltersSourcesModule.h" // For export macro
#include "vtkImageAlgorithm.h"

class HOVRFILTERSSOURCES_EXPORT vtkCubeFieldSource : public vtkImageAlgorithm
{
public:
  vtkTypeMacro(vtkCubeFieldSource, vtkImageAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /**
   * Points along each axis, at least 2. Initial value is 129 x 129 x 129.
   */
  vtkSetVector3Macro(Dimensions, int);
  vtkGetVector3Macro(Dimensions, int);
  ///@}

protected:
  vtkCubeFieldSource();
  ~vtkCubeFieldSource() override = default;

  /**
   * Name of the output's scalar array.
   */
  virtual const char* GetFieldName() = 0;

  /**
   * Whether the subclass's settings are valid; it reports what is not (vtkErrorMacro).
   */
  virtual bool CheckFieldSettings() { return true; }

  /**
   * The field at a point (x, y, z); called from several threads at once.
   */
  virtual double EvaluateField(const double point[3]) = 0;

  int RequestInformation(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  void ExecuteDataWithInformation(vtkDataObject* output, vtkInformation* outInfo) override;

  int Dimensions[3] = { 129, 129, 129 };

private:
  vtkCubeFieldSource(const vtkCubeFieldSource&) = delete;
  void operator=(const vtkCubeFieldSource&) = delete;
};

#endif
