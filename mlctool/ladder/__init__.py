"""Ladder diagrams: IL rungs as series/parallel networks, laid out on a grid and rendered
as SVG, a self-contained HTML page, terminal text, or a simulation report (docs/ladder.md)."""
