// The RAM breakdown of the firmware's one big static object, for
// tools/size_report.py (`make size`, docs/memory.md). The service lives in a
// single .bss symbol, so the ELF's symbol table cannot split it; this table
// records sizeof() of its parts as the Cortex-M7 compiler lays them out, in a
// section the linker script keeps out of memory (INFO: in the file only).
// Built into every planner image (port/CMakeLists.txt): the production
// images' tables (default and road configuration), and the test image's with
// its QP-check row (ITP_IMAGE_QP_CHECK). Also the compile-time half of the
// default production image's RAM budget: its service alone must fit.
#include <cstdint>

#include "../common/image_services.hpp"
#include "itp/link/frame.hpp"
#include "itp/link/segments.hpp"

namespace {

#if defined(ITP_IMAGE_QP_CHECK)
using Service = port_image::QpCheckImageService;
#else
using Service = port_image::PlannerService;
#endif
using Cfg = port_image::FirmwareConfig;
using Planner = itp::planner::BasicPlanner<Cfg>;

struct RamEntry {
  char name[44];        // "module" or "module.part", NUL-padded
  std::uint32_t bytes;  // sizeof on this target
};

constexpr std::uint32_t size(unsigned long bytes) { return static_cast<std::uint32_t>(bytes); }

constexpr std::uint32_t kInboxBytes = size(sizeof(Service::RequestInbox));
constexpr std::uint32_t kOutboxBytes = size(sizeof(itp::link::Outbox<Service::kMaxReplyBytes>));
constexpr std::uint32_t kControlBytes =
    size(sizeof(itp::link::Outbox<itp::link::kSegmentReportBytes>) + itp::link::kMaxWireFrameBytes);
constexpr std::uint32_t kDecoderBytes = size(sizeof(itp::link::FrameDecoder));

#if defined(ITP_RAM_BUDGET_BYTES)
// ITP_RAM_BUDGET_BYTES: .data + .bss + stack, from port/mps2_an500/ram_budget.ld.
static_assert(sizeof(Service) <= ITP_RAM_BUDGET_BYTES,
              "the firmware service alone exceeds the RAM budget (port/mps2_an500/ram_budget.ld)");
#endif

}  // namespace

// Parts nest by name: "service.planner.decision_stage.coarse_qp" is inside
// "service.planner.decision_stage", which is inside "service.planner";
// size_report.py prints each parent's remainder as "other".
extern "C" __attribute__((section(".itp_ram_table"), used)) const RamEntry itp_ram_table[] = {
    {"service", size(sizeof(Service))},
    {"service.planner", size(sizeof(Planner))},
    {"service.planner.qp_arena", size(sizeof(itp::qp::PlannerQpArenas<Cfg>))},
    {"service.planner.decision_stage", size(sizeof(Planner::DecisionStage))},
    {"service.planner.decision_stage.coarse_qp", size(sizeof(itp::decision::BasicCoarseEvaluator<Cfg>))},
    {"service.planner.path_qp", size(sizeof(Planner::PathOptimizer))},
    {"service.planner.st_graph", size(sizeof(Planner::StGraph))},
    {"service.planner.speed_qp", size(sizeof(Planner::SpeedOptimizer))},
    {"service.planner.speed_bounds", size(sizeof(Planner::SpeedBounds))},
    {"service.planner.path_speed_results", size(sizeof(Planner::PathResult) + sizeof(Planner::SpeedResult))},
    {"service.planner.reference_line",
     size(sizeof(Planner::ReferenceLine) +
          (Cfg::kShareQpStorage ? 0 : sizeof(itp::geometry::BasicSmoothingSplineWorkspace<Cfg>)))},
    {"service.planner.sl_scene", size(sizeof(itp::planner::BasicSlScene<Cfg>))},
    {"service.planner.previous_plans", size(2 * sizeof(Planner::Plan))},
    {"service.scene", size(sizeof(itp::scene::BasicScene<Cfg>))},
    {"service.link", kDecoderBytes + kInboxBytes + kOutboxBytes + kControlBytes},
    {"service.link.inbox", kInboxBytes},
    {"service.link.outbox", kOutboxBytes},
    {"service.link.decoder", kDecoderBytes},
    {"service.link.control_tx", kControlBytes},
    {"service.secure_channel", size(sizeof(itp::link::SecureChannel))},
#if defined(ITP_IMAGE_QP_CHECK)
    {"service.qp_check", size(sizeof(port_image::QpCheck))},
#endif
};
