// Where a test finds a mesh file: the copy that ships with the repository (resources/meshes,
// always there), else the optional extra set beside the clone (SDP_SHARED_DIR/meshes: larger real
// meshes whose licence does not let them ship). Both use the same relative paths
// ("disk/nefertiti.off", "invalid/truncated.off", ...). A test whose mesh is in neither skips
// (SDP_MESH_OR_SKIP), and ctest reports it as skipped, not passed (SKIP_REGULAR_EXPRESSION).
#pragma once

#include <filesystem>
#include <set>
#include <string>
#include <vector>

namespace sdp::test {

inline std::string meshFile(const std::string& relative) {
  for (const char* root : {SDP_BUNDLED_MESH_DIR, SDP_SHARED_DIR "/meshes"}) {
    const std::filesystem::path path = std::filesystem::path(root) / relative;
    if (std::filesystem::exists(path)) return path.string();
  }
  return {};
}

// Every file of a mesh folder ("invalid"), bundled and extra, each name once.
inline std::vector<std::string> meshFilesIn(const std::string& folder) {
  std::set<std::string> names;
  std::vector<std::string> paths;
  for (const char* root : {SDP_BUNDLED_MESH_DIR, SDP_SHARED_DIR "/meshes"}) {
    const std::filesystem::path dir = std::filesystem::path(root) / folder;
    if (!std::filesystem::is_directory(dir)) continue;
    for (const auto& entry : std::filesystem::directory_iterator(dir)) {
      if (entry.path().extension() == ".off" && names.insert(entry.path().filename()).second)
        paths.push_back(entry.path().string());
    }
  }
  return paths;
}

}  // namespace sdp::test

#define SDP_MESH_OR_SKIP(variable, relative)                                        \
  const std::string variable = ::sdp::test::meshFile(relative);                     \
  if (variable.empty())                                                             \
  GTEST_SKIP() << (relative) << " is not in resources/meshes, and SDP_SHARED_DIR (" \
               << SDP_SHARED_DIR << ") holds no copy"
