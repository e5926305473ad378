// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
#include "vtkWholeVolumeAssembler.h"

#include "vtkDataArray.h"
#include "vtkImageData.h"
#include "vtkMatrix3x3.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkUnsignedCharArray.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <new>

vtkStandardNewMacro(vtkWholeVolumeAssembler);

namespace
{
// Points per axis of extent at stride.
void CountPoints(const int extent[6], int stride, int counts[3])
{
  for (int a = 0; a < 3; ++a)
  {
    counts[a] = (extent[2 * a + 1] - extent[2 * a]) / stride + 1;
  }
}

template <typename T>
bool IsNaN(T value)
{
  return value != value; // NOLINT: NaN alone differs from itself (integers never)
}

// The piece's values at the whole grid's points it holds; the lowest value and coverage 0
// elsewhere, the lowest value and coverage 2 at NaN.
template <typename T>
void Fill(const T* piece,
  const int pieceExtent[6],
  const int wholeExtent[6],
  int stride,
  T* values,
  unsigned char* coverage)
{
  int counts[3];
  CountPoints(wholeExtent, stride, counts);
  const vtkIdType total = static_cast<vtkIdType>(counts[0]) * counts[1] * counts[2];
  std::fill(values, values + total, std::numeric_limits<T>::lowest());
  std::fill(coverage, coverage + total, static_cast<unsigned char>(0));
  if (!piece)
  {
    return;
  }
  // Per axis, the whole grid's points (at the stride) inside the piece.
  int first[3], last[3];
  for (int a = 0; a < 3; ++a)
  {
    const int w0 = wholeExtent[2 * a];
    const int lo = std::max(pieceExtent[2 * a], w0), hi = pieceExtent[2 * a + 1];
    first[a] = (lo - w0 + stride - 1) / stride;
    last[a] = std::min((hi - w0) / stride, counts[a] - 1);
    if (hi < lo || last[a] < first[a])
    {
      return;
    }
  }
  const vtkIdType px = pieceExtent[1] - pieceExtent[0] + 1;
  const vtkIdType py = pieceExtent[3] - pieceExtent[2] + 1;
  for (int k = first[2]; k <= last[2]; ++k)
  {
    for (int j = first[1]; j <= last[1]; ++j)
    {
      for (int i = first[0]; i <= last[0]; ++i)
      {
        const vtkIdType x = wholeExtent[0] + static_cast<vtkIdType>(i) * stride - pieceExtent[0];
        const vtkIdType y = wholeExtent[2] + static_cast<vtkIdType>(j) * stride - pieceExtent[2];
        const vtkIdType z = wholeExtent[4] + static_cast<vtkIdType>(k) * stride - pieceExtent[4];
        const T value = piece[x + px * (y + py * z)];
        const vtkIdType w = i + static_cast<vtkIdType>(counts[0]) * (j + counts[1] * k);
        const bool nan = IsNaN(value);
        values[w] = nan ? std::numeric_limits<T>::lowest() : value;
        coverage[w] = nan ? 2 : 1;
      }
    }
  }
}

template <typename T>
void RestoreNaN(T* values, const unsigned char* coverage, vtkIdType total)
{
  if (std::numeric_limits<T>::has_quiet_NaN)
  {
    for (vtkIdType w = 0; w < total; ++w)
    {
      if (coverage[w] == 2)
      {
        values[w] = std::numeric_limits<T>::quiet_NaN();
      }
    }
  }
}
}

//------------------------------------------------------------------------------
vtkWholeVolumeAssembler::vtkWholeVolumeAssembler()
  : Coverage(vtkUnsignedCharArray::New())
{
}

//------------------------------------------------------------------------------
vtkWholeVolumeAssembler::~vtkWholeVolumeAssembler()
{
  if (this->Values)
  {
    this->Values->Delete();
  }
  this->Coverage->Delete();
}

//------------------------------------------------------------------------------
int vtkWholeVolumeAssembler::ComputeStride(const int wholeExtent[6],
  int valueSize,
  double maximumBytes)
{
  for (int stride = 1;; ++stride)
  {
    int counts[3];
    CountPoints(wholeExtent, stride, counts);
    const double bytes =
      static_cast<double>(counts[0]) * counts[1] * counts[2] * std::max(valueSize, 1);
    if (bytes <= maximumBytes || (counts[0] <= 1 && counts[1] <= 1 && counts[2] <= 1))
    {
      return stride;
    }
  }
}

//------------------------------------------------------------------------------
bool vtkWholeVolumeAssembler::Prepare(vtkImageData* piece,
  vtkDataArray* scalars,
  int dataType,
  const int wholeExtent[6],
  int stride)
{
  if (stride < 1 || wholeExtent[1] < wholeExtent[0] || wholeExtent[3] < wholeExtent[2] ||
    wholeExtent[5] < wholeExtent[4])
  {
    vtkErrorMacro("The whole volume needs a non-empty extent and a stride of at least 1.");
    return false;
  }
  if (scalars &&
    (scalars->GetNumberOfComponents() != 1 || scalars->GetDataType() != dataType || !piece ||
      scalars->GetNumberOfTuples() != piece->GetNumberOfPoints()))
  {
    vtkErrorMacro("The piece's scalars must be one point value of type "
      << dataType << " per point of the piece.");
    return false;
  }
  std::copy(wholeExtent, wholeExtent + 6, this->WholeExtent);
  this->Stride = stride;
  int counts[3];
  CountPoints(wholeExtent, stride, counts);
  const vtkIdType total = static_cast<vtkIdType>(counts[0]) * counts[1] * counts[2];
  if (this->Values)
  {
    this->Values->Delete();
  }
  this->Values = vtkDataArray::CreateDataArray(dataType);
  if (!this->Values)
  {
    vtkErrorMacro("No array of type " << dataType << ".");
    return false;
  }
  this->Values->SetNumberOfComponents(1);
  try
  {
    if (!this->Values->SetNumberOfValues(total) || !this->Coverage->SetNumberOfValues(total))
    {
      throw std::bad_alloc();
    }
  }
  catch (const std::bad_alloc&)
  {
    vtkErrorMacro("Not enough memory for the whole volume's " << total << " points.");
    this->Values->Initialize();
    this->Coverage->Initialize();
    return false;
  }
  const int* pieceExtent = piece ? piece->GetExtent() : wholeExtent;
  switch (dataType)
  {
    vtkTemplateMacro(
      Fill(scalars ? static_cast<const VTK_TT*>(scalars->GetVoidPointer(0)) : nullptr,
        pieceExtent,
        wholeExtent,
        stride,
        static_cast<VTK_TT*>(this->Values->GetVoidPointer(0)),
        this->Coverage->GetPointer(0)));
    default:
      vtkErrorMacro("Scalars of type " << dataType << " are not supported.");
      return false;
  }
  return true;
}

//------------------------------------------------------------------------------
bool vtkWholeVolumeAssembler::Finish(vtkDataArray* values,
  vtkUnsignedCharArray* coverage,
  vtkImageData* piece,
  const char* name,
  vtkImageData* output)
{
  int counts[3];
  CountPoints(this->WholeExtent, this->Stride, counts);
  const vtkIdType total = static_cast<vtkIdType>(counts[0]) * counts[1] * counts[2];
  if (!values || !coverage || !piece || !output || values->GetNumberOfTuples() != total ||
    coverage->GetNumberOfTuples() != total || values->GetNumberOfComponents() != 1)
  {
    vtkErrorMacro("Finish() needs the reduced values and coverage of Prepare()'s grid.");
    return false;
  }
  const unsigned char* held = coverage->GetPointer(0);
  for (vtkIdType w = 0; w < total; ++w)
  {
    if (held[w] == 0)
    {
      vtkErrorMacro("Point " << w << " of the whole volume is held by no piece.");
      return false;
    }
  }
  vtkDataArray* scalars = values->NewInstance();
  scalars->DeepCopy(values);
  scalars->SetName(name);
  switch (scalars->GetDataType())
  {
    vtkTemplateMacro(RestoreNaN(static_cast<VTK_TT*>(scalars->GetVoidPointer(0)), held, total));
  }
  output->Initialize();
  output->SetDirectionMatrix(piece->GetDirectionMatrix());
  if (this->Stride == 1)
  {
    output->SetExtent(this->WholeExtent);
    output->SetOrigin(piece->GetOrigin());
    output->SetSpacing(piece->GetSpacing());
  }
  else
  {
    double first[3];
    piece->TransformContinuousIndexToPhysicalPoint(
      this->WholeExtent[0], this->WholeExtent[2], this->WholeExtent[4], first);
    const double* spacing = piece->GetSpacing();
    output->SetExtent(0, counts[0] - 1, 0, counts[1] - 1, 0, counts[2] - 1);
    output->SetOrigin(first);
    output->SetSpacing(
      this->Stride * spacing[0], this->Stride * spacing[1], this->Stride * spacing[2]);
  }
  output->GetPointData()->SetScalars(scalars);
  scalars->Delete();
  return true;
}

//------------------------------------------------------------------------------
void vtkWholeVolumeAssembler::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "WholeExtent: " << this->WholeExtent[0] << " " << this->WholeExtent[1] << " "
     << this->WholeExtent[2] << " " << this->WholeExtent[3] << " " << this->WholeExtent[4] << " "
     << this->WholeExtent[5] << "\n";
  os << indent << "Stride: " << this->Stride << "\n";
}
