#pragma once
// The firmware's target-independent main loop (port/common/firmware_main.cpp).
// Hosts enter it through main(); bare-metal reset handlers call it directly.
void firmware_run();
