#pragma once
// Messages in segments (docs/protocol.md, "Segments and retransmission"):
// an Inbox reassembles one message from its segment frames in any order,
// ignoring duplicates; an Outbox holds one message and hands out the wire
// frames of the segments queued for sending (all of them, or those the peer
// reports missing). Both ends use them; capacities are template parameters,
// so a firmware image sizes them by its largest message.
#include <array>
#include <cstddef>
#include <cstdint>
#include <span>

#include "itp/link/frame.hpp"
#include "itp/link/frame_decoder.hpp"

namespace itp::link {

// One bit per segment index (kMaxSegments = 255 fits 32 bytes).
class SegmentSet {
 public:
  static constexpr std::size_t kBytes = 32;
  void clear() { bits_.fill(0); }
  void fill_first(std::size_t count);  // indices 0 .. count-1
  void set(std::size_t i) { bits_[i / 8] = static_cast<std::uint8_t>(bits_[i / 8] | bit(i)); }
  void reset(std::size_t i) { bits_[i / 8] = static_cast<std::uint8_t>(bits_[i / 8] & ~bit(i)); }
  bool test(std::size_t i) const { return i < 8 * kBytes && (bits_[i / 8] & bit(i)) != 0u; }
  std::size_t count() const;
  // The complement within 0 .. count-1 (what a receiver holding *this misses).
  SegmentSet missing(std::size_t count) const;
  const std::array<std::uint8_t, kBytes>& bytes() const { return bits_; }
  std::array<std::uint8_t, kBytes>& bytes() { return bits_; }

 private:
  static constexpr unsigned bit(std::size_t i) { return 1u << (i % 8u); }
  std::array<std::uint8_t, kBytes> bits_{};
};

enum class InboxResult : std::uint8_t {
  kStored,     // a new segment of an incomplete message
  kDuplicate,  // a segment it already holds (retransmissions overlap)
  kComplete,   // this segment completed the message
  kTooLarge,   // the message exceeds the capacity: dropped
};

// Where an Inbox reassembles: bytes of its own (InlineBytes), or bytes it
// borrows between uses by their owner (the firmware borrows the planner's
// QP storage between cycles, app/firmware_service.hpp). A Bytes type has
//   void take();                 claim the buffer for the inbox
//   bool kept() const;           nobody else used it since the last take()
//   std::uint8_t* data();        the buffer (Capacity bytes)
template <std::size_t Capacity>
class InlineBytes {
 public:
  void take() {}
  bool kept() const { return true; }
  std::uint8_t* data() { return bytes_.data(); }

 private:
  std::array<std::uint8_t, Capacity> bytes_{};
};

// Reassembles one message at a time. A segment of another message (type,
// sequence number, length or count differ) starts that message afresh: the
// sender has moved on, or the old one was never going to complete. So does
// one whose borrowed bytes their owner used meanwhile (its segments are
// then asked for again, like lost ones).
template <std::size_t Capacity, class Bytes = InlineBytes<Capacity>>
class Inbox {
 public:
  InboxResult add(const FrameView& frame) {
    const FrameHeader& h = frame.header;
    if (h.message_length > Capacity) {
      return InboxResult::kTooLarge;
    }
    if (!active_ || h.type != type_ || h.sequence != sequence_ || h.message_length != length_ ||
        h.segment_count != count_ || !bytes_.kept()) {
      bytes_.take();
      active_ = true;
      type_ = h.type;
      sequence_ = h.sequence;
      length_ = h.message_length;
      count_ = h.segment_count;
      have_.clear();
    }
    if (have_.test(h.segment_index)) {
      return InboxResult::kDuplicate;
    }
    const std::size_t offset = segment_offset(length_, count_, h.segment_index);
    std::uint8_t* const buffer = bytes_.data();
    for (std::size_t k = 0; k < frame.chunk.size(); ++k) {  // <= kMaxSegmentBytes
      buffer[offset + k] = frame.chunk[k];
    }
    have_.set(h.segment_index);
    return have_.count() == count_ ? InboxResult::kComplete : InboxResult::kStored;
  }

  bool active() const { return active_; }
  bool holds(MessageType type, std::uint16_t sequence) const {
    return active_ && type_ == type && sequence_ == sequence && bytes_.kept();
  }
  bool complete() const { return active_ && have_.count() == count_; }
  MessageType type() const { return type_; }
  std::uint16_t sequence() const { return sequence_; }
  std::size_t segment_count() const { return count_; }
  const SegmentSet& received() const { return have_; }
  // The whole message; meaningful once complete().
  std::span<std::uint8_t> message() { return std::span<std::uint8_t>(bytes_.data(), length_); }
  void clear() { active_ = false; }
  Bytes& bytes() { return bytes_; }  // to attach borrowed bytes to their owner

 private:
  Bytes bytes_{};
  SegmentSet have_{};
  MessageType type_{};
  std::uint16_t sequence_ = 0;
  std::size_t length_ = 0;
  std::size_t count_ = 0;
  bool active_ = false;
};

// Holds one message to send and the set of its segments still to go.
template <std::size_t Capacity>
class Outbox {
 public:
  // Where the caller writes the message before stage().
  std::span<std::uint8_t> buffer() { return std::span<std::uint8_t>(buffer_.data(), Capacity); }

  // The message is buffer()[0, length). It is cut into segments of at most
  // `max_segment` bytes (more if it would otherwise need over kMaxSegments); `answer_units` goes into every frame (the size the
  // peer should answer in); with `poll_last` the last frame of each burst
  // asks the peer for a Status. Queues every segment. False if it does not fit.
  bool stage(MessageType type, std::uint16_t sequence, std::size_t length, std::size_t max_segment,
             std::uint8_t answer_units, bool poll_last) {
    if (length > Capacity || length > kMaxMessageBytes || max_segment == 0) {
      staged_ = false;
      return false;
    }
    // At most kMaxSegments segments: a long message takes larger ones.
    const std::size_t fewest = (length + kMaxSegments - 1) / kMaxSegments;
    const std::size_t wanted = max_segment < kMaxSegmentBytes ? max_segment : kMaxSegmentBytes;
    const std::size_t count = segments_for(length, wanted > fewest ? wanted : fewest);
    if (count > kMaxSegments) {
      staged_ = false;
      return false;
    }
    header_ = FrameHeader{};
    header_.type = type;
    header_.sequence = sequence;
    header_.message_length = static_cast<std::uint16_t>(length);
    header_.segment_count = static_cast<std::uint8_t>(count);
    header_.answer_units = answer_units;
    poll_last_ = poll_last;
    staged_ = true;
    queue_all();
    return true;
  }

  void queue_all() {
    queued_.fill_first(staged_ ? header_.segment_count : 0);
    queued_count_ = staged_ ? header_.segment_count : 0;
    next_ = 0;
  }
  // Queues the segments in `which` (e.g. a peer's missing set); returns how many.
  std::size_t queue(const SegmentSet& which) {
    std::size_t n = 0;
    for (std::size_t i = 0; staged_ && i < header_.segment_count; ++i) {  // <= kMaxSegments
      if (which.test(i)) {
        if (!queued_.test(i)) {
          queued_.set(i);
          ++queued_count_;
        }
        next_ = i < next_ ? i : next_;
        ++n;
      }
    }
    return n;
  }
  void drop() {
    staged_ = false;
    queued_.clear();
    queued_count_ = 0;
  }

  // Encodes the next queued segment into `out` and dequeues it; 0 when none is queued.
  std::size_t next_frame(std::span<std::uint8_t> out) {
    // No queued index lies below next_: one pass over the segments per burst.
    for (std::size_t i = next_; staged_ && queued_count_ > 0 && i < header_.segment_count; ++i) {  // <= kMaxSegments
      if (!queued_.test(i)) {
        continue;
      }
      queued_.reset(i);
      --queued_count_;
      next_ = i + 1;
      FrameHeader h = header_;
      h.segment_index = static_cast<std::uint8_t>(i);
      h.flags = poll_last_ && queued_count_ == 0 ? kFlagPoll : std::uint8_t{0};
      return encode_segment(h, std::span<const std::uint8_t>(buffer_.data(), header_.message_length), out);
    }
    return 0;
  }

  bool staged() const { return staged_; }
  bool pending() const { return staged_ && queued_count_ > 0; }
  bool holds(MessageType type, std::uint16_t sequence) const {
    return staged_ && header_.type == type && header_.sequence == sequence;
  }
  MessageType type() const { return header_.type; }
  std::uint16_t sequence() const { return header_.sequence; }
  std::size_t segment_count() const { return staged_ ? header_.segment_count : 0; }
  std::span<const std::uint8_t> message() const {
    return std::span<const std::uint8_t>(buffer_.data(), staged_ ? header_.message_length : 0);
  }

 private:
  std::array<std::uint8_t, Capacity> buffer_{};
  FrameHeader header_{};
  SegmentSet queued_{};
  std::size_t queued_count_ = 0;  // segments in queued_
  std::size_t next_ = 0;          // lowest index that may be queued
  bool poll_last_ = false;
  bool staged_ = false;
};

}  // namespace itp::link
