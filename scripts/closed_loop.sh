#!/usr/bin/env bash
# The closed-loop accuracy study of photo analysis (issue #6; tests/closed_loop.h):
# runs the ClosedLoop test with PLUMAGE_CLOSED_LOOP_REPORT set, then puts its table
# into docs/analysis.md (between the closed-loop markers) and its three overlays
# into docs/images/closed-loop-{1,2,3}.jpg.
#   scripts/closed_loop.sh            (needs a built build/plumage_tests)
#   BUILD_DIR=... scripts/closed_loop.sh
set -euo pipefail
cd "$(dirname "$0")/.."
build=${BUILD_DIR:-build}
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
status=0
PLUMAGE_CLOSED_LOOP_REPORT="$out" "$build/plumage_tests" \
  --gtest_filter='ClosedLoop.TwentyRenderedFeathersOnWhiteAndBlackMeetTheBounds' || status=$?
[ -f "$out/closed-loop-table.md" ] || { echo "closed_loop.sh: the study wrote no table" >&2; exit 1; }
python3 scripts/doc_table.py docs/analysis.md closed-loop "$out/closed-loop-table.md"
for i in 1 2 3; do cp "$out/closed-loop-$i.jpg" "docs/images/closed-loop-$i.jpg"; done
echo "closed_loop.sh: table in docs/analysis.md, overlays in docs/images/closed-loop-{1,2,3}.jpg (test status $status)"
exit $status
