// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
#include "vtkAdaptiveSamplingPyramid.h"

#include "vtkOpenGLFramebufferObject.h"
#include "vtkOpenGLQuadHelper.h"
#include "vtkOpenGLRenderWindow.h"
#include "vtkOpenGLShaderCache.h"
#include "vtkOpenGLState.h"
#include "vtkOpenGLVolumeBricks.h"
#include "vtkShaderProgram.h"
#include "vtkTextureObject.h"
#include "vtk_glew.h"

#include "hovrAdaptivePyramidLevel.h"
#include "hovrVolumeAtlas.h"

#include <algorithm>
#include <array>
#include <limits>

namespace
{
vtkSmartPointer<vtkTextureObject> MakeTarget(vtkOpenGLRenderWindow* context, int w, int h)
{
  auto texture = vtkSmartPointer<vtkTextureObject>::New();
  texture->SetContext(context);
  texture->SetInternalFormat(GL_RGBA32F);
  texture->SetFormat(GL_RGBA);
  texture->SetDataType(GL_FLOAT);
  texture->SetMinificationFilter(vtkTextureObject::Nearest);
  texture->SetMagnificationFilter(vtkTextureObject::Nearest);
  texture->SetWrapS(vtkTextureObject::ClampToEdge);
  texture->SetWrapT(vtkTextureObject::ClampToEdge);
  texture->Allocate2D(w, h, 4, VTK_FLOAT);
  return texture;
}

// Binds fbo for drawing into its first `targets` attachments, the counters (attachment 1) only
// when counting. The draw buffers are set directly: vtkOpenGLState caches only the first one
// per binding.
void BindTargets(vtkOpenGLFramebufferObject* fbo, int targets, bool counting)
{
  fbo->Bind();
  const GLenum buffers[4] = { GL_COLOR_ATTACHMENT0,
    counting ? static_cast<GLenum>(GL_COLOR_ATTACHMENT1) : static_cast<GLenum>(GL_NONE),
    GL_COLOR_ATTACHMENT2,
    GL_COLOR_ATTACHMENT3 };
  glDrawBuffers(targets, buffers);
}

void SetUniform3d(vtkShaderProgram* program, const char* name, const double v[3])
{
  const int location = program->FindUniform(name);
  if (location >= 0)
  {
    glUniform3d(location, v[0], v[1], v[2]);
  }
}

void SetUniform3i(vtkShaderProgram* program, const char* name, const int v[3])
{
  const int location = program->FindUniform(name);
  if (location >= 0)
  {
    glUniform3i(location, v[0], v[1], v[2]);
  }
}
}

//------------------------------------------------------------------------------
vtkAdaptiveSamplingPyramid::vtkAdaptiveSamplingPyramid() = default;

//------------------------------------------------------------------------------
vtkAdaptiveSamplingPyramid::~vtkAdaptiveSamplingPyramid() = default;

//------------------------------------------------------------------------------
int vtkAdaptiveSamplingPyramid::SliceLevel(vtkIdType slice, int maximumLevel)
{
  if (slice == 0)
  {
    return maximumLevel;
  }
  int level = 0;
  while (level < maximumLevel && (slice & (vtkIdType(1) << level)) == 0)
  {
    ++level;
  }
  return level;
}

//------------------------------------------------------------------------------
void vtkAdaptiveSamplingPyramid::ReleaseGraphicsResources(vtkWindow* window)
{
  for (Level& level : this->Levels)
  {
    for (int c = 0; c < 2; ++c)
    {
      for (vtkTextureObject* texture : { level.State[c].Get(),
             level.Counts[c].Get(),
             level.Previous[c].Get(),
             level.Colour[c].Get() })
      {
        if (texture)
        {
          texture->ReleaseGraphicsResources(window);
        }
      }
      if (level.Targets[c])
      {
        level.Targets[c]->ReleaseGraphicsResources(window);
      }
    }
  }
  this->Levels.clear();
  if (this->Pass)
  {
    this->Pass->ReleaseGraphicsResources(window);
    this->Pass.reset();
  }
  this->Context = nullptr;
}

//------------------------------------------------------------------------------
bool vtkAdaptiveSamplingPyramid::Prepare(vtkOpenGLRenderWindow* context,
  int levels,
  int width,
  int height,
  const std::string& atlasDefines)
{
  if (context != this->Context)
  {
    this->ReleaseGraphicsResources(this->Context);
    this->Context = context;
  }
  if (static_cast<int>(this->Levels.size()) != levels + 1 || this->Levels[0].Width != width ||
    this->Levels[0].Height != height)
  {
    std::unique_ptr<vtkOpenGLQuadHelper> pass = std::move(this->Pass);
    this->ReleaseGraphicsResources(context);
    this->Pass = std::move(pass);
    this->Context = context;
    this->Levels.assign(static_cast<size_t>(levels + 1), Level());
    for (int l = 0; l <= levels; ++l)
    {
      Level& level = this->Levels[l];
      level.Width = width >> l;
      level.Height = height >> l;
      for (int c = 0; c < 2; ++c)
      {
        level.State[c] = MakeTarget(context, level.Width, level.Height);
        level.Counts[c] = MakeTarget(context, level.Width, level.Height);
        if (l == 0)
        {
          level.Previous[c] = MakeTarget(context, level.Width, level.Height);
          level.Colour[c] = MakeTarget(context, level.Width, level.Height);
        }
        level.Targets[c] = vtkSmartPointer<vtkOpenGLFramebufferObject>::New();
        level.Targets[c]->SetContext(context);
        vtkOpenGLFramebufferObject* fbo = level.Targets[c];
        context->GetState()->PushFramebufferBindings();
        fbo->Bind();
        fbo->AddColorAttachment(0, level.State[c]);
        fbo->AddColorAttachment(1, level.Counts[c]);
        if (l == 0)
        {
          fbo->AddColorAttachment(2, level.Previous[c]);
          fbo->AddColorAttachment(3, level.Colour[c]);
        }
        context->GetState()->PopFramebufferBindings();
      }
    }
  }
  if (this->Pass && atlasDefines != this->PassDefines)
  {
    this->Pass->ReleaseGraphicsResources(context);
    this->Pass.reset();
  }
  if (!this->Pass)
  {
    std::string fragment = hovrAdaptivePyramidLevel;
    vtkShaderProgram::Substitute(fragment, "//HOVR::Atlas", atlasDefines + hovrVolumeAtlas);
    this->Pass.reset(new vtkOpenGLQuadHelper(context, nullptr, fragment.c_str(), ""));
    this->PassDefines = atlasDefines;
  }
  if (!this->Pass->Program)
  {
    this->Pass.reset();
    return false;
  }
  return true;
}

//------------------------------------------------------------------------------
void vtkAdaptiveSamplingPyramid::Clear()
{
  // Every level transparent: s NaN, d 1, counters 0; level 0 without a previous slice
  // (i_prev = -1). Both sets: passes limited to rectangles leave the pixels outside as they
  // are.
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float state[4] = { nan, 1.0f, 0.0f, 0.0f };
  const float zero[4] = { 0.0f, 0.0f, 0.0f, 0.0f };
  const float previous[4] = { nan, -1.0f, 0.0f, 0.0f };
  for (size_t l = 0; l < this->Levels.size(); ++l)
  {
    Level& level = this->Levels[l];
    level.Current = 0;
    for (int c = 0; c < 2; ++c)
    {
      BindTargets(level.Targets[c], l == 0 ? 4 : 2, true);
      glClearBufferfv(GL_COLOR, 0, state);
      glClearBufferfv(GL_COLOR, 1, zero);
      if (l == 0)
      {
        glClearBufferfv(GL_COLOR, 2, previous);
        glClearBufferfv(GL_COLOR, 3, zero);
      }
    }
  }
}

//------------------------------------------------------------------------------
vtkIdType vtkAdaptiveSamplingPyramid::Draw(const Frame& frame)
{
  vtkOpenGLState* state = this->Context->GetState();
  vtkOpenGLState::ScopedglViewport viewportSaver(state);
  vtkOpenGLState::ScopedglScissor scissorSaver(state);
  vtkOpenGLState::ScopedglEnableDisable blend(state, GL_BLEND);
  vtkOpenGLState::ScopedglEnableDisable depth(state, GL_DEPTH_TEST);
  vtkOpenGLState::ScopedglEnableDisable scissor(state, GL_SCISSOR_TEST);
  vtkOpenGLState::ScopedglColorMask colourMask(state);
  state->vtkglDisable(GL_BLEND);
  state->vtkglDisable(GL_DEPTH_TEST);
  state->vtkglDisable(GL_SCISSOR_TEST);
  state->vtkglColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  this->Clear();

  // Without counting, each level's pass covers only the pixels that can matter: on level 0
  // the caller's rectangle; on level l + 1 every pixel that level l's synthesis reads (fine
  // pixel X reads coarse X / 2 - 1 .. X / 2 + 1, clamped to the edge). Inside, every pixel
  // computes what the full pass computes.
  const int lmax = frame.MaximumLevel;
  std::vector<std::array<int, 4>> rectangles(static_cast<size_t>(lmax + 1));
  for (int a = 0; a < 4; ++a)
  {
    rectangles[0][a] = frame.Rectangle[a];
  }
  for (int l = 1; l <= lmax; ++l)
  {
    const int size[2] = { this->Levels[l].Width, this->Levels[l].Height };
    for (int a = 0; a < 2; ++a)
    {
      rectangles[l][a] = std::max(rectangles[l - 1][a] / 2 - 1, 0);
      rectangles[l][a + 2] = std::min(rectangles[l - 1][a + 2] / 2 + 1, size[a] - 1);
    }
  }
  const bool counting = frame.Count;
  if (!counting)
  {
    state->vtkglEnable(GL_SCISSOR_TEST);
  }

  vtkShaderProgram* program = this->Pass->Program;
  this->Context->GetShaderCache()->ReadyShaderProgram(program);
  program->SetUniformi("maxLevel", lmax);
  program->SetUniformi("lastSlice", static_cast<int>(frame.LastSlice));
  program->SetUniformi("segmentTables", 1 << lmax);
  program->SetUniformi("tableSize", frame.TableSize);
  program->SetUniformi("minimumOracle", frame.MinimumOracle ? 1 : 0);
  program->SetUniformi("earlyTermination", frame.EarlyTermination ? 1 : 0);
  program->SetUniformi("countOperations", counting ? 1 : 0);
  program->SetUniformf("invalidValue", std::numeric_limits<float>::quiet_NaN());
  program->SetUniformf("opacityThreshold", 1.0f - 1.0f / 255.0f);
  const float imageSize[2] = { static_cast<float>(frame.Width), static_cast<float>(frame.Height) };
  program->SetUniform2f("imageSize", imageSize);
  SetUniform3d(program, "rayOrigin", frame.RayOrigin);
  SetUniform3d(program, "rayAxisX", frame.RayAxisX);
  SetUniform3d(program, "rayAxisY", frame.RayAxisY);
  SetUniform3d(program, "sliceStep", frame.SliceStep);
  SetUniform3d(program, "boxMax", frame.BoxMax);
  SetUniform3d(program, "wholeMin", frame.WholeMin);
  SetUniform3d(program, "wholeMax", frame.WholeMax);
  program->SetUniformi("piece", frame.Piece ? 1 : 0);
  SetUniform3d(program, "structuredOrigin", frame.StructuredOrigin);
  SetUniform3d(program, "structuredAxisX", frame.StructuredAxisX);
  SetUniform3d(program, "structuredAxisY", frame.StructuredAxisY);
  SetUniform3d(program, "structuredStep", frame.StructuredStep);
  SetUniform3d(program, "ownedLo", frame.OwnedLo);
  SetUniform3d(program, "ownedHi", frame.OwnedHi);
  SetUniform3i(program, "sharedLo", frame.SharedLo);
  SetUniform3i(program, "sharedHi", frame.SharedHi);
  SetUniform3d(program, "axisLength", frame.AxisLength);
  const int spacingLocation = program->FindUniform("sliceSpacing");
  if (spacingLocation >= 0)
  {
    glUniform1d(spacingLocation, frame.SliceSpacing);
  }
  frame.Volume->Activate(0);
  frame.Oracle->Activate(0);
  frame.Tables->Activate();
  frame.Volume->SetSamplerUniform(program, "volumeIndex", 0);
  frame.Oracle->SetSamplerUniform(program, "oracleWorld", 0);
  program->SetUniformi("tables", frame.Tables->GetTextureUnit());
  frame.Volume->SetAtlasUniforms(program);
  const float rawToIndex[2] = { static_cast<float>(frame.RawToIndex[0]),
    static_cast<float>(frame.RawToIndex[1]) };
  program->SetUniform2f("rawToIndex", rawToIndex);

  // PROJECTSLICE for every slice (Fig. 7), levels l_slice down to 0.
  vtkIdType passes = 0;
  for (vtkIdType slice = frame.FirstSlice; slice <= frame.LastSlice; ++slice)
  {
    const int lslice = SliceLevel(slice, lmax);
    program->SetUniformi("slice", static_cast<int>(slice));
    program->SetUniformi("sliceLevel", lslice);
    for (int l = lslice; l >= 0; --l)
    {
      Level& level = this->Levels[l];
      const int read = level.Current, write = 1 - read;
      vtkTextureObject* coarse =
        l < lmax ? this->Levels[l + 1].State[this->Levels[l + 1].Current].Get() : nullptr;
      vtkTextureObject* fine =
        l > 0 ? this->Levels[l - 1].State[this->Levels[l - 1].Current].Get() : nullptr;
      vtkTextureObject* active[6] = { level.State[read],
        level.Counts[read],
        level.Previous[read],
        level.Colour[read],
        coarse,
        fine };
      for (vtkTextureObject* texture : active)
      {
        if (texture)
        {
          texture->Activate();
        }
      }
      // Samplers a level does not read point at its own state (one unit per sampler type).
      const int own = level.State[read]->GetTextureUnit();
      program->SetUniformi("level", l);
      program->SetUniformi("stateIn", own);
      program->SetUniformi("countsIn", level.Counts[read]->GetTextureUnit());
      program->SetUniformi("previousIn", l == 0 ? level.Previous[read]->GetTextureUnit() : own);
      program->SetUniformi("colourIn", l == 0 ? level.Colour[read]->GetTextureUnit() : own);
      program->SetUniformi("coarseState", coarse ? coarse->GetTextureUnit() : own);
      program->SetUniformi("fineState", fine ? fine->GetTextureUnit() : own);
      BindTargets(level.Targets[write], l == 0 ? 4 : 2, counting);
      state->vtkglViewport(0, 0, level.Width, level.Height);
      if (!counting)
      {
        const std::array<int, 4>& r = rectangles[l];
        state->vtkglScissor(r[0], r[1], r[2] - r[0] + 1, r[3] - r[1] + 1);
      }
      this->Pass->Render();
      for (vtkTextureObject* texture : active)
      {
        if (texture)
        {
          texture->Deactivate();
        }
      }
      level.Current = write;
      ++passes;
    }
  }
  frame.Volume->Deactivate(0);
  frame.Oracle->Deactivate(0);
  frame.Tables->Deactivate();
  return passes;
}

//------------------------------------------------------------------------------
void vtkAdaptiveSamplingPyramid::ReadCounts(vtkIdType totals[4])
{
  // Per pixel the counters are integers below 2^24, exact in float32; summed in double.
  double sums[4] = { 0, 0, 0, 0 };
  for (Level& level : this->Levels)
  {
    std::vector<float> counts(static_cast<size_t>(level.Width) * level.Height * 4);
    level.Targets[level.Current]->Bind(GL_READ_FRAMEBUFFER);
    glReadBuffer(GL_COLOR_ATTACHMENT1);
    glPixelStorei(GL_PACK_ALIGNMENT, 4);
    glReadPixels(0, 0, level.Width, level.Height, GL_RGBA, GL_FLOAT, counts.data());
    for (size_t p = 0; p < counts.size(); p += 4)
    {
      sums[0] += counts[p];
      sums[1] += counts[p + 1];
      sums[2] += counts[p + 2];
      sums[3] += counts[p + 3];
    }
  }
  for (int c = 0; c < 4; ++c)
  {
    totals[c] = static_cast<vtkIdType>(sums[c]);
  }
}

//------------------------------------------------------------------------------
vtkTextureObject* vtkAdaptiveSamplingPyramid::GetImage()
{
  return this->Levels.empty() ? nullptr : this->Levels[0].Colour[this->Levels[0].Current].Get();
}
