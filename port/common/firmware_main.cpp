// Hosts enter the firmware through main(); bare-metal reset handlers call
// firmware_run() directly. The image (image_*.cpp) defines firmware_run().
#include "port/firmware_run.hpp"

int main() {
  firmware_run();
  return 0;
}
