#include "aperture/tools/options/camera_options.h"

#include <cstdio>

#include "aperture/terrain/view/camera.h"

namespace aal {

void addCameraOptions(CLI::App& app, CameraOptions& camera) {
  app.add_option("--camera", camera.position,
                 "camera position X,Y,Z in metres (DEM frame: x east, y north, "
                 "z up, origin at the DEM centre), within 10,000 km of the centre (100 DEM "
                 "diagonals for larger DEMs); default: from the south-east");
  app.add_option("--look-at", camera.lookAt,
                 "point the camera looks at, X,Y,Z in metres (within --camera's reach)");
  app.add_option("--fov", camera.fovDeg, "vertical field of view in degrees")
      ->check(CLI::Range(kMinFovDeg, kMaxFovDeg))
      ->capture_default_str();
}

void addCameraPathOption(CLI::App& app, std::string& path, const std::string& use) {
  char format[256];
  std::snprintf(format, sizeof format,
                "keyframes 'TIME_S X Y Z LOOK_X LOOK_Y LOOK_Z [FOV_DEG]' per line (DEM frame, "
                "metres, within 10,000 km of the DEM's centre, %g DEM diagonals for larger "
                "DEMs; FOV_DEG in [%g, %g])",
                kCameraReachDiagonals, kMinFovDeg, kMaxFovDeg);
  app.add_option("--camera-path", path, format + ("; " + use));
}

}  // namespace aal
