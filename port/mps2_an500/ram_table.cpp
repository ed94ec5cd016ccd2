// The RAM breakdown of the firmware's one big static object, for
// tools/size_report.py (`make size`, docs/memory.md). The service lives in a
// single .bss symbol, so the ELF's symbol table cannot split it; this table
// records sizeof() of its parts as the Cortex-M7 compiler lays them out, in a
// section the linker script keeps out of memory (INFO: in the file only).
// Also the compile-time half of the RAM budget: the service alone must fit.
#include <cstdint>

#include "itp/app/firmware_service.hpp"
#include "itp/link/frame.hpp"

namespace {

using Service = itp::app::FirmwareService;
using Cfg = Service::Config;
using Planner = itp::planner::BasicPlanner<Cfg>;
using QpDims = Service::TargetQpDims;

struct RamEntry {
  char name[44];        // "module" or "module.part", NUL-padded
  std::uint32_t bytes;  // sizeof on this target
};

constexpr std::uint32_t size(unsigned long bytes) { return static_cast<std::uint32_t>(bytes); }

// ITP_RAM_BUDGET_BYTES: .data + .bss + stack, from port/mps2_an500/ram_budget.ld.
static_assert(sizeof(Service) <= ITP_RAM_BUDGET_BYTES,
              "the firmware service alone exceeds the RAM budget (port/mps2_an500/ram_budget.ld)");

}  // namespace

// Parts nest by name: "planner.decision_stage.coarse_qp" is inside
// "planner.decision_stage", which is inside "planner"; size_report.py prints
// each parent's remainder as ".other".
extern "C" __attribute__((section(".itp_ram_table"), used)) const RamEntry itp_ram_table[] = {
    {"service", size(sizeof(Service))},
    {"service.planner", size(sizeof(Planner))},
    {"service.planner.decision_stage", size(sizeof(Planner::DecisionStage))},
    {"service.planner.decision_stage.coarse_qp", size(sizeof(itp::decision::BasicCoarseEvaluator<Cfg>))},
    {"service.planner.path_qp", size(sizeof(Planner::PathOptimizer))},
    {"service.planner.st_graph", size(sizeof(Planner::StGraph))},
    {"service.planner.speed_qp", size(sizeof(Planner::SpeedOptimizer))},
    {"service.planner.speed_bounds", size(sizeof(Planner::SpeedBounds))},
    {"service.planner.path_speed_results", size(sizeof(Planner::PathResult) + sizeof(Planner::SpeedResult))},
    {"service.planner.reference_line",
     size(sizeof(Planner::ReferenceLine) + sizeof(itp::geometry::BasicSmoothingSplineWorkspace<Cfg>))},
    {"service.planner.sl_scene", size(sizeof(itp::planner::BasicSlScene<Cfg>))},
    {"service.planner.previous_plan", size(sizeof(Planner::Plan))},
    {"service.qp_storage",
     size(sizeof(itp::qp::QpProblem<QpDims>) + sizeof(itp::qp::QpWorkspace<QpDims>) +
          sizeof(itp::qp::QpResult<QpDims>))},
    {"service.scene", size(sizeof(itp::scene::BasicScene<Cfg>))},
    {"service.plan", size(sizeof(itp::planner::BasicPlan<Cfg>))},
    {"service.link_buffers",
     size(sizeof(itp::link::FrameDecoder) + itp::config::kMaxPayloadBytes + itp::link::kMaxWireFrameBytes)},
};
