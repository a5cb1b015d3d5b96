"""The commands (`python3 -m tigris TOOL`, or `tigris TOOL`): sweep, reproduce, diff, plot,
pipeline_dse. Each is a main(argv) over the layers below it."""
