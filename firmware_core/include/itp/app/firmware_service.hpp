#pragma once
// The target-independent heart of the firmware: received bytes in, reply
// frames out. The port's main loop moves bytes between the serial line and
// this object; framing, segments, authentication and dispatch happen here,
// where the host tests can reach them without any port.
//
// It is a class template on the planner configuration, chosen by the
// firmware image (port/common/firmware_config.hpp) and nowhere else, and on
// an Extension that serves further request types (a test image's QP check,
// app/qp_check_service.hpp). Every buffer is sized by the largest message of
// that configuration and extension.
#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <type_traits>

#include "itp/core/stack_probe.hpp"
#include "itp/core/tick_source.hpp"
#include "itp/link/crc32.hpp"
#include "itp/link/frame_decoder.hpp"
#include "itp/link/messages.hpp"
#include "itp/link/planner_messages.hpp"
#include "itp/link/secure_channel.hpp"
#include "itp/link/segments.hpp"
#include "itp/planner/planner.hpp"
#include "itp/scene/scene.hpp"
#include "itp/scene/validation.hpp"

namespace itp::app {

// The production image serves nothing beyond Ping, the session and planning.
struct NoExtension {
  static constexpr std::size_t kMaxRequestBytes = 0;  // [bytes] largest request body
  static constexpr std::size_t kMaxReplyBytes = 0;    // [bytes] largest reply body
  static constexpr bool serves(link::MessageType) { return false; }
  // Writes the reply body to `out` and its type to `reply_type`; 0: malformed request.
  std::size_t serve(link::MessageType, std::span<const std::uint8_t>, std::span<std::uint8_t>,
                    link::MessageType&, const TickSource&) {
    return 0;
  }
};

// An inbox's bytes borrowed from the planner's shared QP storage, which is
// free between cycles (planner.hpp, lend): a request is reassembled there
// and decoded before the cycle it asks for runs (link/segments.hpp, Bytes).
template <class Planner>
class PlannerLentBytes {
 public:
  void attach(Planner* planner) { planner_ = planner; }
  void take() { bytes_ = planner_->lend(this).data(); }
  bool kept() const { return planner_->lent_to(this); }
  std::uint8_t* data() { return bytes_; }

 private:
  Planner* planner_ = nullptr;
  std::uint8_t* bytes_ = nullptr;
};

template <class Cfg, class Extension = NoExtension>
class FirmwareService {
  static constexpr std::size_t max_of(std::size_t a, std::size_t b) { return a > b ? a : b; }

 public:
  // Largest messages in and out [bytes]: the secured Scene and Plan (or the
  // extension's), and the plain control messages.
  static constexpr std::size_t kMaxRequestBytes =
      max_of(max_of(link::kMaxSceneBytes<Cfg>, Extension::kMaxRequestBytes) + link::kSecuredOverhead,
             max_of(link::kHandshakeBytes, link::kSegmentReportBytes));
  static constexpr std::size_t kMaxReplyBytes =
      max_of(max_of(link::kMaxPlanBytes<Cfg>, Extension::kMaxReplyBytes) + link::kSecuredOverhead,
             max_of(link::kPongBytes, link::kDiagnosticsBytes));
  static_assert(kMaxRequestBytes <= link::kMaxMessageBytes && kMaxReplyBytes <= link::kMaxMessageBytes,
                "a message of this configuration does not fit the link");
  using Planner = planner::BasicPlanner<Cfg>;
  // Requests are reassembled in the planner's QP storage where it is shared
  // and large enough (docs/memory.md, "Lent storage"), else in the inbox's own bytes.
  static constexpr bool kInboxInQpStorage = Planner::kLendableBytes >= kMaxRequestBytes;
  using InboxBytes = std::conditional_t<kInboxInQpStorage, PlannerLentBytes<Planner>,
                                        link::InlineBytes<kMaxRequestBytes>>;
  using RequestInbox = link::Inbox<kMaxRequestBytes, InboxBytes>;

  // The firmware constructs it in place in zeroed static storage (.bss).
  FirmwareService() {
    if constexpr (kInboxInQpStorage) {
      inbox_.bytes().attach(&planner_);
    }
  }
  // `build_id` must outlive the service (a string literal in practice).
  void set_build_id(const char* build_id) { build_id_ = build_id; }
  // The port's counter, reported in Pong and used for per-stage timing.
  void set_tick_source(TickSource source) {
    ticks_ = source;
    planner_.set_tick_source(source);
  }
  // The long-term link key and this boot's entropy, from the port's key slot
  // (an HSM stand-in). Without both, every secured request is refused (no_key).
  void provision(std::span<const std::uint8_t> key, std::span<const std::uint8_t> entropy) {
    channel_.set_key(key);
    channel_.set_entropy(entropy);
  }

  // The port's stack measurement, reported in the Diagnostics reply.
  void set_stack_probe(StackProbe probe) { stack_ = probe; }

  // Feeds one received byte. Replies become available through next_frame().
  void on_byte(std::uint8_t byte) {
    if (decoder_.push(byte) == link::DecodeResult::kFrame) {
      on_frame(decoder_.frame());
    }
  }

  // The next wire frame to send (valid until the next call), or empty when
  // there is nothing to send. Control answers (Status) go before reply segments.
  std::span<const std::uint8_t> next_frame() {
    std::size_t n = control_.next_frame(tx_);
    if (n == 0) {
      n = outbox_.next_frame(tx_);
    }
    return std::span<const std::uint8_t>(tx_.data(), n);
  }

  link::FirmwareCounters counters() const {
    link::FirmwareCounters c = counters_;
    c.link = decoder_.counters();
    c.auth = channel_.counters();
    return c;
  }
  std::uint32_t replies_sent() const { return replies_; }
  bool in_session() const { return channel_.in_session(); }

 private:
  using Type = link::MessageType;

  void on_frame(const link::FrameView& frame) {
    if (frame.header.type == Type::kQuery) {
      answer_query(frame);
      return;
    }
    switch (inbox_.add(frame)) {
      case link::InboxResult::kComplete:
        ++counters_.messages;
        on_message(frame.header.answer_units);
        inbox_.clear();
        return;
      case link::InboxResult::kTooLarge:
        ++counters_.too_large;
        if ((frame.header.flags & link::kFlagPoll) != 0) {
          reply_error(frame.header.type, frame.header.sequence, link::ErrorCode::kTooLarge);
        }
        return;
      case link::InboxResult::kStored:
      case link::InboxResult::kDuplicate:
        if ((frame.header.flags & link::kFlagPoll) != 0) {
          send_status(frame.header.type, frame.header.sequence, inbox_.received());
        }
        return;
    }
  }

  // A Query names a request: resend the reply segments the host misses, or
  // say which request segments arrived (none, if the request is unknown).
  void answer_query(const link::FrameView& frame) {
    link::SegmentReport q;
    if (frame.header.segment_count != 1 || !link::decode(frame.chunk, q)) {
      return;  // a control message is one segment; anything else is noise that passed the CRC
    }
    const auto type = static_cast<Type>(q.type);
    if (outbox_.staged() && answered_type_ == type && outbox_.sequence() == q.sequence) {
      counters_.resent += static_cast<std::uint32_t>(outbox_.queue(q.segments));
      return;
    }
    link::SegmentSet none;
    send_status(type, q.sequence, inbox_.holds(type, q.sequence) ? inbox_.received() : none);
  }

  void send_status(Type type, std::uint16_t seq, const link::SegmentSet& have) {
    link::SegmentReport s;
    s.type = static_cast<std::uint8_t>(type);
    s.sequence = seq;
    s.segments = have;
    const std::size_t n = link::encode(s, control_.buffer());
    static_cast<void>(control_.stage(Type::kStatus, seq, n, link::kMaxSegmentBytes, 0, false));
  }

  void on_message(std::uint8_t answer_units) {
    const Type type = inbox_.type();
    const std::uint16_t seq = inbox_.sequence();
    const std::span<const std::uint8_t> message = inbox_.message();
    const std::uint32_t crc = link::crc32(message);
    // The request acted on last, complete again (a host that lost our reply
    // resent it, or a replay): answer it again, never act on it twice.
    if (processed_valid_ && type == processed_type_ && seq == processed_seq_ && crc == processed_crc_) {
      ++counters_.duplicates;
      if (outbox_.staged() && answered_type_ == type && outbox_.sequence() == seq) {
        outbox_.queue_all();
      } else {
        reply_auth_error(type, seq, link::AuthStatus::kStale);  // its answer is gone: a late repeat
      }
      return;
    }
    reply_segment_ = answer_units == 0 ? link::kMaxSegmentBytes : answer_units * link::kAnswerSegmentUnit;
    answered_type_ = type;
    std::span<const std::uint8_t> body = message;
    if (link::is_secured(type)) {
      const link::AuthStatus auth = channel_.open(type, seq, message, body);
      if (auth != link::AuthStatus::kOk) {
        reply_auth_error(type, seq, auth);  // counted by the channel; never acted on
        return;
      }
    }
    processed_type_ = type;
    processed_seq_ = seq;
    processed_crc_ = crc;
    processed_valid_ = true;
    dispatch(type, seq, body);
  }

  void dispatch(Type type, std::uint16_t seq, std::span<const std::uint8_t> body) {
    const std::span<std::uint8_t> out = outbox_.buffer();
    switch (type) {
      case Type::kPing: {
        link::Ping ping;
        if (!link::decode(body, ping)) {
          break;
        }
        link::Pong pong;
        pong.nonce = ping.nonce;
        link::set_build_id(pong, build_id_ != nullptr ? build_id_ : "");
        pong.counters = counters();
        pong.ticks = ticks_.ticks();
        pong.tick_hz = ticks_.hz;
        stage(Type::kPong, seq, link::encode(pong, out));
        return;
      }
      case Type::kDiagnosticsRequest: {
        // Read-only and not authenticated, like Ping (docs/protocol.md, threat model).
        if (!body.empty()) {
          break;
        }
        link::Diagnostics diag;
        diag.stack_bytes = stack_.size_bytes;
        diag.stack_peak_bytes = stack_.peak();
        stage(Type::kDiagnosticsReply, seq, link::encode(diag, out));
        return;
      }
      case Type::kSessionOpen: {
        const link::AuthStatus auth = channel_.challenge(seq, body, out);
        if (auth != link::AuthStatus::kOk) {
          reply_auth_error(type, seq, auth);
          return;
        }
        stage(Type::kSessionChallenge, seq, link::kHandshakeBytes);
        return;
      }
      case Type::kSessionConfirm: {
        const link::AuthStatus auth = channel_.confirm(seq, body);
        if (auth != link::AuthStatus::kOk) {
          reply_auth_error(type, seq, auth);
          return;
        }
        planner_.reset();  // a new session starts from a clean planner
        stage(Type::kSessionAccept, seq, channel_.seal(Type::kSessionAccept, seq, out, 0));
        return;
      }
      case Type::kPlanRequest: {
        const std::size_t n = plan_cycle(body, out.subspan(link::kFreshnessBytes));
        if (n == 0) {
          break;
        }
        stage(Type::kPlanReply, seq, channel_.seal(Type::kPlanReply, seq, out, n));
        return;
      }
      default: {
        if (!Extension::serves(type)) {
          reply_error(type, seq, link::ErrorCode::kUnsupportedMessage);
          return;
        }
        // An extension's requests and replies travel secured.
        Type reply_type = Type::kError;
        const std::size_t n = extension_.serve(type, body, out.subspan(link::kFreshnessBytes), reply_type, ticks_);
        if (n == 0 || !link::is_secured(reply_type)) {
          break;
        }
        stage(reply_type, seq, channel_.seal(reply_type, seq, out, n));
        return;
      }
    }
    reply_error(type, seq, link::ErrorCode::kMalformedPayload);
  }

  // One planning cycle. Every field is validated here, where it enters, with
  // the scene time: a scene that does not validate is never planned (the
  // planner's state, its previous plan and time, stay as they were), and
  // the reply repeats none of it: status invalid_input with the reason, no
  // trajectory (the vehicle's own safe stop applies) and origin (0, 0).
  std::size_t plan_cycle(std::span<const std::uint8_t> request, std::span<std::uint8_t> out) {
    link::SceneHeader header;
    if (!link::decode_scene(request, header, scene_)) {
      return 0;
    }
    link::PlanHeader ph;
    ph.cycle = header.cycle;
    ph.scene_crc = link::crc32(request);
    const Scalar now = static_cast<Scalar>(header.now);
    const scene::ValidationResult valid = scene::validate(scene_, now);
    if (!valid.ok()) {
      return link::encode_rejected_plan(ph, valid.reason, out);
    }
    if (header.reset) {
      planner_.reset();
    }
    const planner::BasicPlan<Cfg>& plan = planner_.plan(planner::BasicPlanRequest<Cfg>{&scene_, now});
    ph.origin_x = static_cast<double>(scene_.reference_line[0].x);  // validated: >= 2 finite points
    ph.origin_y = static_cast<double>(scene_.reference_line[0].y);
    return link::encode_plan(ph, plan, out);
  }

  void reply_error(Type type, std::uint16_t seq, link::ErrorCode code) {
    answered_type_ = type;
    const link::ErrorReply err{code, static_cast<std::uint8_t>(type)};
    stage(Type::kError, seq, link::encode(err, outbox_.buffer()));
  }

  void reply_auth_error(Type type, std::uint16_t seq, link::AuthStatus why) {
    answered_type_ = type;
    const link::AuthErrorReply err{why, static_cast<std::uint8_t>(type)};
    stage(Type::kAuthError, seq, link::encode(err, outbox_.buffer()));
  }

  // Queues the reply in outbox_.buffer()[0, n) for sending, in the segment
  // size the request asked for.
  void stage(Type type, std::uint16_t seq, std::size_t n) {
    if (n == 0) {
      return;  // an encoder or seal that did not fit: no reply (the host's Query then gets a Status)
    }
    if (outbox_.stage(type, seq, n, reply_segment_, 0, false)) {
      ++replies_;
    }
  }

  const char* build_id_ = nullptr;
  TickSource ticks_{};
  StackProbe stack_{};
  link::FrameDecoder decoder_;                     // one segment frame
  RequestInbox inbox_;                             // the request being reassembled
  link::Outbox<kMaxReplyBytes> outbox_;            // the last reply (resent on a Query)
  link::Outbox<link::kSegmentReportBytes> control_;  // a Status
  std::array<std::uint8_t, link::kMaxWireFrameBytes> tx_{};  // the frame next_frame() returns
  link::SecureChannel channel_{link::Role::kFirmware};
  link::FirmwareCounters counters_{};
  std::uint32_t replies_ = 0;
  std::size_t reply_segment_ = link::kMaxSegmentBytes;  // [bytes] segment size of the reply
  // The request type outbox_ answers (with the request's sequence number).
  Type answered_type_{};
  // The request acted on last (a complete repeat of it is answered, not acted on).
  Type processed_type_{};
  std::uint16_t processed_seq_ = 0;
  std::uint32_t processed_crc_ = 0;
  bool processed_valid_ = false;

  // Planning service: one cycle per Scene message.
  scene::BasicScene<Cfg> scene_{};
  Planner planner_{};  // holds the cycle's plan until it is encoded
  Extension extension_{};
};

}  // namespace itp::app
