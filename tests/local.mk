# Host tests: plugin loading and refusals, pipeline validation and runs.
