// hovr: from the window to the box VTK draws, for the hovr mappers that walk rays themselves.

// Texture coordinates (VTK's, texel-centred) of the point at window depth z on this fragment's
// pixel-centre ray, through the matrices VTK uses for its ray termination point. Rays start
// from here rather than at the interpolated ip_textureCoords, which rasterisers compute from
// vertices snapped to a sub-pixel grid: up to 1/512 pixel off the pixel centre.
vec3 hovr_windowToTexture(float z)
{
  vec4 ndc = vec4((gl_FragCoord.xy - in_windowLowerLeftCorner) * 2.0 * in_inverseWindowSize - 1.0,
    (2.0 * z - (gl_DepthRange.near + gl_DepthRange.far)) / gl_DepthRange.diff, 1.0);
  vec4 p = ip_inverseTextureDataAdjusted * in_inverseVolumeMatrix[0] * in_inverseModelViewMatrix *
    in_inverseProjectionMatrix * ndc;
  return p.xyz / p.w;
}

// The window depth of what the frame has drawn at this pixel (1 where nothing): opaque
// geometry ends the rays there.
float hovr_frameDepth()
{
  return texture2D(in_depthSampler, (gl_FragCoord.xy - in_windowLowerLeftCorner) *
    in_inverseWindowSize).x;
}
