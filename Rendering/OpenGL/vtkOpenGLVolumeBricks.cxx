// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
#include "vtkOpenGLVolumeBricks.h"

#include "vtkDataArray.h"
#include "vtkObjectFactory.h"
#include "vtkOpenGLRenderWindow.h"
#include "vtkSMPTools.h"
#include "vtkShaderProgram.h"
#include "vtkSmartPointer.h"
#include "vtkTextureObject.h"
#include "vtkVolumeBrickLayout.h"
#include "vtkVolumeScalarView.h"
#include "vtk_glew.h"

#include <algorithm>
#include <cmath>
#include <memory>
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

// A value as a texel of the format: (v - shift) / scale in float, else the normalised integer
// (v + offset) * factor, rounded.
template <typename Out>
Out ToTexel(double v, const Format& format, double shift, double scale)
{
  return format.Float ? static_cast<Out>((v - shift) / scale)
                      : static_cast<Out>(std::lround((v + format.Offset) * format.Factor));
}

// One slice (points x0..x1, y0..y1 at z) of a single-component array's values (of type S)
// into texels of type Out.
template <typename Out, typename S>
void FillSlice(const S* values,
  const int dims[3],
  const int points[6],
  int z,
  const Format& format,
  double shift,
  double scale,
  Out* out)
{
  const int w = points[1] - points[0] + 1;
  const vtkIdType row = dims[0], plane = static_cast<vtkIdType>(dims[0]) * dims[1];
  const bool identity =
    format.Float ? shift == 0.0 && scale == 1.0 : format.Offset == 0.0 && format.Factor == 1.0;
  for (int y = points[2]; y <= points[3]; ++y)
  {
    const S* in = values + points[0] + row * y + plane * z;
    for (int x = 0; x < w; ++x)
    {
      *out++ = identity ? static_cast<Out>(in[x]) : ToTexel<Out>(in[x], format, shift, scale);
    }
  }
}

// The same for any array: `components` components of each point (3: all of them, else
// component 0), read one by one.
template <typename Out>
void FillSliceOf(vtkDataArray* scalars,
  const int dims[3],
  const int points[6],
  int z,
  int components,
  const Format& format,
  double shift,
  double scale,
  Out* out)
{
  const int w = points[1] - points[0] + 1;
  const vtkIdType row = dims[0], plane = static_cast<vtkIdType>(dims[0]) * dims[1];
  for (int y = points[2]; y <= points[3]; ++y)
  {
    const vtkIdType base = points[0] + row * y + plane * z;
    for (int x = 0; x < w; ++x)
    {
      for (int c = 0; c < components; ++c)
      {
        *out++ = ToTexel<Out>(scalars->GetComponent(base + x, c), format, shift, scale);
      }
    }
  }
}
}

//------------------------------------------------------------------------------
bool vtkOpenGLVolumeBricks::WriteSlices(vtkTextureObject* texture,
  const int offset[3],
  const int size[3],
  int components,
  int vtkType,
  const std::function<void(int, void*)>& fillSlice)
{
  const size_t sliceBytes =
    static_cast<size_t>(size[0]) * size[1] * components * vtkDataArray::GetDataTypeSize(vtkType);
  // A slab of a few MiB: each thread fills several slices, and no whole copy is kept.
  constexpr size_t slabBytes = 8u << 20;
  const int slab = static_cast<int>(
    std::min<size_t>(size[2], std::max<size_t>(1, slabBytes / std::max<size_t>(sliceBytes, 1))));
  std::unique_ptr<unsigned char[]> buffer;
  try
  {
    buffer.reset(new unsigned char[sliceBytes * slab]);
  }
  catch (const std::bad_alloc&)
  {
    return false;
  }
  const GLenum format = components == 1 ? GL_RED
    : components == 2                   ? GL_RG
    : components == 3                   ? GL_RGB
                                        : GL_RGBA;
  const GLenum type = vtkType == VTK_UNSIGNED_CHAR ? GL_UNSIGNED_BYTE
    : vtkType == VTK_UNSIGNED_SHORT                ? GL_UNSIGNED_SHORT
                                                   : GL_FLOAT;
  GLint alignment = 4;
  glGetIntegerv(GL_UNPACK_ALIGNMENT, &alignment);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  texture->Activate();
  for (int z0 = 0; z0 < size[2]; z0 += slab)
  {
    const int z1 = std::min(size[2], z0 + slab);
    vtkSMPTools::For(z0,
      z1,
      [&](vtkIdType begin, vtkIdType end)
      {
        for (vtkIdType z = begin; z < end; ++z)
        {
          fillSlice(static_cast<int>(z), buffer.get() + sliceBytes * (z - z0));
        }
      });
    glTexSubImage3D(GL_TEXTURE_3D,
      0,
      offset[0],
      offset[1],
      offset[2] + z0,
      size[0],
      size[1],
      z1 - z0,
      format,
      type,
      buffer.get());
  }
  texture->Deactivate();
  glPixelStorei(GL_UNPACK_ALIGNMENT, alignment);
  return true;
}

//------------------------------------------------------------------------------
bool vtkOpenGLVolumeBricks::HasTexture3D(vtkTextureObject* texture,
  vtkOpenGLRenderWindow* context,
  const int dims[3],
  int components,
  int vtkType)
{
  return texture && texture->GetHandle() != 0 && texture->GetContext() == context &&
    static_cast<int>(texture->GetWidth()) == dims[0] &&
    static_cast<int>(texture->GetHeight()) == dims[1] &&
    static_cast<int>(texture->GetDepth()) == dims[2] && texture->GetComponents() == components &&
    texture->GetVTKDataType() == vtkType;
}

//------------------------------------------------------------------------------
vtkOpenGLVolumeBricks::vtkOpenGLVolumeBricks() = default;

//------------------------------------------------------------------------------
vtkOpenGLVolumeBricks::~vtkOpenGLVolumeBricks() = default;

//------------------------------------------------------------------------------
vtkTextureObject* vtkOpenGLVolumeBricks::GetTexture(int brick) const
{
  if (brick < 0 || brick >= this->GetNumberOfBricks())
  {
    return nullptr;
  }
  if (!this->Atlas)
  {
    return this->Textures[brick].Get();
  }
  const int perPage = this->AtlasTiles[0] * this->AtlasTiles[1] * this->AtlasTiles[2];
  return this->Textures[std::min(brick / perPage, this->GetNumberOfTextures() - 1)].Get();
}

//------------------------------------------------------------------------------
std::vector<vtkTextureObject*> vtkOpenGLVolumeBricks::GetTexturesOf(int brick) const
{
  std::vector<vtkTextureObject*> textures;
  if (this->Atlas)
  {
    for (const auto& texture : this->Textures)
    {
      textures.push_back(texture.Get());
    }
  }
  else if (vtkTextureObject* texture = this->GetTexture(brick))
  {
    textures.push_back(texture);
  }
  return textures;
}

//------------------------------------------------------------------------------
void vtkOpenGLVolumeBricks::Activate(int brick)
{
  for (vtkTextureObject* texture : this->GetTexturesOf(brick))
  {
    texture->Activate();
  }
}

//------------------------------------------------------------------------------
void vtkOpenGLVolumeBricks::Deactivate(int brick)
{
  for (vtkTextureObject* texture : this->GetTexturesOf(brick))
  {
    texture->Deactivate();
  }
}

//------------------------------------------------------------------------------
void vtkOpenGLVolumeBricks::SetSamplerUniform(vtkShaderProgram* program,
  const char* name,
  int brick) const
{
  std::vector<int> units;
  for (vtkTextureObject* texture : this->GetTexturesOf(brick))
  {
    units.push_back(texture->GetTextureUnit());
  }
  if (!this->Atlas && units.size() == 1)
  {
    program->SetUniformi(name, units[0]);
  }
  else if (!units.empty())
  {
    program->SetUniform1iv(name, static_cast<int>(units.size()), units.data());
  }
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
  // An own layout follows from the settings in the key; it is updated below, so its brick
  // count here would be the last frame's and would make the second frame upload again. A
  // shared layout is already up to date: its bricks are in the key.
  std::ostringstream key;
  key << type << " " << components << " " << this->Precision << " " << this->Filtered << " "
      << dims[0] << " " << dims[1] << " " << dims[2] << " " << layout->GetGhostPoints() << " "
      << layout->GetMaximumBrickPoints() << " " << layout->GetMaximumBrickBytes() << " "
      << this->MinimumBytesPerPoint << " " << (shared ? shared->GetNumberOfBricks() : -1) << " "
      << this->Atlas << " " << context;
  if (key.str() == this->Key && scalars == this->Scalars &&
    scalars->GetMTime() == this->ScalarsTime && !this->Textures.empty())
  {
    return true;
  }
  // New values in the same layout and format (a time step) are written into the textures
  // already made.
  std::vector<vtkSmartPointer<vtkTextureObject>> previous;
  if (key.str() == this->Key)
  {
    previous.swap(this->Textures);
  }
  this->ReleaseGraphicsResources(context);
  if (!shared)
  {
    layout->SetDimensions(dims[0], dims[1], dims[2]);
    layout->SetBytesPerPoint(std::max(format.Bytes, this->MinimumBytesPerPoint));
    bool ok = layout->Update();
    // Atlas mode: a volume beyond one texture goes into bricks of at most a quarter of the
    // texture's bytes, so that they pack into pages with little left empty (bricks of over
    // half would take a page each).
    if (ok && this->Atlas && layout->GetNumberOfBricks() > 1)
    {
      const double pageBytes = layout->GetMaximumBrickBytes();
      layout->SetMaximumBrickBytes(pageBytes / 4.0);
      ok = layout->Update();
      layout->SetMaximumBrickBytes(pageBytes);
    }
    if (!ok)
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

  // Atlas mode: pages of tiles the size of the largest brick, planned for the layout's bytes
  // per point so that another array in the same layout gets the same pages.
  const int bricks = layout->GetNumberOfBricks();
  std::fill(this->AtlasTiles, this->AtlasTiles + 3, 1);
  if (this->Atlas &&
    !this->PlanAtlas(context, layout, std::max(format.Bytes, layout->GetBytesPerPoint()), why))
  {
    return false;
  }

  for (int n = 0; n < 16 && glGetError() != GL_NO_ERROR; ++n)
  {
  }
  const int vtkType = format.Float ? VTK_FLOAT
    : format.Bytes == 1            ? VTK_UNSIGNED_CHAR
                                   : VTK_UNSIGNED_SHORT;
  const int filter = this->Filtered ? vtkTextureObject::Linear : vtkTextureObject::Nearest;
  // Values read in place when they can be; others one by one (never a whole copy).
  vtkVolumeScalarView view;
  if (vtkVolumeScalarView::CanReadInPlace(scalars))
  {
    view.SetArray(scalars);
  }
  vtkSmartPointer<vtkTextureObject> texture;
  const int perPage = this->AtlasTiles[0] * this->AtlasTiles[1] * this->AtlasTiles[2];
  for (int b = 0; b < bricks && why.empty(); ++b)
  {
    int points[6], size[3];
    layout->GetBrickPoints(b, points);
    layout->GetBrickSize(b, size);
    int offset[3] = { 0, 0, 0 };
    const int* created = size;
    // Atlas mode: a page begins at every perPage-th brick.
    const bool first = !this->Atlas || b % perPage == 0;
    if (this->Atlas)
    {
      const int tile = b % perPage;
      offset[0] = this->AtlasTileSize[0] * (tile % this->AtlasTiles[0]);
      offset[1] = this->AtlasTileSize[1] * ((tile / this->AtlasTiles[0]) % this->AtlasTiles[1]);
      offset[2] = this->AtlasTileSize[2] * (tile / (this->AtlasTiles[0] * this->AtlasTiles[1]));
      created = this->AtlasSize;
    }
    bool ok = true;
    GLenum error = GL_NO_ERROR;
    if (first)
    {
      const size_t index = this->Textures.size();
      if (index < previous.size() &&
        HasTexture3D(previous[index], context, created, components, vtkType))
      {
        texture = previous[index];
        previous[index] = nullptr;
      }
      else
      {
        texture = vtkSmartPointer<vtkTextureObject>::New();
        texture->SetContext(context);
        texture->SetInternalFormat(format.InternalFormat);
        texture->SetFormat(components == 3 ? GL_RGB : GL_RED);
        texture->SetDataType(format.GLType);
        ok = texture->Create3DFromRaw(
          created[0], created[1], created[2], components, vtkType, nullptr);
        error = glGetError();
        ++this->CreateCount;
      }
    }
    if (ok && error == GL_NO_ERROR)
    {
      auto fill = [&](int z, void* out)
      {
        z += points[4];
        auto write = [&](auto* texels)
        {
          if (view.GetNumberOfValues() == 0)
          {
            FillSliceOf(scalars, dims, points, z, components, format, shift, scale, texels);
            return;
          }
          view.Visit([&](const auto* values)
            { FillSlice(values, dims, points, z, format, shift, scale, texels); });
        };
        if (format.Float)
        {
          write(static_cast<float*>(out));
        }
        else if (format.Bytes == 2)
        {
          write(static_cast<unsigned short*>(out));
        }
        else
        {
          write(static_cast<unsigned char*>(out));
        }
      };
      ok = WriteSlices(texture, offset, size, components, vtkType, fill);
      error = glGetError();
    }
    if (!ok || error != GL_NO_ERROR)
    {
      std::ostringstream message;
      message << "OpenGL could not create ";
      if (this->Atlas)
      {
        message << "texture " << b / perPage + 1 << " of " << this->AtlasPages << " (" << created[0]
                << " x " << created[1] << " x " << created[2] << ") of the volume's bricks";
      }
      else
      {
        message << "brick " << b << " (" << size[0] << " x " << size[1] << " x " << size[2] << ")";
      }
      if (error == GL_OUT_OF_MEMORY)
      {
        message << ": out of memory";
      }
      why = message.str();
      break;
    }
    if (first)
    {
      texture->SetWrapS(vtkTextureObject::ClampToEdge);
      texture->SetWrapT(vtkTextureObject::ClampToEdge);
      texture->SetWrapR(vtkTextureObject::ClampToEdge);
      texture->SetMinificationFilter(filter);
      texture->SetMagnificationFilter(filter);
      this->Textures.emplace_back(texture);
      this->MemorySize +=
        static_cast<vtkIdType>(created[0]) * created[1] * created[2] * format.Bytes;
    }
    ++this->UploadCount;
  }
  for (auto& unused : previous)
  {
    if (unused)
    {
      unused->ReleaseGraphicsResources(context);
    }
  }
  if (!why.empty())
  {
    this->ReleaseGraphicsResources(context);
    return false;
  }
  this->BrickCount = bricks;
  this->Key = key.str();
  this->Scalars = scalars;
  this->ScalarsTime = scalars->GetMTime();
  return true;
}

//------------------------------------------------------------------------------
bool vtkOpenGLVolumeBricks::PlanAtlas(vtkOpenGLRenderWindow* context,
  vtkVolumeBrickLayout* layout,
  int bytesPerTexel,
  std::string& why)
{
  const int bricks = layout->GetNumberOfBricks();
  layout->GetNumberOfPieces(this->AtlasPieces);
  layout->GetDimensions(this->AtlasDimensions);
  std::fill(this->AtlasTileSize, this->AtlasTileSize + 3, 1);
  for (int b = 0; b < bricks; ++b)
  {
    int size[3];
    layout->GetBrickSize(b, size);
    for (int a = 0; a < 3; ++a)
    {
      this->AtlasTileSize[a] = std::max(this->AtlasTileSize[a], size[a]);
    }
  }
  // The cuts along each axis: the first cell of every piece, then the cells.
  const int stride =
    std::max({ this->AtlasPieces[0], this->AtlasPieces[1], this->AtlasPieces[2] }) + 1;
  this->AtlasCuts.assign(3 * static_cast<size_t>(stride), 0);
  for (int a = 0; a < 3; ++a)
  {
    for (int p = 0; p < this->AtlasPieces[a]; ++p)
    {
      int index[3] = { 0, 0, 0 };
      index[a] = p;
      int cells[6];
      layout->GetBrickCells(
        index[0] + this->AtlasPieces[0] * (index[1] + this->AtlasPieces[1] * index[2]), cells);
      this->AtlasCuts[a * stride + p] = cells[2 * a];
      this->AtlasCuts[a * stride + p + 1] = cells[2 * a + 1];
    }
  }
  // The fewest pages, then the fewest tiles a page (then the smallest largest axis), that hold
  // the bricks within the GPU's largest 3D texture and the bytes a texture may take.
  const int largest = std::max(vtkTextureObject::GetMaximumTextureSize3D(context), 2);
  const double maximumBytes = layout->GetMaximumBrickBytes();
  const int limit[3] = { largest / this->AtlasTileSize[0],
    largest / this->AtlasTileSize[1],
    largest / this->AtlasTileSize[2] };
  const double tileBytes = static_cast<double>(this->AtlasTileSize[0]) * this->AtlasTileSize[1] *
    this->AtlasTileSize[2] * bytesPerTexel;
  long long best = -1;
  for (int pages = 1; pages <= std::min(MaximumAtlasPages, bricks) && best < 0; ++pages)
  {
    const int wanted = (bricks + pages - 1) / pages;
    long long bestAxis = 0;
    for (int t0 = 1; t0 <= std::min(limit[0], wanted); ++t0)
    {
      for (int t1 = 1; t1 <= std::min(limit[1], wanted); ++t1)
      {
        const int t2 = (wanted + t0 * t1 - 1) / (t0 * t1);
        const long long tiles = static_cast<long long>(t0) * t1 * t2;
        if (t2 > limit[2] || static_cast<double>(tiles) * tileBytes > maximumBytes)
        {
          continue;
        }
        const long long axis = std::max({ static_cast<long long>(t0) * this->AtlasTileSize[0],
          static_cast<long long>(t1) * this->AtlasTileSize[1],
          static_cast<long long>(t2) * this->AtlasTileSize[2] });
        if (best < 0 || tiles < best || (tiles == best && axis < bestAxis))
        {
          best = tiles;
          bestAxis = axis;
          this->AtlasTiles[0] = t0;
          this->AtlasTiles[1] = t1;
          this->AtlasTiles[2] = t2;
          this->AtlasPages = (bricks + static_cast<int>(tiles) - 1) / static_cast<int>(tiles);
        }
      }
    }
  }
  if (best < 0)
  {
    std::ostringstream message;
    message << "the volume's " << bricks << " bricks of up to " << this->AtlasTileSize[0] << " x "
            << this->AtlasTileSize[1] << " x " << this->AtlasTileSize[2] << " points ("
            << tileBytes / 1048576.0 << " MiB each) do not fit in " << MaximumAtlasPages
            << " 3D textures of at most " << largest << " points a side and "
            << maximumBytes / 1048576.0 << " MiB";
    why = message.str();
    return false;
  }
  for (int a = 0; a < 3; ++a)
  {
    this->AtlasSize[a] = this->AtlasTiles[a] * this->AtlasTileSize[a];
  }
  return true;
}

//------------------------------------------------------------------------------
std::string vtkOpenGLVolumeBricks::GetAtlasDefines() const
{
  const int cuts = this->AtlasCuts.empty() ? 2 : static_cast<int>(this->AtlasCuts.size() / 3);
  const int pages = this->Atlas ? std::max(this->GetNumberOfTextures(), 1) : 1;
  return "#define HOVR_ATLAS_CUTS " + std::to_string(cuts) + "\n#define HOVR_ATLAS_PAGES " +
    std::to_string(pages) + "\n";
}

//------------------------------------------------------------------------------
std::string vtkOpenGLVolumeBricks::GetAtlasSamplerCode(const std::string& name) const
{
  // GLSL indexes sampler arrays by constants only: one branch per page.
  const int pages = this->Atlas ? std::max(this->GetNumberOfTextures(), 1) : 1;
  std::ostringstream code;
  code << "uniform sampler3D " << name << "[" << pages << "];\n";
  const char* readers[2][3] = {
    { "vec4 ", "_texture(int page, vec3 coordinate)", "textureLod(%, coordinate, 0.0)" },
    { "vec4 ", "_texelFetch(int page, ivec3 texel)", "texelFetch(%, texel, 0)" }
  };
  for (const auto& reader : readers)
  {
    code << reader[0] << name << reader[1] << "\n{\n";
    for (int p = pages - 1; p >= 0; --p)
    {
      std::string call = reader[2];
      call.replace(call.find('%'), 1, name + "[" + std::to_string(p) + "]");
      code << (p > 0
          ? "  if (page == " + std::to_string(p) + ")\n  {\n    return " + call + ";\n  }\n"
          : "  return " + call + ";\n");
    }
    code << "}\n";
  }
  return code.str();
}

//------------------------------------------------------------------------------
void vtkOpenGLVolumeBricks::SetAtlasUniforms(vtkShaderProgram* program) const
{
  if (!this->AtlasCuts.empty())
  {
    program->SetUniform1iv(
      "hovr_atlasCuts", static_cast<int>(this->AtlasCuts.size()), this->AtlasCuts.data());
  }
  // Cells, pieces, tiles and the tile size, 3 each (hovrVolumeAtlas.glsl's hovr_atlasGrid).
  int grid[12];
  for (int a = 0; a < 3; ++a)
  {
    grid[a] = this->AtlasDimensions[a] - 1;
    grid[3 + a] = this->AtlasPieces[a];
    grid[6 + a] = this->AtlasTiles[a];
    grid[9 + a] = this->AtlasTileSize[a];
  }
  program->SetUniform1iv("hovr_atlasGrid", 12, grid);
  const float inverse[3] = {
    1.0f / this->AtlasSize[0], 1.0f / this->AtlasSize[1], 1.0f / this->AtlasSize[2]
  };
  program->SetUniform3f("hovr_atlasInvSize", inverse);
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
  os << indent << "Atlas: " << this->Atlas << "\n";
  os << indent << "AtlasPages: " << (this->Atlas ? this->GetNumberOfTextures() : 0) << "\n";
  os << indent << "MinimumBytesPerPoint: " << this->MinimumBytesPerPoint << "\n";
  os << indent << "NumberOfBricks: " << this->GetNumberOfBricks() << "\n";
  os << indent << "MemorySize: " << this->MemorySize << "\n";
  os << indent << "UploadCount: " << this->UploadCount << "\n";
  os << indent << "CreateCount: " << this->CreateCount << "\n";
}
