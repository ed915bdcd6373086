// The GPU side of one DEM: height, aperture and albedo textures, the quadtree
// LOD (terrain/view/quadtree_lod.h) and its patch mesh. DEMs beyond one image of
// the device (or a forced tile size) are split into tiles with borders
// (engine/terrain_tiles.h); every tile stays resident (docs/rendering.md).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "aperture/engine/horizon_relay.h"
#include "aperture/engine/terrain_tiles.h"
#include "aperture/engine/vk/buffer.h"
#include "aperture/engine/vk/compute.h"
#include "aperture/engine/vk/image.h"
#include "aperture/engine/vk/upload.h"
#include "aperture/terrain/heightfield.h"
#include "aperture/terrain/io/albedo_image.h"
#include "aperture/terrain/io/aperture_map.h"
#include "aperture/terrain/io/horizon_map.h"
#include "aperture/terrain/reference/relief.h"
#include "aperture/terrain/view/quadtree_lod.h"

namespace aal {

class Device;

// The tile limits of `device` (image size, array layers, allocation size),
// narrowed by `tiling`: what TerrainScene plans its tiles with.
TerrainTileLimits deviceTileLimits(const Device& device, const TerrainTiling& tiling);

// The azimuth of a sun direction (DEM frame: x east, y north, z up) in the
// directional horizons' convention: rad counter-clockwise from east; 0 at
// the zenith, where any azimuth serves. What the renderer picks the
// horizons' pair and weights with (horizonPairFor, horizonPairWeights).
float sunAzimuthRad(const glm::vec3& sunDirection);

// What a scene takes from its DEM alone, with the host's longest work (the
// quadtree LOD's geometric errors: 0.36 s at 4096^2 on two cores), made on
// any thread: aal-view reads a dropped DEM and prepares it on one.
struct PreparedTerrain {
  std::shared_ptr<const Heightfield> field;
  std::unique_ptr<LodQuadtree> lod;
  float minHeight = 0, maxHeight = 0;
  // Its aperture map as the device holds it, when the caller has one
  // (checkApertureMatchesDem, readHalfApertureMap); none (width 0): an open
  // sky.
  HalfApertureMap aperture;
};
PreparedTerrain prepareTerrain(std::shared_ptr<const Heightfield> field);

class TerrainScene {
 public:
  ~TerrainScene();
  // Uploads everything in one batch. The aperture map must belong to the DEM
  // (checkApertureMatchesDem). `albedo` may be null: a palette by height and
  // slope is used then. `triangleBudget` caps the triangles the LOD draws per
  // frame (lodBudgetErrorScale; never coarser than the crack-free ranges allow).
  // `tiling` may ask for smaller tiles and fewer per page than the device
  // allows (tests, aal-render --max-tile). Throws
  // std::runtime_error (planTerrainTiles) when the DEM needs more texture
  // pages than the renderer binds, and VulkanError naming the DEM, its tiles
  // and the bytes when the device cannot hold them.
  TerrainScene(const Device& device, const Heightfield& field, const ApertureMap& aperture,
               const AlbedoImage* albedo, size_t triangleBudget, const TerrainTiling& tiling = {});
  // The same, streaming the aperture map from its file band by band (it must
  // match the DEM, checkApertureMatchesDem), so it is never held as floats.
  TerrainScene(const Device& device, const Heightfield& field, ApertureMapReader& aperture,
               const AlbedoImage* albedo, size_t triangleBudget, const TerrainTiling& tiling = {});
  // The same with an open sky at every texel (bent normal up, arc length
  // pi/2) in place of an aperture map: aal-view shows the baseline modes with
  // it while the real map is baked.
  TerrainScene(const Device& device, const Heightfield& field, const AlbedoImage* albedo,
               size_t triangleBudget, const TerrainTiling& tiling = {});

  // The scene of `prepared` (its map, else an open sky) made without a
  // stall (aal-view's dropped DEMs): the images and the LOD's mesh are made
  // now, what they hold goes to the device a share a frame by
  // recordBuildShare, and nothing may draw the scene before built(). The
  // scene keeps the prepared field and map until then: the shares read them.
  // Throws std::invalid_argument for a map of another size.
  static std::unique_ptr<TerrainScene> staged(const Device& device, PreparedTerrain prepared,
                                              size_t triangleBudget,
                                              const TerrainTiling& tiling = {});
  // Whether every texture is on the device (always, but for a staged scene
  // before its last share).
  bool built() const { return stagedBuild_ == nullptr; }
  // Records the next share of a staged scene into `frame`, before any of
  // its passes: whole bands of about `texels` level-0 texels of the heights
  // and apertures (their mip levels made on the host, each share's staging
  // buffer retired into the device's DeletionQueue: nothing waits), then,
  // from the share after the last copy, the slopes' bands, computed on the
  // device. Returns true with the last share (built() then) and when
  // nothing is staged.
  bool recordBuildShare(const Device& device, VkCommandBuffer frame, uint64_t texels);
  // Level-0 texels a staged build still has to copy, and then to compute
  // the slopes of (0: built).
  uint64_t buildTexelsLeft() const;

  // Replaces the aperture map without a stall (aal-view's background bake):
  // new pages are made now and filled a share a frame by
  // recordApertureShare from `map` (as the device holds it: RGBA halves;
  // readHalfApertureMap), which the scene keeps until then. Frames keep drawing the map before
  // until the last share. A map staged before and not yet complete is
  // dropped. Throws std::invalid_argument for a map of another size and
  // VulkanError when the device cannot hold the second set of pages.
  void stageAperture(const Device& device, HalfApertureMap map);
  bool apertureStaged() const { return staged_ != nullptr; }
  // Records the next share of the staged map's upload into `frame`, before
  // any of its passes: whole bands of about `texels` level-0 texels, their
  // mip levels made on the host (a fresh staging buffer each time, retired
  // into the device's DeletionQueue: nothing waits). With the last share the
  // scene swaps the pages in, retiring the ones before, and takes a new id()
  // (what the shading's histories are kept for changed); it returns true
  // then. Nothing staged: returns true and records nothing.
  bool recordApertureShare(VkCommandBuffer frame, uint64_t texels);
  // Level-0 texels still to be copied of the staged map (0: none staged).
  uint64_t apertureTexelsLeft() const;

  // How the textures are tiled (one tile: the images are the DEM).
  const TerrainTileLayout& tiles() const { return tiles_; }
  // The texture pages per kind (2D array images, one layer per tile;
  // tiles().pages of them; without an albedo image one page of one texel).
  const std::vector<Image>& heightPages() const { return heights_; }
  const std::vector<Image>& aperturePages() const { return aperture_; }
  const std::vector<Image>& albedoPages() const { return albedo_; }
  // Slopes of the heights (dz/dx east, dz/dy north per mip level,
  // shaders/slopes.glsl), in the heights' tiles and pages: the terrain's
  // normals in one fetch. RG16F; RGBA16F with directional horizons, whose
  // B and A hold the means of the horizons (rad) of the pair of stored
  // directions beside the sun (setHorizons), each level's the mean of the
  // level below's.
  const std::vector<Image>& slopePages() const { return slopes_; }
  // With directional horizons: the second moments of the pair's horizons
  // (rad^2, R and G; terrain/light/horizon_moments.h), RG16F in the slopes'
  // tiles, pages and levels; else none.
  const std::vector<Image>& horizonMomentPages() const { return horizonMoments_; }
  // Device memory of the textures (bytes, level 0).
  uint64_t textureBytes() const { return textureBytes_; }
  bool hasAlbedo() const { return hasAlbedo_; }
  // Directional horizons for the horizon mode (terrain/io/horizon_map.h).
  // The device holds two of the map's directions at a time, `first` and
  // first + 1 mod n (horizonPairFor), decoded and prefiltered as moments:
  // the means in the slope texture's B and A channels (which makes it
  // RGBA16F: 4 B more per texel), the second moments in horizonMomentPages
  // (4 B more);
  // the scene keeps `map` (shared, not copied) to lay another pair. Replaces
  // the slope images, retiring the ones before into the device's
  // DeletionQueue (frames in flight may still read them). Throws
  // std::invalid_argument for a map of another size or an invalid pair.
  void setHorizons(const Device& device, std::shared_ptr<const HorizonMap> map, int first = 0);
  // The same with a copy of `map` (tests; the tools share theirs).
  void setHorizons(const Device& device, const HorizonMap& map, int first = 0);
  // setHorizons without a stall (aal-view's background bake): the slopes
  // with the pair's horizons and their moments are made in new images, a
  // share a frame by recordHorizonShare; until the last share the scene draws
  // as before (without horizons: hasHorizons() false, or with the ones it
  // had). Throws as setHorizons; drops horizons staged before.
  void stageHorizons(const Device& device, std::shared_ptr<const HorizonMap> map, int first);
  bool horizonsStaged() const { return stagedHorizons_ != nullptr; }
  // Records the next share into `frame`, before any of its passes: whole
  // bands of about `texels` level-0 texels (at least one band), their codes
  // uploaded and every level's slopes and horizons computed (nothing waits;
  // what it made retired into the device's DeletionQueue; a share whose
  // codes exceed one staging buffer is submitted and waited for instead). With the last
  // share the scene takes the new images (the ones before retired) and the
  // map, as setHorizons would have left it, and returns true; also when
  // nothing is staged.
  bool recordHorizonShare(const Device& device, VkCommandBuffer frame, uint64_t texels);

  // Writes the horizons of another pair into the slope texture at once
  // (nothing when it is the current one): an upload of the codes and a
  // compute pass, waited for; of one direction when the pairs share the
  // other (only its channel changes), else of both. Frames already submitted
  // may read the slopes (the compute pass's barrier waits for them);
  // commands recorded but not yet submitted must not. Const: the horizons
  // stay what they are, only the pair on the device changes.
  void relayHorizons(const Device& device, int first) const;
  // One frame's share of a re-lay (engine/horizon_relay.h planHorizonRelay):
  // the bands' codes uploaded and their rows of every level computed.
  // TerrainRenderer::record calls it for a frame's sun with the frame's
  // command buffer, after the frame's first barrier and before its passes:
  // a band step (one channel's, or a spread jump's both) whose codes fit one
  // staging buffer is recorded there (its staging, code images and views
  // retired into the device's DeletionQueue) and nothing waits; a whole
  // pair at once (LayPair), or a larger step, is submitted and
  // waited for, as relayHorizons does, before any of `frame`'s commands may
  // read the slopes. Without `frame`, every step is submitted and waited for.
  void writeHorizonRelay(const Device& device, const HorizonRelayStep& step,
                         VkCommandBuffer frame = VK_NULL_HANDLE) const;
  // What B and A hold now, per band while a re-lay is under way.
  const HorizonChannels& horizonChannels() const { return horizonChannels_; }
  // Bands of kTerrainMipAlignment rows of every tile image a re-lay writes,
  // and the level-0 texels of one (all tiles).
  uint32_t horizonBands() const;
  uint64_t horizonBandTexels() const;
  bool hasHorizons() const { return horizonMap_ != nullptr; }
  uint64_t horizonBytes() const { return horizonBytes_; }  // of textureBytes()
  int horizonBits() const { return horizonBits_; }
  int horizonDirections() const { return horizonDirections_; }  // 0: none
  // Of the pair on the device (while a re-lay is under way: the pair before).
  int horizonFirst() const;
  // Re-lays so far, each counted when it is complete (TerrainRenderer's,
  // tests).
  uint64_t horizonRelays() const { return horizonRelays_; }
  // The LOD patch's index buffer (makeLodPatchIndices).
  const Buffer& indices() const { return indices_; }
  const LodQuadtree& lod() const { return *lod_; }
  size_t triangleBudget() const { return triangleBudget_; }
  // lodBudgetErrorScale of the quadtree and the budget (+inf: no limit).
  double lodBudgetErrorScale() const { return lodBudgetErrorScale_; }
  // width, height (texels), cell size x, y (metres)
  glm::vec4 demInfo() const { return demInfo_; }
  float minHeight() const { return minHeight_; }
  // Unique among the scenes of the process (what the renderer's kept
  // obscurance samples belong to).
  uint64_t id() const { return id_; }
  float maxHeight() const { return maxHeight_; }

 private:
  TerrainScene() = default;  // staged()
  // Fills slopes_ from heights_ on the device (after their upload), and
  // with horizons their B and A and horizonMoments_ from the pair `first`,
  // first + 1; `keepSlopes`: R and G are there already (a re-lay), only the
  // horizons' moments change.
  void computeSlopes(const Device& device, int first, bool keepSlopes) const;
  // The images a slope pass writes: the scene's, or staged ones
  // (stageHorizons). `kept`: they hold what other rows need (written
  // before, in SHADER_READ_ONLY_OPTIMAL), else their contents are dropped.
  struct SlopeTargets {
    const std::vector<Image>& slopes;
    const std::vector<Image>& moments;
    bool kept;
  };
  // The pass of slopes.comp or (with `codes`) slopes_horizons.comp over rows
  // [rowBegin, rowEnd) (multiples of kTerrainMipAlignment) of every tile
  // image and level of `targets`; with horizons it writes `channel` (0 B, 1
  // A, 2 both) from the codes, which hold those rows; `keepSlopes`: R and G
  // are left as they are. With `frame` it is recorded there (what it made
  // retired), else submitted and waited for.
  void runSlopePass(const Device& device, const std::vector<Image>* codes, bool keepSlopes,
                    int channel, uint32_t rowBegin, uint32_t rowEnd, VkCommandBuffer frame,
                    const SlopeTargets& targets) const;
  // setHorizons' checks and images (the slopes with horizons, the moments),
  // made before anything changes; the horizon pipeline made once.
  struct HorizonPages;
  HorizonPages makeHorizonPages(const Device& device, const HorizonMap& map, int first);
  // The scene takes `pages` and the map: the pair `first` on the device.
  void adoptHorizons(const Device& device, HorizonPages pages,
                     std::shared_ptr<const HorizonMap> map, int first);
  struct BuildRows;
  // One texture kind a scene uploads from the DEM's rows.
  struct TextureKind {
    TerrainTexture texture;
    std::vector<Image>* pages;
    VkFormat format;
    std::function<void(uint32_t, uint32_t, void*)> BuildRows::*rows;
    MipReducer reduce;
  };
  std::array<TextureKind, 3> textureKinds();
  // The tiles, the texture and slope images, the LOD's index buffer (the
  // indices into `rows`); the scene takes `lod` and the heights' range (min,
  // max): all but the upload.
  void makeImages(const Device& device, const Heightfield& field, std::unique_ptr<LodQuadtree> lod,
                  glm::vec2 heightRange, bool albedo, size_t triangleBudget,
                  const TerrainTiling& tiling, BuildRows& rows);
  // Adds every texture and the index buffer to `upload`, read from `rows`
  // (which must outlive it).
  void addUploads(UploadBatch& upload, BuildRows& rows);
  // `apertureRows` writes whole DEM rows of RGBA16F bent normal + arc length.
  void build(const Device& device, const Heightfield& field,
             const std::function<void(uint32_t firstRow, uint32_t endRow, void* destination)>&
                 apertureRows,
             const AlbedoImage* albedo, size_t triangleBudget, const TerrainTiling& tiling);

  struct StagedAperture;
  struct StagedHorizons;
  struct StagedBuild;

  TerrainTiling tiling_;  // what the caller asked for beyond the device's limits
  TerrainTileLayout tiles_;
  std::vector<Image> heights_, aperture_, albedo_, slopes_;
  std::vector<Image> horizonMoments_;             // with horizons (horizonMomentPages)
  std::shared_ptr<const HorizonMap> horizonMap_;  // the host copy (for re-laying); null: none
  // slopes_horizons.comp, made once (a pipeline is compiled on lavapipe:
  // tens of ms a re-lay otherwise).
  std::unique_ptr<ComputePipeline> horizonSlopes_;
  // slopes.comp for a staged build's bands (else made per pass).
  std::unique_ptr<ComputePipeline> plainSlopes_;
  int horizonBits_ = kHorizonBits;
  int horizonDirections_ = 0;
  // What B and A hold now: the device's state, not the scene's content
  // (relayHorizons is const).
  mutable HorizonChannels horizonChannels_;
  mutable uint64_t horizonRelays_ = 0;
  uint64_t horizonBytes_ = 0;
  uint64_t textureBytes_ = 0;
  Buffer indices_;
  bool hasAlbedo_ = false;
  std::unique_ptr<LodQuadtree> lod_;
  size_t triangleBudget_ = 0;
  double lodBudgetErrorScale_ = 0;
  glm::vec4 demInfo_{0.0f};
  float minHeight_ = 0, maxHeight_ = 0;
  uint64_t id_ = 0;
  std::unique_ptr<StagedAperture> staged_;          // stageAperture's map until it is swapped in
  std::unique_ptr<StagedHorizons> stagedHorizons_;  // stageHorizons' until they are
  std::unique_ptr<StagedBuild> stagedBuild_;        // staged()'s until built
};

}  // namespace aal
