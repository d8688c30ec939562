#!/usr/bin/env bash
# The pages in a real browser: a small verification run, its report and the page of one of its
# corpus cases, and the page of a culling system's failure (the reference system adapter with its
# planted bug, refuted, shrunk and recorded), checked in headless Chromium against the run's JSON
# and its corpus (web/test/check-report.mjs). Screenshots are kept in OUT/screenshots.
#   browser_report.sh CULLPROOF WEB_DIR OUT SYSTEM_ADAPTER
set -euo pipefail
cullproof=$1 web=$2 out=$3 adapter=$4
if [ ! -d "$web/node_modules/playwright-core" ]; then
  echo "browser_report: $web/node_modules is missing: run scripts/install-deps (npm ci in web/)" >&2
  exit 1
fi
rm -rf "$out"
mkdir -p "$out"
"$cullproof" verify --cases 300 --seed 1 --threads 2 --no-progress --corpus "$out/corpus" --json "$out/verify.json" > "$out/verify.txt"
# The adapter's planted bug (the near plane forgotten) breaks its claim: exit 1, the run recorded
# unshrunk (its other objects drawn beside the failing one).
status=0
"$cullproof" systems --runs 2 --objects 60 --frames 6 --family along-planes --external reference-flat \
  --shrink-budget 0 --corpus "$out/corpus" --json "$out/systems.json" -- "$adapter" drop-near > "$out/systems.txt" || status=$?
if [ "$status" -ne 1 ]; then echo "browser_report: cullproof systems exited $status, not 1" >&2; cat "$out/systems.txt" >&2; exit 1; fi
record=$(ls "$out"/corpus/systems/reference-flat/along-planes/*.json | head -1)
"$cullproof" corpus show "$(basename "$record" .json)" --dir "$out/corpus" --html "$out/system.html" > /dev/null
"$cullproof" report --from "$out/verify.json" --corpus "$out/corpus" --systems "$out/systems.json" --out "$out/report.html" > "$out/report.txt"
id=$("$cullproof" corpus list --dir "$out/corpus" | awk 'NR == 2 { print $1 }')
"$cullproof" corpus show "$id" --dir "$out/corpus" --html "$out/case.html" > /dev/null
node "$web/test/check-report.mjs" --report "$out/report.html" --result "$out/verify.json" --corpus "$out/corpus" \
  --case "$out/case.html" --system "$out/system.html" --systems "$out/systems.json" --shots "$out/screenshots"
