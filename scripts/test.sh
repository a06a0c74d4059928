#!/usr/bin/env bash
# The whole test suite on a fresh Debian 12 machine (the README's test command; CI runs it):
# installs dependencies, builds everything (core, CLI, both MeshLab plugins, tests) and runs
# ctest: core and CLI GoogleTests, real meshlabserver and MeshLab GUI under Xvfb, and pytest
# inside real pymeshlab. Fails if any front end could not be built or tested.
#   SDP_BUILD_DIR=DIR   build folder (default: <repo>/build)
#   SDP_SANITIZE=1      build with AddressSanitizer + UBSan (separate folder build-asan)
set -euo pipefail

repo_dir=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
cd "$repo_dir"
sanitize="${SDP_SANITIZE:-0}"
default_build=build
[[ "$sanitize" == 1 ]] && default_build=build-asan
build_dir="${SDP_BUILD_DIR:-$repo_dir/$default_build}"

bash scripts/install-deps.sh

sanitize_flag=OFF
[[ "$sanitize" == 1 ]] && sanitize_flag=ON
cmake -S . -B "$build_dir" -DCMAKE_BUILD_TYPE=Release -DSDP_SANITIZE="$sanitize_flag"
cmake --build "$build_dir" -j"$(nproc)"

# A front end that silently dropped out of the build would leave its tests unregistered:
# refuse that instead of reporting fewer tests as a pass.
for plugin in meshlab-2020.09 meshlab-2025.07; do
  if [[ ! -f "$build_dir/plugins/$plugin/libfilter_straightest_param.so" ]]; then
    echo "test.sh: $build_dir/plugins/$plugin/libfilter_straightest_param.so was not built" >&2
    exit 1
  fi
done

cd "$build_dir"
ctest --output-on-failure --timeout 900
