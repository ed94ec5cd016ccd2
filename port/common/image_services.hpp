#pragma once
// The service type of each firmware image, in one place: the image sources
// (image_*.cpp) allocate it, port/mps2_an500/ram_table.cpp records sizeof()
// of its parts for `make size`.
#include "firmware_config.hpp"
#include "itp/app/firmware_service.hpp"
#include "itp/app/qp_check_service.hpp"

namespace port_image {

// Production: Ping, Diagnostics, the authenticated session and the planner.
using PlannerService = itp::app::FirmwareService<FirmwareConfig>;

// Test image: the production service plus the QP-check service.
using QpCheck = itp::app::QpCheckService<itp::qp::PathQpDims<itp::Scalar, FirmwareConfig>>;
using QpCheckImageService = itp::app::FirmwareService<FirmwareConfig, QpCheck>;

}  // namespace port_image
