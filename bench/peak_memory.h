// Peak resident memory of this process, from /proc (Linux).
#pragma once

#include <fstream>
#include <string>

namespace sdp::bench {

inline double peakRssMegabytes() {
  std::ifstream status("/proc/self/status");
  std::string line;
  while (std::getline(status, line))
    if (line.rfind("VmHWM:", 0) == 0) return std::stod(line.substr(6)) / 1024.0;
  return -1;
}

}  // namespace sdp::bench

namespace sdp::bench {

inline double currentRssMegabytes() {
  std::ifstream status("/proc/self/status");
  std::string line;
  while (std::getline(status, line))
    if (line.rfind("VmRSS:", 0) == 0) return std::stod(line.substr(6)) / 1024.0;
  return -1;
}

// Makes the next peakRssMegabytes() count from now on (Linux clear_refs value 5), so loading
// and subdividing a mesh do not hide the peak of the step being measured.
inline void resetPeakRss() {
  std::ofstream("/proc/self/clear_refs") << "5";
}

}  // namespace sdp::bench
