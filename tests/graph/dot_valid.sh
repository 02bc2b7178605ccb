#!/bin/sh
# tests/graph/dot_valid.sh — `tessera dot GRAPH` must be DOT that Graphviz
# accepts, with one drawn node per graph node and one arrow per edge (the
# counts `tessera check` reports for the same file).
# usage: dot_valid.sh TESSERA DOT GRAPH [FLAGS...]
set -u
tessera=$1 dot=$2 graph=$3
shift 3
tmp=$(mktemp -d) || exit 1
trap 'rm -rf "$tmp"' EXIT
if ! "$tessera" check "$@" "$graph" >"$tmp/check"; then
  echo "FAIL: tessera check rejects $graph" >&2; exit 1
fi
nodes=$(sed -n 's/^ok: \([0-9]*\) nodes\{0,1\}, .*/\1/p' "$tmp/check")
edges=$(sed -n 's/^ok: [0-9]* nodes\{0,1\}, \([0-9]*\) edges\{0,1\}, .*/\1/p' "$tmp/check")
if [ -z "$nodes" ] || [ -z "$edges" ]; then
  echo "FAIL: no counts in: $(cat "$tmp/check")" >&2; exit 1
fi
if ! "$tessera" dot "$@" "$graph" >"$tmp/graph.dot"; then
  echo "FAIL: tessera dot failed on $graph" >&2; exit 1
fi
if ! "$dot" -Tsvg "$tmp/graph.dot" >"$tmp/graph.svg" 2>"$tmp/dot.err" || [ -s "$tmp/dot.err" ]; then
  echo "FAIL: Graphviz rejects the output (or warns):" >&2
  cat "$tmp/dot.err" "$tmp/graph.dot" >&2; exit 1
fi
drawn_nodes=$(grep -c 'class="node"' "$tmp/graph.svg")
drawn_edges=$(grep -c 'class="edge"' "$tmp/graph.svg")
echo "$graph: $nodes nodes, $edges edges; drawn: $drawn_nodes nodes, $drawn_edges edges"
if [ "$drawn_nodes" -ne "$nodes" ] || [ "$drawn_edges" -ne "$edges" ]; then
  echo "FAIL: drawing does not match the graph" >&2; exit 1
fi
