// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
/**
 * @class   vtkWholeVolumeAssembler
 * @brief   the whole volume (or every Stride-th point of it) put together from its pieces by
 *          a maximum over the processes that hold them
 *
 * A volume drawn in pieces (ParaView's ranks) measures what depends on the whole volume, such
 * as the pre-integration table sizes, on the whole volume on every process, so that every
 * process, and one process drawing the volume alone, measures the same. Each process:
 *   1. calls Prepare() with its piece (or none), the whole extent and the stride
 *      (ComputeStride() gives the one every process derives alike): GetValues() then holds,
 *      for every point of the whole grid at that stride, the piece's value where the piece
 *      holds the point and the type's lowest value elsewhere, and GetCoverage() 1 where the
 *      piece holds the point (2 where its value is NaN, which GetValues() holds as the lowest
 *      value), 0 elsewhere;
 *   2. reduces both arrays with a maximum over the processes (vtkCommunicator::AllReduce with
 *      MAX_OP): pieces that share points hold the same values there;
 *   3. calls Finish() with the reduced arrays: the output is the whole volume at the stride,
 *      NaN restored, or an error when some point is held by no piece.
 * Every value is copied, never converted: at stride 1 the output's scalars equal the whole
 * volume's, bit for bit, and its geometry (extent, origin, spacing, direction) is the whole
 * volume's. At a stride s > 1 its extent is [0, n - 1] per axis, its spacing s times the
 * input's and its origin the whole extent's first point.
 *
 * Point scalars of one component only.
 */
#ifndef vtkWholeVolumeAssembler_h
#define vtkWholeVolumeAssembler_h

#include "hovrRenderingCoreModule.h" // For export macro
#include "vtkObject.h"

class vtkDataArray;
class vtkImageData;
class vtkUnsignedCharArray;

class HOVRRENDERINGCORE_EXPORT vtkWholeVolumeAssembler : public vtkObject
{
public:
  static vtkWholeVolumeAssembler* New();
  vtkTypeMacro(vtkWholeVolumeAssembler, vtkObject);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  /**
   * The smallest stride whose points of wholeExtent take at most maximumBytes at valueSize
   * bytes per value (at least 1).
   */
  static int ComputeStride(const int wholeExtent[6], int valueSize, double maximumBytes);

  /**
   * Fill GetValues() and GetCoverage() for the points of wholeExtent at stride that piece
   * holds (its point scalars, one component); piece and scalars may be null (a process
   * without data), dataType then gives the values' type (VTK_FLOAT, ...). The piece's
   * geometry must be the whole volume's (origin, spacing, direction). False, with an error,
   * for an empty whole extent, a stride below 1, scalars of several components or another
   * type than dataType, or not enough memory.
   */
  bool Prepare(vtkImageData* piece,
    vtkDataArray* scalars,
    int dataType,
    const int wholeExtent[6],
    int stride);

  /**
   * The piece's values and coverage on the whole grid at the stride (after Prepare()).
   */
  vtkDataArray* GetValues() { return this->Values; }
  vtkUnsignedCharArray* GetCoverage() { return this->Coverage; }

  /**
   * The whole volume at the stride into output from the values and coverage reduced over the
   * pieces (those of GetValues() and GetCoverage() on a single process), with piece's
   * geometry (any piece: an empty one of the same origin and spacing will do) and the
   * scalars named name. False, with an error, when some point is held by no piece.
   */
  bool Finish(vtkDataArray* values,
    vtkUnsignedCharArray* coverage,
    vtkImageData* piece,
    const char* name,
    vtkImageData* output);

protected:
  vtkWholeVolumeAssembler();
  ~vtkWholeVolumeAssembler() override;

  vtkDataArray* Values = nullptr;
  vtkUnsignedCharArray* Coverage;
  int WholeExtent[6] = { 0, -1, 0, -1, 0, -1 };
  int Stride = 1;

private:
  vtkWholeVolumeAssembler(const vtkWholeVolumeAssembler&) = delete;
  void operator=(const vtkWholeVolumeAssembler&) = delete;
};

#endif
