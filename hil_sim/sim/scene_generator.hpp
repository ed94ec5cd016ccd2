#pragma once
// Seeded, reproducible generator of closed-loop scene/1 worlds covering the
// paper's test envelope (Table 1): half-enclosed road, 1-10 static and 1-5
// dynamic obstacles. Archetypes and solvability rules: docs/simulation.md.
#include <cstdint>
#include <string_view>
#include <vector>

#include "sim/world.hpp"

namespace hil::sim {

struct GeneratorConfig {
  double duration = 12.0;         // [s] closed-loop run length, trajectories cover it
  double sample_dt = 0.1;         // [s] dynamic obstacle trajectory step
  double ref_spacing = 2.0;       // [m] reference line sampling
  double lane_width = 3.5;        // [m]
  double max_brake = 3.0;         // [m/s^2] comfortable stop used by the solvability rules
  double max_lat_acc = 2.5;       // [m/s^2] road radius >= v_limit^2 / this (and >= 50 m)
  double map_end_probability = 0.12;  // the reference line (the road) ends ahead of the ego
  int min_static = 1, max_static = 10;
  int min_dynamic = 1, max_dynamic = 5;
};

// Archetype names (also written as obstacle "kind" and scene "tags").
namespace archetype {
inline constexpr std::string_view kParkedCar = "parked_car";
inline constexpr std::string_view kDebris = "debris";
inline constexpr std::string_view kSlowLeader = "slow_leader";
inline constexpr std::string_view kAdjacentCar = "adjacent_car";
inline constexpr std::string_view kCutIn = "cut_in";
inline constexpr std::string_view kOncoming = "oncoming";
inline constexpr std::string_view kPedestrian = "pedestrian";
inline constexpr std::string_view kCyclist = "cyclist";
inline constexpr std::string_view kCutInBrake = "cut_in_brake";
inline constexpr std::string_view kOvertaker = "overtaker";
inline constexpr std::string_view kMapEnd = "map_end";  // scene tag: the road ends ahead
}  // namespace archetype

// Scene `index` of the suite with this seed; name "paper-NNNN". Pure function
// of (seed, index, config): no global state, bit-identical on every run.
World generate_scene(std::uint64_t seed, int index, const GeneratorConfig& config = {});

// Scenes 0 .. count-1 of generate_scene(seed, i).
std::vector<World> default_suite(int count, std::uint64_t seed, const GeneratorConfig& config = {});

}  // namespace hil::sim
