// A solid base under the DEM (aal-render --base DEPTH; docs/rendering.md,
// "Solid base"): four side walls from the DEM's edge down to a flat bottom,
// and the bottom, generated from gl_VertexIndex (no vertex buffer). Each
// wall has one quad per DEM cell along its edge, its top at the edge texels'
// heights (level 0 of the height texture), its bottom at frame.baseBottomM. The
// body of base.vert and base_paged.vert (the texture variants: see
// terrain_textures.glsl). Draw baseVertexCount(W, H) vertices
// (engine/terrain_renderer.cpp): 6 per quad.
#ifndef AAL_BASE_VERTEX_GLSL
#define AAL_BASE_VERTEX_GLSL

#include "frame.glsl"
#include "terrain_textures.glsl"

layout(location = 0) out vec3 worldPosition;
layout(location = 1) flat out vec3 baseNormal;

// x east from the DEM centre, y north (row 0 is the northern edge), as the
// terrain's worldAt in terrain_vertex.glsl.
vec3 baseWorldAt(vec2 texel, float z) {
  vec2 half_ = 0.5 * (frame.demSize - 1.0);
  return vec3((texel.x - half_.x) * frame.cellSizeM.x, (half_.y - texel.y) * frame.cellSizeM.y, z);
}

void main() {
  int w = int(frame.demSize.x), h = int(frame.demSize.y);
  int quad = gl_VertexIndex / 6, corner = gl_VertexIndex % 6;
  // Two triangles of the quad's corners (bit 0 along the edge, bit 1 down:
  // top 0, bottom 1), wound counter-clockwise seen from outside the block so
  // that the pipeline culls the faces turned away from the camera: the far
  // walls' inner sides (their level-0 tops would show above the coarser LOD
  // edge of the terrain in front of them) and the bottom seen from above.
  // With along = +x (north, south walls; the bottom) or -y (west, east) the
  // order (0, 2, 1), (1, 2, 3) faces -y, -x or +z: right for the south and
  // west walls, reversed for the others.
  const int kOutward[6] = int[6](0, 2, 1, 1, 2, 3);
  const int kReversed[6] = int[6](0, 1, 2, 1, 3, 2);
  int walls = 2 * (w - 1) + 2 * (h - 1);
  bool reversed = quad >= walls || quad < w - 1 ||
                  (quad >= 2 * (w - 1) + (h - 1));  // bottom, north, east
  int c = reversed ? kReversed[corner] : kOutward[corner];
  float along = float(c & 1), down = float(c >> 1);
  vec2 texel;
  if (quad >= walls) {  // the bottom: the DEM's rectangle at the base's height
    texel = vec2(along * float(w - 1), down * float(h - 1));
    worldPosition = baseWorldAt(texel, frame.baseBottomM);
    baseNormal = vec3(0.0, 0.0, -1.0);
  } else {
    if (quad < w - 1) {  // north edge (row 0), west to east
      texel = vec2(float(quad) + along, 0.0);
      baseNormal = vec3(0.0, 1.0, 0.0);
    } else if (quad < 2 * (w - 1)) {  // south edge (last row)
      texel = vec2(float(quad - (w - 1)) + along, float(h - 1));
      baseNormal = vec3(0.0, -1.0, 0.0);
    } else if (quad < 2 * (w - 1) + (h - 1)) {  // west edge (column 0), north to south
      texel = vec2(0.0, float(quad - 2 * (w - 1)) + along);
      baseNormal = vec3(-1.0, 0.0, 0.0);
    } else {  // east edge (last column)
      texel = vec2(float(w - 1), float(quad - 2 * (w - 1) - (h - 1)) + along);
      baseNormal = vec3(1.0, 0.0, 0.0);
    }
    float top = terrainHeightLod(texel, 0.0);
    worldPosition = baseWorldAt(texel, mix(top, frame.baseBottomM, down));
  }
  gl_Position = frame.viewProj * vec4(worldPosition, 1.0);
}

#endif
