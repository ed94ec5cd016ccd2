#pragma once
// The one place that chooses the firmware's planner configuration. Every
// firmware image (image_*.cpp) builds its service for FirmwareConfig: the
// default configuration, or the one the build names for this image
// (ITP_FIRMWARE_CONFIG, set by itp_set_firmware_config in port/CMakeLists.txt:
// RoadConfig for the road image). A product with its own sizes adds a
// configuration to itp/configurations.hpp and names it there. Nothing in
// firmware_core assumes a configuration.
#include "itp/configurations.hpp"

#ifndef ITP_FIRMWARE_CONFIG
#define ITP_FIRMWARE_CONFIG DefaultConfig
#endif

namespace port_image {

using FirmwareConfig = ::itp::ITP_FIRMWARE_CONFIG;

}  // namespace port_image
