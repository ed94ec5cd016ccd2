#pragma once
// One solver workspace for QPs that never run at the same time. The planner's
// coarse, path and speed QPs run one after another, so one block the size of
// the largest workspace (the path QP's) serves all three (docs/memory.md,
// "QP arena"). Each stage keeps its own problem and result; only the solver's
// scratch and factors are shared. A stage claims the block before it solves;
// a claim by another stage ends the previous holder's hold, and that stage's
// next solve restarts warm from its last working set (StageQp). Plain static
// storage: no heap.
#include <cstddef>
#include <new>

#include "itp/qp/dimensions.hpp"
#include "itp/qp/workspace.hpp"

namespace itp::qp {

template <std::size_t Bytes>
class QpWorkspaceArena {
 public:
  static constexpr std::size_t kBytes = Bytes;
  static constexpr std::size_t kAlign = alignof(std::max_align_t);

  QpWorkspaceArena() = default;
  QpWorkspaceArena(const QpWorkspaceArena&) = delete;
  QpWorkspaceArena& operator=(const QpWorkspaceArena&) = delete;

  // The block as the workspace of shape D for `holder`. `fresh`: the holder
  // did not hold it; it then holds another QP's bytes and no factor.
  template <class D>
  QpWorkspace<D>& claim(const void* holder, bool& fresh) {
    static_assert(sizeof(QpWorkspace<D>) <= Bytes, "the QP arena is smaller than this QP's workspace");
    static_assert(alignof(QpWorkspace<D>) <= kAlign, "the QP arena is less aligned than this QP's workspace");
    fresh = holder_ != holder;
    if (fresh) {
      // Default-initialisation: the scalar members' initialisers run (no
      // factor, empty working set), the arrays keep the bytes they have; a
      // solve writes every array entry before it reads it (its factorisation
      // starts from the problem). So a claim costs O(1), not O(Bytes).
      object_ = ::new (static_cast<void*>(bytes_)) QpWorkspace<D>;
      holder_ = holder;
    }
    return *static_cast<QpWorkspace<D>*>(object_);
  }
  bool held_by(const void* holder) const { return holder_ == holder; }
  // Nobody holds it (a new scene: every stage starts cold).
  void release() { holder_ = nullptr; }

 private:
  alignas(kAlign) unsigned char bytes_[Bytes];
  void* object_ = nullptr;        // the workspace placed in bytes_ by the last claim
  const void* holder_ = nullptr;  // who claimed it
};

template <class... Ds>
constexpr std::size_t largest_workspace() {
  std::size_t bytes = 0;
  ((bytes = sizeof(QpWorkspace<Ds>) > bytes ? sizeof(QpWorkspace<Ds>) : bytes), ...);
  return bytes;
}

// The planner's arena: the largest of its coarse, path and speed QP workspaces.
template <class Cfg>
using PlannerQpArena = QpWorkspaceArena<largest_workspace<PathQpDims<Scalar, Cfg>, SpeedQpDims<Scalar, Cfg>,
                                                          CoarseQpDims<Scalar, Cfg>>()>;

}  // namespace itp::qp
