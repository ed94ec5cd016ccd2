#pragma once
// The one place that chooses the firmware's planner configuration. Every
// firmware image (image_*.cpp) builds its service for FirmwareConfig; a
// product with its own sizes adds a configuration to itp/configurations.hpp
// and names it here. Nothing in firmware_core assumes a configuration.
#include "itp/configurations.hpp"

namespace port_image {

using FirmwareConfig = ::itp::DefaultConfig;

}  // namespace port_image
