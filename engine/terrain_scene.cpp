#include "aperture/engine/terrain_scene.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstring>
#include <stdexcept>
#include <string>
#include <tuple>
#include <utility>

#include <Imath/half.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "aperture/engine/vk/commands.h"
#include "aperture/engine/vk/compute.h"
#include "aperture/engine/vk/deletion_queue.h"
#include "aperture/engine/vk/descriptors.h"
#include "aperture/engine/vk/device.h"
#include "aperture/engine/vk/upload.h"
#include "aperture/engine/vk/vk_check.h"
#include "aperture/terrain/view/height_mips.h"

namespace aal {

namespace {

// Writes whole DEM rows [firstRow, endRow) of one texture kind, tightly packed.
using DemRows = std::function<void(uint32_t firstRow, uint32_t endRow, void* destination)>;

// TRANSFER_SRC: tests read the levels back.
constexpr VkImageUsageFlags kTextureUsage =
    VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT;

// The rows of tile (tileX, tileY)'s image: its core and border (and the
// rounding up to the mip alignment), texels beyond the DEM clamped to its
// edge (what a sampler's clamp would read there). `scratch` holds the DEM rows of one band.
RowWriter tileRows(const TerrainTileLayout& t, uint32_t tileX, uint32_t tileY, size_t texelBytes,
                   const DemRows& demRows, std::vector<unsigned char>& scratch) {
  return [&t, tileX, tileY, texelBytes, &demRows, &scratch](uint32_t first, uint32_t end,
                                                            void* destination) {
    const int64_t row0 = int64_t{tileY} * t.coreHeight - t.border;
    const auto demRow = [&](uint32_t r) {
      return static_cast<uint32_t>(std::clamp<int64_t>(row0 + r, 0, int64_t{t.demHeight} - 1));
    };
    const uint32_t demFirst = demRow(first), demEnd = demRow(end - 1) + 1;
    const size_t demRowBytes = size_t{t.demWidth} * texelBytes;
    scratch.resize(std::max(scratch.size(), (demEnd - demFirst) * demRowBytes));
    demRows(demFirst, demEnd, scratch.data());

    const int64_t col0 = int64_t{tileX} * t.coreWidth - t.border;
    const int64_t width = t.imageWidth();
    // Columns [inside, outside) of the tile lie in the DEM; the rest repeat
    // its first or last column.
    const int64_t inside = std::clamp<int64_t>(-col0, 0, width);
    const int64_t outside = std::clamp<int64_t>(int64_t{t.demWidth} - col0, inside, width);
    auto* out = static_cast<unsigned char*>(destination);
    for (uint32_t r = first; r < end; ++r) {
      const unsigned char* source = scratch.data() + (demRow(r) - demFirst) * demRowBytes;
      for (int64_t c = 0; c < inside; ++c) std::memcpy(out + c * texelBytes, source, texelBytes);
      std::memcpy(out + inside * texelBytes, source + (col0 + inside) * texelBytes,
                  (outside - inside) * texelBytes);
      const unsigned char* last = source + demRowBytes - texelBytes;
      for (int64_t c = outside; c < width; ++c) std::memcpy(out + c * texelBytes, last, texelBytes);
      out += width * texelBytes;
    }
  };
}

// Mip levels (UploadBatch): the mean of 2 x 2 texels (meanOf2x2), the same
// in every tile that holds it and in HeightMips.
void reduceHeights(const unsigned char* upper, const unsigned char* lower, unsigned char* out,
                   uint32_t width) {
  const auto* a = reinterpret_cast<const float*>(upper);
  const auto* b = reinterpret_cast<const float*>(lower);
  auto* o = reinterpret_cast<float*>(out);
  for (uint32_t i = 0; i < width; ++i) {
    o[i] = meanOf2x2(a[2 * i], a[2 * i + 1], b[2 * i], b[2 * i + 1]);
  }
}

// Each channel of each RGBA texel from its 2 x 2 texels of the level above:
// mean(upper left, upper right, lower left, lower right).
template <class Channel, class Mean>
void reduceRgba(const unsigned char* upper, const unsigned char* lower, unsigned char* out,
                uint32_t width, Mean mean) {
  const auto* a = reinterpret_cast<const Channel*>(upper);
  const auto* b = reinterpret_cast<const Channel*>(lower);
  auto* o = reinterpret_cast<Channel*>(out);
  for (uint32_t i = 0; i < 4 * width; ++i) {
    const uint32_t left = 8 * (i / 4) + i % 4;  // the channel in the left texel above
    o[i] = mean(a[left], a[left + 4], b[left], b[left + 4]);
  }
}

void reduceApertures(const unsigned char* upper, const unsigned char* lower, unsigned char* out,
                     uint32_t width) {
  const auto value = [](uint16_t bits) {
    Imath::half h;
    h.setBits(bits);
    return float(h);
  };
  reduceRgba<uint16_t>(
      upper, lower, out, width, [&](uint16_t a, uint16_t b, uint16_t c, uint16_t d) {
        return Imath::half(meanOf2x2(value(a), value(b), value(c), value(d))).bits();
      });
}

void reduceAlbedo(const unsigned char* upper, const unsigned char* lower, unsigned char* out,
                  uint32_t width) {
  reduceRgba<unsigned char>(upper, lower, out, width,
                            [](unsigned a, unsigned b, unsigned c, unsigned d) {
                              return static_cast<unsigned char>((a + b + c + d + 2) / 4);
                            });
}

// The slope pages (in the heights' pages and layers, every mip level): RG16F
// slopes, or RGBA16F with the horizon pair in B and A.
std::vector<Image> makeSlopePages(const Device& device, const TerrainTileLayout& tiles,
                                  bool horizons) {
  std::vector<Image> pages;
  for (uint32_t page = 0; page < tiles.pagesOf(TerrainTexture::Height); ++page) {
    pages.emplace_back(
        device, ImageDesc{tiles.imageWidth(), tiles.imageHeight(),
                          horizons ? VK_FORMAT_R16G16B16A16_SFLOAT : VK_FORMAT_R16G16_SFLOAT,
                          kTextureUsage | VK_IMAGE_USAGE_STORAGE_BIT, VK_IMAGE_ASPECT_COLOR_BIT,
                          tiles.layersIn(TerrainTexture::Height, page), true, kTerrainMipLevels});
  }
  return pages;
}

// The pages of the horizons' second moments (RG16F, as the slopes' pages).
std::vector<Image> makeHorizonMomentPages(const Device& device, const TerrainTileLayout& tiles) {
  std::vector<Image> pages;
  for (uint32_t page = 0; page < tiles.pagesOf(TerrainTexture::Height); ++page) {
    pages.emplace_back(
        device, ImageDesc{tiles.imageWidth(), tiles.imageHeight(), VK_FORMAT_R16G16_SFLOAT,
                          kTextureUsage | VK_IMAGE_USAGE_STORAGE_BIT, VK_IMAGE_ASPECT_COLOR_BIT,
                          tiles.layersIn(TerrainTexture::Height, page), true, kTerrainMipLevels});
  }
  return pages;
}

// Their bytes at level 0 (as textureBytes counts); with horizons the
// second moments' 4 B a texel too.
uint64_t slopeBytes(const TerrainTileLayout& tiles, bool horizons) {
  uint64_t layers = 0;
  for (uint32_t page = 0; page < tiles.pagesOf(TerrainTexture::Height); ++page) {
    layers += tiles.layersIn(TerrainTexture::Height, page);
  }
  return tiles.layerTexels() * layers * (horizons ? 8 + 4 : 4);
}

}  // namespace

namespace {

// One mip level of one page, as a storage image view.
class LevelView {
 public:
  LevelView(const Device& device, const Image& image, uint32_t level) : device_(device.handle()) {
    const VkImageViewCreateInfo info{.sType = VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO,
                                     .image = image.handle(),
                                     .viewType = VK_IMAGE_VIEW_TYPE_2D_ARRAY,
                                     .format = image.desc().format,
                                     .subresourceRange = {.aspectMask = VK_IMAGE_ASPECT_COLOR_BIT,
                                                          .baseMipLevel = level,
                                                          .levelCount = 1,
                                                          .baseArrayLayer = 0,
                                                          .layerCount = image.desc().layers}};
    AAL_VK_CHECK(vkCreateImageView(device_, &info, nullptr, &view_));
  }
  ~LevelView() { vkDestroyImageView(device_, view_, nullptr); }
  LevelView(const LevelView&) = delete;
  LevelView& operator=(const LevelView&) = delete;
  VkImageView handle() const { return view_; }

 private:
  VkDevice device_;
  VkImageView view_ = VK_NULL_HANDLE;
};

}  // namespace

namespace {

// The codes of one or two directions (R, G) as R8_UINT or R8G8_UINT images
// in the heights' tiles and pages, rows [rowBegin, rowEnd) of every tile
// image (borders included, level 0 only): what slopes_horizons.comp decodes
// into the slope texture.
std::vector<Image> horizonCodePages(const Device& device, const TerrainTileLayout& tiles,
                                    const HorizonMap& map, const std::vector<int>& directions,
                                    uint32_t rowBegin, uint32_t rowEnd,
                                    VkCommandBuffer cmd = VK_NULL_HANDLE) {
  const size_t count = directions.size();
  const DemRows codeRows = [&](uint32_t firstRow, uint32_t endRow, void* destination) {
    // Rows in parallel: every texel's codes are n bytes in a row, so this
    // reads the whole map's rows (memory bound; docs/performance.md).
    const size_t width = size_t(map.width), n = size_t(map.directions);
    tbb::parallel_for(tbb::blocked_range<uint32_t>(firstRow, endRow, 8), [&](const auto& rows) {
      for (uint32_t row = rows.begin(); row < rows.end(); ++row) {
        const uint8_t* codes = map.texel(0, int(row));
        auto* out = static_cast<uint8_t*>(destination) + (row - firstRow) * width * count;
        for (size_t col = 0; col < width; ++col, codes += n) {
          for (size_t d = 0; d < count; ++d) out[count * col + d] = codes[directions[d]];
        }
      }
    });
  };
  std::vector<Image> pages;
  for (uint32_t page = 0; page < tiles.pagesOf(TerrainTexture::Height); ++page) {
    pages.emplace_back(
        device,
        ImageDesc{tiles.imageWidth(), rowEnd - rowBegin,
                  count == 1 ? VK_FORMAT_R8_UINT : VK_FORMAT_R8G8_UINT,
                  VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT,
                  VK_IMAGE_ASPECT_COLOR_BIT, tiles.layersIn(TerrainTexture::Height, page), true});
  }
  UploadBatch upload(device);
  std::vector<unsigned char> scratch;  // one band of DEM rows while a tile is filled
  std::vector<RowWriter> tileWriters;  // alive until submit()
  tileWriters.reserve(tiles.tileCount());
  const uint32_t perPage = tiles.layersPerPageOf(TerrainTexture::Height);
  for (uint32_t tile = 0; tile < tiles.tileCount(); ++tile) {
    tileWriters.push_back(
        tileRows(tiles, tile % tiles.tilesX, tile / tiles.tilesX, count, codeRows, scratch));
    const RowWriter& whole = tileWriters.back();
    upload.addImage(
        pages[tile / perPage], count,
        [&whole, rowBegin](uint32_t first, uint32_t end, void* destination) {
          whole(rowBegin + first, rowBegin + end, destination);
        },
        tile % perPage);
  }
  if (cmd != VK_NULL_HANDLE) {
    upload.record(cmd);
  } else {
    upload.submit();
  }
  return pages;
}

}  // namespace

namespace {

// shaders/slopes.glsl's push constants.
struct SlopePush {
  int32_t level;
  float cellSizeXM, cellSizeYM;
  int32_t horizonBits;
  int32_t keepSlopes;
  int32_t channel;  // horizons written: 0 B, 1 A, 2 both
  int32_t rowBegin, rowEnd;
};

constexpr int32_t kBothChannels = 2;

// Unique in the process: a scene's id, renewed when its aperture map changes.
uint64_t nextSceneId() {
  static std::atomic<uint64_t> ids{0};
  return ++ids;
}

// The 2D array images of one texture kind in `tiles`' pages, with every mip
// level.
std::vector<Image> makeTexturePages(const Device& device, const TerrainTileLayout& tiles,
                                    TerrainTexture texture, VkFormat format) {
  std::vector<Image> pages;
  for (uint32_t page = 0; page < tiles.pagesOf(texture); ++page) {
    pages.emplace_back(device, ImageDesc{tiles.imageWidth(), tiles.imageHeight(), format,
                                         kTextureUsage, VK_IMAGE_ASPECT_COLOR_BIT,
                                         tiles.layersIn(texture, page), true, kTerrainMipLevels});
  }
  return pages;
}

// Adds every tile of one texture kind to `upload`, each layer of `pages`
// filled from the DEM rows `rows` (which, with `scratch`, must outlive the
// upload).
void addTileImages(UploadBatch& upload, const TerrainTileLayout& tiles,
                   const std::vector<Image>& pages, TerrainTexture texture, const DemRows& rows,
                   std::vector<unsigned char>& scratch, MipReducer reduce) {
  const size_t texelBytes = kTerrainTextureBytes[int(texture)];
  const uint32_t perPage = tiles.layersPerPageOf(texture);
  for (uint32_t tile = 0; tile < tiles.tileCount(); ++tile) {
    upload.addImage(
        pages[tile / perPage], texelBytes,
        tileRows(tiles, tile % tiles.tilesX, tile / tiles.tilesX, texelBytes, rows, scratch),
        tile % perPage, reduce);
  }
}

// A write of `codeBytes` of horizon codes goes into `frame`'s commands when
// it fits one staging buffer; a larger one is submitted and waited for
// (VK_NULL_HANDLE), through a staging buffer of bounded size.
VkCommandBuffer frameForCodes(VkCommandBuffer frame, uint64_t codeBytes) {
  return codeBytes > UploadBatch::kDefaultStagingBytes ? VK_NULL_HANDLE : frame;
}

}  // namespace

void TerrainScene::computeSlopes(const Device& device, int first, bool keepSlopes) const {
  const bool horizons = horizonMap_ != nullptr;
  const std::vector<Image> codes =
      horizons ? horizonCodePages(device, tiles_, *horizonMap_,
                                  {first, (first + 1) % horizonMap_->directions}, 0,
                                  tiles_.imageHeight())
               : std::vector<Image>{};
  runSlopePass(device, horizons ? &codes : nullptr, keepSlopes, kBothChannels, 0,
               tiles_.imageHeight(), VK_NULL_HANDLE, {slopes_, horizonMoments_, keepSlopes});
}

void TerrainScene::runSlopePass(const Device& device, const std::vector<Image>* codes,
                                bool keepSlopes, int channel, uint32_t rowBegin, uint32_t rowEnd,
                                VkCommandBuffer frame, const SlopeTargets& targets) const {
  const bool horizons = codes != nullptr;
  const std::vector<Image>& slopes = targets.slopes;
  const std::vector<Image>& moments = targets.moments;
  const VkImageLayout before =
      targets.kept ? VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL : VK_IMAGE_LAYOUT_UNDEFINED;
  std::unique_ptr<ComputePipeline> plain;
  if (!horizons && !plainSlopes_) {
    plain = std::make_unique<ComputePipeline>(device, "slopes.comp", sizeof(SlopePush));
  }
  const ComputePipeline& pipeline = horizons ? *horizonSlopes_ : plain ? *plain : *plainSlopes_;
  auto nearest = std::make_unique<Sampler>(device, VK_FILTER_NEAREST, true);
  // Integer texels: no filter.
  auto codeSampler = std::make_unique<Sampler>(device, VK_FILTER_NEAREST, false);
  std::vector<std::vector<std::unique_ptr<LevelView>>> views(slopes.size());
  std::vector<std::vector<std::unique_ptr<LevelView>>> momentViews(moments.size());
  for (size_t p = 0; p < slopes.size(); ++p) {
    for (uint32_t level = 0; level < slopes[p].desc().mipLevels; ++level) {
      views[p].push_back(std::make_unique<LevelView>(device, slopes[p], level));
      if (horizons) {
        momentViews[p].push_back(std::make_unique<LevelView>(device, moments[p], level));
      }
    }
  }
  const auto record = [&](VkCommandBuffer cmd) {
    for (size_t p = 0; p < slopes.size(); ++p) {
      const Image& page = slopes[p];
      const uint32_t levels = page.desc().mipLevels;
      transitionImage(cmd, page, before, VK_IMAGE_LAYOUT_GENERAL);
      // The second moments as the horizons: a re-lay keeps the channel it
      // does not write, and the rows outside its band.
      if (horizons) {
        transitionImage(cmd, moments[p], before, VK_IMAGE_LAYOUT_GENERAL);
      }
      for (uint32_t level = 0; level < levels; ++level) {
        // The rows are whole multiples of the mip alignment: each level's
        // rows come from the level below's rows of the same band.
        const uint32_t begin = rowBegin >> level, end = rowEnd >> level;
        const SlopePush push{static_cast<int32_t>(level),
                             demInfo_.z,
                             demInfo_.w,
                             horizonBits_,
                             keepSlopes ? 1 : 0,
                             channel,
                             static_cast<int32_t>(begin),
                             static_cast<int32_t>(end)};
        const uint32_t w = page.desc().width >> level;
        DescriptorWrites writes;
        // Level 0 takes the heights' differences (and decodes the codes);
        // each level above is the mean of the one below (bound at level 0
        // too, unread: any other level).
        const uint32_t below = level > 0 ? level - 1 : std::min(1u, levels - 1);
        writes.image(0, heights_[p].view(), nearest->handle())
            .image(1, views[p][level]->handle())
            .image(3, views[p][below]->handle());
        if (horizons) {
          writes.image(2, (*codes)[p].view(), codeSampler->handle())
              .image(4, momentViews[p][level]->handle())
              .image(5, momentViews[p][below]->handle());
        }
        pipeline.record(cmd, writes, &push, (w + 7) / 8, (end - begin + 7) / 8, page.desc().layers);
        // The next level reads this one's slopes and horizons.
        transitionImage(cmd, page, VK_IMAGE_LAYOUT_GENERAL, VK_IMAGE_LAYOUT_GENERAL);
        if (horizons) {
          transitionImage(cmd, moments[p], VK_IMAGE_LAYOUT_GENERAL, VK_IMAGE_LAYOUT_GENERAL);
        }
      }
      transitionImage(cmd, page, VK_IMAGE_LAYOUT_GENERAL, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
      if (horizons) {
        transitionImage(cmd, moments[p], VK_IMAGE_LAYOUT_GENERAL,
                        VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
      }
    }
  };
  if (frame == VK_NULL_HANDLE) {
    submitAndWait(device, record);
    return;
  }
  // In a frame's commands: what they use lives until the frame has run.
  record(frame);
  device.deletionQueue().retire(std::make_tuple(std::move(views), std::move(momentViews),
                                                std::move(nearest), std::move(codeSampler),
                                                std::move(plain)));
}

float sunAzimuthRad(const glm::vec3& sun) {
  return std::abs(sun.x) + std::abs(sun.y) > 0.0f ? std::atan2(sun.y, sun.x) : 0.0f;
}

TerrainTileLimits deviceTileLimits(const Device& device, const TerrainTiling& tiling) {
  VkPhysicalDeviceMaintenance3Properties maintenance3{
      VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_MAINTENANCE_3_PROPERTIES};
  VkPhysicalDeviceProperties2 properties{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2};
  properties.pNext = &maintenance3;
  vkGetPhysicalDeviceProperties2(device.physical(), &properties);
  TerrainTileLimits limits;
  limits.maxTileTexels = tiling.maxTileTexels;
  limits.maxImageDimension = device.properties().limits.maxImageDimension2D;
  limits.maxArrayLayers = device.properties().limits.maxImageArrayLayers;
  limits.maxAllocationBytes = maintenance3.maxMemoryAllocationSize;
  if (tiling.maxPageBytes > 0) {
    limits.maxAllocationBytes = std::min<uint64_t>(limits.maxAllocationBytes, tiling.maxPageBytes);
  }
  return limits;
}

namespace {

DemRows heightRowsOf(const Heightfield& field) {
  const size_t w = static_cast<size_t>(field.width);
  return [&field, w](uint32_t first, uint32_t end, void* destination) {
    std::memcpy(destination, field.z.data() + first * w, (end - first) * w * 4);
  };
}

// Every texel an open sky: bent normal up, arc length pi/2.
DemRows openSkyRows(size_t width) {
  return [width](uint32_t first, uint32_t end, void* destination) {
    static const uint16_t up[4] = {Imath::half(0.0f).bits(), Imath::half(0.0f).bits(),
                                   Imath::half(1.0f).bits(), Imath::half(1.5707964f).bits()};
    uint16_t* out = static_cast<uint16_t*>(destination);
    for (size_t i = 0; i < (end - first) * width; ++i) std::copy(up, up + 4, out + 4 * i);
  };
}

// RGBA8 from the linear RGB floats, band by band (no second full copy).
DemRows albedoRowsOf(size_t width, const AlbedoImage* albedo) {
  if (!albedo) return {};
  return [albedo, width](uint32_t first, uint32_t end, void* destination) {
    auto* out = static_cast<uint8_t*>(destination);
    for (size_t i = first * width; i < end * width; ++i, out += 4) {
      for (int c = 0; c < 3; ++c) {
        out[c] =
            static_cast<uint8_t>(std::clamp(albedo->rgb[3 * i + c], 0.0f, 1.0f) * 255.0f + 0.5f);
      }
      out[3] = 255;
    }
  };
}

// The rows of an aperture map held as halves (HalfApertureMap::texels).
DemRows halfMapRows(const uint16_t* texels, size_t width) {
  return [texels, width](uint32_t first, uint32_t end, void* destination) {
    std::memcpy(destination, texels + first * width * 4, (end - first) * width * 8);
  };
}

// The lowest and highest height of `field`.
glm::vec2 heightRange(const Heightfield& field) {
  const auto [lo, hi] = std::minmax_element(field.z.begin(), field.z.end());
  return {*lo, *hi};
}

// The one texel of a scene without an albedo image (the shader ignores it).
constexpr uint8_t kNoAlbedo[4] = {128, 128, 128, 255};

// Level-0 bytes a texel of a staged build copies: its height and aperture.
constexpr size_t kStagedTexelBytes = kTerrainTextureBytes[int(TerrainTexture::Height)] +
                                     kTerrainTextureBytes[int(TerrainTexture::Aperture)];

}  // namespace

TerrainScene::TerrainScene(const Device& device, const Heightfield& field,
                           const ApertureMap& aperture, const AlbedoImage* albedo,
                           size_t triangleBudget, const TerrainTiling& tiling) {
  const size_t width = static_cast<size_t>(field.width);
  build(
      device, field,
      [&](uint32_t first, uint32_t end, void* destination) {
        const float* source = aperture.texels.data() + first * width * 4;
        std::transform(source, source + (end - first) * width * 4,
                       static_cast<uint16_t*>(destination),
                       [](float v) { return Imath::half(v).bits(); });
      },
      albedo, triangleBudget, tiling);
}

TerrainScene::TerrainScene(const Device& device, const Heightfield& field,
                           ApertureMapReader& aperture, const AlbedoImage* albedo,
                           size_t triangleBudget, const TerrainTiling& tiling) {
  build(
      device, field,
      [&](uint32_t first, uint32_t end, void* destination) {
        aperture.readHalfRows(static_cast<int>(first), static_cast<int>(end), destination);
      },
      albedo, triangleBudget, tiling);
}

TerrainScene::TerrainScene(const Device& device, const Heightfield& field,
                           const AlbedoImage* albedo, size_t triangleBudget,
                           const TerrainTiling& tiling) {
  build(device, field, openSkyRows(static_cast<size_t>(field.width)), albedo, triangleBudget,
        tiling);
}

// A map on its way to the device (stageAperture): the texels, the pages
// they fill and the upload, which reads the texels band by band.
struct TerrainScene::StagedAperture {
  const Device* device = nullptr;
  std::vector<uint16_t> texels;
  DemRows rows;                        // the texels' DEM rows, for tileRows
  std::vector<unsigned char> scratch;  // one band of DEM rows (tileRows)
  std::vector<Image> pages;
  std::unique_ptr<UploadBatch> upload;
};

// What build() fills the images from (each kind's DEM rows, the LOD's
// indices); kept with the upload while a staged build is under way.
struct TerrainScene::BuildRows {
  DemRows heights, apertures, albedo;
  std::vector<unsigned char> scratch;  // one band of DEM rows (tileRows)
  std::vector<uint32_t> patchIndices;
};

// A scene on its way to the device (staged): the rows its upload reads, the
// upload, and the slopes' next band once the upload is done.
struct TerrainScene::StagedBuild {
  std::shared_ptr<const Heightfield> field;
  std::vector<uint16_t> apertures;  // the map's halves; none: an open sky
  BuildRows rows;
  std::unique_ptr<UploadBatch> upload;  // null once every texture is copied
  uint32_t nextSlopeBand = 0;
};

// Like the scene's own pages, a staged map's live until the frames that
// used the scene have run (the viewer retires whole scenes).
TerrainScene::~TerrainScene() = default;

void TerrainScene::stageAperture(const Device& device, HalfApertureMap map) {
  const size_t width = static_cast<size_t>(demInfo_.x), height = static_cast<size_t>(demInfo_.y);
  if (size_t(map.width) != width || size_t(map.height) != height ||
      map.texels.size() != width * height * 4) {
    throw std::invalid_argument("stageAperture: a map of " + std::to_string(map.width) + "x" +
                                std::to_string(map.height) + " for a DEM of " +
                                std::to_string(width) + "x" + std::to_string(height));
  }
  auto staged = std::make_unique<StagedAperture>();
  staged->device = &device;
  staged->texels = std::move(map.texels);
  const uint16_t* texels = staged->texels.data();
  staged->rows = halfMapRows(texels, width);
  staged->pages =
      makeTexturePages(device, tiles_, TerrainTexture::Aperture, aperture_.front().desc().format);
  staged->upload = std::make_unique<UploadBatch>(device);
  addTileImages(*staged->upload, tiles_, staged->pages, TerrainTexture::Aperture, staged->rows,
                staged->scratch, reduceApertures);
  // A share of the one before may be on the device.
  if (staged_) device.deletionQueue().retire(std::move(staged_->pages));
  staged_ = std::move(staged);
}

uint64_t TerrainScene::apertureTexelsLeft() const {
  if (!staged_) return 0;
  // Staging bytes of the levels, 4/3 of level 0's.
  const size_t texelBytes = kTerrainTextureBytes[int(TerrainTexture::Aperture)];
  return staged_->upload->bytesLeft() * 3 / 4 / texelBytes;
}

bool TerrainScene::recordApertureShare(VkCommandBuffer frame, uint64_t texels) {
  if (!staged_) return true;
  const size_t texelBytes = kTerrainTextureBytes[int(TerrainTexture::Aperture)];
  // A band's levels take 4/3 of its level-0 bytes.
  if (!staged_->upload->recordShare(frame, texels * texelBytes * 4 / 3)) return false;
  // The frames before this one read the old pages.
  staged_->device->deletionQueue().retire(std::exchange(aperture_, std::move(staged_->pages)));
  staged_.reset();
  id_ = nextSceneId();
  return true;
}

std::array<TerrainScene::TextureKind, 3> TerrainScene::textureKinds() {
  return {{{TerrainTexture::Height, &heights_, VK_FORMAT_R32_SFLOAT, &BuildRows::heights,
            reduceHeights},
           {TerrainTexture::Aperture, &aperture_, VK_FORMAT_R16G16B16A16_SFLOAT,
            &BuildRows::apertures, reduceApertures},
           {TerrainTexture::Albedo, &albedo_, VK_FORMAT_R8G8B8A8_UNORM, &BuildRows::albedo,
            reduceAlbedo}}};
}

PreparedTerrain prepareTerrain(std::shared_ptr<const Heightfield> field) {
  if (!field) throw std::invalid_argument("prepareTerrain: no heightfield");
  PreparedTerrain prepared;
  prepared.lod = std::make_unique<LodQuadtree>(*field);
  const glm::vec2 range = heightRange(*field);
  prepared.minHeight = range.x;
  prepared.maxHeight = range.y;
  prepared.field = std::move(field);
  return prepared;
}

void TerrainScene::build(const Device& device, const Heightfield& field,
                         const DemRows& apertureRows, const AlbedoImage* albedo,
                         size_t triangleBudget, const TerrainTiling& tiling) {
  BuildRows rows{heightRowsOf(field), apertureRows,
                 albedoRowsOf(static_cast<size_t>(field.width), albedo)};
  makeImages(device, field, std::make_unique<LodQuadtree>(field), heightRange(field),
             albedo != nullptr, triangleBudget, tiling, rows);
  UploadBatch upload(device);
  addUploads(upload, rows);
  upload.submit();
  computeSlopes(device, 0, false);
}

void TerrainScene::makeImages(const Device& device, const Heightfield& field,
                              std::unique_ptr<LodQuadtree> lod, glm::vec2 heightRange, bool albedo,
                              size_t triangleBudget, const TerrainTiling& tiling, BuildRows& rows) {
  if (triangleBudget < 2) throw std::invalid_argument("triangle budget must be at least 2");
  id_ = nextSceneId();
  const uint32_t w = static_cast<uint32_t>(field.width), h = static_cast<uint32_t>(field.height);
  tiling_ = tiling;
  tiles_ = planTerrainTiles(w, h, deviceTileLimits(device, tiling));
  hasAlbedo_ = albedo;
  textureBytes_ = 0;
  try {
    for (const TextureKind& kind : textureKinds()) {
      if (kind.pages == &albedo_ && !albedo) {
        // A bound texture is required; one texel that the shader ignores.
        albedo_.emplace_back(device, ImageDesc{1, 1, kind.format, kTextureUsage,
                                               VK_IMAGE_ASPECT_COLOR_BIT, 1, true});
        continue;
      }
      *kind.pages = makeTexturePages(device, tiles_, kind.texture, kind.format);
      for (const Image& page : *kind.pages) {
        textureBytes_ +=
            tiles_.layerTexels() * page.desc().layers * kTerrainTextureBytes[int(kind.texture)];
      }
    }
    slopes_ = makeSlopePages(device, tiles_, false);
    textureBytes_ += slopeBytes(tiles_, false);
  } catch (const VulkanError& e) {
    throw VulkanError("the DEM's textures (" + describeTerrainTiles(tiles_) + ", " +
                      std::to_string(tiles_.texelsPerKind() * (hasAlbedo_ ? 20 : 16) >> 20) +
                      " MiB) do not fit the device's memory: " + e.what());
  }

  lod_ = std::move(lod);
  triangleBudget_ = triangleBudget;
  lodBudgetErrorScale_ = aal::lodBudgetErrorScale(*lod_, triangleBudget);
  rows.patchIndices = makeLodPatchIndices();
  indices_ = Buffer(device, rows.patchIndices.size() * sizeof(uint32_t),
                    VK_BUFFER_USAGE_INDEX_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                    MemoryIntent::DeviceLocal);
  demInfo_ = {static_cast<float>(field.width), static_cast<float>(field.height),
              static_cast<float>(field.cellSizeXM), static_cast<float>(field.cellSizeYM)};
  minHeight_ = heightRange.x;
  maxHeight_ = heightRange.y;
}

void TerrainScene::addUploads(UploadBatch& upload, BuildRows& rows) {
  // The indices first: a share takes at least the widest band of the images
  // still to come, so they never go a few bytes a share.
  upload.addBuffer(indices_, rows.patchIndices.data(), rows.patchIndices.size() * sizeof(uint32_t));
  for (const TextureKind& kind : textureKinds()) {
    if (kind.pages == &albedo_ && !hasAlbedo_) {
      upload.addImage(albedo_[0], 4, kNoAlbedo);
      continue;
    }
    addTileImages(upload, tiles_, *kind.pages, kind.texture, rows.*kind.rows, rows.scratch,
                  kind.reduce);
  }
}

std::unique_ptr<TerrainScene> TerrainScene::staged(const Device& device, PreparedTerrain prepared,
                                                   size_t triangleBudget,
                                                   const TerrainTiling& tiling) {
  if (!prepared.field || !prepared.lod) {
    throw std::invalid_argument("TerrainScene::staged: not a prepared terrain");
  }
  std::unique_ptr<TerrainScene> scene(new TerrainScene());
  auto staged = std::make_unique<StagedBuild>();
  staged->field = prepared.field;
  const Heightfield& f = *staged->field;
  const size_t width = static_cast<size_t>(f.width);
  HalfApertureMap& map = prepared.aperture;
  if (map.width != 0 && (map.width != f.width || map.height != f.height ||
                         map.texels.size() != width * static_cast<size_t>(f.height) * 4)) {
    throw std::invalid_argument("TerrainScene::staged: a map of " + std::to_string(map.width) +
                                "x" + std::to_string(map.height) + " for a DEM of " +
                                std::to_string(f.width) + "x" + std::to_string(f.height));
  }
  staged->apertures = std::move(map.texels);
  staged->rows = {
      heightRowsOf(f),
      staged->apertures.empty() ? openSkyRows(width) : halfMapRows(staged->apertures.data(), width),
      {}};
  scene->makeImages(device, f, std::move(prepared.lod), {prepared.minHeight, prepared.maxHeight},
                    false, triangleBudget, tiling, staged->rows);
  staged->upload = std::make_unique<UploadBatch>(device);
  scene->addUploads(*staged->upload, staged->rows);
  // One pipeline for every band's pass (lavapipe compiles each anew).
  scene->plainSlopes_ = std::make_unique<ComputePipeline>(device, "slopes.comp", sizeof(SlopePush));
  scene->stagedBuild_ = std::move(staged);
  return scene;
}

bool TerrainScene::recordBuildShare(const Device& device, VkCommandBuffer frame, uint64_t texels) {
  if (!stagedBuild_) return true;
  StagedBuild& staged = *stagedBuild_;
  if (staged.upload) {
    // The heights' and the apertures' bands; a band's levels take 4/3 of
    // its level-0 bytes.
    if (!staged.upload->recordShare(frame, texels * kStagedTexelBytes * 4 / 3)) return false;
    // The slopes read the heights of the bands beside their own: they begin
    // with the next share, once every height is copied.
    staged.upload.reset();
    return false;
  }
  const uint32_t bands = horizonBands();
  const uint32_t count = static_cast<uint32_t>(
      std::clamp<uint64_t>(texels / horizonBandTexels(), 1, bands - staged.nextSlopeBand));
  const uint32_t rowBegin = staged.nextSlopeBand * kTerrainMipAlignment;
  const uint32_t rowEnd = (staged.nextSlopeBand + count) * kTerrainMipAlignment;
  runSlopePass(device, nullptr, false, kBothChannels, rowBegin, rowEnd, frame,
               {slopes_, horizonMoments_, staged.nextSlopeBand > 0});
  staged.nextSlopeBand += count;
  if (staged.nextSlopeBand < bands) return false;
  // What the upload read (the heights are the field's) is no longer needed.
  stagedBuild_.reset();
  return true;
}

uint64_t TerrainScene::buildTexelsLeft() const {
  if (!stagedBuild_) return 0;
  const uint64_t slopeTexels =
      uint64_t(horizonBands() - stagedBuild_->nextSlopeBand) * horizonBandTexels();
  if (!stagedBuild_->upload) return slopeTexels;
  return stagedBuild_->upload->bytesLeft() * 3 / 4 / kStagedTexelBytes + slopeTexels;
}

void TerrainScene::setHorizons(const Device& device, const HorizonMap& map, int first) {
  setHorizons(device, std::make_shared<const HorizonMap>(map), first);
}

struct TerrainScene::HorizonPages {
  std::vector<Image> slopes, moments;
};

// A pair of horizons on its way to the device (stageHorizons): its images,
// filled band by band, and the next band.
struct TerrainScene::StagedHorizons {
  std::shared_ptr<const HorizonMap> map;
  int first = 0;
  HorizonPages pages;
  uint32_t nextBand = 0;
};

TerrainScene::HorizonPages TerrainScene::makeHorizonPages(const Device& device,
                                                          const HorizonMap& map, int first) {
  const glm::vec4 dem = demInfo_;
  if (map.width != int(dem.x) || map.height != int(dem.y) ||
      !validHorizonDirections(map.directions) || !validHorizonBits(map.bits) ||
      map.codes.size() != size_t(map.width) * size_t(map.height) * size_t(map.directions)) {
    throw std::invalid_argument("the horizon map is " + std::to_string(map.width) + "x" +
                                std::to_string(map.height) + ", the DEM " +
                                std::to_string(int(dem.x)) + "x" + std::to_string(int(dem.y)));
  }
  if (!validHorizonPair(map.directions, first)) {
    throw std::invalid_argument("setHorizons: direction " + std::to_string(first) + " of " +
                                std::to_string(map.directions));
  }
  // RGBA16F slopes: R and G the slopes, B and A the pair's horizons, in the
  // heights' pages, which were planned for 4 bytes a texel: each page's 8
  // must fit an allocation too.
  const TerrainTileLimits limits = deviceTileLimits(device, tiling_);
  const uint64_t pageBytes =
      tiles_.layerTexels() * tiles_.layersPerPageOf(TerrainTexture::Height) * 8;
  if (pageBytes > limits.maxAllocationBytes / 16 * 15) {
    throw std::runtime_error("the directional horizons of " + describeTerrainTiles(tiles_) + " (" +
                             std::to_string(pageBytes >> 20) +
                             " MiB a page of slopes with horizons) do not fit one image of the "
                             "device (" +
                             std::to_string(limits.maxAllocationBytes >> 20) +
                             " MiB an allocation)");
  }
  HorizonPages pages{makeSlopePages(device, tiles_, true), makeHorizonMomentPages(device, tiles_)};
  if (!horizonSlopes_) {
    horizonSlopes_ =
        std::make_unique<ComputePipeline>(device, "slopes_horizons.comp", sizeof(SlopePush));
  }
  return pages;
}

void TerrainScene::adoptHorizons(const Device& device, HorizonPages pages,
                                 std::shared_ptr<const HorizonMap> map, int first) {
  const uint64_t bytes = slopeBytes(tiles_, true) - slopeBytes(tiles_, false);
  // Frames in flight may still read the images before: retired.
  device.deletionQueue().retire(std::exchange(slopes_, std::move(pages.slopes)));
  device.deletionQueue().retire(std::exchange(horizonMoments_, std::move(pages.moments)));
  textureBytes_ += bytes - horizonBytes_;  // a second map replaces the first
  horizonBytes_ = bytes;
  horizonBits_ = map->bits;
  horizonDirections_ = map->directions;
  horizonMap_ = std::move(map);
  horizonChannels_ = HorizonChannels{{first, (first + 1) % horizonDirections_}};
}

void TerrainScene::setHorizons(const Device& device, std::shared_ptr<const HorizonMap> shared,
                               int first) {
  if (!shared) throw std::invalid_argument("setHorizons: no horizon map");
  // Made before anything changes, so a device too small keeps the scene as
  // it was.
  HorizonPages pages = makeHorizonPages(device, *shared, first);
  adoptHorizons(device, std::move(pages), std::move(shared), first);
  computeSlopes(device, first, false);
}

void TerrainScene::stageHorizons(const Device& device, std::shared_ptr<const HorizonMap> shared,
                                 int first) {
  if (!shared) throw std::invalid_argument("stageHorizons: no horizon map");
  auto staged = std::make_unique<StagedHorizons>();
  staged->pages = makeHorizonPages(device, *shared, first);
  staged->map = std::move(shared);
  staged->first = first;
  // A share of the ones before may be on the device.
  if (stagedHorizons_) {
    device.deletionQueue().retire(std::move(stagedHorizons_->pages.slopes));
    device.deletionQueue().retire(std::move(stagedHorizons_->pages.moments));
  }
  stagedHorizons_ = std::move(staged);
}

bool TerrainScene::recordHorizonShare(const Device& device, VkCommandBuffer frame,
                                      uint64_t texels) {
  if (!stagedHorizons_) return true;
  StagedHorizons& staged = *stagedHorizons_;
  const uint32_t bands = horizonBands();
  const uint32_t count = static_cast<uint32_t>(
      std::clamp<uint64_t>(texels / horizonBandTexels(), 1, bands - staged.nextBand));
  const uint32_t rowBegin = staged.nextBand * kTerrainMipAlignment;
  const uint32_t rowEnd = (staged.nextBand + count) * kTerrainMipAlignment;
  const int n = staged.map->directions;
  frame = frameForCodes(frame, 2 * uint64_t(count) * horizonBandTexels());
  std::vector<Image> codes = horizonCodePages(
      device, tiles_, *staged.map, {staged.first, (staged.first + 1) % n}, rowBegin, rowEnd, frame);
  // The first band finds the images new; the others keep the bands before.
  runSlopePass(device, &codes, false, kBothChannels, rowBegin, rowEnd, frame,
               {staged.pages.slopes, staged.pages.moments, staged.nextBand > 0});
  if (frame != VK_NULL_HANDLE) device.deletionQueue().retire(std::move(codes));
  staged.nextBand += count;
  if (staged.nextBand < bands) return false;
  adoptHorizons(device, std::move(staged.pages), std::move(staged.map), staged.first);
  stagedHorizons_.reset();
  return true;
}

int TerrainScene::horizonFirst() const {
  return horizonMap_ ? horizonChannelsPair(horizonDirections_, horizonChannels_) : 0;
}

uint32_t TerrainScene::horizonBands() const {
  return tiles_.imageHeight() / kTerrainMipAlignment;
}

uint64_t TerrainScene::horizonBandTexels() const {
  uint64_t layers = 0;
  for (const Image& page : slopes_) layers += page.desc().layers;
  return uint64_t{tiles_.imageWidth()} * kTerrainMipAlignment * layers;
}

void TerrainScene::relayHorizons(const Device& device, int first) const {
  if (!horizonMap_) return;
  if (!validHorizonPair(horizonDirections_, first)) {
    throw std::invalid_argument("relayHorizons: direction " + std::to_string(first) + " of " +
                                std::to_string(horizonDirections_));
  }
  const int n = horizonDirections_, now = horizonFirst();
  // Mixed or half laid, the channels are laid anew.
  const bool whole = !horizonChannels_.mixing() && !horizonChannels_.layingPair();
  if (first == now && whole) return;
  HorizonRelayStep step;
  if (whole && (first == (now + 1) % n || first == (now + n - 1) % n)) {
    // One direction in common: only the other's channel is written.
    const bool up = first == (now + 1) % n;
    const int replaced = up ? now : (now + 1) % n;
    step.kind = HorizonRelayStep::Kind::WriteBands;
    step.channel = horizonChannels_.directions[0] == replaced ? 0 : 1;
    step.direction = up ? (now + 2) % n : first;
    step.bandBegin = 0;
    step.bandEnd = horizonBands();
  } else {
    step.kind = HorizonRelayStep::Kind::LayPair;
    step.first = first;
  }
  writeHorizonRelay(device, step);
}

void TerrainScene::writeHorizonRelay(const Device& device, const HorizonRelayStep& step,
                                     VkCommandBuffer frame) const {
  if (!horizonMap_ || step.kind == HorizonRelayStep::Kind::Keep) return;
  const int before = horizonFirst();
  if (step.kind == HorizonRelayStep::Kind::LayPair) {
    if (!validHorizonPair(horizonDirections_, step.first)) {
      throw std::invalid_argument("writeHorizonRelay: direction " + std::to_string(step.first) +
                                  " of " + std::to_string(horizonDirections_));
    }
    // The same images, written in place: frames already submitted may still
    // read them, and the pass's first barrier waits for those reads
    // (runSlopePass); commands not yet submitted must not (the caller's
    // promise).
    computeSlopes(device, step.first, true);
  } else {
    const bool pair = step.kind == HorizonRelayStep::Kind::LayBands;
    if ((pair ? !validHorizonPair(horizonDirections_, step.first)
              : step.channel < 0 || step.channel > 1 ||
                    !validHorizonPair(horizonDirections_, step.direction)) ||
        step.bandBegin >= step.bandEnd || step.bandEnd > horizonBands()) {
      throw std::invalid_argument("writeHorizonRelay: bands " + std::to_string(step.bandBegin) +
                                  " to " + std::to_string(step.bandEnd) + " of " +
                                  std::to_string(horizonBands()));
    }
    // Whole bands of kTerrainMipAlignment rows: every level's rows of the
    // band come from the band's rows below (docs/rendering.md).
    const uint32_t rowBegin = step.bandBegin * kTerrainMipAlignment;
    const uint32_t rowEnd = step.bandEnd * kTerrainMipAlignment;
    // Into the frame's commands when its codes fit one staging buffer (a
    // frame's share of a spread re-lay): nothing waits; a whole re-lay at
    // once is submitted and waited for. One code a channel: the pair's two,
    // or the written channel's twice.
    const std::vector<int> directions =
        pair ? std::vector<int>{step.first, (step.first + 1) % horizonDirections_}
             : std::vector<int>{step.direction, step.direction};
    frame = frameForCodes(
        frame, directions.size() * uint64_t(step.bandEnd - step.bandBegin) * horizonBandTexels());
    std::vector<Image> codes =
        horizonCodePages(device, tiles_, *horizonMap_, directions, rowBegin, rowEnd, frame);
    runSlopePass(device, &codes, true, pair ? kBothChannels : step.channel, rowBegin, rowEnd, frame,
                 {slopes_, horizonMoments_, true});
    if (frame != VK_NULL_HANDLE) device.deletionQueue().retire(std::move(codes));
  }
  horizonChannels_ = afterHorizonRelay(horizonDirections_, horizonChannels_, step, horizonBands());
  if (!horizonChannels_.mixing() && !horizonChannels_.layingPair() && horizonFirst() != before) {
    ++horizonRelays_;
  }
}

}  // namespace aal
