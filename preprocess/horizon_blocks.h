// The line sweep of horizon_sweep.h, restructured for speed: the same lines,
// hulls and blending, but each step of a group of lines hands the horizons
// of its texels over as one block, and the arithmetic runs in single
// precision in loops over the group that the compiler turns into vector
// code. The hull update (a stack pop loop per line) is scalar, except on
// CPUs with AVX2, where it runs 8 lines at a time (bake_avx2.cpp, chosen at
// run time; the same results bit for bit).
// Without a distance limit, or with one short enough to scan
// (scansWithinLimit: each line then keeps its last points instead of a
// hull): sweepHorizons() remains the general path and the reference this
// one is tested against. sweepOpposedHorizonBlocks()
// hands over azimuths phi and phi + pi together, so that a bake touches a
// texel's sums once for both.
//
// The groups of lines: horizon_blocks.cpp; one group's walk:
// block_line_walker.h.
//
// Single precision: distances along a line are at most ~350 km from the DEM
// centre even for 16384 x 30 m grids, where a float is good to 3 cm; the
// tangents that come out are within ~1e-4 of the double-precision sweep's.
#pragma once

#include <cstddef>
#include <memory>
#include <type_traits>

#include "aperture/preprocess/bake_terrain.h"
#include "aperture/preprocess/horizon_sweep.h"

// The AVX2 kernels (bake_avx2.cpp) exist on x86-64 with GCC or clang.
#if defined(__x86_64__) && defined(__GNUC__)
#define AAL_HORIZON_AVX2 1
#else
#define AAL_HORIZON_AVX2 0
#endif

namespace aal {

class FarFieldWindow;

// The texels of one sweep step of one group of lines: texel j (0 <= j <
// count) is firstTexel + j * stride in the heightfield, with horizon
// tangent tanHorizon[j] (kNoHorizonTangent when no terrain lies ahead).
struct HorizonBlock {
  // Lines stepped together; a block is up to kLines texels. 32 beat 16 by
  // 3 % at 1024² and 10 % at 4096² (fewer groups, so fewer passes over each
  // column's cache lines); 64 was slower at 1024² (docs/performance.md).
  // 39 beat 32 by 3 % at 1024² and 2.5 % at 4096² with the AVX2 walk: its
  // group walks 40 lines, 5 whole vectors of 8, where 32 walks 33.
  static constexpr int kLines = 39;
  size_t firstTexel = 0;
  ptrdiff_t stride = 1;
  int count = 0;
  const float* tanHorizon = nullptr;
  // The same group's texels kAheadSteps steps later (aheadCount 0: none),
  // for the visitor to prefetch what it will touch there.
  static constexpr int kAheadSteps = 6;
  size_t aheadFirstTexel = 0;
  int aheadCount = 0;
  // sweepOpposedHorizonBlocks: the tangents of the opposite azimuth.
  const float* tanOpposite = nullptr;
  // The surface's slopes at the texels, BakeTerrain::slopeEastAt and
  // slopeNorthAt bit for bit: the walk computes them from the heights it
  // loads anyway, so a bake needs no stored slopes.
  const float* slopeEast = nullptr;
  const float* slopeNorth = nullptr;
  // Room for a block's texels in whole vectors of 8.
  static constexpr int kPaddedTexels = (kLines + 7) / 8 * 8;
};

// Finite stand-in for -infinity: keeps the vector loops free of inf tests.
constexpr float kNoHorizonTangent = -1e30f;

// What the sweeps call with each block, concurrently: a reference to the
// caller's callable (which must outlive the sweep), so that the sweeps are
// compiled once (horizon_blocks.cpp) whoever calls them. One indirect call
// per block of up to kLines texels.
class HorizonBlockVisitor {
 public:
  template <class Visit>
  requires(std::is_invocable_v<Visit&, const HorizonBlock&> &&
           !std::is_same_v<std::remove_cvref_t<Visit>, HorizonBlockVisitor>)
      HorizonBlockVisitor(Visit&& visit)  // NOLINT(google-explicit-constructor): takes lambdas
      : visit_(const_cast<void*>(static_cast<const void*>(std::addressof(visit)))),
        call_([](void* v, const HorizonBlock& b) {
          (*static_cast<std::remove_reference_t<Visit>*>(v))(b);
        }) {}

  void operator()(const HorizonBlock& b) const { call_(visit_, b); }

 private:
  void* visit_;
  void (*call_)(void*, const HorizonBlock&);
};

// Lets sweeps and bakes started from now on use AVX2 where the CPU has it
// (the default), or not: for tests of the scalar path on any CPU. Both
// paths give the same tangents bit for bit.
void setHorizonAvx2Allowed(bool allowed);

namespace detail {
// Whether this CPU runs the AVX2 hull update (BlockLineWalker) and the
// bake's AVX2 visitor, and setHorizonAvx2Allowed allows them: the build
// targets plain x86-64, so the choice is made at run time.
bool horizonAvx2();
}  // namespace detail

// Calls visit(const HorizonBlock&) for the texels of every step of every
// group of lines of azimuth phi (as sweepHorizons(): each texel exactly once,
// blocks concurrently). A distance limit must be one the walk scans
// (scansWithinLimit; else std::invalid_argument): its lines then start as
// a window's do (sweepWindowHorizonBlocks, with the limit as the reach).
void sweepHorizonBlocks(const BakeTerrain& terrain, double phi, const HorizonSweepOptions& options,
                        HorizonBlockVisitor visit);

// The texels of a partial window (terrain.window) for azimuth phi, its
// lines walked with the unlimited hull from options.windowReachM before it
// (with a distance limit, scanned: from the limit before it):
// sweepHorizons() with windowReachM, in blocks whose texels are window
// indices (BakeTerrain::windowIndex).
// With `far` (the blocks of a far field's pyramid this window reads;
// docs/baking.md, "Far field"), each line starts with the block maxima beyond its
// first point in its hull (FarLineMarch), so the tangents cover the whole
// DEM; with clamped edges the ground beyond the DEM goes on flat from the
// last of them. Without, edges must be open (options.clampEdge false): the
// walk of a line that begins inside the field would take its first point
// for the edge (with a limit they may be clamped: that point lies beyond it).
void sweepWindowHorizonBlocks(const BakeTerrain& terrain, double phi,
                              const HorizonSweepOptions& options, HorizonBlockVisitor visit,
                              const FarFieldWindow* far = nullptr);

// Texels around a window that its sweeps with reach `reachM` (a max
// distance or options.windowReachM) read, in rows and in columns alike.
// Each line starts S = stepsCovering(reachM) steps before the first window
// texel it passes beside (SweepLayout::lineStart) and moves by up to one
// texel across a step; the block sweeps walk it with up to kMaxLines - 1
// neighbours, which may have started later and are read from its start on,
// and read one texel either side of them and one slice either side along
// (the slopes, the leaving slope). Lines advancing by rows drift in
// columns as far as lines advancing by columns drift in rows, so one halo
// serves both (TileWindow.TheHaloHoldsEveryReadInRowsAndInColumnsAlike).
int windowSweepHalo(const BakeTerrain& terrain, double reachM);

// The same for two opposite azimuths phi and phiOpposite (phi + pi, as the
// caller computes it) in one pass: each block holds both azimuths'
// tangents of its texels (tanHorizon for phi, tanOpposite for phiOpposite),
// so a visitor reads and writes a texel's sums once for both. Each line of
// either azimuth is still walked from its own far end: the opposite walk of
// a group goes first and its tangents wait in a buffer of one float per
// step and line. Returns false, having visited nothing, where the two
// sweeps' lines do not pair up (their major axes differ, at exactly 45
// degrees): then sweep each azimuth on its own.
// With options.windowReachM, a partial window's lines as
// sweepWindowHorizonBlocks walks them, each azimuth's lines from the near
// reach before the window on its own side, with `far` as there.
bool sweepOpposedHorizonBlocks(const BakeTerrain& terrain, double phi, double phiOpposite,
                               const HorizonSweepOptions& options, HorizonBlockVisitor visit,
                               const FarFieldWindow* far = nullptr);

}  // namespace aal
