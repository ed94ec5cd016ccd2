// The CommonRoad XML reader (formats/commonroad.hpp): what the development
// files contain, read back; every refusal names the element and its line;
// malformed input never throws.
#include <doctest/doctest.h>

#include <fstream>
#include <map>
#include <random>
#include <sstream>
#include <string>

#include "commonroad_xml.hpp"
#include "formats/commonroad.hpp"
#include "sim/commonroad_world.hpp"

using namespace hil::formats::commonroad;
namespace x = commonroad_xml;

namespace {

std::string read_file(const std::string& name) {
  std::ifstream in(std::string(ITP_COMMONROAD_DATA_DIR) + "/" + name, std::ios::binary);
  REQUIRE_MESSAGE(in.good(), name);
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

const Obstacle* find_obstacle(const Scenario& sc, long id) {
  for (const Obstacle& o : sc.obstacles) {
    if (o.id == id) return &o;
  }
  return nullptr;
}

// The error of reading `xml`, which must fail.
std::string error_of(const std::string& xml, const ReadOptions& options = {}) {
  const ReadResult r = read_commonroad(xml, options);
  REQUIRE_FALSE(r.scenario.has_value());
  return r.error;
}

const std::string kRoad = x::lanelet(1, 0, 100, 0, 3.5);

}  // namespace

TEST_CASE("test_reading_all.xml: every element type read as written") {
  ReadOptions opt;
  opt.drop_set_based = true;
  const ReadResult r = read_commonroad(read_file("test_reading_all.xml"), opt);
  REQUIRE_MESSAGE(r.scenario.has_value(), r.error);
  const Scenario& sc = *r.scenario;
  CHECK(sc.version == "2020a");
  CHECK(sc.time_step == doctest::Approx(0.1));
  REQUIRE(sc.lanelets.size() == 6);
  const Lanelet& l100 = sc.lanelets[0];
  CHECK(l100.id == 100);
  CHECK(l100.left_bound.size() == 3);
  CHECK(l100.left_bound[2].x == doctest::Approx(2.0));
  CHECK(l100.left_bound[2].y == doctest::Approx(2.0));
  CHECK(l100.successors == std::vector<long>{101});
  REQUIRE(l100.left.has_value());
  CHECK(l100.left->id == 103);
  CHECK(l100.left->direction == DrivingDirection::kSame);
  CHECK_FALSE(l100.right.has_value());
  CHECK(l100.traffic_signs == std::vector<long>{201});
  CHECK(l100.types == std::vector<std::string>{"highway", "mainCarriageWay"});
  REQUIRE(sc.traffic_signs.size() == 1);
  CHECK(sc.traffic_signs[0].elements[0].sign_id == "274");
  CHECK(sc.traffic_signs[0].elements[0].values == std::vector<std::string>{"10"});
  // The static circle and the dynamic obstacle with a trajectory; the
  // set-based dynamic obstacle 1 and the phantom obstacle are left out and noted.
  const Obstacle* circle = find_obstacle(sc, 3);
  REQUIRE(circle != nullptr);
  CHECK_FALSE(circle->dynamic);
  REQUIRE(circle->shape.size() == 1);
  CHECK(circle->shape[0].kind == ShapePart::Kind::kCircle);
  CHECK(circle->shape[0].radius == doctest::Approx(2.0));
  const Obstacle* moving = find_obstacle(sc, 2);
  REQUIRE(moving != nullptr);
  CHECK(moving->dynamic);
  REQUIRE(moving->trajectory.size() == 1);
  CHECK(moving->trajectory[0].time_step == 1);
  CHECK(moving->trajectory[0].position.y == doctest::Approx(1.0));
  CHECK(find_obstacle(sc, 1) == nullptr);
  int set_based_notes = 0;
  for (const std::string& n : sc.ignored) set_based_notes += n.find("set-based") != std::string::npos ? 1 : 0;
  CHECK(set_based_notes == 2);
  REQUIRE(sc.planning_problems.size() == 1);
  const PlanningProblem& p = sc.planning_problems[0];
  CHECK(p.id == 1000);
  CHECK(p.initial.velocity.value_or(-1) == doctest::Approx(0.1));
  REQUIRE(p.goals.size() == 2);
  CHECK(p.goals[0].time_end.value_or(-1) == 1);
  CHECK(p.goals[1].time_start.value_or(-1) == 1);
  REQUIRE(p.goals[1].area_centres.size() == 1);
  CHECK(p.goals[1].area_centres[0].x == doctest::Approx(10.0));
}

TEST_CASE("a 2018b file: <obstacle role>, lanelet <speedLimit>, uncertain states read as their centres") {
  const ReadResult r = read_commonroad(read_file("DEU_A9-3_1_T-1.xml"));
  REQUIRE_MESSAGE(r.scenario.has_value(), r.error);
  const Scenario& sc = *r.scenario;
  CHECK(sc.version == "2018b");
  CHECK(sc.time_step == doctest::Approx(0.2));
  CHECK(sc.obstacles.size() == 9);
  CHECK(sc.lanelets.size() == 32);
  CHECK(sc.lanelets[0].speed_limit.value_or(0) == doctest::Approx(27.78));
  const Obstacle* o = find_obstacle(sc, 3536);
  REQUIRE(o != nullptr);
  CHECK(o->dynamic);
  CHECK(o->initial.uncertain);
  CHECK(o->initial.position.x == doctest::Approx(351.6643758281));  // the region's centre
  CHECK(o->initial.orientation == doctest::Approx(0.5 * (0.0011 + 0.0347)));
  CHECK(o->initial.velocity.value_or(0) == doctest::Approx(0.5 * (27.0104 + 27.4908)));
}

TEST_CASE("set-based content is refused, naming the element and its line") {
  const std::string e = error_of(read_file("test_reading_obstacles.xml"));
  CHECK(e.find("line 60") != std::string::npos);
  CHECK(e.find("dynamicObstacle 1") != std::string::npos);
  CHECK(e.find("occupancySet") != std::string::npos);
  const std::string phantom = x::scenario(kRoad + "<phantomObstacle id=\"7\"><occupancySet/></phantomObstacle>\n");
  CHECK(error_of(phantom).find("phantomObstacle 7") != std::string::npos);
  const std::string interval_time = x::scenario(
      kRoad + "<dynamicObstacle id=\"5\"><type>car</type><shape><rectangle><length>4</length><width>2</width>"
              "</rectangle></shape><initialState>" + x::state(10, 1.75, 0, 0, 5) + "</initialState><trajectory><state>" +
      "<position>" + x::point(10, 1.75) + "</position><orientation><exact>0</exact></orientation>"
      "<time><intervalStart>1</intervalStart><intervalEnd>2</intervalEnd></time></state></trajectory></dynamicObstacle>\n");
  const std::string e2 = error_of(interval_time);
  CHECK(e2.find("dynamicObstacle 5: trajectory state 0") != std::string::npos);
  CHECK(e2.find("time interval") != std::string::npos);
}

TEST_CASE("malformed content: an error naming the element and the line") {
  struct Case {
    std::string xml;
    std::string expect;  // substrings of the error
    std::string line;
  };
  const std::string car_shape = "<shape><rectangle><length>4</length><width>2</width></rectangle></shape>";
  const std::vector<Case> cases{
      {"<commonRoad timeStepSize=\"0.1\"><lanelet id=\"1\"><leftBound>", "not well-formed XML", "line 1"},
      {"<?xml version=\"1.0\"?>\n<scenario/>", "no <commonRoad> root element", ""},
      {"<commonRoad commonRoadVersion=\"2020a\">\n" + kRoad + "</commonRoad>", "timeStepSize missing", "line 1"},
      {"<commonRoad timeStepSize=\"-0.1\"/>", "timeStepSize='-0.1' is not a positive number", "line 1"},
      {x::scenario("<lanelet id=\"4\"><leftBound><point><x>1.0abc</x><y>2</y></point><point><x>2</x><y>2</y></point>"
                   "</leftBound><rightBound>" + x::point(1, 0) + x::point(2, 0) + "</rightBound></lanelet>\n"),
       "lanelet 4: leftBound: point 0: <x>: '1.0abc' is not a finite number", "line 3"},
      {x::scenario("<lanelet id=\"4\"><leftBound>" + x::point(1, 2) + x::point(2, 2) + "</leftBound><rightBound>" +
                   "<point><x>nan</x><y>0</y></point>" + x::point(2, 0) + "</rightBound></lanelet>\n"),
       "lanelet 4: rightBound: point 0: <x>: 'nan' is not a finite number", "line 3"},
      {x::scenario("<lanelet id=\"4\"><leftBound>" + x::point(1, 2) + "</leftBound><rightBound>" + x::point(1, 0) +
                   x::point(2, 0) + "</rightBound></lanelet>\n"),
       "lanelet 4: leftBound: 1 points, at least 2 needed", "line 3"},
      {x::scenario("<lanelet id=\"x4\"/>\n"), "lanelet: attribute id='x4' is not an integer", "line 3"},
      {x::scenario(x::lanelet(1, 0, 50, 0, 3.5, "<adjacentLeft ref=\"2\" drivingDir=\"sideways\"/>")),
       "lanelet 1: adjacentLeft: drivingDir 'sideways'", "line 3"},
      {x::scenario(kRoad + x::lanelet(1, 0, 50, 5, 3.5)), "lanelet 1: the id is used twice", "line 4"},
      {x::scenario(kRoad + "<staticObstacle id=\"9\"><type>unknown</type><shape><circle><radius>-1</radius></circle>"
                           "</shape><initialState>" + x::state(5, 1, 0, 0, 0) + "</initialState></staticObstacle>\n"),
       "staticObstacle 9: shape: circle: radius must be positive", "line 4"},
      {x::scenario(kRoad + "<staticObstacle id=\"9\"><type>unknown</type><shape><ellipse/></shape><initialState>" +
                   x::state(5, 1, 0, 0, 0) + "</initialState></staticObstacle>\n"),
       "staticObstacle 9: shape: unknown shape <ellipse>", "line 4"},
      {x::scenario(kRoad + "<staticObstacle id=\"9\"><type>unknown</type>" + car_shape + "</staticObstacle>\n"),
       "staticObstacle 9: <initialState> missing", "line 4"},
      {x::scenario(kRoad + "<dynamicObstacle id=\"8\"><type>car</type>" + car_shape + "<initialState>" +
                   x::state(5, 1, 0, 3, 5) + "</initialState><trajectory><state>" + x::state(6, 1, 0, 2, 5) +
                   "</state></trajectory></dynamicObstacle>\n"),
       "dynamicObstacle 8: trajectory state 0: time step 2 does not follow 3", "line 4"},
      {x::scenario(kRoad + "<dynamicObstacle id=\"8\"><type>car</type>" + car_shape +
                   "<initialState><position>" + x::point(5, 1) + "</position><time><exact>0</exact></time>"
                   "</initialState></dynamicObstacle>\n"),
       "dynamicObstacle 8: initialState: <orientation> missing", "line 4"},
      {x::scenario(kRoad + "<dynamicObstacle id=\"8\"><type>car</type>" + car_shape + "<initialState>" +
                   x::state(5, 1, 0, 0, 5) + "<acceleration><intervalStart>2</intervalStart><intervalEnd>1</intervalEnd>"
                   "</acceleration></initialState></dynamicObstacle>\n"),
       "dynamicObstacle 8: initialState: acceleration: interval [2, 1] is empty", "line 4"},
      {x::scenario(kRoad + "<obstacle id=\"8\"><role>flying</role></obstacle>\n"), "obstacle: <role> 'flying'", "line 4"},
      {x::scenario(kRoad + "<trafficSign id=\"3\"><trafficSignElement><additionalValue>5</additionalValue>"
                           "</trafficSignElement></trafficSign>\n"),
       "trafficSign 3: <trafficSignElement> without <trafficSignID>", "line 4"},
  };
  for (const Case& c : cases) {
    CAPTURE(c.xml);
    const std::string e = error_of(c.xml);
    CHECK_MESSAGE(e.find(c.expect) != std::string::npos, e);
    CHECK_MESSAGE(e.find(c.line) != std::string::npos, e);
  }
}

TEST_CASE("mutated and truncated scenario files never throw: a world or an error, always") {
  const std::string base = read_file("ZAM_Tutorial-1_1_T-1.xml");
  std::mt19937 rng(11);
  std::uniform_int_distribution<std::size_t> at(0, base.size() - 1);
  const std::string junk = "<>/&\"'=;x0.-e9\n ";
  int errors = 0;
  for (int trial = 0; trial < 300; ++trial) {
    std::string text = base;
    if (trial % 3 == 0) {
      text.resize(at(rng));  // truncated
    } else {
      for (int k = 0; k < 1 + trial % 7; ++k) text[at(rng)] = junk[at(rng) % junk.size()];  // flipped bytes
    }
    hil::sim::CommonRoadImport r;
    CHECK_NOTHROW(r = hil::sim::import_commonroad(text));
    CHECK(r.world.has_value() != !r.error.empty());
    errors += r.world ? 0 : 1;
  }
  CHECK(errors > 100);
  const hil::sim::CommonRoadImport whole = hil::sim::import_commonroad(base);
  CHECK_MESSAGE(whole.world.has_value(), whole.error);
}

TEST_CASE("traffic lights: the cycle, the offset, the lanelet's references and its stop line are read and mapped") {
  const std::string light =
      "<trafficLight id=\"7\"><cycle>"
      "<cycleElement><duration>400</duration><color>green</color></cycleElement>"
      "<cycleElement><duration>30</duration><color>yellow</color></cycleElement>"
      "<cycleElement><duration>570</duration><color>red</color></cycleElement>"
      "<timeOffset>590</timeOffset></cycle><position>" + x::point(100, 4) + "</position>"
      "<direction>all</direction><active>true</active></trafficLight>\n";
  const std::string off =
      "<trafficLight id=\"8\"><cycle><cycleElement><duration>10</duration><color>red</color></cycleElement></cycle>"
      "<active>false</active></trafficLight>\n";
  // Lanelet 1 ends at its light (no stop-line points: the lanelet's end);
  // lanelet 2's stop line is drawn at x = 160; lanelet 3's light is off.
  const std::string body =
      x::lanelet(1, 0, 100, 0, 3.5, "<successor ref=\"2\"/><stopLine><lineMarking>solid</lineMarking>"
                                    "<trafficLightRef ref=\"7\"/></stopLine><trafficLightRef ref=\"7\"/>") +
      x::lanelet(2, 100, 200, 0, 3.5, "<stopLine>" + x::point(160, 0) + x::point(160, 3.5) +
                                          "<lineMarking>solid</lineMarking></stopLine><trafficLightRef ref=\"7\"/>") +
      x::lanelet(3, 100, 200, 3.5, 3.5, "<trafficLightRef ref=\"8\"/>") + light + off +
      x::planning_problem(100, 10, 1.75, 0, 10);
  const ReadResult r = read_commonroad(x::scenario(body));
  REQUIRE_MESSAGE(r.scenario.has_value(), r.error);
  REQUIRE(r.scenario->traffic_lights.size() == 2);
  const TrafficLight& t = r.scenario->traffic_lights[0];
  CHECK(t.id == 7);
  REQUIRE(t.cycle.size() == 3);
  CHECK(t.cycle[1].color == "yellow");
  CHECK(t.cycle[2].duration == 570);
  CHECK(t.time_offset == 590);
  CHECK(t.active);
  CHECK_FALSE(r.scenario->traffic_lights[1].active);
  CHECK(r.scenario->lanelets[0].traffic_lights == std::vector<long>{7});  // the two references, once
  CHECK(r.scenario->lanelets[0].stop_line.empty());
  CHECK(r.scenario->lanelets[1].stop_line.size() == 2);

  const hil::sim::CommonRoadImport imp = hil::sim::import_commonroad(x::scenario(body));
  REQUIRE_MESSAGE(imp.world.has_value(), imp.error);
  std::map<long, const hil::sim::Lane*> lanes;
  for (const hil::sim::Lane& l : imp.world->lanes) lanes[l.id] = &l;
  REQUIRE(lanes.count(1) == 1);
  REQUIRE(lanes[1]->traffic_lights.size() == 1);
  CHECK(lanes[1]->stop_s == doctest::Approx(100.0));  // the end of the 100 m lanelet
  CHECK(lanes[1]->traffic_lights[0].time_offset == doctest::Approx(59.0));
  CHECK(lanes[1]->traffic_lights[0].cycle[2].duration == doctest::Approx(57.0));
  CHECK(hil::sim::light_color(lanes[1]->traffic_lights[0], 0.0) == "yellow");
  CHECK(hil::sim::light_color(lanes[1]->traffic_lights[0], 2.0) == "red");
  CHECK(lanes[2]->stop_s == doctest::Approx(60.0));  // its stop line, 60 m along it
  CHECK(lanes[3]->traffic_lights.empty());          // inactive: no stop
  // A malformed cycle is an error naming the light.
  const std::string bad = "<trafficLight id=\"9\"><cycle><cycleElement><duration>-3</duration><color>red</color>"
                          "</cycleElement></cycle></trafficLight>\n";
  CHECK(error_of(x::scenario(kRoad + bad)).find("trafficLight 9: cycleElement 0") != std::string::npos);
  const std::string purple = "<trafficLight id=\"9\"><cycle><cycleElement><duration>3</duration><color>purple</color>"
                             "</cycleElement></cycle></trafficLight>\n";
  CHECK(error_of(x::scenario(kRoad + purple)).find("purple") != std::string::npos);
}
