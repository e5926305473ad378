// hovr: what first- and second-order pre-integration share: the ray a fragment integrates and
// the pieces it is cut into, the samples and normals, the table's lookup coordinate and
// zero-opacity runs. Inserted by vtkPreIntegrationVolumeMapper before the order's own code,
// which declares hovr_preintTable and defines hovr_piece().
//
// The volume is drawn brick by brick (vtkOpenGLVolumeBricks: each brick's texture holds its
// own cells and the ghost points around them) and this code takes the whole ray over from
// VTK's loop: hovr_preintRay() runs where VTK would initialise its loop, which then never runs.
// The ray is the camera model's (vtkCameraRayModel): t is the distance from its origin (the
// plane through the camera, or the eye) measured in the data's coordinates, where VTK measures
// its sample distance and opacity unit distance (world distance without a volume matrix).
// Pieces end on the ray's own grid, t = (m + j) span for integers m (span the sample distance,
// or two for second order's slabs; j the jitter), then at the ray's end; the first starts
// where the ray enters the volume. A brick integrates the pieces whose front lies in its own
// box, reading its ghost points for their far ends, so that the bricks composited back to
// front give the image of one piece.
//
// The ray is known twice: in the volume's grid index (the same uniforms for every brick, so
// that every brick decides alike which piece is whose) and in the brick texture's own grid index
// (the same ray rounded at the brick's scale, where the samples are taken).

uniform sampler3D hovr_volume;
uniform vec3 hovr_volumeInvTexels; // 1 / the brick texture's size
uniform vec3 hovr_volumeLast;      // the volume's last point in the brick's grid index
uniform vec3 hovr_volumeFirst;     // and its first
uniform vec3 hovr_ownedMin;        // the brick's own box, the volume's grid index
uniform vec3 hovr_ownedMax;
uniform vec3 hovr_volumeMin; // the box the rays are walked in (a piece with ghost points:
uniform vec3 hovr_volumeMax; // the whole volume it is a piece of), the volume's grid index
uniform vec3 hovr_dataMax;   // the input's last point (its first is 0), where rays end

// The rays (vtkCameraRayModel::GetGridRayFrame): the ray of the pixel at offset p from the
// frame's pixel centre passes through centre + p.x dx + p.y dy, along that point minus eye
// (perspective) or forward (parallel, where the point's t is hovr_planeT).
uniform vec3 hovr_rayCentre;
uniform vec3 hovr_rayDx;
uniform vec3 hovr_rayDy;
uniform vec3 hovr_rayEye;
uniform vec3 hovr_rayForward;
uniform vec2 hovr_rayPixelCentre;
uniform vec3 hovr_localCentre; // the brick's frame: centred near the brick, its grid index
uniform vec3 hovr_localEye;
uniform vec2 hovr_localPixelCentre;
uniform int hovr_rayPerspective;
uniform float hovr_planeT;
uniform mat3 hovr_indexToWorld;  // linear part of grid index -> world (the volume's matrix)
uniform mat3 hovr_indexToObject; // linear part of grid index -> the data's coordinates
uniform mat3 hovr_gradientToObject; // its inverse transposed, for gradients
uniform vec3 hovr_viewDirection;    // the camera's direction of projection, world, unit
uniform float hovr_near;            // the camera's near distance
uniform float hovr_step;            // the sample distance, the data's coordinates

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

#if HOVR_CLIPPING
// Clipping planes in the volume's grid index, (n, d): points with n . p + d >= 0 are kept.
uniform int hovr_clippingCount;
uniform vec4 hovr_clippingPlanes[6];
#endif
#if HOVR_CROPPING
// Cropping: the planes in the volume's grid index (x0, x1, y0, y1, z0, z1) and the regions
// drawn (bit x + 3 y + 9 z of region (x, y, z), each 0 below, 1 between, 2 above the planes).
uniform float hovr_croppingPlanes[6];
uniform int hovr_croppingRegions;
#endif
uniform vec3 hovr_brickOrigin; // the brick texture's first point, the volume's grid index

// Starts the brick's first piece at t (its front sample), and composites the piece from tFront
// to tBack (t on this ray), whose front is known, making its back the next piece's front.
// Defined by the order's code.
void hovr_pieceStart(float t);
void hovr_piece(float tFront, float tBack);

vec3 hovr_view; // towards the eye, per ray, the data's coordinates (shading)

// This fragment's ray in the brick's grid index: a point, the step per unit of t, and that
// point's t.
vec3 hovr_base;
vec3 hovr_dir;
float hovr_baseT;

// The ray of the pixel in a frame: its point, unit step and the point's t.
void hovr_frameRay(vec3 centre, vec3 eye, vec2 pixelCentre, out vec3 base, out vec3 dir,
  out float baseT)
{
  vec2 p = gl_FragCoord.xy - in_windowLowerLeftCorner - pixelCentre;
  base = centre + p.x * hovr_rayDx + p.y * hovr_rayDy;
  vec3 d = hovr_rayPerspective == 1 ? base - eye : hovr_rayForward;
  float w = length(hovr_indexToObject * d);
  dir = d / w;
  baseT = hovr_rayPerspective == 1 ? w : hovr_planeT / length(hovr_indexToWorld * dir);
}

// The t interval of a ray inside the box [lo, hi]; empty (x >= y) when it misses. A ray
// parallel to an axis is inside along it when lo <= base < hi, or base <= hi where hi is the
// volume's last point: the rays on a plane between two bricks belong to one of them.
vec2 hovr_boxT(vec3 lo, vec3 hi, vec3 last, vec3 base, vec3 dir, float baseT)
{
  bvec3 still = equal(dir, vec3(0.0));
  vec3 inv = 1.0 / mix(dir, vec3(1.0), still);
  vec3 ta = (lo - base) * inv;
  vec3 tb = (hi - base) * inv;
  vec3 tlo = mix(min(ta, tb), vec3(-1e30), still);
  vec3 thi = mix(max(ta, tb), vec3(1e30), still);
  vec3 below = vec3(lessThan(base, lo));
  vec3 above = mix(vec3(greaterThanEqual(base, hi)), vec3(greaterThan(base, hi)),
    vec3(greaterThanEqual(hi, last)));
  if (dot(vec3(still), below + above) > 0.0)
  {
    return vec2(1.0, 0.0);
  }
  return vec2(max(max(tlo.x, tlo.y), tlo.z), min(min(thi.x, thi.y), thi.z)) + baseT;
}

// The brick's grid index of a texture coordinate of the box VTK draws: the brick texture's.
vec3 hovr_textureToLocal(vec3 tex)
{
  return (tex - in_texMin[0]) / (in_texMax[0] - in_texMin[0]) * (1.0 / hovr_volumeInvTexels - 1.0);
}

// Whether a cropping region that is not drawn holds the point (the brick's grid index).
bool hovr_cropped(vec3 p)
{
#if HOVR_CROPPING
  vec3 g = p + hovr_brickOrigin;
  int region = 0;
  int weight = 1;
  for (int a = 0; a < 3; ++a)
  {
    int r = g[a] < hovr_croppingPlanes[2 * a] ? 0 : (g[a] > hovr_croppingPlanes[2 * a + 1] ? 2 : 1);
    region += r * weight;
    weight *= 3;
  }
  return ((hovr_croppingRegions >> region) & 1) == 0;
#else
  return false;
#endif
}

// The t of a point of the brick's grid index on this fragment's ray.
float hovr_tOf(vec3 p)
{
  return hovr_baseT + dot(hovr_indexToObject * (p - hovr_base), hovr_indexToObject * hovr_dir);
}

// The point at t, in the brick's grid index.
vec3 hovr_at(float t)
{
  return hovr_base + (t - hovr_baseT) * hovr_dir;
}

// The centre-axis table coordinate of the sample at a point of the brick's grid index.
float hovr_tableCoord(vec3 p)
{
  return texture(hovr_volume, (p + 0.5) * hovr_volumeInvTexels).r * hovr_rawToTable.x +
    hovr_rawToTable.y;
}

float hovr_emptyRun(float coord)
{
  int spacing = clamp(int(floor(coord * float(hovr_tableSize) - 0.5)), 0, hovr_tableSize - 2);
  return texelFetch(hovr_emptyRuns, ivec2(spacing, 0), 0).r;
}

// The gradient at a point of the brick's grid index: the differences of the trilinear field
// one point either side along each axis, clamped to the volume (vtkVolumeReferenceIntegrator's
// and the twin's point gradients), in the data's coordinates, where the lights are.
float hovr_difference(vec3 p, vec3 e)
{
  vec3 up = clamp(p + e, hovr_volumeFirst, hovr_volumeLast);
  vec3 down = clamp(p - e, hovr_volumeFirst, hovr_volumeLast);
  return texture(hovr_volume, (up + 0.5) * hovr_volumeInvTexels).r -
    texture(hovr_volume, (down + 0.5) * hovr_volumeInvTexels).r;
}

// (No loop over the axes: llvmpipe caps the iterations of a loop over the whole fragment, and
// the ray's loop runs this once per sample.)
vec3 hovr_gradient(vec3 p)
{
  vec3 g = vec3(hovr_difference(p, vec3(1.0, 0.0, 0.0)), hovr_difference(p, vec3(0.0, 1.0, 0.0)),
    hovr_difference(p, vec3(0.0, 0.0, 1.0)));
  return hovr_gradientToObject * g;
}

// The ray's grid: point m at t = m step + phase (the jitter); second order's slabs (span two
// steps) lie between the even points.
float hovr_phase;
float hovr_span;
float hovr_ownedEnd; // t where this brick's box ends on the ray
float hovr_rayEnd;   // t where the ray ends: the volume's exit, opaque geometry, clipping
float hovr_firstEven; // second order: the first even point after the ray's start

float hovr_gridPoint(float m)
{
  return m * hovr_step + hovr_phase;
}

// The index of the first grid point at or after t (after t when strictly). Counting the points
// (rather than finding the next one from a t) keeps pieces from shrinking to nothing where t
// rounds coarser than the step.
float hovr_firstGridPoint(float t, bool strictly)
{
  float m = ceil((t - hovr_phase) / hovr_step);
  // The division may round either way: step to the first point at or after t exactly.
  m = hovr_gridPoint(m - 1.0) >= t ? m - 1.0 : m;
  m = hovr_gridPoint(m) >= t ? m : m + 1.0;
  return strictly && hovr_gridPoint(m) == t ? m + 1.0 : m;
}

// Whether grid point m ends a piece: every point for first order; for second order the even
// points, and the odd ones before the first even point (the piece from the ray's start is cut
// there, so that no partial piece is longer than a step) or whose slab would reach past the
// ray's end. Every brick tells the same, so that a brick's first piece starts where the
// previous brick's last piece ends.
bool hovr_endsPiece(float m)
{
#if HOVR_ORDER == 2
  return mod(m, 2.0) == 0.0 || m < hovr_firstEven || hovr_gridPoint(m + 1.0) > hovr_rayEnd;
#else
  return true;
#endif
}

// The grid point that ends the piece from grid point m.
float hovr_nextEnd(float m)
{
#if HOVR_ORDER == 2
  return mod(m, 2.0) == 0.0 && hovr_gridPoint(m + 2.0) <= hovr_rayEnd ? m + 2.0 : m + 1.0;
#else
  return m + 1.0;
#endif
}

// Walks this brick's pieces of the ray; called once, where VTK initialises its sampling loop.
void hovr_preintRay()
{
  vec3 gBase, gDir;
  float gBaseT;
  hovr_frameRay(hovr_rayCentre, hovr_rayEye, hovr_rayPixelCentre, gBase, gDir, gBaseT);
  hovr_frameRay(hovr_localCentre, hovr_localEye, hovr_localPixelCentre, hovr_base, hovr_dir,
    hovr_baseT);
  // Decisions of which piece is whose: in the volume's frame, alike in every brick.
  vec2 inVolume = hovr_boxT(hovr_volumeMin, hovr_volumeMax, hovr_volumeMax, gBase, gDir, gBaseT);
  vec2 owned = hovr_boxT(hovr_ownedMin, hovr_ownedMax, hovr_volumeMax, gBase, gDir, gBaseT);
  // The ray starts at the volume's entry or the camera's near plane (the same for every
  // brick), and ends at its exit or where VTK terminates it (opaque geometry, clipping).
  float cosine = dot(hovr_indexToWorld * gDir, hovr_viewDirection);
  float rayStart = max(inVolume.x, cosine > 0.0 ? hovr_near / cosine : 0.0);
  // (VTK's own termination point mixes texture coordinates of two kinds once it clips, which
  // matters with the 2-point box VTK draws: the depth and the planes are taken here.)
  vec3 termination = hovr_textureToLocal(hovr_windowToTexture(hovr_frameDepth()));
  vec2 inData = hovr_boxT(vec3(0.0), hovr_dataMax, hovr_dataMax, gBase, gDir, gBaseT);
  hovr_rayEnd = min(min(inVolume.y, inData.y), hovr_tOf(termination));
#if HOVR_CLIPPING
  for (int i = 0; i < hovr_clippingCount; ++i)
  {
    vec4 plane = hovr_clippingPlanes[i];
    float along = dot(plane.xyz, gDir);
    float at = dot(plane.xyz, gBase) + plane.w;
    if (along == 0.0)
    {
      rayStart = at >= 0.0 ? rayStart : 1e30;
    }
    else if (along > 0.0)
    {
      rayStart = max(rayStart, gBaseT - at / along);
    }
    else
    {
      hovr_rayEnd = min(hovr_rayEnd, gBaseT - at / along);
    }
  }
#endif
  hovr_ownedEnd = owned.y;
  if (!(max(owned.x, rayStart) < hovr_ownedEnd && max(owned.x, rayStart) < hovr_rayEnd))
  {
    return;
  }
#if HOVR_SHADED
  hovr_view = -normalize(hovr_indexToObject * hovr_dir);
#endif
  float jitter = 0.0;
#if HOVR_JITTER
  // VTK's per-pixel noise, the same for every brick.
  jitter = texture2D(in_noiseSampler, gl_FragCoord.xy / vec2(textureSize(in_noiseSampler, 0))).x;
#endif
  hovr_span = hovr_step * float(HOVR_ORDER);
  hovr_phase = jitter * hovr_step;
  float first = hovr_firstGridPoint(rayStart, true);
  hovr_firstEven = mod(first, 2.0) == 0.0 ? first : first + 1.0;
  // The brick's first piece starts at the ray's start when that is inside the brick, else at
  // the first point inside it that ends a piece; m is the point its piece ends on.
  float tFront;
  float m;
  if (rayStart >= owned.x)
  {
    tFront = rayStart;
    m = first;
  }
  else
  {
    float front = hovr_firstGridPoint(owned.x, false);
    front = hovr_endsPiece(front) ? front : front + 1.0;
    tFront = hovr_gridPoint(front);
    m = hovr_nextEnd(front);
  }
  if (!(tFront < hovr_ownedEnd && tFront < hovr_rayEnd))
  {
    return;
  }
  hovr_pieceStart(tFront);
  int guard = int((min(hovr_ownedEnd, hovr_rayEnd) - tFront) / hovr_step) + 3;
  for (int n = 0; n < guard; ++n)
  {
    float tBack = min(hovr_gridPoint(m), hovr_rayEnd);
    hovr_piece(tFront, tBack);
    if (tBack >= hovr_rayEnd || tBack >= hovr_ownedEnd || g_fragColor.a > g_opacityThreshold)
    {
      break;
    }
    tFront = tBack;
    m = hovr_nextEnd(m);
  }
}
