#pragma once
// The firmware's entry: defined by the firmware image (port/common/image_*.cpp),
// which runs the main loop of port/common/firmware_loop.hpp.
// Hosts enter it through main(); bare-metal reset handlers call it directly.
void firmware_run();
