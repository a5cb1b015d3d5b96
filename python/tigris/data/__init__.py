"""The data layer: the tigris binary as the tools see it (binary: its sub-commands, flags and
configuration keys), sweep specs (spec), sweep CSVs and the figures they hold (evaldata), and the
pipeline DSE's documents (dse_data). It imports the shared core only."""
