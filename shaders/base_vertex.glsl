// A solid base under the DEM (aal-render --base DEPTH; docs/rendering.md,
// "Solid base"): four side walls from the DEM's edge down to a flat bottom,
// and the bottom, generated from gl_VertexIndex and the LOD patches (no
// vertex buffer). The walls hang from the terrain's own edge: one quad per
// patch grid cell along each patch edge that lies on the DEM's edge, its top
// the terrain's vertex there computed by the same code (patchVertex in
// patch_vertex.glsl: same grid point, morph and level of detail), so the
// terrain and the wall share their edge exactly and rasterization leaves no
// pixel between them; its bottom at frame.baseBottomM. The body of base.vert and
// base_paged.vert (the texture variants: see terrain_textures.glsl).
//
// Draws (engine/terrain_renderer.cpp, drawBase): instance = the patch
// (firstInstance), vertices 6 per quad. Vertex v < 6 * AAL_BASE_LINE_VERTICES
// is on patch grid line v / AAL_BASE_LINE_VERTICES: lines 0, 1, 2 are the
// rows 0, N/2, N and lines 3, 4, 5 the columns 0, N/2, N (N =
// AAL_LOD_PATCH_QUADS), quad (v % AAL_BASE_LINE_VERTICES) / 6 along it; the
// six vertices from 6 * AAL_BASE_LINE_VERTICES on are the bottom.
#ifndef AAL_BASE_VERTEX_GLSL
#define AAL_BASE_VERTEX_GLSL

#include "patch_vertex.glsl"

layout(location = 0) out vec3 worldPosition;
layout(location = 1) flat out vec3 baseNormal;

// x east from the DEM centre, y north (row 0 is the northern edge), as the
// terrain's worldAt in patch_vertex.glsl.
vec3 baseWorldAt(vec2 texel, float z) {
  vec2 half_ = 0.5 * (frame.demSize - 1.0);
  return vec3((texel.x - half_.x) * frame.cellSizeM.x, (half_.y - texel.y) * frame.cellSizeM.y, z);
}

void main() {
  const int n = AAL_LOD_PATCH_QUADS;
  int line = gl_VertexIndex / AAL_BASE_LINE_VERTICES;
  int quad = (gl_VertexIndex % AAL_BASE_LINE_VERTICES) / 6, corner = gl_VertexIndex % 6;
  // Two triangles of the quad's corners (bit 0 along the edge, bit 1 down:
  // top 0, bottom 1), wound counter-clockwise seen from outside the block so
  // that the pipeline culls the faces turned away from the camera: the far
  // walls' inner sides and the bottom seen from above. With along = +x
  // (rows: north, south walls; the bottom) or -y (columns: west, east) the
  // order (0, 2, 1), (1, 2, 3) faces -y, -x or +z: right for the south and
  // west walls, reversed for the others.
  const int kOutward[6] = int[6](0, 2, 1, 1, 2, 3);
  const int kReversed[6] = int[6](0, 1, 2, 1, 3, 2);
  if (line >= 6) {  // the bottom: the DEM's rectangle at the base's height
    int c = kReversed[corner];
    vec2 texel = vec2(float(c & 1) * (frame.demSize.x - 1.0), float(c >> 1) * (frame.demSize.y - 1.0));
    worldPosition = baseWorldAt(texel, frame.baseBottomM);
    baseNormal = vec3(0.0, 0.0, -1.0);
  } else {
    LodPatch node = patches[gl_InstanceIndex];
    bool row = line < 3;
    float gridLine = float((line % 3) * (n / 2));
    // Which edge of the DEM: the patch's grid line at texel 0 is the
    // northern (row) or western (column) one; the drawer only asks for
    // lines on the DEM's edge, so any other is the southern or eastern.
    bool first = (row ? node.node.y : node.node.x) + gridLine * node.node.z == 0.0;
    bool reversed = row == first;  // north or east
    int c = reversed ? kReversed[corner] : kOutward[corner];
    float along = float(quad + (c & 1)), down = float(c >> 1);
    vec2 texel;
    vec3 top = patchVertex(node, row ? vec2(along, gridLine) : vec2(gridLine, along), texel);
    worldPosition = down == 0.0 ? top : baseWorldAt(texel, frame.baseBottomM);
    baseNormal = row ? vec3(0.0, first ? 1.0 : -1.0, 0.0) : vec3(first ? -1.0 : 1.0, 0.0, 0.0);
  }
  gl_Position = frame.viewProj * vec4(worldPosition, 1.0);
}

#endif
