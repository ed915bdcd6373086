// Headless rendering of a terrain scene: the frame is a list of passes
// (terrain, sky, obscurance/W, 4x4 filter and composite, tone map) into
// offscreen targets, read back to the host.
// The windowed viewer reuses the passes with a swapchain image as target.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <glm/vec3.hpp>

#include "aperture/engine/vk/buffer.h"
#include "aperture/engine/vk/gpu_timer.h"
#include "aperture/engine/vk/graphics_pipeline.h"
#include "aperture/engine/vk/image.h"
#include "aperture/engine/vk/serial_pass_timer.h"
#include "aperture/terrain/light/lighting.h"
#include "aperture/terrain/light/obscurance.h"
#include "aperture/terrain/light/shading.h"
#include "aperture/terrain/view/camera.h"
#include "aperture/terrain/view/quadtree_lod.h"
#include "aperture/terrain/view/texel_footprint.h"

namespace aal {

class Device;
class TerrainScene;
struct FramePlan;
struct FrameTargets;
struct FrameUniforms;
struct PassPipelines;

struct FrameSettings {
  Camera camera;
  ShadingMode mode = ShadingMode::Approx;
  // Sun, sky, haze and exposure (terrain/light/lighting.h).
  Lighting lighting;
  // Paint heights at or below this level (m) as water; none unless the user
  // asks (--water-level): a plain at 0 m is not a lake.
  std::optional<float> waterLevelM;
  // Containment-test obscurances and W (docs/design.md §6,
  // terrain/light/obscurance.h): W multiplies the sky fill of the approx/exact modes;
  // the debug-obscurance and debug-transfer modes show O and W. The renderer
  // takes the settings as given (tools validate them with
  // checkObscuranceSettings); radiusM 0 means defaultObscuranceRadiusM of the
  // DEM.
  ObscuranceSettings obscurance;
  // A constant albedo for every texel, instead of the scene's image or palette.
  std::optional<glm::vec3> albedoValue;
  // The terrain's quadtree LOD (terrain/view/quadtree_lod.h); the triangle budget
  // is the scene's.
  LodSettings lod;
  // The most probes along each fragment's footprint on the DEM with which
  // every terrain texture is read, 1..kMaxFootprintProbes
  // (terrain/view/texel_footprint.h; aal-render --anisotropy). 1 is one
  // trilinear fetch at the level of the footprint's longer axis (a GPU's
  // isotropic filter): the fastest, blurred in oblique views; each probe
  // more costs a fetch per texture (docs/rendering.md, "Footprint
  // filtering"). Values outside are clamped.
  int anisotropy = kDefaultFootprintProbes;
  // Pixels without terrain (the sky, or the debug views' black) get alpha 0
  // in the display and linear images instead of 1; their colour is kept
  // (aal-render --background transparent).
  bool transparentBackground = false;
  // A solid base under the DEM (aal-render --base): side walls from the
  // DEM's edge down to depthM below its lowest height, and a bottom, of
  // albedo `albedo` (shaders/base_vertex.glsl, base_shading.glsl).
  struct Base {
    float depthM = 0.0f;
    glm::vec3 albedo{0.3f};
  };
  std::optional<Base> base;
  // The horizon mode's re-lays when the sun leaves the pair on the device
  // (engine/horizon_relay.h, docs/rendering.md): 0: each done in the frame
  // that needs it, every frame as a fresh scene would draw it (aal-render);
  // above 0: spread over frames, at least this many level-0 texels a frame,
  // begun ahead of a moving sun (aal-view: no frame stalls for a whole one).
  uint64_t horizonRelayTexelsPerFrame = 0;
};

// The debug views, whose display values are the raw values clamped to
// [0, 1] instead of tone-mapped radiance.
bool isDebugMode(ShadingMode mode);

struct FrameResult {
  uint32_t width = 0, height = 0;
  std::vector<uint8_t> display;  // RGBA8, sRGB encoded (debug modes: raw values)
  std::vector<float> linear;     // RGBA32F linear radiance, when asked for
  std::vector<std::pair<std::string, double>> passMilliseconds;
  size_t triangles = 0;                   // terrain triangles drawn (LOD patches)
  std::vector<uint32_t> patchesPerLevel;  // LOD patches drawn per level (0: finest)
};

// Where and how record() leaves a frame.
struct FrameOutput {
  // Keep the linear radiance in hdrImage() and tone-map it into the display
  // image in a last pass (aal-render's EXR output); otherwise the passes
  // write display values directly, the tone map folded into the last pass
  // that writes each pixel.
  bool linear = false;
  // When set: the frame's display values go here (an image of the
  // renderer's display format and size, such as a swapchain image), left in
  // VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL. Otherwise into displayImage(),
  // left in VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL. Not with `linear`.
  VkImage image = VK_NULL_HANDLE;
  VkImageView view = VK_NULL_HANDLE;
  // Dynamic resolution: the fraction (0, 1] of the width and height drawn.
  // Below 1 the passes draw a smaller picture into the top-left of their
  // targets, scaled up (bilinear, shaders/upscale.frag) into `image` (which
  // must be set).
  float resolutionScale = 1.0f;
  // Accumulate this frame and the ones before it (shaders/resolve.glsl: the
  // last accumulated frame reprojected with the camera's motion and clamped
  // to the drawn neighbours; docs/rendering.md, "Temporal reconstruction"):
  // - below full resolution, the full-resolution picture rebuilt from
  //   jittered frames instead of scaled up;
  // - at full resolution with `linear`, each pixel's linear radiance the
  //   mean of its points over the frames (jittered while the camera stands
  //   still; antialiasing for image sequences), which hdrImage() and the
  //   display then hold.
  // Otherwise (full resolution, display values) it does nothing. The history
  // goes with any frame that does not accumulate, with a switch between the
  // two uses, and with restartTemporal().
  bool temporal = false;
  // Which copy of the frame's host-written buffers (uniforms, obscurance
  // samples, LOD patches) and of the GPU timer it uses, 0 ..
  // kFramesInFlight - 1 (engine/vk/frames_in_flight.h): the windowed loop's
  // FrameSync::slot(). The frame that last used the slot must have
  // completed; headless frames, each waited for, use 0.
  uint32_t frameSlot = 0;
};

class TerrainRenderer {
 public:
  // Throws VulkanError when width/height are 0 or beyond the device limit.
  // `displayFormat`: of displayImage(), an 8-bit UNORM RGBA or BGRA format
  // (it holds sRGB-encoded values).
  TerrainRenderer(const Device& device, uint32_t width, uint32_t height,
                  VkFormat displayFormat = VK_FORMAT_R8G8B8A8_UNORM);
  ~TerrainRenderer();

  // Headless frame: records the passes, submits, waits and reads back. A
  // frame of its own for the device's DeletionQueue: what it retired is
  // destroyed after the wait (so not while a windowed frame is recorded).
  FrameResult render(const TerrainScene& scene, const FrameSettings& settings, bool wantLinear);
  // The same with temporal antialiasing (FrameOutput::temporal at full
  // resolution): a frame of a sequence, whose pixels are the mean of their
  // points over the frames since restartTemporal() (or since the last frame
  // that did not accumulate), moved with the camera.
  FrameResult renderAccumulated(const TerrainScene& scene, const FrameSettings& settings,
                                bool wantLinear);
  // Such a frame accumulated and nothing read back (the frames that lead a
  // sequence in, engine/supersampling.h startAccumulation).
  void accumulate(const TerrainScene& scene, const FrameSettings& settings);
  // The next accumulating frame starts a new history (another sequence, or
  // other settings: the history is kept across frames of one scene whatever
  // their settings).
  void restartTemporal() { resolveValid_ = false; }
  // A headless frame (display output, nothing read back) and its wall-clock
  // and CPU time: `serialized`, each step submitted on its own and waited
  // for, a Step each (the host's preparation one of them); else one Step,
  // the frame in one submission (aal-render --pass-profile). What a CPU
  // device's timestamps cannot tell (engine/vk/serial_pass_timer.h).
  std::vector<SerialPassTimer::Step> profile(const TerrainScene& scene,
                                             const FrameSettings& settings, bool serialized);

  // Records the frame's passes into `cmd` (the windowed viewer presents the
  // result; see FrameOutput for where it goes). Writes the frame's uniforms
  // at once, into the copies of output.frameSlot, which no frame in flight
  // may use; its first barrier waits for every earlier frame's work (the
  // passes rewrite the images the frame before may still read). What it
  // replaces (a grown patch buffer, the cap table's staging) it retires into
  // the device's DeletionQueue. In the horizon mode it first re-lays the
  // scene's horizons when the frame's sun left their pair of directions (a
  // spread re-lay's share recorded into `cmd`; a whole re-lay an upload and
  // a compute pass, waited for; docs/rendering.md). With `output.linear` hdrImage() then holds the
  // linear radiance, in VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL.
  void record(VkCommandBuffer cmd, const TerrainScene& scene, const FrameSettings& settings,
              const FrameOutput& output = {});

  // RGBA8 UNORM holding sRGB-encoded values (debug modes: raw values).
  const Image& displayImage() const { return display_; }
  // RGBA16F linear radiance (after record(..., linear = true)).
  const Image& hdrImage() const { return hdr_; }
  uint32_t width() const { return width_; }
  uint32_t height() const { return height_; }
  // The LOD selection of the last recorded frame (its triangle count).
  const LodSelection& lodSelection() const { return selection_; }
  // Milliseconds per pass of the last frame recorded in `frameSlot`
  // (FrameOutput::frameSlot), once it has finished; empty before one was.
  std::vector<std::pair<std::string, double>> passMilliseconds(uint32_t frameSlot = 0) const;

 private:
  // The host's part of the frame (engine/frame_preparation.cpp), the only
  // one that changes the scene (the horizon re-lay) or the renderer's state:
  // the LOD selection, the uniforms, the cap table and the obscurance
  // history's bookkeeping. Decides which passes run and where they write.
  // A spread re-lay's share of the frame goes into `cmd`.
  FramePlan prepareFrame(VkCommandBuffer cmd, const TerrainScene& scene,
                         const FrameSettings& settings, const FrameOutput& output);
  // A headless frame, submitted and waited for; `readBack`: its display
  // values (and with `wantLinear` its radiance) copied out, else nothing.
  FrameResult renderHeadless(const TerrainScene& scene, const FrameSettings& settings,
                             bool wantLinear, bool temporal, bool readBack = true);
  // Re-lays the scene's horizons when the frame's sun left their pair (a
  // spread re-lay's share recorded into `cmd`).
  void relayHorizons(const TerrainScene& scene, const FrameSettings& settings, VkCommandBuffer cmd);
  // Writes the frame's uniforms (and, with `obscurance`, the sample set);
  // `rebuilt`: the frame is drawn for the temporal reconstruction (jittered
  // by jitter_, its textures read at the output pixels' footprint).
  void writeUniforms(const TerrainScene& scene, const FrameSettings& settings, bool obscurance,
                     bool rebuilt);
  // The obscurance uniforms and the history's validity for this frame.
  void setObscurance(FrameUniforms& u, const TerrainScene& scene, const FrameSettings& settings,
                     bool obscurance);
  // Selects the LOD patches for the camera and writes them to patches_.
  void selectPatches(const TerrainScene& scene, const FrameSettings& settings);
  // Makes the exact mode's cap table for the frame's sun radius when it
  // changed (on the host, terrain/light/cap_table.h) into its staging
  // copy; returns whether the frame uploads it.
  bool prepareCapTable(const FrameSettings& settings);
  // Makes the obscurance history's images on first use and picks the one
  // this frame reads and the one it writes.
  void prepareHistory(FramePlan& plan);
  // The renderer's images, as the passes see them.
  FrameTargets frameTargets() const;

  const Device& device_;
  uint32_t width_, height_;
  VkExtent2D extent_{0, 0};  // drawn this frame: width_ x height_, or less (FrameOutput)
  Image hdr_, depth_, display_;
  // Terrain pass outputs for the obscurance pass and the composite (see
  // shaders/terrain_shading.glsl), and the per-pixel O/W.
  Image ambient_, surface_, transfer_, filtered_;
  Image skyTable_;  // the sky's radiance per view direction (shaders/sky_lut.glsl)
  // The exact cap intersection against the sun (shaders/cap_table.glsl), for
  // the sun radius capTableRadius_ (0: not made yet), and its staging copy
  // (a new one for each table; the one before retired).
  Image capTable_;
  Buffer capTableStaging_;
  float capTableRadius_ = 0.0f;
  // Obscurance reuse (ObscuranceSettings::History): the means and points the
  // previous frame wrote (index historyRead_) and this one writes (the
  // other); made on first use.
  struct HistoryKey {
    uint64_t scene = 0;
    float radiusM = 0;
    int samples = 0, steps = 0;
    bool interleaved = false, halfResolution = false;
    int albedoSource = 0;
    glm::vec3 albedoValue{0.0f};
    bool operator==(const HistoryKey&) const = default;
  };
  std::unique_ptr<Image> historyMeans_[2], historyPoints_[2];
  int historyRead_ = 0;
  bool historyValid_ = false;
  HistoryKey historyKey_;
  uint32_t historySubset_ = 0;
  // The sun's azimuth in the previous horizon frame of scene
  // horizonSunScene_ (0: none): the sun's motion, which a spread re-lay
  // starts ahead of.
  uint64_t horizonSunScene_ = 0;
  float horizonSunAzimuth_ = 0.0f;
  glm::mat4 previousViewProj_{1.0f};
  VkExtent2D previousExtent_{0, 0};
  // What the host writes for a frame, and the frame's GPU timer: one of
  // each per frame in flight (FrameOutput::frameSlot).
  struct FrameSlot {
    explicit FrameSlot(const Device& device);
    Buffer uniforms, samples;
    Buffer patches;  // LodPatch instances of the frame (grows as needed)
    GpuTimer timer;
  };
  std::vector<std::unique_ptr<FrameSlot>> slots_;
  // slots_[index]; std::invalid_argument naming `caller` when there is none.
  FrameSlot& frameSlot(uint32_t index, const char* caller) const;
  FrameSlot* slot_ = nullptr;  // of the frame being prepared and recorded
  LodSelection selection_;
  glm::mat4 viewProj_{1.0f};   // of the last writeUniforms, without the jitter
  glm::dmat4 viewProjD_{1.0};  // the same in double (the reprojections invert it)
  // The resolve pass's constants and history for this frame. `rebuild`:
  // frames drawn smaller, else accumulated at full size; `moved`: the camera
  // moved since the last accumulated frame.
  void prepareResolve(FramePlan& plan, const TerrainScene& scene, bool rebuild, bool moved);
  // Temporal reconstruction: the rebuilt or accumulated frames (the last one
  // at index resolveRead_, valid for scene resolveScene_ while
  // resolveValid_), the last one's view-projection, and this frame's jitter
  // (drawn pixels).
  std::unique_ptr<Image> resolveHistory_[2];
  int resolveRead_ = 0;
  bool resolveValid_ = false;
  uint64_t resolveScene_ = 0;
  bool resolveRebuilt_ = false;  // the history rebuilt frames drawn smaller, else accumulated
  uint32_t resolveFrames_ = 0;   // in the history (full-resolution accumulation)
  Camera resolveCamera_;         // of the last accumulated frame
  glm::dmat4 resolveViewProjD_{1.0};
  uint32_t jitterIndex_ = 0;
  glm::vec2 jitter_{0.0f};
  std::unique_ptr<PassPipelines> passes_;
  // Set while profile() records: each step is then submitted on its own.
  SerialPassTimer* serial_ = nullptr;
};

}  // namespace aal
