// The specialisation constants of the pipelines that shade the terrain and
// the sky (AAL_SPEC_* in config.h; engine/terrain_renderer.cpp sets them per
// frame). Lavapipe runs every arm of a branch whatever the condition, so a
// uniform mode would make every fragment pay for every mode; constants let
// the driver drop the arms a frame does not take.
#ifndef AAL_VARIANT_GLSL
#define AAL_VARIANT_GLSL

#include "config.h"

// AAL_MODE_* (terrain/light/shading.h ShadingMode).
layout(constant_id = AAL_SPEC_SHADING_MODE) const int kShadingMode = AAL_MODE_APPROX;
// AAL_ALBEDO_*: palette by height and slope, albedo image, constant.
layout(constant_id = AAL_SPEC_ALBEDO_SOURCE) const int kAlbedoSource = AAL_ALBEDO_PALETTE;
// true: the pass writes display values (tone-mapped, sRGB encoded; debug
// modes their raw values) instead of linear radiance.
layout(constant_id = AAL_SPEC_DISPLAY_OUTPUT) const bool kDisplayOutput = false;
// Most probes of the footprint filtering (texel_footprint.glsl,
// FrameSettings::anisotropy), 1..AAL_FOOTPRINT_MAX_PROBES.
layout(constant_id = AAL_SPEC_FOOTPRINT_PROBES) const int kFootprintProbes = AAL_FOOTPRINT_MAX_PROBES;

// Debug modes show raw values: no aerial perspective, no tone map.
const bool kRawOutput =
    kShadingMode >= AAL_MODE_DEBUG_VISIBLE && kShadingMode <= AAL_MODE_DEBUG_TRANSFER;

#endif
