#!/usr/bin/env bash
# Core, CLI and robustness tests built with AddressSanitizer + UndefinedBehaviorSanitizer
# (CMake option SDP_SANITIZE) in build-asan. The MeshLab plugins are left out: a sanitized
# plugin cannot be loaded into the uninstrumented MeshLab and pymeshlab binaries.
set -euo pipefail
repo_dir=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
cd "$repo_dir"
build_dir="${SDP_ASAN_BUILD_DIR:-$repo_dir/build-asan}"
cmake -S . -B "$build_dir" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DSDP_SANITIZE=ON \
  -DSDP_BUILD_PLUGINS=OFF -DSDP_BUILD_BENCH=OFF > /dev/null
cmake --build "$build_dir" -j"${SDP_JOBS:-$(nproc)}"
cd "$build_dir"
ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
  ctest --output-on-failure --timeout 900 -L "core|cli|robustness"
