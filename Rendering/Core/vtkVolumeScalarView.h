// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
/**
 * @class   vtkVolumeScalarView
 * @brief   the values of a volume's scalar array as doubles, read in place
 *
 * The CPU integrators (the reference, the table sizer, the shader's twin, the adaptive
 * pyramid's core) read a volume's point values by index, in double. Copying a large volume to
 * double costs 8 bytes per point, twice the volume itself for float data and eight times for
 * 8-bit data, so the view reads the array's own memory and converts each value as it is read.
 * Arrays it cannot read in place (several components, a layout other than the standard one,
 * a type that is not a plain number) are copied to double once, and the copy is shared by
 * copies of the view.
 *
 * A lightweight value type, not a vtkObject: copies are cheap and share the array (which must
 * outlive them) or the copy.
 */
#ifndef vtkVolumeScalarView_h
#define vtkVolumeScalarView_h

#include "vtkDataArray.h"
#include "vtkType.h"

#include <algorithm> // For std::fill
#include <memory>    // For std::shared_ptr
#include <new>       // For std::bad_alloc
#include <vector>    // For std::vector

#ifndef __VTK_WRAP__
class vtkVolumeScalarView
{
public:
  /**
   * View component 0 of `array`: in place when the array has one component in standard
   * memory layout, else a double copy of that component. False (and an empty view) when the
   * copy does not fit in memory.
   */
  bool SetArray(vtkDataArray* array)
  {
    this->Copy.reset();
    this->Data = nullptr;
    this->Type = VTK_VOID;
    this->Count = 0;
    if (!array)
    {
      return true;
    }
    const vtkIdType n = array->GetNumberOfTuples();
    if (CanReadInPlace(array))
    {
      this->Data = array->GetVoidPointer(0);
      this->Type = array->GetDataType();
      this->Count = n;
      return true;
    }
    try
    {
      auto copy = std::make_shared<std::vector<double>>(static_cast<size_t>(n));
      for (vtkIdType i = 0; i < n; ++i)
      {
        (*copy)[i] = array->GetComponent(i, 0);
      }
      this->Copy = copy;
    }
    catch (const std::bad_alloc&)
    {
      return false;
    }
    this->Data = this->Copy->data();
    this->Type = VTK_DOUBLE;
    this->Count = n;
    return true;
  }

  /**
   * Whether SetArray views `array` in place (one component, standard memory layout, a plain
   * number type), not through a copy.
   */
  static bool CanReadInPlace(vtkDataArray* array)
  {
    return array && array->GetNumberOfComponents() == 1 && array->HasStandardMemoryLayout() &&
      IsReadInPlace(array->GetDataType());
  }

  /**
   * View n doubles in place (the caller keeps them alive).
   */
  void SetValues(const double* values, vtkIdType n)
  {
    this->Copy.reset();
    this->Data = values;
    this->Type = VTK_DOUBLE;
    this->Count = n;
  }

  vtkIdType GetNumberOfValues() const { return this->Count; }

  /**
   * Bytes this view holds beyond the array it reads (its double copy, if any).
   */
  vtkIdType GetCopySize() const
  {
    return this->Copy ? static_cast<vtkIdType>(this->Copy->size() * sizeof(double)) : 0;
  }

  double operator[](vtkIdType i) const
  {
    switch (this->Type)
    {
      case VTK_FLOAT:
        return static_cast<const float*>(this->Data)[i];
      case VTK_DOUBLE:
        return static_cast<const double*>(this->Data)[i];
      case VTK_UNSIGNED_CHAR:
        return static_cast<const unsigned char*>(this->Data)[i];
      case VTK_UNSIGNED_SHORT:
        return static_cast<const unsigned short*>(this->Data)[i];
      case VTK_SHORT:
        return static_cast<const short*>(this->Data)[i];
      case VTK_SIGNED_CHAR:
        return static_cast<const signed char*>(this->Data)[i];
      case VTK_CHAR:
        return static_cast<const char*>(this->Data)[i];
      case VTK_INT:
        return static_cast<const int*>(this->Data)[i];
      case VTK_UNSIGNED_INT:
        return static_cast<const unsigned int*>(this->Data)[i];
      default:
        return 0.0;
    }
  }

  /**
   * Call f(values) with the viewed values as a pointer to their own type (float, double,
   * unsigned char, ...; a copy is double), so that a loop over many of them converts each
   * without a type dispatch per value. Nothing is called on an empty view.
   */
  template <typename Functor>
  void Visit(Functor&& f) const
  {
    switch (this->Type)
    {
      case VTK_FLOAT:
        f(static_cast<const float*>(this->Data));
        break;
      case VTK_DOUBLE:
        f(static_cast<const double*>(this->Data));
        break;
      case VTK_UNSIGNED_CHAR:
        f(static_cast<const unsigned char*>(this->Data));
        break;
      case VTK_UNSIGNED_SHORT:
        f(static_cast<const unsigned short*>(this->Data));
        break;
      case VTK_SHORT:
        f(static_cast<const short*>(this->Data));
        break;
      case VTK_SIGNED_CHAR:
        f(static_cast<const signed char*>(this->Data));
        break;
      case VTK_CHAR:
        f(static_cast<const char*>(this->Data));
        break;
      case VTK_INT:
        f(static_cast<const int*>(this->Data));
        break;
      case VTK_UNSIGNED_INT:
        f(static_cast<const unsigned int*>(this->Data));
        break;
      default:
        break;
    }
  }

  /**
   * The 8 corners of the cell whose lowest point is `base` (x, then y at +sy, then z at +sz),
   * indexed i + 2 j + 4 k: one type dispatch for the 8 reads.
   */
  void GetCellCorners(vtkIdType base, vtkIdType sy, vtkIdType sz, double corner[8]) const
  {
    if (!this->Data)
    {
      std::fill(corner, corner + 8, 0.0);
      return;
    }
    this->Visit([&](const auto* values) { Gather(values + base, sy, sz, corner); });
  }

private:
  template <typename T>
  static void Gather(const T* v, vtkIdType sy, vtkIdType sz, double corner[8])
  {
    corner[0] = v[0];
    corner[1] = v[1];
    corner[2] = v[sy];
    corner[3] = v[sy + 1];
    corner[4] = v[sz];
    corner[5] = v[sz + 1];
    corner[6] = v[sz + sy];
    corner[7] = v[sz + sy + 1];
  }

  static bool IsReadInPlace(int type)
  {
    switch (type)
    {
      case VTK_FLOAT:
      case VTK_DOUBLE:
      case VTK_UNSIGNED_CHAR:
      case VTK_UNSIGNED_SHORT:
      case VTK_SHORT:
      case VTK_SIGNED_CHAR:
      case VTK_CHAR:
      case VTK_INT:
      case VTK_UNSIGNED_INT:
        return true;
      default:
        return false;
    }
  }

  const void* Data = nullptr;
  int Type = VTK_VOID;
  vtkIdType Count = 0;
  std::shared_ptr<std::vector<double>> Copy;
};

#endif // __VTK_WRAP__

#endif
