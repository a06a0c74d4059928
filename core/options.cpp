#include "options.h"

#include "refine_budget.h"
#include "work.h"

namespace sdp {
namespace {

template <class Enum, size_t N>
std::optional<Enum> parseByName(const std::string& name, const char* const (&names)[N]) {
  for (size_t i = 0; i < N; ++i)
    if (name == names[i]) return static_cast<Enum>(i);
  return std::nullopt;
}

const char* const kWeightNames[] = {"straightest", "ltd", "floater", "mean_value", "uniform"};
const char* const kBoundaryNames[] = {"measured", "circle", "square"};
const char* const kSourceRuleNames[] = {"farthest", "centroid"};
// In enum order (refine_budget.h, options.h).
const char* const kRefineStopNames[] = {"not run", "iterations", "converged", "work budget",
                                        "time limit"};
const char* const kStorageNames[] = {"double", "float", "float, 6 decimals"};

}  // namespace

const char* weightSchemeName(WeightScheme w) {
  return kWeightNames[static_cast<int>(w)];
}
const char* boundaryShapeName(BoundaryShape b) {
  return kBoundaryNames[static_cast<int>(b)];
}
const char* sourceRuleName(SourceRule r) {
  return kSourceRuleNames[static_cast<int>(r)];
}

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

std::optional<WeightScheme> parseWeightScheme(const std::string& name) {
  return parseByName<WeightScheme>(name, kWeightNames);
}
std::optional<BoundaryShape> parseBoundaryShape(const std::string& name) {
  return parseByName<BoundaryShape>(name, kBoundaryNames);
}
std::optional<SourceRule> parseSourceRule(const std::string& name) {
  return parseByName<SourceRule>(name, kSourceRuleNames);
}

}  // namespace sdp
