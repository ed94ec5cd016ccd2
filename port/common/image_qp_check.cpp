// The test firmware image: the production service plus the QP-check service
// (a second copy of the path QP's memory), which the QEMU and host QP
// agreement tests use (hil_sim qp-check). Never flashed on a product.
#include <cstddef>

#include "firmware_loop.hpp"
#include "image_services.hpp"
#include "port/firmware_run.hpp"

namespace {

using Service = port_image::QpCheckImageService;
alignas(Service) std::byte g_service_storage[sizeof(Service)];

}  // namespace

void firmware_run() { port_image::run<Service>(g_service_storage, ITP_BUILD_ID); }
