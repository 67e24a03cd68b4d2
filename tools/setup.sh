#!/usr/bin/env bash
# Kerf setup: install the Debian packages the project needs (idempotent: apt-get update runs
# once, and only when something is missing), then configure and build.
#
#   bash tools/setup.sh                       # Release-ish build in ./build
#   bash tools/setup.sh --werror              # warnings are errors (CI)
#   bash tools/setup.sh --debug-checks        # arm KERF_ASSERT (CI builds do)
#   bash tools/setup.sh --build-dir build-asan --sanitize address,undefined
#   bash tools/setup.sh --fuzz --build-dir build-asan    # clang, ASan+UBSan: tests + fuzz targets
#   bash tools/setup.sh --bench-peers         # also VTK and CGAL, for the cutting benchmark
#   bash tools/setup.sh --no-build            # packages only
set -euo pipefail

here=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build_dir="$here/build"
build_type=RelWithDebInfo
werror=OFF
debug_checks=OFF
sanitize=""
fuzz=OFF
bench_peers=0
do_build=1
targets=()

usage() { sed -n '2,13p' "${BASH_SOURCE[0]}" | sed 's/^# \{0,1\}//'; }
while [[ $# -gt 0 ]]; do
  case "$1" in
    --build-dir) build_dir=$(realpath -m "$2"); shift 2 ;;
    --type) build_type="$2"; shift 2 ;;
    --werror) werror=ON; shift ;;
    --debug-checks) debug_checks=ON; shift ;;
    --sanitize) sanitize="$2"; shift 2 ;;
    --fuzz) fuzz=ON; shift ;;
    --bench-peers) bench_peers=1; shift ;;
    --no-build) do_build=0; shift ;;
    --target) targets+=(--target "$2"); shift 2 ;;
    -h|--help) usage; exit 0 ;;
    *) echo "setup.sh: unknown argument '$1' (try --help)" >&2; exit 2 ;;
  esac
done

packages=(
  build-essential cmake pkg-config ninja-build ccache clang libclang-rt-14-dev
  libopenmesh-dev libglm-dev libhidapi-dev libusb-1.0-0-dev
  libegl-dev libgles-dev libgbm-dev libegl-mesa0 libgl1-mesa-dri
  libtomlplusplus-dev libspdlog-dev libcli11-dev libstb-dev libboost-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  clang-format-14
  libembree-dev
  valgrind
  libx11-dev libdrm-dev xvfb
  nlohmann-json3-dev
  gnuplot-nox
)
if [[ $bench_peers == 1 ]]; then packages+=(libvtk9-dev libcgal-dev libjsoncpp-dev); fi

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [[ ${#missing[@]} -gt 0 ]]; then
  echo "setup.sh: installing ${missing[*]}"
  sudo_cmd=""; [[ $(id -u) -ne 0 ]] && sudo_cmd=sudo
  $sudo_cmd apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo_cmd apt-get install -y -qq --no-install-recommends "${missing[@]}"
else
  echo "setup.sh: all ${#packages[@]} Debian packages present"
fi
[[ $do_build == 1 ]] || exit 0

# ccache keyed on paths relative to the checkout, so a fresh clone anywhere (CI clones main
# afresh every run) reuses what an earlier clone compiled; the price is that a cached object's
# debug info names the directory it was first compiled in.
export CCACHE_BASEDIR="${CCACHE_BASEDIR:-$here}" CCACHE_NOHASHDIR="${CCACHE_NOHASHDIR:-true}"
cmake_args=(-S "$here" -B "$build_dir" -G Ninja -DCMAKE_BUILD_TYPE="$build_type"
            -DKERF_WERROR="$werror" -DKERF_DEBUG_CHECKS="$debug_checks" -DKERF_SANITIZE="$sanitize" -DKERF_FUZZ="$fuzz"
            -DCMAKE_C_COMPILER_LAUNCHER=ccache -DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
if [[ $bench_peers == 1 ]]; then
  # Forget any earlier "not found" so CMake searches again, and make a missing peer an error.
  cmake_args+=(-DKERF_BENCH_PEERS=ON -UVTK_DIR -UCGAL_DIR)
fi
if [[ $fuzz == ON ]]; then
  cmake_args+=(-DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++)
fi
if [[ $fuzz == ON || -n $sanitize ]]; then
  # Sanitizer builds run tests, never benchmarks; -O1 and line tables only keep them quick to
  # build on 2 cores while reports still name file and line.
  cmake_args+=(-DKERF_BENCH=OFF -DCMAKE_C_FLAGS_RELWITHDEBINFO="-O1 -g1 -DNDEBUG"
               -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1 -DNDEBUG")
fi
cmake "${cmake_args[@]}"
cmake --build "$build_dir" -j "$(nproc)" "${targets[@]}"
echo "setup.sh: built in $build_dir"
