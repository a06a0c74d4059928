#include "io/scan.h"

#include <cctype>
#include <charconv>
#include <climits>
#include <cstdlib>
#include <filesystem>
#include <system_error>

namespace sdp::io::detail {

[[noreturn]] void fail(const std::string& name, const std::string& what) {
  throw ParameterizationError(name + ": " + what);
}

std::string lineAt(int line) {
  return "line " + std::to_string(line) + ": ";
}

std::string lowercase(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

std::string fileNameOf(const std::string& path) {
  const std::string name = std::filesystem::path(path).filename().string();
  return name.empty() ? path : name;
}

// Quotes a token for an error message, shortened so the reason stays one readable line.
std::string quoted(std::string_view token) {
  std::string shown(token.substr(0, 40));
  for (char& c : shown) {
    if (!std::isprint(static_cast<unsigned char>(c))) c = '?';
  }
  return "'" + shown + (token.size() > 40 ? "...'" : "'");
}

// Locale-independent; accepts a leading '+', "nan" and "inf" (read as-is, the core rejects them).
bool parseDouble(std::string_view token, double& value) {
  if (token.size() > 1 && token[0] == '+' && token[1] != '-' && token[1] != '+') {
    token.remove_prefix(1);
  }
  const char* end = token.data() + token.size();
  const auto [ptr, ec] = std::from_chars(token.data(), end, value);
  if (ptr != end || token.empty()) return false;
  if (ec == std::errc::result_out_of_range) {
    // Beyond double range: let strtod pick +-HUGE_VAL or the underflowed value.
    const std::string copy(token);
    value = std::strtod(copy.c_str(), nullptr);
    return true;
  }
  return ec == std::errc();
}

bool parseInteger(std::string_view token, long long& value) {
  if (token.size() > 1 && token[0] == '+' && token[1] != '-' && token[1] != '+') {
    token.remove_prefix(1);
  }
  const char* end = token.data() + token.size();
  const auto [ptr, ec] = std::from_chars(token.data(), end, value);
  return ec == std::errc() && ptr == end && !token.empty();
}

size_t plausibleCount(long long claimed, size_t remaining_bytes, size_t min_bytes_each) {
  const size_t possible = remaining_bytes / min_bytes_each + 1;
  return claimed < 0 ? 0 : std::min(static_cast<size_t>(claimed), possible);
}

MeshData MeshBuilder::build(const std::string& name) const {
  if (corners_.empty()) fail(name, "contains no faces");
  if (vertexCount() > static_cast<size_t>(INT_MAX) ||
      triangleCount() > static_cast<size_t>(INT_MAX) ||
      texcoordCount() > static_cast<size_t>(INT_MAX)) {
    fail(name, "too many vertices, texture coordinates or faces (more than 2^31)");
  }
  MeshData mesh;
  mesh.V.resize(static_cast<Eigen::Index>(vertexCount()), 3);
  std::copy(coords_.begin(), coords_.end(), mesh.V.data());
  mesh.F.resize(static_cast<Eigen::Index>(triangleCount()), 3);
  std::copy(corners_.begin(), corners_.end(), mesh.F.data());
  mesh.polygons_triangulated = polygons_triangulated_;
  const bool any_corner =
      std::any_of(texcoord_corners_.begin(), texcoord_corners_.end(), [](int t) { return t >= 0; });
  if (!texcoords_.empty() || any_corner) {
    mesh.texcoords.uv.resize(static_cast<Eigen::Index>(texcoordCount()), 2);
    std::copy(texcoords_.begin(), texcoords_.end(), mesh.texcoords.uv.data());
    mesh.texcoords.face_uv.resize(mesh.F.rows(), 3);
    std::copy(texcoord_corners_.begin(), texcoord_corners_.end(), mesh.texcoords.face_uv.data());
    // A reference past the last row (an OBJ forward reference the file never filled) is none.
    mesh.texcoords.face_uv = (mesh.texcoords.face_uv.array() < static_cast<int>(texcoordCount()))
                                 .select(mesh.texcoords.face_uv, -1);
    for (Eigen::Index f = 0; f < mesh.F.rows(); ++f) {
      if ((mesh.texcoords.face_uv.row(f).array() < 0).any()) ++mesh.faces_without_texcoords;
    }
  }
  return mesh;
}

}  // namespace sdp::io::detail
