#include "report.h"

#include <cmath>
#include <cstdio>
#include <sstream>

namespace sdp {
namespace {

std::string jsonString(const std::string& s) {
  std::string out = "\"";
  for (char c : s) {
    switch (c) {
      case '"':
        out += "\\\"";
        break;
      case '\\':
        out += "\\\\";
        break;
      case '\n':
        out += "\\n";
        break;
      case '\t':
        out += "\\t";
        break;
      default:
        if (static_cast<unsigned char>(c) < 0x20) {
          char buf[8];
          std::snprintf(buf, sizeof buf, "\\u%04x", c);
          out += buf;
        } else {
          out += c;
        }
    }
  }
  return out + "\"";
}

// JSON has no inf/nan: a non-finite number is written as null.
std::string jsonNumber(double x) {
  if (!std::isfinite(x)) return "null";
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.9g", x);
  return buf;
}

}  // namespace

std::string Report::toJson() const {
  std::ostringstream o;
  o << "{\n";
  o << "  \"l2_stretch\": " << jsonNumber(l2_stretch) << ",\n";
  o << "  \"linf_stretch\": " << jsonNumber(linf_stretch) << ",\n";
  o << "  \"flipped_faces\": " << flipped_faces << ",\n";
  o << "  \"fallbacks\": " << fallbacks << ",\n";
  o << "  \"source_vertex\": " << source_vertex << ",\n";
  o << "  \"seconds\": " << jsonNumber(seconds) << ",\n";
  o << "  \"vertices\": " << vertices << ",\n";
  o << "  \"faces\": " << faces << ",\n";
  o << "  \"weights\": " << jsonString(weights) << ",\n";
  o << "  \"boundary\": " << jsonString(boundary) << ",\n";
  o << "  \"boundary_used\": " << jsonString(boundary_used) << ",\n";
  o << "  \"stretch_iterations\": " << stretch_iterations_run << ",\n";
  o << "  \"best_iteration\": " << best_iteration << ",\n";
  o << "  \"l2_stretch_linear\": " << jsonNumber(l2_stretch_linear) << ",\n";
  o << "  \"l2_stretch_fixed_boundary\": " << jsonNumber(l2_stretch_fixed_boundary) << ",\n";
  o << "  \"free_boundary_steps\": " << free_boundary_steps << ",\n";
  o << "  \"refinement_stop\": " << jsonString(refinement_stop) << ",\n";
  o << "  \"fallback_counts\": {\"straightest_to_ltd\": " << straightest_to_ltd
    << ", \"degenerate_rings\": " << degenerate_rings << ", \"walk_fallbacks\": " << walk_fallbacks
    << ", \"boundary_fallbacks\": " << boundary_fallbacks << "},\n";
  o << "  \"unreferenced_vertices\": " << unreferenced_vertices << ",\n";
  o << "  \"holes_filled\": " << holes_filled << ",\n";
  o << "  \"ears_unfolded\": " << ears_unfolded << ",\n";
  o << "  \"storage\": {\"precision\": " << jsonString(storage)
    << ", \"degenerate_faces\": " << storage_degenerate_faces
    << ", \"moved_vertices\": " << storage_moved_vertices << "},\n";
  o << "  \"stage_seconds\": {";
  for (size_t i = 0; i < stage_seconds.size(); ++i)
    o << (i ? ", " : "") << jsonString(stage_seconds[i].first) << ": "
      << jsonNumber(stage_seconds[i].second);
  o << "},\n";
  o << "  \"warnings\": [";
  for (size_t i = 0; i < warnings.size(); ++i) o << (i ? ", " : "") << jsonString(warnings[i]);
  o << "],\n";
  o << "  \"notes\": [";
  for (size_t i = 0; i < notes.size(); ++i) o << (i ? ", " : "") << jsonString(notes[i]);
  o << "]\n}\n";
  return o.str();
}

}  // namespace sdp
