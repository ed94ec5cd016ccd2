#pragma once
// The scene in the reference line's frame (paper 1.1, first step): the road's
// edges as lateral profiles, every static obstacle as an SL box, and every
// dynamic obstacle as its motion at the ST samples (as planned against,
// road_prediction.hpp) with an SL box per sample and its classification
// (oncoming, from behind, crossing). Per iteration, place_dynamic() adds the
// dynamic obstacles at their meeting places with the ego behind the static
// boxes; the convex space is built from boxes().
#include <array>
#include <span>

#include "itp/core/static_vector.hpp"
#include "itp/decision/road_sl.hpp"
#include "itp/geometry/reference_line.hpp"
#include "itp/geometry/sl_box.hpp"
#include "itp/planner/planner_settings.hpp"
#include "itp/scene/obstacle_motion.hpp"
#include "itp/scene/scene.hpp"
#include "itp/speed/st_graph.hpp"

namespace itp::planner {

// One dynamic obstacle's motion at the ST samples t_k = now + k dt.
template <class Cfg>
using MotionSamples = std::array<scene::ObstacleSample, Cfg::kStSamples>;

template <class Cfg>
class BasicSlScene {
 public:
  using Scene = scene::BasicScene<Cfg>;
  using ReferenceLine = geometry::BasicReferenceLine<Cfg>;
  using RoadSl = decision::BasicRoadSl<Cfg>;
  using DynamicTrack = speed::BasicDynamicTrack<Cfg>;
  using Motion = MotionSamples<Cfg>;
  using StSamples = std::array<Scalar, Cfg::kStSamples>;  // one value per ST sample
  // ST samples: every horizon / kSpeedSamples (0.1 s) over the speed horizon.
  static constexpr Scalar kDt = Cfg::kSpeedHorizon / static_cast<Scalar>(Cfg::kSpeedSamples);  // [s]

  // A validated scene at time `now`, the ego's rear axle at path s `s_start`,
  // the SL horizon ending at `s_end` (the road's cuts are chosen within it).
  void build(const Scene& scene, const ReferenceLine& line, Scalar now, Scalar s_start, Scalar s_end,
             const PlannerSettings& settings);

  // Back to the static boxes, then each dynamic obstacle not `skip`ped and
  // not crossing at its meeting place with the ego driving `s_guess`
  // (speed-s from s_start per ST sample). Returns how many were placed.
  // The decision stage holds Cfg::kDecisionDynamics of them: with more, the
  // nearest (their placed box's start from the ego's rear axle).
  int place_dynamic(const StSamples& s_guess, const bool* skip);

  // The track of the nearest placed moving obstacle whose box overlaps
  // [s_lo, s_hi] in s and that is not skipped; -1: none. Never one whose
  // whole sweep is occupied (the ST graph cannot make the ego wait for those
  // in their lane).
  int nearest_dynamic(const bool* skip, Scalar s_lo, Scalar s_hi) const;

  std::span<const geometry::SlBox> boxes() const { return boxes_.span(); }
  // Static obstacles of the scene the decision stage does not see (the
  // least relevant, when the scene holds more than Cfg::kDecisionStatics).
  int statics_left_out() const { return statics_left_out_; }
  std::span<const geometry::SlBox> static_boxes() const { return boxes_.span().first(static_count_); }
  std::span<const DynamicTrack> tracks() const {
    return {tracks_.data(), static_cast<std::size_t>(track_count_)};
  }
  std::span<const Motion> motions() const {
    return {motion_.data(), static_cast<std::size_t>(track_count_)};
  }
  const RoadSl& road() const { return road_; }
  Scalar lane_target() const { return road_.target_lane_offset; }  // [m]
  Scalar s_start() const { return s_start_; }  // [m]
  Scalar front() const { return front_; }      // [m] rear axle to front bumper
  Scalar rear() const { return rear_; }        // [m] rear overhang

 private:
  void project_statics(const Scene& scene, const ReferenceLine& line, Scalar s_end, Scalar static_margin);
  void project_dynamics(const Scene& scene, const ReferenceLine& line, Scalar now,
                        Scalar dynamic_margin);
  void keep_on_road(Scalar s, geometry::SlBox& box) const;
  // Grows `box` over what an oncoming or from-behind mover covers over the
  // horizon from the ego on; false: nothing of it is left (all in the target lane).
  bool occupied_sweep(const DynamicTrack& tr, geometry::SlBox& box) const;

  RoadSl road_{};
  Scalar s_start_ = 0;  // [m] the ego's path s
  Scalar ego_l_ = 0;    // [m] the ego's lateral offset
  Scalar ego_v_ = 0;    // [m/s]
  Scalar front_ = 0;    // [m]
  Scalar rear_ = 0;     // [m]
  Scalar road_margin_ = 0;     // [m] road_'s edges lie this far inside the real ones
  Scalar dynamic_margin_ = 0;  // [m] moving boxes are inflated by this
  // Static boxes (inflated in s by the ego's extents), then the dynamic ones
  // at their meeting places: the decision stage's.
  StaticVector<geometry::SlBox, Cfg::kMaxDecisionObstacles> boxes_;
  std::size_t static_count_ = 0;
  int statics_left_out_ = 0;
  std::array<DynamicTrack, Cfg::kMaxDynamicObstacles> tracks_{};
  std::array<Motion, Cfg::kMaxDynamicObstacles> motion_{};
  int track_count_ = 0;
};

}  // namespace itp::planner
