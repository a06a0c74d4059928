// What the mesh readers and writers of io/ share (not part of the library's interface): error
// reasons that name the file, line and token scanning of untrusted text, number parsing, and
// the mesh assembly with fan triangulation and per-corner texture coordinates.
#pragma once

#include <algorithm>
#include <string>
#include <string_view>
#include <vector>

#include "io/mesh_io.h"

namespace sdp::io::detail {

// Throws ParameterizationError("<name>: <what>").
[[noreturn]] void fail(const std::string& name, const std::string& what);
// "line N: ", the prefix of a reason about line N (1-based).
std::string lineAt(int line);
std::string lowercase(std::string s);
// The file name of a path, for reasons (the path itself when it has none).
std::string fileNameOf(const std::string& path);
// Quotes a token for an error message, shortened so the reason stays one readable line.
std::string quoted(std::string_view token);
// Locale-independent; accepts a leading '+', "nan" and "inf" (read as-is, the core rejects them).
bool parseDouble(std::string_view token, double& value);
bool parseInteger(std::string_view token, long long& value);
// Header counts are claims, not facts: at most as many items as the remaining bytes could hold
// (each at least `min_bytes_each`) are reserved; reading simply runs out when the claim is false.
size_t plausibleCount(long long claimed, size_t remaining_bytes, size_t min_bytes_each);

inline bool isBlank(char c) {
  return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f';
}

// Splits one line into whitespace-separated tokens.
class LineTokens {
 public:
  LineTokens() = default;
  explicit LineTokens(std::string_view line) : rest_(line) {}

  bool next(std::string_view& token) {
    size_t begin = 0;
    while (begin < rest_.size() && isBlank(rest_[begin])) ++begin;
    if (begin == rest_.size()) {
      rest_ = {};
      return false;
    }
    size_t end = begin;
    while (end < rest_.size() && !isBlank(rest_[end])) ++end;
    token = rest_.substr(begin, end - begin);
    rest_ = rest_.substr(end);
    return true;
  }

 private:
  std::string_view rest_;
};

// Hands out lines with their 1-based numbers; optionally drops '#' comments (OFF, OBJ).
class LineReader {
 public:
  LineReader(std::string_view text, bool strip_comments)
      : text_(text), strip_comments_(strip_comments) {}

  bool next(std::string_view& line) {
    if (pos_ >= text_.size()) return false;
    const size_t end = std::min(text_.find('\n', pos_), text_.size());
    line = text_.substr(pos_, end - pos_);
    pos_ = end + 1;
    ++line_;
    if (strip_comments_) line = line.substr(0, line.find('#'));
    return true;
  }

  // Skips lines that are empty once comments are removed.
  bool nextContent(std::string_view& line) {
    while (next(line)) {
      if (hasToken(line)) return true;
    }
    return false;
  }

  // Whether anything but blanks and comments follows the current line.
  bool hasMoreContent() const {
    LineReader ahead = *this;
    std::string_view line;
    return ahead.nextContent(line);
  }

  int line() const { return line_; }
  size_t remainingBytes() const { return pos_ >= text_.size() ? 0 : text_.size() - pos_; }

 private:
  static bool hasToken(std::string_view line) {
    return std::any_of(line.begin(), line.end(), [](char c) { return !isBlank(c); });
  }

  std::string_view text_;
  bool strip_comments_;
  size_t pos_ = 0;
  int line_ = 0;
};

// Tokens across line breaks (ASCII PLY bodies).
class TokenStream {
 public:
  explicit TokenStream(std::string_view text, int first_line)
      : lines_(text, false), first_line_(first_line) {}

  bool next(std::string_view& token) {
    while (!tokens_.next(token)) {
      std::string_view line;
      if (!lines_.next(line)) return false;
      tokens_ = LineTokens(line);
    }
    return true;
  }

  int line() const { return first_line_ + lines_.line(); }

 private:
  LineReader lines_;
  LineTokens tokens_;
  int first_line_;
};

// Vertices, texture coordinates and polygons as the readers meet them; polygons are
// fan-triangulated, each triangle corner keeping its texture coordinate row (-1: none).
class MeshBuilder {
 public:
  void reserveVertices(size_t n) { coords_.reserve(3 * n); }
  void reserveTriangles(size_t n) {
    corners_.reserve(3 * n);
    texcoord_corners_.reserve(3 * n);
  }

  void addVertex(double x, double y, double z) {
    coords_.push_back(x);
    coords_.push_back(y);
    coords_.push_back(z);
  }
  size_t vertexCount() const { return coords_.size() / 3; }

  void addTexcoord(double u, double v) {
    texcoords_.push_back(u);
    texcoords_.push_back(v);
  }
  size_t texcoordCount() const { return texcoords_.size() / 2; }

  // Fan triangulation: corners arrive one by one, a triangle per corner from the third on.
  void beginPolygon() { polygon_corners_ = 0; }
  void addCorner(int v, int texcoord = -1) {
    if (polygon_corners_ == 0) {
      first_ = {v, texcoord};
    } else if (polygon_corners_ >= 2) {
      for (const Corner& c : {first_, previous_, Corner{v, texcoord}}) {
        corners_.push_back(c.vertex);
        texcoord_corners_.push_back(c.texcoord);
      }
    }
    previous_ = {v, texcoord};
    ++polygon_corners_;
  }
  void endPolygon() {
    if (polygon_corners_ > 3) ++polygons_triangulated_;
  }
  size_t triangleCount() const { return corners_.size() / 3; }

  MeshData build(const std::string& name) const;

 private:
  struct Corner {
    int vertex = 0;
    int texcoord = -1;
  };
  std::vector<double> coords_;
  std::vector<double> texcoords_;
  std::vector<int> corners_;
  std::vector<int> texcoord_corners_;
  int polygon_corners_ = 0;
  Corner first_;
  Corner previous_;
  int polygons_triangulated_ = 0;
};

// The readers of each format (io/off.cpp, io/obj.cpp, io/ply.cpp, io/stl.cpp); `name` starts every
// reason.
MeshData parseOff(std::string_view text, const std::string& name);
MeshData parseObj(std::string_view text, const std::string& name);
MeshData parsePly(std::string_view text, const std::string& name);
MeshData parseStl(std::string_view bytes, const std::string& name);

}  // namespace sdp::io::detail
