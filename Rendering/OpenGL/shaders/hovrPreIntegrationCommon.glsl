// hovr: what first- and second-order pre-integration share (hovrPreIntegration1.glsl and
// hovrPreIntegration2.glsl): the table's lookup coordinate and zero-opacity runs, and the
// distance to the volume's exit. Inserted by vtkPreIntegrationVolumeMapper before the
// order's own code; that code declares hovr_preintTable (sampler2D or sampler3D).

// Zero-opacity run of each table spacing (-1: some opacity), read with texelFetch.
uniform sampler2D hovr_emptyRuns;
uniform int hovr_tableSize;
// Centre-axis texture coordinate of a raw texture value: raw * x + y. The table's axes are
// the chord's centre (front + back) / 2, the chord back - front and, for second order, the
// deviation of the middle sample from the centre; all are affine in the samples, so their
// coordinates follow from the samples' centre-axis coordinates.
uniform vec2 hovr_rawToTable;
// Chord coordinate of a difference of centre-axis coordinates (0 at 1/2).
uniform float hovr_chordScale;

float hovr_tableCoord(vec3 pos)
{
  return texture(in_volume[0], pos).r * hovr_rawToTable.x + hovr_rawToTable.y;
}

float hovr_emptyRun(float coord)
{
  int spacing = clamp(int(floor(coord * float(hovr_tableSize) - 0.5)), 0, hovr_tableSize - 2);
  return texelFetch(hovr_emptyRuns, ivec2(spacing, 0), 0).r;
}

// Steps (in units of g_dirStep) from pos to where the ray leaves the volume's box.
float hovr_stepsToExit(vec3 pos)
{
  vec3 bound = mix(in_texMin[0], in_texMax[0], step(vec3(0.0), g_dirStep));
  vec3 steps = vec3(1e30);
  for (int a = 0; a < 3; ++a)
  {
    if (g_dirStep[a] != 0.0)
    {
      steps[a] = (bound[a] - pos[a]) / g_dirStep[a];
    }
  }
  return min(steps.x, min(steps.y, steps.z));
}
