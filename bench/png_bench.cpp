// The checkerboard PNG: the project's writer (zlib's deflate in a PNG container, io/png.cpp)
// against libpng's, on the default (1024) and the largest (8192) texture size. Both files are
// read back with libpng and compared with the pixels. bench/readers.py runs it.
//   sdp_png_bench FOLDER   prints one line per size: seconds and bytes of each, and whether
//                          both decode to the pixels
#include <png.h>

#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "best_of_three.h"
#include "io/checkerboard.h"
#include "io/mesh_io.h"

namespace {

bool writeWithLibpng(const std::string& path, int size, const std::vector<unsigned char>& rgb) {
  FILE* file = std::fopen(path.c_str(), "wb");
  if (!file) return false;
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  png_infop info = png_create_info_struct(png);
  if (setjmp(png_jmpbuf(png))) {
    png_destroy_write_struct(&png, &info);
    std::fclose(file);
    return false;
  }
  png_init_io(png, file);
  png_set_IHDR(png, info, size, size, 8, PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE,
               PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  png_write_info(png, info);
  for (int y = 0; y < size; ++y)
    png_write_row(png, const_cast<png_bytep>(rgb.data() + static_cast<size_t>(y) * size * 3));
  png_write_end(png, nullptr);
  png_destroy_write_struct(&png, &info);
  return std::fclose(file) == 0;
}

bool decodesTo(const std::string& path, int size, const std::vector<unsigned char>& rgb) {
  png_image image{};
  image.version = PNG_IMAGE_VERSION;
  if (!png_image_begin_read_from_file(&image, path.c_str())) return false;
  image.format = PNG_FORMAT_RGB;
  std::vector<unsigned char> pixels(PNG_IMAGE_SIZE(image));
  const bool read = png_image_finish_read(&image, nullptr, pixels.data(), 0, nullptr);
  return read && static_cast<int>(image.width) == size && pixels == rgb;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: sdp_png_bench FOLDER\n");
    return 2;
  }
  const std::filesystem::path folder = argv[1];
  for (const int size : {1024, 8192}) {
    const std::vector<unsigned char> rgb = sdp::checkerboardRGB(size, 16);
    const std::string ours = (folder / ("ours_" + std::to_string(size) + ".png")).string();
    const std::string libpng = (folder / ("libpng_" + std::to_string(size) + ".png")).string();
    const double ours_s =
        sdp::bench::bestOfThreeSeconds([&] { sdp::io::writePng(ours, size, size, rgb); });
    bool written = true;
    const double libpng_s = sdp::bench::bestOfThreeSeconds(
        [&] { written = written && writeWithLibpng(libpng, size, rgb); });
    std::printf("%d ours %.4f s %ju bytes %s libpng %.4f s %ju bytes %s\n", size, ours_s,
                static_cast<uintmax_t>(std::filesystem::file_size(ours)),
                decodesTo(ours, size, rgb) ? "decodes" : "WRONG", libpng_s,
                static_cast<uintmax_t>(std::filesystem::file_size(libpng)),
                written && decodesTo(libpng, size, rgb) ? "decodes" : "WRONG");
  }
  return 0;
}
