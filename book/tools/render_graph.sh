#!/usr/bin/env bash
# Renders the box-lid AND/OR graph for Tutorial 3 at book build time. Run from the
# repository root after `cargo build --release`.
#
# Tracked files (book/src/figures/box_lid_graph.dot and its Markdown fragment, the DOT
# text in a code block) are rewritten only when `declutter graph` prints something else,
# so a clean checkout stays clean; tests/book.rs fails in that case too, until they are
# committed. The SVG goes to book/src/figures/generated/, which git ignores: the page
# shows it when it exists and falls back to the DOT text when it does not (no Graphviz).
set -euo pipefail
fig=book/src/figures
gen=$fig/generated
mkdir -p "$gen"
./target/release/declutter graph examples/box_lid.dcl > "$gen/box_lid_graph.dot"
{ echo '```dot'; cat "$gen/box_lid_graph.dot"; echo '```'; } > "$gen/box_lid_graph.md"
for f in box_lid_graph.dot box_lid_graph.md; do
  if ! cmp -s "$gen/$f" "$fig/$f"; then
    cp "$gen/$f" "$fig/$f"
    echo "render_graph: $fig/$f was stale and has been updated: commit it" >&2
  fi
done
rm -f "$gen/box_lid_graph.svg"
if command -v dot >/dev/null 2>&1; then
  dot -Tsvg "$gen/box_lid_graph.dot" > "$gen/box_lid_graph.svg"
else
  echo "render_graph: Graphviz's dot is not installed: the book shows the graph as DOT text" >&2
fi
