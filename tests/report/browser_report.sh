#!/usr/bin/env bash
# The pages in a real browser: a small verification run, its report and the page of one of its
# corpus cases, checked in headless Chromium against the run's JSON and its corpus
# (web/test/check-report.mjs). Screenshots are kept in OUT/screenshots.
#   browser_report.sh CULLPROOF WEB_DIR OUT
set -euo pipefail
cullproof=$1 web=$2 out=$3
if [ ! -d "$web/node_modules/playwright-core" ]; then
  echo "browser_report: $web/node_modules is missing: run scripts/install-deps (npm ci in web/)" >&2
  exit 1
fi
rm -rf "$out"
mkdir -p "$out"
"$cullproof" verify --cases 300 --seed 1 --threads 2 --no-progress --corpus "$out/corpus" --json "$out/verify.json" > "$out/verify.txt"
"$cullproof" report --from "$out/verify.json" --corpus "$out/corpus" --out "$out/report.html" > "$out/report.txt"
id=$("$cullproof" corpus list --dir "$out/corpus" | awk 'NR == 2 { print $1 }')
"$cullproof" corpus show "$id" --dir "$out/corpus" --html "$out/case.html" > /dev/null
node "$web/test/check-report.mjs" --report "$out/report.html" --result "$out/verify.json" --corpus "$out/corpus" \
  --case "$out/case.html" --shots "$out/screenshots"
