#pragma once
// The one SL rectangle: an obstacle's footprint in the Frenet frame of the
// reference line, already inflated by its margin (paper 1.1, "SL block").
// A dynamic obstacle's box is where it is at its meeting time with the ego.
#include <cstdint>

#include "itp/config.hpp"

namespace itp::geometry {

struct SlBox {
  Scalar s_min = 0;  // [m]
  Scalar s_max = 0;  // [m]
  Scalar l_min = 0;  // [m]
  Scalar l_max = 0;  // [m]
  std::int32_t obstacle_id = 0;  // the obstacle it stands for (0: none)
  bool dynamic = false;          // a moving obstacle's box
};

}  // namespace itp::geometry
