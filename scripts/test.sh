#!/usr/bin/env bash
# The whole test suite on a fresh Debian 12 machine (the README's test command; CI runs it):
#  1. installs dependencies, checks that every C++ file is clang-formatted, builds everything (core,
#     CLI, one MeshLab plugin per row of meshlab-builds.tsv, tests, bench) and runs ctest: core and
#     CLI GoogleTests, robustness cases, real meshlabserver and this machine's MeshLab GUI under
#     Xvfb, the newer MeshLab GUIs (and their own plugin loaders, headless) in Debian roots, and
#     pytest inside real pymeshlab;
#  2. builds the Debian packages and the pip package and tests them as installed
#     (scripts/test-packages.sh);
#  3. builds the core, CLI and their tests again with AddressSanitizer + UBSan and runs them;
#  4. replays the fuzz regression inputs and fuzzes the mesh pipeline (120,000 inputs from a fixed seed).
# Fails if any step fails or any front end could not be built.
#   SDP_BUILD_DIR=DIR   build folder (default: <repo>/build)
#   SDP_QUICK=1         step 1 only
#   SDP_SKIP_ROOTS=1    no trixie/sid roots: their plugins link unchecked and their tests are not run
set -euo pipefail

repo_dir=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
cd "$repo_dir"
build_dir="${SDP_BUILD_DIR:-$repo_dir/build}"

# Each stage prints the seconds it took, so a slow CI run shows where the time went.
suite_started=$SECONDS
stage() {  # name command...
  local name=$1 started=$SECONDS
  shift
  echo "test.sh: stage '$name'"
  "$@"
  echo "test.sh: stage '$name' took $((SECONDS - started)) s (total $((SECONDS - suite_started)) s)"
}

stage "install dependencies" bash scripts/install-deps.sh
stage "format check" bash scripts/check-format.sh

stage "configure" cmake -S . -B "$build_dir" -DCMAKE_BUILD_TYPE=Release
stage "build" cmake --build "$build_dir" -j"${SDP_JOBS:-$(nproc)}"

# A front end that silently dropped out of the build would leave its tests unregistered:
# refuse that instead of reporting fewer tests as a pass.
source scripts/meshlab-builds.sh
for plugin in $(meshlab_builds | cut -f1); do
  if [[ ! -f "$build_dir/plugins/$plugin/libfilter_straightest_param.so" ]]; then
    echo "test.sh: $build_dir/plugins/$plugin/libfilter_straightest_param.so was not built" >&2
    exit 1
  fi
done

# The same for the tests inside the Debian roots (registered only when the roots exist): per
# build three GUI tests (per-user and system plugin folder, the atlas) and, on the bundled meshes
# alone, four headless cases (more with the extra meshes of SDP_SHARED_DIR).
if [[ "${SDP_SKIP_ROOTS:-0}" != 1 ]]; then
  root_builds=$(meshlab_root_builds | wc -l)
  registered=$(cd "$build_dir" && ctest -N -L meshlab_roots | awk '/^Total Tests:/ { print $3 }')
  if [[ "${registered:-0}" -lt $((7 * root_builds)) ]]; then
    echo "test.sh: only ${registered:-0} tests in the MeshLab roots registered (want $((7 * root_builds)) or more for $root_builds builds): see the configure warnings" >&2
    exit 1
  fi
fi

# The vcglib adapter tests: one group (ctest prefix vcg<version>.) per MeshLab source tree of the
# table, each built against that tree's vcglib; a missing source must not pass as fewer tests.
vcglib_versions=$(meshlab_sources | wc -l)
vcglib_groups=$(cd "$build_dir" && ctest -N -L vcg_adapters |
  sed -n 's/^ *Test *#[0-9]*: vcg\([0-9_]*\)\..*/\1/p' | sort -u | wc -l)
if [[ "$vcglib_groups" -lt "$vcglib_versions" ]]; then
  echo "test.sh: $vcglib_groups vcglib adapter test groups registered, want $vcglib_versions (one per MeshLab source of meshlab-builds.tsv): see the configure warnings" >&2
  exit 1
fi

run_ctest() { (cd "$build_dir" && ctest --output-on-failure --timeout 900); }
stage "ctest" run_ctest
[[ "${SDP_QUICK:-0}" == 1 ]] && exit 0

stage "packages: .deb in each MeshLab, wheel in a fresh venv" bash scripts/test-packages.sh "$build_dir"

stage "core and CLI tests under AddressSanitizer + UndefinedBehaviorSanitizer" bash scripts/sanitize.sh
stage "fuzzing" bash scripts/fuzz.sh
