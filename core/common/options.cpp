#include "options.h"

#include "work.h"

namespace sdp {
namespace {

// In enum order (options.h).
const char* const kStorageNames[] = {"double", "float", "float, 6 decimals"};

}  // namespace

Options productDefaults() {
  Options options;
  options.stretch_iterations = kDefaultStretchIterations;
  options.refine_work_factor = kDefaultRefineWorkFactor;
  options.refine_min_work = kMinRefineWork;
  return options;
}

const char* uvStorageName(UVStorage storage) {
  return kStorageNames[static_cast<int>(storage)];
}

}  // namespace sdp
