// Resampling a road to the planner's capacities (sim/road_resampling.hpp):
// edges fitted inside the true edge, checked against a dense sampling of the
// truth (not the fit's own error formula); polylines simplified to a vertex
// subset whose distance to the original is checked by dense sampling too.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "sim/box_geometry.hpp"
#include "sim/road_resampling.hpp"

using namespace hil::sim;

namespace {

using Knot = Boundary::Knot;

// An independent evaluation of a piecewise-linear l(s), constant beyond the ends.
double eval(const std::vector<Knot>& k, double s) {
  if (s <= k.front().s) return k.front().l;
  if (s >= k.back().s) return k.back().l;
  for (std::size_t i = 1; i < k.size(); ++i) {
    if (s <= k[i].s) return k[i - 1].l + (s - k[i - 1].s) / (k[i].s - k[i - 1].s) * (k[i].l - k[i - 1].l);
  }
  return k.back().l;
}

// A road edge with `n` knots: lanes that widen, narrow, step and wiggle.
std::vector<Knot> random_edge(std::mt19937& rng, int n, double spacing, double base) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<Knot> k;
  double l = base;
  for (int i = 0; i < n; ++i) {
    const double r = u(rng);
    if (r < 0.05) l += (u(rng) < 0.5 ? -3.5 : 3.5);  // a lane starts or ends
    else if (r < 0.4) l += 0.3 * (u(rng) - 0.5);     // noise of real map data
    k.push_back({spacing * i + 0.37 * u(rng), l});
  }
  std::sort(k.begin(), k.end(), [](const Knot& a, const Knot& b) { return a.s < b.s; });
  return k;
}

struct DenseCheck {
  double outside = 0.0;  // [m] largest excursion beyond the truth (must be 0)
  double narrowing = 0.0;
};

// Samples every 1 cm over [s0, s1]: how far the fit goes outside the truth
// and how much narrower it is.
DenseCheck dense_check(const std::vector<Knot>& truth, const std::vector<Knot>& fit, double s0, double s1,
                       EdgeSide side) {
  DenseCheck c;
  for (double s = s0; s <= s1 + 1e-9; s += 0.01) {
    const double gap = side == EdgeSide::kLeft ? eval(truth, s) - eval(fit, s) : eval(fit, s) - eval(truth, s);
    c.outside = std::max(c.outside, -gap);
    c.narrowing = std::max(c.narrowing, gap);
  }
  return c;
}

// Largest oscillation (max - min) of the truth over any window of length w in [s0, s1].
double oscillation(const std::vector<Knot>& truth, double s0, double s1, double w) {
  double worst = 0.0;
  for (double a = s0; a <= s1; a += 0.05) {
    double lo = 1e9, hi = -1e9;
    for (double s = a; s <= std::min(s1, a + w) + 1e-9; s += 0.05) {
      lo = std::min(lo, eval(truth, s));
      hi = std::max(hi, eval(truth, s));
    }
    worst = std::max(worst, hi - lo);
  }
  return worst;
}

}  // namespace

TEST_CASE("an edge with few knots in the window is copied exactly") {
  const std::vector<Knot> truth{{0, 5.25}, {50, 5.25}, {60, 1.75}, {200, 1.75}};
  const EdgeFit fit = fit_edge_inside(truth, 10.0, 150.0, 32, EdgeSide::kLeft);
  REQUIRE(fit.knots.size() == 4);  // both window ends plus the two knots inside
  CHECK(fit.knots.front().s == doctest::Approx(10.0));
  CHECK(fit.knots[1].s == doctest::Approx(50.0));
  CHECK(fit.knots[2].l == doctest::Approx(1.75));
  CHECK(fit.max_narrowing == doctest::Approx(0.0));
  CHECK(dense_check(truth, fit.knots, 10.0, 150.0, EdgeSide::kLeft).narrowing < 1e-12);
}

TEST_CASE("edges with more knots than the capacity: never outside the true edge, error reported exactly") {
  std::mt19937 rng(7);
  int greedy_better = 0;
  for (int trial = 0; trial < 60; ++trial) {
    CAPTURE(trial);
    const EdgeSide side = trial % 2 == 0 ? EdgeSide::kLeft : EdgeSide::kRight;
    const std::vector<Knot> truth = random_edge(rng, 150 + trial, 1.0 + 0.05 * trial, side == EdgeSide::kLeft ? 5.0 : -2.0);
    const double s0 = truth[5].s + 0.3;
    const double s1 = s0 + 152.0;
    const int budget = 8 + trial % 25;
    const EdgeFit fit = fit_edge_inside(truth, s0, s1, budget, side);
    REQUIRE(fit.knots.size() <= static_cast<std::size_t>(budget));
    CHECK(fit.knots.front().s == doctest::Approx(s0));
    CHECK(fit.knots.back().s == doctest::Approx(s1));
    const DenseCheck c = dense_check(truth, fit.knots, s0, s1, side);
    CHECK(c.outside <= 1e-9);                        // never wider than the road
    CHECK(c.narrowing <= fit.max_narrowing + 1e-9);  // the reported error is an upper bound ...
    CHECK(c.narrowing >= fit.max_narrowing - 0.02);  // ... and a tight one
    // The documented bound: the oscillation of the truth over 3 grid spacings.
    const double h = (s1 - s0) / (budget - 1);
    CHECK(fit.max_narrowing <= oscillation(truth, s0, s1, 3.0 * h) + 1e-9);
    // A uniform fit has a knot at every grid point; the greedy chords do not.
    bool uniform = fit.knots.size() == static_cast<std::size_t>(budget);
    for (std::size_t j = 0; uniform && j < fit.knots.size(); ++j) uniform = std::fabs(fit.knots[j].s - (s0 + h * static_cast<double>(j))) < 1e-6;
    greedy_better += uniform ? 0 : 1;
  }
  CHECK(greedy_better > 0);  // both fits are exercised
}

TEST_CASE("a lane that ends within the window: the edge narrows no later than the truth does") {
  // Three lanes (left edge at 8.75) until s = 100, then two (5.25); 1 m knots.
  std::vector<Knot> truth;
  for (int i = 0; i <= 300; ++i) truth.push_back({1.0 * i, i <= 100 ? 8.75 : 5.25});
  const EdgeFit fit = fit_edge_inside(truth, 20.0, 172.0, 32, EdgeSide::kLeft);
  CHECK(edge_at(fit.knots, 101.0) <= 5.25 + 1e-9);
  CHECK(dense_check(truth, fit.knots, 20.0, 172.0, EdgeSide::kLeft).outside <= 1e-9);
  // The greedy fit needs only the knots around the step: nothing narrower elsewhere.
  CHECK(edge_at(fit.knots, 50.0) == doctest::Approx(8.75));
  CHECK(edge_at(fit.knots, 150.0) == doctest::Approx(5.25));
}

TEST_CASE("polyline simplification: a vertex subset within the reported distance, dense-checked") {
  std::mt19937 rng(3);
  std::normal_distribution<double> noise(0.0, 0.02);
  for (const double radius : {30.0, 80.0, 400.0}) {
    CAPTURE(radius);
    std::vector<Point2> line;
    for (double s = 0.0; s <= 150.0; s += 0.4) {  // 376 points: 3x the default capacity
      const double phi = s / radius;
      line.push_back({radius * std::sin(phi) + noise(rng), radius - radius * std::cos(phi) + noise(rng)});
    }
    const PolylineFit fit = simplify_polyline(line, 128);
    REQUIRE(fit.points.size() <= 128);
    CHECK(fit.points.front().x == line.front().x);
    CHECK(fit.points.back().y == line.back().y);
    // Every output point is an input vertex.
    for (const Point2& p : fit.points) {
      CHECK(std::any_of(line.begin(), line.end(), [&](const Point2& q) { return q.x == p.x && q.y == p.y; }));
    }
    // Hausdorff distance by dense sampling of both polylines (5 cm steps).
    auto dense = [](const std::vector<Point2>& l) {
      std::vector<Point2> d;
      for (std::size_t i = 0; i + 1 < l.size(); ++i) {
        const double len = std::hypot(l[i + 1].x - l[i].x, l[i + 1].y - l[i].y);
        const int n = std::max(1, static_cast<int>(len / 0.05));
        for (int k = 0; k < n; ++k) {
          const double u = static_cast<double>(k) / n;
          d.push_back({l[i].x + u * (l[i + 1].x - l[i].x), l[i].y + u * (l[i + 1].y - l[i].y)});
        }
      }
      d.push_back(l.back());
      return d;
    };
    auto distance_to = [](const std::vector<Point2>& l, Point2 p) {
      double d = 1e9;
      for (std::size_t i = 0; i + 1 < l.size(); ++i) d = std::min(d, point_segment_distance(p, l[i], l[i + 1]));
      return d;
    };
    double hausdorff = 0.0;
    for (const Point2& p : dense(line)) hausdorff = std::max(hausdorff, distance_to(fit.points, p));
    for (const Point2& p : dense(fit.points)) hausdorff = std::max(hausdorff, distance_to(line, p));
    CHECK(hausdorff <= fit.max_deviation + 1e-9);
    CHECK(fit.max_deviation < 0.05);  // the noise is 2 cm: dropping points costs little more
    // No chord longer than the 5 m the planner's spline is documented for.
    for (std::size_t i = 0; i + 1 < fit.points.size(); ++i) {
      CHECK(std::hypot(fit.points[i + 1].x - fit.points[i].x, fit.points[i + 1].y - fit.points[i].y) <= 5.0 + 1e-9);
    }
  }
}

TEST_CASE("a polyline within the capacity is returned unchanged") {
  std::vector<Point2> line;
  for (int i = 0; i < 50; ++i) line.push_back({2.0 * i, 0.1 * i * i});
  const PolylineFit fit = simplify_polyline(line, 128);
  CHECK(fit.points.size() == line.size());
  CHECK(fit.max_deviation == 0.0);
}
