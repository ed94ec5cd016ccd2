// CommonRoad -> World (sim/commonroad_world.hpp): the development scenarios
// checked against independent geometry on the raw XML bounds (the reference
// line is the lanelet centre, the road never wider than the lanelets), and
// small hand-written scenarios for shapes, states, the speed limit, the
// route's choices and every error.
#include <doctest/doctest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <sstream>
#include <string>

#include "commonroad_xml.hpp"
#include "formats/commonroad.hpp"
#include "sim/box_geometry.hpp"
#include "sim/commonroad_world.hpp"
#include "sim/scene_files.hpp"

using namespace hil::sim;
namespace cr = hil::formats::commonroad;
namespace x = commonroad_xml;

namespace {

std::string data_path(const std::string& name) { return std::string(ITP_COMMONROAD_DATA_DIR) + "/" + name; }

std::string read_file(const std::string& name) {
  std::ifstream in(data_path(name), std::ios::binary);
  REQUIRE_MESSAGE(in.good(), name);
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

World import_ok(const std::string& xml, const CommonRoadOptions& opt = {}) {
  const CommonRoadImport r = import_commonroad(xml, opt);
  REQUIRE_MESSAGE(r.world.has_value(), r.error);
  return *r.world;
}

std::string import_error(const std::string& xml, const CommonRoadOptions& opt = {}) {
  const CommonRoadImport r = import_commonroad(xml, opt);
  REQUIRE_FALSE(r.world.has_value());
  return r.error;
}

// Independent geometry on the raw bounds: the distance of p to a polyline, and
// point in polygon by the crossing number.
double distance_to(const std::vector<cr::Vec2>& line, Point2 p) {
  double d = 1e18;
  for (std::size_t i = 0; i + 1 < line.size(); ++i) {
    d = std::min(d, point_segment_distance(p, {line[i].x, line[i].y}, {line[i + 1].x, line[i + 1].y}));
  }
  return d;
}

bool inside_lanelet(const cr::Lanelet& l, Point2 p) {
  std::vector<cr::Vec2> poly = l.left_bound;
  poly.insert(poly.end(), l.right_bound.rbegin(), l.right_bound.rend());
  int crossings = 0;
  for (std::size_t i = 0; i < poly.size(); ++i) {
    const cr::Vec2& a = poly[i];
    const cr::Vec2& b = poly[(i + 1) % poly.size()];
    if ((a.y > p.y) != (b.y > p.y) && p.x < a.x + (p.y - a.y) / (b.y - a.y) * (b.x - a.x)) ++crossings;
  }
  return crossings % 2 == 1;
}

bool vehicle_lane(const cr::Lanelet& l) {
  for (const std::string& t : l.types) {
    if (t == "sidewalk" || t == "crosswalk" || t == "bicycleLane") return false;
  }
  return true;
}

// The road as the simulator judges it (a point is on the road when its
// projection onto the reference line, project_to_polyline, has right(s) <= l
// <= left(s)) must lie inside the lanelets, over the route but its first and
// last metre (where the map ends, lanelets end obliquely and no edge is
// defined: docs/commonroad.md). Candidate points: every 0.5 m in
// s, in 2 cm steps across a 0.5 m band around each edge and every 0.5 m
// between; those the simulator calls on the road (1 mm inside) are checked
// against the raw lanelet polygons (vehicle lanes). And every reference point
// lies in a lanelet, halfway between its bounds.
struct RoadCheck {
  int points = 0;       // candidates the simulator calls on the road
  int outside_road = 0;
  double worst_centre_offset = 0.0;  // [m] |d(left bound) - d(right bound)| / 2
  int reference_outside = 0;
  std::string first_failures;  // for the message
};

bool on_lanelet_or_edge(const cr::Lanelet& l, Point2 p) {
  const std::vector<cr::Vec2> start{l.left_bound.front(), l.right_bound.front()};
  const std::vector<cr::Vec2> end{l.left_bound.back(), l.right_bound.back()};
  return inside_lanelet(l, p) || distance_to(l.left_bound, p) < 1e-6 || distance_to(l.right_bound, p) < 1e-6 ||
         distance_to(start, p) < 1e-6 || distance_to(end, p) < 1e-6;
}

RoadCheck check_road(const World& w, const cr::Scenario& sc) {
  RoadCheck c;
  const std::vector<double> arc = polyline_arc_lengths(w.reference_line);
  // Neighbouring lanelets of recorded maps do not always share their bounds
  // exactly: slivers up to ~7 mm wide lie between them (US-101). A point within
  // 1 cm of a vehicle lanelet counts as on it.
  auto on_road = [&](Point2 p) {
    for (const cr::Lanelet& l : sc.lanelets) {
      if (vehicle_lane(l) && on_lanelet_or_edge(l, p)) return true;
    }
    for (const cr::Lanelet& l : sc.lanelets) {
      if (vehicle_lane(l) && (distance_to(l.left_bound, p) < 0.01 || distance_to(l.right_bound, p) < 0.01)) return true;
    }
    return false;
  };
  for (double s = 0.0; s <= arc.back(); s += 0.5) {
    const double left = w.road.left_boundary.at(s);
    const double right = w.road.right_boundary.at(s);
    std::vector<double> ls;
    for (double l = -0.25; l <= 0.25; l += 0.02) {
      ls.push_back(right + l);
      ls.push_back(left + l);
    }
    for (double l = right + 0.5; l < left - 0.5; l += 0.5) ls.push_back(l);
    for (const double l : ls) {
      const Pose p = polyline_pose(w.reference_line, arc, s, l);
      const PolylineProjection pr = project_to_polyline(w.reference_line, p.x, p.y);
      if (pr.s < 1.0 || pr.s > arc.back() - 1.0) continue;
      if (pr.l > w.road.left_boundary.at(pr.s) - 1e-3 || pr.l < w.road.right_boundary.at(pr.s) + 1e-3) continue;
      ++c.points;
      if (!on_road({p.x, p.y}) && ++c.outside_road <= 5) {
        c.first_failures += fmt::format(" (s {:.2f}, l {:.2f} of [{:.2f}, {:.2f}])", pr.s, pr.l,
                                        w.road.right_boundary.at(pr.s), w.road.left_boundary.at(pr.s));
      }
    }
  }
  for (const Point2& p : w.reference_line) {
    double best = 1e18;
    for (const cr::Lanelet& l : sc.lanelets) {
      if (!on_lanelet_or_edge(l, p)) continue;
      best = std::min(best, 0.5 * std::fabs(distance_to(l.left_bound, p) - distance_to(l.right_bound, p)));
    }
    if (best > 1e17) {
      ++c.reference_outside;
      c.first_failures += fmt::format(" reference point ({:.2f}, {:.2f}) on no lanelet", p.x, p.y);
    } else {
      c.worst_centre_offset = std::max(c.worst_centre_offset, best);
    }
  }
  return c;
}

struct DevFile {
  const char* name;
  std::size_t dynamic_obstacles;
};
const DevFile kDevFiles[] = {{"ZAM_Tutorial-1_1_T-1.xml", 1},
                             {"DEU_A9-3_1_T-1.xml", 9},
                             {"FRA_Anglet-1_1_T-1.xml", 8},
                             {"USA_Peach-4_8_T-1.xml", 9},
                             {"USA_US101-3_3_T-1.xml", 12}};

}  // namespace

TEST_CASE("the development scenarios: reference line on the lanelet centre, road inside the lanelets, state and obstacles as in the file") {
  for (const DevFile& f : kDevFiles) {
    for (const bool opposite : {false, true}) {
      const std::string name = f.name;
      CAPTURE(name);
      CAPTURE(opposite);
      const std::string xml = read_file(f.name);
      const cr::ReadResult read = cr::read_commonroad(xml);
      REQUIRE(read.scenario.has_value());
      const cr::Scenario& sc = *read.scenario;
      CommonRoadOptions opt;
      opt.opposite_lanes = opposite;
      const World w = import_ok(xml, opt);

      // scene/1 as written reads back.
      const SceneParseResult again = parse_scene_text(scene_to_text(w));
      REQUIRE_MESSAGE(again.world.has_value(), again.error);
      CHECK(again.world->reference_line.size() == w.reference_line.size());

      const RoadCheck road = check_road(w, sc);
      CHECK(road.points > 2000);
      CHECK_MESSAGE(road.outside_road == 0, road.first_failures);  // never wider than the lanelets
      CHECK(road.reference_outside == 0);   // every reference point lies on a lanelet
      // ... halfway between its bounds (CommonRoad's centre pairs the bounds' vertices:
      // on the tight urban curves of the dev set that is up to 6 cm from equidistant).
      CHECK(road.worst_centre_offset < 0.1);

      // The ego: CommonRoad's position is the vehicle centre = our box centre.
      const cr::State& init = sc.planning_problems.front().initial;
      const OrientedBox ego = ego_box(w.ego);
      CHECK(ego.cx == doctest::Approx(init.position.x).epsilon(1e-12));
      CHECK(ego.cy == doctest::Approx(init.position.y).epsilon(1e-12));
      CHECK(w.ego.heading == doctest::Approx(wrap_angle(init.orientation)));
      CHECK(w.ego.v == doctest::Approx(init.velocity.value_or(-1)));
      CHECK(std::fabs(project_to_polyline(w.reference_line, ego.cx, ego.cy).l) < 1.75);

      // Every obstacle, every state, at the file's time step.
      CHECK(w.static_obstacles.empty());
      REQUIRE(w.dynamic_obstacles.size() == f.dynamic_obstacles);
      for (std::size_t i = 0; i < w.dynamic_obstacles.size(); ++i) {
        const cr::Obstacle& o = sc.obstacles[i];
        const DynamicObstacle& d = w.dynamic_obstacles[i];
        CHECK(d.id == o.id);
        REQUIRE(d.trajectory.size() == o.trajectory.size() + 1);
        CHECK(d.trajectory.back().t == doctest::Approx(static_cast<double>(o.trajectory.back().time_step) * sc.time_step));
        CHECK(d.length == doctest::Approx(o.shape[0].length));
        CHECK(d.width == doctest::Approx(o.shape[0].width));
        CHECK(d.trajectory.front().x == doctest::Approx(o.initial.position.x));
      }
      CHECK(w.duration.value_or(0) > 2.0);
      CHECK(w.duration.value_or(0) <= kCommonRoadMaxDuration);
    }
  }
}

TEST_CASE("the ZAM tutorial: the car's trajectory at 0.1 s steps, the ego's lanelet and the default speed limit") {
  const World w = import_ok(read_file("ZAM_Tutorial-1_1_T-1.xml"));
  CHECK(w.name == "ZAM_Tutorial-1_1_T-1");
  REQUIRE(w.dynamic_obstacles.size() == 1);
  const DynamicObstacle& car = w.dynamic_obstacles[0];
  CHECK(car.id == 42);
  CHECK(car.kind == "car");
  CHECK(car.trajectory[0].x == doctest::Approx(2.25));
  CHECK(car.trajectory[0].y == doctest::Approx(3.5));
  CHECK(car.trajectory[0].v == doctest::Approx(23.0));
  CHECK(car.trajectory[10].t == doctest::Approx(1.0));
  CHECK(w.duration.value_or(0) == doctest::Approx(4.0));  // the goal's time interval ends at step 40
  // No sign: 50 km/h raised to the fastest initial speed (the car's 23 m/s).
  CHECK(w.road.speed_limit == doctest::Approx(23.0));
  CHECK(w.road.lane_width == doctest::Approx(3.5).epsilon(1e-3));
}

TEST_CASE("shapes: circles and polygons as their bounding boxes, rectangles with a centre and orientation offset") {
  const double pi = std::numbers::pi;
  const double c30 = std::cos(pi / 6), s30 = std::sin(pi / 6);
  auto rotated = [&](double u, double v) { return x::point(40 + c30 * u - s30 * v, 1.5 + s30 * u + c30 * v); };
  const std::string body =
      x::lanelet(1, 0, 200, 0, 3.5) + x::planning_problem(100, 10, 1.75, 0, 10) +
      // Circle r = 1 with its centre 2 m ahead (local x), the obstacle turned 90 deg: the box sits 2 m to its left.
      "<staticObstacle id=\"1\"><type>unknown</type><shape><circle><radius>1</radius><center><x>2</x><y>0</y>"
      "</center></circle></shape><initialState>" + x::state(30, 1.75, pi / 2, 0, 0) + "</initialState></staticObstacle>\n" +
      // A 3 x 1 rectangle given as a polygon turned by 30 deg: its box exactly.
      "<staticObstacle id=\"2\"><type>unknown</type><shape><polygon>" + rotated(-1.5, -0.5) + rotated(1.5, -0.5) +
      rotated(1.5, 0.5) + rotated(-1.5, 0.5) + "</polygon></shape><initialState>" + x::state(0, 0, 0, 0, 0) +
      "</initialState></staticObstacle>\n" +
      // A moving 4 x 2 rectangle turned 90 deg and 1 m ahead of the state: aligned with the motion.
      "<dynamicObstacle id=\"3\"><type>car</type><shape><rectangle><length>4</length><width>2</width>"
      "<orientation>1.5707963267948966</orientation><center><x>1</x><y>0</y></center></rectangle></shape>"
      "<initialState>" + x::state(60, 1.75, 0, 0, 5) + "</initialState></dynamicObstacle>\n";
  const World w = import_ok(x::scenario(body));
  REQUIRE(w.static_obstacles.size() == 2);
  const StaticObstacle& circle = w.static_obstacles[0];
  CHECK(circle.x == doctest::Approx(30.0));
  CHECK(circle.y == doctest::Approx(3.75));
  CHECK(circle.length == doctest::Approx(2.0));
  CHECK(circle.width == doctest::Approx(2.0));
  const StaticObstacle& poly = w.static_obstacles[1];
  CHECK(poly.length * poly.width == doctest::Approx(3.0));  // not the 3.1 x 1.9 axis-aligned box
  CHECK(std::max(poly.length, poly.width) == doctest::Approx(3.0));
  CHECK(poly.x == doctest::Approx(40.0));
  CHECK(poly.y == doctest::Approx(1.5));
  // Its corners are the polygon's (independent check: every corner within 1e-9 of a vertex).
  const auto corners = obstacle_box(poly).corners();
  for (const Point2& c : corners) {
    bool found = false;
    for (const auto& [u, v] : {std::pair{-1.5, -0.5}, {1.5, -0.5}, {1.5, 0.5}, {-1.5, 0.5}}) {
      found = found || std::hypot(c.x - (40 + c30 * u - s30 * v), c.y - (1.5 + s30 * u + c30 * v)) < 1e-9;
    }
    CHECK(found);
  }
  REQUIRE(w.dynamic_obstacles.size() == 1);
  const DynamicObstacle& car = w.dynamic_obstacles[0];
  CHECK(car.length == doctest::Approx(2.0));
  CHECK(car.width == doctest::Approx(4.0));
  CHECK(car.trajectory[0].x == doctest::Approx(61.0));
  CHECK(car.trajectory[0].heading == doctest::Approx(0.0));
}

TEST_CASE("an obstacle given only by its initial state moves on at constant velocity, and a missing speed comes from its positions") {
  const std::string car = "<shape><rectangle><length>4</length><width>2</width></rectangle></shape>";
  const std::string body =
      x::lanelet(1, 0, 200, 0, 3.5) + x::planning_problem(100, 10, 1.75, 0, 10) +
      "<dynamicObstacle id=\"5\"><type>pedestrian</type>" + car + "<initialState>" +
      x::state(80, -5, std::numbers::pi / 2, 0, 1.5) + "</initialState></dynamicObstacle>\n" +
      "<dynamicObstacle id=\"6\"><type>car</type>" + car + "<initialState><position>" + x::point(20, 1.75) +
      "</position><orientation><exact>0</exact></orientation><time><exact>0</exact></time></initialState><trajectory>"
      "<state><position>" + x::point(21, 1.75) + "</position><orientation><exact>0</exact></orientation><time><exact>1"
      "</exact></time></state><state><position>" + x::point(22.5, 1.75) + "</position><orientation><exact>0</exact>"
      "</orientation><time><exact>2</exact></time></state></trajectory></dynamicObstacle>\n";
  const World w = import_ok(x::scenario(body));
  REQUIRE(w.dynamic_obstacles.size() == 2);
  const DynamicObstacle& walker = w.dynamic_obstacles[0];
  REQUIRE(walker.trajectory.size() == 1);
  const auto at2 = pose_at(walker, 2.0);
  REQUIRE(at2.has_value());
  CHECK(at2->x == doctest::Approx(80.0));
  CHECK(at2->y == doctest::Approx(-5.0 + 3.0));
  const DynamicObstacle& car6 = w.dynamic_obstacles[1];
  REQUIRE(car6.trajectory.size() == 3);
  CHECK(car6.trajectory[0].v == doctest::Approx(10.0));  // 1 m in 0.1 s
  CHECK(car6.trajectory[1].v == doctest::Approx(15.0));
  CHECK(car6.trajectory[2].v == doctest::Approx(15.0));  // the last step's speed carries on
}

TEST_CASE("the planning problem's state: centre to rear axle, acceleration, curvature from the yaw rate") {
  const std::string state = "<acceleration><exact>0.5</exact></acceleration>";
  std::string pp = x::planning_problem(100, 30, 1.75, 0.1, 10, state);
  pp.replace(pp.find("<yawRate><exact>0</exact>"), 25, "<yawRate><exact>0.2</exact>");
  const World w = import_ok(x::scenario(x::lanelet(1, 0, 200, 0, 3.5) + pp));
  CHECK(w.ego.x == doctest::Approx(30 - 0.5 * kCommonRoadEgoWheelbase * std::cos(0.1)));
  CHECK(w.ego.y == doctest::Approx(1.75 - 0.5 * kCommonRoadEgoWheelbase * std::sin(0.1)));
  CHECK(w.ego.a == doctest::Approx(0.5));
  CHECK(w.ego.kappa == doctest::Approx(0.02));
  CHECK(w.ego.length == doctest::Approx(4.508));
  CHECK(w.ego.width == doctest::Approx(1.610));
  CHECK(w.duration.value_or(0) == doctest::Approx(5.0));  // goal interval end: step 50
}

TEST_CASE("speed limit: the lowest max-speed sign along the route, the one in force behind the ego, else the default") {
  auto sign = [](long id, const char* sign_id, const char* value) {
    return fmt::format("<trafficSign id=\"{}\"><trafficSignElement><trafficSignID>{}</trafficSignID><additionalValue>{}"
                       "</additionalValue></trafficSignElement><virtual>true</virtual></trafficSign>\n",
                       id, sign_id, value);
  };
  const std::string pp = x::planning_problem(100, 60, 1.75, 0, 9);
  // 1 -> 2 -> 3; the ego in 2.
  auto road = [](const std::string& s1, const std::string& s2, const std::string& s3) {
    return x::lanelet(1, 0, 50, 0, 3.5, "<successor ref=\"2\"/>" + s1) +
           x::lanelet(2, 50, 100, 0, 3.5, "<predecessor ref=\"1\"/><successor ref=\"3\"/>" + s2) +
           x::lanelet(3, 100, 300, 0, 3.5, "<predecessor ref=\"2\"/>" + s3);
  };
  const std::string r10 = "<trafficSignRef ref=\"50\"/>";
  const std::string r8 = "<trafficSignRef ref=\"51\"/>";
  const std::string signs = sign(50, "274", "10") + sign(51, "R2-1", "8") + sign(52, "206", "");
  CHECK(import_ok(x::scenario(road("", r10, "") + signs + pp)).road.speed_limit == doctest::Approx(10.0));
  CHECK(import_ok(x::scenario(road("", r10, r8) + signs + pp)).road.speed_limit == doctest::Approx(8.0));
  CHECK(import_ok(x::scenario(road(r10, "", "") + signs + pp)).road.speed_limit == doctest::Approx(10.0));
  CHECK(import_ok(x::scenario(road("", "<trafficSignRef ref=\"52\"/>", "") + signs + pp)).road.speed_limit ==
        doctest::Approx(kCommonRoadDefaultSpeedLimit));
  CommonRoadOptions fixed;
  fixed.speed_limit = 12.5;
  CHECK(import_ok(x::scenario(road("", r10, "") + signs + pp), fixed).road.speed_limit == doctest::Approx(12.5));
  // 2018b: <speedLimit> inside the lanelet.
  CHECK(import_ok(x::scenario(road("", "<speedLimit>7.5</speedLimit>", "") + pp, "2018b")).road.speed_limit ==
        doctest::Approx(7.5));
}

TEST_CASE("the route: the straightest successor, or the one towards the goal") {
  // 1 (0..50) branches into 2 (straight on) and 3 (30 deg to the left).
  std::string turn_left, turn_right;
  for (int i = 0; i <= 20; ++i) {
    const double d = 5.0 * i;
    const double c = std::cos(std::numbers::pi / 6), s = std::sin(std::numbers::pi / 6);
    turn_left += x::point(50 + d * c, 3.5 + d * s);
    turn_right += x::point(50 + d * c, d * s);
  }
  const std::string branch =
      "<lanelet id=\"3\"><leftBound>" + turn_left + "</leftBound><rightBound>" + turn_right +
      "</rightBound><predecessor ref=\"1\"/><laneletType>urban</laneletType></lanelet>\n";
  const std::string net = x::lanelet(1, 0, 50, 0, 3.5, "<successor ref=\"2\"/><successor ref=\"3\"/>") +
                          x::lanelet(2, 50, 250, 0, 3.5, "<predecessor ref=\"1\"/>") + branch;
  const World straight = import_ok(x::scenario(net + x::planning_problem(100, 10, 1.75, 0, 10)));
  CHECK(straight.reference_line.back().y == doctest::Approx(1.75));
  const CommonRoadImport towards_goal =
      import_commonroad(x::scenario(net + x::planning_problem(100, 10, 1.75, 0, 10, "", "<position><lanelet ref=\"3\"/></position>")));
  REQUIRE_MESSAGE(towards_goal.world.has_value(), towards_goal.error);
  CHECK(towards_goal.world->reference_line.back().y > 40.0);
  bool noted = false;
  for (const std::string& n : towards_goal.notes) noted = noted || n.find("towards the goal") != std::string::npos;
  CHECK(noted);
}

TEST_CASE("the road: same-direction neighbours, opposite lanes only when asked") {
  // 1: y in [0, 3.5] (ego), 2: [3.5, 7] same direction, 3: [7, 10.5] opposite, 4: [-3.5, 0] a sidewalk.
  const std::string net =
      x::lanelet(1, 0, 200, 0, 3.5, "<adjacentLeft ref=\"2\" drivingDir=\"same\"/><adjacentRight ref=\"4\" drivingDir=\"same\"/>") +
      x::lanelet(2, 0, 200, 3.5, 3.5, "<adjacentLeft ref=\"3\" drivingDir=\"opposite\"/><adjacentRight ref=\"1\" drivingDir=\"same\"/>") +
      x::lanelet(3, 0, 200, 10.5, 3.5, "<adjacentLeft ref=\"2\" drivingDir=\"opposite\"/>", true) +
      "<lanelet id=\"4\"><leftBound>" + x::point(0, 0) + x::point(200, 0) + "</leftBound><rightBound>" + x::point(0, -3.5) +
      x::point(200, -3.5) + "</rightBound><laneletType>sidewalk</laneletType></lanelet>\n";
  const std::string xml = x::scenario(net + x::planning_problem(100, 20, 1.75, 0, 10));
  const World own = import_ok(xml);
  CHECK(own.road.left_boundary.at(50) == doctest::Approx(5.25));
  CHECK(own.road.right_boundary.at(50) == doctest::Approx(-1.75));
  CommonRoadOptions opt;
  opt.opposite_lanes = true;
  const World wide = import_ok(xml, opt);
  CHECK(wide.road.left_boundary.at(50) == doctest::Approx(8.75));
  CHECK(wide.road.right_boundary.at(50) == doctest::Approx(-1.75));  // never onto the sidewalk
}

TEST_CASE("import errors name the element (and its line where it has one)") {
  const std::string road = x::lanelet(1, 0, 200, 0, 3.5);
  const std::string pp = x::planning_problem(100, 10, 1.75, 0, 10);
  struct Case {
    std::string xml;
    CommonRoadOptions options;
    std::string expect;
  };
  CommonRoadOptions pick_7;
  pick_7.planning_problem = 7;
  const std::vector<Case> cases{
      {x::scenario(road), {}, "no <planningProblem>"},
      {x::scenario(road + pp), pick_7, "no planningProblem with id 7 (the file has: 100)"},
      {x::scenario(x::lanelet(1, 0, 50, 0, 3.5, "<successor ref=\"99\"/>") + pp), {}, "lanelet 1: successor 99 does not exist"},
      {x::scenario(x::lanelet(1, 0, 200, 0, 3.5, "<adjacentLeft ref=\"98\" drivingDir=\"same\"/>") + pp), {},
       "lanelet 1: adjacentLeft 98 does not exist"},
      {x::scenario(x::lanelet(1, 0, 200, 0, 3.5, "<trafficSignRef ref=\"97\"/>") + pp), {},
       "lanelet 1: trafficSignRef 97 does not exist"},
      {x::scenario(road + x::planning_problem(100, 10, 9.0, 0, 10)), {},
       "planningProblem 100: initialState: the ego at (10.00, 9.00), heading 0.000 rad, lies in no lanelet"},
      {x::scenario(road + x::planning_problem(100, 10, 1.75, std::numbers::pi, 10)), {}, "lies in no lanelet that runs its way"},
      {x::scenario(road + x::planning_problem(100, 10, 1.75, 0, 10, "", "<position><lanelet ref=\"96\"/></position>")), {},
       "goal lanelet 96 does not exist"},
      {x::scenario(road + x::planning_problem(100, 10, 1.75, 0, -3)), {},
       "planningProblem 100: initialState: velocity -3 m/s: driving backwards is not supported"},
      {x::scenario("<lanelet id=\"1\"><leftBound>" + x::point(0, 3.5) + x::point(0.8, 3.5) + "</leftBound><rightBound>" +
                   x::point(0, 0) + x::point(0.8, 0) + "</rightBound></lanelet>\n" + x::planning_problem(100, 0.4, 1.75, 0, 3)),
       {},
       "lanelet 1: the route from the ego's lanelet is 0.8 m long; the planner needs 1 m"},
      {x::scenario(pp), {}, "the scenario has no <lanelet>"},
  };
  for (const Case& c : cases) {
    CAPTURE(c.xml);
    const std::string e = import_error(c.xml, c.options);
    CHECK_MESSAGE(e.find(c.expect) != std::string::npos, e);
  }
  // The planning problem's line is named.
  CHECK(import_error(x::scenario(road + x::planning_problem(100, 10, -9.0, 0, 10))).find("line 4: planningProblem 100") !=
        std::string::npos);
  // A missing velocity.
  std::string no_v = x::planning_problem(100, 10, 1.75, 0, 10);
  no_v.erase(no_v.find("<velocity>"), std::string("<velocity><exact>10</exact></velocity>").size());
  CHECK(import_error(x::scenario(road + no_v)).find("initialState: <velocity> missing") != std::string::npos);
}

TEST_CASE("input limits: a bound, the route, the road's bounds and coordinates beyond them are refused naming the element") {
  // Straight lanelets along +x with two-point bounds (no densified XML), width 4 m.
  const auto lanelet = [](long id, double x0, double x1, double y_right, const std::string& extra = "") {
    return fmt::format("<lanelet id=\"{}\"><leftBound>{}{}</leftBound><rightBound>{}{}</rightBound>{}</lanelet>\n", id,
                       x::point(x0, y_right + 4), x::point(x1, y_right + 4), x::point(x0, y_right), x::point(x1, y_right),
                       extra);
  };
  const auto refused = [](const std::string& xml, const std::vector<std::string>& expect) {
    CAPTURE(xml.substr(0, 400));
    const std::string e = import_error(xml);
    for (const std::string& part : expect) CHECK_MESSAGE(e.find(part) != std::string::npos, e);
  };
  const auto pp = [](double x, double y = 2.0) { return x::planning_problem(100, x, y, 0, 10); };

  // A lanelet bound: at most limits::kMaxBoundLength (10 km) long.
  REQUIRE(cr::limits::kMaxBoundLength == 10000.0);
  import_ok(x::scenario(lanelet(1, 0, 10000, 0) + pp(10)));
  refused(x::scenario(lanelet(1, 0, 10000.5, 0) + pp(10)),
          {"line 3: lanelet 1: leftBound: 10000.5 m long", "the importer's limit for a lanelet bound is 10000 m"});
  // A bound's length is the sum of its segments: 6 km out and back along x.
  refused(x::scenario("<lanelet id=\"1\"><leftBound>" + x::point(0, 4) + x::point(100, 4) + "</leftBound><rightBound>" +
                      x::point(0, 0) + x::point(6000, 0) + x::point(100, 0) + "</rightBound></lanelet>\n" + pp(10)),
          {"lanelet 1: rightBound: 11900.0 m long", "limit for a lanelet bound is 10000 m"});

  // Coordinates: |x|, |y| <= limits::kMaxCoordinate (1e8 m), of every point.
  REQUIRE(cr::limits::kMaxCoordinate == 1.0e8);
  const World remote = import_ok(x::scenario(lanelet(1, 1.0e8 - 200, 1.0e8, -1.0e8) + pp(1.0e8 - 190, -1.0e8 + 2)));
  CHECK(remote.reference_line.size() >= 2);
  refused(x::scenario(lanelet(1, 1.0e8 - 200, 1.0e8 + 1, 0) + pp(1.0e8 - 190)),
          {"lanelet 1: leftBound: point 1: <x> 100000001 m lies beyond the importer's coordinate limit |x| <= 1e+08 m"});
  refused(x::scenario(lanelet(1, 0, 200, 0) + x::planning_problem(100, 10, -2.5e8, 0, 10)),
          {"planningProblem 100: initialState: position: <y> -250000000 m lies beyond", "|y| <= 1e+08 m"});

  // The route: at most limits::kMaxRouteLength (20 km) of reference line. The
  // ego near the end of a 10 km lanelet, the route continues through its
  // successor (9 999 m: inside; beyond a 10 km gap: 30 km, refused).
  REQUIRE(cr::limits::kMaxRouteLength == 20000.0);
  const World long_route = import_ok(
      x::scenario(lanelet(1, 0, 10000, 0, "<successor ref=\"2\"/>") + lanelet(2, 10000, 19999, 0) + pp(9900)));
  CHECK(polyline_arc_lengths(long_route.reference_line).back() == doctest::Approx(19999.0));
  refused(x::scenario(lanelet(1, 0, 10000, 0, "<successor ref=\"2\"/>") + lanelet(2, 20000, 30000, 0) + pp(9900)),
          {"planningProblem 100: initialState: lanelet 1: the route from the ego's lanelet through 2 lanelets (1 to 2) is "
           "30000.0 m long; the importer's limit for a route is 20000 m"});

  // The road's bounds: at most limits::kMaxRoadBoundLength (40 km), each
  // counted once. Route lanelets 1 and 2 (100 m each), each beside its own
  // lanes left and right whose outer bounds are `far` long.
  REQUIRE(cr::limits::kMaxRoadBoundLength == 40000.0);
  const auto road = [&](double far, bool shared) {
    const std::string a2 = shared ? "3" : "5", b2 = shared ? "4" : "6";
    const auto beside = [&](long id, double x0, double x1, double y_right, bool left) {
      // The outer bound runs `far` m: from x0 - (far - (x1 - x0)) / 2 to x1 + the same.
      const double over = 0.5 * (far - (x1 - x0));
      const cr::Vec2 o0{x0 - over, left ? y_right + 4 : y_right}, o1{x1 + over, left ? y_right + 4 : y_right};
      const std::string outer = x::point(o0.x, o0.y) + x::point(o1.x, o1.y);
      const std::string inner = x::point(x0, left ? y_right : y_right + 4) + x::point(x1, left ? y_right : y_right + 4);
      return fmt::format("<lanelet id=\"{}\"><leftBound>{}</leftBound><rightBound>{}</rightBound></lanelet>\n", id,
                         left ? outer : inner, left ? inner : outer);
    };
    std::string net =
        lanelet(1, 0, 100, 0,
                "<successor ref=\"2\"/><adjacentLeft ref=\"3\" drivingDir=\"same\"/><adjacentRight ref=\"4\" drivingDir=\"same\"/>") +
        lanelet(2, 100, 200, 0,
                fmt::format("<predecessor ref=\"1\"/><adjacentLeft ref=\"{}\" drivingDir=\"same\"/>"
                            "<adjacentRight ref=\"{}\" drivingDir=\"same\"/>",
                            a2, b2)) +
        beside(3, 0, 100, 4, true) + beside(4, 0, 100, -4, false);
    if (!shared) net += beside(5, 100, 200, 4, true) + beside(6, 100, 200, -4, false);
    return x::scenario(net + pp(10));
  };
  // 4 x 9 900 m + the route lanelets' own 4 x 100 m = 40 000 m: inside.
  const World wide = import_ok(road(9900, false));
  CHECK(wide.road.left_boundary.at(50) == doctest::Approx(6.0));
  CHECK(wide.road.right_boundary.at(150) == doctest::Approx(-6.0));
  refused(road(9901, false), {"planningProblem 100: initialState: lanelet 1: the road along the route is built from 8 lanelet bounds",
                              "of 40004.0 m in all, the longest lanelet 3 leftBound, 9901.0 m; the importer's limit is 40000 m"});
  // The same 10 km neighbours beside both route lanelets count once: 20 400 m.
  import_ok(road(10000, true));
}

TEST_CASE("scenes load by extension or content: scene/1 JSON, or CommonRoad XML imported on the fly") {
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / "itp_test_scene_files";
  std::filesystem::create_directories(dir);
  const World w = import_ok(read_file("ZAM_Tutorial-1_1_T-1.xml"));
  const std::string json_path = (dir / "zam.json").string();
  REQUIRE(save_scene_file(w, json_path).empty());
  const std::string xml_no_ext = (dir / "zam_scenario").string();
  std::ofstream(xml_no_ext) << read_file("ZAM_Tutorial-1_1_T-1.xml");
  const LoadedScene a = load_scene(json_path);
  const LoadedScene b = load_scene(data_path("ZAM_Tutorial-1_1_T-1.xml"));
  const LoadedScene c = load_scene(xml_no_ext);
  REQUIRE(a.world.has_value());
  REQUIRE(b.world.has_value());
  REQUIRE(c.world.has_value());
  CHECK(a.kind == SceneFileKind::kSceneJson);
  CHECK(b.kind == SceneFileKind::kCommonRoadXml);
  CHECK(c.kind == SceneFileKind::kCommonRoadXml);
  CHECK(scene_to_text(*a.world) == scene_to_text(*b.world));
  const LoadedScene bad = load_scene(data_path("test_reading_lanelets.xml"));
  CHECK_FALSE(bad.world.has_value());
  CHECK(bad.error.find("test_reading_lanelets.xml: CommonRoad: no <planningProblem>") != std::string::npos);
  std::filesystem::remove_all(dir);
}
