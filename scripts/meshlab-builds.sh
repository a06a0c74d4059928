#!/usr/bin/env bash
# Sourced by the scripts that need the MeshLab builds (meshlab-builds.tsv at the repository's
# top): `meshlab_builds` prints its rows without comments, tab-separated, in the table's order:
#   while IFS=$'\t' read -r folder version api scalar runs_in tarball sha256 deb root_extras users source; do
#     ...
#   done < <(meshlab_builds)
# `meshlab_root_builds` the rows whose MeshLab runs in a Debian root (runs_in is a suite, not
# host or pymeshlab*), and `meshlab_root_suites` those suites, once each;
# `meshlab_pymeshlab_builds` the rows that run in a pymeshlab wheel (runs_in pymeshlab or
# pymeshlab-VERSION), and `meshlab_sources` each source version once (column 11).
meshlab_builds_table="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)/meshlab-builds.tsv"
meshlab_builds() {
  grep -v -e '^#' -e '^[[:space:]]*$' "$meshlab_builds_table"
}
meshlab_root_builds() {
  meshlab_builds | awk -F'\t' '$5 != "host" && $5 !~ /^pymeshlab/'
}
meshlab_pymeshlab_builds() {
  meshlab_builds | awk -F'\t' '$5 ~ /^pymeshlab/'
}
meshlab_sources() {
  meshlab_builds | awk -F'\t' '!seen[$11]++ { print $11 }'
}
meshlab_root_suites() {
  meshlab_root_builds | awk -F'\t' '!seen[$5]++ { print $5 }'
}
