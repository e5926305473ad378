// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
/**
 * @class   vtkBlobSource
 * @brief   a few small Gaussian blobs in empty space: a sparse test volume
 *
 * Point scalars f(p) = sum over blobs k of A_k exp(-|p - c_k|^2 / (2 (s sigma_k)^2)), s =
 * BlobScale, on the grid [-1, 1]^3 with Dimensions points per axis (spacing 2 / (n - 1),
 * origin -1); float scalars "Blobs". Most of the volume is empty (f below 1e-3 of the peak
 * outside a few widths of a blob), which is where adaptive sampling pays: the volume of the
 * sparse cases of presets/bench/adaptive.json. The six blobs are fixed so that images are
 * reproducible (centre c_k, width sigma_k, amplitude A_k):
 *   (-0.5, -0.4, -0.3), 0.08, 1.0;   (0.45, -0.35, 0.2), 0.06, 0.8;
 *   (0.1, 0.5, -0.45), 0.1, 0.9;     (-0.3, 0.35, 0.5), 0.05, 1.0;
 *   (0.5, 0.45, 0.55), 0.07, 0.7;    (0.0, 0.0, 0.0), 0.1, 0.6.
 * They are far apart compared with their widths, so the peaks keep their amplitudes (to
 * 1e-6). Dimensions below 2 or a BlobScale that is not a positive finite number are an error
 * with an empty output. Any sub-extent can be requested (a piece of a parallel pipeline
 * computes only its own points, the same values as in the whole volume).
 */
#ifndef vtkBlobSource_h
#define vtkBlobSource_h

#include "hovrFiltersSourcesModule.h" // For export macro
#include "vtkCubeFieldSource.h"

class HOVRFILTERSSOURCES_EXPORT vtkBlobSource : public vtkCubeFieldSource
{
public:
  static vtkBlobSource* New();
  vtkTypeMacro(vtkBlobSource, vtkCubeFieldSource);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /**
   * Factor s on every blob's width, positive and finite. Initial value is 1.
   */
  vtkSetMacro(BlobScale, double);
  vtkGetMacro(BlobScale, double);
  ///@}

  /**
   * The field at a point (x, y, z) for the given width factor.
   */
  static double Evaluate(const double point[3], double scale);

protected:
  vtkBlobSource() = default;
  ~vtkBlobSource() override = default;

  const char* GetFieldName() override { return "Blobs"; }
  bool CheckFieldSettings() override;
  double EvaluateField(const double point[3]) override;

  double BlobScale = 1.0;

private:
  vtkBlobSource(const vtkBlobSource&) = delete;
  void operator=(const vtkBlobSource&) = delete;
};

#endif
