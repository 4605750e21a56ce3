#!/usr/bin/env bash
# Installs what is missing from Debian's packages (and nothing when all is present), then
# configures and builds redpost in ./build.
#
#   scripts/setup.sh [extra cmake args...]          everything: the tests, benchmarks, tools
#   scripts/setup.sh --main [extra cmake args...]   only what the main job needs: the library,
#                                                   the CLI and the Tcl package (quickstart.sh)
set -euo pipefail
cd "$(dirname "$0")/.."

mode=full
if [[ ${1:-} == --main ]]; then
  mode=main
  shift
fi

# The library, the CLI and the Tcl package (and the report's three.js, inlined at build time).
packages=(
  build-essential cmake pkg-config
  libeigen3-dev libtinyxml2-dev libfmt-dev libcli11-dev tcl8.6-dev libnlopt-cxx-dev
    libfcl-dev libqhull-dev libjs-three
)
# The test suite, its independent peers, the benchmarks and the reliability tools.
if [[ $mode == full ]]; then
  packages+=(
    catch2 liborocos-kdl-dev libbenchmark-dev clang-format locales time python3
      chromium chromium-driver valgrind clang libclang-rt-dev libxml2-utils
  )
fi

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if ((${#missing[@]})); then
  echo "setup: installing ${missing[*]}"
  sudo=""
  if [ "$(id -u)" -ne 0 ]; then sudo="sudo"; fi
  export DEBIAN_FRONTEND=noninteractive
  $sudo apt-get update -q
  $sudo apt-get install -y -q --no-install-recommends "${missing[@]}"
fi

# The locale test converts under a German locale (decimal comma) and expects identical bytes.
if [[ $mode == full ]] && ! locale -a 2>/dev/null | grep -qi '^de_DE\.utf-\?8$'; then
  echo "setup: generating the de_DE.UTF-8 locale for the locale test"
  sudo=""
  if [ "$(id -u)" -ne 0 ]; then sudo="sudo"; fi
  $sudo localedef -i de_DE -f UTF-8 de_DE.UTF-8 || echo "setup: could not generate de_DE.UTF-8"
fi

jobs=$(nproc 2>/dev/null || echo 2)
# Both modes say what they build, so that one after the other in the same build/ does not keep
# the other's choice.
if [[ $mode == main ]]; then
  targets=(-DREDPOST_BUILD_TESTS=OFF -DREDPOST_BUILD_BENCHMARKS=OFF)
else
  targets=(-DREDPOST_BUILD_TESTS=ON -DREDPOST_BUILD_BENCHMARKS=ON)
fi
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release "${targets[@]}" "$@" >/dev/null
cmake --build build -j "$jobs"
