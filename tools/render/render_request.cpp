#include "aperture/tools/render/render_request.h"

#include <string>
#include <tuple>

#include "aperture/engine/screenshot.h"
#include "aperture/terrain/errors.h"
#include "aperture/terrain/view/camera_path.h"
#include "aperture/tools/horizon_option.h"
#include "aperture/tools/render/render_paths.h"
#include "aperture/tools/tool_options.h"
#include "aperture/tools/tool_paths.h"

namespace aal {
namespace {

// -o or --compare, and what each of them and --mode reference take.
void checkOutputChoice(const RenderOptions& o, bool reference, ShadingMode mode) {
  if (o.output.empty() == o.compare.empty()) {
    throw InputError("give -o IMAGE or --compare FOLDER (one of them)");
  }
  if ((reference || !o.compare.empty()) && !o.albedo.empty()) {
    throw InputError(
        "the reference renderer knows only a constant albedo: use --albedo-value, not --albedo");
  }
  if (reference && o.supersample > 1) {
    throw InputError(
        "--supersample is for the GPU's modes: the reference takes --reference-subpixels");
  }
  if (reference && !o.compare.empty()) {
    throw InputError("--compare renders the reference itself: leave out --mode reference");
  }
  if (o.horizons.size() > 1 && o.compare.empty()) {
    throw InputError("--horizons given " + std::to_string(o.horizons.size()) +
                     " times: only --compare takes several");
  }
  if (mode == ShadingMode::Horizon && o.horizons.empty()) {
    throw InputError("--mode horizon needs --horizons FILE (aal-bake --horizons)");
  }
  if (!o.output.empty()) {
    if (!isSupportedImageOutput(o.output)) {
      throw InputError("output " + o.output + " must end in .png or .exr");
    }
    requireWritableOutput(o.output);
  }
}

// What only the GPU renderer draws into -o images (the base, a transparent
// background), and the base's colour.
glm::vec3 checkedBase(const RenderOptions& o, bool reference) {
  const std::string renderer = reference ? "--mode reference" : "--compare";
  if (o.baseDepthM && (reference || !o.compare.empty())) {
    throw InputError("--base is drawn by the GPU renderer into -o images, not " + renderer);
  }
  const glm::vec3 baseAlbedo = parseAlbedoValue(o.baseColor, "--base-color");
  if (o.background == "transparent" && (reference || !o.compare.empty())) {
    throw InputError("--background transparent is for -o images of the GPU renderer, not " +
                     renderer);
  }
  return baseAlbedo;
}

// The sun's options that only make sense together.
void checkSunChoice(const RenderOptions& o) {
  if (o.sun.azimuthDeg.has_value() != o.sun.elevationDeg.has_value()) {
    throw InputError("give --sun-azimuth and --sun-elevation together");
  }
  // As aal-relief: a place without a time would be ignored.
  if (o.sun.time.empty() && o.timeRange.empty() && (o.sun.latitudeDeg || o.sun.longitudeDeg)) {
    throw InputError("--lat and --lon place the sun for --time (or --time-range); give --time too");
  }
}

}  // namespace

RenderRequest checkedRequest(const RenderOptions& o) {
  RenderRequest r;
  r.reference = o.mode == kReferenceMode;
  r.mode = r.reference ? ShadingMode::Approx : toolShadingModes().at(o.mode);
  std::tie(r.width, r.height) = parseSize(o.size);
  checkOutputChoice(o, r.reference, r.mode);
  r.baseAlbedo = checkedBase(o, r.reference);
  checkSunChoice(o);
  r.sequence = imageSequenceOf(o, r.reference);
  checkRenderPaths(o, r.sequence);
  // Read once the paths are known to be apart.
  if (r.sequence && !o.cameraPath.empty()) r.sequence->path = CameraPath::load(o.cameraPath);

  if (o.passProfile > 0 && (r.reference || r.sequence || !o.compare.empty())) {
    throw InputError("--pass-profile times the GPU renderer's still image: not with " +
                     std::string(r.reference  ? "--mode reference"
                                 : r.sequence ? "a sequence"
                                              : "--compare"));
  }
  if (!o.albedo.empty() && !o.albedoValue.empty()) {
    throw InputError("give --albedo or --albedo-value, not both");
  }
  if (!o.albedoValue.empty()) r.albedoValue = parseAlbedoValue(o.albedoValue);
  return r;
}

}  // namespace aal
