#!/usr/bin/env bash
# Fuzzes the mesh pipeline (reader -> parameterize -> verification) with libFuzzer under
# AddressSanitizer + UBSan, in its own clang build folder (build-fuzz).
#   bash scripts/fuzz.sh            the test suite's run: replay the regression inputs, then 120,000
#                                   inputs from seed 1 and the seed meshes alone (5-6 minutes here,
#                                   15 at most). The log carries each finding, so a CI result replays.
#   bash scripts/fuzz.sh --seconds 3600 [--seed N]   a longer run from a random seed (or N) that
#                                   keeps its corpus in build-fuzz/corpus between runs: finds new
#                                   inputs (documented in docs/robustness.md).
# Seeds: the test meshes (resources/meshes, plus SDP_SHARED_DIR's when there; STL and tristrip
# PLY from resources/meshes/inputs) and tests/fuzz/regressions (inputs that once failed, kept
# forever).
# New findings land in build-fuzz/findings/; the run fails if there is one.
set -euo pipefail
repo_dir=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
cd "$repo_dir"
seconds=""
fuzz_seed=""
while [[ $# -gt 0 ]]; do
  case "$1" in
    --seconds) seconds="$2"; shift 2 ;;
    --seed) fuzz_seed="$2"; shift 2 ;;
    *) echo "fuzz.sh: unknown argument $1" >&2; exit 2 ;;
  esac
done
shared_dir="${SDP_SHARED_DIR:-$repo_dir/../shared}"
build_dir="$repo_dir/build-fuzz"
if [[ -z "$seconds" ]]; then
  # The suite's run: a fresh corpus, a fixed seed and a fixed number of inputs (the time limit
  # only guards a machine far slower than this one).
  corpus="$build_dir/corpus-suite"
  rm -rf "$corpus"
  limits=(-seed="${fuzz_seed:-1}" -runs=120000 -max_total_time=900)
  what="120000 inputs from seed ${fuzz_seed:-1}"
else
  corpus="$build_dir/corpus"
  limits=(-seed="${fuzz_seed:-0}" -max_total_time="$seconds")
  what="$seconds s from seed ${fuzz_seed:-0} (0: random)"
fi

CC=clang CXX=clang++ cmake -S . -B "$build_dir" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DSDP_FUZZ=ON \
  -DSDP_BUILD_PLUGINS=OFF -DSDP_BUILD_TESTS=OFF -DSDP_BUILD_BENCH=OFF > /dev/null
nice -n 10 cmake --build "$build_dir" -j"${SDP_JOBS:-$(nproc)}" --target fuzz_mesh_pipeline
fuzzer="$build_dir/bin/fuzz_mesh_pipeline"

# Seed corpus: each test mesh as an OFF input (format byte 0) with default options: the bundled
# ones, then the extra set's others when it is there (a name seeds once; the copies are identical).
rm -rf "$build_dir/findings"  # a finding is reported once; keep it in tests/fuzz/regressions
mkdir -p "$corpus" "$build_dir/findings"
bundled="$repo_dir/resources/meshes"
for mesh in "$bundled"/disk/nefertiti.off "$bundled"/invalid/*.off \
            "$shared_dir"/meshes/disk/nefertiti.off "$shared_dir"/meshes/invalid/*.off \
            "$shared_dir"/meshes/holes/halftunnel_quads.off; do
  [[ -f "$mesh" ]] || continue
  seed="$corpus/seed_$(basename "$mesh")"
  [[ -f "$seed" ]] || { printf '\x00\x00\x00\x00' > "$seed"; cat "$mesh" >> "$seed"; }
done
# The atlas path (byte 3, bit 7): closed, many-piece and bad meshes, 64-texel texture.
for mesh in "$bundled"/closed/*.off "$bundled"/invalid/*.off "$shared_dir"/meshes/invalid/*.off; do
  [[ -f "$mesh" ]] || continue
  seed="$corpus/atlas_seed_$(basename "$mesh")"
  [[ -f "$seed" ]] || { printf '\x00\x00\x02\x80' > "$seed"; cat "$mesh" >> "$seed"; }
done

# STL (format byte 3, binary and ASCII) and PLY tristrips (format byte 2), through the atlas.
for entry in "03 torus_binary.stl" "03 torus_ascii.stl" "02 torus_tristrips.ply"; do
  mesh="$bundled/inputs/${entry#* }"
  seed="$corpus/atlas_seed_${entry#* }"
  [[ -f "$seed" ]] || { printf "\\x${entry%% *}\\x00\\x02\\x80" > "$seed"; cat "$mesh" >> "$seed"; }
done

echo "fuzz: replaying $(ls tests/fuzz/regressions | wc -l) regression inputs"
if compgen -G "tests/fuzz/regressions/*" > /dev/null; then
  "$fuzzer" tests/fuzz/regressions/* 2>&1 | tail -n 2
fi
echo "fuzz: fuzzing $what"
# A finding is a crash, a sanitizer report, a leak, an allocation past the limit or an input that
# runs 60 s (a hang: the slowest seen here take 2 s alone and 7 s beside a build, under the
# sanitizers). Slow but finishing inputs are shown, not failed: libFuzzer would write every
# input slower than 10 s as an artifact, and a slower CI machine crossed that on a 768-face atlas.
"$fuzzer" "${limits[@]}" -max_len=65536 -rss_limit_mb=4096 -timeout=60 -report_slow_units=60 \
  -artifact_prefix="$build_dir/findings/" -print_final_stats=1 "$corpus" 2>&1 |
  grep -E "^(#[0-9]+[[:space:]]+DONE|stat::number_of_executed_units|stat::peak_rss|==[0-9]+== ?ERROR|fuzz finding|SUMMARY|Slowest unit|artifact_prefix)" || true
findings=("$build_dir"/findings/*)
if [[ -e "${findings[0]}" ]]; then
  # Each finding goes into the log, so a CI failure can be replayed where it was not kept:
  #   base64 -d < lines | gunzip > finding; build-fuzz/bin/fuzz_mesh_pipeline finding
  for finding in "${findings[@]}"; do
    echo "fuzz: finding $(basename "$finding") ($(stat -c %s "$finding") bytes), gzip | base64:" >&2
    gzip -9 -c "$finding" | base64 -w 100 | head -n 400 >&2
  done
  echo "fuzz: findings in $build_dir/findings" >&2
  exit 1
fi
echo "fuzz: no findings"
