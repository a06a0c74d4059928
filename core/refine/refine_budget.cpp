#include "refine_budget.h"

namespace sdp {
namespace {

// In enum order.
const char* const kRefineStopNames[] = {"not run", "iterations", "converged", "work budget",
                                        "time limit"};

}  // namespace

const char* refineStopName(RefineStop stop) {
  return kRefineStopNames[static_cast<int>(stop)];
}

}  // namespace sdp
