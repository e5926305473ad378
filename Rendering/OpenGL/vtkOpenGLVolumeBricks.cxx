// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
#include "vtkOpenGLVolumeBricks.h"

#include "vtkDataArray.h"
#include "vtkObjectFactory.h"
#include "vtkOpenGLRenderWindow.h"
#include "vtkTextureObject.h"
#include "vtkVolumeBrickLayout.h"
#include "vtk_glew.h"

#include <algorithm>
#include <cmath>
#include <new>
#include <sstream>

vtkStandardNewMacro(vtkOpenGLVolumeBricks);

namespace
{
// How one scalar type goes into a texture: texel = (value + offset) * factor in the texel type
// (a normalised integer) or, for Float, (value - shift) / scale in float.
struct Format
{
  int InternalFormat;
  int GLType;
  int Bytes;
  bool Float;
  double Offset;
  double Factor;
};

Format FormatOf(int type, int precision, int components)
{
  if (components == 3)
  {
    return Format{ GL_RGB32F, GL_FLOAT, 12, true, 0.0, 1.0 };
  }
  const bool signedChar =
    type == VTK_SIGNED_CHAR || (type == VTK_CHAR && static_cast<char>(-1) < 0);
  const bool unsignedChar = type == VTK_UNSIGNED_CHAR || (type == VTK_CHAR && !signedChar);
  if (precision == vtkOpenGLVolumeBricks::FLOAT32 || components != 1)
  {
    return Format{ GL_R32F, GL_FLOAT, 4, true, 0.0, 1.0 };
  }
  if (unsignedChar || signedChar)
  {
    const double offset = signedChar ? 128.0 : 0.0;
    return precision == vtkOpenGLVolumeBricks::WIDE
      ? Format{ GL_R16, GL_UNSIGNED_SHORT, 2, false, offset, 257.0 }
      : Format{ GL_R8, GL_UNSIGNED_BYTE, 1, false, offset, 1.0 };
  }
  if (type == VTK_UNSIGNED_SHORT)
  {
    return Format{ GL_R16, GL_UNSIGNED_SHORT, 2, false, 0.0, 1.0 };
  }
  if (type == VTK_SHORT)
  {
    return Format{ GL_R16, GL_UNSIGNED_SHORT, 2, false, 32768.0, 1.0 };
  }
  return Format{ GL_R32F, GL_FLOAT, 4, true, 0.0, 1.0 };
}

// One slice (points x0..x1, y0..y1 at z) of `components` components into texels of type Out.
template <typename Out>
void FillSlice(vtkDataArray* scalars,
  const int dims[3],
  const int points[6],
  int z,
  int components,
  const Format& format,
  double shift,
  double scale,
  std::vector<Out>& slice)
{
  const int w = points[1] - points[0] + 1, h = points[3] - points[2] + 1;
  slice.resize(static_cast<size_t>(w) * h * components);
  const vtkIdType row = dims[0], plane = static_cast<vtkIdType>(dims[0]) * dims[1];
  Out* out = slice.data();
  for (int y = points[2]; y <= points[3]; ++y)
  {
    const vtkIdType base = points[0] + row * y + plane * z;
    for (int x = 0; x < w; ++x)
    {
      for (int c = 0; c < components; ++c)
      {
        const double v = scalars->GetComponent(base + x, c);
        if (format.Float)
        {
          *out++ = static_cast<Out>((v - shift) / scale);
        }
        else
        {
          *out++ = static_cast<Out>(std::lround((v + format.Offset) * format.Factor));
        }
      }
    }
  }
}
}

//------------------------------------------------------------------------------
vtkOpenGLVolumeBricks::vtkOpenGLVolumeBricks() = default;

//------------------------------------------------------------------------------
vtkOpenGLVolumeBricks::~vtkOpenGLVolumeBricks() = default;

//------------------------------------------------------------------------------
vtkTextureObject* vtkOpenGLVolumeBricks::GetTexture(int brick) const
{
  return brick >= 0 && brick < this->GetNumberOfBricks() ? this->Textures[brick].Get() : nullptr;
}

//------------------------------------------------------------------------------
bool vtkOpenGLVolumeBricks::Update(vtkOpenGLRenderWindow* context,
  vtkDataArray* scalars,
  const int dims[3],
  std::string& why,
  vtkVolumeBrickLayout* shared)
{
  why.clear();
  const int type = scalars->GetDataType();
  const int components = scalars->GetNumberOfComponents() == 3 ? 3 : 1;
  const Format format = FormatOf(type, this->Precision, components);
  vtkVolumeBrickLayout* layout = shared ? shared : this->Layout.Get();
  std::ostringstream key;
  key << type << " " << components << " " << this->Precision << " " << this->Filtered << " "
      << dims[0] << " " << dims[1] << " " << dims[2] << " " << layout->GetGhostPoints() << " "
      << layout->GetMaximumBrickPoints() << " " << layout->GetMaximumBrickBytes() << " "
      << this->MinimumBytesPerPoint << " " << layout->GetNumberOfBricks() << " " << context;
  if (key.str() == this->Key && scalars == this->Scalars &&
    scalars->GetMTime() == this->ScalarsTime && !this->Textures.empty())
  {
    return true;
  }
  this->ReleaseGraphicsResources(context);
  if (!shared)
  {
    layout->SetDimensions(dims[0], dims[1], dims[2]);
    layout->SetBytesPerPoint(std::max(format.Bytes, this->MinimumBytesPerPoint));
    if (!layout->Update())
    {
      why = "the volume cannot be split into bricks within the texture limits";
      return false;
    }
  }

  // The raw -> data map of the format (the range only for rescaled types).
  double shift = 0.0, scale = 1.0;
  const bool exactInFloat = type == VTK_FLOAT || type == VTK_UNSIGNED_CHAR ||
    type == VTK_SIGNED_CHAR || type == VTK_CHAR || type == VTK_UNSIGNED_SHORT || type == VTK_SHORT;
  if (format.Float && !(exactInFloat || components == 3))
  {
    double range[2];
    scalars->GetFiniteRange(range, 0);
    shift = range[0];
    scale = range[1] > range[0] ? range[1] - range[0] : 1.0;
    this->Scale = scale;
    this->Shift = shift;
  }
  else if (format.Float)
  {
    this->Scale = 1.0;
    this->Shift = 0.0;
  }
  else
  {
    // Normalised texel t / (2^bits - 1) = (v + offset) * factor / (2^bits - 1).
    const double full = format.Bytes == 1 ? 255.0 : 65535.0;
    this->Scale = full / format.Factor;
    this->Shift = -format.Offset;
  }

  GLint alignment = 4;
  glGetIntegerv(GL_UNPACK_ALIGNMENT, &alignment);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  for (int n = 0; n < 16 && glGetError() != GL_NO_ERROR; ++n)
  {
  }
  std::vector<float> floats;
  std::vector<unsigned short> shorts;
  std::vector<unsigned char> bytes;
  for (int b = 0; b < layout->GetNumberOfBricks() && why.empty(); ++b)
  {
    int points[6], size[3];
    layout->GetBrickPoints(b, points);
    layout->GetBrickSize(b, size);
    vtkNew<vtkTextureObject> texture;
    texture->SetContext(context);
    texture->SetInternalFormat(format.InternalFormat);
    texture->SetFormat(components == 3 ? GL_RGB : GL_RED);
    texture->SetDataType(format.GLType);
    const int vtkType = format.Float ? VTK_FLOAT
      : format.Bytes == 1            ? VTK_UNSIGNED_CHAR
                                     : VTK_UNSIGNED_SHORT;
    bool ok = texture->Create3DFromRaw(size[0], size[1], size[2], components, vtkType, nullptr);
    GLenum error = glGetError();
    if (ok && error == GL_NO_ERROR)
    {
      texture->Activate();
      try
      {
        for (int z = points[4]; z <= points[5]; ++z)
        {
          const void* data = nullptr;
          if (format.Float)
          {
            FillSlice(scalars, dims, points, z, components, format, shift, scale, floats);
            data = floats.data();
          }
          else if (format.Bytes == 2)
          {
            FillSlice(scalars, dims, points, z, components, format, shift, scale, shorts);
            data = shorts.data();
          }
          else
          {
            FillSlice(scalars, dims, points, z, components, format, shift, scale, bytes);
            data = bytes.data();
          }
          glTexSubImage3D(GL_TEXTURE_3D,
            0,
            0,
            0,
            z - points[4],
            size[0],
            size[1],
            1,
            components == 3 ? GL_RGB : GL_RED,
            format.GLType,
            data);
        }
      }
      catch (const std::bad_alloc&)
      {
        ok = false;
      }
      texture->Deactivate();
      error = glGetError();
    }
    if (!ok || error != GL_NO_ERROR)
    {
      std::ostringstream message;
      message << "OpenGL could not create brick " << b << " (" << size[0] << " x " << size[1]
              << " x " << size[2] << ")";
      if (error == GL_OUT_OF_MEMORY)
      {
        message << ": out of memory";
      }
      why = message.str();
      break;
    }
    texture->SetWrapS(vtkTextureObject::ClampToEdge);
    texture->SetWrapT(vtkTextureObject::ClampToEdge);
    texture->SetWrapR(vtkTextureObject::ClampToEdge);
    const int filter = this->Filtered ? vtkTextureObject::Linear : vtkTextureObject::Nearest;
    texture->SetMinificationFilter(filter);
    texture->SetMagnificationFilter(filter);
    this->Textures.emplace_back(texture);
    this->MemorySize += static_cast<vtkIdType>(size[0]) * size[1] * size[2] * format.Bytes;
    ++this->UploadCount;
  }
  glPixelStorei(GL_UNPACK_ALIGNMENT, alignment);
  if (!why.empty())
  {
    this->ReleaseGraphicsResources(context);
    return false;
  }
  this->Key = key.str();
  this->Scalars = scalars;
  this->ScalarsTime = scalars->GetMTime();
  return true;
}

//------------------------------------------------------------------------------
void vtkOpenGLVolumeBricks::ReleaseGraphicsResources(vtkWindow* window)
{
  for (auto& texture : this->Textures)
  {
    texture->ReleaseGraphicsResources(window);
  }
  this->Textures.clear();
  this->MemorySize = 0;
  this->Scalars = nullptr;
  this->Key.clear();
}

//------------------------------------------------------------------------------
void vtkOpenGLVolumeBricks::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Precision: " << this->Precision << "\n";
  os << indent << "Filtered: " << this->Filtered << "\n";
  os << indent << "MinimumBytesPerPoint: " << this->MinimumBytesPerPoint << "\n";
  os << indent << "NumberOfBricks: " << this->GetNumberOfBricks() << "\n";
  os << indent << "MemorySize: " << this->MemorySize << "\n";
  os << indent << "UploadCount: " << this->UploadCount << "\n";
}
