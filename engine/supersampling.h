// Supersampling: a frame rendered at `factor` times the output's width and
// height, averaged back to the output's size. The renderer shades one point
// per pixel; where the picture varies within a pixel (the mesh's occluding
// edges, detail the textures' filtering cannot average for a nonlinear
// shading) that point aliases and shimmers in motion, which only more points
// per pixel remove (docs/comparison.md, "Shimmer in motion").
#pragma once

#include <cstdint>

#include "aperture/engine/terrain_renderer.h"

namespace aal {

// Largest supersampling factor the tools offer (factor² points per pixel).
inline constexpr uint32_t kMaxSupersampling = 4;

// The output frame of `big`, rendered with its linear radiance at `factor`
// times the width and height: each pixel the mean of its factor × factor
// linear values (alpha: the terrain's coverage; colour: the mean over the
// covered points, alpha being unassociated), displayed as the
// renderer displays them (toneMap at `exposure`, or for debug views, `raw`,
// the values clamped to [0, 1]; 8 bits, rounded). `keepLinear`: whether the
// result carries the averaged linear values. Throws std::invalid_argument
// when `big` has no linear values or a size that is not a multiple of factor.
FrameResult downsampleFrame(const FrameResult& big, uint32_t factor, float exposure, bool raw,
                            bool keepLinear);

// A frame of `factor` × `factor` points per pixel from a renderer of factor
// times the output's width and height: rendered with its linear values and
// averaged down (downsampleFrame); factor 1 is the renderer's own frame. An
// explicit settings.lod.maxErrorPixels stays in output pixels.
// `accumulate`: a frame of a sequence, accumulated over the frames before
// it (TerrainRenderer::renderAccumulated).
FrameResult renderSupersampled(TerrainRenderer& renderer, const TerrainScene& scene,
                               FrameSettings settings, uint32_t factor, bool keepLinear,
                               bool accumulate = false);

// The frames startAccumulation draws before a sequence: one cycle of the
// jitter (engine/frame_preparation.cpp), so that the first frame's pixels
// already hold that many points.
inline constexpr int kAccumulationLeadFrames = 8;

// Starts an accumulated sequence (renderSupersampled with `accumulate`)
// whose first frame has `settings`: restarts the renderer's history and
// accumulates kAccumulationLeadFrames frames of that first picture, so that
// the sequence's first frame is as converged as the ones after it.
void startAccumulation(TerrainRenderer& renderer, const TerrainScene& scene,
                       const FrameSettings& settings, uint32_t factor);

}  // namespace aal
