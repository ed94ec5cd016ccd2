#include "sim/world.hpp"

#include <cmath>
#include <cstdint>
#include <limits>
#include <fstream>
#include <numbers>
#include <sstream>
#include <stdexcept>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

namespace hil::sim {

using nlohmann::json;

double wrap_angle(double a) {
  constexpr double kPi = std::numbers::pi;
  a = std::fmod(a + kPi, 2.0 * kPi);
  if (a <= 0.0) {
    a += 2.0 * kPi;
  }
  return a - kPi;
}

const std::string& light_color(const TrafficLightCycle& light, double t) {
  static const std::string kNone = "inactive";
  double total = 0.0;
  for (const LightPhase& ph : light.cycle) total += ph.duration;
  if (light.cycle.empty() || !(total > 0.0) || !std::isfinite(t)) return kNone;
  double phase = std::fmod(t - light.time_offset, total);
  if (phase < 0.0) phase += total;
  // Half a microsecond of slack: a phase boundary given in time steps (0.1 s)
  // lands on it despite the float division.
  constexpr double kEdge = 5e-7;
  for (const LightPhase& ph : light.cycle) {
    if (phase + kEdge < ph.duration) return ph.color;
    phase -= ph.duration;
  }
  return light.cycle.back().color;
}

bool is_stop_color(const std::string& color) { return color == "red" || color == "yellow" || color == "redYellow"; }

double Boundary::at(double s) const {
  if (knots.empty()) {
    return constant;
  }
  if (s <= knots.front().s) {
    return knots.front().l;
  }
  if (s >= knots.back().s) {
    return knots.back().l;
  }
  // Few knots: a linear scan is clear and fast enough on the host.
  for (std::size_t i = 1; i < knots.size(); ++i) {
    if (s <= knots[i].s) {
      const Knot& a = knots[i - 1];
      const Knot& b = knots[i];
      const double u = (s - a.s) / (b.s - a.s);
      return a.l + u * (b.l - a.l);
    }
  }
  return knots.back().l;
}

std::optional<Pose> pose_at(const DynamicObstacle& obstacle, double t) {
  const auto& tr = obstacle.trajectory;
  if (tr.empty() || t < tr.front().t) {
    return std::nullopt;
  }
  if (t >= tr.back().t) {
    const TimedPose& p = tr.back();
    const double dt = t - p.t;
    return Pose{p.x + p.v * dt * std::cos(p.heading), p.y + p.v * dt * std::sin(p.heading),
                p.heading};
  }
  // Binary search for the segment [i-1, i] holding t (strictly ascending t).
  std::size_t lo = 0;
  std::size_t hi = tr.size() - 1;
  while (hi - lo > 1) {
    const std::size_t mid = (lo + hi) / 2;
    if (tr[mid].t <= t) {
      lo = mid;
    } else {
      hi = mid;
    }
  }
  const TimedPose& a = tr[lo];
  const TimedPose& b = tr[hi];
  const double u = (t - a.t) / (b.t - a.t);
  const double dh = wrap_angle(b.heading - a.heading);
  return Pose{a.x + u * (b.x - a.x), a.y + u * (b.y - a.y), wrap_angle(a.heading + u * dh)};
}

namespace {

json boundary_to_json(const Boundary& b) {
  if (b.is_constant()) {
    return b.constant;
  }
  json arr = json::array();
  for (const auto& k : b.knots) {
    arr.push_back(json::array({k.s, k.l}));
  }
  return arr;
}

// Throws std::runtime_error with the JSON path in the message.
[[noreturn]] void fail(const std::string& where, const std::string& what) {
  throw std::runtime_error(fmt::format("scene/1: {}: {}", where, what));
}

double number(const json& j, const char* key, const std::string& where) {
  if (!j.is_object() || !j.contains(key)) {
    fail(where, fmt::format("missing key \"{}\"", key));
  }
  const json& v = j.at(key);
  if (!v.is_number()) {
    fail(where, fmt::format("\"{}\" must be a number", key));
  }
  const double d = v.get<double>();
  if (!std::isfinite(d)) {
    fail(where, fmt::format("\"{}\" must be finite", key));
  }
  return d;
}

double positive(const json& j, const char* key, const std::string& where) {
  const double d = number(j, key, where);
  if (!(d > 0.0)) {
    fail(where, fmt::format("\"{}\" must be > 0", key));
  }
  return d;
}

// An integer that fits the planner's 32-bit ids: JSON integers beyond that
// range are refused by name, never wrapped (4294967297 is not 1).
std::int32_t integer(const json& j, const char* key, const std::string& where) {
  if (!j.is_object() || !j.contains(key)) {
    fail(where, fmt::format("missing key \"{}\"", key));
  }
  const json& v = j.at(key);
  if (!v.is_number_integer()) {
    fail(where, fmt::format("\"{}\" must be an integer", key));
  }
  constexpr auto lo = std::numeric_limits<std::int32_t>::min();
  constexpr auto hi = std::numeric_limits<std::int32_t>::max();
  const bool in_range = v.is_number_unsigned() ? v.get<std::uint64_t>() <= static_cast<std::uint64_t>(hi)
                                               : v.get<std::int64_t>() >= lo && v.get<std::int64_t>() <= hi;
  if (!in_range) {
    fail(where, fmt::format("\"{}\" must be an integer in [{}, {}]", key, lo, hi));
  }
  return static_cast<std::int32_t>(v.get<std::int64_t>());
}

std::string optional_kind(const json& j) {
  if (j.contains("kind") && j.at("kind").is_string()) {
    return j.at("kind").get<std::string>();
  }
  return {};
}

Boundary boundary_from_json(const json& j, const std::string& where) {
  if (j.is_number()) {
    return Boundary::constant_at(j.get<double>());
  }
  if (!j.is_array() || j.empty()) {
    fail(where, "must be a number or a non-empty list of [s, l] pairs");
  }
  Boundary b;
  for (std::size_t i = 0; i < j.size(); ++i) {
    const json& p = j[i];
    if (!p.is_array() || p.size() != 2 || !p[0].is_number() || !p[1].is_number()) {
      fail(fmt::format("{}[{}]", where, i), "must be an [s, l] pair of numbers");
    }
    Boundary::Knot k{p[0].get<double>(), p[1].get<double>()};
    if (!b.knots.empty() && !(k.s > b.knots.back().s)) {
      fail(fmt::format("{}[{}]", where, i), "s must be strictly ascending");
    }
    b.knots.push_back(k);
  }
  return b;
}

}  // namespace

void to_json(json& j, const World& w) {
  j = json::object();
  j["format"] = "scene/1";
  j["name"] = w.name;
  json ref = json::array();
  for (const auto& p : w.reference_line) {
    ref.push_back(json::array({p.x, p.y}));
  }
  j["reference_line"] = std::move(ref);
  j["road"] = {{"lane_width", w.road.lane_width},
               {"left_boundary", boundary_to_json(w.road.left_boundary)},
               {"right_boundary", boundary_to_json(w.road.right_boundary)},
               {"target_lane_offset", w.road.target_lane_offset},
               {"speed_limit", w.road.speed_limit}};
  const Ego& e = w.ego;
  j["ego"] = {{"x", e.x},         {"y", e.y},         {"heading", e.heading},
              {"v", e.v},         {"a", e.a},         {"kappa", e.kappa},
              {"length", e.length}, {"width", e.width}, {"wheelbase", e.wheelbase}};
  json st = json::array();
  for (const auto& o : w.static_obstacles) {
    json jo = {{"id", o.id},           {"x", o.x},           {"y", o.y},
               {"heading", o.heading}, {"length", o.length}, {"width", o.width}};
    if (!o.kind.empty()) {
      jo["kind"] = o.kind;
    }
    st.push_back(std::move(jo));
  }
  j["static_obstacles"] = std::move(st);
  json dy = json::array();
  for (const auto& o : w.dynamic_obstacles) {
    json tr = json::array();
    for (const auto& p : o.trajectory) {
      tr.push_back({{"t", p.t}, {"x", p.x}, {"y", p.y}, {"heading", p.heading}, {"v", p.v}});
    }
    json jo = {{"id", o.id}, {"length", o.length}, {"width", o.width}, {"trajectory", std::move(tr)}};
    if (!o.kind.empty()) {
      jo["kind"] = o.kind;
    }
    dy.push_back(std::move(jo));
  }
  j["dynamic_obstacles"] = std::move(dy);
  if (w.duration) {
    j["duration"] = *w.duration;
  }
  if (!w.tags.empty()) {
    j["tags"] = w.tags;
  }
  if (!w.lanes.empty()) {
    json lanes = json::array();
    for (const Lane& l : w.lanes) {
      auto points = [](const std::vector<Point2>& line) {
        json arr = json::array();
        for (const Point2& p : line) arr.push_back(json::array({p.x, p.y}));
        return arr;
      };
      json jl = {{"id", l.id},
                 {"centre", points(l.centre)},
                 {"left", points(l.left)},
                 {"right", points(l.right)},
                 {"successors", l.successors}};
      if (!l.traffic_lights.empty()) {
        json lights = json::array();
        for (const TrafficLightCycle& c : l.traffic_lights) {
          json cycle = json::array();
          for (const LightPhase& ph : c.cycle) cycle.push_back({{"color", ph.color}, {"duration", ph.duration}});
          lights.push_back({{"cycle", std::move(cycle)}, {"time_offset", c.time_offset}});
        }
        jl["traffic_lights"] = std::move(lights);
        jl["stop_s"] = l.stop_s;
      }
      lanes.push_back(std::move(jl));
    }
    j["lanes"] = std::move(lanes);
  }
}

// Keys that scene/1 writers may leave out: a missing one takes its default.
static double optional_number(const json& j, const char* key, const std::string& where, double fallback) {
  return j.contains(key) ? number(j, key, where) : fallback;
}

void from_json(const json& j, World& w) {
  if (!j.is_object()) {
    fail("<root>", "must be a JSON object");
  }
  if (!j.contains("format")) {
    fail("<root>", "missing key \"format\" (expected \"scene/1\")");
  }
  if (!j.at("format").is_string() || j.at("format").get<std::string>() != "scene/1") {
    fail("format", fmt::format("expected \"scene/1\", got {}", j.at("format").dump()));
  }
  World out;
  if (j.contains("name")) {
    if (!j.at("name").is_string()) {
      fail("name", "not a string");
    }
    out.name = j.at("name").get<std::string>();
  }

  if (!j.contains("reference_line") || !j.at("reference_line").is_array()) {
    fail("reference_line", "missing or not a list");
  }
  const json& ref = j.at("reference_line");
  if (ref.size() < 2) {
    fail("reference_line", "needs at least 2 points");
  }
  for (std::size_t i = 0; i < ref.size(); ++i) {
    const json& p = ref[i];
    if (!p.is_array() || p.size() != 2 || !p[0].is_number() || !p[1].is_number()) {
      fail(fmt::format("reference_line[{}]", i), "must be an [x, y] pair of numbers");
    }
    out.reference_line.push_back({p[0].get<double>(), p[1].get<double>()});
  }

  if (!j.contains("road") || !j.at("road").is_object()) {
    fail("road", "missing or not an object");
  }
  const json& road = j.at("road");
  out.road.lane_width = positive(road, "lane_width", "road");
  if (!road.contains("left_boundary")) {
    fail("road", "missing key \"left_boundary\"");
  }
  if (!road.contains("right_boundary")) {
    fail("road", "missing key \"right_boundary\"");
  }
  out.road.left_boundary = boundary_from_json(road.at("left_boundary"), "road.left_boundary");
  out.road.right_boundary = boundary_from_json(road.at("right_boundary"), "road.right_boundary");
  out.road.target_lane_offset = optional_number(road, "target_lane_offset", "road", 0.0);
  out.road.speed_limit = number(road, "speed_limit", "road");
  if (out.road.speed_limit < 0.0) {
    fail("road", "\"speed_limit\" must be >= 0");
  }

  if (!j.contains("ego") || !j.at("ego").is_object()) {
    fail("ego", "missing or not an object");
  }
  const json& e = j.at("ego");
  out.ego.x = number(e, "x", "ego");
  out.ego.y = number(e, "y", "ego");
  out.ego.heading = number(e, "heading", "ego");
  out.ego.v = number(e, "v", "ego");
  out.ego.a = optional_number(e, "a", "ego", 0.0);
  out.ego.kappa = optional_number(e, "kappa", "ego", 0.0);
  out.ego.length = positive(e, "length", "ego");
  out.ego.width = positive(e, "width", "ego");
  out.ego.wheelbase = positive(e, "wheelbase", "ego");

  if (j.contains("static_obstacles") && !j.at("static_obstacles").is_array()) {
    fail("static_obstacles", "not a list");
  }
  const json& st = j.contains("static_obstacles") ? j.at("static_obstacles") : json::array();
  for (std::size_t i = 0; i < st.size(); ++i) {
    const std::string where = fmt::format("static_obstacles[{}]", i);
    const json& o = st[i];
    StaticObstacle so;
    so.id = integer(o, "id", where);
    so.x = number(o, "x", where);
    so.y = number(o, "y", where);
    so.heading = number(o, "heading", where);
    so.length = positive(o, "length", where);
    so.width = positive(o, "width", where);
    so.kind = optional_kind(o);
    out.static_obstacles.push_back(std::move(so));
  }

  if (j.contains("dynamic_obstacles") && !j.at("dynamic_obstacles").is_array()) {
    fail("dynamic_obstacles", "not a list");
  }
  const json& dy = j.contains("dynamic_obstacles") ? j.at("dynamic_obstacles") : json::array();
  for (std::size_t i = 0; i < dy.size(); ++i) {
    const std::string where = fmt::format("dynamic_obstacles[{}]", i);
    const json& o = dy[i];
    DynamicObstacle d;
    d.id = integer(o, "id", where);
    d.length = positive(o, "length", where);
    d.width = positive(o, "width", where);
    d.kind = optional_kind(o);
    if (!o.contains("trajectory") || !o.at("trajectory").is_array() || o.at("trajectory").empty()) {
      fail(where, "\"trajectory\" missing, not a list or empty");
    }
    const json& tr = o.at("trajectory");
    for (std::size_t k = 0; k < tr.size(); ++k) {
      const std::string w2 = fmt::format("{}.trajectory[{}]", where, k);
      TimedPose p;
      p.t = number(tr[k], "t", w2);
      p.x = number(tr[k], "x", w2);
      p.y = number(tr[k], "y", w2);
      p.heading = number(tr[k], "heading", w2);
      p.v = number(tr[k], "v", w2);
      if (!d.trajectory.empty() && !(p.t > d.trajectory.back().t)) {
        fail(w2, "\"t\" must be strictly ascending");
      }
      d.trajectory.push_back(p);
    }
    out.dynamic_obstacles.push_back(std::move(d));
  }

  if (j.contains("duration")) {
    out.duration = positive(j, "duration", "<root>");
  }
  if (j.contains("tags")) {
    const json& tags = j.at("tags");
    if (!tags.is_array()) {
      fail("tags", "must be a list of strings");
    }
    for (const auto& t : tags) {
      if (!t.is_string()) {
        fail("tags", "must be a list of strings");
      }
      out.tags.push_back(t.get<std::string>());
    }
  }
  if (j.contains("lanes")) {
    const json& lanes = j.at("lanes");
    if (!lanes.is_array()) {
      fail("lanes", "must be a list of lanes");
    }
    for (std::size_t i = 0; i < lanes.size(); ++i) {
      const std::string where = fmt::format("lanes[{}]", i);
      const json& jl = lanes[i];
      if (!jl.is_object() || !jl.contains("id") || !jl.at("id").is_number_integer()) {
        fail(where, "must be an object with an integer \"id\"");
      }
      Lane lane;
      lane.id = jl.at("id").get<long>();
      auto points = [&](const char* key, std::vector<Point2>& line) {
        if (!jl.contains(key) || !jl.at(key).is_array() || jl.at(key).size() < 2) {
          fail(where, fmt::format("\"{}\" must be a list of at least 2 [x, y] points", key));
        }
        for (std::size_t k = 0; k < jl.at(key).size(); ++k) {
          const json& p = jl.at(key)[k];
          if (!p.is_array() || p.size() != 2 || !p[0].is_number() || !p[1].is_number() ||
              !std::isfinite(p[0].get<double>()) || !std::isfinite(p[1].get<double>())) {
            fail(fmt::format("{}.{}[{}]", where, key, k), "must be an [x, y] pair of finite numbers");
          }
          line.push_back({p[0].get<double>(), p[1].get<double>()});
        }
      };
      points("centre", lane.centre);
      points("left", lane.left);
      points("right", lane.right);
      if (jl.contains("successors")) {
        const json& succ = jl.at("successors");
        if (!succ.is_array()) fail(where, "\"successors\" must be a list of lane ids");
        for (const json& id : succ) {
          if (!id.is_number_integer()) fail(where, "\"successors\" must be a list of lane ids");
          lane.successors.push_back(id.get<long>());
        }
      }
      if (jl.contains("traffic_lights")) {
        const json& lights = jl.at("traffic_lights");
        if (!lights.is_array()) fail(where, "\"traffic_lights\" must be a list of traffic lights");
        for (std::size_t k = 0; k < lights.size(); ++k) {
          const std::string at = fmt::format("{}.traffic_lights[{}]", where, k);
          const json& jt = lights[k];
          if (!jt.is_object() || !jt.contains("cycle") || !jt.at("cycle").is_array() || jt.at("cycle").empty()) {
            fail(at, "must be an object with a non-empty \"cycle\"");
          }
          TrafficLightCycle c;
          for (const json& ph : jt.at("cycle")) {
            if (!ph.is_object() || !ph.contains("color") || !ph.at("color").is_string() || !ph.contains("duration") ||
                !ph.at("duration").is_number() || !(ph.at("duration").get<double>() > 0) ||
                !std::isfinite(ph.at("duration").get<double>())) {
              fail(at, "every cycle phase must be {\"color\": string, \"duration\": seconds > 0}");
            }
            c.cycle.push_back({ph.at("color").get<std::string>(), ph.at("duration").get<double>()});
          }
          if (jt.contains("time_offset")) {
            if (!jt.at("time_offset").is_number() || !std::isfinite(jt.at("time_offset").get<double>())) {
              fail(at, "\"time_offset\" must be a finite number of seconds");
            }
            c.time_offset = jt.at("time_offset").get<double>();
          }
          lane.traffic_lights.push_back(std::move(c));
        }
        if (!jl.contains("stop_s") || !jl.at("stop_s").is_number() || !std::isfinite(jl.at("stop_s").get<double>())) {
          fail(where, "a lane with \"traffic_lights\" needs \"stop_s\" (a finite number of metres)");
        }
        lane.stop_s = jl.at("stop_s").get<double>();
      }
      out.lanes.push_back(std::move(lane));
    }
  }
  w = std::move(out);
}

SceneParseResult parse_scene(const json& j) {
  SceneParseResult r;
  try {
    World w;
    from_json(j, w);
    r.world = std::move(w);
  } catch (const std::exception& ex) {
    r.error = ex.what();
  }
  return r;
}

SceneParseResult parse_scene_text(const std::string& text) {
  json j = json::parse(text, nullptr, /*allow_exceptions=*/false);
  if (j.is_discarded()) {
    SceneParseResult r;
    r.error = "scene/1: not valid JSON";
    return r;
  }
  return parse_scene(j);
}

SceneParseResult load_scene_file(const std::string& path) {
  std::ifstream in(path);
  if (!in) {
    SceneParseResult r;
    r.error = fmt::format("scene/1: cannot open '{}'", path);
    return r;
  }
  std::ostringstream ss;
  ss << in.rdbuf();
  SceneParseResult r = parse_scene_text(ss.str());
  if (!r) {
    r.error = fmt::format("{} ({})", r.error, path);
  }
  return r;
}

std::string scene_to_text(const World& w, int indent) {
  json j = w;
  return j.dump(indent) + "\n";
}

std::string save_scene_file(const World& w, const std::string& path) {
  std::ofstream out(path);
  if (!out) {
    return fmt::format("cannot write '{}'", path);
  }
  out << scene_to_text(w);
  return out ? std::string{} : fmt::format("error writing '{}'", path);
}

}  // namespace hil::sim
