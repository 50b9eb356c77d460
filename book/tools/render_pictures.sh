#!/usr/bin/env bash
# The book's pictures of cells and schedules: `declutter show` pages photographed by
# headless Chromium, the path tests/show_browser.rs checks. Run from the repository
# root after `cargo build --release`:
#
#   book/tools/render_pictures.sh           # into book/src/figures/generated/ (untracked)
#   book/tools/render_pictures.sh --commit  # also over the committed copies in figures/replay/
#
# The pages show the generated picture and fall back to the committed copy when the
# build could not run a browser.
set -euo pipefail
fig=book/src/figures
gen=$fig/generated
mkdir -p "$gen"
chrome=$(command -v chromium || command -v chromium-browser || command -v google-chrome || true)
if [ -z "$chrome" ]; then
  echo "render_pictures: no chromium: the book shows the committed pictures" >&2
  exit 0
fi
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
bin=./target/release/declutter
for ex in box_lid cans_5; do
  "$bin" compile "examples/$ex.dcl" -o "$tmp/$ex.yaml" 2>/dev/null
  "$bin" show "examples/$ex.dcl" "$tmp/$ex.yaml" -o "$tmp/$ex.html" 2>/dev/null
done
"$bin" show examples/box_lid.dcl -o "$tmp/box_lid_cell.html" 2>/dev/null

pictures=()
# shot NAME PAGE HASH: the page at that moment, without its panels.
shot() {
  "$chrome" --headless --no-sandbox --disable-dev-shm-usage --user-data-dir="$tmp/profile" \
    --use-angle=swiftshader --enable-unsafe-swiftshader --disable-background-networking \
    --disable-component-update --no-first-run --disable-sync --window-size=900,560 \
    --virtual-time-budget=8000 --screenshot="$gen/$1.png" "file://$tmp/$2#$3&bare" >/dev/null 2>&1
  pictures+=("$1")
}
shot box_lid-cell box_lid_cell.html at=0
shot box_lid-lid box_lid.html at=0.42
shot box_lid-end box_lid.html t=4.4
shot cans_5-middle cans_5.html at=0.3

if [ "${1:-}" = --commit ]; then
  mkdir -p "$fig/replay"
  for p in "${pictures[@]}"; do cp "$gen/$p.png" "$fig/replay/$p.png"; done
  echo "render_pictures: committed copies updated in $fig/replay/" >&2
fi
