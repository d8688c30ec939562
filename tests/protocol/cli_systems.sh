#!/usr/bin/env bash
# `cullproof systems` with a culling system behind the process protocol (the reference adapter):
#   holds    the adapter holds its claim: exit 0, "every system held its claim";
#   refuted  its planted bug (drop-near): exit 1, the shrunk run recorded, a reproduce line that
#            names the program;
#   fault    it crashes on the scene message: exit 3, the fault named, the run saved; a built-in
#            system run beside it is judged to the end and its table printed and in the JSON.
set -uo pipefail
cullproof=$1
adapter=$2
mode=$3
name=cli_systems
source "$(dirname "$0")/cli_common.sh"
short=(--runs 2 --objects 100 --frames 6 --external reference-flat --corpus "$out")
case "$mode" in
  holds)
    log=$("$cullproof" systems "${short[@]}" -- "$adapter" 2>&1); status=$?
    echo "$log"
    expect 0 "every system held its claim"
    ;;
  refuted)
    log=$("$cullproof" systems "${short[@]}" --family along-planes -- "$adapter" drop-near 2>&1); status=$?
    echo "$log"
    expect 1 "reproduce: cullproof systems --external reference-flat --family along-planes --index [0-9]+ .* -- .*cullproof_reference_system_adapter drop-near"
    record=$(ls "$out"/systems/reference-flat/along-planes/*.json | head -1)
    [ -n "$record" ] || { echo "cli_systems: no record" >&2; exit 1; }
    # The record replays as recorded with the bug, and as fixed without it (exit 1: no longer failing).
    log=$("$cullproof" systems --replay --external reference-flat --corpus "$out" -- "$adapter" drop-near 2>&1); status=$?
    echo "$log"
    expect 0 "reference-flat/along-planes/.*json +still failing"
    log=$("$cullproof" systems --replay --external reference-flat --corpus "$out" -- "$adapter" 2>&1); status=$?
    echo "$log"
    expect 1 "reference-flat/along-planes/.*json +fixed"
    # corpus show finds it by its name; corpus replay lists it as not replayed (not a built-in system).
    log=$("$cullproof" corpus show "$(basename "$record" .json)" --dir "$out" 2>&1); status=$?
    echo "$log"
    expect 0 "system: reference-flat \\(claim conservative\\)"
    log=$("$cullproof" corpus replay --dir "$out" 2>&1); status=$?
    echo "$log"
    expect 0 "not replayed: system 'reference-flat' is not among those run here"
    ;;
  fault)
    log=$("$cullproof" systems "${short[@]}" --system bvh-masked --family clusters --family straddling --json "$out/r.json" \
      -- "$adapter" crash-on-scene 2>&1); status=$?
    echo "$log"
    expect 3 "FAULT: system 'reference-flat' threw in build on frame 0: .*before answering scene message 1"
    expect 3 "reference-flat faulted: system 'reference-flat' threw in build"
    expect 3 "^  straddling +2 +1200 +0 "
    ls "$out"/systems/faults/reference-flat/clusters-0.json > /dev/null || { echo "cli_systems: the run was not saved" >&2; exit 1; }
    grep -q '"fault": "system .reference-flat. threw in build' "$out/r.json" || { echo "cli_systems: no fault in the JSON" >&2; exit 1; }
    grep -q '"system": "bvh-masked"' "$out/r.json" || { echo "cli_systems: bvh-masked missing from the JSON" >&2; exit 1; }
    ;;
  *)
    echo "cli_systems: unknown mode '$mode' (holds, refuted, fault)" >&2
    exit 2
    ;;
esac
