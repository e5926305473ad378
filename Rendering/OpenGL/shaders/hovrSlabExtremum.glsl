// hovr: the extremum of a second-order slab's scalar path, shared by the second-order ray
// caster (hovrPreIntegration2.glsl) and the GPU table builder (hovrPreIntegration2Build.glsl);
// vtkSecondOrderPreIntegrationTableKernel::SlabExtremum is its CPU mirror, in the same float
// operations.
//
// The quadratic path x(t) = x0 + t (b + a t) over t in [0, 1] (El Hajjar et al., Eq. 2) spans
// the range of its ends and, when its vertex lies inside, of its extremum: true and the
// extremum's value when it does.
bool hovr_slabExtremum(float x0, float b, float a, out float extremum)
{
  extremum = x0;
  if (a == 0.0)
  {
    return false;
  }
  float vertex = -b / (2.0 * a);
  if (!(vertex > 0.0 && vertex < 1.0))
  {
    return false;
  }
  extremum = x0 + vertex * (b + a * vertex);
  return true;
}
