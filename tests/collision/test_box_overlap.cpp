#include <doctest/doctest.h>

#include <cmath>
#include <random>

#include "itp/collision/box_overlap.hpp"

using namespace itp::collision;
using itp::geometry::box_from_rear_axle;
using itp::geometry::corners;

namespace {

OrientedBox box(double cx, double cy, double heading, double length, double width) {
  return OrientedBox{{cx, cy}, heading, length, width};
}

// Is point (x, y) inside the box? (independent: box-local coordinates)
bool contains(const OrientedBox& b, double x, double y) {
  const double dx = x - b.center.x;
  const double dy = y - b.center.y;
  const double lx = std::cos(b.heading) * dx + std::sin(b.heading) * dy;
  const double ly = -std::sin(b.heading) * dx + std::cos(b.heading) * dy;
  return std::fabs(lx) <= b.length / 2 && std::fabs(ly) <= b.width / 2;
}

// Brute force on a grid of points of box a: overlap if any lies in b, and
// the smallest distance from a's points to b's points.
std::pair<bool, double> brute(const OrientedBox& a, const OrientedBox& b, int n) {
  bool hit = false;
  double best = 1e9;
  std::vector<std::pair<double, double>> pb;
  for (int i = 0; i <= n; ++i) {
    for (int j = 0; j <= n; ++j) {
      const double u = (double(i) / n - 0.5) * b.length;
      const double v = (double(j) / n - 0.5) * b.width;
      pb.emplace_back(b.center.x + std::cos(b.heading) * u - std::sin(b.heading) * v,
                      b.center.y + std::sin(b.heading) * u + std::cos(b.heading) * v);
    }
  }
  for (int i = 0; i <= n; ++i) {
    for (int j = 0; j <= n; ++j) {
      const double u = (double(i) / n - 0.5) * a.length;
      const double v = (double(j) / n - 0.5) * a.width;
      const double x = a.center.x + std::cos(a.heading) * u - std::sin(a.heading) * v;
      const double y = a.center.y + std::sin(a.heading) * u + std::cos(a.heading) * v;
      hit = hit || contains(b, x, y);
      for (const auto& [qx, qy] : pb) {
        best = std::min(best, std::hypot(x - qx, y - qy));
      }
    }
  }
  return {hit, best};
}

}  // namespace

TEST_CASE("axis-aligned boxes: overlap and exact distance") {
  const OrientedBox a = box(0, 0, 0, 4, 2);
  CHECK(overlap(a, box(3.9, 0, 0, 4, 2)));
  CHECK_FALSE(overlap(a, box(4.1, 0, 0, 4, 2)));
  CHECK(distance(a, box(5, 0, 0, 4, 2)) == doctest::Approx(1.0));
  CHECK(distance(a, box(0, 3, 0, 4, 2)) == doctest::Approx(1.0));
  CHECK(distance(a, box(5, 3, 0, 4, 2)) == doctest::Approx(std::sqrt(2.0)));
  CHECK(distance(a, box(1, 0.5, 0.3, 4, 2)) == 0);
}

TEST_CASE("random oriented boxes agree with a brute-force point test") {
  std::mt19937 rng(31);
  std::uniform_real_distribution<double> u(0, 1);
  int overlaps = 0;
  for (int trial = 0; trial < 400; ++trial) {
    const OrientedBox a = box(0, 0, 6.3 * u(rng), 1 + 4 * u(rng), 0.5 + 2 * u(rng));
    const OrientedBox b = box(-5 + 10 * u(rng), -5 + 10 * u(rng), 6.3 * u(rng), 1 + 4 * u(rng), 0.5 + 2 * u(rng));
    const auto [hit, d_grid] = brute(a, b, 24);
    const bool sat = overlap(a, b);
    if (hit) {
      CHECK(sat);  // a sampled point inside b proves overlap
    }
    const double d = distance(a, b);
    CHECK(d == doctest::Approx(overlap(b, a) ? 0.0 : d).epsilon(1e-12));  // symmetric overlap
    CHECK(distance(b, a) == doctest::Approx(d).epsilon(1e-9));
    if (!sat) {
      CHECK(d > 0);
      CHECK(d <= d_grid + 1e-9);                 // exact distance is a lower bound of the sampled one
      CHECK(d >= d_grid - 0.25);                 // and close to it at this grid density
    }
    overlaps += sat ? 1 : 0;
  }
  CHECK(overlaps > 20);
  CHECK(overlaps < 380);
}

TEST_CASE("the ego's box sits ahead of its rear axle") {
  const OrientedBox b = box_from_rear_axle({10, 5}, M_PI / 2, 4.8, 1.9, 1.0);
  CHECK(b.center.x == doctest::Approx(10));
  CHECK(b.center.y == doctest::Approx(5 + 1.4));
}

TEST_CASE("corners run counter-clockwise from the front-right") {
  // A box heading +y (90 deg), centre (1, 2), 4 long and 2 wide: its front
  // is at y = 4, its right side at x = 2.
  const auto c = corners(box(1, 2, M_PI / 2, 4, 2));
  const double want[4][2] = {{2, 4}, {0, 4}, {0, 0}, {2, 0}};
  for (std::size_t i = 0; i < 4; ++i) {
    CHECK(c[i].x == doctest::Approx(want[i][0]));
    CHECK(c[i].y == doctest::Approx(want[i][1]));
  }
}
