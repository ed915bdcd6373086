// The picture the geometric-error LOD (terrain/view/quadtree_lod.h)
// draws against the finest mesh the budget allows: over the shipped DEM, in
// the framed start view and two low flights, the tone-mapped image stays
// within 1 % RMSE while the mesh has a fraction of the triangles.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "aperture/engine/terrain_renderer.h"
#include "aperture/engine/terrain_scene.h"
#include "aperture/preprocess/bake.h"
#include "aperture/terrain/io/dem_loader.h"
#include "aperture/terrain/light/sky_lighting.h"
#include "aperture/terrain/view/camera.h"
#include "aperture/tests/engine/vulkan_test.h"

namespace aal {
namespace {

constexpr uint32_t kWidth = 1280, kHeight = 720;  // the viewer's default window

// Root mean square of the 8-bit RGB differences, as a fraction of 255.
double rmse(const FrameResult& a, const FrameResult& b) {
  double sum = 0;
  size_t n = 0;
  for (size_t i = 0; i < a.display.size(); i += 4) {
    for (int c = 0; c < 3; ++c, ++n) {
      const double d = (double(a.display[i + c]) - double(b.display[i + c])) / 255.0;
      sum += d * d;
    }
  }
  return std::sqrt(sum / double(n));
}

class LodQuality : public VulkanTest {};

TEST_F(LodQuality, DefaultErrorKeepsThePictureWithinOnePercentOfTheFinestMesh) {
  const Heightfield field = loadDem(AAL_TEST_SOURCE_DIR "/heightmaps/jacksboro_fault_dem.tif");
  const ApertureMap aperture = bakeApertures(field, {}).aperture;
  const TerrainScene scene(device(), field, aperture, nullptr, 2'000'000);
  TerrainRenderer renderer(device(), kWidth, kHeight);
  struct View {
    const char* name;
    glm::dvec3 position, lookAt;
  };
  const Camera framed = defaultCamera(field, double(kWidth) / kHeight);
  const View views[] = {{"framed", framed.position, framed.lookAt},
                        {"flight", {-12000, -12000, 1800}, {-9000, -9000, 1200}},
                        {"low", {8000, -6000, 900}, {5000, -3000, 700}}};
  for (const View& v : views) {
    FrameSettings s;
    s.camera.position = v.position;
    s.camera.lookAt = v.lookAt;
    s.camera.verticalFovDeg = 40;
    setSunAndSky(s.lighting, 250, 25, 2.5);
    s.lighting.exposure = 0.07f;
    s.obscurance.enabled = false;
    const FrameResult coarse = renderer.render(scene, s, false);  // the default error
    s.lod.maxErrorPixels = 1e-3;                                  // level 0 wherever it shows
    const FrameResult finest = renderer.render(scene, s, false);
    const double error = rmse(coarse, finest);
    std::printf("%-6s: %zu triangles (finest %zu), RMSE %.2f %%\n", v.name, coarse.triangles,
                finest.triangles, 100 * error);
    EXPECT_LT(error, 0.01) << v.name;
    EXPECT_LT(coarse.triangles, finest.triangles) << v.name;
  }
}

}  // namespace
}  // namespace aal
