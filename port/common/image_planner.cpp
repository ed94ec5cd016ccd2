// The production firmware image: Ping, Diagnostics, the authenticated session
// and the planner, for the configuration chosen in firmware_config.hpp.
#include <cstddef>

#include "firmware_loop.hpp"
#include "image_services.hpp"
#include "port/firmware_run.hpp"

namespace {

using Service = port_image::PlannerService;
alignas(Service) std::byte g_service_storage[sizeof(Service)];

}  // namespace

void firmware_run() { port_image::run<Service>(g_service_storage, ITP_BUILD_ID); }
