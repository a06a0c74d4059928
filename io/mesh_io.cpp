// The library's entry points: reading by extension, and plain text files. The formats are in
// io/off.cpp, io/obj.cpp, io/ply.cpp, io/stl.cpp and io/png.cpp.
#include "io/mesh_io.h"

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <system_error>

#include "io/scan.h"
#include "io/write.h"

namespace sdp::io {
namespace {

namespace fs = std::filesystem;
using detail::fail;
using detail::lowercase;

MeshData parseMesh(std::string_view bytes, const std::string& format, const std::string& name) {
  if (format == "off") return detail::parseOff(bytes, name);
  if (format == "obj") return detail::parseObj(bytes, name);
  if (format == "ply") return detail::parsePly(bytes, name);
  if (format == "stl") return detail::parseStl(bytes, name);
  fail(name, "unsupported mesh format '" + format + "' (expected .off, .obj, .ply or .stl)");
}

std::string extensionOf(const std::string& path) {
  std::string ext = lowercase(fs::path(path).extension().string());
  if (!ext.empty() && ext[0] == '.') ext.erase(0, 1);
  return ext;
}

}  // namespace

bool isReadableMeshPath(const std::string& path) {
  const std::string ext = extensionOf(path);
  return ext == "off" || ext == "obj" || ext == "ply" || ext == "stl";
}

MeshData readMesh(const std::string& path) {
  const std::string name = detail::fileNameOf(path);
  if (!isReadableMeshPath(path)) {
    fail(name, "unsupported mesh format (expected .off, .obj, .ply or .stl)");
  }
  std::error_code ec;
  const fs::file_status status = fs::status(path, ec);
  if (ec || !fs::exists(status)) {
    throw ParameterizationError("cannot open " + path + ": no such file");
  }
  if (!fs::is_regular_file(status)) {
    throw ParameterizationError("cannot open " + path + ": not a regular file");
  }
  errno = 0;
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    const std::string reason = errno != 0 ? std::strerror(errno) : "cannot open file";
    throw ParameterizationError("cannot open " + path + ": " + reason);
  }
  std::string bytes;
  {
    // Read in blocks rather than trusting the reported size.
    char block[1 << 16];
    while (in.read(block, sizeof block) || in.gcount() > 0) {
      bytes.append(block, static_cast<size_t>(in.gcount()));
    }
    if (in.bad()) throw ParameterizationError("cannot read " + path + ": I/O error");
  }
  return parseMesh(bytes, extensionOf(path), name);
}

MeshData readMeshFromMemory(const std::string& bytes, const std::string& format) {
  std::string ext = lowercase(format);
  if (!ext.empty() && ext[0] == '.') ext.erase(0, 1);
  return parseMesh(bytes, ext, "<memory>." + ext);
}

void writeTextFile(const std::string& path, const std::string& text) {
  detail::AtomicFile file(path);
  file.stream().write(text.data(), static_cast<std::streamsize>(text.size()));
  file.commit();
}

}  // namespace sdp::io
