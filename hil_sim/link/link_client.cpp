#include "link/link_client.hpp"

#include <algorithm>
#include <array>
#include <random>
#include <thread>

#include "itp/link/frame.hpp"
#include "itp/link/messages.hpp"

namespace hil {

namespace link = itp::link;
using link::MessageType;

struct LinkClient::Boxes {
  link::Outbox<link::kMaxMessageBytes> out;  // the request being sent
  link::Inbox<link::kMaxMessageBytes> in;    // the reply being reassembled
  link::SecureChannel channel{link::Role::kHost};
  std::array<std::uint8_t, link::kMaxWireFrameBytes> wire{};
};

LinkClient::LinkClient(ByteTransport& transport, ClientPacing pacing)
    : transport_(transport), pacing_(pacing), boxes_(std::make_unique<Boxes>()), segment_(pacing.max_segment) {}

LinkClient::~LinkClient() = default;

void LinkClient::set_key(std::span<const std::uint8_t> key) { boxes_->channel.set_key(key); }

bool LinkClient::in_session() const { return boxes_->channel.in_session(); }

const itp::link::AuthCounters& LinkClient::auth_counters() const { return boxes_->channel.counters(); }

bool LinkClient::send_queued() {
  Boxes& b = *boxes_;
  for (std::size_t k = 0; k < link::kMaxSegments; ++k) {
    const std::size_t n = b.out.next_frame(b.wire);
    if (n == 0) {
      return true;
    }
    if (!transport_.write_all(std::span<const std::uint8_t>(b.wire.data(), n))) {
      return false;
    }
  }
  return true;
}

std::optional<Reply> LinkClient::exchange(MessageType type, std::span<const std::uint8_t> body,
                                          Clock::time_point deadline) {
  Boxes& b = *boxes_;
  const std::uint16_t seq = next_sequence_++;
  const std::span<std::uint8_t> buf = b.out.buffer();
  std::size_t length = 0;
  if (link::is_secured(type)) {
    if (body.size() + link::kSecuredOverhead > buf.size()) {
      return std::nullopt;
    }
    std::copy(body.begin(), body.end(), buf.begin() + link::kFreshnessBytes);
    length = b.channel.seal(type, seq, buf, body.size());
    if (length == 0) {
      return std::nullopt;
    }
  } else {
    if (body.size() > buf.size()) {
      return std::nullopt;
    }
    std::copy(body.begin(), body.end(), buf.begin());
    length = body.size();
  }
  const auto units = static_cast<std::uint8_t>(std::clamp<std::size_t>(segment_ / link::kAnswerSegmentUnit, 1, 255));
  if (!b.out.stage(type, seq, length, segment_, units, true)) {
    return std::nullopt;
  }
  ++counters_.requests;
  if (!send_queued()) {
    return std::nullopt;
  }
  b.in.clear();
  bool loss = false;      // segments went missing in either direction
  bool answered = false;  // the firmware has sent something for this request
  auto last_activity = Clock::now();  // last byte received or Query sent
  auto last_nudge_ref = Clock::now(); // last byte received or nudge sent
  bool mid_frame = false;             // the last byte received was not a delimiter
  std::array<std::uint8_t, 4096> rx{};
  const auto take_backlog = [&] {  // bytes read past an earlier reply come first
    const std::size_t k = std::min(backlog_.size(), rx.size());
    std::copy_n(backlog_.begin(), k, rx.begin());
    backlog_.erase(backlog_.begin(), backlog_.begin() + static_cast<std::ptrdiff_t>(k));
    return k;
  };
  const auto adapt = [&](bool lost) {
    segment_ = lost ? std::max(pacing_.min_segment, segment_ / 2) : std::min(pacing_.max_segment, segment_ * 2);
  };
  std::size_t got = take_backlog();
  while (got > 0 || Clock::now() < deadline) {
    for (std::size_t i = 0; i < got; ++i) {
      mid_frame = rx[i] != 0u;
      if (decoder_.push(rx[i]) != link::DecodeResult::kFrame) {
        continue;
      }
      const link::FrameView& f = decoder_.frame();
      if (f.header.sequence != seq) {
        ++counters_.stale_replies;
        continue;
      }
      answered = true;
      if (f.header.type == MessageType::kStatus) {
        link::SegmentReport report;
        if (f.header.segment_count == 1 && link::decode(f.chunk, report) &&
            report.type == static_cast<std::uint8_t>(type) && report.sequence == seq) {
          ++counters_.statuses;
          const std::size_t n = b.out.queue(report.segments.missing(b.out.segment_count()));
          if (n > 0) {
            loss = true;
            counters_.segments_resent += static_cast<std::uint32_t>(n);
            if (!send_queued()) {
              return std::nullopt;
            }
          }
        }
        continue;
      }
      if (f.header.type == MessageType::kQuery || b.in.add(f) != link::InboxResult::kComplete) {
        continue;
      }
      Reply reply{b.in.type(), seq, {}};
      const std::span<const std::uint8_t> message = b.in.message();
      if (link::is_secured(reply.type)) {
        std::span<const std::uint8_t> opened;
        if (b.channel.open(reply.type, seq, message, opened) != link::AuthStatus::kOk) {
          ++counters_.auth_refused;  // forged, replayed or of another session: not a reply
          b.in.clear();
          continue;
        }
        reply.payload.assign(opened.begin(), opened.end());
      } else {
        reply.payload.assign(message.begin(), message.end());
      }
      counters_.auth_errors += reply.type == MessageType::kAuthError ? 1u : 0u;
      ++counters_.replies;
      backlog_.insert(backlog_.begin(), rx.begin() + static_cast<std::ptrdiff_t>(i + 1),
                      rx.begin() + static_cast<std::ptrdiff_t>(got));
      b.in.clear();
      adapt(loss);
      return reply;
    }
    got = take_backlog();
    if (got > 0) {
      continue;
    }
    auto now = Clock::now();
    if (now >= deadline) {
      break;
    }
    // Quiet for too long: ask for what is missing (all of the reply if none came).
    const auto quiet = answered ? pacing_.gap : pacing_.first_gap;
    if (now - last_activity >= quiet) {
      link::SegmentReport q;
      q.type = static_cast<std::uint8_t>(type);
      q.sequence = seq;
      if (b.in.active() && b.in.sequence() == seq) {
        q.segments = b.in.received().missing(b.in.segment_count());
        loss = true;
      } else {
        q.segments.fill_first(link::kMaxSegments);
      }
      std::array<std::uint8_t, link::kSegmentReportBytes> qbody{};
      const std::size_t qn = link::encode(q, qbody);
      const std::size_t wn = link::encode_frame(MessageType::kQuery, seq,
                                                std::span<const std::uint8_t>(qbody.data(), qn), b.wire);
      if (!transport_.write_all(std::span<const std::uint8_t>(b.wire.data(), wn))) {
        break;
      }
      ++counters_.queries;
      last_activity = now;
      last_nudge_ref = now;
    } else if (pacing_.nudge_after.count() > 0 && now - last_nudge_ref >= pacing_.nudge_after) {
      static constexpr std::array<std::uint8_t, 1> kDelimiter{0u};
      if (!transport_.write_all(kDelimiter)) {
        break;  // peer gone
      }
      ++counters_.nudges;
      last_nudge_ref = now;
    }
    if (mid_frame && pacing_.frame_settle.count() > 0) {
      // Let the rest of the frame pile up in the pipe instead of waking per byte.
      std::this_thread::sleep_for(std::min<Clock::duration>(pacing_.frame_settle, deadline - now));
      now = Clock::now();
    }
    Clock::duration wait = deadline - now;
    wait = std::min<Clock::duration>(wait, quiet - (now - last_activity));
    if (pacing_.nudge_after.count() > 0) {
      wait = std::min<Clock::duration>(wait, pacing_.nudge_after - (now - last_nudge_ref));
    }
    const auto wait_ms = std::max(std::chrono::ceil<std::chrono::milliseconds>(wait), std::chrono::milliseconds(1));
    got = transport_.read_some(rx, wait_ms);
    if (got > 0) {
      last_activity = Clock::now();
      last_nudge_ref = last_activity;
    }
  }
  ++counters_.timeouts;
  adapt(true);
  return std::nullopt;
}

bool LinkClient::handshake(Clock::time_point deadline) {
  Boxes& b = *boxes_;
  std::array<std::uint8_t, link::kNonceBytes> nonce{};
  std::random_device rd;  // the host's nonce must never repeat
  for (auto& x : nonce) {
    x = static_cast<std::uint8_t>(rd());
  }
  std::array<std::uint8_t, link::kHandshakeBytes> body{};
  const std::size_t n = b.channel.start_handshake(nonce, body);
  const auto challenge = exchange(MessageType::kSessionOpen, std::span<const std::uint8_t>(body.data(), n), deadline);
  if (!challenge || challenge->type != MessageType::kSessionChallenge) {
    return false;
  }
  const std::uint16_t confirm_seq = next_sequence_;  // exchange() takes it next
  if (b.channel.answer_challenge(challenge->sequence, challenge->payload, confirm_seq, body) != link::AuthStatus::kOk) {
    return false;
  }
  const auto accept = exchange(MessageType::kSessionConfirm, body, deadline);
  if (!accept || accept->type != MessageType::kSessionAccept || !b.channel.in_session()) {
    return false;
  }
  ++counters_.sessions;
  return true;
}

bool LinkClient::open_session(std::chrono::milliseconds deadline) {
  return handshake(Clock::now() + deadline);
}

std::optional<Reply> LinkClient::request(MessageType type, std::span<const std::uint8_t> body,
                                         std::chrono::milliseconds deadline) {
  const auto until = Clock::now() + deadline;
  std::optional<Reply> reply;
  for (int attempt = 0; attempt < 3; ++attempt) {  // a lost session is re-established at most twice
    if (link::is_secured(type) && !boxes_->channel.in_session() && !handshake(until)) {
      return std::nullopt;
    }
    reply = exchange(type, body, until);
    if (!reply || reply->type != MessageType::kAuthError || !link::is_secured(type)) {
      return reply;
    }
    link::AuthErrorReply err;
    if (!link::decode(reply->payload, err) ||
        (err.code != link::AuthStatus::kNoSession && err.code != link::AuthStatus::kBadTag &&
         err.code != link::AuthStatus::kStale)) {
      return reply;  // no key on the firmware: a new session would not help
    }
    boxes_->channel.end_session();
  }
  return reply;
}

void LinkClient::resync() {
  backlog_.clear();
  decoder_.push(0u);  // a delimiter ends any partial frame; counted if it was bad
}

}  // namespace hil
