// hovr: what vtkAnalyticVolumeMapper's analytic and stock modes share: the output that
// replaces the colour for measurements and the map from texture coordinates to grid index.

uniform vec2 hovr_rawToData; // data value = raw texture value * x + y
uniform vec2 hovr_rawRange;  // the data's finite range in raw texture values

// What HOVR_OUTPUT 1 (hit position) and 2 (extremum) write instead of the colour.
vec4 hovr_output = vec4(0.0);

// The volume the analytic method reads: HOVR_VOLUME is hovr_volume (the brick drawn, whose
// box VTK draws) or, for VTK's own sampling, in_volume[0].
#ifdef HOVR_BRICKED
uniform sampler3D hovr_volume;
#define HOVR_VOLUME hovr_volume
#else
#define HOVR_VOLUME in_volume[0]
#endif

// Continuous grid index (point i at i) of HOVR_VOLUME of a texture coordinate of VTK's box.
vec3 hovr_textureToIndex(vec3 tex)
{
  vec3 last = vec3(textureSize(HOVR_VOLUME, 0) - ivec3(1));
  return (tex - in_texMin[0]) / (in_texMax[0] - in_texMin[0]) * last;
}

// hovr_windowToTexture: hovrWindow.glsl.
