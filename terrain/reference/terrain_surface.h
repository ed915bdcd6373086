// The terrain as the reference ray tracer sees it (reference_renderer.h): the
// bilinear surface through the texel centres with uniform cells (the centre
// row's for geographic grids, as engine/terrain_scene uploads it), world
// metres with the DEM's centre at the origin, x east, y north, z up.
#pragma once

#include <glm/vec3.hpp>

#include "aperture/terrain/heightfield.h"

namespace aal {

class TerrainSurface {
 public:
  explicit TerrainSurface(const Heightfield& field);

  // Within the DEM's footprint (1e-9 m of slack).
  bool inside(double x, double y) const;
  double heightAt(double x, double y) const;
  double col(double x) const { return x / cellX_ + halfX_; }
  double row(double y) const { return halfY_ - y / cellY_; }
  double cell() const { return cellX_ < cellY_ ? cellX_ : cellY_; }

  // Central differences one texel apart (shaders/terrain_shading.glsl surfaceNormal).
  glm::dvec3 normalAt(double x, double y) const;

  // The first crossing of the surface by origin + s * dir for s in (sStart,
  // sEnd], exact: the ray is walked cell by cell, and in each cell the
  // bilinear patch along the ray is a quadratic in s whose first root is the
  // crossing. (Sampling the ray in steps, as this did until 2026-12-03, steps
  // over ridges and peaks narrower than a step: thin crests cast no shadow
  // and hide no sky.) A ray that starts under the surface (one entering the
  // DEM's box through a side, below the edge) hits where it comes up
  // through it, as the GPU's two-sided triangles would show. A ray that
  // starts outside the footprint, leaves it or rises above the DEM's top
  // escapes. `dir` need not be unit length; s is in its units.
  bool intersect(const glm::dvec3& origin, const glm::dvec3& dir, double sStart, double sEnd,
                 double& sHit) const;

  // The part [sIn, sOut] of origin + s * dir (s >= 0) inside the DEM's
  // footprint and below its top; false when there is none.
  bool clipToBox(const glm::dvec3& origin, const glm::dvec3& dir, double& sIn, double& sOut) const;

 private:
  double heightAtTexel(double c, double r) const { return field_.bilinearHeight(c, r); }

  const Heightfield& field_;
  double cellX_, cellY_, halfX_, halfY_, maxHeight_;
};

}  // namespace aal
