// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
/**
 * @class   vtkObjectOrderRayCasterShading
 * @brief   the headlight of vtkObjectOrderRayCaster, and its pre-shading normals
 *
 * A white headlight along the view with the volume property's ambient, diffuse, specular and
 * specular power, two-sided (|n.l|). Gradients are taken in grid index units (central
 * differences) and turned into data-space normals by ToData (the transposed physical-to-index
 * matrix); Light is the headlight in data space. Pre-shading (the paper's section 4.3.2)
 * quantizes each point's normal once per volume to one of 8100 octahedral bins (one more
 * index for "no gradient") and builds, per frame, each bin's (ambient + diffuse |n.l|,
 * specular |n.l|^power): the reflectance map.
 *
 * Part of vtkObjectOrderRayCaster's frame: a value class for its inner loops (not a
 * vtkObject, not wrapped, not installed).
 */
#ifndef vtkObjectOrderRayCasterShading_h
#define vtkObjectOrderRayCasterShading_h

#include "vtkMath.h" // For vtkMath::Dot, vtkMath::Norm
#include "vtkType.h" // For vtkMTimeType

#include <cmath>   // For std::abs, std::pow
#include <cstdint> // For uint16_t
#include <vector>  // For std::vector

class vtkDataArray;
class vtkImageData;
class vtkMatrix4x4;
class vtkObjectOrderRayCasterBricks;
class vtkVolumeProperty;

class vtkObjectOrderRayCasterShading
{
public:
  enum Modes
  {
    NONE = 0,
    POST_SHADING = 1, ///< gradients interpolated and shaded at every sample
    PRE_SHADING = 2   ///< quantized normals, vertices shaded, shading interpolated
  };

  /**
   * The mode, and when it shades, the light of the rays of direction viewDirection (world)
   * in the data space of input (placed in the world by the inverse of worldToData) with the
   * property's coefficients.
   */
  void Update(int mode,
    vtkImageData* input,
    vtkVolumeProperty* property,
    const double viewDirection[3],
    vtkMatrix4x4* worldToData);

  /**
   * Whether the quantized normals are those of the volume's scalars, as they are now, with
   * the current ToData.
   */
  bool HasNormalsOf(vtkDataArray* scalars, const vtkObjectOrderRayCasterBricks& volume) const;

  /**
   * Each point's quantized data-space normal, at the point's address in the volume's bricks.
   * Throws std::bad_alloc when the memory runs out.
   */
  void QuantizeNormals(vtkDataArray* scalars, const vtkObjectOrderRayCasterBricks& volume);

  /**
   * The reflectance map of the bins for the current light; the last entry has no normal
   * (ambient).
   */
  void BuildReflectanceMap();

  /**
   * Free the quantized normals (not just empty them).
   */
  void ReleaseNormals();

  /**
   * Bytes of the quantized normals.
   */
  size_t GetMemorySize() const { return this->Directions.size() * sizeof(uint16_t); }

  /**
   * The data-space normal (not normalised) of an index-space gradient.
   */
  void DataNormal(const float g[3], double n[3]) const
  {
    for (int r = 0; r < 3; ++r)
    {
      n[r] = this->ToData[r][0] * g[0] + this->ToData[r][1] * g[1] + this->ToData[r][2] * g[2];
    }
  }

  /**
   * |n.l| for the headlight of the data-space normal of an index-space gradient; -1 when the
   * gradient vanishes (no normal: ambient light only).
   */
  double LightCosine(const float g[3]) const
  {
    double n[3];
    this->DataNormal(g, n);
    const double norm = vtkMath::Norm(n);
    return norm > 0.0 ? std::abs(vtkMath::Dot(n, this->Light)) / norm : -1.0;
  }

  /**
   * The lighting of a normal at cosine nl (-1: none): the factor on the transfer function's
   * colour (ambient + diffuse |n.l|) and the added highlight (specular |n.l|^power).
   */
  void Lighting(double nl, float& shade, float& highlight) const
  {
    shade = nl < 0.0 ? this->Ambient : this->Ambient + this->Diffuse * static_cast<float>(nl);
    highlight = nl > 0.0 ? this->Specular * static_cast<float>(std::pow(nl, this->Power)) : 0.0f;
  }

  int Mode = NONE;
  double ToData[3][3];
  double Light[3];
  float Ambient = 0, Diffuse = 1, Specular = 0, Power = 1;
  // Pre-shading: each point's bin (Bins^2 for no gradient) and, per frame, each bin's
  // (shade, highlight).
  std::vector<uint16_t> Directions;
  vtkDataArray* DirectionScalars = nullptr; // not referenced: only compared
  vtkMTimeType DirectionTime = 0;
  double DirectionToData[3][3] = {}; // the ToData the directions were quantized with
  std::vector<float> Reflectance;
};

#endif
