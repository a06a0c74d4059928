// The checkerboard texture every front end attaches, so a user sees stretch and folds at once.
#pragma once

#include <vector>

namespace sdp {

// size x size RGB pixels, row-major, top row first; `checkers` squares per side, with a thin
// grid line so that shear stays visible even where squares are large.
std::vector<unsigned char> checkerboardRGB(int size, int checkers);

}  // namespace sdp
