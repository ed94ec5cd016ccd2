#pragma once
// The ego vehicle's geometry and its dynamic limits (scene/1 "ego"), and the
// footprint they give at a rear-axle pose.
#include "itp/config.hpp"
#include "itp/geometry/oriented_box.hpp"

namespace itp::scene {

struct VehicleGeometry {
  Scalar length = Scalar(4.8);     // [m] bumper to bumper
  Scalar width = Scalar(1.9);      // [m]
  Scalar wheelbase = Scalar(2.8);  // [m] rear to front axle
};

// Dynamic limits. scene/1 carries them only as the optional "ego.limits"
// object; the defaults are those of a passenger car in comfortable driving.
struct VehicleLimits {
  Scalar a_min = Scalar(-6);          // [m/s^2] strongest braking (< 0)
  Scalar a_max = Scalar(3);           // [m/s^2] strongest acceleration (> 0)
  Scalar lat_acc_max = Scalar(3);     // [m/s^2] |v^2 kappa| bound
  Scalar kappa_max = Scalar(0.2);     // [1/m] |kappa| bound (radius 5 m)
};

// Rear axle to rear bumper, with the axles centred in the body. [m]
inline Scalar rear_overhang(const VehicleGeometry& g) { return Scalar(0.5) * (g.length - g.wheelbase); }
// Rear axle to front bumper. [m]
inline Scalar front_reach(const VehicleGeometry& g) { return g.length - rear_overhang(g); }

// The ego's footprint with its rear axle at `rear_axle`, heading `heading`.
inline geometry::OrientedBox footprint(const VehicleGeometry& g, geometry::Point2 rear_axle, Scalar heading) {
  return geometry::box_from_rear_axle(rear_axle, heading, g.length, g.width, rear_overhang(g));
}

}  // namespace itp::scene
