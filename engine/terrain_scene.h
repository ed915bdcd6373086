// The GPU side of one DEM: height, aperture and albedo textures and the grid.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <vector>

#include <glm/vec4.hpp>

#include "albedo_image.h"
#include "aperture_map.h"
#include "buffer.h"
#include "heightfield.h"
#include "image.h"
#include "terrain_grid.h"

namespace aal {

class Device;

class TerrainScene {
 public:
  // Uploads everything in one batch. The aperture map must belong to the DEM
  // (checkApertureMatchesDem). `albedo` may be null: a palette by height and
  // slope is used then. Throws VulkanError when the DEM exceeds the device's
  // image size limit.
  TerrainScene(const Device& device, const Heightfield& field, const ApertureMap& aperture,
               const AlbedoImage* albedo, size_t triangleBudget);
  // The same, streaming the aperture map from its file band by band (it must
  // match the DEM, checkApertureMatchesDem), so it is never held as floats.
  TerrainScene(const Device& device, const Heightfield& field, ApertureMapReader& aperture,
               const AlbedoImage* albedo, size_t triangleBudget);
  // The same with an open sky at every texel (bent normal up, arc length
  // pi/2) in place of an aperture map: aal-view shows the baseline modes with
  // it while the real map is baked.
  TerrainScene(const Device& device, const Heightfield& field, const AlbedoImage* albedo,
               size_t triangleBudget);

  const Image& heights() const { return heights_; }
  const Image& aperture() const { return aperture_; }
  const Image& albedo() const { return albedo_; }
  bool hasAlbedo() const { return hasAlbedo_; }
  const Buffer& indices() const { return indices_; }
  int gridColumns() const { return gridColumns_; }
  int gridRows() const { return gridRows_; }
  uint32_t indexCount() const { return indexCount_; }
  // width, height (texels), cell size x, y (metres)
  glm::vec4 demInfo() const { return demInfo_; }
  float minHeight() const { return minHeight_; }
  float maxHeight() const { return maxHeight_; }

 private:
  // `apertureRows` writes rows of RGBA16F bent normal + arc length.
  void build(const Device& device, const Heightfield& field,
             const std::function<void(uint32_t, uint32_t, void*)>& apertureRows,
             const AlbedoImage* albedo, size_t triangleBudget);

  Image heights_, aperture_, albedo_;
  Buffer indices_;
  bool hasAlbedo_ = false;
  int gridColumns_ = 0, gridRows_ = 0;
  uint32_t indexCount_ = 0;
  glm::vec4 demInfo_{0.0f};
  float minHeight_ = 0, maxHeight_ = 0;
};

}  // namespace aal
