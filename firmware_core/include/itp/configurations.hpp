#pragma once
// The configurations the firmware library is compiled for. Each stage's
// .cpp explicitly instantiates its templates for every entry of
// ITP_FOR_EACH_CONFIG, so a product adds its own configuration here (one
// line) and gets the whole planner for it; the linker's --gc-sections drops
// the instantiations a firmware image does not use.
#include "itp/config.hpp"

namespace itp {

// A smaller planner, for a city ECU with less RAM: 60 m and 5 s horizons,
// 4 static + 2 dynamic obstacles, fewer and shorter QP blocks. The tests
// plan with it to prove that nothing in the library assumes the default sizes.
struct CompactSizes : DefaultSizes {
  static constexpr Scalar kPathLength = Scalar(60);
  static constexpr Scalar kMaxPathLength = Scalar(120);
  static constexpr Scalar kSpeedHorizon = Scalar(5);
  static constexpr int kMaxReferencePoints = 64;
  static constexpr int kMaxBoundaryPoints = 8;
  static constexpr int kMaxRoadCuts = 4;
  static constexpr int kMaxStaticObstacles = 4;
  static constexpr int kMaxDynamicObstacles = 2;
  static constexpr int kMaxPredictionSamples = 60;
  static constexpr int kKeptDecisions = 8;
  static constexpr int kMaxTreeNodes = 512;
  static constexpr int kCoarseSamples = 12;
  static constexpr int kPathBlocks = 12;
  static constexpr int kSpeedBlocks = 10;
  static constexpr int kMaxPlannerIterations = 4;
  static constexpr int kMaxPathSolvesPerCycle = 8;
  static constexpr bool kShareQpStorage = true;  // its QPs share one storage
  static constexpr unsigned long kPlannerBytesBudget = 94208;  // 92 KiB (91 872 B)
};
using CompactConfig = Configuration<CompactSizes>;

// The default sizes for an ECU where RAM is tighter than time: the coarse,
// path and speed QPs share one problem + workspace (kShareQpStorage). The
// float image plans with it (docs/memory.md, "The float image").
struct LowRamSizes : DefaultSizes {
  static constexpr bool kShareQpStorage = true;
  // Its QP work per cycle. A solve after another stage's claim rebuilds,
  // factors and reloads its working set, so a unit costs more than in
  // DefaultSizes' fit; the units are still charged at DefaultSizes' costs,
  // which cover every measured cycle's QP total x 1.2 (worst 0.97 of what is
  // charged; the float image under QEMU, tools/wcet_costs_f32.json), and 20 M
  // keeps the measured maximum within 15 M (docs/performance.md, "The float image").
  static constexpr int kQpWorkPerCycle = 20000;  // [k instructions]
  static constexpr unsigned long kPlannerBytesBudget = 200704;  // 196 KiB (197 984 B in double)
};
using LowRamConfig = Configuration<LowRamSizes>;

// A road ECU fed by sensor fusion: its object list, up to 32 static and 32
// moving objects, arrives whole. The decision stage keeps the default's
// envelope (10 + 5: the most relevant, planner/sl_scene); the ST graph and
// the collision check see every object. Predictions at 0.2 s steps over 8 s
// (every 0.1 s they would not fit one link message).
struct RoadSizes : DefaultSizes {
  static constexpr int kMaxStaticObstacles = 32;
  static constexpr int kMaxDynamicObstacles = 32;
  static constexpr int kMaxPredictionSamples = 40;
  static constexpr unsigned long kPlannerBytesBudget = 495616;  // 484 KiB (493 040 B)
};
using RoadConfig = Configuration<RoadSizes>;

}  // namespace itp

// X(config type) for every configuration the library is built for.
#define ITP_FOR_EACH_CONFIG(X) \
  X(::itp::DefaultConfig)      \
  X(::itp::CompactConfig)      \
  X(::itp::LowRamConfig)       \
  X(::itp::RoadConfig)
