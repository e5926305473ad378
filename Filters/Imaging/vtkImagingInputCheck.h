// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
/**
 * @class   vtkImagingInputCheck
 * @brief   the input checks hovr's image filters share: one point scalar per grid point
 *
 * Check() tells whether the array an image filter is to read (GetInputArrayToProcess, with its
 * association) is a 1-component point array of one value per point of a non-empty grid with
 * finite, non-zero spacing, and not the array the filter writes (outputName); otherwise it
 * returns false with the message for the filter's error, which names what the filter needs
 * the values for (purpose, e.g. "gradients need values at the grid's points") and what its
 * output would overwrite (product, e.g. "the normals").
 */
#ifndef vtkImagingInputCheck_h
#define vtkImagingInputCheck_h

#include "vtkDataArray.h"
#include "vtkDataObject.h"
#include "vtkImageData.h"

#include <cmath>
#include <cstring>
#include <sstream>
#include <string>

struct vtkImagingInputCheck
{
  static bool Check(vtkImageData* input,
    vtkDataArray* scalars,
    int association,
    const char* outputName,
    const char* purpose,
    const char* product,
    std::string& message)
  {
    std::ostringstream out;
    int dims[3];
    input->GetDimensions(dims);
    const vtkIdType points = input->GetNumberOfPoints();
    const char* name = scalars && scalars->GetName() ? scalars->GetName() : "";
    const double* spacing = input->GetSpacing();
    if (dims[0] < 1 || dims[1] < 1 || dims[2] < 1 || points == 0)
    {
      out << "The input image is empty (" << dims[0] << " x " << dims[1] << " x " << dims[2]
          << " points).";
    }
    else if (!scalars)
    {
      out << "The input has no point array to process (no point scalars, or the selected array "
             "does not exist).";
    }
    else if (association != vtkDataObject::FIELD_ASSOCIATION_POINTS)
    {
      out << "The array '" << name << "' is not a point array; " << purpose << ".";
    }
    else if (scalars->GetNumberOfComponents() != 1)
    {
      out << "The array '" << name << "' has " << scalars->GetNumberOfComponents()
          << " components; " << product << " take a single one.";
    }
    else if (scalars->GetNumberOfTuples() != points)
    {
      out << "The array '" << name << "' has " << scalars->GetNumberOfTuples() << " values for the "
          << points << " points of the grid.";
    }
    else if (std::strcmp(name, outputName) == 0)
    {
      out << "OutputArrayName '" << name << "' is the input array's name; " << product
          << " would replace the scalars they are computed from.";
    }
    else
    {
      for (int a = 0; a < 3; ++a)
      {
        if (!std::isfinite(spacing[a]) || spacing[a] == 0.0)
        {
          out << "The spacing (" << spacing[0] << ", " << spacing[1] << ", " << spacing[2]
              << ") must be finite and non-zero on every axis.";
          break;
        }
      }
    }
    message = out.str();
    return message.empty();
  }
};

#endif
