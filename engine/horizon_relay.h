// The horizon mode's re-lay spread over frames (docs/rendering.md, "Where the
// horizons lie"): what the slope texture's B and A channels hold, the plan of
// one frame's share of a re-lay, and the weights the frame reads the channels
// with. Pure logic: TerrainScene does the writing, TerrainRenderer plans.
//
// A sun turning from pair (k, k + 1) to (k + 1, k + 2) keeps direction k + 1:
// only the channel of k is rewritten, with k + 2, band by band of rows. While
// that channel holds k in some bands and k + 2 in others the frame reads the
// other channel alone, the horizon of the shared direction k + 1 (weights 1
// and 0), which is right in every band. That costs accuracy only while the
// sun is off k + 1, and never more than horizonRelayReach steps off it: there
// the rest is written at once. So the horizon a frame reads is always either
// the pair's interpolation for the sun or the horizon of a stored direction
// within horizonRelayReach steps of the sun, which differs from the
// interpolation by at most horizonRelayReach x |h(k + 1) - h(k or k + 2)|.
//
// A sun that jumps (past the next pair, or past the reach with more than a
// few frames' bands of a channel left to write) needs both channels anew.
// Spread, they are laid band by band too, and while that lasts no band's
// pair is sure to be the sun's: the frames draw `approx` instead (the
// renderer's choice, TerrainRenderer::record), which reads no horizons.
#pragma once

#include <array>
#include <cstdint>

namespace aal {

// The azimuth either side of the shared direction within which a frame may
// read that direction alone (a re-lay under way, or a sun resting just
// outside its pair's span): 5.625 degrees, whatever the directions, so that
// a sun turning at a given rate leaves as many frames for a re-lay with 16
// directions as with 8. In direction steps (horizonRelayReach): 1/8 of a
// step with 8 directions, 1/4 with 16; the bound above is then about the
// same angle of a horizon that changes smoothly with azimuth (half the step,
// twice its share).
constexpr float kHorizonRelayReachRad = 0.09817477f;  // 2 pi / 64
float horizonRelayReach(int directions);

// What the slope texture holds: direction `directions[c]` in channel c (0: B,
// 1: A) at every texel, except while a re-lay is under way: then channel
// `mixed` holds direction `head` in the bands [0, split) of every tile image
// and directions[mixed] in the rest, and the other channel the shared
// direction everywhere. The two directions are adjacent (a pair). While a
// pair is laid over frames (`laying`, its first direction), the bands
// [0, split) hold it in both channels and the rest what they held before
// (`directions`, the pair before, is kept for horizonChannelsPair).
struct HorizonChannels {
  std::array<int, 2> directions{0, 1};
  int mixed = -1;  // -1: none
  int head = -1;
  uint32_t split = 0;
  int laying = -1;  // -1: none
  bool mixing() const { return mixed >= 0; }
  bool layingPair() const { return laying >= 0; }
  bool operator==(const HorizonChannels&) const = default;
};

// The pair (its first direction, horizonPairFor's) the channels hold where
// they are not mixed; while mixing or laying, the one they held before.
int horizonChannelsPair(int directions, const HorizonChannels& channels);

// One frame's share of the re-lay.
struct HorizonRelayStep {
  enum class Kind {
    Keep,        // nothing to write
    LayPair,     // both channels, every band: `first` in B, first + 1 in A (a jump)
    WriteBands,  // channel `channel`'s bands [bandBegin, bandEnd) get `direction`
    LayBands     // a jump spread: both channels of bands [bandBegin, bandEnd) get
                 // pair `first` (bandBegin 0: a new laying)
  };
  Kind kind = Kind::Keep;
  int first = 0;
  int channel = 0, direction = 0;
  uint32_t bandBegin = 0, bandEnd = 0;
};

// How a re-lay is spread. bandsPerFrame 0: every re-lay done in the frame
// that needs it, with horizonPairFor's margin (aal-render: every frame as
// exact as a fresh scene). Above 0: at least that many bands a frame, more
// when the sun would otherwise leave horizonRelayReach of the shared
// direction first (the rest at once when it does, if that is at most
// kHorizonAtOnceFrames frames' bands), started ahead of a sun moving
// towards the next pair; a jump, or a rest larger than that, lays the sun's
// pair bandsPerFrame bands a frame (LayBands; aal-view).
struct HorizonRelayPolicy {
  uint32_t bandsPerFrame = 0;
};
inline constexpr uint32_t kHorizonAtOnceFrames = 2;

// Direction steps a sun went from one azimuth to the next, the shorter way
// round: in [-n/2, n/2), positive counter-clockwise.
float horizonMotionSteps(int directions, float fromAzimuthRad, float toAzimuthRad);

// The step for a frame whose sun is at azimuthRad (the horizons' convention),
// having moved motionSteps direction steps since the previous frame (signed,
// 0: still or unknown), with `bands` bands in every tile image.
HorizonRelayStep planHorizonRelay(int directions, const HorizonChannels& now, float azimuthRad,
                                  float motionSteps, uint32_t bands,
                                  const HorizonRelayPolicy& policy);

// The channels once `step` is written.
HorizonChannels afterHorizonRelay(int directions, const HorizonChannels& now,
                                  const HorizonRelayStep& step, uint32_t bands);

// The weights of B and A for a sun at azimuthRad: horizonPairWeights of the
// pair, each on its direction's channel; while mixing 1 on the shared
// direction's channel, 0 on the mixed one; while laying 0 and 0 (no horizon
// is read: those frames draw approx).
std::array<float, 2> horizonChannelWeights(int directions, const HorizonChannels& channels,
                                           float azimuthRad);

}  // namespace aal
