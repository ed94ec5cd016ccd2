#pragma once
// The inputs of every stage of one cycle, filled once from the start state
// (init_sl, init_st), the scene's vehicle and road, and the horizon: the
// convex space and coarse QP (1.1), the path QP (1.2), the ST graph and the
// speed QP (1.3). The iteration changes only what it decides per step (the
// curvature bound, the stop position, the acceleration bounds).
#include "itp/decision/coarse_evaluation.hpp"
#include "itp/decision/convex_space.hpp"
#include "itp/path/path_optimizer.hpp"
#include "itp/planner/curvature_bounds.hpp"
#include "itp/planner/planner_settings.hpp"
#include "itp/scene/scene.hpp"
#include "itp/speed/speed_optimizer.hpp"
#include "itp/speed/st_graph.hpp"

namespace itp::planner {

// Where the cycle starts, in the Frenet frame: the ego state converted
// (geometry::frenet_state_of) or the previous plan's point at this time.
struct StartState {
  Scalar s = 0;                    // [m]
  Scalar l = 0, dl = 0, ddl = 0;   // [m], [-], [1/m]
  Scalar v = 0, a = 0;             // [m/s], [m/s^2] along s
  Scalar stitched_age = -1;        // [s] age of the previous plan it was stitched from; < 0: not stitched
};

template <class Cfg>
struct BasicCycleInputs {
  decision::ConvexSpaceParams convex;
  decision::BasicCoarseInput<Cfg> coarse;
  path::BasicPathInput<Cfg> path;
  speed::BasicStParams<Cfg> st;
  speed::BasicSpeedInput<Cfg> speed;
};

// `length`: the SL horizon; `stop_s`: where the front must stop when nothing
// else stops it (the end of the map less the stop margin).
template <class Cfg>
BasicCycleInputs<Cfg> make_cycle_inputs(const StartState& start, const scene::BasicScene<Cfg>& scene,
                                        const decision::MotionLimits& limits,
                                        const BasicCurvatureBounds<Cfg>& bounds,
                                        const PlannerSettings& settings, Scalar front, Scalar rear,
                                        Scalar length, Scalar stop_s) {
  BasicCycleInputs<Cfg> in;
  const Scalar width = scene.ego.geometry.width;
  const Scalar l_target = scene.road.target_lane_offset;
  in.st.s0 = start.s;
  in.st.v0 = start.v;
  in.st.a0 = start.a;
  in.st.front = front;
  in.st.rear = rear;
  in.st.half_width = Scalar(0.5) * width;
  in.st.limits = limits;
  in.st.comfort_decel = settings.comfort_decel;
  in.st.kappa_ref = &bounds.reference;
  in.st.stop_s = stop_s;
  in.st.path_end = start.s + length;
  in.convex.s_start = start.s;
  in.convex.s_end = start.s + length;
  in.convex.vehicle_width = width;
  in.convex.ego_l = start.l;
  in.coarse.l_init = start.l;
  in.coarse.v_init = start.v;
  in.coarse.l_ref = l_target;
  in.coarse.vehicle_width = width;
  in.coarse.stop_margin = settings.stop_margin;
  in.coarse.limits = limits;
  in.coarse.kappa_ref = &bounds.reference;
  in.path.s0 = start.s;
  in.path.length = length;
  in.path.l0 = start.l;
  in.path.dl0 = start.dl;
  in.path.ddl0 = start.ddl;
  in.path.l_target = l_target;
  in.path.vehicle_width = width;
  in.path.front_reach = front;
  in.path.rear_reach = rear;
  in.path.kappa_max = limits.kappa_max;
  in.path.kappa_ref = &bounds.reference;
  in.speed.v0 = start.v;
  in.speed.a0 = start.a;
  in.speed.a_min = limits.a_min;
  in.speed.a_max = limits.a_max;
  return in;
}

}  // namespace itp::planner
