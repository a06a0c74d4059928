#include "io/write.h"

#include <atomic>
#include <cerrno>
#include <charconv>
#include <chrono>
#include <cstring>
#include <filesystem>
#include <system_error>

namespace sdp::io::detail {

namespace fs = std::filesystem;

AtomicFile::AtomicFile(const std::string& path) : path_(path) {
  static std::atomic<unsigned> counter{0};
  const auto ticks = std::chrono::steady_clock::now().time_since_epoch().count();
  for (int attempt = 0; attempt < 100 && temp_.empty(); ++attempt) {
    const std::string candidate =
        path + ".tmp" + std::to_string(ticks % 1000000) + "_" + std::to_string(counter++);
    std::error_code ec;
    if (!fs::exists(candidate, ec)) temp_ = candidate;
  }
  if (temp_.empty()) throw ParameterizationError("cannot write " + path + ": no temporary name");
  errno = 0;
  stream_.open(temp_, std::ios::out | std::ios::binary | std::ios::trunc);
  if (!stream_) {
    const std::string reason = errno != 0 ? std::strerror(errno) : "cannot create file";
    temp_.clear();
    throw ParameterizationError("cannot write " + path + ": " + reason);
  }
}

AtomicFile::~AtomicFile() {
  if (temp_.empty()) return;
  stream_.close();
  std::error_code ec;
  fs::remove(temp_, ec);
}

void AtomicFile::commit() {
  stream_.flush();
  const bool written = static_cast<bool>(stream_);
  stream_.close();
  if (!written || stream_.fail()) {
    throw ParameterizationError("cannot write " + path_ + ": write failed (disk full?)");
  }
  std::error_code ec;
  fs::rename(temp_, path_, ec);
  if (ec) throw ParameterizationError("cannot write " + path_ + ": " + ec.message());
  temp_.clear();
}

void appendNumber(std::string& out, double value) {
  char buffer[64];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
  out.append(buffer, result.ptr);
}

void appendNumber(std::string& out, long long value) {
  char buffer[32];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
  out.append(buffer, result.ptr);
}

void checkMeshForWriting(const std::string& path, const Positions& V, const Triangles& F,
                         const Layout& layout) {
  if (layout.face_uv.rows() != F.rows()) {
    throw ParameterizationError("cannot write " + path + ": texture corners for " +
                                std::to_string(layout.face_uv.rows()) + " faces, the mesh has " +
                                std::to_string(F.rows()));
  }
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    for (int c = 0; c < 3; ++c) {
      if (F(f, c) < 0 || F(f, c) >= V.rows()) {
        throw ParameterizationError("cannot write " + path + ": face " + std::to_string(f) +
                                    " refers to a missing vertex");
      }
      if (layout.face_uv(f, c) < 0 || layout.face_uv(f, c) >= layout.uv.rows()) {
        throw ParameterizationError("cannot write " + path + ": face " + std::to_string(f) +
                                    " refers to a missing texture coordinate");
      }
    }
  }
}

void putLittleEndian32(std::string& out, uint32_t bits) {
  for (int b = 0; b < 4; ++b) out.push_back(static_cast<char>((bits >> (8 * b)) & 0xff));
}

void putFloat(std::string& out, double value) {
  const float f = static_cast<float>(value);
  uint32_t bits;
  std::memcpy(&bits, &f, sizeof bits);
  putLittleEndian32(out, bits);
}

void putDouble(std::string& out, double value) {
  uint64_t bits;
  std::memcpy(&bits, &value, sizeof bits);
  for (int b = 0; b < 8; ++b) out.push_back(static_cast<char>((bits >> (8 * b)) & 0xff));
}

void putBigEndian32(std::string& out, uint32_t value) {
  for (int b = 3; b >= 0; --b) out.push_back(static_cast<char>((value >> (8 * b)) & 0xff));
}

}  // namespace sdp::io::detail
