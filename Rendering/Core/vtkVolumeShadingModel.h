// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
/**
 * @class   vtkVolumeShadingModel
 * @brief   the lighting of shaded volumes: per point for the references, per segment for
 *          shaded pre-integration
 *
 * The one lighting model of hovr, shared by the ground truth (vtkVolumeReferenceIntegrator),
 * the CPU mirror of the shaded segments and the GLSL of vtkPreIntegrationVolumeMapper
 * (hovrPreIntegrationShading.glsl repeats ShadeSegment() operation for operation).
 *
 * At a point of scalar colour c and unit normal N (0 where the gradient vanishes), seen along
 * the unit direction V towards the eye, the emission per unit extinction is (Blinn-Phong,
 * Guetat et al. 2010 Eq. 3)
 *   q = c (Ka + Kd sum_k d_k diff(N . L_k)) + Ks sum_k s_k spec(N . H_k),  H_k = |L_k + V|
 * over the directional lights k (towards-light direction L_k, diffuse colour d_k, specular
 * colour s_k, colours times intensity), diff(x) = max(x, 0) and spec(x) = max(x, 0)^n (LOBE,
 * VTK's model) or max(1 + k (x - 1), 0) (CONE, the paper's approximation of the lobe, line 182,
 * with k = n; see SpecularCone).
 * With TwoSidedLighting, N . L and N . H are taken as absolute values, as VTK does. A headlight
 * shines from the eye: L = V on every ray. Ambient light is Ka c, VTK's treatment of the
 * headlight, whatever the lights. N is the normalised gradient, pointing towards increasing
 * scalar as in VTK's GPU ray caster.
 *
 * With Gooch on (Eq. 11, key light L = the first light), q = 1/2 (cool + a Kd c)(1 + N . L) +
 * 1/2 (warm + b Kd c)(1 - N . L) and there is no specular term.
 *
 * ShadeSegment() gives the shaded emission of a ray segment between two samples from its
 * moment integrals (J basis: weights (1 - u), u, u (1 - u)^2, u^2 (1 - u) of the position u in
 * the segment) and the normals at both ends, interpolated as GradientInterpolation says:
 *   - CONSTANT: the normalised average of both normals for the whole segment;
 *   - LINEAR: the endpoint shading values faded linearly (Lum et al., the paper's baseline);
 *   - NONLINEAR: the paper's Eq. 8 and 10 with the quadratic normalisation of Eq. 5 written as
 *     f J0 + b J1 + m (f J2 + b J3), m = 4 (1 - cos a) / cos a, a half the angle between the
 *     normals, with the three diffuse and specular cases of its section 5 (lines 162-215).
 * Methods always use the CONE for the specular term, the only one whose segment integral is a
 * polynomial in u.
 */
#ifndef vtkVolumeShadingModel_h
#define vtkVolumeShadingModel_h

#include "hovrRenderingCoreModule.h" // For export macro
#include "vtkObject.h"

#include <vector> // For the lights

class vtkMatrix4x4;
class vtkRenderer;
class vtkVolumeProperty;

class HOVRRENDERINGCORE_EXPORT vtkVolumeShadingModel : public vtkObject
{
public:
  static vtkVolumeShadingModel* New();
  vtkTypeMacro(vtkVolumeShadingModel, vtkObject);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  enum GradientInterpolations
  {
    CONSTANT = 0,
    LINEAR = 1,
    NONLINEAR = 2
  };

  enum SpecularModels
  {
    LOBE = 0, ///< max(N . H, 0)^n, VTK's
    CONE = 1  ///< max(1 + n (N . H - 1), 0), the paper's
  };

  ///@{
  /**
   * Ambient, diffuse and specular coefficients and the specular power n. SetFromProperty()
   * copies them from component 0 of a volume property. Initial values are VTK's: 0.1, 0.7,
   * 0.2 and 10.
   */
  vtkSetMacro(Ambient, double);
  vtkGetMacro(Ambient, double);
  vtkSetMacro(Diffuse, double);
  vtkGetMacro(Diffuse, double);
  vtkSetMacro(Specular, double);
  vtkGetMacro(Specular, double);
  vtkSetClampMacro(SpecularPower, double, 1.0, 1e6);
  vtkGetMacro(SpecularPower, double);
  ///@}

  /**
   * Copy Ambient, Diffuse, Specular and SpecularPower of component 0 (a power below 1, which
   * the cone cannot model, becomes 1).
   */
  void SetFromProperty(vtkVolumeProperty* property);

  ///@{
  /**
   * The specular term. Initial value is LOBE.
   */
  vtkSetClampMacro(SpecularModel, int, LOBE, CONE);
  vtkGetMacro(SpecularModel, int);
  ///@}

  enum SpecularCones
  {
    PAPER_CONE = 0,  ///< slope n: the lobe's tangent at its peak (the paper's)
    MATCHED_CONE = 1 ///< slope (n + 1) / 2: the lobe's integral over all directions
  };

  ///@{
  /**
   * The cone 1 + k (N . H - 1) that stands for the lobe (N . H)^n, in ShadeSegment() and in
   * ShadePoint() with SpecularModel CONE: PAPER_CONE takes the paper's slope k = n, the
   * lobe's tangent at N . H = 1, whose light over all directions (pi / n) is half the lobe's
   * (2 pi / (n + 1)); MATCHED_CONE takes k = (n + 1) / 2, the cone as wide as that light
   * needs, with the lobe's peak. Any slope keeps the segment integral a polynomial in the
   * position. Initial value is PAPER_CONE.
   */
  vtkSetClampMacro(SpecularCone, int, PAPER_CONE, MATCHED_CONE);
  vtkGetMacro(SpecularCone, int);
  ///@}

  /**
   * The slope k of the cone (see SpecularCone).
   */
  double GetConeSlope() const;

  ///@{
  /**
   * Light both sides of every surface (absolute N . L and N . H), as VTK's renderers do by
   * default. Initial value is true.
   */
  vtkSetMacro(TwoSidedLighting, bool);
  vtkGetMacro(TwoSidedLighting, bool);
  vtkBooleanMacro(TwoSidedLighting, bool);
  ///@}

  ///@{
  /**
   * Gooch shading (Eq. 11) instead of Blinn-Phong, with the cool and warm tones and the
   * weights a and b of the object colour. Initial values: off, cool (0, 0, 0.4), warm
   * (0.4, 0.4, 0), a 0.2, b 0.6 (the paper's example weights).
   */
  vtkSetMacro(Gooch, bool);
  vtkGetMacro(Gooch, bool);
  vtkBooleanMacro(Gooch, bool);
  vtkSetVector3Macro(GoochCool, double);
  vtkGetVector3Macro(GoochCool, double);
  vtkSetVector3Macro(GoochWarm, double);
  vtkGetVector3Macro(GoochWarm, double);
  vtkSetMacro(GoochAlpha, double);
  vtkGetMacro(GoochAlpha, double);
  vtkSetMacro(GoochBeta, double);
  vtkGetMacro(GoochBeta, double);
  ///@}

  ///@{
  /**
   * How ShadeSegment() interpolates the normal between the two samples of a segment. Initial
   * value is NONLINEAR.
   */
  vtkSetClampMacro(GradientInterpolation, int, CONSTANT, NONLINEAR);
  vtkGetMacro(GradientInterpolation, int);
  ///@}

  ///@{
  /**
   * Lower bound of cos a, a half the angle between a segment's normals, in the non-linear
   * interpolation: the quadratic normalisation (Eq. 5) diverges as the normals become
   * antiparallel (the paper's r -> -infinity), and overshoots the exact normalisation by 19%
   * at 120 degrees between the normals (cos a = 0.5). Initial value is 0.5.
   */
  vtkSetClampMacro(MinimumCosHalfAngle, double, 0.01, 1.0);
  vtkGetMacro(MinimumCosHalfAngle, double);
  ///@}

  /**
   * Remove every light.
   */
  void RemoveAllLights();

  /**
   * Add a directional light: towardLight points from the scene to the light (normalised
   * here); a headlight ignores it and shines along each ray's view direction.
   */
  void AddLight(const double towardLight[3],
    const double diffuseColor[3],
    const double specularColor[3],
    bool headlight);

  /**
   * Take the switched-on lights of a renderer and its TwoSidedLighting, in world coordinates.
   * Positional lights are not modelled: they are skipped and counted in the return value.
   */
  int SetLightsFromRenderer(vtkRenderer* renderer);

  /**
   * Express the light directions in the coordinates of a volume whose matrix (object to world)
   * is given, as the GPU's gradients are (directions are multiplied by the inverse matrix and
   * normalised). False for a singular matrix.
   */
  bool TransformLights(vtkMatrix4x4* volumeMatrix);

  int GetNumberOfLights() const { return static_cast<int>(this->Lights.size()); }

  /**
   * Light k: its towards-light direction, colours and whether it is a headlight.
   */
  void GetLight(int k,
    double towardLight[3],
    double diffuse[3],
    double specular[3],
    bool& headlight) const;

  /**
   * Emission per unit extinction at a point (see the class description): normal unit or zero,
   * view the unit direction towards the eye, colour the transfer function's.
   */
  void ShadePoint(const double normal[3],
    const double view[3],
    const double colour[3],
    double rgb[3]) const;

  /**
   * The shaded emission of a segment (premultiplied, attenuation inside the segment included)
   * from its moments: moments[k] (k = 0..3) holds J_k (colour-weighted, RGB) and J'_k
   * (extinction only) as (r, g, b, J'), for normals front and back (unit or zero) and the
   * unit view direction. Ambient is Ka (J_0 + J_1). SpecularModel is ignored: segments use the
   * cone. The highlight between two samples (the third specular case) takes the paper's tent
   * integral I'' as 3 (J'_2 + J'_3): equal to it where the extinction-weighted step weight is
   * linear along the segment (thin segments), up to 1.5 times it for an opaque one.
   */
  void ShadeSegment(const double moments[4][4],
    const double front[3],
    const double back[3],
    const double view[3],
    double rgb[3]) const;

  /**
   * The largest value of the non-linear specular profile p(u) = fh (1 - u) + bh u + m (fh
   * u (1 - u)^2 + bh u^2 (1 - u)) at an interior critical point of u in (0, 1); false if it
   * has none. The highlight search of the paper's third specular case (line 211).
   */
  static bool InteriorMaximum(double fh, double bh, double m, double& value);

  /**
   * m = 4 (1 - cos a) / cos a for unit or zero normals (0 if either is zero), cos a clamped
   * below by MinimumCosHalfAngle; cos a from the half-angle identity.
   */
  double ArcCoefficient(const double front[3], const double back[3]) const;

protected:
  vtkVolumeShadingModel();
  ~vtkVolumeShadingModel() override;

  struct Light
  {
    double Direction[3];
    double Diffuse[3];
    double Specular[3];
    bool Headlight;
  };

  double Ambient = 0.1;
  double Diffuse = 0.7;
  double Specular = 0.2;
  double SpecularPower = 10.0;
  int SpecularModel = LOBE;
  int SpecularCone = PAPER_CONE;
  bool TwoSidedLighting = true;
  bool Gooch = false;
  double GoochCool[3] = { 0.0, 0.0, 0.4 };
  double GoochWarm[3] = { 0.4, 0.4, 0.0 };
  double GoochAlpha = 0.2;
  double GoochBeta = 0.6;
  int GradientInterpolation = NONLINEAR;
  double MinimumCosHalfAngle = 0.5;
  std::vector<Light> Lights;

private:
  vtkVolumeShadingModel(const vtkVolumeShadingModel&) = delete;
  void operator=(const vtkVolumeShadingModel&) = delete;
};

#endif
