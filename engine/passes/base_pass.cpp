#include "aperture/engine/passes/frame_passes.h"

#include "aperture/engine/terrain_scene.h"

namespace aal {

namespace {

// For every drawn patch or quadrant of `selection` whose edge lies on the
// DEM's edge, the wall quads under that edge, whose tops are the terrain's
// edge vertices; then the bottom. A patch grid line is drawn as the quads
// from `first` to `last` along it, with the patch as the instance.
void drawWallsAndBottom(VkCommandBuffer cmd, const LodSelection& selection, glm::vec2 demSize) {
  constexpr uint32_t n = kLodPatchQuads, half = n / 2;
  const auto line = [&](uint32_t patch, uint32_t index, uint32_t first, uint32_t last) {
    vkCmdDraw(cmd, (last - first) * 6, 1, index * AAL_BASE_LINE_VERTICES + first * 6, patch);
  };
  // The DEM's last column and row: patches reaching beyond them are clamped
  // onto them (lodPatchTexel), so their edge is the grid line that reaches them.
  const float lastColumn = demSize.x - 1.0f, lastRow = demSize.y - 1.0f;
  uint32_t patch = 0;
  const auto piece = [&](uint32_t c0, uint32_t r0, uint32_t size) {
    const glm::vec4 node = selection.patches[patch].node;
    const float x0 = node.x + float(c0) * node.z, x1 = node.x + float(c0 + size) * node.z;
    const float y0 = node.y + float(r0) * node.z, y1 = node.y + float(r0 + size) * node.z;
    // (A piece folded onto the edge entirely draws nothing of its own.)
    if (x0 < lastColumn && y0 < lastRow) {
      if (y0 == 0.0f) line(patch, r0 / half, c0, c0 + size);                     // north: row r0
      if (y1 >= lastRow) line(patch, (r0 + size) / half, c0, c0 + size);         // south
      if (x0 == 0.0f) line(patch, 3 + c0 / half, r0, r0 + size);                 // west: column c0
      if (x1 >= lastColumn) line(patch, 3 + (c0 + size) / half, r0, r0 + size);  // east
    }
    ++patch;
  };
  for (uint32_t i = 0; i < selection.wholeCount; ++i) piece(0, 0, n);
  for (uint32_t q = 0; q < 4; ++q) {
    for (uint32_t i = 0; i < selection.quadrantCount[q]; ++i)
      piece((q & 1) * half, (q >> 1) * half, half);
  }
  vkCmdDraw(cmd, 6, 1, 6 * AAL_BASE_LINE_VERTICES, 0);
}

}  // namespace

// With the terrain's bindings: the base's vertex shader reads the heights at
// the DEM's edge (shaders/base_vertex.glsl).
void drawBase(const PassContext& pass, const FramePlan& plan) {
  pass.pipelines.base(plan.paging, plan.mode, plan.obscurance, plan.direct)
      .bind(pass.cmd, terrainWrites(pass).buffer(kAfterTerrainTextures, pass.patches), nullptr);
  drawWallsAndBottom(pass.cmd, *plan.selection, glm::vec2(pass.scene.demInfo()));
}

}  // namespace aal
