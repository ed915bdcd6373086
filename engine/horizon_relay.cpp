#include "aperture/engine/horizon_relay.h"

#include <algorithm>
#include <cmath>

#include "aperture/terrain/io/horizon_map.h"
#include "aperture/terrain/units.h"

namespace aal {

namespace {

int wrapDirection(int direction, int directions) {
  return ((direction % directions) + directions) % directions;
}

int channelOf(const HorizonChannels& c, int direction) {
  return c.directions[0] == direction ? 0 : 1;
}

// Writes up to `count` bands of the mixed channel towards `target` (its head
// or its tail direction): the head grows from band 0 up, the tail back down.
HorizonRelayStep writeTowards(const HorizonChannels& m, int target, uint32_t count,
                              uint32_t bands) {
  HorizonRelayStep step;
  step.kind = HorizonRelayStep::Kind::WriteBands;
  step.channel = m.mixed;
  step.direction = target;
  if (target == m.head) {
    step.bandBegin = m.split;
    step.bandEnd = std::min(bands, m.split + count);
  } else {
    step.bandEnd = m.split;
    step.bandBegin = m.split - std::min(count, m.split);
  }
  return step;
}

HorizonRelayStep layPair(int first) {
  HorizonRelayStep step;
  step.kind = HorizonRelayStep::Kind::LayPair;
  step.first = first;
  return step;
}

// The next bands of pair `first` laid over frames: from `split` on when it
// is the pair being laid, else from band 0.
HorizonRelayStep layBands(const HorizonChannels& now, int first, uint32_t count, uint32_t bands) {
  HorizonRelayStep step;
  step.kind = HorizonRelayStep::Kind::LayBands;
  step.first = first;
  step.bandBegin = now.laying == first ? now.split : 0;
  step.bandEnd = std::min(bands, step.bandBegin + count);
  return step;
}

}  // namespace

int horizonChannelsPair(int directions, const HorizonChannels& c) {
  return c.directions[1] == (c.directions[0] + 1) % directions ? c.directions[0] : c.directions[1];
}

float horizonRelayReach(int directions) {
  return kHorizonRelayReachRad * float(directions) / (2.0f * kPiFloat);
}

float horizonMotionSteps(int directions, float fromAzimuthRad, float toAzimuthRad) {
  const float n = float(directions);
  const float steps = horizonStepsFrom(directions, toAzimuthRad, 0) -
                      horizonStepsFrom(directions, fromAzimuthRad, 0);
  return steps - n * std::floor(steps / n + 0.5f);
}

HorizonRelayStep planHorizonRelay(int directions, const HorizonChannels& now, float azimuthRad,
                                  float motionSteps, uint32_t bands,
                                  const HorizonRelayPolicy& policy) {
  const bool spread = policy.bandsPerFrame > 0;
  const float reach = horizonRelayReach(directions);
  const float margin = spread ? reach : kHorizonPairMargin;
  // A jump: spread, the sun's pair laid over frames; else at once.
  const auto jump = [&](int first) {
    return spread ? layBands(now, first, policy.bandsPerFrame, bands) : layPair(first);
  };
  if (now.layingPair()) {
    // The pair being laid while the sun stays by it (the reach's margin),
    // else the sun's pair from the first band.
    return jump(horizonPairFor(directions, azimuthRad, now.laying, margin));
  }
  HorizonChannels m = now;
  if (!now.mixing()) {
    const int first = horizonChannelsPair(directions, now);
    const int next = wrapDirection(first + 1, directions);
    const int before = wrapDirection(first - 1, directions);
    int target = horizonPairFor(directions, azimuthRad, first, margin);
    if (target == first) {
      if (!spread || motionSteps == 0.0f) return {};
      // Ahead of a sun moving towards the pair's end: started about half
      // the re-lay's frames (at the least rate) before the sun reaches the
      // end's direction, so that it ends about as far past it; never more
      // than the reach ahead. A sun turning back meanwhile takes the
      // written bands back the same way, spread too.
      const float frames = std::ceil(float(bands) / float(policy.bandsPerFrame));
      const float lead = std::min(reach, 0.5f * frames * std::abs(motionSteps));
      const float past = horizonStepsFrom(directions, azimuthRad, first);
      if (motionSteps > 0.0f && past >= 1.0f - lead) {
        target = next;
      } else if (motionSteps < 0.0f && past <= lead) {
        target = before;
      } else {
        return {};
      }
    }
    if (target == next) {  // keeps `next`, rewrites `first`'s channel
      m.mixed = channelOf(now, first);
      m.head = wrapDirection(first + 2, directions);
    } else if (target == before) {  // keeps `first`
      m.mixed = channelOf(now, next);
      m.head = before;
    } else {
      return jump(target);  // no direction in common
    }
    m.split = 0;
  }

  const int shared = m.directions[1 - m.mixed];
  const float off = horizonStepsFrom(directions, azimuthRad, shared);
  if (std::abs(off) > 1.0f + margin) return jump(horizonPairFor(directions, azimuthRad, -1));
  const int up = wrapDirection(shared + 1, directions);
  const int down = wrapDirection(shared - 1, directions);
  const bool inReach = spread && std::abs(off) <= reach;
  int target = off >= 0.0f ? up : down;
  if (inReach) target = motionSteps > 0.0f ? up : motionSteps < 0.0f ? down : m.head;
  const uint32_t remaining = target == m.head ? bands - m.split : m.split;
  uint32_t count = remaining;  // outside the reach: the rest at once
  if (inReach) {
    count = policy.bandsPerFrame;
    if (motionSteps != 0.0f) {
      // Enough a frame to be done before the sun leaves the reach.
      const float toEdge = reach - (motionSteps > 0.0f ? off : -off);
      const float framesLeft = std::floor(std::max(0.0f, toEdge) / std::abs(motionSteps)) + 1.0f;
      count = std::max(count, uint32_t(std::ceil(float(remaining) / framesLeft)));
    }
  } else if (spread && remaining > kHorizonAtOnceFrames * policy.bandsPerFrame) {
    // Past the reach with too much left for one frame: laid anew, spread.
    return jump(horizonPairFor(directions, azimuthRad, -1));
  }
  return writeTowards(m, target, std::min(count, remaining), bands);
}

HorizonChannels afterHorizonRelay(int directions, const HorizonChannels& now,
                                  const HorizonRelayStep& step, uint32_t bands) {
  HorizonChannels c = now;
  switch (step.kind) {
    case HorizonRelayStep::Kind::Keep: return c;
    case HorizonRelayStep::Kind::LayPair:
      return HorizonChannels{{step.first, wrapDirection(step.first + 1, directions)}};
    case HorizonRelayStep::Kind::LayBands:
      if (step.bandEnd >= bands) {
        return HorizonChannels{{step.first, wrapDirection(step.first + 1, directions)}};
      }
      // The pair before stays named (horizonChannelsPair) until the new one
      // is whole.
      c.mixed = c.head = -1;
      c.laying = step.first;
      c.split = step.bandEnd;
      return c;
    case HorizonRelayStep::Kind::WriteBands: break;
  }
  if (!c.mixing()) {
    c.mixed = step.channel;
    c.head = step.direction;
    c.split = 0;
  }
  c.split = step.direction == c.head ? step.bandEnd : step.bandBegin;
  if (c.split >= bands) c.directions[c.mixed] = c.head;
  if (c.split >= bands || c.split == 0) c = HorizonChannels{c.directions};
  return c;
}

std::array<float, 2> horizonChannelWeights(int directions, const HorizonChannels& channels,
                                           float azimuthRad) {
  std::array<float, 2> w{0.0f, 0.0f};
  if (channels.layingPair()) return w;
  if (channels.mixing()) {
    w[1 - channels.mixed] = 1.0f;
    return w;
  }
  const int first = horizonChannelsPair(directions, channels);
  const std::array<float, 2> pair = horizonPairWeights(directions, azimuthRad, first);
  const int c = channelOf(channels, first);
  w[c] = pair[0];
  w[1 - c] = pair[1];
  return w;
}

}  // namespace aal
