// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
// vtkVolumeShadingModel: the shaded segment from its moment integrals (Guetat et al. 2010,
// Eq. 8 and 10 in the J basis, the cases of their section 5, the cone and the highlight
// search, Gooch, several lights) against the paper's monomial form, against exact integrals
// of the normalised interpolated normal, and against integrals of the point shading; the
// point shading itself; the lights (transformation, renderer); and the moment layers of
// vtkSecondOrderPreIntegrationTable against its RGBA table and a double-precision integral.
// One file, beyond the usual length: every check shares the discretised-segment fixture.
#include "vtkCamera.h"
#include "vtkColorTransferFunction.h"
#include "vtkLight.h"
#include "vtkMatrix4x4.h"
#include "vtkNew.h"
#include "vtkPiecewiseFunction.h"
#include "vtkRenderer.h"
#include "vtkSecondOrderPreIntegrationTable.h"
#include "vtkSmartPointer.h"
#include "vtkVolumeProperty.h"
#include "vtkVolumeShadingModel.h"
#include "vtkVolumeTransferFunctionSampler.h"

#include "hovrTestUtilities.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <iomanip>
#include <iostream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

namespace
{
hovrTest::Checker check;

constexpr double Pi = 3.14159265358979323846;
// The same sums of a few O(1) products as the class, in another order or with another
// rounding of the normals: a few ulps of values below 10.
constexpr double Rounding = 1e-14;

using Vec = std::array<double, 3>;
using Shading = vtkVolumeShadingModel;

double Rad(double degrees)
{
  return degrees * Pi / 180.0;
}

double Dot(const Vec& a, const Vec& b)
{
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

Vec Normalized(const Vec& v)
{
  const double norm = std::sqrt(Dot(v, v));
  return { v[0] / norm, v[1] / norm, v[2] / norm };
}

Vec Negated(const Vec& v)
{
  return { -v[0], -v[1], -v[2] };
}

// v rotated by `degrees` about the unit axis (Rodrigues).
Vec Rotated(const Vec& v, const Vec& axis, double degrees)
{
  const double c = std::cos(Rad(degrees)), s = std::sin(Rad(degrees));
  const Vec k = Normalized(axis);
  const Vec cross = {
    k[1] * v[2] - k[2] * v[1], k[2] * v[0] - k[0] * v[2], k[0] * v[1] - k[1] * v[0]
  };
  const double kv = Dot(k, v);
  Vec out;
  for (int a = 0; a < 3; ++a)
  {
    out[a] = v[a] * c + cross[a] * s + k[a] * kv * (1.0 - c);
  }
  return out;
}

// The unit vector at polar angle theta from +z and azimuth phi (degrees).
Vec Polar(double theta, double phi)
{
  return { std::sin(Rad(theta)) * std::cos(Rad(phi)),
    std::sin(Rad(theta)) * std::sin(Rad(phi)),
    std::cos(Rad(theta)) };
}

double Cone(double x, double n)
{
  return 1.0 + n * (x - 1.0);
}

std::string Str(double v)
{
  std::ostringstream os;
  os << std::setprecision(6) << v;
  return os.str();
}

// A ray segment of length 1 discretised into midpoint steps u_j = (j + 1/2) / steps with
// step weights w_j = T_j (1 - exp(-tau(u_j) / steps)), T_j the transmittance before step j,
// and its moments from the same steps: J_k = sum w_j c(u_j) weight_k(u_j) (RGB),
// J'_k = sum w_j weight_k(u_j), weights (1 - u), u, u (1 - u)^2, u^2 (1 - u), and the paper's
// tent I'' = sum w_j min(2 u_j, 2 - 2 u_j). References integrate shadings over the same steps, so
// a shading the class integrates exactly (polynomial in u in the J basis) matches to rounding.
struct Segment
{
  std::vector<double> U, W;
  std::vector<Vec> Colour;
  double M[4][4] = {};
  double Tent = 0.0;

  // sum_j w_j q(u_j, c(u_j)).
  Vec Integrate(const std::function<Vec(double, const Vec&)>& q) const
  {
    Vec sum = { 0.0, 0.0, 0.0 };
    for (size_t j = 0; j < this->U.size(); ++j)
    {
      const Vec v = q(this->U[j], this->Colour[j]);
      for (int c = 0; c < 3; ++c)
      {
        sum[c] += this->W[j] * v[c];
      }
    }
    return sum;
  }

  double I0(int c) const { return this->M[0][c] + this->M[1][c]; }
};

Segment MakeSegment(int steps,
  const std::function<double(double)>& tau,
  const std::function<Vec(double)>& colour)
{
  Segment s;
  double transmittance = 1.0;
  for (int j = 0; j < steps; ++j)
  {
    const double u = (j + 0.5) / steps;
    const double alpha = -std::expm1(-tau(u) / steps);
    const double w = transmittance * alpha;
    const Vec c = colour(u);
    const double weights[4] = { 1.0 - u, u, u * (1.0 - u) * (1.0 - u), u * u * (1.0 - u) };
    for (int k = 0; k < 4; ++k)
    {
      for (int a = 0; a < 3; ++a)
      {
        s.M[k][a] += w * c[a] * weights[k];
      }
      s.M[k][3] += w * weights[k];
    }
    s.Tent += w * std::min(2.0 * u, 2.0 - 2.0 * u);
    s.U.push_back(u);
    s.W.push_back(w);
    s.Colour.push_back(c);
    transmittance *= 1.0 - alpha;
  }
  return s;
}

// A segment with varying extinction and colour, optical depth about 1.5.
Segment GenericSegment(int steps = 400)
{
  return MakeSegment(
    steps,
    [](double u) { return 1.0 + u; },
    [](double u) {
      return Vec{ 0.2 + 0.6 * u, 0.9 - 0.5 * u, 0.5 };
    });
}

vtkSmartPointer<Shading> Model(double ka, double kd, double ks, double n, int mode, bool twoSided)
{
  auto model = vtkSmartPointer<Shading>::New();
  model->SetAmbient(ka);
  model->SetDiffuse(kd);
  model->SetSpecular(ks);
  model->SetSpecularPower(n);
  model->SetGradientInterpolation(mode);
  model->SetTwoSidedLighting(twoSided);
  return model;
}

void AddLight(Shading* model,
  const Vec& toward,
  bool headlight = false,
  const Vec& diffuse = { 1.0, 1.0, 1.0 },
  const Vec& specular = { 1.0, 1.0, 1.0 })
{
  model->AddLight(toward.data(), diffuse.data(), specular.data(), headlight);
}

// Diffuse only (Ka = Ks = 0, Kd = 1, one white light): ShadeSegment gives the diffuse integral.
vtkSmartPointer<Shading> DiffuseModel(int mode, bool twoSided, const Vec& light)
{
  auto model = Model(0.0, 1.0, 0.0, 10.0, mode, twoSided);
  AddLight(model, light);
  return model;
}

// Specular only (Ka = Kd = 0, Ks = 1, one white light): ShadeSegment gives the cone integral.
vtkSmartPointer<Shading> SpecularModel(int mode, bool twoSided, double n, const Vec& light)
{
  auto model = Model(0.0, 0.0, 1.0, n, mode, twoSided);
  AddLight(model, light);
  return model;
}

Vec Shade(const Shading* model,
  const Segment& s,
  const Vec& front,
  const Vec& back,
  const Vec& view)
{
  Vec rgb;
  model->ShadeSegment(s.M, front.data(), back.data(), view.data(), rgb.data());
  return rgb;
}

Vec ShadePoint(const Shading* model, const Vec& normal, const Vec& view, const Vec& colour)
{
  Vec rgb;
  model->ShadePoint(normal.data(), view.data(), colour.data(), rgb.data());
  return rgb;
}

double Largest(const Vec& a, const Vec& b)
{
  return std::max({ std::abs(a[0] - b[0]), std::abs(a[1] - b[1]), std::abs(a[2] - b[2]) });
}

// Largest difference between rgb and expected(c) over the channels.
double Largest(const Vec& rgb, const std::function<double(int)>& expected)
{
  return Largest(rgb, Vec{ expected(0), expected(1), expected(2) });
}

bool Finite(const Vec& v)
{
  return std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]);
}

// The direction of light k of a model.
Vec LightDirection(const Shading* model, int k, bool* headlight = nullptr)
{
  Vec d, diffuse, specular;
  bool h;
  model->GetLight(k, d.data(), diffuse.data(), specular.data(), h);
  if (headlight)
  {
    *headlight = h;
  }
  return d;
}

const Vec Z = { 0.0, 0.0, 1.0 };
const Vec Zero = { 0.0, 0.0, 0.0 };
const char* const ModeName[3] = { "CONSTANT", "LINEAR", "NONLINEAR" };

//------------------------------------------------------------------------------
// 1. Equal normals: no arc (m = 0), and the three interpolations are one.
void TestEqualNormals()
{
  const Segment seg = GenericSegment();
  std::mt19937 random(7);
  std::normal_distribution<double> gauss;
  auto direction = [&]() { return Normalized(Vec{ gauss(random), gauss(random), gauss(random) }); };
  vtkNew<Shading> model;
  double arc = 0.0;
  for (int t = 0; t < 100; ++t)
  {
    const Vec n = direction();
    arc = std::max(arc, std::abs(model->ArcCoefficient(n.data(), n.data())));
  }
  // N . N of a unit vector is 1 within an ulp or two: m = 4 (1 - cos a) / cos a ~ 1e-16.
  check.Near(arc, 0.0, 1e-15, "equal random unit normals: ArcCoefficient ~ 0");
  for (const Vec& n : { Z, Vec{ 1.0, 0.0, 0.0 }, Vec{ 0.0, -1.0, 0.0 } })
  {
    check(model->ArcCoefficient(n.data(), n.data()) == 0.0,
      "equal axis-aligned normals: ArcCoefficient is exactly 0");
  }

  // Full Blinn-Phong (ambient, coloured light, cone), random normal, light and view, one- and
  // two-sided: CONSTANT, LINEAR and NONLINEAR agree wherever N . L and N . H fall.
  for (bool twoSided : { false, true })
  {
    double worst = 0.0;
    for (int t = 0; t < 200; ++t)
    {
      const Vec n = direction(), l = direction(), v = direction();
      Vec rgb[3];
      for (int mode = 0; mode < 3; ++mode)
      {
        auto m = Model(0.1, 0.7, 0.4, 10.0, mode, twoSided);
        AddLight(m, l, false, { 0.9, 0.8, 0.7 }, { 1.0, 1.0, 0.5 });
        rgb[mode] = Shade(m, seg, n, n, v);
      }
      worst = std::max({ worst, Largest(rgb[0], rgb[2]), Largest(rgb[1], rgb[2]) });
    }
    check.Near(worst,
      0.0,
      Rounding,
      std::string("equal normals, random light and view, ") + (twoSided ? "two" : "one") +
        "-sided: CONSTANT == LINEAR == NONLINEAR");
  }

  // The same, spelled out. Diffuse: max(N . L, 0) I0 one-sided (0 when N faces away),
  // |N . L| I0 two-sided.
  const Vec l = Polar(30.0, 10.0);
  for (double angle : { 20.0, 70.0, 120.0, 160.0 })
  {
    const Vec n = Polar(angle, 80.0);
    const double nl = Dot(n, Normalized(l));
    for (bool twoSided : { false, true })
    {
      const double d = twoSided ? std::abs(nl) : std::max(nl, 0.0);
      for (int mode = 0; mode < 3; ++mode)
      {
        const Vec rgb = Shade(DiffuseModel(mode, twoSided, l), seg, n, n, Z);
        check.Near(Largest(rgb, [&](int c) { return d * seg.I0(c); }),
          0.0,
          Rounding,
          std::string(ModeName[mode]) + " diffuse of equal normals at " + Str(angle) +
            " deg from a light " + (twoSided ? "(two" : "(one") +
            "-sided): max(N.L, 0) I0 one-sided, |N.L| I0 two-sided");
      }
    }
  }
  // Specular, case 1 (N . H above the threshold (n - 1)/n = 0.9): cone(N . H) I'0 > 0.
  {
    const Vec v = Polar(25.0, 200.0);
    const Vec h = Normalized(Vec{ l[0] + v[0], l[1] + v[1], l[2] + v[2] });
    const Vec n = Rotated(h, Vec{ 1.0, 1.0, 0.0 }, 5.0);
    const double expected = Cone(Dot(n, h), 10.0) * (seg.M[0][3] + seg.M[1][3]);
    check(expected > 0.0, "the specular fixture is inside the cone");
    for (bool twoSided : { false, true })
    {
      for (int mode = 0; mode < 3; ++mode)
      {
        const Vec rgb = Shade(SpecularModel(mode, twoSided, 10.0, l), seg, n, n, v);
        check.Near(Largest(rgb, [&](int) { return expected; }),
          0.0,
          Rounding,
          std::string(ModeName[mode]) + " specular of equal normals 5 deg from H: cone(N.H) I'0");
      }
    }
  }
}

//------------------------------------------------------------------------------
// 2. The J basis against the paper's monomial form: Eq. 8 (diffuse) and Eq. 10 (cone) with
//    I0..I3 derived from random J values and r from acos/cos, not the class' half-angle formula.
void TestMonomialForm()
{
  std::mt19937 random(11);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  std::normal_distribution<double> gauss;
  auto direction = [&]() { return Normalized(Vec{ gauss(random), gauss(random), gauss(random) }); };
  auto paper = [](double f, double b, double r, const double I[4])
  {
    const double a[4] = { f, b - (1.0 + r) * f, r * (2.0 * f - b), r * (b - f) };
    return a[0] * I[0] + a[1] * I[1] + a[2] * I[2] + a[3] * I[3];
  };
  // I_k from J_k of channel c: I0 = J0 + J1, I1 = J1, I2 = I1 - J2 - J3, I3 = I1 - J2 - 2 J3.
  auto monomials = [](const Segment& s, int c, double I[4])
  {
    const double J[4] = { s.M[0][c], s.M[1][c], s.M[2][c], s.M[3][c] };
    I[0] = J[0] + J[1];
    I[1] = J[1];
    I[2] = I[1] - J[2] - J[3];
    I[3] = I[1] - J[2] - 2.0 * J[3];
  };
  double worstDiffuse = 0.0, worstSpecular = 0.0;
  int diffuseCases = 0, specularCases = 0;
  for (int t = 0; t < 400; ++t)
  {
    Segment s;
    for (auto& layer : s.M)
    {
      for (double& v : layer)
      {
        v = uniform(random);
      }
    }
    const Vec l = direction(), v = direction();
    const Vec h = Normalized(Vec{ l[0] + v[0], l[1] + v[1], l[2] + v[2] });
    // Diffuse: normals facing the light, less than 110 deg apart (the clamp of cos a at 0.5
    // starts at 120 deg).
    {
      auto facing = [&](const Vec& n) { return Dot(n, l) < 0.0 ? Negated(n) : n; };
      const Vec nf = facing(direction()), nb = facing(direction());
      const double f = Dot(nf, l), b = Dot(nb, l), between = std::acos(Dot(nf, nb));
      if (between < Rad(110.0))
      {
        ++diffuseCases;
        const double ca = std::cos(0.5 * between), r = 4.0 * (ca - 1.0) / ca;
        const Vec rgb = Shade(DiffuseModel(Shading::NONLINEAR, false, l), s, nf, nb, v);
        for (int c = 0; c < 3; ++c)
        {
          double I[4];
          monomials(s, c, I);
          worstDiffuse = std::max(worstDiffuse, std::abs(rgb[c] - paper(f, b, r, I)));
        }
      }
    }
    // Specular: normals within 20 deg of H, inside the cone of n = 10 (N . H > 0.9).
    {
      const double n = 10.0;
      const Vec nf = Rotated(h, direction(), 20.0 * uniform(random));
      const Vec nb = Rotated(h, direction(), 20.0 * uniform(random));
      const double fh = Dot(nf, h), bh = Dot(nb, h);
      if (fh > 0.9 && bh > 0.9)
      {
        ++specularCases;
        const double ca = std::cos(0.5 * std::acos(std::min(Dot(nf, nb), 1.0)));
        const double r = 4.0 * (ca - 1.0) / ca;
        double I[4];
        monomials(s, 3, I);
        // Eq. 10: Ks (I'0 + n sum_k a_k(H) I'_k - n I'0).
        const double expected = I[0] + n * paper(fh, bh, r, I) - n * I[0];
        const Vec rgb = Shade(SpecularModel(Shading::NONLINEAR, false, n, l), s, nf, nb, v);
        worstSpecular = std::max(worstSpecular, Largest(rgb, [&](int) { return expected; }));
      }
    }
  }
  check(diffuseCases > 250 && specularCases > 300, "the monomial fixtures cover enough cases");
  // J in [0, 1], |r| <= 4: the monomial form cancels terms of order 10; 1e-12 leaves room for
  // the acos/cos round trip of r (relative 1e-16 / sin(a)).
  check.Near(worstDiffuse, 0.0, 1e-12, "diffuse in the J basis == Eq. 8 (paper's a_k, I_k)");
  check.Near(worstSpecular, 0.0, 1e-12, "cone in the J basis == Eq. 10 (paper's a_k(H), I'_k)");
}

//------------------------------------------------------------------------------
// 3. Against the exactly normalised interpolation: a constant-scalar segment (optical depth
//    tau, white), a headlight, normals at `angle` to each other; the exact diffuse integral is
//    sum w_j max(normalize((1 - u) Nf + u Nb) . L, 0).
void TestExactNormalisation()
{
  const double tau = 1.5;
  // 200000 midpoint steps: the moments and the exact integral share them, and their own
  // error against the continuous integral (~1e-11) is far below the 1% under test.
  const Segment seg = MakeSegment(
    200000,
    [=](double) { return tau; },
    [](double) {
      return Vec{ 1.0, 1.0, 1.0 };
    });
  auto nonlinear = Model(0.0, 1.0, 0.0, 10.0, Shading::NONLINEAR, true);
  auto linear = Model(0.0, 1.0, 0.0, 10.0, Shading::LINEAR, true);
  AddLight(nonlinear, Z, true);
  AddLight(linear, Z, true);
  std::cout << "Diffuse integral of a constant segment (tau = " << tau
            << ") with a headlight, normals `angle' apart:\n"
            << "  normals          angle     exact  nonlinear     linear  nonlin err  linear err\n";
  for (int config = 0; config < 2; ++config)
  {
    for (double angle = 10.0; angle <= 90.0; angle += 10.0)
    {
      // Symmetric about the view, or the front normal on the view.
      const Vec nf = config == 0 ? Polar(0.5 * angle, 0.0) : Z;
      const Vec nb = config == 0 ? Polar(0.5 * angle, 180.0) : Polar(angle, 0.0);
      const Vec exact = seg.Integrate(
        [&](double u, const Vec&)
        {
          const Vec n = Normalized(Vec{ (1.0 - u) * nf[0] + u * nb[0],
            (1.0 - u) * nf[1] + u * nb[1],
            (1.0 - u) * nf[2] + u * nb[2] });
          const double d = std::max(Dot(n, Z), 0.0);
          return Vec{ d, d, d };
        });
      const double e = exact[0];
      const double nl = Shade(nonlinear, seg, nf, nb, Z)[0];
      const double li = Shade(linear, seg, nf, nb, Z)[0];
      std::cout << "  " << (config == 0 ? "symmetric  " : "front on V ") << std::fixed
                << std::setprecision(0) << std::setw(8) << angle << std::setprecision(6)
                << std::setw(10) << e << std::setw(11) << nl << std::setw(11) << li << std::showpos
                << std::setprecision(3) << std::setw(11) << 100.0 * (nl - e) / e << "%"
                << std::setw(11) << 100.0 * (li - e) / e << "%" << std::noshowpos
                << std::defaultfloat << "\n";
      const std::string where = std::string(config == 0 ? "symmetric" : "front-on-view") +
        " normals " + Str(angle) + " deg apart";
      if (angle <= 60.0)
      {
        // The paper's quadratic normalisation (Eq. 5) is within 0.8% of the exact norm up to
        // 60 deg (design A.3), so its integral is within 1%.
        check.Near(nl, e, 0.01 * e, "non-linear diffuse within 1% of the exact one, " + where);
      }
      check(std::abs(nl - e) < std::abs(li - e), "non-linear closer than linear, " + where);
    }
  }
}

//------------------------------------------------------------------------------
// 4. Antiparallel normals: m is clamped (cos a >= MinimumCosHalfAngle), the output finite.
void TestAntiparallel()
{
  const Segment seg = GenericSegment();
  vtkNew<Shading> model;
  const Vec x = { 1.0, 0.0, 0.0 };
  // cos a = 0 clamped to 0.5: m = 4 (1 - 0.5) / 0.5 = 4, exact in binary.
  check(model->ArcCoefficient(x.data(), Negated(x).data()) == 4.0,
    "antiparallel normals: m = 4 (cos a clamped at 0.5)");
  const Vec n = Normalized(Vec{ 1.0, 2.0, 3.0 });
  // N . -N = -1 within an ulp: cos a = sqrt(0.5 (1 + N . -N)) ~ 1e-8 < 0.5 anyway.
  check(model->ArcCoefficient(n.data(), Negated(n).data()) == 4.0,
    "antiparallel random normals: m = 4 (clamped)");
  model->SetMinimumCosHalfAngle(0.01);
  // 4 * 0.99 / 0.01 in double: a few ulps of 396.
  check.Near(model->ArcCoefficient(x.data(), Negated(x).data()),
    396.0,
    1e-12,
    "antiparallel normals, MinimumCosHalfAngle 0.01: m = 396");
  model->SetMinimumCosHalfAngle(0.0);
  check(model->GetMinimumCosHalfAngle() == 0.01, "MinimumCosHalfAngle is clamped at 0.01");

  // Finite everywhere: every mode, both lightings, Gooch, lights around, normals exactly and
  // nearly antiparallel, the loosest clamp.
  bool finite = true;
  for (double minimum : { 0.5, 0.01 })
  {
    for (bool gooch : { false, true })
    {
      for (bool twoSided : { false, true })
      {
        for (int mode = 0; mode < 3; ++mode)
        {
          auto m = Model(0.1, 0.7, 0.5, 50.0, mode, twoSided);
          m->SetGooch(gooch);
          m->SetMinimumCosHalfAngle(minimum);
          AddLight(m, Polar(40.0, 30.0));
          AddLight(m, Z, true);
          for (const Vec& nf : { x, n, Polar(89.0, 0.0) })
          {
            for (const Vec& nb : { Negated(nf), Rotated(Negated(nf), Z, 0.001) })
            {
              for (const Vec& v : { Z, Polar(60.0, 45.0), Negated(nf) })
              {
                finite = finite && Finite(Shade(m, seg, nf, nb, v));
              }
            }
          }
        }
      }
    }
  }
  check(finite, "antiparallel normals: finite output in every mode");

  // 170 deg apart, both 85 deg from the light (positive dots), one-sided: case 1 with m from
  // cos a = cos 85 deg = 0.087, clamped to 0.5: m = 4.
  const Vec nf = Polar(85.0, 0.0), nb = Polar(85.0, 180.0);
  const double f = Dot(nf, Z), b = Dot(nb, Z);
  check(f > 0.0 && b > 0.0, "the 170 deg fixture faces the light at both ends");
  for (double minimum : { 0.5, 0.01 })
  {
    auto m = DiffuseModel(Shading::NONLINEAR, false, Z);
    m->SetMinimumCosHalfAngle(minimum);
    const double ca = std::max(std::cos(Rad(85.0)), minimum), arc = 4.0 * (1.0 - ca) / ca;
    const Vec rgb = Shade(m, seg, nf, nb, Polar(30.0, 90.0));
    check.Near(
      Largest(rgb,
        [&](int c)
        { return f * seg.M[0][c] + b * seg.M[1][c] + arc * (f * seg.M[2][c] + b * seg.M[3][c]); }),
      0.0,
      Rounding,
      "normals 170 deg apart facing the light, MinimumCosHalfAngle " + Str(minimum) +
        ": f J0 + b J1 + m (f J2 + b J3), m = " + Str(arc));
  }
}

//------------------------------------------------------------------------------
// 5. Zero normals: no arc; one zero end fades the other; two zero ends give nothing.
void TestZeroNormals()
{
  const Segment seg = GenericSegment();
  vtkNew<Shading> model;
  const Vec n = Polar(30.0, 40.0);
  check(model->ArcCoefficient(Zero.data(), n.data()) == 0.0 &&
      model->ArcCoefficient(n.data(), Zero.data()) == 0.0 &&
      model->ArcCoefficient(Zero.data(), Zero.data()) == 0.0,
    "a zero normal at either end: m == 0");
  const Vec v = Polar(20.0, 200.0);
  for (bool twoSided : { false, true })
  {
    for (int mode : { Shading::LINEAR, Shading::NONLINEAR })
    {
      const std::string where =
        std::string(ModeName[mode]) + (twoSided ? ", two" : ", one") + "-sided";
      auto diffuse = DiffuseModel(mode, twoSided, Z);
      const double d = Dot(n, Z);
      check.Near(Largest(Shade(diffuse, seg, Zero, n, v), [&](int c) { return d * seg.M[1][c]; }),
        0.0,
        Rounding,
        "zero front normal: b J1, " + where);
      check.Near(Largest(Shade(diffuse, seg, n, Zero, v), [&](int c) { return d * seg.M[0][c]; }),
        0.0,
        Rounding,
        "zero back normal: f J0, " + where);
      if (twoSided)
      {
        check.Near(
          Largest(Shade(diffuse, seg, Zero, Negated(n), v), [&](int c) { return d * seg.M[1][c]; }),
          0.0,
          Rounding,
          "zero front normal, back facing away: |b| J1, " + where);
      }
      // Specular: the back normal 3 deg from H inside the cone of n = 10, the front one zero.
      const Vec h = Normalized(Vec{ v[0], v[1], v[2] + 1.0 });
      const Vec nh = Rotated(h, Vec{ 0.0, 1.0, 0.0 }, 3.0);
      const double expected = Cone(Dot(nh, h), 10.0) * seg.M[1][3];
      check.Near(Largest(Shade(SpecularModel(mode, twoSided, 10.0, Z), seg, Zero, nh, v),
                   [&](int) { return expected; }),
        0.0,
        Rounding,
        "zero front normal: cone(bh) J'1, " + where);
    }
  }
  // Both ends zero: no diffuse, and the cone at N . H = 0 is 1 - n <= 0 for n >= 1.
  bool zero = true;
  for (double power : { 1.0, 10.0, 1000.0 })
  {
    for (bool twoSided : { false, true })
    {
      for (int mode = 0; mode < 3; ++mode)
      {
        auto m = Model(0.0, 0.7, 0.5, power, mode, twoSided);
        AddLight(m, Polar(30.0, 20.0));
        AddLight(m, Z, true);
        const Vec rgb = Shade(m, seg, Zero, Zero, v);
        zero = zero && rgb[0] == 0.0 && rgb[1] == 0.0 && rgb[2] == 0.0;
      }
    }
  }
  check(zero, "zero normals at both ends: no diffuse and no specular (n = 1, 10, 1000)");
}

//------------------------------------------------------------------------------
// 6. N . L changing sign inside the segment.
void TestSignChange()
{
  const Segment seg = GenericSegment();
  const Vec v = Polar(50.0, 300.0);
  const Vec up = Polar(60.0, 0.0), down = Polar(120.0, 30.0); // N . L = 0.5 and -0.5
  const double f = Dot(up, Z), b = Dot(down, Z);
  for (int mode : { Shading::LINEAR, Shading::NONLINEAR })
  {
    const std::string name = ModeName[mode];
    auto one = DiffuseModel(mode, false, Z);
    auto two = DiffuseModel(mode, true, Z);
    check.Near(Largest(Shade(one, seg, up, down, v), [&](int c) { return f * seg.M[0][c]; }),
      0.0,
      Rounding,
      name + " one-sided, back facing away: f J0 (case 2)");
    check.Near(Largest(Shade(one, seg, down, up, v), [&](int c) { return f * seg.M[1][c]; }),
      0.0,
      Rounding,
      name + " one-sided, front facing away: b J1 (case 2)");
    check.Near(Largest(Shade(one, seg, down, Negated(up), v), [](int) { return 0.0; }),
      0.0,
      0.0,
      name + " one-sided, both facing away: 0 (case 3)");
    check.Near(Largest(Shade(two, seg, up, down, v),
                 [&](int c) { return f * seg.M[0][c] + std::abs(b) * seg.M[1][c]; }),
      0.0,
      Rounding,
      name + " two-sided, sign change: |f| J0 + |b| J1");
    check.Near(Largest(Shade(two, seg, down, up, v),
                 [&](int c) { return std::abs(b) * seg.M[0][c] + f * seg.M[1][c]; }),
      0.0,
      Rounding,
      name + " two-sided, sign change (reversed): |f| J0 + |b| J1");
    // Both facing away, two-sided: lit as the mirrored pair, with the arc between them.
    check.Near(
      Largest(Shade(two, seg, Negated(up), down, v), Shade(two, seg, up, Negated(down), v)),
      0.0,
      Rounding,
      name + " two-sided, both facing away: as both mirrored");
  }
  {
    auto two = DiffuseModel(Shading::NONLINEAR, true, Z);
    vtkNew<Shading> arc;
    const Vec nf = Negated(up), nb = down; // both N . L < 0
    const double m = arc->ArcCoefficient(nf.data(), nb.data());
    check(m > 0.1, "the both-away fixture has an arc");
    check.Near(Largest(Shade(two, seg, nf, nb, v),
                 [&](int c)
                 {
                   return -Dot(nf, Z) * seg.M[0][c] - Dot(nb, Z) * seg.M[1][c] +
                     m * (-Dot(nf, Z) * seg.M[2][c] - Dot(nb, Z) * seg.M[3][c]);
                 }),
      0.0,
      Rounding,
      "NONLINEAR two-sided, both facing away: |f| J0 + |b| J1 + m (|f| J2 + |b| J3)");
  }
  // Specular: N . H from +0.9986 to -0.9986 (n = 10, threshold 0.9).
  {
    const Vec h = Normalized(Vec{ v[0], v[1], v[2] + 1.0 });
    const Vec nf = Rotated(h, Vec{ 1.0, 0.0, 0.0 }, 3.0);
    const Vec nb = Negated(Rotated(h, Vec{ 0.0, 1.0, 0.0 }, 4.0));
    const double fh = Dot(nf, h), bh = Dot(nb, h);
    auto one = SpecularModel(Shading::NONLINEAR, false, 10.0, Z);
    auto two = SpecularModel(Shading::NONLINEAR, true, 10.0, Z);
    check.Near(
      Largest(Shade(one, seg, nf, nb, v), [&](int) { return Cone(fh, 10.0) * seg.M[0][3]; }),
      0.0,
      Rounding,
      "specular one-sided, N . H changes sign: cone(fh) J'0");
    check.Near(Largest(Shade(two, seg, nf, nb, v),
                 [&](int) { return Cone(fh, 10.0) * seg.M[0][3] + Cone(-bh, 10.0) * seg.M[1][3]; }),
      0.0,
      Rounding,
      "specular two-sided, N . H changes sign: cone(|fh|) J'0 + cone(|bh|) J'1");
  }
}

//------------------------------------------------------------------------------
// 7. A highlight between the samples (the paper's third specular case): both ends outside the
//    cone, the arc through H.
void TestHighlightBetweenSamples()
{
  const Segment seg = GenericSegment();
  const double n = 50.0, threshold = (n - 1.0) / n;
  auto model = SpecularModel(Shading::NONLINEAR, true, n, Z);
  model->RemoveAllLights();
  AddLight(model, Z, true); // headlight: H = V = z
  // Brute-force peak of p(u) = fh (1 - u) + bh u + m (fh u (1 - u)^2 + bh u^2 (1 - u)) on
  // 10^6 + 1 points: its error is at most |p''| (1e-6)^2 / 8 < 1e-12.
  auto peak = [](double fh, double bh, double m)
  {
    double best = -1e300;
    const int count = 1000000;
    for (int i = 0; i <= count; ++i)
    {
      const double u = static_cast<double>(i) / count;
      best = std::max(
        best, fh * (1 - u) + bh * u + m * (fh * u * (1 - u) * (1 - u) + bh * u * u * (1 - u)));
    }
    return best;
  };
  const Vec y = { 0.0, 1.0, 0.0 };
  for (const auto& angles :
    { std::array<double, 2>{ 15.0, -15.0 }, std::array<double, 2>{ 12.0, -20.0 } })
  {
    const Vec nf = Rotated(Z, y, angles[0]), nb = Rotated(Z, y, angles[1]);
    const double fh = Dot(nf, Z), bh = Dot(nb, Z);
    const std::string where =
      "normals at " + Str(angles[0]) + " and " + Str(angles[1]) + " deg around H, n = 50";
    check(fh < threshold && bh < threshold, "both ends outside the cone: " + where);
    const double m = model->ArcCoefficient(nf.data(), nb.data());
    double value = 0.0;
    check(Shading::InteriorMaximum(fh, bh, m, value), "InteriorMaximum finds the peak: " + where);
    const double brute = peak(fh, bh, m);
    // Cardano-free closed form against the grid: the grid's error (< 1e-12) dominates.
    check.Near(value, brute, 1e-11, "InteriorMaximum == brute-force max of p(u): " + where);
    // The tent integral I'' as 3 (J'_2 + J'_3), summed here from the steps themselves.
    const double tent = seg.Integrate(
      [](double u, const Vec&) {
        return Vec{ 3.0 * u * (1.0 - u), 0.0, 0.0 };
      })[0];
    const double expected = Cone(brute, n) * tent;
    const Vec rgb = Shade(model, seg, nf, nb, Z);
    check(rgb[0] > 0.0, "highlight between the samples: specular > 0, " + where);
    // n times the grid's error on the peak, plus rounding.
    check.Near(Largest(rgb, [&](int) { return expected; }),
      0.0,
      1e-9,
      "specular == cone(peak) 3 (J'2 + J'3), " + where);
  }
  // 3 (J'_2 + J'_3) against the paper's tent integral I'': equal for a step weight linear in u
  // (both weights are symmetric about 1/2 with integral 1/2), close on the generic segment,
  // at most 1.5 times it on an opaque segment (the limit of a weight concentrated at u = 0,
  // where 3 u (1 - u) and the tent have slopes 3 and 2).
  {
    auto ratio = [](const Segment& s) { return 3.0 * (s.M[2][3] + s.M[3][3]) / s.Tent; };
    const auto white = [](double) { return Vec{ 1.0, 1.0, 1.0 }; };
    const Segment flat = MakeSegment(
      4096, [](double) { return 1e-6; }, white);
    check.Near(ratio(flat), 1.0, 1e-6, "3 (J'2 + J'3) == I'' for a constant weight");
    const Segment ramp = MakeSegment(
      4096, [](double u) { return 1e-6 * (1.0 + 3.0 * u); }, white);
    check.Near(ratio(ramp), 1.0, 1e-6, "3 (J'2 + J'3) == I'' for a linear weight");
    std::cout << "3 (J'2 + J'3) / I'' on the generic segment: " << ratio(seg) << "\n";
    check(
      std::abs(ratio(seg) - 1.0) < 0.01, "3 (J'2 + J'3) within 1% of I'' on the generic segment");
    const Segment opaque = MakeSegment(
      4096, [](double) { return 60.0; }, white);
    check(ratio(opaque) > 1.0 && ratio(opaque) <= 1.5,
      "an opaque segment: 3 (J'2 + J'3) between I'' and 1.5 I'', got " + Str(ratio(opaque)));
  }
  // Symmetric ends: the peak is p(1/2) = fh + m fh / 4 exactly.
  {
    const double c15 = std::cos(Rad(15.0)), m = 0.3;
    double value = 0.0;
    check(Shading::InteriorMaximum(c15, c15, m, value), "symmetric ends: an interior maximum");
    check.Near(value, c15 + 0.25 * m * c15, 1e-15, "symmetric ends: maximum at u = 1/2");
  }
  // A local maximum and a local minimum both inside (0, 1) (u ~ 0.14 and 0.97 for fh = 0.97,
  // bh = -0.5, m = 4, and mirrored): the maximum is the one wanted.
  for (const auto& ends :
    { std::array<double, 2>{ 0.97, -0.5 }, std::array<double, 2>{ -0.5, 0.97 } })
  {
    double value = 0.0;
    const bool found = Shading::InteriorMaximum(ends[0], ends[1], 4.0, value);
    check(
      found && value > 0.97, "two interior critical points: an interior maximum above the ends");
    check.Near(value,
      peak(ends[0], ends[1], 4.0),
      1e-11,
      "two interior critical points: the maximum, not the minimum");
  }
  // No arc: p is linear, no interior critical point.
  double unused = 0.0;
  check(!Shading::InteriorMaximum(0.9, 0.95, 0.0, unused) &&
      !Shading::InteriorMaximum(0.95, 0.95, 0.0, unused),
    "InteriorMaximum is false for m == 0");
  // The arc passes 20 deg from H: its peak ~cos 20 deg is outside the cone, no highlight.
  {
    const Vec d = Rotated(Z, Vec{ 1.0, 0.0, 0.0 }, 20.0);
    const Vec nf = Rotated(d, y, 15.0), nb = Rotated(d, y, -15.0);
    const Vec rgb = Shade(model, seg, nf, nb, Z);
    check(rgb[0] == 0.0 && rgb[1] == 0.0 && rgb[2] == 0.0,
      "an arc that misses the cone gives no highlight");
  }
}

//------------------------------------------------------------------------------
// 8. Shininess 1 and 1000: the cone's width is acos(1 - 1/n) (2.56 deg for n = 1000).
void TestShininess()
{
  const Segment seg = GenericSegment();
  bool finite = true;
  for (double n : { 1.0, 1000.0, 1e6 })
  {
    for (int mode = 0; mode < 3; ++mode)
    {
      for (bool twoSided : { false, true })
      {
        auto m = Model(0.1, 0.7, 1.0, n, mode, twoSided);
        AddLight(m, Z, true);
        AddLight(m, Polar(50.0, 10.0));
        for (double a : { 0.0, 0.5, 5.0, 45.0, 90.0, 150.0 })
        {
          for (double b : { 0.0, 3.0, -5.0, 60.0 })
          {
            finite =
              finite && Finite(Shade(m, seg, Polar(a, 0.0), Polar(b, 90.0), Polar(10.0, 45.0)));
          }
        }
      }
    }
  }
  check(finite, "specular powers 1, 1000 and 1e6: finite output");
  // n = 1: threshold 0, the cone is N . H itself: equal normals at 60 deg from H give
  // cos 60 deg I'0.
  {
    auto m = SpecularModel(Shading::NONLINEAR, false, 1.0, Z);
    const double expected = Dot(Polar(60.0, 0.0), Z) * (seg.M[0][3] + seg.M[1][3]);
    check.Near(
      Largest(Shade(m, seg, Polar(60.0, 0.0), Polar(60.0, 0.0), Z), [&](int) { return expected; }),
      0.0,
      Rounding,
      "n = 1: the cone is N . H");
  }
  // n = 1000, headlight (H = V = z), equal normals.
  auto m = SpecularModel(Shading::NONLINEAR, true, 1000.0, Z);
  m->RemoveAllLights();
  AddLight(m, Z, true);
  const Vec far = Polar(5.0, 30.0), near = Polar(0.5, 30.0);
  check(Shade(m, seg, far, far, Z)[0] == 0.0, "n = 1000: no specular 5 deg from H");
  const double expected = Cone(Dot(near, Z), 1000.0) * (seg.M[0][3] + seg.M[1][3]);
  const Vec rgb = Shade(m, seg, near, near, Z);
  check(rgb[0] > 0.0, "n = 1000: specular > 0 0.5 deg from H");
  // The cone multiplies the rounding of N . H by n = 1000.
  check.Near(rgb[0], expected, 1000.0 * Rounding, "n = 1000, 0.5 deg from H: cone(N.H) I'0");
  // Normals 5 deg either side of H: the arc crosses the narrow cone.
  check(Shade(m, seg, Polar(5.0, 0.0), Polar(5.0, 180.0), Z)[0] > 0.0,
    "n = 1000: a highlight between normals 5 deg either side of H");
}

//------------------------------------------------------------------------------
// 9. Several lights: the sum of the single lights (ambient once); a headlight is a light
//    along the view.
void TestSeveralLights()
{
  const Segment seg = GenericSegment();
  const Vec l1 = Polar(35.0, 20.0), l2 = Polar(70.0, 200.0);
  const Vec c1 = { 0.9, 0.7, 0.5 }, c2 = { 0.3, 0.6, 1.0 }, s1 = { 1.0, 1.0, 1.0 },
            s2 = { 0.5, 0.5, 0.2 };
  const Vec v = Polar(20.0, 100.0);
  for (int mode = 0; mode < 3; ++mode)
  {
    for (bool twoSided : { false, true })
    {
      auto both = Model(0.15, 0.7, 0.4, 10.0, mode, twoSided);
      auto first = Model(0.15, 0.7, 0.4, 10.0, mode, twoSided);
      auto second = Model(0.15, 0.7, 0.4, 10.0, mode, twoSided);
      AddLight(both, l1, false, c1, s1);
      AddLight(both, l2, false, c2, s2);
      AddLight(first, l1, false, c1, s1);
      AddLight(second, l2, false, c2, s2);
      check(both->GetNumberOfLights() == 2, "two lights added");
      double worst = 0.0;
      for (const auto& normals : { std::array<Vec, 2>{ Polar(30.0, 0.0), Polar(50.0, 40.0) },
             std::array<Vec, 2>{ Polar(100.0, 10.0), Polar(20.0, 200.0) },
             std::array<Vec, 2>{ Polar(150.0, 0.0), Polar(130.0, 60.0) } })
      {
        const Vec all = Shade(both, seg, normals[0], normals[1], v);
        const Vec a = Shade(first, seg, normals[0], normals[1], v);
        const Vec b = Shade(second, seg, normals[0], normals[1], v);
        worst =
          std::max(worst, Largest(all, [&](int c) { return a[c] + b[c] - 0.15 * seg.I0(c); }));
        const Vec p = ShadePoint(both, normals[0], v, c1);
        const Vec pa = ShadePoint(first, normals[0], v, c1);
        const Vec pb = ShadePoint(second, normals[0], v, c1);
        worst = std::max(worst, Largest(p, [&](int c) { return pa[c] + pb[c] - 0.15 * c1[c]; }));
      }
      check.Near(worst,
        0.0,
        Rounding,
        std::string(ModeName[mode]) + (twoSided ? ", two" : ", one") +
          "-sided: two lights == the sum of single lights minus one ambient");
    }
  }
  // A headlight follows the view: the same as a directional light along it, whatever its
  // stored direction.
  double worst = 0.0;
  for (const Vec& view : { Z, Polar(40.0, 70.0), Polar(120.0, 250.0) })
  {
    for (int mode = 0; mode < 3; ++mode)
    {
      auto head = Model(0.1, 0.7, 0.4, 10.0, mode, true);
      auto along = Model(0.1, 0.7, 0.4, 10.0, mode, true);
      AddLight(head, Polar(80.0, 0.0), true, c1, s2);
      AddLight(along, view, false, c1, s2);
      worst = std::max({ worst,
        Largest(Shade(head, seg, Polar(30.0, 0.0), Polar(50.0, 40.0), view),
          Shade(along, seg, Polar(30.0, 0.0), Polar(50.0, 40.0), view)),
        Largest(ShadePoint(head, Polar(30.0, 0.0), view, c2),
          ShadePoint(along, Polar(30.0, 0.0), view, c2)) });
    }
  }
  check.Near(worst, 0.0, Rounding, "a headlight == a directional light along the view");
}

//------------------------------------------------------------------------------
// 10. Gooch: linear in N . L, so the segment integral of the point shading is exact for equal
//     normals, and negative N . L needs no cases.
void TestGooch()
{
  const Segment seg = GenericSegment();
  const Vec l = Polar(40.0, 30.0), v = Polar(15.0, 250.0);
  auto make = [&](int mode, bool twoSided, bool headlight)
  {
    auto m = Model(0.1, 0.7, 0.4, 10.0, mode, twoSided);
    m->SetGooch(true);
    AddLight(m, headlight ? Polar(90.0, 0.0) : l, headlight);
    AddLight(m, Polar(80.0, 180.0)); // ignored: Gooch uses the first light
    return m;
  };
  double worst = 0.0;
  for (int mode = 0; mode < 3; ++mode)
  {
    for (bool twoSided : { false, true })
    {
      for (bool headlight : { false, true })
      {
        auto m = make(mode, twoSided, headlight);
        // N . L from 0.9 to -0.9.
        for (double angle : { 10.0, 60.0, 100.0, 170.0 })
        {
          const Vec n = Rotated(headlight ? v : l, Vec{ 1.0, -1.0, 0.0 }, angle);
          const Vec integral =
            seg.Integrate([&](double, const Vec& c) { return ShadePoint(m, n, v, c); });
          worst = std::max(worst, Largest(Shade(m, seg, n, n, v), integral));
        }
      }
    }
  }
  // Sums of 400 steps of O(1) values.
  check.Near(worst,
    0.0,
    Rounding,
    "Gooch, equal normals (N . L of both signs): segment == integral of ShadePoint");

  // The point formula: 1/2 (cool + a Kd c)(1 + N.L) + 1/2 (warm + b Kd c)(1 - N.L).
  {
    auto m = make(Shading::NONLINEAR, true, false);
    const Vec c = { 0.3, 0.5, 0.9 }, n = Polar(130.0, 10.0);
    const double nl = Dot(n, LightDirection(m, 0));
    const Vec rgb = ShadePoint(m, n, v, c);
    const double cool[3] = { 0.0, 0.0, 0.4 }, warm[3] = { 0.4, 0.4, 0.0 };
    check.Near(Largest(rgb,
                 [&](int k)
                 {
                   return 0.5 * (cool[k] + 0.2 * 0.7 * c[k]) * (1 + nl) +
                     0.5 * (warm[k] + 0.6 * 0.7 * c[k]) * (1 - nl);
                 }),
      0.0,
      Rounding,
      "Gooch ShadePoint: Eq. 11 with the default tones and weights");
  }
  // N . L changing sign with the arc: no cases, P = f J0 + b J1 + m (f J2 + b J3), negative
  // parts included, one- and two-sided alike.
  for (bool twoSided : { false, true })
  {
    auto m = make(Shading::NONLINEAR, twoSided, false);
    const Vec nf = Rotated(l, Vec{ 0.0, 1.0, 0.0 }, 30.0),
              nb = Rotated(l, Vec{ 1.0, 0.0, 0.0 }, 150.0);
    const double f = Dot(nf, LightDirection(m, 0)), b = Dot(nb, LightDirection(m, 0));
    check(f > 0.0 && b < 0.0, "the Gooch sign-change fixture");
    const double arc = m->ArcCoefficient(nf.data(), nb.data());
    auto P = [&](int c)
    { return f * seg.M[0][c] + b * seg.M[1][c] + arc * (f * seg.M[2][c] + b * seg.M[3][c]); };
    const double cool[3] = { 0.0, 0.0, 0.4 }, warm[3] = { 0.4, 0.4, 0.0 };
    check.Near(Largest(Shade(m, seg, nf, nb, v),
                 [&](int c)
                 {
                   return 0.5 * (cool[c] + warm[c]) * (seg.M[0][3] + seg.M[1][3]) +
                     0.5 * 0.7 * (0.2 + 0.6) * seg.I0(c) + 0.5 * (cool[c] - warm[c]) * P(3) +
                     0.5 * 0.7 * (0.2 - 0.6) * P(c);
                 }),
      0.0,
      Rounding,
      std::string("Gooch, N . L changing sign (") + (twoSided ? "two" : "one") +
        "-sided): no cases, the non-linear profile with its negative part");
  }
}

//------------------------------------------------------------------------------
// 11. ShadePoint: the lobe and the cone.
void TestShadePoint()
{
  const Vec c = { 0.8, 0.4, 0.2 };
  const double ka = 0.1, kd = 0.7, ks = 0.3, n = 20.0;
  const Vec v = Polar(25.0, 300.0);
  for (int model : { Shading::LOBE, Shading::CONE })
  {
    for (bool twoSided : { false, true })
    {
      auto m = Model(ka, kd, ks, n, Shading::NONLINEAR, twoSided);
      m->SetSpecularModel(model);
      AddLight(m, Polar(30.0, 10.0));
      const Vec l = LightDirection(m, 0);
      // H as the class forms it: (L + V) over its norm.
      Vec h = { l[0] + v[0], l[1] + v[1], l[2] + v[2] };
      const double norm = std::sqrt(Dot(h, h));
      for (double& x : h)
      {
        x /= norm;
      }
      double worst = 0.0;
      for (double theta : { 0.0, 10.0, 25.0, 50.0, 89.0, 100.0, 150.0, 179.0 })
      {
        for (double phi : { 0.0, 190.0 })
        {
          const Vec nn = Rotated(h, Vec{ std::cos(Rad(phi)), std::sin(Rad(phi)), 0.0 }, theta);
          double nl = Dot(nn, l), nh = Dot(nn, h);
          if (twoSided)
          {
            nl = std::abs(nl);
            nh = std::abs(nh);
          }
          const double spec = model == Shading::LOBE ? (nh > 0.0 ? std::pow(nh, n) : 0.0)
                                                     : std::max(1.0 + n * (nh - 1.0), 0.0);
          const Vec rgb = ShadePoint(m, nn, v, c);
          worst = std::max(worst,
            Largest(
              rgb, [&](int k) { return ka * c[k] + (kd * std::max(nl, 0.0) * c[k] + ks * spec); }));
        }
      }
      // The class' own operations in the same order: exact.
      check.Near(worst,
        0.0,
        0.0,
        std::string(model == Shading::LOBE ? "LOBE" : "CONE") + (twoSided ? " two" : " one") +
          "-sided ShadePoint: Ka c + Kd c max(N.L, 0) + Ks spec(N.H), exactly");
      const Vec ambient = ShadePoint(m, Zero, v, c);
      check(ambient[0] == ka * c[0] && ambient[1] == ka * c[1] && ambient[2] == ka * c[2],
        "ShadePoint of a zero normal: ambient only");
    }
  }
  // The cone at its apex and at its edge acos(1 - 1/n).
  auto m = Model(0.0, 0.0, 1.0, n, Shading::NONLINEAR, false);
  m->SetSpecularModel(Shading::CONE);
  AddLight(m, Z, true);
  check.Near(ShadePoint(m, Z, Z, c)[0], 1.0, 0.0, "cone at N = H: 1");
  check.Near(ShadePoint(m, Polar(std::acos(1.0 - 1.0 / n) * 180.0 / Pi, 0.0), Z, c)[0],
    0.0,
    Rounding * n,
    "cone at its edge acos(1 - 1/n): 0");
  check(ShadePoint(m, Polar(30.0, 0.0), Z, c)[0] == 0.0, "cone outside its edge: 0");
  // No lights: ambient only.
  auto dark = Model(0.25, 0.7, 0.3, 10.0, Shading::NONLINEAR, true);
  const Vec rgb = ShadePoint(dark, Z, Z, c);
  check(rgb[0] == 0.25 * c[0] && rgb[2] == 0.25 * c[2], "ShadePoint without lights: ambient");
}

//------------------------------------------------------------------------------
// 12. TransformLights: directions by the inverse of the volume's matrix.
void TestTransformLights()
{
  vtkNew<Shading> model;
  const Vec d1 = Polar(30.0, 40.0), d2 = Normalized(Vec{ -1.0, 2.0, 0.5 });
  AddLight(model, d1);
  AddLight(model, d2, true);
  check(model->TransformLights(nullptr), "no matrix: nothing to do");
  // A rotation by 40 deg about (1, 2, 3) with a translation: the directions by R^T = R^-1.
  const Vec axis = Normalized(Vec{ 1.0, 2.0, 3.0 });
  vtkNew<vtkMatrix4x4> matrix;
  for (int col = 0; col < 3; ++col)
  {
    Vec e = { 0.0, 0.0, 0.0 };
    e[col] = 1.0;
    const Vec r = Rotated(e, axis, 40.0);
    for (int row = 0; row < 3; ++row)
    {
      matrix->SetElement(row, col, r[row]);
    }
  }
  matrix->SetElement(0, 3, 5.0);
  matrix->SetElement(1, 3, -3.0);
  matrix->SetElement(2, 3, 2.0);
  check(model->TransformLights(matrix), "a rotation is invertible");
  bool headlight = false;
  const Vec t1 = LightDirection(model, 0), t2 = LightDirection(model, 1, &headlight);
  // A 4x4 inverse and a normalisation of unit vectors: a few ulps.
  check.Near(Largest(t1, Rotated(d1, axis, -40.0)),
    0.0,
    Rounding,
    "rotated volume: light direction rotated back");
  check.Near(Largest(t2, Rotated(d2, axis, -40.0)),
    0.0,
    Rounding,
    "rotated volume: second light rotated back");
  check(headlight, "the headlight flag survives the transformation");
  // A non-uniform scale: M^-1 d, normalised.
  vtkNew<vtkMatrix4x4> scale;
  scale->SetElement(0, 0, 2.0);
  scale->SetElement(2, 2, 0.5);
  const Vec before = LightDirection(model, 0);
  check(model->TransformLights(scale), "a scale is invertible");
  check.Near(Largest(LightDirection(model, 0),
               Normalized(Vec{ before[0] / 2.0, before[1], before[2] * 2.0 })),
    0.0,
    Rounding,
    "scaled volume: the direction by the inverse scale, normalised");
  // Singular: false, the lights unchanged.
  const Vec kept = LightDirection(model, 0);
  vtkNew<vtkMatrix4x4> flat;
  flat->SetElement(1, 1, 0.0);
  check(!model->TransformLights(flat), "a singular matrix is refused");
  const Vec after = LightDirection(model, 0);
  check(after == kept, "a refused matrix leaves the lights alone");
  vtkNew<vtkMatrix4x4> nothing;
  for (int r = 0; r < 4; ++r)
  {
    nothing->SetElement(r, r, 0.0);
  }
  check(!model->TransformLights(nothing), "the zero matrix is refused");
  // Determinant 1e-310 (subnormal, not 0): the inverse overflows to infinity.
  vtkNew<vtkMatrix4x4> thin;
  thin->SetElement(0, 0, 1e-310);
  check(!model->TransformLights(thin), "a matrix whose inverse overflows is refused");
  check(LightDirection(model, 0) == kept, "... and leaves the lights alone");
  // Run under valgrind, the singular matrices above also check that nothing reads an inverse
  // vtkMatrix4x4::Invert left unset (it does not write one for a zero determinant).
}

//------------------------------------------------------------------------------
// 13. SetLightsFromRenderer (no render window needed).
void TestLightsFromRenderer()
{
  vtkNew<vtkRenderer> renderer;
  vtkNew<vtkCamera> camera;
  camera->SetPosition(3.0, -2.0, 5.0);
  camera->SetFocalPoint(0.5, 1.0, -1.0);
  camera->SetViewUp(0.0, 1.0, 0.0);
  renderer->SetActiveCamera(camera);
  vtkNew<vtkLight> head, cameraLight, positional, off;
  head->SetLightTypeToHeadlight();
  cameraLight->SetLightTypeToCameraLight();
  cameraLight->SetPosition(0.0, 0.0, 1.0);
  cameraLight->SetFocalPoint(0.0, 0.0, 0.0);
  cameraLight->SetDiffuseColor(1.0, 0.5, 0.25);
  cameraLight->SetSpecularColor(0.2, 0.4, 0.8);
  cameraLight->SetIntensity(0.5);
  positional->SetLightTypeToSceneLight();
  positional->SetPositional(true);
  off->SetLightTypeToSceneLight();
  off->SwitchOff();
  renderer->AddLight(head);
  renderer->AddLight(cameraLight);
  renderer->AddLight(positional);
  renderer->AddLight(off);

  vtkNew<Shading> model;
  AddLight(model, Z); // replaced
  renderer->TwoSidedLightingOff();
  check(model->SetLightsFromRenderer(renderer) == 1, "one positional light skipped");
  check(model->GetNumberOfLights() == 2, "two directional lights taken (switched-off one left)");
  check(!model->GetTwoSidedLighting(), "TwoSidedLighting off follows the renderer");
  if (model->GetNumberOfLights() == 2)
  {
    Vec d, diffuse, specular;
    bool headlight = false;
    model->GetLight(0, d.data(), diffuse.data(), specular.data(), headlight);
    check(headlight, "the headlight is flagged");
    model->GetLight(1, d.data(), diffuse.data(), specular.data(), headlight);
    check(!headlight, "the camera light is not a headlight");
    Vec dop;
    camera->GetDirectionOfProjection(dop.data());
    // Camera (0, 0, 1) is the camera's position, (0, 0, 0) its focal point: the light shines
    // against the direction of projection; a 4x4 transform of two points, then normalised.
    check.Near(Largest(d, Negated(dop)),
      0.0,
      Rounding,
      "camera light at (0, 0, 1): direction == -direction of projection");
    check.Near(Largest(diffuse, Vec{ 0.5, 0.25, 0.125 }),
      0.0,
      0.0,
      "camera light diffuse colour times intensity");
    check.Near(Largest(specular, Vec{ 0.1, 0.2, 0.4 }),
      0.0,
      1e-16,
      "camera light specular colour times intensity");
  }
  renderer->TwoSidedLightingOn();
  model->SetLightsFromRenderer(renderer);
  check(model->GetTwoSidedLighting(), "TwoSidedLighting on follows the renderer");
  check(model->SetLightsFromRenderer(nullptr) == 0 && model->GetNumberOfLights() == 0,
    "no renderer: no lights");
}

//------------------------------------------------------------------------------
// 14. The moment layers of vtkSecondOrderPreIntegrationTable.
void TestMomentTables()
{
  vtkNew<vtkColorTransferFunction> color;
  color->AddRGBPoint(0.0, 1.0, 0.2, 0.0);
  color->AddRGBPoint(1.0, 0.0, 0.5, 1.0);
  vtkNew<vtkPiecewiseFunction> opacity;
  opacity->AddPoint(0.0, 0.0);
  opacity->AddPoint(1.0, 0.9);
  vtkNew<vtkVolumeProperty> property;
  property->SetColor(color);
  property->SetScalarOpacity(opacity);
  property->SetScalarOpacityUnitDistance(1.0);
  const int nc = 33, nb = 9;
  auto make = [&](int moments, int deviations)
  {
    auto table = vtkSmartPointer<vtkSecondOrderPreIntegrationTable>::New();
    table->SetVolumeProperty(property);
    table->SetScalarRange(0.0, 1.0);
    table->SetTableSize(nc);
    table->SetChordSize(nb);
    table->SetDeviationSize(deviations);
    table->SetSegmentLength(1.0);
    table->SetMoments(moments);
    return table;
  };
  auto rgba = make(0, 1);
  auto moments = make(4, 1);
  check(rgba->Update() && moments->Update(), "the RGBA and the moment tables build");
  check(rgba->GetNumberOfLayers() == 1 && moments->GetNumberOfLayers() == 4,
    "layers: 1 without moments, 4 with Moments 4");
  check(make(4, 3)->GetNumberOfLayers() == 1, "Moments ignored (1 layer) with DeviationSize 3");
  check(make(2, 1)->GetNumberOfLayers() == 2, "Moments 2: 2 layers");
  check(moments->GetMemorySize() == 4 * rgba->GetMemorySize() &&
      moments->GetNumberOfEntries() == 4 * nc * nb,
    "four layers: four times the memory and the entries");

  // Layers 0 + 1 are the RGBA (weights (1 - u) + u = 1), over the same steps.
  double worstRelative = 0.0;
  for (int i = 0; i < nc; ++i)
  {
    for (int j = 0; j < nb; ++j)
    {
      double a[4], j0[4], j1[4];
      rgba->GetEntry(i, j, 0, a);
      moments->GetEntry(i, j, 0, j0);
      moments->GetEntry(i, j, 1, j1);
      for (int c = 0; c < 4; ++c)
      {
        const double difference = std::abs(j0[c] + j1[c] - a[c]);
        worstRelative = std::max(worstRelative, difference / std::max(std::abs(a[c]), 1e-6));
      }
    }
  }
  // Float sums of up to 64 steps, (1 - u) + u rounded once more: ~100 float ulps at most
  // (values below 1e-6, near-empty entries, are compared absolutely at 1e-11).
  check.Near(worstRelative, 0.0, 1e-5, "layers 0 + 1 == the RGBA table (relative)");

  // Entries against the moments of the linear path in double: 20000 midpoint steps, the
  // transfer function through the table's sampler, the scalar clamped to the range.
  vtkVolumeTransferFunctionSampler* sampler = moments->GetSampler();
  auto reference = [&](int i, int j, double out[4][4])
  {
    double path[3];
    moments->GetEntryPath(i, j, 0, path);
    for (int l = 0; l < 4; ++l)
    {
      std::fill(out[l], out[l] + 4, 0.0);
    }
    const int steps = 20000;
    const double h = 1.0 / steps; // segment length 1
    double transmittance = 1.0;
    for (int m = 0; m < steps; ++m)
    {
      const double u = (m + 0.5) / steps;
      const double s = std::min(std::max(path[0] + path[1] * u, 0.0), 1.0);
      double rgbTau[4];
      sampler->Evaluate(s, rgbTau);
      const double alpha = -std::expm1(-rgbTau[3] * h);
      const double w = transmittance * alpha;
      const double weights[4] = { 1.0 - u, u, u * (1.0 - u) * (1.0 - u), u * u * (1.0 - u) };
      for (int l = 0; l < 4; ++l)
      {
        for (int c = 0; c < 3; ++c)
        {
          out[l][c] += w * rgbTau[c] * weights[l];
        }
        out[l][3] += w * weights[l];
      }
      transmittance *= 1.0 - alpha;
    }
  };
  double worst = 0.0;
  // Chord 0 (j = 4), and chords with their mirrors (j, 8 - j), near both ends of the range
  // (clamped paths) and inside.
  const int entries[][2] = { { 16, 4 },
    { 0, 4 },
    { 32, 4 },
    { 10, 0 },
    { 10, 8 },
    { 20, 2 },
    { 20, 6 },
    { 3, 1 },
    { 3, 7 },
    { 30, 3 },
    { 30, 5 } };
  std::cout << "Moment layers against the double-precision path integral (largest |difference| "
               "over the channels):\n";
  for (const auto& e : entries)
  {
    double expected[4][4];
    reference(e[0], e[1], expected);
    double entryWorst = 0.0;
    for (int l = 0; l < 4; ++l)
    {
      double v[4];
      moments->GetEntry(e[0], e[1], l, v);
      for (int c = 0; c < 4; ++c)
      {
        entryWorst = std::max(entryWorst, std::abs(v[c] - expected[l][c]));
      }
    }
    std::cout << "  centre " << e[0] << ", chord " << e[1] << ": " << entryWorst
              << " (J'0 + J'1 = " << expected[0][3] + expected[1][3] << ")\n";
    worst = std::max(worst, entryWorst);
  }
  // The table's float midpoint steps (at least 16) weight each step's alpha by the position
  // weights' average over the step, ignoring the transmittance's slope inside it: an error
  // of about tau^2 / 12 / steps^2 ~ 1e-3 at tau = 2.3 and 16 steps.
  check.Near(worst, 0.0, 2e-3, "moment entries == the double-precision path integral");
}
}

int TestVolumeShadingModel(int, char*[])
{
  hovrTest::MessageCapture messages;
  TestEqualNormals();
  TestMonomialForm();
  TestExactNormalisation();
  TestAntiparallel();
  TestZeroNormals();
  TestSignChange();
  TestHighlightBetweenSamples();
  TestShininess();
  TestSeveralLights();
  TestGooch();
  TestShadePoint();
  TestTransformLights();
  TestLightsFromRenderer();
  TestMomentTables();
  messages.ExpectNone(check, "during the test");
  return check.Result("TestVolumeShadingModel");
}
