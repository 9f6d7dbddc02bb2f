"""The paper's generator: reads results/*.csv, results/runs/*.json and results/registry.json and
writes paper/generated/ — every measured number the text quotes, as a keyed LaTeX value with
its provenance (table, line, run), the generated tables, and the run facts.

The hand-written .tex files never hold a measured number; they write \\R{key} and the key is
defined here (paper/tests/ enforce both halves)."""
