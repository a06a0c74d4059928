// PNG out: 8-bit RGB, deflated with zlib, no filter (the checkerboard compresses well as is).
#include <zlib.h>

#include <string>
#include <vector>

#include "io/write.h"

namespace sdp::io {
namespace {

using detail::putBigEndian32;

void appendPngChunk(std::string& png, const char type[4], const std::string& data) {
  putBigEndian32(png, static_cast<uint32_t>(data.size()));
  const size_t type_offset = png.size();
  png.append(type, 4);
  png += data;
  uLong crc = crc32(0L, Z_NULL, 0);
  crc = crc32(crc, reinterpret_cast<const Bytef*>(png.data() + type_offset),
              static_cast<uInt>(4 + data.size()));
  putBigEndian32(png, static_cast<uint32_t>(crc));
}

}  // namespace

void writePng(const std::string& path, int width, int height,
              const std::vector<unsigned char>& rgb) {
  if (width <= 0 || height <= 0 || width > (1 << 16) || height > (1 << 16)) {
    throw ParameterizationError("cannot write " + path + ": bad image size " +
                                std::to_string(width) + "x" + std::to_string(height));
  }
  const size_t row_bytes = static_cast<size_t>(width) * 3;
  if (rgb.size() != row_bytes * static_cast<size_t>(height)) {
    throw ParameterizationError("cannot write " + path + ": pixel buffer has the wrong size");
  }
  // Each scanline is preceded by its filter type; 0 (none) keeps the encoder trivial.
  std::string raw;
  raw.reserve((row_bytes + 1) * static_cast<size_t>(height));
  for (int y = 0; y < height; ++y) {
    raw.push_back(0);
    raw.append(reinterpret_cast<const char*>(rgb.data()) + y * row_bytes, row_bytes);
  }
  uLongf compressed_size = compressBound(static_cast<uLong>(raw.size()));
  std::string compressed(compressed_size, '\0');
  if (compress2(reinterpret_cast<Bytef*>(compressed.data()), &compressed_size,
                reinterpret_cast<const Bytef*>(raw.data()), static_cast<uLong>(raw.size()),
                Z_DEFAULT_COMPRESSION) != Z_OK) {
    throw ParameterizationError("cannot write " + path + ": zlib compression failed");
  }
  compressed.resize(compressed_size);

  std::string header;
  putBigEndian32(header, static_cast<uint32_t>(width));
  putBigEndian32(header, static_cast<uint32_t>(height));
  header +=
      std::string("\x08\x02\x00\x00\x00", 5);  // 8 bits, RGB, deflate, no filter, no interlace

  std::string png("\x89PNG\r\n\x1a\n", 8);
  appendPngChunk(png, "IHDR", header);
  appendPngChunk(png, "IDAT", compressed);
  appendPngChunk(png, "IEND", std::string());

  detail::AtomicFile file(path);
  file.stream().write(png.data(), static_cast<std::streamsize>(png.size()));
  file.commit();
}

}  // namespace sdp::io
