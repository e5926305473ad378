// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
#include "vtkVolumeShadingModel.h"

#include "vtkCamera.h"
#include "vtkLight.h"
#include "vtkLightCollection.h"
#include "vtkMatrix4x4.h"
#include "vtkObjectFactory.h"
#include "vtkRenderer.h"
#include "vtkVolumeProperty.h"

#include <algorithm>
#include <cmath>

vtkStandardNewMacro(vtkVolumeShadingModel);

namespace
{
double Dot(const double a[3], const double b[3])
{
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

// Normalises v in place; a vector too short to have a direction becomes zero.
void Normalize(double v[3])
{
  const double norm = std::sqrt(Dot(v, v));
  for (int a = 0; a < 3; ++a)
  {
    v[a] = norm > 1e-300 ? v[a] / norm : 0.0;
  }
}

// N . d as a side is lit by it: its absolute value with two-sided lighting.
double Side(double x, bool twoSided)
{
  return twoSided ? std::abs(x) : x;
}

// The dot products of a segment's end normals with a direction, as its shading sees them.
// Two-sided lighting lights a side by |N . d|: ends that both face away are lit as if both
// faced d, and ends that face opposite ways (Split) are faded out each on its own, because
// the field's normal between them crosses the plane perpendicular to d, where N . d = 0.
// Mirroring one end instead sends the interpolated normal through d and adds light the field
// does not have (the paper notes the gain, line 173).
struct Ends
{
  double Front, Back;
  bool Split;
};
Ends Orient(double f, double b, bool twoSided)
{
  if (twoSided && f < 0.0 && b < 0.0)
  {
    return { -f, -b, false };
  }
  if (twoSided && (f < 0.0) != (b < 0.0))
  {
    return { std::abs(f), std::abs(b), true };
  }
  return { f, b, false };
}

// The paper's cone (line 182): the first-order expansion of the lobe x^n at x = 1.
double Cone(double x, double n)
{
  return 1.0 + n * (x - 1.0);
}
}

//------------------------------------------------------------------------------
vtkVolumeShadingModel::vtkVolumeShadingModel() = default;

//------------------------------------------------------------------------------
vtkVolumeShadingModel::~vtkVolumeShadingModel() = default;

//------------------------------------------------------------------------------
void vtkVolumeShadingModel::SetFromProperty(vtkVolumeProperty* property)
{
  if (!property)
  {
    return;
  }
  this->SetAmbient(property->GetAmbient(0));
  this->SetDiffuse(property->GetDiffuse(0));
  this->SetSpecular(property->GetSpecular(0));
  this->SetSpecularPower(std::max(property->GetSpecularPower(0), 1.0));
}

//------------------------------------------------------------------------------
void vtkVolumeShadingModel::RemoveAllLights()
{
  if (!this->Lights.empty())
  {
    this->Lights.clear();
    this->Modified();
  }
}

//------------------------------------------------------------------------------
void vtkVolumeShadingModel::AddLight(const double towardLight[3],
  const double diffuseColor[3],
  const double specularColor[3],
  bool headlight)
{
  Light light;
  std::copy(towardLight, towardLight + 3, light.Direction);
  Normalize(light.Direction);
  std::copy(diffuseColor, diffuseColor + 3, light.Diffuse);
  std::copy(specularColor, specularColor + 3, light.Specular);
  light.Headlight = headlight;
  this->Lights.push_back(light);
  this->Modified();
}

//------------------------------------------------------------------------------
int vtkVolumeShadingModel::SetLightsFromRenderer(vtkRenderer* renderer)
{
  this->RemoveAllLights();
  if (!renderer)
  {
    return 0;
  }
  this->SetTwoSidedLighting(renderer->GetTwoSidedLighting() != 0);
  vtkCamera* camera = renderer->GetActiveCamera();
  int positional = 0;
  vtkLightCollection* lights = renderer->GetLights();
  vtkCollectionSimpleIterator it;
  lights->InitTraversal(it);
  while (vtkLight* light = lights->GetNextLight(it))
  {
    if (!light->GetSwitch() || light->GetIntensity() <= 0.0)
    {
      continue;
    }
    if (light->GetPositional())
    {
      ++positional;
      continue;
    }
    double position[4] = { 0, 0, 0, 1 }, focal[4] = { 0, 0, 0, 1 };
    light->GetPosition(position);
    light->GetFocalPoint(focal);
    // Camera lights live in camera coordinates: the renderer moves them with the camera on
    // each render, here the camera's light transform does it.
    if (light->LightTypeIsCameraLight() && camera)
    {
      vtkMatrix4x4* toWorld = camera->GetCameraLightTransformMatrix();
      toWorld->MultiplyPoint(position, position);
      toWorld->MultiplyPoint(focal, focal);
    }
    const double direction[3] = { position[0] / position[3] - focal[0] / focal[3],
      position[1] / position[3] - focal[1] / focal[3],
      position[2] / position[3] - focal[2] / focal[3] };
    double diffuse[3], specular[3];
    light->GetDiffuseColor(diffuse);
    light->GetSpecularColor(specular);
    for (int c = 0; c < 3; ++c)
    {
      diffuse[c] *= light->GetIntensity();
      specular[c] *= light->GetIntensity();
    }
    this->AddLight(direction, diffuse, specular, light->LightTypeIsHeadlight() != 0);
  }
  return positional;
}

//------------------------------------------------------------------------------
bool vtkVolumeShadingModel::TransformLights(vtkMatrix4x4* volumeMatrix)
{
  if (!volumeMatrix)
  {
    return true;
  }
  // The determinant first: vtkMatrix4x4::Invert leaves its output unset for a singular matrix.
  if (volumeMatrix->Determinant() == 0.0)
  {
    return false;
  }
  double inverse[16];
  vtkMatrix4x4::Invert(volumeMatrix->GetData(), inverse);
  if (!std::all_of(inverse, inverse + 16, [](double v) { return std::isfinite(v); }))
  {
    return false;
  }
  for (Light& light : this->Lights)
  {
    const double d[3] = { light.Direction[0], light.Direction[1], light.Direction[2] };
    for (int r = 0; r < 3; ++r)
    {
      light.Direction[r] =
        inverse[4 * r] * d[0] + inverse[4 * r + 1] * d[1] + inverse[4 * r + 2] * d[2];
    }
    Normalize(light.Direction);
  }
  this->Modified();
  return true;
}

//------------------------------------------------------------------------------
void vtkVolumeShadingModel::GetLight(int k,
  double towardLight[3],
  double diffuse[3],
  double specular[3],
  bool& headlight) const
{
  const Light& light = this->Lights.at(k);
  std::copy(light.Direction, light.Direction + 3, towardLight);
  std::copy(light.Diffuse, light.Diffuse + 3, diffuse);
  std::copy(light.Specular, light.Specular + 3, specular);
  headlight = light.Headlight;
}

//------------------------------------------------------------------------------
void vtkVolumeShadingModel::ShadePoint(const double normal[3],
  const double view[3],
  const double colour[3],
  double rgb[3]) const
{
  const double n = this->SpecularPower;
  if (this->Gooch)
  {
    const double nl = this->Lights.empty()
      ? 0.0
      : Dot(normal, this->Lights[0].Headlight ? view : this->Lights[0].Direction);
    for (int c = 0; c < 3; ++c)
    {
      rgb[c] =
        0.5 * (this->GoochCool[c] + this->GoochAlpha * this->Diffuse * colour[c]) * (1 + nl) +
        0.5 * (this->GoochWarm[c] + this->GoochBeta * this->Diffuse * colour[c]) * (1 - nl);
    }
    return;
  }
  for (int c = 0; c < 3; ++c)
  {
    rgb[c] = this->Ambient * colour[c];
  }
  for (const Light& light : this->Lights)
  {
    const double* l = light.Headlight ? view : light.Direction;
    double h[3] = { l[0] + view[0], l[1] + view[1], l[2] + view[2] };
    Normalize(h);
    double nl = Dot(normal, l), nh = Dot(normal, h);
    if (this->TwoSidedLighting)
    {
      nl = std::abs(nl);
      nh = std::abs(nh);
    }
    const double specular = this->SpecularModel == CONE
      ? std::max(Cone(nh, this->GetConeSlope()), 0.0)
      : (nh > 0.0 ? std::pow(nh, n) : 0.0);
    for (int c = 0; c < 3; ++c)
    {
      rgb[c] += this->Diffuse * light.Diffuse[c] * std::max(nl, 0.0) * colour[c] +
        this->Specular * light.Specular[c] * specular;
    }
  }
}

//------------------------------------------------------------------------------
double vtkVolumeShadingModel::ArcCoefficient(const double front[3], const double back[3]) const
{
  if (Dot(front, front) < 0.5 || Dot(back, back) < 0.5)
  {
    return 0.0; // no arc between a normal and no normal
  }
  // cos a by the half-angle identity: no acos, and a dot product just beyond -1 is harmless.
  const double cosAngle = std::min(std::max(Dot(front, back), -1.0), 1.0);
  const double ca = std::max(std::sqrt(0.5 * (1.0 + cosAngle)), this->MinimumCosHalfAngle);
  return 4.0 * (1.0 - ca) / ca; // m = -r of Eq. 8
}

//------------------------------------------------------------------------------
bool vtkVolumeShadingModel::InteriorMaximum(double fh, double bh, double m, double& value)
{
  // p(u) = a0 + a1 u + a2 u^2 + a3 u^3 with the paper's a_k(H) (Eq. 8, r = -m), evaluated as
  // q(u) (1 + m u (1 - u)) with q(u) = fh (1 - u) + bh u.
  const double a1 = bh - fh + m * fh;
  const double a2 = m * (bh - 2.0 * fh);
  const double a3 = m * (fh - bh);
  const double disc = a2 * a2 - 3.0 * a1 * a3;
  if (disc < 0.0)
  {
    return false;
  }
  // The root of p' without cancellation first, the other from the product of the roots; with
  // a3 = 0 the second is the linear root -a1 / (2 a2), and a2 = a3 = 0 has none.
  const double q = -(a2 + std::copysign(std::sqrt(disc), a2));
  const double roots[2] = { a3 != 0.0 ? q / (3.0 * a3) : -1.0, q != 0.0 ? a1 / q : -1.0 };
  bool found = false;
  for (double u : roots)
  {
    if (u > 0.0 && u < 1.0)
    {
      const double p = (fh + (bh - fh) * u) * (1.0 + m * u * (1.0 - u));
      value = found ? std::max(value, p) : p;
      found = true;
    }
  }
  return found;
}

//------------------------------------------------------------------------------
void vtkVolumeShadingModel::ShadeSegment(const double moments[4][4],
  const double front[3],
  const double back[3],
  const double view[3],
  double rgb[3]) const
{
  const double* J0 = moments[0];
  const double* J1 = moments[1];
  const double* J2 = moments[2];
  const double* J3 = moments[3];
  // The tent integral I'' of the highlight search (line 213) from the moments at hand: 3 u
  // (1 - u), the weight of 3 (J'_2 + J'_3), has the tent min(2u, 2 - 2u)'s integral against any
  // weight linear in u (both are symmetric about u = 1/2 with integral 1/2).
  const double tent = 3.0 * (J2[3] + J3[3]);
  const double n = this->GetConeSlope(); // the cone: 1 + n (x - 1)
  const int mode = this->GradientInterpolation;
  // The segment's unshaded colour and its opacity: I_0 = J_0 + J_1, I'_0 = J'_0 + J'_1.
  double I0[4];
  for (int c = 0; c < 4; ++c)
  {
    I0[c] = J0[c] + J1[c];
  }
  // The diffuse-type integral of the profile f(1-u) + b u (+ m (...)) for the normals' dot
  // products f, b with a direction, channel c (3: the extinction-only moments).
  auto profile = [&](double f, double b, double m, int c)
  { return f * J0[c] + b * J1[c] + m * (f * J2[c] + b * J3[c]); };
  // The constant interpolation's normal: the normalised average (zero if they cancel).
  auto average = [](const double* a, const double* b, double out[3])
  {
    for (int k = 0; k < 3; ++k)
    {
      out[k] = a[k] + b[k];
    }
    Normalize(out);
  };

  if (this->Gooch)
  {
    const double* l = this->Lights.empty()
      ? nullptr
      : (this->Lights[0].Headlight ? view : this->Lights[0].Direction);
    double p[4] = { 0, 0, 0, 0 };
    if (l)
    {
      if (mode == CONSTANT)
      {
        double nc[3];
        average(front, back, nc);
        for (int c = 0; c < 4; ++c)
        {
          p[c] = Dot(nc, l) * I0[c];
        }
      }
      else
      {
        // No cases: Gooch is linear in N . L, negative values included (line 234).
        const double m = mode == NONLINEAR ? this->ArcCoefficient(front, back) : 0.0;
        for (int c = 0; c < 4; ++c)
        {
          p[c] = profile(Dot(front, l), Dot(back, l), m, c);
        }
      }
    }
    const double a = this->GoochAlpha, b = this->GoochBeta;
    for (int c = 0; c < 3; ++c)
    {
      rgb[c] = 0.5 * (this->GoochCool[c] + this->GoochWarm[c]) * I0[3] +
        0.5 * this->Diffuse * (a + b) * I0[c] +
        0.5 * (this->GoochCool[c] - this->GoochWarm[c]) * p[3] +
        0.5 * this->Diffuse * (a - b) * p[c];
    }
    return;
  }

  for (int c = 0; c < 3; ++c)
  {
    rgb[c] = this->Ambient * I0[c];
  }
  const bool twoSided = this->TwoSidedLighting;
  for (const Light& light : this->Lights)
  {
    const double* l = light.Headlight ? view : light.Direction;
    double h[3] = { l[0] + view[0], l[1] + view[1], l[2] + view[2] };
    Normalize(h);

    // The arc between the normals, for the non-linear interpolation.
    const double m = mode == NONLINEAR ? this->ArcCoefficient(front, back) : 0.0;
    double nc[3]; // the constant interpolation's normal
    average(front, back, nc);

    // Diffuse.
    double diffuse[3] = { 0, 0, 0 };
    if (mode == CONSTANT)
    {
      const double d = std::max(Side(Dot(nc, l), twoSided), 0.0); // one-sided: none facing away
      for (int c = 0; c < 3; ++c)
      {
        diffuse[c] = d * I0[c];
      }
    }
    else
    {
      const Ends e = Orient(Dot(front, l), Dot(back, l), twoSided);
      for (int c = 0; c < 3; ++c)
      {
        // The paper's three cases (lines 162-173): a negative end fades the other one out.
        diffuse[c] = mode == LINEAR || e.Split
          ? std::max(e.Front, 0.0) * J0[c] + std::max(e.Back, 0.0) * J1[c]
          : e.Front >= 0.0 && e.Back >= 0.0 ? profile(e.Front, e.Back, m, c)
          : e.Front > 0.0                   ? e.Front * J0[c]
          : e.Back > 0.0                    ? e.Back * J1[c]
                                            : 0.0;
      }
    }

    // Specular, the cone.
    double specular = 0.0;
    if (this->Specular != 0.0)
    {
      const Ends e = Orient(Dot(front, h), Dot(back, h), twoSided);
      const double fh = e.Front, bh = e.Back;
      const double threshold = (n - 1.0) / n; // the cone is positive above it (line 207)
      if (mode == CONSTANT)
      {
        specular = std::max(Cone(Side(Dot(nc, h), twoSided), n), 0.0) * I0[3];
      }
      else if (mode == LINEAR || e.Split)
      {
        specular = std::max(Cone(fh, n), 0.0) * J0[3] + std::max(Cone(bh, n), 0.0) * J1[3];
      }
      else if (fh > threshold && bh > threshold)
      {
        specular = Cone(fh, n) * J0[3] + Cone(bh, n) * J1[3] + n * m * (fh * J2[3] + bh * J3[3]);
      }
      else if (fh > threshold)
      {
        // The cone's value faded out, not its argument: the printed formula (line 210)
        // fades N . H inside the cone and turns negative.
        specular = Cone(fh, n) * J0[3];
      }
      else if (bh > threshold)
      {
        specular = Cone(bh, n) * J1[3];
      }
      else
      {
        // A highlight between the samples (lines 211-215): its peak value times the tent.
        // The profile is at most max(fh, bh) (1 + m / 4), the largest weight of the arc:
        // below the threshold no peak can reach the cone, and the search is skipped.
        double peak;
        if (std::max(fh, bh) * (1.0 + 0.25 * m) > threshold && InteriorMaximum(fh, bh, m, peak) &&
          Cone(peak, n) > 0.0)
        {
          specular = Cone(peak, n) * tent;
        }
      }
    }
    for (int c = 0; c < 3; ++c)
    {
      rgb[c] += this->Diffuse * light.Diffuse[c] * diffuse[c] +
        this->Specular * light.Specular[c] * specular;
    }
  }
}

//------------------------------------------------------------------------------
double vtkVolumeShadingModel::GetConeSlope() const
{
  // The lobe x^n integrates to 2 pi / (n + 1) over the directions, a cone of slope k to
  // pi / k: slope (n + 1) / 2 keeps the lobe's energy.
  return this->SpecularCone == MATCHED_CONE ? 0.5 * (this->SpecularPower + 1.0)
                                            : this->SpecularPower;
}

//------------------------------------------------------------------------------
void vtkVolumeShadingModel::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Ambient: " << this->Ambient << "\n";
  os << indent << "Diffuse: " << this->Diffuse << "\n";
  os << indent << "Specular: " << this->Specular << "\n";
  os << indent << "SpecularPower: " << this->SpecularPower << "\n";
  os << indent << "SpecularModel: " << (this->SpecularModel == CONE ? "Cone" : "Lobe") << "\n";
  os << indent << "SpecularCone: " << (this->SpecularCone == MATCHED_CONE ? "Matched" : "Paper")
     << "\n";
  os << indent << "TwoSidedLighting: " << (this->TwoSidedLighting ? "On" : "Off") << "\n";
  os << indent << "Gooch: " << (this->Gooch ? "On" : "Off") << "\n";
  os << indent << "GradientInterpolation: " << this->GradientInterpolation << "\n";
  os << indent << "MinimumCosHalfAngle: " << this->MinimumCosHalfAngle << "\n";
  os << indent << "Lights: " << this->Lights.size() << "\n";
}
