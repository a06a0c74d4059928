#include "checkerboard.h"

#include <algorithm>

namespace sdp {

std::vector<unsigned char> checkerboardRGB(int size, int checkers) {
  size = std::max(size, 2);
  checkers = std::clamp(checkers, 1, size / 2);
  std::vector<unsigned char> rgb(static_cast<size_t>(size) * size * 3);
  const int line = std::max(1, size / (checkers * 32));
  for (int y = 0; y < size; ++y) {
    for (int x = 0; x < size; ++x) {
      const int cx = x * checkers / size, cy = y * checkers / size;
      const bool dark = (cx + cy) % 2 == 1;
      const bool on_line =
          (x * checkers) % size < line * checkers || (y * checkers) % size < line * checkers;
      unsigned char* p = &rgb[(static_cast<size_t>(y) * size + x) * 3];
      if (on_line) {
        p[0] = 200, p[1] = 40, p[2] = 40;  // red grid lines
      } else if (dark) {
        p[0] = 40, p[1] = 40, p[2] = 40;
      } else {
        p[0] = 235, p[1] = 235, p[2] = 235;
      }
    }
  }
  return rgb;
}

}  // namespace sdp
