#!/usr/bin/env bash
# Installs the build tree into a temporary prefix and builds examples/consumer against it with
# find_package(cullproof), then runs it; then the same against the build tree's own package. The
# consumer asks for no component, so the package must not look for the other components'
# dependencies: they are hidden from find_package.
set -euo pipefail
build_dir=$1
consumer_src=$2
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
hidden=()
for p in CGAL rapidcheck TBB fmt GTest; do
  hidden+=("-DCMAKE_DISABLE_FIND_PACKAGE_$p=ON")
done
flags=""
if grep -qw fma /proc/cpuinfo 2> /dev/null; then
  flags="-mfma -ffp-contract=fast"
fi
cmake --install "$build_dir" --prefix "$work/prefix" > "$work/install.log"
cmake -S "$consumer_src" -B "$work/build" -DCMAKE_PREFIX_PATH="$work/prefix" -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_FLAGS="$flags" "${hidden[@]}" \
  > "$work/configure.log" || { cat "$work/configure.log"; exit 1; }
cmake --build "$work/build" > "$work/build.log" || { cat "$work/build.log"; exit 1; }
"$work/build/consumer"
cmake -S "$consumer_src" -B "$work/build-tree" -Dcullproof_DIR="$build_dir" -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_FLAGS="$flags" "${hidden[@]}" \
  > "$work/configure-tree.log" || { cat "$work/configure-tree.log"; exit 1; }
cmake --build "$work/build-tree" > "$work/build-tree.log" || { cat "$work/build-tree.log"; exit 1; }
"$work/build-tree/consumer"
