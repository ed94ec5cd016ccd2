#pragma once
// Scene and Plan messages (docs/protocol.md, "Planner messages"): one planning
// cycle over the link. Positions travel as float32 offsets from an origin
// (the first reference point, float64), so a 300 m scene keeps ~0.1 mm; the
// predictions may be thinned (every `stride`-th sample) to save link time,
// the planner interpolates between samples.
#include <cstddef>
#include <cstdint>
#include <span>

#include "itp/link/secure_channel.hpp"
#include "itp/planner/plan.hpp"
#include "itp/scene/scene.hpp"

namespace itp::link {

struct SceneHeader {
  std::uint32_t cycle = 0;  // counter of the sender, echoed in the Plan
  double now = 0;           // [s] scene time of this cycle
  bool reset = false;       // first cycle of a new scene: forget the previous plan
};

// What a Plan reply says about itself besides the plan.
struct PlanHeader {
  std::uint32_t cycle = 0;      // the Scene's cycle
  std::uint32_t scene_crc = 0;  // CRC-32 of the Scene body the firmware planned (an end-to-end echo)
  double origin_x = 0;          // [m] positions are float offsets from here
  double origin_y = 0;          // [m]
};

// Largest Scene and Plan bodies of configuration Cfg [bytes] (docs/protocol.md
// gives the layouts). Counts travel as one byte each, and a body must fit one
// link payload: both are checked for every configuration at compile time.
template <class Cfg>
inline constexpr std::size_t kMaxSceneBytes =
    29 + (1 + 8 * Cfg::kMaxReferencePoints) + 12 + 2 * (5 + 8 * Cfg::kMaxBoundaryPoints) + 52 +
    (1 + 24 * Cfg::kMaxStaticObstacles) +
    (1 + Cfg::kMaxDynamicObstacles * (13 + 20 * Cfg::kMaxPredictionSamples));
template <class Cfg>
inline constexpr std::size_t kMaxPlanBytes =
    123 + 36 * Cfg::kTrajectorySamples + 1 + 7 * Cfg::kMaxObstacles;

// Both travel secured (freshness and tag around the body) in at most
// kMaxSegments segments.
template <class Cfg>
constexpr bool fits_link() {
  return kMaxSceneBytes<Cfg> + kSecuredOverhead <= kMaxMessageBytes &&
         kMaxPlanBytes<Cfg> + kSecuredOverhead <= kMaxMessageBytes && Cfg::kMaxReferencePoints <= 255 &&
         Cfg::kMaxBoundaryPoints <= 255 && Cfg::kMaxStaticObstacles <= 255 &&
         Cfg::kMaxDynamicObstacles <= 255 && Cfg::kMaxPredictionSamples <= 255 &&
         Cfg::kTrajectorySamples <= 255 && Cfg::kMaxObstacles <= 255;
}

// Returns the body size; 0 if it does not fit `out`, or when a finite value
// (or a position's offset from the origin) lies beyond float32's range: such
// a value is refused, never sent as infinity.
template <class Cfg>
std::size_t encode_scene(const SceneHeader& header, const scene::BasicScene<Cfg>& scene,
                         int prediction_stride, std::span<std::uint8_t> out);
// False on a malformed body or a count beyond capacity (then `scene` is unusable).
template <class Cfg>
bool decode_scene(std::span<const std::uint8_t> in, SceneHeader& header,
                  scene::BasicScene<Cfg>& scene);

template <class Cfg>
std::size_t encode_plan(const PlanHeader& header, const planner::BasicPlan<Cfg>& plan,
                        std::span<std::uint8_t> out);
// The bytes encode_plan gives for an empty plan with status invalid_input
// and reason `why` (no trajectory; the vehicle's own safe stop applies).
std::size_t encode_rejected_plan(const PlanHeader& header, scene::ValidationReason why,
                                 std::span<std::uint8_t> out);
template <class Cfg>
bool decode_plan(std::span<const std::uint8_t> in, PlanHeader& header, planner::BasicPlan<Cfg>& plan);

}  // namespace itp::link
