// Inbox and Outbox (itp/link/segments.hpp): a message cut into segments by
// an Outbox comes back whole from an Inbox in any order, duplicates
// included; what a receiver reports missing is exactly what is resent.
#include <doctest/doctest.h>

#include <algorithm>
#include <memory>
#include <random>
#include <vector>

#include "frame_helpers.hpp"
#include "itp/link/segments.hpp"

using namespace itp::link;

namespace {

constexpr std::size_t kCap = 12000;

// The frames an outbox produces now, each decoded.
std::vector<std::vector<std::uint8_t>> drain(Outbox<kCap>& out) {
  std::vector<std::vector<std::uint8_t>> frames;
  std::vector<std::uint8_t> wire(kMaxWireFrameBytes);
  for (std::size_t n = out.next_frame(wire); n > 0; n = out.next_frame(wire)) {
    frames.emplace_back(wire.begin(), wire.begin() + static_cast<long>(n));
  }
  return frames;
}

}  // namespace

TEST_CASE("a message reassembles from shuffled and duplicated segments") {
  std::mt19937 rng(3);
  auto out = std::make_unique<Outbox<kCap>>();
  auto in = std::make_unique<Inbox<kCap>>();
  for (std::size_t length : {0u, 1u, 64u, 1500u, 9963u}) {
    const auto message = link_test::random_bytes(rng, length, 5);
    std::copy(message.begin(), message.end(), out->buffer().begin());
    REQUIRE(out->stage(MessageType::kPlanRequest, 9, length, 100, 0, false));
    auto frames = drain(*out);
    REQUIRE(frames.size() == segments_for(length, 100));
    const auto copy = frames;
    frames.insert(frames.end(), copy.begin(), copy.begin() + static_cast<long>(copy.size() / 2));  // duplicates
    std::shuffle(frames.begin(), frames.end(), rng);
    FrameDecoder dec;
    int complete = 0;
    in->clear();
    for (const auto& f : frames) {
      REQUIRE(link_test::feed(dec, f) == 1);
      const InboxResult r = in->add(dec.frame());
      complete += r == InboxResult::kComplete ? 1 : 0;
      if (complete > 0 && r != InboxResult::kComplete) {
        CHECK(r == InboxResult::kDuplicate);  // after completion only repeats arrive
      }
    }
    CHECK(complete == 1);
    CHECK(std::vector<std::uint8_t>(in->message().begin(), in->message().end()) == message);
  }
}

TEST_CASE("an inbox restarts on another message and refuses one beyond its capacity") {
  auto out = std::make_unique<Outbox<kCap>>();
  auto in = std::make_unique<Inbox<2000>>();
  FrameDecoder dec;
  REQUIRE(out->stage(MessageType::kPlanRequest, 1, 300, 100, 0, false));
  auto a = drain(*out);
  REQUIRE(link_test::feed(dec, a[0]) == 1);
  CHECK(in->add(dec.frame()) == InboxResult::kStored);
  REQUIRE(out->stage(MessageType::kPlanRequest, 2, 300, 100, 0, false));  // the sender moved on
  auto b = drain(*out);
  for (std::size_t i = 0; i < b.size(); ++i) {
    REQUIRE(link_test::feed(dec, b[i]) == 1);
    CHECK(in->add(dec.frame()) == (i + 1 == b.size() ? InboxResult::kComplete : InboxResult::kStored));
  }
  CHECK(in->sequence() == 2);
  REQUIRE(out->stage(MessageType::kPlanRequest, 3, 2001, 1024, 0, false));
  auto c = drain(*out);
  REQUIRE(link_test::feed(dec, c[0]) == 1);
  CHECK(in->add(dec.frame()) == InboxResult::kTooLarge);
}

namespace {

// Borrowed bytes whose owner a test can take back (as a plan() takes the
// planner's QP storage back from the firmware's inbox).
struct LentForTest {
  std::vector<std::uint8_t>* bytes = nullptr;
  bool* kept_flag = nullptr;
  void take() { *kept_flag = true; }
  bool kept() const { return *kept_flag; }
  std::uint8_t* data() { return bytes->data(); }
};

}  // namespace

TEST_CASE("an inbox in borrowed bytes starts its message again when the owner used them meanwhile") {
  std::vector<std::uint8_t> storage(2000);
  bool kept = false;
  Inbox<2000, LentForTest> in;
  in.bytes() = LentForTest{&storage, &kept};
  auto out = std::make_unique<Outbox<kCap>>();
  std::mt19937 rng(7);
  const auto message = link_test::random_bytes(rng, 1000, 5);
  std::copy(message.begin(), message.end(), out->buffer().begin());
  REQUIRE(out->stage(MessageType::kPlanRequest, 4, message.size(), 100, 0, false));
  const auto frames = drain(*out);
  REQUIRE(frames.size() == 10);
  FrameDecoder dec;
  for (std::size_t i = 0; i < 5; ++i) {
    REQUIRE(link_test::feed(dec, frames[i]) == 1);
    CHECK(in.add(dec.frame()) == InboxResult::kStored);
  }
  CHECK(in.holds(MessageType::kPlanRequest, 4));
  CHECK(in.received().count() == 5);
  kept = false;  // the owner used the bytes: what they held is gone
  std::fill(storage.begin(), storage.end(), std::uint8_t{0xEE});
  CHECK_FALSE(in.holds(MessageType::kPlanRequest, 4));  // a Query then hears "none held"
  REQUIRE(link_test::feed(dec, frames[5]) == 1);
  CHECK(in.add(dec.frame()) == InboxResult::kStored);
  CHECK(in.received().count() == 1);  // only the segment that came after
  for (std::size_t i : {0u, 1u, 2u, 3u, 6u, 7u, 8u}) {
    REQUIRE(link_test::feed(dec, frames[i]) == 1);
    CHECK(in.add(dec.frame()) == InboxResult::kStored);
  }
  REQUIRE(link_test::feed(dec, frames[4]) == 1);
  CHECK(in.add(dec.frame()) == InboxResult::kStored);
  REQUIRE(link_test::feed(dec, frames[9]) == 1);
  CHECK(in.add(dec.frame()) == InboxResult::kComplete);
  CHECK(std::vector<std::uint8_t>(in.message().begin(), in.message().end()) == message);
}

TEST_CASE("an outbox resends exactly the segments reported missing, polling with the last") {
  auto out = std::make_unique<Outbox<kCap>>();
  auto in = std::make_unique<Inbox<kCap>>();
  REQUIRE(out->stage(MessageType::kPlanRequest, 4, 1000, 64, 8, true));
  auto frames = drain(*out);
  REQUIRE(frames.size() == 16);
  FrameDecoder dec;
  for (std::size_t i = 0; i < frames.size(); ++i) {
    REQUIRE(link_test::feed(dec, frames[i]) == 1);
    CHECK(dec.frame().header.answer_units == 8);
    CHECK(((dec.frame().header.flags & kFlagPoll) != 0) == (i + 1 == frames.size()));
    if (i % 3 != 1) {
      in->add(dec.frame());  // segments 1, 4, 7, 10, 13 are "lost"
    }
  }
  const SegmentSet missing = in->received().missing(in->segment_count());
  CHECK(missing.count() == 5);
  CHECK(out->queue(missing) == 5);
  auto again = drain(*out);
  REQUIRE(again.size() == 5);
  int completed = 0;
  for (std::size_t i = 0; i < again.size(); ++i) {
    REQUIRE(link_test::feed(dec, again[i]) == 1);
    CHECK(dec.frame().header.segment_index == 1 + 3 * i);
    CHECK(((dec.frame().header.flags & kFlagPoll) != 0) == (i + 1 == again.size()));
    completed += in->add(dec.frame()) == InboxResult::kComplete ? 1 : 0;
  }
  CHECK(completed == 1);
  CHECK(drain(*out).empty());
}
