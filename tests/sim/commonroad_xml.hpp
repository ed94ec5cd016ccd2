#pragma once
// Small hand-written CommonRoad XML scenarios for the importer's tests.
#include <string>
#include <vector>

#include <fmt/format.h>

namespace commonroad_xml {

inline std::string point(double x, double y) { return fmt::format("<point><x>{}</x><y>{}</y></point>", x, y); }

// A straight lanelet along +x (or -x when `reversed`) from x0 to x1, its right
// bound at y_right (in its own driving direction), `width` wide, points every 5 m.
inline std::string lanelet(long id, double x0, double x1, double y_right, double width, const std::string& extra = "",
                           bool reversed = false) {
  std::string left, right;
  const int n = static_cast<int>((x1 - x0) / 5.0 + 0.5);
  for (int i = 0; i <= n; ++i) {
    const double u = static_cast<double>(i) / n;
    const double x = reversed ? x1 - u * (x1 - x0) : x0 + u * (x1 - x0);
    const double yl = reversed ? y_right - width : y_right + width;
    left += point(x, yl);
    right += point(x, y_right);
  }
  return fmt::format("<lanelet id=\"{}\"><leftBound>{}</leftBound><rightBound>{}</rightBound>{}"
                     "<laneletType>urban</laneletType></lanelet>\n",
                     id, left, right, extra);
}

inline std::string planning_problem(long id, double x, double y, double orientation, double v,
                                    const std::string& extra_state = "", const std::string& goal_position = "",
                                    int goal_end = 50) {
  return fmt::format(
      "<planningProblem id=\"{}\"><initialState><position>{}</position><orientation><exact>{}</exact></orientation>"
      "<time><exact>0</exact></time><velocity><exact>{}</exact></velocity>{}<yawRate><exact>0</exact></yawRate>"
      "<slipAngle><exact>0</exact></slipAngle></initialState>"
      "<goalState>{}<time><intervalStart>0</intervalStart><intervalEnd>{}</intervalEnd></time></goalState>"
      "</planningProblem>\n",
      id, point(x, y), orientation, v, extra_state, goal_position, goal_end);
}

inline std::string scenario(const std::string& body, const std::string& version = "2020a") {
  return fmt::format(
      "<?xml version=\"1.0\" ?>\n<commonRoad commonRoadVersion=\"{}\" benchmarkID=\"ZAM_Test-1_1_T-1\" "
      "timeStepSize=\"0.1\" author=\"test\" affiliation=\"test\" source=\"test\" date=\"2024-01-01\">\n{}</commonRoad>\n",
      version, body);
}

inline std::string state(double x, double y, double orientation, int step, double v) {
  return fmt::format("<position>{}</position><orientation><exact>{}</exact></orientation>"
                     "<time><exact>{}</exact></time><velocity><exact>{}</exact></velocity>",
                     point(x, y), orientation, step, v);
}

}  // namespace commonroad_xml
