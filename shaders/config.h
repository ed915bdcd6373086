// Constants shared by C++ and GLSL. Include from both; keep it to #defines so
// either language parses it.
#ifndef AAL_CONFIG_H
#define AAL_CONFIG_H

#define AAL_PI 3.14159265358979323846
#define AAL_TWO_PI 6.28318530717958647692

// Workgroup size of the cap parity compute shader.
#define AAL_CAPS_PARITY_GROUP_SIZE 64

// Shading modes (terrain/light/shading.h ShadingMode, shaders/shading.glsl).
#define AAL_MODE_APPROX 0
#define AAL_MODE_EXACT 1
#define AAL_MODE_BASELINE_LAMBERT 2
#define AAL_MODE_BASELINE_AO 3
#define AAL_MODE_DEBUG_VISIBLE 4
#define AAL_MODE_DEBUG_BENT_NORMAL 5
#define AAL_MODE_DEBUG_SUN_FRACTION 6
#define AAL_MODE_DEBUG_SKY_FILL 7
#define AAL_MODE_DEBUG_OBSCURANCE 8
#define AAL_MODE_DEBUG_TRANSFER 9
// The sun through the directional horizons, the sky through the aperture
// (terrain/io/horizon_map.h).
#define AAL_MODE_HORIZON 10

// Specialisation constant IDs of the pipelines that shade (shaders/variant.glsl):
// lavapipe runs every arm of a branch, so the frame's shading mode, albedo
// source, output and footprint probes are compiled in, not branched on.
#define AAL_SPEC_SHADING_MODE 0
#define AAL_SPEC_ALBEDO_SOURCE 1
#define AAL_SPEC_DISPLAY_OUTPUT 2
#define AAL_SPEC_FOOTPRINT_PROBES 3

// The most the footprint's spread may widen the sun's transition at the
// aperture's edge (rad; terrain/light/shading.h sunEdgeFootprintDistance):
// across a depth edge the screen derivatives mix two surfaces.
#define AAL_SUN_EDGE_MAX_WIDENING_RAD 0.05

// The exact cap intersection against the sun as a table (terrain/light/cap_table.h,
// shaders/cap_table.glsl, docs/caps.md): texels across the transition band
// (t = 0: nested .. 1: disjoint) and rows of aperture arc length (graded
// towards the aperture as large as the sun; (rows - 1) even puts that
// aperture on a row). Made when the sun's radius changes.
#define AAL_CAP_TABLE_WIDTH 256
#define AAL_CAP_TABLE_HEIGHT 65

// Workgroup size of the shading parity compute shader.
#define AAL_SHADING_PARITY_GROUP_SIZE 64

// Containment-test obscurances (terrain/light/obscurance.h, shaders/obscurance.glsl).
// Largest sample count n (the sample uniform buffer holds this many).
#define AAL_OBSCURANCE_MAX_SAMPLES 32
// Sample sets, one per cell of the 4x4 interleave pattern
// (kObscuranceSampleSets, terrain/light/obscurance_samples.h).
#define AAL_OBSCURANCE_SAMPLE_SETS 16
// The 4x4 filter skips neighbours whose view distance differs from the
// centre's by more than this fraction of it (Umenhoffer et al., "Efficient
// Methods for Ambient Lighting", 2009, §4.2).
#define AAL_OBSCURANCE_DEPTH_TOLERANCE 0.05
// Temporal reuse of obscurance samples (the viewer while the view moves,
// shaders/obscurance_pass.glsl): each frame evaluates one of this many parts
// of every pixel's sample set.
#define AAL_OBSCURANCE_SUBSETS 4
// Albedo sources (Frame.grid.w): palette by height and slope, image, constant.
#define AAL_ALBEDO_PALETTE 0
#define AAL_ALBEDO_IMAGE 1
#define AAL_ALBEDO_CONSTANT 2
// Workgroup size of the obscurance parity compute shader.
#define AAL_OBSCURANCE_PARITY_GROUP_SIZE 64

// Quadtree LOD (terrain/view/quadtree_lod.h, terrain/view/lod_patch.h, shaders/lod.glsl):
// quads across one patch (even, so that its quadrants and the morph's odd and
// even grid points line up with the next coarser level).
#define AAL_LOD_PATCH_QUADS 32
// Vertices of one patch grid line of the solid base's walls: two triangles
// per quad along it (shaders/base_vertex.glsl).
#define AAL_BASE_LINE_VERTICES (6 * AAL_LOD_PATCH_QUADS)
// Workgroup size of the LOD morph parity compute shader.
#define AAL_LOD_PARITY_GROUP_SIZE 64

// Tiled terrain textures (engine/terrain_tiles.h, shaders/tile_lookup.glsl,
// shaders/terrain_textures.glsl): mip levels of every tile image (the
// coarsest, AAL_TERRAIN_MIP_LEVELS - 1, has texels of 32 x 32 DEM texels),
// border texels per tile side (enough for a bilinear fetch of the coarsest
// level at a core's edge: 1.5 of its texels, rounded up to whole ones),
// texture pages (2D array images) per kind, and the first of the 3 x
// AAL_TERRAIN_TILE_PAGES bindings (heights, apertures, albedo) in every
// pipeline that samples them.
#define AAL_TERRAIN_MIP_LEVELS 6
#define AAL_TERRAIN_TILE_BORDER 64
#define AAL_TERRAIN_TILE_PAGES 4
#define AAL_TERRAIN_TEXTURE_BINDING 1
// Kinds of DEM texture bound from AAL_TERRAIN_TEXTURE_BINDING, each in
// AAL_TERRAIN_TILE_PAGES pages: heights, apertures, albedo, slopes.
#define AAL_TERRAIN_TEXTURE_KINDS 4
// The first binding after them.
#define AAL_TERRAIN_TEXTURES_END \
  (AAL_TERRAIN_TEXTURE_BINDING + AAL_TERRAIN_TEXTURE_KINDS * AAL_TERRAIN_TILE_PAGES)
// Workgroup size of the tile lookup parity compute shader.
#define AAL_TILE_PARITY_GROUP_SIZE 64

// Footprint filtering of the terrain's textures (terrain/view/texel_footprint.h,
// shaders/texel_footprint.glsl): most probes along the footprint's longer
// axis, and the slack with which the axes' ratio is rounded up to a count.
#define AAL_FOOTPRINT_MAX_PROBES 4
#define AAL_FOOTPRINT_RATIO_TOLERANCE 0.01
// Workgroup size of the footprint parity compute shader.
#define AAL_FOOTPRINT_PARITY_GROUP_SIZE 64

// Sun and sky (terrain/light/sky_model.h, terrain/light/tone_map.h, shaders/sky.glsl,
// shaders/tone_map.glsl).
// Floor on cos(view zenith angle) in the Perez function: views at and below
// the horizon see the horizon's value.
#define AAL_SKY_MIN_COS_THETA 0.001
// CIE XYZ to linear Rec. 709 / sRGB, rows, from the BT.709 primaries and the
// D65 white point (IEC 61966-2-1 prints it to 4 digits); use as
// vec3(AAL_XYZ_TO_LINEAR_SRGB_ROW0) in either language.
#define AAL_XYZ_TO_LINEAR_SRGB_ROW0 3.2404542, -1.5371385, -0.4985314
#define AAL_XYZ_TO_LINEAR_SRGB_ROW1 -0.9692660, 1.8760108, 0.0415560
#define AAL_XYZ_TO_LINEAR_SRGB_ROW2 0.0556434, -0.2040259, 1.0572252
// CIE daylight locus y_D(x) = A x^2 + B x + C (CIE 15:2004, "Colorimetry",
// eq. 3.3; Judd, MacAdam & Wyszecki 1964). The sky's chromaticity is kept on
// or above it (terrain/light/sky_model.h, docs/sun-and-sky.md).
#define AAL_DAYLIGHT_LOCUS_A -3.000
#define AAL_DAYLIGHT_LOCUS_B 2.870
#define AAL_DAYLIGHT_LOCUS_C -0.275
// Hable's filmic curve (Uncharted 2, GDC 2010): shoulder strength A, linear
// strength B, linear angle C, toe strength D, toe numerator E, toe
// denominator F, linear white point W.
#define AAL_FILMIC_A 0.15
#define AAL_FILMIC_B 0.50
#define AAL_FILMIC_C 0.10
#define AAL_FILMIC_D 0.20
#define AAL_FILMIC_E 0.02
#define AAL_FILMIC_F 0.30
#define AAL_FILMIC_W 11.2
// The sky's radiance per view direction, drawn into a small table every frame
// (shaders/sky_lut.glsl): azimuth across, sqrt(sin(elevation)) down.
#define AAL_SKY_LUT_WIDTH 256
#define AAL_SKY_LUT_HEIGHT 128
// Workgroup size of the sky and tone-map parity compute shaders.
#define AAL_SKY_PARITY_GROUP_SIZE 64

#endif
