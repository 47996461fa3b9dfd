#!/usr/bin/env bash
# Refits the card response table (renderer/include/plumage/renderer/card_response.h):
# runs RenderMaterial.CardResponseFit with PLUMAGE_CARD_RESPONSE_FIT set, which
# renders the closed vane of tests/render_material_test.cpp over four cards at each
# of the table's albedos under the dome and fits seen / card = through + reflect / c
# + bounce c per albedo, then prints the rows to paste into renderer/src/card_response.cpp
# (about 40 s on 2 cores). Rerun after a change to the hair BCSDF, the substructure,
# the dome rig or the card's placement (BackdropPlacement::Vane).
#   scripts/fit_card_response.sh            (needs a built build/plumage_tests)
#   BUILD_DIR=... scripts/fit_card_response.sh
set -euo pipefail
cd "$(dirname "$0")/.."
build=${BUILD_DIR:-build}
out=$(mktemp)
trap 'rm -f "$out"' EXIT
PLUMAGE_CARD_RESPONSE_FIT="$out" "$build/plumage_tests" --gtest_filter='RenderMaterial.CardResponseFit' > /dev/null
cat "$out"
