#!/usr/bin/env bash
# Installs the build tree into a temporary prefix, configures an example project against it with
# find_package(cullproof COMPONENTS gtest), builds it and runs its tests, then checks what the
# example shows:
#   culler (examples/verify-my-culler): the correct culler holds its claim, the planted bug is
#     refuted with a shrunk case written to its corpus folder;
#   system (examples/verify-my-system): the correct system holds its claim, the planted bug is
#     refuted.
set -euo pipefail
build_dir=$1
example_src=$2
kind=$3
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cmake --install "$build_dir" --prefix "$work/prefix" > "$work/install.log"
cmake -S "$example_src" -B "$work/build" -G Ninja -DCMAKE_PREFIX_PATH="$work/prefix" -DCMAKE_BUILD_TYPE=Release \
  > "$work/configure.log" || { cat "$work/configure.log"; exit 1; }
cmake --build "$work/build" > "$work/build.log" || { cat "$work/build.log"; exit 1; }
ctest --test-dir "$work/build" --output-on-failure -V | tee "$work/test.log"
case "$kind" in
  culler)
    grep -Eq "MyCuller.HoldsItsClaim .*Passed" "$work/test.log"
    grep -q "my-culler-with-a-bug (user method) breaks its claim" "$work/test.log"
    ls "$work/build/corpus/my-culler-with-a-bug"/*/*.json > /dev/null
    if [ -d "$work/build/corpus/my-culler" ]; then
      echo "verify_example: the correct culler has corpus cases" >&2
      exit 1
    fi
    echo "verify_example: correct culler held, planted bug refuted with $(ls "$work/build/corpus/my-culler-with-a-bug"/*/*.json | wc -l) shrunk case(s)"
    ;;
  system)
    grep -Eq "MySystem.HoldsItsClaim .*Passed" "$work/test.log"
    grep -Eq "MySystemWithABug.IsCaught .*Passed" "$work/test.log"
    grep -q "my-grid-with-a-bug (user system) breaks its claim 'conservative'" "$work/test.log"
    echo "verify_example: correct system held, planted bug refuted"
    ;;
  *)
    echo "verify_example: unknown example kind '$kind' (culler, system)" >&2
    exit 2
    ;;
esac
