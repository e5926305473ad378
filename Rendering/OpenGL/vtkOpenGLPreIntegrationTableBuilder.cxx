// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
#include "vtkOpenGLPreIntegrationTableBuilder.h"

#include "vtkFloatArray.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkOpenGLFramebufferObject.h"
#include "vtkOpenGLQuadHelper.h"
#include "vtkOpenGLRenderWindow.h"
#include "vtkOpenGLShaderCache.h"
#include "vtkOpenGLState.h"
#include "vtkSecondOrderPreIntegrationTable.h"
#include "vtkShaderProgram.h"
#include "vtkTextureObject.h"
#include "vtkTimerLog.h"
#include "vtkVolumeTransferFunctionSampler.h"
#include "vtk_glew.h"

#include "hovrPreIntegration2Build.h" // the fragment shader of one table slice
#include "hovrSlabExtremum.h"         // the slab's extremum, shared with the ray caster

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

vtkStandardNewMacro(vtkOpenGLPreIntegrationTableBuilder);

namespace
{
// An RGBA32F (components 4) or R32F (components 1) texture holding count values for
// texelFetch, in rows of width texels (the iteration table can exceed the maximum width of a
// texture).
bool UploadRows(vtkOpenGLRenderWindow* context,
  vtkTextureObject* texture,
  const float* values,
  int count,
  int components,
  int width)
{
  const int rows = (count + width - 1) / width;
  std::vector<float> padded(static_cast<size_t>(width) * rows * components, 0.0f);
  std::copy(values, values + static_cast<size_t>(count) * components, padded.begin());
  texture->SetContext(context);
  texture->SetInternalFormat(components == 4 ? GL_RGBA32F : GL_R32F);
  texture->SetFormat(components == 4 ? GL_RGBA : GL_RED);
  texture->SetDataType(GL_FLOAT);
  // texelFetch ignores filtering, but a texture whose filter wants mipmaps is incomplete.
  texture->SetMinificationFilter(vtkTextureObject::Nearest);
  texture->SetMagnificationFilter(vtkTextureObject::Nearest);
  return texture->Create2DFromRaw(width, rows, components, VTK_FLOAT, padded.data());
}

// The smallest power of two >= count, at most the largest one <= maximum.
int RowShift(int count, int maximum)
{
  int shift = 0;
  while ((1 << shift) < count && (2 << shift) <= maximum)
  {
    ++shift;
  }
  return shift;
}
}

//------------------------------------------------------------------------------
vtkOpenGLPreIntegrationTableBuilder::vtkOpenGLPreIntegrationTableBuilder() = default;

//------------------------------------------------------------------------------
vtkOpenGLPreIntegrationTableBuilder::~vtkOpenGLPreIntegrationTableBuilder() = default;

//------------------------------------------------------------------------------
bool vtkOpenGLPreIntegrationTableBuilder::Build(vtkOpenGLRenderWindow* context,
  vtkSecondOrderPreIntegrationTable* table,
  vtkTextureObject* target,
  unsigned int internalFormat)
{
  if (!context || !table || !target)
  {
    vtkErrorMacro("Build needs a render window, a table and a target texture.");
    return false;
  }
  if (internalFormat != GL_RGBA8 && internalFormat != GL_RGBA16F && internalFormat != GL_RGBA32F)
  {
    // (vtkErrorMacro's stream takes no manipulators such as std::hex: the hex digits first.)
    char format[16];
    std::snprintf(format, sizeof(format), "0x%04X", internalFormat);
    vtkErrorMacro(
      "Unsupported internal format " << format << "; use GL_RGBA8, GL_RGBA16F or GL_RGBA32F.");
    return false;
  }
  const int nc = table->GetTableSize();
  const int nb = table->GetChordSize();
  const int nd = table->GetDeviationSize();
  const int fine = table->GetNumberOfIterationSamples();
  vtkFloatArray* steps = table->GetIterationTable();
  vtkFloatArray* runs = table->GetIterationEmptyRuns();
  if (table->GetBuildCount() == 0 || steps->GetNumberOfComponents() != 4 || fine < 2 ||
    steps->GetNumberOfTuples() != fine || runs->GetNumberOfTuples() != fine - 1 ||
    fine != table->GetIterationSamplesPerSpacing() * (nc - 1) + 1)
  {
    vtkErrorMacro("The table's iteration table does not match its size "
      << nc << "; call Update() on the table (with ComputeEntries off) before Build().");
    return false;
  }

  const double start = vtkTimerLog::GetUniversalTime();
  context->MakeCurrent();
  const int maxSize3D = vtkTextureObject::GetMaximumTextureSize3D(context);
  if (maxSize3D > 0 && std::max(nc, std::max(nb, nd)) > maxSize3D)
  {
    vtkErrorMacro("Table size " << nc << " x " << nb << " x " << nd
                                << " exceeds the OpenGL 3D texture limit " << maxSize3D << ".");
    return false;
  }

  // Inputs: the iteration table and its empty runs, from the CPU.
  const int rowShift = RowShift(fine, vtkTextureObject::GetMaximumTextureSize(context));
  vtkNew<vtkTextureObject> stepsTexture;
  vtkNew<vtkTextureObject> runsTexture;
  if (!UploadRows(context, stepsTexture, steps->GetPointer(0), fine, 4, 1 << rowShift) ||
    !UploadRows(context, runsTexture, runs->GetPointer(0), fine - 1, 1, 1 << rowShift))
  {
    vtkErrorMacro("Could not upload the iteration table.");
    return false;
  }

  // The target: a 3D texture of the table's sizes and the requested format, created only when
  // it differs.
  if (target->GetHandle() == 0 || target->GetContext() != context ||
    target->GetNumberOfDimensions() != 3 || target->GetWidth() != static_cast<unsigned int>(nc) ||
    target->GetHeight() != static_cast<unsigned int>(nb) ||
    target->GetDepth() != static_cast<unsigned int>(nd) ||
    target->GetInternalFormat(VTK_FLOAT, 4, false) != internalFormat)
  {
    target->ReleaseGraphicsResources(context);
    target->SetContext(context);
    target->SetInternalFormat(internalFormat);
    target->SetFormat(GL_RGBA);
    target->SetDataType(GL_FLOAT);
    if (!target->Allocate3D(nc, nb, nd, 4, VTK_FLOAT))
    {
      vtkErrorMacro(
        "Could not allocate the " << nc << " x " << nb << " x " << nd << " table texture.");
      return false;
    }
  }
  target->SetWrapS(vtkTextureObject::ClampToEdge);
  target->SetWrapT(vtkTextureObject::ClampToEdge);
  target->SetWrapR(vtkTextureObject::ClampToEdge);
  target->SetMinificationFilter(vtkTextureObject::Linear);
  target->SetMagnificationFilter(vtkTextureObject::Linear);

  // One full-screen pass per slice, straight into the slice; nothing blended or tested.
  vtkOpenGLState* state = context->GetState();
  vtkOpenGLState::ScopedglViewport savedViewport(state);
  vtkOpenGLState::ScopedglColorMask savedColorMask(state);
  vtkOpenGLState::ScopedglEnableDisable savedBlend(state, GL_BLEND);
  vtkOpenGLState::ScopedglEnableDisable savedDepthTest(state, GL_DEPTH_TEST);
  vtkOpenGLState::ScopedglEnableDisable savedScissorTest(state, GL_SCISSOR_TEST);
  vtkOpenGLState::ScopedglEnableDisable savedStencilTest(state, GL_STENCIL_TEST);
  vtkOpenGLState::ScopedglEnableDisable savedCullFace(state, GL_CULL_FACE);
  state->vtkglDisable(GL_BLEND);
  state->vtkglDisable(GL_DEPTH_TEST);
  state->vtkglDisable(GL_SCISSOR_TEST);
  state->vtkglDisable(GL_STENCIL_TEST);
  state->vtkglDisable(GL_CULL_FACE);
  state->vtkglColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  state->vtkglViewport(0, 0, nc, nb);

  std::string fragment = hovrPreIntegration2Build;
  vtkShaderProgram::Substitute(fragment, "//HOVR::SlabExtremum", hovrSlabExtremum);
  vtkOpenGLQuadHelper quad(context, nullptr, fragment.c_str(), nullptr);
  vtkShaderProgram* program = quad.Program;
  if (!program || !context->GetShaderCache()->ReadyShaderProgram(program))
  {
    vtkErrorMacro("Could not compile the table-building shader.");
    return false;
  }
  stepsTexture->Activate();
  runsTexture->Activate();
  const vtkSecondOrderPreIntegrationTableKernel kernel = table->GetKernel();
  program->SetUniformi("hovr_steps", stepsTexture->GetTextureUnit());
  program->SetUniformi("hovr_stepRuns", runsTexture->GetTextureUnit());
  program->SetUniformi("hovr_rowShift", rowShift);
  program->SetUniformi("hovr_centreSize", nc);
  program->SetUniformi("hovr_samplesPerSpacing", kernel.SamplesPerSpacing);
  program->SetUniformi("hovr_samples", kernel.Samples);
  program->SetUniformi("hovr_chordSize", kernel.ChordSize);
  program->SetUniformi("hovr_deviationSize", kernel.DeviationSize);
  program->SetUniformf("hovr_chordHalfStep", kernel.ChordHalfStep);
  program->SetUniformf("hovr_deviationHalfStep", kernel.DeviationHalfStep);
  program->SetUniformi("hovr_maximumSteps", kernel.MaximumSteps);
  program->SetUniformf("hovr_length", kernel.Length);

  state->PushFramebufferBindings();
  vtkNew<vtkOpenGLFramebufferObject> framebuffer;
  framebuffer->SetContext(context);
  framebuffer->Bind();
  bool complete = true;
  for (int k = 0; k < nd; ++k)
  {
    // AddColorAttachment ignores a new slice of the texture already attached.
    framebuffer->RemoveColorAttachment(0);
    framebuffer->AddColorAttachment(0, target, k);
    if (k == 0)
    {
      framebuffer->ActivateDrawBuffer(0);
      complete = framebuffer->CheckFrameBufferStatus(GL_DRAW_FRAMEBUFFER) != 0;
      if (!complete)
      {
        break;
      }
    }
    program->SetUniformi("hovr_deviation", k);
    quad.Render();
  }
  framebuffer->RemoveColorAttachment(0);
  state->PopFramebufferBindings();
  stepsTexture->Deactivate();
  runsTexture->Deactivate();
  if (!complete)
  {
    vtkErrorMacro("The table texture cannot be rendered into (incomplete framebuffer).");
    return false;
  }
  glFinish(); // LastBuildTime measures the GPU work, not its submission
  this->LastBuildTime = vtkTimerLog::GetUniversalTime() - start;
  return true;
}

//------------------------------------------------------------------------------
bool vtkOpenGLPreIntegrationTableBuilder::DownloadTable(vtkTextureObject* texture,
  vtkFloatArray* table)
{
  vtkOpenGLRenderWindow* context = texture ? texture->GetContext() : nullptr;
  if (!context || !table || texture->GetHandle() == 0 || texture->GetNumberOfDimensions() != 3)
  {
    vtkErrorMacro("DownloadTable needs an allocated 3D texture and an array.");
    return false;
  }
  const int width = static_cast<int>(texture->GetWidth());
  const int height = static_cast<int>(texture->GetHeight());
  const int depth = static_cast<int>(texture->GetDepth());
  const vtkIdType sliceValues = 4 * static_cast<vtkIdType>(width) * height;
  table->SetNumberOfComponents(4);
  table->SetNumberOfTuples(static_cast<vtkIdType>(width) * height * depth);
  context->MakeCurrent();
  vtkOpenGLState* state = context->GetState();
  state->PushReadFramebufferBinding();
  vtkNew<vtkOpenGLFramebufferObject> framebuffer;
  framebuffer->SetContext(context);
  framebuffer->Bind(GL_READ_FRAMEBUFFER);
  state->vtkglPixelStorei(GL_PACK_ALIGNMENT, 1);
  bool complete = true;
  for (int z = 0; z < depth; ++z)
  {
    framebuffer->RemoveColorAttachment(0);
    framebuffer->AddColorAttachment(0, texture, z);
    if (z == 0)
    {
      framebuffer->ActivateReadBuffer(0);
      complete = framebuffer->CheckFrameBufferStatus(GL_READ_FRAMEBUFFER) != 0;
      if (!complete)
      {
        break;
      }
    }
    glReadPixels(0, 0, width, height, GL_RGBA, GL_FLOAT, table->GetPointer(z * sliceValues));
  }
  framebuffer->RemoveColorAttachment(0);
  state->PopReadFramebufferBinding();
  if (!complete)
  {
    vtkErrorMacro("The texture cannot be read through a framebuffer.");
  }
  return complete;
}

//------------------------------------------------------------------------------
void vtkOpenGLPreIntegrationTableBuilder::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "LastBuildTime: " << this->LastBuildTime << "\n";
}
