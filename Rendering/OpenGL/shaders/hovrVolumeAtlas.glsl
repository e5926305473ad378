// hovr: a volume's bricks packed into one 3D texture (vtkOpenGLVolumeBricks in atlas mode),
// read by a point of the volume's 0-based grid index. A sample reads the brick that owns the
// cell it lies in; the brick holds all 8 corners of its cells (neighbouring bricks share their
// face points), so every trilinear sample is the volume's own, whatever the split.
// HOVR_ATLAS_CUTS (the most cuts along an axis) is defined before this code.

// Axis a's cuts (the first cell of each piece, then the cells) at a * HOVR_ATLAS_CUTS.
uniform int hovr_atlasCuts[3 * HOVR_ATLAS_CUTS];
// Cells, pieces, tiles along the atlas's axes and a tile's size, 3 each.
uniform int hovr_atlasGrid[12];
uniform vec3 hovr_atlasInvSize; // 1 / the atlas's texels

// The piece along an axis that owns cell c (0 <= c < cells), and its first cell. The pieces
// are cut at floor(p cells / pieces), so c pieces / cells is the piece or the one before.
int hovr_atlasPiece(int axis, int c, out int first)
{
  int cells = hovr_atlasGrid[axis];
  int pieces = hovr_atlasGrid[3 + axis];
  int base = axis * HOVR_ATLAS_CUTS;
  int p = min(c * pieces / cells, pieces - 1);
  if (p + 1 < pieces && hovr_atlasCuts[base + p + 1] <= c)
  {
    p += 1;
  }
  first = hovr_atlasCuts[base + p];
  return p;
}

// The atlas texel of corner 000 of the cell (clamped to the volume's cells); the cell's other
// corners follow it along the axes.
ivec3 hovr_atlasTexel(ivec3 cell)
{
  ivec3 cells = ivec3(hovr_atlasGrid[0], hovr_atlasGrid[1], hovr_atlasGrid[2]);
  cell = clamp(cell, ivec3(0), cells - 1);
#if HOVR_ATLAS_CUTS == 2
  return cell; // one brick
#endif
  ivec3 first;
  int px = hovr_atlasPiece(0, cell.x, first.x);
  int py = hovr_atlasPiece(1, cell.y, first.y);
  int pz = hovr_atlasPiece(2, cell.z, first.z);
  int b = px + hovr_atlasGrid[3] * (py + hovr_atlasGrid[4] * pz);
  ivec3 tiles = ivec3(hovr_atlasGrid[6], hovr_atlasGrid[7], hovr_atlasGrid[8]);
  ivec3 tile = ivec3(b % tiles.x, (b / tiles.x) % tiles.y, b / (tiles.x * tiles.y));
  ivec3 tileSize = ivec3(hovr_atlasGrid[9], hovr_atlasGrid[10], hovr_atlasGrid[11]);
  return tile * tileSize + cell - first;
}

// The atlas texture coordinate of the trilinear sample at p, clamped to the volume's points
// (as clamp-to-edge addressing of one texture would).
vec3 hovr_atlasCoord(vec3 p)
{
  vec3 cells = vec3(hovr_atlasGrid[0], hovr_atlasGrid[1], hovr_atlasGrid[2]);
  p = clamp(p, vec3(0.0), cells);
#if HOVR_ATLAS_CUTS == 2
  return (p + 0.5) * hovr_atlasInvSize; // one brick
#endif
  vec3 cell = min(floor(p), cells - 1.0);
  return (vec3(hovr_atlasTexel(ivec3(cell))) + (p - cell) + 0.5) * hovr_atlasInvSize;
}
