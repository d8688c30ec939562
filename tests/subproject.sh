#!/usr/bin/env bash
# Builds tests/subproject, which takes cullproof's source tree with add_subdirectory, with no build
# type of its own, and runs its consumer.
set -euo pipefail
source_dir=$1
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
if ! cmake -S "$source_dir/tests/subproject" -B "$work/build" -G Ninja -DCULLPROOF_SOURCE_DIR="$source_dir" > "$work/configure.log" 2>&1; then
  cat "$work/configure.log"
  exit 1
fi
cmake --build "$work/build" --target consumer > "$work/build.log" 2>&1 || { tail -50 "$work/build.log"; exit 1; }
"$work/build/consumer"
