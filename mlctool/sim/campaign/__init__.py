"""Many runs of one program: `mlc test`'s scenarios (suite.py), `mlc sim` batches
(batch.py: bit-sliced lanes; word_lanes.py: numpy word lanes; lane_codegen.py, what the two
share), Dask clusters (cluster.py), coverage (coverage.py) and the JUnit report (junit.py).

Belongs here: running scenarios together or spread out, with the single run's results.
Imports run/ and what it imports. Does not belong here: a single run (run/), the CLI's
options and exit codes (mlctool/cli/).
"""
