// The DEM's textures (heights, apertures, albedo, slopes) as every pass
// samples them: a texel position of the whole DEM goes through the tile lookup
// (tile_lookup.glsl, engine/terrain_tiles.h) to a layer of one of
// AAL_TERRAIN_TILE_PAGES 2D array images per kind. A single-tile scene has
// one page of one layer whose image is the DEM: the same fetches as one
// plain texture. Array images instead of arrays of textures: lavapipe has no
// descriptor indexing (not even dynamically uniform), and layers are chosen
// per fetch. The shaders that include it are built as variants, one per
// paging (AAL_TERRAIN_PAGED, AAL_TERRAIN_APERTURE_PAGES): see
// aal_shader_variant in shaders/CMakeLists.txt.
#ifndef AAL_TERRAIN_TEXTURES_GLSL
#define AAL_TERRAIN_TEXTURES_GLSL

#include "config.h"
#include "frame.glsl"
#include "texel_footprint.glsl"
#include "tile_lookup.glsl"
#include "variant.glsl"

#if AAL_TERRAIN_TILE_PAGES != 4
#error "terrain_textures.glsl declares four pages per kind"
#endif

#define AAL_TERRAIN_PAGES(name, first)                                        \
  layout(set = 0, binding = first + 0) uniform sampler2DArray name##Page0; \
  layout(set = 0, binding = first + 1) uniform sampler2DArray name##Page1; \
  layout(set = 0, binding = first + 2) uniform sampler2DArray name##Page2; \
  layout(set = 0, binding = first + 3) uniform sampler2DArray name##Page3;

AAL_TERRAIN_PAGES(terrainHeight, AAL_TERRAIN_TEXTURE_BINDING)
AAL_TERRAIN_PAGES(terrainAperture, AAL_TERRAIN_TEXTURE_BINDING + AAL_TERRAIN_TILE_PAGES)
AAL_TERRAIN_PAGES(terrainAlbedo, AAL_TERRAIN_TEXTURE_BINDING + 2 * AAL_TERRAIN_TILE_PAGES)
AAL_TERRAIN_PAGES(terrainSlope, AAL_TERRAIN_TEXTURE_BINDING + 3 * AAL_TERRAIN_TILE_PAGES)
#if AAL_TERRAIN_TEXTURE_KINDS != 4
#error "terrain_textures.glsl declares four kinds"
#endif

// Trilinear fetch at an explicit LOD (valid in any control flow: 0 is the
// DEM's own texels) from the tile's page. Lavapipe runs every arm of a branch for every fetch (a
// four-way pick made the terrain pass 1.6x and the obscurance pass 2.7x
// slower), so a pick is compiled in only where a scene needs it: the
// *_paged variants (AAL_TERRAIN_PAGED) pick among four pages for the
// apertures and two for the heights and albedo;
// the *_aperture_pagesN ones (AAL_TERRAIN_APERTURE_PAGES N = 2 or 4) among N
// for the apertures only (8 bytes a texel: they fill pages first); the
// others read page 0 (scenes of one page per kind: all but the largest DEMs).
#define AAL_TERRAIN_FETCH_FROM(name, n, t, lod) \
  textureLod(name##Page##n, vec3((t).uv, float((t).layer)), lod)
#define AAL_TERRAIN_FETCH_PAGES1(name, t, lod) AAL_TERRAIN_FETCH_FROM(name, 0, t, lod)
#define AAL_TERRAIN_FETCH_PAGES2(name, t, lod)                                   \
  ((t).page == 0 ? AAL_TERRAIN_FETCH_FROM(name, 0, t, lod) \
                 : AAL_TERRAIN_FETCH_FROM(name, 1, t, lod))
#define AAL_TERRAIN_FETCH_PAGES4(name, t, lod)                    \
  ((t).page == 0   ? AAL_TERRAIN_FETCH_FROM(name, 0, t, lod)     \
   : (t).page == 1 ? AAL_TERRAIN_FETCH_FROM(name, 1, t, lod)     \
   : (t).page == 2 ? AAL_TERRAIN_FETCH_FROM(name, 2, t, lod)     \
                   : AAL_TERRAIN_FETCH_FROM(name, 3, t, lod))
#if defined(AAL_TERRAIN_PAGED)
// Heights and albedo (4 bytes a texel) fill half the pages of the apertures
// (8): two at most where the apertures fit four (planTerrainTiles checks).
#define AAL_TERRAIN_FETCH_HEIGHT AAL_TERRAIN_FETCH_PAGES2
#define AAL_TERRAIN_FETCH_APERTURE AAL_TERRAIN_FETCH_PAGES4
#define AAL_TERRAIN_FETCH_ALBEDO AAL_TERRAIN_FETCH_PAGES2
#else
#define AAL_TERRAIN_FETCH_HEIGHT AAL_TERRAIN_FETCH_PAGES1
#define AAL_TERRAIN_FETCH_ALBEDO AAL_TERRAIN_FETCH_PAGES1
#if !defined(AAL_TERRAIN_APERTURE_PAGES)
#define AAL_TERRAIN_FETCH_APERTURE AAL_TERRAIN_FETCH_PAGES1
#elif AAL_TERRAIN_APERTURE_PAGES == 2
#define AAL_TERRAIN_FETCH_APERTURE AAL_TERRAIN_FETCH_PAGES2
#else
#define AAL_TERRAIN_FETCH_APERTURE AAL_TERRAIN_FETCH_PAGES4
#endif
#endif

// The tile of a DEM texel position, in the pages of a kind with
// `layersPerPage` tiles per page (frame.heightLayersPerPage and its kin).
TerrainTileTexel terrainTexel(vec2 texel, int layersPerPage) {
  TerrainTiles tiles = TerrainTiles(
      ivec4(frame.tileCoreSize, frame.tileCount),
      ivec4(frame.tileBorder, layersPerPage, frame.tileImageSize));
  return terrainTileTexel(tiles, texel);
}

// The fetches take a level of detail: 0 reads the DEM's own texels, l the
// mip level whose texels span 2^l of them (AAL_TERRAIN_MIP_LEVELS levels;
// beyond the coarsest the sampler clamps), fractions blend two levels.

// Height (m) at a DEM texel position, bilinear, clamped to the DEM's edge.
float terrainHeightLod(vec2 texel, float lod) {
  TerrainTileTexel t = terrainTexel(texel, frame.heightLayersPerPage);
  return AAL_TERRAIN_FETCH_HEIGHT(terrainHeight, t, lod).r;
}
float terrainHeight(vec2 texel) {
  return terrainHeightLod(texel, 0.0);
}

// rgb bent normal (not unit length above level 0: an average), a arc length (rad).
vec4 terrainApertureLod(vec2 texel, float lod) {
  TerrainTileTexel t = terrainTexel(texel, frame.apertureLayersPerPage);
  return AAL_TERRAIN_FETCH_APERTURE(terrainAperture, t, lod);
}

// Albedo image (linear RGB as stored).
vec3 terrainAlbedoLod(vec2 texel, float lod) {
  TerrainTileTexel t = terrainTexel(texel, frame.albedoLayersPerPage);
  return AAL_TERRAIN_FETCH_ALBEDO(terrainAlbedo, t, lod).rgb;
}
vec3 terrainAlbedo(vec2 texel) {
  return terrainAlbedoLod(texel, 0.0);
}

// Slope of the heights (xy: dz/dx east, dz/dy north; m/m) at level of
// detail `lod`: the mean over the footprint of the DEM's central differences
// (slopes.glsl), laid out in tiles and pages as the heights. zw:
// with directional horizons, the horizons (rad) of the pair of directions
// beside the sun (engine/terrain_scene.h setHorizons); else 0, 1.
vec4 terrainSlopeLod(vec2 texel, float lod) {
  TerrainTileTexel t = terrainTexel(texel, frame.heightLayersPerPage);
  return AAL_TERRAIN_FETCH_HEIGHT(terrainSlope, t, lod);
}

// The same, filtered over a fragment's footprint: the mean of its probes
// (texel_footprint.glsl) around `texel`. The kind's tile is looked up once,
// at the fragment, and every probe reads that tile's image: footprintProbes
// keeps them within its border, which holds the neighbours' texels bit for
// bit, so a tiled DEM reads as one image. The loop runs the frame's most
// probes (kFootprintProbes, a constant: unrolled), a fragment with fewer
// repeating its last probe at weight 0: on lavapipe a loop over a
// per-fragment count cost more than the fetches it saved (docs/rendering.md).
#define AAL_TERRAIN_PROBE_MEAN(Type, texel, p, layersPerPage, FETCH)     \
  TerrainTileTexel t = terrainTexel(texel, layersPerPage);              \
  vec2 step = p.step / vec2(frame.tileImageSize);                       \
  vec2 first = t.uv - 0.5 * float(p.count - 1) * step;                  \
  Type sum = Type(0.0);                                                 \
  for (int i = 0; i < kFootprintProbes; ++i) {                          \
    t.uv = first + float(min(i, p.count - 1)) * step;                   \
    sum += (i < p.count ? 1.0 : 0.0) * FETCH;                           \
  }                                                                     \
  return sum / float(p.count);

vec4 terrainApertureProbes(vec2 texel, FootprintProbes p) {
  AAL_TERRAIN_PROBE_MEAN(vec4, texel, p, frame.apertureLayersPerPage,
                         AAL_TERRAIN_FETCH_APERTURE(terrainAperture, t, p.lod))
}
vec3 terrainAlbedoProbes(vec2 texel, FootprintProbes p) {
  AAL_TERRAIN_PROBE_MEAN(vec3, texel, p, frame.albedoLayersPerPage,
                         AAL_TERRAIN_FETCH_ALBEDO(terrainAlbedo, t, p.lod).rgb)
}
vec4 terrainSlopeProbes(vec2 texel, FootprintProbes p) {
  AAL_TERRAIN_PROBE_MEAN(vec4, texel, p, frame.heightLayersPerPage,
                         AAL_TERRAIN_FETCH_HEIGHT(terrainSlope, t, p.lod))
}

// The second moments of the horizons of the pair of directions beside the
// sun (rad^2; engine/terrain_scene.h horizonMomentPages) at a level of
// detail, read once per fragment (terrain_shading.glsl). They take the slope
// kind's pages 2 and 3, which the slopes (in the heights' pages, two at
// most) never use: no binding of their own (engine/terrain_renderer.cpp).
#if defined(AAL_TERRAIN_PAGED)
#define AAL_TERRAIN_FETCH_HORIZON_MOMENTS(t, lod)                            \
  ((t).page == 0 ? AAL_TERRAIN_FETCH_FROM(terrainSlope, 2, t, lod) \
                 : AAL_TERRAIN_FETCH_FROM(terrainSlope, 3, t, lod))
#else
#define AAL_TERRAIN_FETCH_HORIZON_MOMENTS(t, lod) AAL_TERRAIN_FETCH_FROM(terrainSlope, 2, t, lod)
#endif
vec2 terrainHorizonMomentsLod(vec2 texel, float lod) {
  TerrainTileTexel t = terrainTexel(texel, frame.heightLayersPerPage);
  return AAL_TERRAIN_FETCH_HORIZON_MOMENTS(t, lod).rg;
}

#endif
