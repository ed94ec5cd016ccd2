// Writes the seed corpus of the fuzz targets (tests/fuzz/corpus/<target>/):
// valid frames and messages of every kind, real Scenes of generated worlds,
// small scene/1 and CommonRoad files, so that fuzzing starts from inputs
// that reach deep. Run: fuzz_write_seeds tests/fuzz/corpus
#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include "itp/link/frame.hpp"
#include "itp/link/messages.hpp"
#include "itp/link/planner_messages.hpp"
#include "itp/link/segments.hpp"
#include "sim/commonroad_xml.hpp"
#include "sim/scene_convert.hpp"
#include "sim/scene_generator.hpp"
#include "sim/world.hpp"

namespace {

namespace link = itp::link;
using Bytes = std::vector<std::uint8_t>;

void write(const std::filesystem::path& dir, const std::string& name, const Bytes& bytes) {
  std::filesystem::create_directories(dir);
  std::ofstream out(dir / name, std::ios::binary);
  out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
}

Bytes frames_of(link::MessageType type, std::uint16_t seq, const Bytes& message, std::size_t segment) {
  static link::Outbox<link::kMaxMessageBytes> box;
  std::copy(message.begin(), message.end(), box.buffer().begin());
  box.stage(type, seq, message.size(), segment, static_cast<std::uint8_t>(segment / 8), true);
  Bytes out;
  std::array<std::uint8_t, link::kMaxWireFrameBytes> wire{};
  for (std::size_t n = box.next_frame(wire); n > 0; n = box.next_frame(wire)) out.insert(out.end(), wire.begin(), wire.begin() + static_cast<long>(n));
  return out;
}

Bytes scene_body(std::uint64_t seed, int index) {
  const hil::sim::World w = hil::sim::generate_scene(seed, index);
  auto scene = std::make_unique<itp::scene::Scene>();
  hil::sim::make_planner_scene(w, hil::sim::ego_at_start(w), 0.0, hil::sim::Prediction::kConstantVelocity, *scene);
  Bytes body(link::kMaxSceneBytes<itp::DefaultConfig>);
  body.resize(link::encode_scene(link::SceneHeader{1, 0.0, true}, *scene, 5, body));
  return body;
}

Bytes ping(std::uint32_t nonce) {
  Bytes b(link::kPingBytes);
  link::encode(link::Ping{nonce}, b);
  return b;
}

// A service_framed record: kind, length, bytes.
void record(Bytes& out, std::uint8_t kind, const Bytes& bytes) {
  out.push_back(kind);
  out.push_back(static_cast<std::uint8_t>(bytes.size() & 0xFF));
  out.push_back(static_cast<std::uint8_t>(bytes.size() >> 8));
  out.insert(out.end(), bytes.begin(), bytes.end());
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: fuzz_write_seeds CORPUS_DIR\n");
    return 2;
  }
  const std::filesystem::path root = argv[1];
  const Bytes scene = scene_body(1, 3);
  const Bytes busy = scene_body(1, 7);

  // Frame decoder: single frames, a message in segments, control messages.
  write(root / "frame_decoder", "ping", frames_of(link::MessageType::kPing, 1, ping(7), 1024));
  write(root / "frame_decoder", "scene_in_64_byte_segments", frames_of(link::MessageType::kPlanRequest, 2, scene, 64));
  link::SegmentReport q;
  q.type = 0x20;
  q.sequence = 2;
  q.segments.fill_first(9);
  Bytes qb(link::kSegmentReportBytes);
  link::encode(q, qb);
  write(root / "frame_decoder", "query", frames_of(link::MessageType::kQuery, 2, qb, 1024));
  write(root / "frame_decoder", "long_block", frames_of(link::MessageType::kPong, 3, Bytes(600, 0x41), 1024));

  // The service on raw bytes: pings, a session opening, a Scene nobody sealed.
  Bytes raw = frames_of(link::MessageType::kPing, 1, ping(1), 1024);
  const Bytes nonce(link::kNonceBytes, 0x33);
  Bytes open = frames_of(link::MessageType::kSessionOpen, 2, nonce, 1024);
  raw.insert(raw.end(), open.begin(), open.end());
  write(root / "service_raw", "ping_open", raw);
  Bytes unsealed(scene.size() + link::kSecuredOverhead, 0);
  std::copy(scene.begin(), scene.end(), unsealed.begin() + link::kFreshnessBytes);
  write(root / "service_raw", "unsealed_scene", frames_of(link::MessageType::kPlanRequest, 3, unsealed, 256));
  write(root / "service_raw", "query", frames_of(link::MessageType::kQuery, 9, qb, 1024));

  // The service with a session: records of sealed Scenes and more.
  Bytes framed;
  record(framed, 0 | (5 << 2), scene);
  write(root / "service_framed", "one_scene", framed);
  Bytes two;
  record(two, 0 | (5 << 2), busy);
  record(two, 0 | (0 << 2), scene);
  record(two, 2, qb);
  Bytes plain_ping{0x01};
  const Bytes pb = ping(5);
  plain_ping.insert(plain_ping.end(), pb.begin(), pb.end());
  record(two, 3, plain_ping);
  write(root / "service_framed", "two_scenes_query_ping", two);

  // scene/1: generated worlds (tests/scene/data is a seed directory too).
  for (int i : {0, 5}) {
    hil::sim::World w = hil::sim::generate_scene(2, i);
    for (auto& d : w.dynamic_obstacles) {
      if (d.trajectory.size() > 20) d.trajectory.resize(20);  // small seeds fuzz faster
    }
    const std::string text = hil::sim::scene_to_text(w, -1);
    write(root / "scene_json", "generated_" + std::to_string(i) + ".json", Bytes(text.begin(), text.end()));
  }

  // CommonRoad: two small hand-written scenarios.
  using namespace commonroad_xml;
  const std::string straight =
      scenario(lanelet(1, 0, 150, -1.75, 3.5) + planning_problem(100, 5, 0, 0, 10));
  write(root / "commonroad", "straight.xml", Bytes(straight.begin(), straight.end()));
  const std::string traffic = scenario(
      lanelet(1, 0, 150, -1.75, 3.5, "<adjacentLeft ref=\"2\" drivingDir=\"same\"/>") +
      lanelet(2, 0, 150, 1.75, 3.5, "<adjacentRight ref=\"1\" drivingDir=\"same\"/>") +
      "<dynamicObstacle id=\"7\"><type>car</type><shape><rectangle><length>4.5</length><width>1.8</width></rectangle></shape>"
      "<initialState>" + state(30, 3.5, 0, 0, 8) + "</initialState><trajectory><state>" + state(30.8, 3.5, 0, 1, 8) +
      "</state></trajectory></dynamicObstacle>\n" +
      planning_problem(100, 5, 0, 0, 10));
  write(root / "commonroad", "two_lanes_one_car.xml", Bytes(traffic.begin(), traffic.end()));
  std::printf("seeds written to %s\n", root.string().c_str());
  return 0;
}
