// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
#include "vtkObjectOrderRayCasterShading.h"

#include "vtkDataArray.h"
#include "vtkImageData.h"
#include "vtkMatrix4x4.h"
#include "vtkObjectOrderRayCasterBricks.h"
#include "vtkSMPTools.h"
#include "vtkVolumeProperty.h"

#include <algorithm>

namespace
{
// Octahedral bins of unit directions for pre-shading: Bins x Bins of them (8100, about the
// paper's 8192).
constexpr int Bins = 90;

// The octahedral map of a unit direction to [-1, 1]^2 and back.
void FoldOctahedron(double p[2])
{
  const double q[2] = { (1.0 - std::abs(p[1])) * (p[0] >= 0.0 ? 1.0 : -1.0),
    (1.0 - std::abs(p[0])) * (p[1] >= 0.0 ? 1.0 : -1.0) };
  p[0] = q[0];
  p[1] = q[1];
}

int DirectionBin(const double n[3])
{
  const double l1 = std::abs(n[0]) + std::abs(n[1]) + std::abs(n[2]);
  double p[2] = { n[0] / l1, n[1] / l1 };
  if (n[2] < 0.0)
  {
    FoldOctahedron(p);
  }
  const int i = std::min(std::max(static_cast<int>((p[0] + 1.0) * 0.5 * Bins), 0), Bins - 1);
  const int j = std::min(std::max(static_cast<int>((p[1] + 1.0) * 0.5 * Bins), 0), Bins - 1);
  return i + Bins * j;
}

void BinDirection(int bin, double n[3])
{
  double p[2] = { ((bin % Bins) + 0.5) / Bins * 2.0 - 1.0,
    ((bin / Bins) + 0.5) / Bins * 2.0 - 1.0 };
  n[2] = 1.0 - std::abs(p[0]) - std::abs(p[1]);
  if (n[2] < 0.0)
  {
    FoldOctahedron(p);
  }
  n[0] = p[0];
  n[1] = p[1];
  vtkMath::Normalize(n);
}
}

//------------------------------------------------------------------------------
void vtkObjectOrderRayCasterShading::Update(int mode,
  vtkImageData* input,
  vtkVolumeProperty* property,
  const double viewDirection[3],
  vtkMatrix4x4* worldToData)
{
  this->Mode = mode;
  if (mode == NONE)
  {
    return;
  }
  const double* m = input->GetPhysicalToIndexMatrix()->GetData();
  for (int r = 0; r < 3; ++r)
  {
    for (int k = 0; k < 3; ++k)
    {
      this->ToData[r][k] = m[4 * k + r]; // transposed: data gradient = M^T index gradient
    }
  }
  // Minus the view direction, taken back through the volume's placement (exact for rigid
  // placements; scaled ones tilt normals, as for any mapper shading in data space).
  double light[4] = { -viewDirection[0], -viewDirection[1], -viewDirection[2], 0.0 };
  worldToData->MultiplyPoint(light, light);
  std::copy(light, light + 3, this->Light);
  vtkMath::Normalize(this->Light);
  this->Ambient = static_cast<float>(property->GetAmbient(0));
  this->Diffuse = static_cast<float>(property->GetDiffuse(0));
  this->Specular = static_cast<float>(property->GetSpecular(0));
  this->Power = static_cast<float>(property->GetSpecularPower(0));
}

//------------------------------------------------------------------------------
bool vtkObjectOrderRayCasterShading::HasNormalsOf(vtkDataArray* scalars,
  const vtkObjectOrderRayCasterBricks& volume) const
{
  return this->DirectionScalars == scalars && this->DirectionTime >= scalars->GetMTime() &&
    this->Directions.size() == volume.Bricks.size() &&
    std::equal(&this->ToData[0][0], &this->ToData[0][0] + 9, &this->DirectionToData[0][0]);
}

//------------------------------------------------------------------------------
void vtkObjectOrderRayCasterShading::QuantizeNormals(vtkDataArray* scalars,
  const vtkObjectOrderRayCasterBricks& volume)
{
  this->Directions.assign(volume.Bricks.size(), static_cast<uint16_t>(Bins * Bins));
  const int* dims = volume.Dims;
  vtkSMPTools::For(0,
    dims[2],
    [&](vtkIdType k0, vtkIdType k1)
    {
      for (int z = static_cast<int>(k0); z < k1; ++z)
      {
        for (int y = 0; y < dims[1]; ++y)
        {
          for (int x = 0; x < dims[0]; ++x)
          {
            float g[3];
            volume.Gradient(x, y, z, g);
            double n[3];
            this->DataNormal(g, n);
            if (vtkMath::Normalize(n) > 0.0)
            {
              this->Directions[volume.Address(x, y, z)] = static_cast<uint16_t>(DirectionBin(n));
            }
          }
        }
      }
    });
  this->DirectionScalars = scalars;
  this->DirectionTime = scalars->GetMTime();
  std::copy(&this->ToData[0][0], &this->ToData[0][0] + 9, &this->DirectionToData[0][0]);
}

//------------------------------------------------------------------------------
void vtkObjectOrderRayCasterShading::BuildReflectanceMap()
{
  this->Reflectance.resize(2 * (Bins * Bins + 1));
  for (int bin = 0; bin < Bins * Bins; ++bin)
  {
    double n[3];
    BinDirection(bin, n);
    this->Lighting(std::abs(vtkMath::Dot(n, this->Light)),
      this->Reflectance[2 * bin],
      this->Reflectance[2 * bin + 1]);
  }
  this->Reflectance[2 * Bins * Bins] = this->Ambient;
  this->Reflectance[2 * Bins * Bins + 1] = 0.0f;
}

//------------------------------------------------------------------------------
void vtkObjectOrderRayCasterShading::ReleaseNormals()
{
  std::vector<uint16_t>().swap(this->Directions);
  this->DirectionScalars = nullptr;
}
