#!/usr/bin/env bash
# Configures cullproof as on a machine that has only the culling library's packages (GLM,
# nlohmann_json, Highway, Boost): every other dependency is hidden from find_package and
# find_program. The configure succeeds, names each part it skips and what that part needs, and
# configures the culling library's targets and none of the others.
set -euo pipefail
source_dir=$1
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
hidden=()
for p in CGAL rapidcheck TBB fmt GTest CLI11 benchmark PkgConfig Vulkan glslang; do
  hidden+=("-DCMAKE_DISABLE_FIND_PACKAGE_$p=ON")
done
if ! cmake -S "$source_dir" -B "$work/build" -G Ninja "${hidden[@]}" -DCULLPROOF_NODE=CULLPROOF_NODE-NOTFOUND \
    > "$work/configure.log" 2>&1; then
  echo "the configure failed:"
  cat "$work/configure.log"
  exit 1
fi
status=0
for part in "skipping the oracle .*CGAL" "skipping the generators .*RapidCheck" "skipping the cullproof program: CLI11" \
            "skipping the tests: GoogleTest" "skipping the benchmarks: Google Benchmark" \
            "skipping the engine adapters .*pkg-config" "skipping the GPU shaders .*Vulkan" \
            "skipped for want of a dependency"; do
  if ! grep -q -- "$part" "$work/configure.log"; then
    echo "the configure does not say: $part"
    status=1
  fi
done
targets=$(ninja -C "$work/build" -t targets all)
for t in cullproof_core cullproof_io cullproof_simd cullproof_methods; do
  grep -q "^$t:" <<< "$targets" || { echo "no target $t"; status=1; }
done
for t in cullproof_oracle cullproof_gen cullproof_campaign cullproof_gpu cullproof; do
  if grep -q "^$t:" <<< "$targets"; then
    echo "target $t is configured although its dependencies are hidden"
    status=1
  fi
done
[ "$status" -eq 0 ] && grep "cullproof:" "$work/configure.log"
exit "$status"
