// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
#include "vtkAnalyticVolumeMapper.h"

#include "vtkContourValues.h"
#include "vtkDataArray.h"
#include "vtkImageData.h"
#include "vtkObjectFactory.h"
#include "vtkOpenGLRenderWindow.h"
#include "vtkRenderer.h"
#include "vtkShaderProgram.h"
#include "vtkVolume.h"
#include "vtkVolumeProperty.h"
#include "vtk_glew.h"

#include "hovrAnalytic.h"       // the GLSL of the analytic ray caster
#include "hovrAnalyticCommon.h" // the GLSL both modes share

#include <cmath>
#include <sstream>

vtkStandardNewMacro(vtkAnalyticVolumeMapper);

namespace
{
bool IsAnalyticBlend(int blend)
{
  return blend == vtkVolumeMapper::ISOSURFACE_BLEND ||
    blend == vtkVolumeMapper::MAXIMUM_INTENSITY_BLEND ||
    blend == vtkVolumeMapper::MINIMUM_INTENSITY_BLEND;
}
}

//------------------------------------------------------------------------------
vtkAnalyticVolumeMapper::vtkAnalyticVolumeMapper() = default;

//------------------------------------------------------------------------------
vtkAnalyticVolumeMapper::~vtkAnalyticVolumeMapper() = default;

//------------------------------------------------------------------------------
const char* vtkAnalyticVolumeMapper::GetStockFallbackReason(vtkVolume* vol,
  vtkDataArray* scalars,
  int cellFlag)
{
  vtkVolumeProperty* property = vol->GetProperty();
  if (scalars->GetNumberOfComponents() != 1)
  {
    return "analytic rendering needs single-component scalars";
  }
  if (cellFlag)
  {
    return "analytic rendering interpolates point scalars; these are cell scalars";
  }
  if (this->GetCropping())
  {
    return "analytic rendering does not support cropping";
  }
  if (property->GetTransferFunctionMode() != vtkVolumeProperty::TF_1D)
  {
    return "analytic rendering does not support 2D transfer functions";
  }
  return nullptr;
}

//------------------------------------------------------------------------------
vtkExtensibleGPUVolumeRayCastMapper::FramePlan vtkAnalyticVolumeMapper::PrepareExtension(
  vtkRenderer* ren,
  vtkVolume* vol)
{
  if (this->Method == STOCK && this->OutputQuantity == OUTPUT_COLOR)
  {
    return DrawStock;
  }
  int dims[3], cellFlag;
  FramePlan plan = DrawWithExtension;
  vtkDataArray* scalars = this->GetFrameScalars(dims, cellFlag, plan);
  if (!scalars)
  {
    return plan;
  }
  if (!IsAnalyticBlend(this->BlendMode))
  {
    this->WarnFallbackOnce(
      "analytic rendering applies to isosurface, maximum and minimum intensity "
      "blending");
    return DrawStock;
  }
  if (this->Method == ANALYTIC)
  {
    if (const char* reason = this->GetStockFallbackReason(vol, scalars, cellFlag))
    {
      this->WarnFallbackOnce(reason);
      return DrawStock;
    }
    GLint max3D = 0;
    if (vtkOpenGLRenderWindow::SafeDownCast(ren->GetRenderWindow()))
    {
      glGetIntegerv(GL_MAX_3D_TEXTURE_SIZE, &max3D);
    }
    if (max3D > 0 && (dims[0] > max3D || dims[1] > max3D || dims[2] > max3D))
    {
      this->WarnFallbackOnce(
        "the volume exceeds the largest 3D texture, and analytic rendering needs "
        "it in one block");
      return DrawStock;
    }
  }
  this->ClearFallbackWarning();

  vtkVolumeProperty* property = vol->GetProperty();
  double scale, shift;
  vtkExtensibleGPUVolumeRayCastMapper::GetTextureValueMapping(scalars, scale, shift);
  this->RawToData[0] = static_cast<float>(scale);
  this->RawToData[1] = static_cast<float>(shift);
  this->IsoRaw.clear();
  if (this->BlendMode == vtkVolumeMapper::ISOSURFACE_BLEND)
  {
    vtkContourValues* values = property->GetIsoSurfaceValues();
    for (int k = 0; values && k < values->GetNumberOfContours(); ++k)
    {
      const double value = values->GetValue(k);
      if (std::isfinite(value))
      {
        this->IsoRaw.push_back(static_cast<float>((value - shift) / scale));
      }
    }
    if (this->IsoRaw.empty())
    {
      vtkErrorMacro("Isosurface blending needs at least one finite isosurface value in the "
                    "volume property (GetIsoSurfaceValues()->SetValue(0, v)); not drawing.");
      return DrawNothing;
    }
  }
  else
  {
    double range[2];
    scalars->GetFiniteRange(range, 0);
    const double extreme =
      this->BlendMode == vtkVolumeMapper::MAXIMUM_INTENSITY_BLEND ? range[1] : range[0];
    this->RawExtreme = static_cast<float>((extreme - shift) / scale);
  }

  std::ostringstream key;
  key << this->Method << " " << this->BlendMode << " " << this->IsoRaw.size() << " "
      << property->GetShade(0) << " " << this->OutputQuantity;
  if (key.str() != this->ShaderKey)
  {
    this->ShaderKey = key.str();
    this->ExtensionShaderModified();
  }
  return DrawWithExtension;
}

//------------------------------------------------------------------------------
bool vtkAnalyticVolumeMapper::ReplaceExtensionShaderValues(std::string&,
  std::string& fragmentShader,
  vtkVolume* vol)
{
  using Self = vtkExtensibleGPUVolumeRayCastMapper;
  const bool iso = this->BlendMode == vtkVolumeMapper::ISOSURFACE_BLEND;
  std::ostringstream switches;
  switches << "#define HOVR_BLEND " << this->BlendMode << "\n"
           << "#define HOVR_ISO_COUNT " << std::max<size_t>(this->IsoRaw.size(), 1) << "\n"
           << "#define HOVR_SHADE " << (vol->GetProperty()->GetShade(0) ? 1 : 0) << "\n"
           << "#define HOVR_OUTPUT " << this->OutputQuantity << "\n";
  bool ok = true;
  if (this->Method == ANALYTIC)
  {
    // The whole ray is walked where VTK would initialise its loop, which then never runs.
    ok = Self::ReplaceShaderTag(fragmentShader,
           "//VTK::Shading::Init",
           "hovr_analyticRay();\n  g_exit = true;",
           Self::ReplaceTag) &&
      Self::ReplaceShaderTag(fragmentShader, "//VTK::Shading::Exit", "", Self::ReplaceTag) &&
      Self::ReplaceShaderTag(fragmentShader,
        "//VTK::ComputeRayDirection::Dec",
        switches.str() + hovrAnalyticCommon + hovrAnalytic,
        Self::BeforeTag);
  }
  else
  {
    // VTK's own sampling, observed: where its isosurface first becomes visible, or its
    // sampled extremum at the end.
    const std::string declarations = switches.str() + hovrAnalyticCommon;
    ok = Self::ReplaceShaderTag(
      fragmentShader, "//VTK::ComputeRayDirection::Dec", declarations, Self::BeforeTag);
    if (iso)
    {
      ok = ok &&
        Self::ReplaceShaderTag(fragmentShader,
          "//VTK::Shading::Impl",
          "if (hovr_output.w == 0.0 && g_fragColor.a > 0.0)\n"
          "  {\n"
          "    hovr_output = vec4(hovr_textureToIndex(g_dataPos), 1.0);\n"
          "  }",
          Self::AfterTag);
    }
    else
    {
      const char* value =
        this->BlendMode == vtkVolumeMapper::MAXIMUM_INTENSITY_BLEND ? "l_maxValue" : "l_minValue";
      std::ostringstream exit;
      exit << "if (!l_firstValue)\n"
           << "  {\n"
           << "    float raw = (" << value << ".w - in_volume_bias[0].r) / in_volume_scale[0].r;\n"
           << "    hovr_output = vec4(raw * hovr_rawToData.x + hovr_rawToData.y, 0.0, 0.0, 1.0);\n"
           << "  }";
      ok = ok &&
        Self::ReplaceShaderTag(fragmentShader, "//VTK::Shading::Exit", exit.str(), Self::AfterTag);
    }
  }
  if (this->OutputQuantity != OUTPUT_COLOR)
  {
    ok = ok &&
      Self::ReplaceShaderTag(
        fragmentShader, "//VTK::DepthPass::Exit", "gl_FragData[0] = hovr_output;", Self::AfterTag);
  }
  if (!ok)
  {
    vtkErrorMacro("The ray caster's shader template lacks a tag that analytic rendering uses.");
  }
  return ok;
}

//------------------------------------------------------------------------------
void vtkAnalyticVolumeMapper::SetExtensionShaderParameters(vtkShaderProgram* program, vtkVolume*)
{
  program->SetUniform2f("hovr_rawToData", this->RawToData);
  if (this->Method != ANALYTIC)
  {
    return;
  }
  if (this->BlendMode == vtkVolumeMapper::ISOSURFACE_BLEND)
  {
    program->SetUniform1fv(
      "hovr_isoRaw", static_cast<int>(this->IsoRaw.size()), this->IsoRaw.data());
  }
  else
  {
    program->SetUniformf("hovr_rawExtreme", this->RawExtreme);
  }
}

//------------------------------------------------------------------------------
void vtkAnalyticVolumeMapper::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Method: " << this->Method << "\n";
  os << indent << "OutputQuantity: " << this->OutputQuantity << "\n";
}
