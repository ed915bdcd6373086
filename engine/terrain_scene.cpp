#include "terrain_scene.h"

#include <algorithm>
#include <stdexcept>

#include <Imath/half.h>

#include "device.h"
#include "upload.h"

namespace aal {

TerrainScene::TerrainScene(const Device& device, const Heightfield& field,
                           const ApertureMap& aperture, const AlbedoImage* albedo,
                           size_t triangleBudget) {
  const size_t width = static_cast<size_t>(field.width);
  build(
      device, field,
      [&](uint32_t first, uint32_t end, void* destination) {
        const float* source = aperture.texels.data() + first * width * 4;
        std::transform(source, source + (end - first) * width * 4,
                       static_cast<uint16_t*>(destination),
                       [](float v) { return Imath::half(v).bits(); });
      },
      albedo, triangleBudget);
}

TerrainScene::TerrainScene(const Device& device, const Heightfield& field,
                           ApertureMapReader& aperture, const AlbedoImage* albedo,
                           size_t triangleBudget) {
  build(
      device, field,
      [&](uint32_t first, uint32_t end, void* destination) {
        aperture.readHalfRows(static_cast<int>(first), static_cast<int>(end), destination);
      },
      albedo, triangleBudget);
}

TerrainScene::TerrainScene(const Device& device, const Heightfield& field,
                           const AlbedoImage* albedo, size_t triangleBudget) {
  const size_t width = static_cast<size_t>(field.width);
  const uint16_t up[4] = {Imath::half(0.0f).bits(), Imath::half(0.0f).bits(),
                          Imath::half(1.0f).bits(), Imath::half(1.5707964f).bits()};
  build(
      device, field,
      [&](uint32_t first, uint32_t end, void* destination) {
        uint16_t* out = static_cast<uint16_t*>(destination);
        for (size_t i = 0; i < (end - first) * width; ++i) std::copy(up, up + 4, out + 4 * i);
      },
      albedo, triangleBudget);
}

void TerrainScene::build(const Device& device, const Heightfield& field,
                         const std::function<void(uint32_t, uint32_t, void*)>& apertureRows,
                         const AlbedoImage* albedo, size_t triangleBudget) {
  const uint32_t w = static_cast<uint32_t>(field.width), h = static_cast<uint32_t>(field.height);
  heights_ = Image(device, {w, h, VK_FORMAT_R32_SFLOAT,
                            VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT});
  aperture_ = Image(device, {w, h, VK_FORMAT_R16G16B16A16_SFLOAT,
                             VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT});

  hasAlbedo_ = albedo != nullptr;
  std::vector<uint8_t> albedoBytes;
  if (albedo) {
    albedo_ = Image(device, {w, h, VK_FORMAT_R8G8B8A8_UNORM,
                             VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT});
    albedoBytes.resize(static_cast<size_t>(w) * h * 4);
    for (size_t i = 0; i < static_cast<size_t>(w) * h; ++i) {
      for (int c = 0; c < 3; ++c) {
        albedoBytes[4 * i + c] =
            static_cast<uint8_t>(std::clamp(albedo->rgb[3 * i + c], 0.0f, 1.0f) * 255.0f + 0.5f);
      }
      albedoBytes[4 * i + 3] = 255;
    }
  } else {
    // A bound texture is required; one texel that the shader ignores.
    albedo_ = Image(device, {1, 1, VK_FORMAT_R8G8B8A8_UNORM,
                             VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT});
    albedoBytes = {128, 128, 128, 255};
  }

  if (triangleBudget < 2) throw std::invalid_argument("triangle budget must be at least 2");
  lod_ = std::make_unique<LodQuadtree>(field);
  triangleBudget_ = triangleBudget;
  lodBudgetScaleM_ = lodBudgetRangeScale(*lod_, triangleBudget);
  const std::vector<uint32_t> patchIndices = makeLodPatchIndices();
  indices_ = Buffer(device, patchIndices.size() * sizeof(uint32_t),
                    VK_BUFFER_USAGE_INDEX_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                    MemoryIntent::DeviceLocal);

  UploadBatch upload(device);
  upload.addImage(heights_, sizeof(float), field.z.data());
  upload.addImage(aperture_, 4 * sizeof(uint16_t), apertureRows);
  upload.addImage(albedo_, 4, albedoBytes.data());
  upload.addBuffer(indices_, patchIndices.data(), patchIndices.size() * sizeof(uint32_t));
  upload.submit();

  demInfo_ = {static_cast<float>(field.width), static_cast<float>(field.height),
              static_cast<float>(field.cellSizeXM), static_cast<float>(field.cellSizeYM)};
  const auto [lo, hi] = std::minmax_element(field.z.begin(), field.z.end());
  minHeight_ = *lo;
  maxHeight_ = *hi;
}

}  // namespace aal
