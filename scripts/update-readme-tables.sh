#!/usr/bin/env bash
# Rewrites docs/usage.md's parameter and report tables (patch and atlas filters) from their
# definitions (filter_straightest_param/filter_definition.cpp, core/common/report.cpp,
# core/atlas/atlas.cpp). The test suite's readme_tables test fails until they match.
set -euo pipefail
cd "$(dirname "$0")/.."
build="${BUILD_DIR:-build}"
cmake --build "$build" --target readme_tables >/dev/null
"$build/bin/readme_tables" docs/usage.md --write
echo "docs/usage.md tables updated"
