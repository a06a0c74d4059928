// One description of the MeshLab filter -- names, parameters, help, defaults -- shared by the
// MeshLab 2020.09 and 2025.07 shims. Plain C++ (no Qt): each shim turns it into its own
// parameter classes, so the two front ends cannot drift apart.
#pragma once

#include <string>
#include <vector>

#include "core/options.h"

namespace sdp::filter {

// docs/method.md §6 names.
extern const char* const kFilterName;  // "Parametrization: Straightest Distances"
extern const char* const
    kPythonFilterName;     // "compute_texcoord_parametrization_straightest_distances"
std::string filterHelp();  // the filter's description shown in MeshLab (HTML)

enum class ParameterType { Enum, Int, Bool, String };

struct ParameterDescription {
  std::string name;   // script / pymeshlab name, e.g. "weights"
  std::string label;  // dialog label
  std::string help;   // tooltip, in the user's terms
  ParameterType type;
  std::vector<std::string> enum_labels;  // Enum only, in docs/method.md §6 order
  int int_default = 0;                   // Enum (index), Int, Bool (0/1)
  std::string string_default;            // String only
};

// In dialog order: weights, boundary, sourcevertex, stretchiterations, selectedonly,
// texturename, checkers, texturesize. No parameter may be added lightly: meshlabserver 2020.09
// aborts (an assertion) on a script that lacks one of the filter's parameters, which every
// script saved before the addition would.
const std::vector<ParameterDescription>& parameters();

// Values read back from a shim's parameter list.
struct FilterValues {
  int weights = 0;
  int boundary = 0;
  int source_vertex = -1;
  int stretch_iterations = sdp::kDefaultStretchIterations;
  bool selected_only = false;
  std::string texture_name = "straightest_checker.png";
  int checkers = 16;
  int texture_size = 1024;
};

// Checks ranges (one-line reason in a ParameterizationError) and maps to core options.
sdp::Options toOptions(const FilterValues& values);

}  // namespace sdp::filter
