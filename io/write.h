// What the writers of io/ share (not part of the library's interface): atomic replacement of
// the target, chunked text output, numbers as shortest round-trip text, little- and big-endian
// binary values, and the check that a layout fits its mesh.
#pragma once

#include <cstdint>
#include <fstream>
#include <ostream>
#include <string>

#include "io/mesh_io.h"

namespace sdp::io::detail {

// A temporary file beside the target, renamed over it on commit() and removed otherwise, so
// a failed write never leaves a partial output under the target's name.
class AtomicFile {
 public:
  explicit AtomicFile(const std::string& path);
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;
  ~AtomicFile();

  std::ofstream& stream() { return stream_; }
  void commit();

 private:
  std::string path_;
  std::string temp_;
  std::ofstream stream_;
};

// Writes bigger text files in chunks without holding the whole file in memory.
class ChunkedWriter {
 public:
  explicit ChunkedWriter(std::ostream& out) : out_(out) {}
  ~ChunkedWriter() = default;
  std::string& buffer() { return buffer_; }
  void maybeFlush() {
    if (buffer_.size() > (1u << 20)) flush();
  }
  void flush() {
    out_.write(buffer_.data(), static_cast<std::streamsize>(buffer_.size()));
    buffer_.clear();
  }

 private:
  std::ostream& out_;
  std::string buffer_;
};

// Shortest text that reads back as the value.
void appendNumber(std::string& out, double value);
void appendNumber(std::string& out, long long value);

void putLittleEndian32(std::string& out, uint32_t bits);
void putFloat(std::string& out, double value);   // as a little-endian float
void putDouble(std::string& out, double value);  // little-endian
void putBigEndian32(std::string& out, uint32_t value);

// Throws "cannot write <path>: ..." unless F's vertices and the layout's rows exist and the
// layout has a corner row per face.
void checkMeshForWriting(const std::string& path, const Positions& V, const Triangles& F,
                         const Layout& layout);

}  // namespace sdp::io::detail
