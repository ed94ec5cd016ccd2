#pragma once
// Storage for a QP's problem and solver workspace, which stages claim. The
// planner's coarse, path and speed QPs run one after another, so with
// Cfg::kShareQpStorage one block the size of the largest (the path QP's)
// serves all three; otherwise each QP has a block of its own
// (PlannerQpArenas below; docs/memory.md, "QP arena"). Each stage keeps its
// result (with its last working set) and its matrix key. A claim by another
// stage ends the previous holder's hold: that stage builds its whole problem
// again (H and A too) and restarts warm from its last working set (StageQp).
// Plain static storage: no heap.
#include <cstddef>
#include <new>
#include <span>
#include <type_traits>

#include "itp/core/assert.hpp"
#include "itp/qp/dimensions.hpp"
#include "itp/qp/problem.hpp"
#include "itp/qp/workspace.hpp"

namespace itp::qp {

// What one QP needs from building its problem to the end of its solve.
template <class D>
struct QpStorage {
  QpProblem<D> problem;
  QpWorkspace<D> workspace;
};

template <std::size_t Bytes>
class QpArena {
 public:
  static constexpr std::size_t kBytes = Bytes;
  static constexpr std::size_t kAlign = alignof(std::max_align_t);

  QpArena() = default;
  QpArena(const QpArena&) = delete;
  QpArena& operator=(const QpArena&) = delete;

  // The block as storage of shape D for `holder`. `fresh`: the holder did not
  // hold it; it then holds another QP's bytes, sizes 0 and no factor.
  template <class D>
  QpStorage<D>& claim(const void* holder, bool& fresh) {
    return claim_object<QpStorage<D>>(holder, fresh);
  }
  // The block as an object of type T for `holder`: a QP's storage, or
  // between QP solves another phase's scratch (the reference spline's
  // workspace). Default-initialisation: the scalar members' initialisers
  // run (sizes 0, no factor), the arrays keep the bytes they have; a build
  // resets the problem and a solve writes every workspace entry before it
  // reads it. So a claim costs O(1), not O(Bytes).
  template <class T>
  T& claim_object(const void* holder, bool& fresh) {
    static_assert(sizeof(T) <= Bytes, "the QP arena is smaller than this object");
    static_assert(alignof(T) <= kAlign, "the QP arena is less aligned than this object");
    static_assert(std::is_trivially_destructible_v<T>, "a claim ends the last object without a destructor");
    fresh = holder_ != holder;
    if (fresh) {
      object_ = ::new (static_cast<void*>(bytes_)) T;
      holder_ = holder;
    }
    return *static_cast<T*>(object_);
  }
  // The block as plain bytes for `holder` (the firmware's inbox, which
  // reassembles a request between cycles). Ends every other hold; the
  // holder asks held_by() before it trusts what it wrote there earlier.
  std::span<unsigned char> claim_bytes(const void* holder) {
    if (holder_ != holder) {
      object_ = nullptr;
      holder_ = holder;
    }
    return std::span<unsigned char>(bytes_, Bytes);
  }
  bool held_by(const void* holder) const { return holder_ == holder; }
  // The storage `holder` claimed last (a precondition: nobody claimed it since).
  template <class D>
  const QpStorage<D>& held(const void* holder) const {
    ITP_EXPECTS(holder_ == holder);
    return *static_cast<const QpStorage<D>*>(object_);
  }

 private:
  alignas(kAlign) unsigned char bytes_[Bytes];
  void* object_ = nullptr;        // the storage placed in bytes_ by the last claim
  const void* holder_ = nullptr;  // who claimed it
};

template <class... Ds>
constexpr std::size_t largest_storage() {
  std::size_t bytes = 0;
  ((bytes = sizeof(QpStorage<Ds>) > bytes ? sizeof(QpStorage<Ds>) : bytes), ...);
  return bytes;
}

// The planner's QP storage, as its configuration chooses (Cfg::kShareQpStorage):
// one arena the size of the largest of the coarse, path and speed QPs, which
// they claim in turn, or one arena per QP, which its stage always holds.
template <class Cfg, bool Shared = Cfg::kShareQpStorage>
struct PlannerQpArenas;

template <class Cfg>
struct PlannerQpArenas<Cfg, true> {
  using Arena = QpArena<largest_storage<PathQpDims<Scalar, Cfg>, SpeedQpDims<Scalar, Cfg>,
                                         CoarseQpDims<Scalar, Cfg>>()>;
  using CoarseArena = Arena;
  using PathArena = Arena;
  using SpeedArena = Arena;
  static constexpr std::size_t kLendableBytes = Arena::kBytes;  // free between cycles (planner.hpp)
  CoarseArena& coarse() { return shared; }
  PathArena& path() { return shared; }
  SpeedArena& speed() { return shared; }
  Arena shared{};
};

template <class Cfg>
struct PlannerQpArenas<Cfg, false> {
  using CoarseArena = QpArena<largest_storage<CoarseQpDims<Scalar, Cfg>>()>;
  using PathArena = QpArena<largest_storage<PathQpDims<Scalar, Cfg>>()>;
  using SpeedArena = QpArena<largest_storage<SpeedQpDims<Scalar, Cfg>>()>;
  static constexpr std::size_t kLendableBytes = 0;  // each stage holds its own at all times
  CoarseArena& coarse() { return coarse_qp; }
  PathArena& path() { return path_qp; }
  SpeedArena& speed() { return speed_qp; }
  CoarseArena coarse_qp{};
  PathArena path_qp{};
  SpeedArena speed_qp{};
};

}  // namespace itp::qp
