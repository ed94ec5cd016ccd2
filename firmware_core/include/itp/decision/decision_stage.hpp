#pragma once
// The whole of paper 1.1 in one call: convex zones, decision tree (K best by
// geometric cost), a coarse QP per kept decision, decision cost, the winner.
// Owns all of its memory; one instance per planner.
#include <array>
#include <cstdint>
#include <span>

#include "itp/core/tick_source.hpp"
#include "itp/core/work_ledger.hpp"
#include "itp/decision/coarse_evaluation.hpp"
#include "itp/decision/convex_space.hpp"
#include "itp/decision/decision_tree.hpp"

namespace itp::decision {

enum class DecisionStatus : std::uint8_t {
  kOk = 0,          // a decision whose corridor reaches the horizon was chosen
  kBlocked,         // the best decision ends before the horizon: stop before its end
  kNoDecision,      // no zone for the ego, or no coarse QP was solvable
  kInvalidInput,
};

const char* to_string(DecisionStatus status);

// What one run may spend (what is left of the cycle's budgets) and what it
// spent. A run with too little left searches fewer nodes and evaluates fewer
// decisions; budget_out says that a cap cut it short.
struct DecisionBudget {
  int tree_nodes = 0;         // at most this many nodes (<= 0 or > kMaxTreeNodes: kMaxTreeNodes)
  int coarse_qps = 0;         // coarse QPs, at most
  int coarse_iterations = 0;  // their iterations, at most
  WorkLedger* ledger = nullptr;  // the cycle's QP work budget, charged per coarse QP (nullptr: none)
};

struct DecisionWork {
  int tree_nodes = 0;
  int coarse_qps = 0;
  int coarse_iterations = 0;
  std::uint64_t coarse_ticks = 0;
  bool budget_out = false;  // decisions were left unevaluated (coarse QPs or iterations spent)
};

struct DecisionWeights {
  GeometricWeights geometric;
  CoarseWeights coarse;
};

template <class Cfg>
class BasicDecisionStage {
 public:
  using RoadSl = BasicRoadSl<Cfg>;
  using ConvexSpace = BasicConvexSpace<Cfg>;
  using DecisionSet = BasicDecisionSet<Cfg>;
  using CoarseInput = BasicCoarseInput<Cfg>;
  using CoarseResult = BasicCoarseResult<Cfg>;
  using CoarseEvaluator = BasicCoarseEvaluator<Cfg>;
  using QpArena = typename qp::PlannerQpArenas<Cfg>::CoarseArena;

  // The coarse QP's storage (shared with the planner's other QPs or its own).
  explicit BasicDecisionStage(QpArena& arena) : evaluator_(arena) {}

  void reset() { evaluator_.reset(); }
  void set_observer(const qp::BasicPlannerQpObserver<Cfg>* observer) {
    evaluator_.set_observer(observer);
  }
  DecisionStatus run(const RoadSl& road, std::span<const SlBox> boxes,
                     const ConvexSpaceParams& params, const CoarseInput& input,
                     const DecisionWeights& weights);
  // The same within `budget`, reporting the work done.
  DecisionStatus run(const RoadSl& road, std::span<const SlBox> boxes,
                     const ConvexSpaceParams& params, const CoarseInput& input,
                     const DecisionWeights& weights, const DecisionBudget& budget, TickSource ticks,
                     DecisionWork& work);

  const ConvexSpace& space() const { return space_; }
  const DecisionSet& decisions() const { return set_; }
  // Coarse scores, index-aligned with decisions().kept.
  const CoarseScore& coarse(std::size_t i) const { return scores_[i]; }
  // Index of the chosen decision in decisions().kept, -1 if none.
  int best() const { return best_; }
  // The coarse samples of kept decision i, for host tools and tests: its
  // coarse QP again, as the last run set it up, solved cold in `evaluator`
  // (the run hotstarted it; the optimum is the same within the QP's
  // tolerance). The run keeps only the scores: 20 results of 1 KB each were
  // the decision stage's second-largest table, and nothing on the target
  // reads their samples.
  void evaluate_again(std::size_t i, CoarseEvaluator& evaluator, CoarseResult& out) const;

 private:
  ConvexSpace space_{};
  DecisionSet set_{};
  CoarseEvaluator evaluator_;
  CoarseResult result_{};  // the decision being evaluated
  std::array<CoarseScore, Cfg::kKeptDecisions> scores_{};
  CoarseInput input_{};    // the last run's, for evaluate_again
  CoarseWeights weights_{};
  int best_ = -1;
};

using DecisionStage = BasicDecisionStage<DefaultConfig>;

}  // namespace itp::decision
