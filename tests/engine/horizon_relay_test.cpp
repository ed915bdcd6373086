// The horizon pair's re-lay spread over frames (engine/horizon_relay.h): the
// plan of each frame and the horizon the frame reads in every band, against
// the error bound of docs/rendering.md ("Where the horizons lie").
#include "aperture/engine/horizon_relay.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include "aperture/terrain/io/horizon_map.h"

namespace aal {
namespace {

constexpr float kPi = std::numbers::pi_v<float>;

// Made-up horizons per band and direction, and the channels' state: what a
// frame reads and what it should read.
struct Bands {
  int directions = 8;
  uint32_t count = 40;
  std::vector<std::vector<float>> horizon;  // [band][direction]

  Bands(int n, uint32_t bands) : directions(n), count(bands) {
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> h(-0.3f, 1.2f);
    horizon.assign(bands, std::vector<float>(size_t(n)));
    for (auto& band : horizon)
      for (float& v : band) v = h(rng);
  }
  int directionIn(const HorizonChannels& c, int channel, uint32_t band) const {
    if (c.layingPair() && band < c.split) return (c.laying + channel) % directions;
    if (c.mixing() && channel == c.mixed && band < c.split) return c.head;
    return c.directions[channel];
  }
  // The horizon the frame reads in `band` (the shader's dot with the weights).
  float read(const HorizonChannels& c, float azimuth, uint32_t band) const {
    const std::array<float, 2> w = horizonChannelWeights(directions, c, azimuth);
    return w[0] * horizon[band][directionIn(c, 0, band)] +
           w[1] * horizon[band][directionIn(c, 1, band)];
  }
  // Linear between the stored directions beside the sun (horizonAtAzimuth).
  float exact(float azimuth, uint32_t band) const {
    const float x = horizonStepsFrom(directions, azimuth, 0);
    const float position = x < 0.0f ? x + float(directions) : x;
    const int k0 = std::min(int(position), directions - 1), k1 = (k0 + 1) % directions;
    const float f = position - float(k0);
    return (1.0f - f) * horizon[band][k0] + f * horizon[band][k1];
  }
  float largestStep(uint32_t band) const {
    float largest = 0;
    for (int k = 0; k < directions; ++k) {
      largest = std::max(largest, std::abs(horizon[band][k] - horizon[band][(k + 1) % directions]));
    }
    return largest;
  }
};

struct Sweep {
  uint32_t relays = 0, mixingFrames = 0, layPairs = 0, mostBands = 0;
  uint32_t layingFrames = 0;   // frames drawn in approx while a pair was laid
  double worstOverBound = -1;  // (error - bound), worst
};

// Drives the plan frame by frame along `azimuths` (rad), checking every
// band's horizon against the bound: horizonRelayReach of the largest step
// between adjacent directions.
Sweep sweep(const Bands& b, HorizonChannels& c, const std::vector<float>& azimuths,
            const HorizonRelayPolicy& policy) {
  Sweep s;
  for (size_t i = 0; i < azimuths.size(); ++i) {
    const float motion =
        i == 0 ? 0.0f : horizonMotionSteps(b.directions, azimuths[i - 1], azimuths[i]);
    const HorizonRelayStep step =
        planHorizonRelay(b.directions, c, azimuths[i], motion, b.count, policy);
    const int before = horizonChannelsPair(b.directions, c);
    if (step.kind == HorizonRelayStep::Kind::LayPair) ++s.layPairs;
    if (step.kind == HorizonRelayStep::Kind::WriteBands ||
        step.kind == HorizonRelayStep::Kind::LayBands) {
      EXPECT_LT(step.bandBegin, step.bandEnd);
      s.mostBands = std::max(s.mostBands, step.bandEnd - step.bandBegin);
    }
    c = afterHorizonRelay(b.directions, c, step, b.count);
    if (c.mixing()) ++s.mixingFrames;
    if (!c.mixing() && !c.layingPair() && horizonChannelsPair(b.directions, c) != before) {
      ++s.relays;
    }
    if (c.layingPair()) {
      // Drawn in approx: no horizon is read.
      EXPECT_EQ(horizonChannelWeights(b.directions, c, azimuths[i]), (std::array<float, 2>{0, 0}));
      ++s.layingFrames;
      continue;
    }
    for (uint32_t band = 0; band < b.count; ++band) {
      const double error = std::abs(b.read(c, azimuths[i], band) - b.exact(azimuths[i], band));
      s.worstOverBound = std::max(
          s.worstOverBound, error - horizonRelayReach(b.directions) * b.largestStep(band) - 1e-5);
    }
  }
  return s;
}

std::vector<float> turn(float fromDeg, float toDeg, float stepDeg) {
  std::vector<float> azimuths;
  const int steps = int(std::lround(std::abs(toDeg - fromDeg) / stepDeg));
  for (int i = 0; i <= steps; ++i) {
    azimuths.push_back((fromDeg + std::copysign(stepDeg, toDeg - fromDeg) * float(i)) * kPi /
                       180.0f);
  }
  return azimuths;
}

// A sun turning a whole way round, either way, 1 degree a frame: every
// direction passed re-lays once, band by band over several frames, never
// all at once and never both channels; in every frame and band the horizon
// read is within the bound.
TEST(HorizonRelay, ASweepReLaysOncePerDirectionWithinTheBound) {
  for (const int n : {8, 16}) {
    for (const float way : {1.0f, -1.0f}) {
      const Bands b(n, 132);
      const std::vector<float> azimuths = turn(10.0f, 10.0f + way * 360.0f, 1.0f);
      HorizonChannels c{{horizonPairFor(n, azimuths[0], -1), 0}};
      c.directions[1] = (c.directions[0] + 1) % n;
      const Sweep s = sweep(b, c, azimuths, HorizonRelayPolicy{8});
      const std::string what = std::to_string(n) + " directions, way " + std::to_string(way);
      EXPECT_EQ(s.relays, uint32_t(n)) << what;
      EXPECT_EQ(s.layPairs, 0u) << what;
      EXPECT_GE(s.mixingFrames, uint32_t(n) * 3) << what << ": spread over frames";
      EXPECT_LE(s.mostBands, b.count / 4) << what << ": no frame writes a whole channel";
      EXPECT_LE(s.worstOverBound, 0.0) << what;
    }
  }
}

// At once (aal-render's policy): each re-lay in the frame that needs it, so
// every frame reads the pair's interpolation exactly (the bound with
// horizonPairFor's margin in place of the reach).
TEST(HorizonRelay, AtOnceEveryFrameReadsThePairOfItsSun) {
  const Bands b(8, 20);
  const std::vector<float> azimuths = turn(3.0f, 363.0f, 1.0f);
  HorizonChannels c{{0, 1}};
  c = afterHorizonRelay(8, c, HorizonRelayStep{HorizonRelayStep::Kind::LayPair, 0}, b.count);
  for (size_t i = 0; i < azimuths.size(); ++i) {
    const HorizonRelayStep step = planHorizonRelay(8, c, azimuths[i], 0.0f, b.count, {});
    c = afterHorizonRelay(8, c, step, b.count);
    ASSERT_FALSE(c.mixing()) << i;
    for (uint32_t band = 0; band < b.count; ++band) {
      ASSERT_LE(std::abs(b.read(c, azimuths[i], band) - b.exact(azimuths[i], band)),
                kHorizonPairMargin * b.largestStep(band) + 1e-5)
          << i;
    }
  }
}

// A sun that stays where it is never re-lays, whatever it rests near: at
// every azimuth (a dense sweep), with the pair laid for it or with a
// neighbouring pair it lies within the reach of.
TEST(HorizonRelay, AStillSunNeverReLays) {
  const int n = 8;
  for (int i = 0; i < 3600; ++i) {
    const float azimuth = float(i) * 0.1f * kPi / 180.0f;
    const int own = horizonPairFor(n, azimuth, -1);
    for (const int first : {own, (own + 1) % n, (own + n - 1) % n}) {
      const HorizonChannels c{{first, (first + 1) % n}};
      if (horizonPairFor(n, azimuth, first, horizonRelayReach(n)) != first) continue;
      for (int frame = 0; frame < 3; ++frame) {
        EXPECT_EQ(planHorizonRelay(n, c, azimuth, 0.0f, 132, HorizonRelayPolicy{8}).kind,
                  HorizonRelayStep::Kind::Keep)
            << "azimuth " << i * 0.1 << ", pair " << first;
      }
    }
  }
}

// A sun that turns back in the middle of a re-lay takes the written bands
// back, spread as well; the bound holds throughout and the pair ends as it
// began.
TEST(HorizonRelay, ATurningSunTakesItsReLayBackAndAJumpLaysThePair) {
  const Bands b(8, 64);
  // Direction 1 lies at 45 degrees: from 30 up to 46, then back to 30.
  std::vector<float> azimuths = turn(30.0f, 46.0f, 0.5f);
  const std::vector<float> back = turn(46.0f, 30.0f, 0.5f);
  azimuths.insert(azimuths.end(), back.begin() + 1, back.end());
  HorizonChannels c{{0, 1}};
  const Sweep s = sweep(b, c, azimuths, HorizonRelayPolicy{2});
  EXPECT_GT(s.mixingFrames, 0u);
  EXPECT_EQ(s.layPairs, 0u);
  EXPECT_LE(s.worstOverBound, 0.0);
  EXPECT_FALSE(c.mixing());
  EXPECT_EQ(horizonChannelsPair(8, c), 0);

  // At once (aal-render's policy), a jump past the next pair lays both
  // channels in one frame, and a step past the reach writes the rest of its
  // channel.
  const float far = 200.0f * kPi / 180.0f;  // direction 4.4
  const HorizonRelayStep jump = planHorizonRelay(8, c, far, 1.0f, 64, {});
  EXPECT_EQ(jump.kind, HorizonRelayStep::Kind::LayPair);
  EXPECT_EQ(jump.first, 4);
  const float next = 70.0f * kPi / 180.0f;  // direction 1.56
  const HorizonRelayStep atOnce = planHorizonRelay(8, c, next, 0.0f, 64, {});
  EXPECT_EQ(atOnce.kind, HorizonRelayStep::Kind::WriteBands);
  EXPECT_EQ(atOnce.bandEnd - atOnce.bandBegin, 64u);
  EXPECT_EQ(atOnce.direction, 2);
  // Spread, a step past the reach whose rest is within kHorizonAtOnceFrames
  // frames' bands writes it at once too.
  const HorizonRelayStep rest = planHorizonRelay(8, c, next, 0.0f, 64, HorizonRelayPolicy{32});
  EXPECT_EQ(rest.kind, HorizonRelayStep::Kind::WriteBands);
  EXPECT_EQ(rest.bandEnd - rest.bandBegin, 64u);
}

// Spread (aal-view's policy), a jump lays the sun's pair bandsPerFrame bands
// a frame, both channels, the frames meanwhile reading no horizon (drawn in
// approx); so does a step past the reach with more than
// kHorizonAtOnceFrames frames' bands of its channel left. A sun that jumps
// again while a pair is laid starts the new one from the first band; one
// that stays by the pair being laid goes on with it.
TEST(HorizonRelay, ASpreadJumpLaysThePairOverFramesAndReadsNoHorizonMeanwhile) {
  const Bands b(8, 64);
  const HorizonRelayPolicy policy{4};
  // Direction 4.4, then 4.5 (the same pair), then 6.5 (another), each held.
  std::vector<float> azimuths(3, 200.0f * kPi / 180.0f);
  azimuths.insert(azimuths.end(), 5, 202.5f * kPi / 180.0f);
  const size_t again = azimuths.size();
  azimuths.insert(azimuths.end(), 20, 292.5f * kPi / 180.0f);
  HorizonChannels c{{0, 1}};
  std::vector<HorizonRelayStep> steps;
  for (size_t i = 0; i < azimuths.size(); ++i) {
    const float motion = i == 0 ? 0.0f : horizonMotionSteps(8, azimuths[i - 1], azimuths[i]);
    steps.push_back(planHorizonRelay(8, c, azimuths[i], motion, b.count, policy));
    c = afterHorizonRelay(8, c, steps.back(), b.count);
    if (c.layingPair()) {
      EXPECT_EQ(horizonChannelsPair(8, c), 0) << i << ": the pair before, until done";
    }
  }
  for (size_t i = 0; i < again; ++i) {
    EXPECT_EQ(steps[i].kind, HorizonRelayStep::Kind::LayBands) << i;
    EXPECT_EQ(steps[i].first, 4) << i;
    EXPECT_EQ(steps[i].bandBegin, 4 * i) << i;
    EXPECT_EQ(steps[i].bandEnd, 4 * i + 4) << i;
  }
  EXPECT_EQ(steps[again].first, 6);
  EXPECT_EQ(steps[again].bandBegin, 0u) << "a new pair starts over";
  // 16 frames of 4 bands lay pair 6; then it is whole and the sun keeps it.
  for (size_t i = again; i < again + 16; ++i) {
    EXPECT_EQ(steps[i].kind, HorizonRelayStep::Kind::LayBands) << i;
  }
  for (size_t i = again + 16; i < steps.size(); ++i) {
    EXPECT_EQ(steps[i].kind, HorizonRelayStep::Kind::Keep) << i;
  }
  EXPECT_FALSE(c.layingPair());
  EXPECT_EQ(c, (HorizonChannels{{6, 7}}));

  // A step past the reach with 64 bands of a channel left (more than 2
  // frames of 4): the sun's pair laid, spread.
  const HorizonChannels pair{{0, 1}};
  const HorizonRelayStep past = planHorizonRelay(8, pair, 70.0f * kPi / 180.0f, 0.0f, 64, policy);
  EXPECT_EQ(past.kind, HorizonRelayStep::Kind::LayBands);
  EXPECT_EQ(past.first, 1);
  EXPECT_EQ(past.bandEnd - past.bandBegin, 4u);

  // Along a sweep that jumps every 40 frames the bound holds in every frame
  // that reads horizons.
  std::vector<float> hops;
  for (int k = 0; k < 6; ++k) {
    const std::vector<float> piece = turn(10.0f + 100.0f * k, 50.0f + 100.0f * k, 1.0f);
    hops.insert(hops.end(), piece.begin(), piece.end());
  }
  HorizonChannels h{{0, 1}};
  const Sweep s = sweep(b, h, hops, policy);
  EXPECT_EQ(s.layPairs, 0u);
  EXPECT_GE(s.layingFrames, 5u * 16u) << "each hop laid over 16 frames";
  // No frame writes half a channel (a spread re-lay hurries past 4 bands a
  // frame to be done within the reach).
  EXPECT_LT(s.mostBands, b.count / 2);
  EXPECT_LE(s.worstOverBound, 0.0);
}

}  // namespace
}  // namespace aal
