# rigflow batch: the worker pool, manifest, resume and lock (test_batch.sh), and the Slurm
# backend against a real one-node Slurm started for the test (test_batch_slurm.sh).
check_LTLIBRARIES += tests/batch/fx_batch.la
tests_batch_fx_batch_la_SOURCES = tests/batch/fx_batch.c
tests_batch_fx_batch_la_LDFLAGS = $(FIXTURE_LDFLAGS)
# LD_PRELOAD'ed by test_batch.sh: a read error on one output, which the job itself cannot cause.
check_LTLIBRARIES += tests/batch/preload/fx_eio.la
tests_batch_preload_fx_eio_la_SOURCES = tests/batch/fx_eio.c
tests_batch_preload_fx_eio_la_LDFLAGS = -module -avoid-version -shared -rpath /nowhere
tests_batch_preload_fx_eio_la_LIBADD = -ldl
TESTS += tests/batch/test_batch.sh tests/batch/test_batch_slurm.sh
dist_noinst_SCRIPTS += tests/batch/test_batch.sh tests/batch/test_batch_slurm.sh
EXTRA_DIST += tests/batch/copy.json tests/batch/slurm-cluster.sh
