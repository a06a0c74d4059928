#include "options.h"

#include "core/refine/refine_budget.h"
#include "work.h"

namespace sdp {
namespace {

// In enum order (refine_budget.h, options.h).
const char* const kRefineStopNames[] = {"not run", "iterations", "converged", "work budget",
                                        "time limit"};
const char* const kStorageNames[] = {"double", "float", "float, 6 decimals"};

}  // namespace

Options productDefaults() {
  Options options;
  options.stretch_iterations = kDefaultStretchIterations;
  options.refine_work_factor = kDefaultRefineWorkFactor;
  options.refine_min_work = kMinRefineWork;
  return options;
}

const char* refineStopName(RefineStop stop) {
  return kRefineStopNames[static_cast<int>(stop)];
}
const char* uvStorageName(UVStorage storage) {
  return kStorageNames[static_cast<int>(storage)];
}

}  // namespace sdp
