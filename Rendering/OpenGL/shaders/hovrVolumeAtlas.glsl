// hovr: a volume's bricks packed into the pages of an atlas (vtkOpenGLVolumeBricks in atlas
// mode), read by a point of the volume's 0-based grid index. A sample reads the brick that owns
// the cell it lies in; the brick holds all 8 corners of its cells (neighbouring bricks share
// their face points), so every trilinear sample is the volume's own, whatever the split.
// HOVR_ATLAS_CUTS (the most cuts along an axis) and HOVR_ATLAS_PAGES are defined before this
// code, and the samplers' readers (GetAtlasSamplerCode) take the page these functions give.

// Axis a's cuts (the first cell of each piece, then the cells) at a * HOVR_ATLAS_CUTS.
uniform int hovr_atlasCuts[3 * HOVR_ATLAS_CUTS];
// Cells, pieces, tiles along a page's axes and a tile's size, 3 each.
uniform int hovr_atlasGrid[12];
uniform vec3 hovr_atlasInvSize; // 1 / a page's texels

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

// The page and its texel of corner 000 of the cell (clamped to the volume's cells); the cell's
// other corners follow it along the axes.
ivec3 hovr_atlasTexel(ivec3 cell, out int page)
{
  ivec3 cells = ivec3(hovr_atlasGrid[0], hovr_atlasGrid[1], hovr_atlasGrid[2]);
  cell = clamp(cell, ivec3(0), cells - 1);
  page = 0;
#if HOVR_ATLAS_CUTS == 2
  return cell; // one brick
#endif
  ivec3 first;
  int px = hovr_atlasPiece(0, cell.x, first.x);
  int py = hovr_atlasPiece(1, cell.y, first.y);
  int pz = hovr_atlasPiece(2, cell.z, first.z);
  int b = px + hovr_atlasGrid[3] * (py + hovr_atlasGrid[4] * pz);
  ivec3 tiles = ivec3(hovr_atlasGrid[6], hovr_atlasGrid[7], hovr_atlasGrid[8]);
#if HOVR_ATLAS_PAGES > 1
  int perPage = tiles.x * tiles.y * tiles.z;
  page = b / perPage;
  b -= page * perPage;
#endif
  ivec3 tile = ivec3(b % tiles.x, (b / tiles.x) % tiles.y, b / (tiles.x * tiles.y));
  ivec3 tileSize = ivec3(hovr_atlasGrid[9], hovr_atlasGrid[10], hovr_atlasGrid[11]);
  return tile * tileSize + cell - first;
}

// The page and its texture coordinate of the trilinear sample at p, clamped to the volume's
// points (as clamp-to-edge addressing of one texture would).
vec3 hovr_atlasCoord(vec3 p, out int page)
{
  vec3 cells = vec3(hovr_atlasGrid[0], hovr_atlasGrid[1], hovr_atlasGrid[2]);
  p = clamp(p, vec3(0.0), cells);
  page = 0;
#if HOVR_ATLAS_CUTS == 2
  return (p + 0.5) * hovr_atlasInvSize; // one brick
#endif
  vec3 cell = min(floor(p), cells - 1.0);
  return (vec3(hovr_atlasTexel(ivec3(cell), page)) + (p - cell) + 0.5) * hovr_atlasInvSize;
}
