#include "filter_description.h"

#include "core/error.h"

namespace sdp::filter {

const char* const kFilterName = "Parametrization: Straightest Distances";
const char* const kPythonFilterName = "compute_texcoord_parametrization_straightest_distances";

std::string filterHelp() {
  return "Flattens a disk-shaped patch onto the plane with per-wedge texture coordinates that "
         "never fold, following <i>Parameterization of 3D Surface Patches by Straightest "
         "Distances</i> (Lee, Kim, Lee): a convex-combination map, one-to-one by Tutte/Floater, "
         "then by default refined to lower stretch in checked steps (Stretch iterations 0 gives "
         "the paper's map). The map is checked as MeshLab stores it (float, 6 decimals in OBJ). "
         "The patch must have one boundary loop and no handles. A checkerboard texture is written "
         "next to the mesh and attached; per-face quality holds the stretch (1 = no distortion), "
         "so <i>Colorize by Quality</i> shows where the map stretches. The log lists L2 and "
         "L&infin; stretch, flipped faces (always 0), fallbacks, the source vertex and the time.";
}

const std::vector<ParameterDescription>& parameters() {
  static const std::vector<ParameterDescription> list = {
      {"weights",
       "Interior weights",
       "How each interior vertex is placed between its neighbours. Straightest distances (the "
       "paper's cutting planes) usually stretches least; LTD and Floater are the classic "
       "shape-preserving maps; Mean value is smooth; Uniform ignores geometry (most robust, most "
       "stretch).",
       ParameterType::Enum,
       {"Straightest distances (cutting planes)", "LTD straightest geodesics",
        "Floater shape-preserving", "Mean value", "Uniform"},
       0,
       {}},
      {"boundary",
       "Boundary shape",
       "Where the boundary goes. Measured follows the patch's own outline (straightest distances "
       "from a source vertex) and lowers stretch near the border; Circle and Square fix it to a "
       "shape (Square suits geometry images).",
       ParameterType::Enum,
       {"Measured (straightest distances)", "Circle", "Square"},
       0,
       {}},
      {"sourcevertex",
       "Source vertex",
       "Centre of the measured boundary: -1 picks the interior vertex farthest from the border; "
       "otherwise a vertex index. A single selected vertex overrides this.",
       ParameterType::Int,
       {},
       -1,
       {}},
      {"stretchiterations",
       "Stretch iterations",
       "Most refinement steps per stage; 0 gives the paper's linear map. Refinement re-solves "
       "with weights that pull less towards stretched areas, then (Measured boundary) lets the "
       "outline move in checked steps and, up to 50k vertices, takes Newton steps on the "
       "stretch itself; the map never folds. A stage stops early once a step gains under 0.1% "
       "of L2 stretch, and refinement stops after twice the linear map's time (at least 1.5 s). "
       "Circle and Square boundaries stay as they are.",
       ParameterType::Int,
       {},
       sdp::kDefaultStretchIterations,
       {}},
      {"selectedonly",
       "Selected faces only",
       "Parameterize only the selected faces (they must form one disk-shaped patch); other faces "
       "keep their texture coordinates.",
       ParameterType::Bool,
       {},
       0,
       {}},
      {"texturename",
       "Texture file name",
       "Name of the checkerboard image written next to the mesh file and attached as its texture.",
       ParameterType::String,
       {},
       0,
       "straightest_checker.png"},
      {"checkers",
       "Checkerboard squares",
       "Squares per side of the checkerboard; more squares show finer distortion.",
       ParameterType::Int,
       {},
       16,
       {}},
      {"texturesize",
       "Texture size (pixels)",
       "Width and height of the checkerboard image.",
       ParameterType::Int,
       {},
       1024,
       {}},
  };
  return list;
}

sdp::Options toOptions(const FilterValues& values) {
  if (values.weights < 0 || values.weights >= kWeightSchemeCount)
    throw ParameterizationError("unknown weights choice " + std::to_string(values.weights));
  if (values.boundary < 0 || values.boundary >= kBoundaryShapeCount)
    throw ParameterizationError("unknown boundary choice " + std::to_string(values.boundary));
  if (values.stretch_iterations < 0 || values.stretch_iterations > 100)
    throw ParameterizationError("stretch iterations must be between 0 and 100");
  if (values.checkers < 1 || values.checkers > 512)
    throw ParameterizationError("checkerboard squares must be between 1 and 512");
  if (values.texture_size < 16 || values.texture_size > 8192)
    throw ParameterizationError("texture size must be between 16 and 8192 pixels");
  if (values.texture_name.empty()) throw ParameterizationError("the texture file name is empty");
  sdp::Options options = sdp::productDefaults();
  options.weights = static_cast<WeightScheme>(values.weights);
  options.boundary = static_cast<BoundaryShape>(values.boundary);
  options.source_vertex = values.source_vertex < 0 ? -1 : values.source_vertex;
  options.stretch_iterations = values.stretch_iterations;
  return options;
}

}  // namespace sdp::filter
