#!/usr/bin/env bash
# `cullproof verify` when something goes wrong, from the command line:
#   fault      one of the reference adapter's three methods aborts the program on known cases
#              (`several`), asked by two threads through two copies: exit 3; every table, the
#              summary and the JSON are written; the fault names that method and the case; the
#              other two methods are judged to the end; the fault's reproduce line runs as
#              printed and faults on the same case;
#   reproduce  the summary's "first:" lines, for built-in methods and for a method behind the
#              protocol, run as printed and refute the same claim on that one case;
#   interrupt  SIGINT once the first distribution's table is out (so it was printed before the
#              run ended), SIGTERM within the first distribution: the run ends with 128 + the
#              signal, the tables, summary and JSON of what was judged, marked interrupted.
set -uo pipefail
cullproof=$1
adapter=$2
mode=$3
name=cli_verify
source "$(dirname "$0")/cli_common.sh"
# Runs a printed command line as printed, with this build's cullproof first on the PATH, in a
# folder of its own (its corpus goes there).
mkdir "$out/run"
run_line() { (cd "$out/run" && PATH="$(dirname "$cullproof"):$PATH" bash -c "$1" 2>&1); }
case "$mode" in
  fault)
    log=$("$cullproof" verify -d uniform -d corner --cases 2000 --seed 3 --threads 2 --no-progress --external all \
      --external-jobs 2 --json "$out/r.json" --corpus "$out/corpus" -- "$adapter" several 2>&1); status=$?
    echo "$log"
    for d in uniform corner; do
      expect 3 "^## $d "
      expect 3 "^FAULT: method 'reference-fragile' faulted on case [0-9]+ of distribution $d \\(seed 3\\)"
    done
    expect 3 "^\\| reference-pn-vertex \\| user \\| conservative held \\| [0-9]+ "
    expect 3 "^\\| reference-p-vertex \\| user \\| conservative held, two-way \\| [0-9]+ "
    expect 3 "^\\| reference-fragile \\| user \\| conservative not refuted before the fault; FAULT on case [0-9]+ "
    expect 3 "exited \\(signal 6\\) before answering frame [0-9]+ \\(1 volume\\(s\\) for method 'reference-fragile'\\)"
    expect 3 "^faults: 2 "
    expect 3 "^FAILED: 2 fault\\(s\\)"
    grep -q '"failed": true' "$out/r.json" || fail "the JSON does not say the run failed"
    [ "$(grep -c '"problem": "method .reference-fragile. threw: external program' "$out/r.json")" -eq 2 ] || fail "the JSON does not hold two faults"
    [ "$(grep -c '"fault": null' "$out/r.json")" -eq 4 ] || fail "the other methods' faults are not null in the JSON"
    ls "$out"/corpus/faults/reference-fragile/*.json > /dev/null || fail "the fault's case was not saved"
    # The fault's reproduce line, as printed, faults again on the same case.
    line=$(grep -m1 -E '^  reproduce: cullproof verify .*--external reference-fragile' <<< "$log" | sed 's/^  reproduce: //')
    [ -n "$line" ] || fail "no reproduce line for the fault"
    index=$(sed -E 's/.*--index ([0-9]+).*/\1/' <<< "$line")
    log=$(run_line "$line"); status=$?
    echo "$log"
    expect 3 "FAULT: method 'reference-fragile' faulted on case $index of distribution uniform"
    ;;
  reproduce)
    log=$("$cullproof" verify -d corner -d touch --cases 3000 --seed 3 --no-progress --no-corpus 2>&1); status=$?
    echo "$log"
    expect 0 "^claims refuted: "
    lines=$(grep -E '^      first: ' <<< "$log" | sed 's/^      first: //')
    [ -n "$lines" ] || fail "no first: lines"
    log=$("$cullproof" verify -d contact --cases 3000 --seed 3 --no-progress --no-corpus --external reference-pn-vertex \
      -- "$adapter" reject-touching 2>&1); status=$?
    echo "$log"
    expect 1 "first: cullproof verify --seed 3 --distribution contact --index [0-9]+ --external reference-pn-vertex -- "
    lines+=$'\n'$(grep -E '^      first: ' <<< "$log" | sed 's/^      first: //')
    # A program's method named as a built-in one says how to name it.
    log=$("$cullproof" verify -d contact --index 0 --method reference-pn-vertex 2>&1); status=$?
    echo "$log"
    expect 2 "unknown method 'reference-pn-vertex' \\(built-in: .*; a method behind a program is named with --external NAME -- PROGRAM"
    while IFS= read -r line; do
      method=$(sed -E 's/.*(--method|--external) ([^ ]+).*/\2/' <<< "$line")
      echo "== $line"
      log=$(run_line "$line"); status=$?
      echo "$log"
      grep -Eq -- "^\\| $method \\| [a-z]+ \\| [a-z-]+ REFUTED \\(1" <<< "$log" || fail "'$line' does not refute $method on its case"
    done <<< "$lines"
    ;;
  interrupt)
    # SIGINT once the first table is out (the second distribution under way: 2,000,000 `corner`
    # cases take several seconds); SIGTERM a second into the first distribution (10,000,000
    # `corner` cases, where the oracle's exact route runs most, take over ten seconds of an idle
    # 2-core machine).
    for sig in INT TERM; do
      rm -f "$out/r.json"
      families="-d uniform -d corner -d near-boundary"
      cases=2000000
      if [ $sig = TERM ]; then families="-d corner -d uniform -d near-boundary" cases=10000000; fi
      "$cullproof" verify $families --cases $cases -m pn-vertex --threads 2 --no-progress \
        --no-corpus --json "$out/r.json" > "$out/log" 2>&1 &
      pid=$!
      if [ $sig = INT ]; then
        for _ in $(seq 1200); do
          grep -q '^## uniform ' "$out/log" && break
          kill -0 $pid 2> /dev/null || { cat "$out/log"; fail "the run ended before it was interrupted"; }
          sleep 0.5
        done
        grep -q '^## uniform ' "$out/log" || { kill -9 $pid; fail "the first table was not printed while the run went on"; }
      else
        sleep 1
      fi
      kill -$sig $pid
      wait $pid; status=$?
      log=$(cat "$out/log")
      echo "$log"
      if [ $sig = INT ]; then
        expect 130 "^## corner \\([0-9]+ cases: INTERRUPTED: [0-9]+ of 2000000 cases judged;"
        expect 130 "^INTERRUPTED: the run was stopped; the counts are over the cases judged, and 1 distribution\\(s\\) were not run"
        expect 130 "^INTERRUPTED by signal 2"
        grep -q '"cases": 2000000,' "$out/r.json" || fail "the first distribution is not whole in the JSON"
      else
        expect 143 "^## corner \\([0-9]+ cases: INTERRUPTED: [0-9]+ of 10000000 cases judged;"
        expect 143 "^INTERRUPTED: the run was stopped; the counts are over the cases judged, and 2 distribution\\(s\\) were not run"
        expect 143 "^INTERRUPTED by signal 15"
      fi
      expect $status "^interrupted: "
      grep -q '"interrupted": true' "$out/r.json" || fail "the JSON does not say interrupted"
    done
    ;;
  *)
    fail "unknown mode '$mode' (fault, reproduce, interrupt)"
    ;;
esac
