#!/bin/sh
# Regenerates the block diagram of docs/architecture.md from its text source (needs Graphviz's dot).
cd "$(dirname "$0")/.." && dot -Tsvg docs/architecture.dot -o docs/architecture.svg
