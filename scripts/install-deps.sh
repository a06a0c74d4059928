#!/usr/bin/env bash
# Installs everything the project needs on a fresh Debian 12 (bookworm), as root; safe to re-run:
#   - Debian packages: build tools (+ clang and its libFuzzer runtime), Qt5, Eigen, GoogleTest,
#     CGAL (benchmark peers), Debian 12's MeshLab (GUI + meshlabserver), Xvfb and X tools for the
#     headless MeshLab tests, ImageMagick for screenshots, debootstrap (the Debian roots) and
#     dpkg-dev (the Debian packages);
#   - the source of every MeshLab version in meshlab-builds.tsv, whose headers the plugins compile
#     against (scripts/fetch-meshlab-sources.sh);
#   - a Debian root per suite of that table, holding the MeshLab GUI that the plugin for it is
#     linked against and tested in (scripts/make-meshlab-root.sh; needs root);
#   - .venv/ with pymeshlab (the MeshLab the double-precision plugin runs in), pytest, numpy and
#     auditwheel (it reports the pip package's platform tag), libigl (SLIM, a bench peer);
#   - .venv-pymeshlab-VERSION/ for each older pymeshlab of meshlab-builds.tsv (pipelines pin them).
#
#   SDP_SKIP_APT=1     skip the Debian packages (e.g. when not root and they are already there)
#   SDP_SKIP_ROOTS=1   skip the Debian roots (their plugins then link unchecked, their tests skip)
#   SDP_VENV_DIR=DIR   virtual environment folder (default: <repo>/.venv)
set -euo pipefail

repo_dir=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
venv_dir="${SDP_VENV_DIR:-$repo_dir/.venv}"

debian_packages=(
  build-essential cmake git pkg-config ca-certificates xz-utils
  python3 python3-venv python3-pip
  qtbase5-dev libqt5opengl5-dev libglew-dev libeigen3-dev
  libgtest-dev libcgal-dev zlib1g-dev libpng-dev clang-format
  clang libclang-rt-14-dev
  meshlab
  xvfb xauth xdotool x11-utils imagemagick
  debootstrap dpkg-dev
)
python_requirements=("pymeshlab==2025.7.post1" "pytest" "numpy" "auditwheel==6.8.2" "libigl==2.6.3")

missing_packages() {
  local pkg
  for pkg in "${debian_packages[@]}"; do
    dpkg-query -W -f='${Status}\n' "$pkg" 2>/dev/null | grep -q '^install ok installed$' || echo "$pkg"
  done
}

if [[ "${SDP_SKIP_APT:-0}" != 1 ]]; then
  mapfile -t missing < <(missing_packages)
  if ((${#missing[@]})); then
    if [[ $(id -u) -ne 0 ]]; then
      echo "install-deps: missing Debian packages (run as root): ${missing[*]}" >&2
      exit 1
    fi
    echo "install-deps: installing ${missing[*]}"
    export DEBIAN_FRONTEND=noninteractive
    apt-get update
    apt-get install -y --no-install-recommends "${missing[@]}"
  else
    echo "install-deps: Debian packages already installed"
  fi
fi

"$repo_dir/scripts/fetch-meshlab-sources.sh"

if [[ "${SDP_SKIP_ROOTS:-0}" != 1 ]]; then
  source "$repo_dir/scripts/meshlab-builds.sh"
  for suite in $(meshlab_root_suites); do
    "$repo_dir/scripts/make-meshlab-root.sh" "$suite" >/dev/null
  done
fi

# Debian's own python3 (not a pyenv/conda one first in PATH): python3-venv is installed for it.
python=/usr/bin/python3
[[ -x "$python" ]] || python=$(command -v python3)
# make_venv DIR REQUIREMENT...: a virtual environment holding the requirements (pinned ones at
# their version), made or completed only when something is missing.
make_venv() {
  local dir=$1
  shift
  if [[ ! -x "$dir/bin/python" ]]; then
    echo "install-deps: creating $dir"
    "$python" -m venv "$dir"
  fi
  if "$dir/bin/python" - "$@" <<'PY'
import re
import sys
from importlib.metadata import version, PackageNotFoundError
for requirement in sys.argv[1:]:
    name = re.split(r"[<>=!]", requirement, 1)[0]
    wanted = requirement.partition("==")[2]
    try:
        have = version(name)
    except PackageNotFoundError:
        sys.exit(1)
    if wanted and have != wanted:
        sys.exit(1)
PY
  then
    echo "install-deps: python packages already installed in $dir"
  else
    "$dir/bin/python" -m pip install --disable-pip-version-check "$@"
  fi
}
make_venv "$venv_dir" "${python_requirements[@]}"

# One more per older pymeshlab that pipelines pin (runs_in pymeshlab-VERSION of
# meshlab-builds.tsv): that wheel, pytest, numpy and the row's extra requirements (numpy<2 for
# 2022.2). pip keeps the downloaded wheels in its cache, so a re-run downloads nothing.
source "$repo_dir/scripts/meshlab-builds.sh"
while IFS=$'\t' read -r -u 3 _folder _version _api _scalar runs_in _tarball _sha256 _deb extras _rest; do
  [[ $runs_in == pymeshlab-* ]] || continue
  requirements=("pymeshlab==${runs_in#pymeshlab-}" pytest numpy)
  if [[ $extras != - ]]; then
    IFS=, read -ra more <<<"$extras"
    requirements+=("${more[@]}")
  fi
  make_venv "$repo_dir/.venv-$runs_in" "${requirements[@]}"
done 3< <(meshlab_pymeshlab_builds)
echo "install-deps: done"
