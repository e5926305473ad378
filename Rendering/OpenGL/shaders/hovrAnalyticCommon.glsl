// hovr: what vtkAnalyticVolumeMapper's analytic and stock modes share: the output that
// replaces the colour for measurements and the map from texture coordinates to grid index.

uniform vec2 hovr_rawToData; // data value = raw texture value * x + y

// What HOVR_OUTPUT 1 (hit position) and 2 (extremum) write instead of the colour.
vec4 hovr_output = vec4(0.0);

// Continuous grid index (point i at i) of a texture coordinate.
vec3 hovr_textureToIndex(vec3 tex)
{
  vec3 last = vec3(textureSize(in_volume[0], 0) - ivec3(1));
  return (tex - in_texMin[0]) / (in_texMax[0] - in_texMin[0]) * last;
}
