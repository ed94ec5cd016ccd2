// The test firmware image: the production service plus the QP-check service
// (a second copy of the path QP's memory), which the QEMU and host QP
// agreement tests use (hil_sim qp-check). Never flashed on a product.
#include <cstddef>

#include "firmware_config.hpp"
#include "firmware_loop.hpp"
#include "itp/app/firmware_service.hpp"
#include "itp/app/qp_check_service.hpp"
#include "port/firmware_run.hpp"

namespace {

using QpCheck = itp::app::QpCheckService<itp::qp::PathQpDims<itp::Scalar, port_image::FirmwareConfig>>;
using Service = itp::app::FirmwareService<port_image::FirmwareConfig, QpCheck>;
alignas(Service) std::byte g_service_storage[sizeof(Service)];

}  // namespace

void firmware_run() { port_image::run<Service>(g_service_storage, ITP_BUILD_ID); }
